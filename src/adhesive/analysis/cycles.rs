//! Stick-slip cycles of the adhesive block: the branch born at the onset,
//! continued in the stiffness by collocation (the engine's cycle branch,
//! Floquet multipliers for stability), down to the scene's stiffness,
//! where the cycle is located exactly (a user point), with the folds of
//! cycles the engine locates on the way (a subcritical onset's branch
//! turns at one). The branch ends where the cycle grazes `v = 0`
//! ([`GRAZING`]): the law's friction vanishes with the slip velocity
//! (`F_a n g(z) ~ F_a n v / V_s`, eq. D8), nothing holds a block that
//! stops while the spring pushes it back, and the forward-sliding model
//! does not describe what follows.

use super::onset::AdhesiveOnset;
use crate::adhesive::block::AdhesiveModel;
use crate::adhesive::params::{AdhesiveParam, AdhesiveParams};
use crate::adhesive::scene::AdhesiveUnits;
use crate::error::NumericalError;
use continuation::periodic::CollocationPoints;
use continuation::periodic::{CycleBranch, CycleEvent, CyclePoint, CycleSettings};

/// One cycle, dimensionless.
#[derive(Clone, Debug, serde::Serialize)]
pub struct AdhesiveCycle {
    pub kappa: f64,
    /// Period, units `tau_out`.
    pub period: f64,
    /// Least and greatest spring force on the cycle.
    pub s_min: f64,
    pub s_max: f64,
    /// Least and greatest slip velocity (units `V_s`).
    pub u_min: f64,
    pub u_max: f64,
    /// Least and greatest bond fraction.
    pub n_min: f64,
    pub n_max: f64,
    /// Stable by its Floquet multipliers.
    pub stable: bool,
    /// The orbit `(t / period, s, u, n)` sampled.
    #[serde(skip)]
    pub orbit: Vec<[f64; 4]>,
    /// The same cycle in the scene's units, beside the dimensionless
    /// values: set by the job that knows the units
    /// ([`AdhesiveCycle::in_units`]).
    #[serde(flatten)]
    pub units: Option<CycleInUnits>,
}

/// An adhesive cycle in the experimenter's units (the columns of the
/// `cycles` CSV and fields of its JSON).
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct CycleInUnits {
    #[serde(rename = "K_N_per_m")]
    pub k_n_per_m: f64,
    pub period_s: f64,
    /// The force drop of a slip, `s_max - s_min` in N.
    #[serde(rename = "force_drop_N")]
    pub force_drop_n: f64,
    #[serde(rename = "s_min_N")]
    pub s_min_n: f64,
    #[serde(rename = "s_max_N")]
    pub s_max_n: f64,
    pub v_min_um_per_s: f64,
    pub v_max_um_per_s: f64,
}

impl CycleInUnits {
    /// The cycle `c` in the units `u`.
    pub fn of(c: &AdhesiveCycle, u: &AdhesiveUnits) -> Self {
        CycleInUnits {
            k_n_per_m: u.stiffness_n_m(c.kappa),
            period_s: u.time_s(c.period),
            force_drop_n: u.force_n(c.s_max - c.s_min),
            s_min_n: u.force_n(c.s_min),
            s_max_n: u.force_n(c.s_max),
            v_min_um_per_s: u.velocity_um_s(c.u_min),
            v_max_um_per_s: u.velocity_um_s(c.u_max),
        }
    }
}

impl AdhesiveCycle {
    /// The cycle with its values in the units `u` beside the
    /// dimensionless ones.
    pub fn in_units(mut self, u: &AdhesiveUnits) -> Self {
        self.units = Some(CycleInUnits::of(&self, u));
        self
    }
}

/// A fold of cycles (limit point, `lpc`) located on the branch: the
/// stiffness where the branch turns.
#[derive(Clone, Debug, serde::Serialize)]
pub struct CycleFold {
    #[serde(flatten)]
    pub cycle: AdhesiveCycle,
    /// The orbit's estimated discretization error (relative).
    pub error_estimate: f64,
}

/// The branch traced and how it ended.
#[derive(Clone, Debug)]
pub struct CycleRun {
    pub cycles: Vec<AdhesiveCycle>,
    /// The cycle at the stiffness asked for ([`trace`]'s `at`), when the
    /// branch passed it: where it passes it more than once (a subcritical
    /// onset's branch, K between `K_c` and the fold of cycles), the stable
    /// one, the cycle the rig runs on.
    pub at_scene: Option<AdhesiveCycle>,
    /// Whether the branch reached its end stiffness `kappa_to`.
    pub reached_end: bool,
    /// The folds of cycles located on the branch (limit points, `lpc`).
    pub folds: Vec<CycleFold>,
    /// The engine's words on how the branch ended; `None` when it reached
    /// its end stiffness.
    pub stop: Option<String>,
    /// Whether the watcher stopped the branch (a stop signal).
    pub interrupted: bool,
}

fn record<B: AdhesiveModel>(model: B, p: &AdhesiveParams, point: &CyclePoint) -> AdhesiveCycle {
    let c = &point.cycle;
    let mut q = *p;
    q.kappa = c.p[AdhesiveParam::Kappa as usize];
    let (s_min, s_max) = c.range(&model, 0);
    let (n_min, n_max) = c.range(&model, model.dim() - 1);
    let (u_min, u_max) = c.range_of(&model, |x| model.velocity(&q, x));
    let mut orbit = Vec::with_capacity(c.mesh.ntst() * 4 + 1);
    c.each_sample(4, |tau, x| {
        orbit.push([tau, x[0], model.velocity(&q, x), model.bonds(x)]);
    });
    AdhesiveCycle {
        kappa: q.kappa,
        period: c.period,
        s_min,
        s_max,
        u_min,
        u_max,
        n_min,
        n_max,
        stable: point.stability.is_stable(),
        orbit,
        units: None,
    }
}

