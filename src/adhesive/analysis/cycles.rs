//! Stick-slip cycles of the adhesive block: the branch born at the onset,
//! continued in the stiffness by collocation (the engine's cycle branch,
//! Floquet multipliers for stability), down to the scene's stiffness,
//! where the cycle is located exactly (a user point).

use super::onset::AdhesiveOnset;
use crate::adhesive::block::AdhesiveModel;
use crate::adhesive::params::{AdhesiveParam, AdhesiveParams};
use crate::error::NumericalError;
use continuation::periodic::CollocationPoints;
use continuation::periodic::{CycleBranch, CyclePoint, CycleSettings};

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
}

/// The branch traced and how it ended.
#[derive(Clone, Debug)]
pub struct CycleRun {
    pub cycles: Vec<AdhesiveCycle>,
    /// The cycle at the scene's stiffness, when the branch reached it.
    pub at_scene: Option<AdhesiveCycle>,
    /// The engine's words on how the branch ended; `None` when it reached
    /// the scene's stiffness.
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
    let orbit = c
        .samples(4)
        .into_iter()
        .map(|(tau, x)| [tau, x[0], model.velocity(&q, &x), model.bonds(&x)])
        .collect();
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
    }
}

/// Continues the cycles from `onset` in `kappa` down to `kappa_to` in at
/// most `max_steps` steps, the mesh refined up to `ntst_max` intervals.
/// `watch` sees each cycle as it is computed (for incremental output) and
/// stops the branch by returning `false` (a stop signal).
pub fn trace<B: AdhesiveModel>(
    model: B,
    p: &AdhesiveParams,
    onset: &AdhesiveOnset,
    kappa_to: f64,
    (max_steps, ntst_max): (usize, usize),
    watch: &mut dyn FnMut(&AdhesiveCycle) -> bool,
) -> Result<CycleRun, NumericalError> {
    let mut q = *p;
    q.kappa = onset.kappa_c;
    let settings = CycleSettings {
        max_steps,
        p_min: kappa_to,
        user_points: vec![kappa_to],
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
    let (mut cycles, mut at_scene) = (Vec::new(), None);
    let mut failure = None;
    let mut interrupted = false;
    for point in branch.by_ref() {
        match point {
            Ok(point) => {
                if let Some(user) = point.user_points().next() {
                    at_scene = Some(record(model, p, user));
                }
                let cycle = record(model, p, &point);
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
    let stop = match (&at_scene, failure) {
        (Some(_), _) => None,
        (None, _) if interrupted => {
            Some(format!("stopped by a signal after {} cycles", cycles.len()))
        }
        (None, Some(e)) => Some(e),
        (None, None) => Some(
            branch
                .stop()
                .map_or("the branch ended".to_string(), |s| s.to_string()),
        ),
    };
    Ok(CycleRun {
        cycles,
        at_scene,
        stop,
        interrupted,
    })
}