/// How far the least slip velocity of a cycle must fall from one cycle to
/// the next, while the stiffness stays put to [`STALLED`], for the branch
/// to be read as grazing `v = 0`.
pub const GRAZING: f64 = 0.5;

/// The relative change of the stiffness between cycles below which the
/// branch no longer moves in `kappa` (a row of the table would repeat
/// the one before to its printed six digits).
pub const STALLED: f64 = 1e-5;

/// Why the branch ends at `next` after `last`: its stiffness stalled
/// ([`STALLED`]) while the least slip velocity fell by more than the
/// factor [`GRAZING`] on an orbit where the spring pushes the block back
/// (`s_min < 0`, which the quasi-static block never has): the orbit grazes
/// `v = 0` (there `du/dt = 0` needs `s = F(n, 0) = 0`, and `s` rises
/// through 0 since `u < nu`), and below this stiffness the block would
/// stop and be pushed back, outside the model. A branch that stalls in the
/// stiffness alone is no graze: near a supercritical onset, or where the
/// branch stands nearly upright, the amplitude grows at nearly fixed
/// `kappa`. `None` while the branch moves.
fn grazing(last: &AdhesiveCycle, next: &AdhesiveCycle) -> Option<String> {
    let stalled = (next.kappa - last.kappa).abs() <= STALLED * last.kappa;
    (stalled && next.u_min < GRAZING * last.u_min && next.s_min < 0.0).then(|| {
        format!(
            "the cycle grazes v = 0 at kappa = {:.10e}: the branch stalls in the stiffness \
             while the least slip velocity falls ({:.3e} to {:.3e} V_s; the spring force \
             down to {:.3e} F_a); below this stiffness the block stops and the spring pushes \
             it back, which the model (forward sliding, friction vanishing as v -> 0, eq. D8) \
             does not describe",
            next.kappa, last.u_min, next.u_min, next.s_min
        )
    })
}

/// Continues the cycles from `onset` in `kappa` down to `kappa_to` in at
/// most `max_steps` steps, the mesh refined up to `ntst_max` intervals,
/// locating the cycle at the stiffness `at` on the way (a user point; the
/// stable one where the branch passes `at` more than once). `watch` sees
/// each cycle as it is computed (for incremental output) and stops the
/// branch by returning `false` (a stop signal).
pub fn trace<B: AdhesiveModel>(
    model: B,
    p: &AdhesiveParams,
    onset: &AdhesiveOnset,
    (kappa_to, at): (f64, f64),
    (max_steps, ntst_max): (usize, usize),
    watch: &mut dyn FnMut(&AdhesiveCycle) -> bool,
) -> Result<CycleRun, NumericalError> {
    let mut q = *p;
    q.kappa = onset.kappa_c;
    let mut user_points = vec![kappa_to];
    if at != kappa_to {
        user_points.push(at);
    }
    let settings = CycleSettings {
        max_steps,
        p_min: kappa_to,
        user_points,
        param_floor: kappa_to.min(onset.kappa_c) * 1e-3,
        mesh: continuation::periodic::Discretization {
            points: CollocationPoints::Radau,
            ntst_max,
            ..Default::default()
        },
        ..CycleSettings::default()
    };
    let k = AdhesiveParam::Kappa as usize;
    let mut branch = CycleBranch::from_hopf(
        &model,
        &onset.state,
        onset.omega_c,
        &q.to_vec(),
        k,
        settings,
    )?;
    let (mut cycles, mut at_scene, mut folds) = (Vec::new(), None::<AdhesiveCycle>, Vec::new());
    let mut reached_end = false;
    let mut failure = None;
    let mut interrupted = false;
    for point in branch.by_ref() {
        match point {
            Ok(point) => {
                let cycle = record(model, p, &point);
                if let Some(why) = cycles.last().and_then(|last| grazing(last, &cycle)) {
                    failure = Some(why);
                    break;
                }
                for user in point.user_points() {
                    let kappa = user.cycle.p[k];
                    // Each user point is the stiffness nearer to it.
                    if (kappa - at).abs() <= (kappa - kappa_to).abs() {
                        let here = record(model, p, user);
                        // A later pass replaces an unstable cycle only.
                        if at_scene.as_ref().is_none_or(|c| !c.stable && here.stable) {
                            at_scene = Some(here);
                        }
                    }
                    if (kappa - kappa_to).abs() <= (kappa - at).abs() {
                        reached_end = true;
                    }
                }
                if let Some(fold) = point.event(CycleEvent::Fold) {
                    folds.push(CycleFold {
                        cycle: record(model, p, fold),
                        error_estimate: fold.error_estimate,
                    });
                }
                let go_on = watch(&cycle);
                cycles.push(cycle);
                if !go_on {
                    interrupted = true;
                    break;
                }
            }
            Err(e) => {
                failure = Some(e.to_string());
                break;
            }
        }
    }
    let stop = match failure {
        _ if reached_end => None,
        _ if interrupted => Some(format!("stopped by a signal after {} cycles", cycles.len())),
        Some(e) => Some(e),
        None => Some(
            branch
                .stop()
                .map_or("the branch ended".to_string(), |s| s.to_string()),
        ),
    };
    Ok(CycleRun {
        cycles,
        at_scene,
        reached_end,
        folds,
        stop,
        interrupted,
    })
}
