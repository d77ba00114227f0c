//! The commands on an adhesive scene, one function each (`hopf`, `branch`,
//! `diagram`, `cycles`, `simulate`): the scene and its model decision in,
//! a result out whose serde form is the command's JSON, in the
//! experimenter's units with the dimensionless values beside.

use super::analysis::cycles::{self, AdhesiveCycle, CycleFold};
use super::analysis::onset::{find_onset, AdhesiveOnset, OnsetOutcome};
use super::analysis::simulate::{simulate as integrate, Run, Segment, SettledCycle};
use super::analysis::steady::{self, Bautin, DiagramPoint, NuHopf, SteadyPoint};
use super::block;
use super::params::AdhesiveParams;
use super::scene::{AdhesiveScene, AdhesiveUnits};
use crate::analysis::hopf::Criticality;
use crate::analysis::operating_point::{
    judge, judge_without_onset, FoldAt, Regime, StabilityAt, TOLERANCE,
};
use crate::error::{Error, InputError, NumericalError};
use crate::jobs::diagram::OperatingPoint;
use crate::model::ModelKind;
use serde::Serialize;

/// Where a command judges the inertia ratio: at the scene's velocity and
/// on its orbit (`hopf`, `cycles`: the scene's own decision,
/// [`AdhesiveSetup::new`]), at every pulling velocity of a protocol
/// (`simulate`, µm/s; the scene's velocity without one; its run judged
/// after), or, besides the scene's own decision, at every velocity of the
/// swept `V_range` (`branch`, `diagram`).
#[derive(Clone, Debug, PartialEq)]
pub enum Judged {
    AtVelocity,
    AtPulling(Vec<f64>),
    OverRange,
}

/// Runs `$body` with `$b` the block of `$kind` (a [`ModelKind`]): the
/// quasi-static [`block::AdhesiveBlock`] or the
/// [`block::InertialAdhesiveBlock`].
macro_rules! with_model {
    ($kind:expr, $b:ident => $body:expr) => {
        match $kind {
            ModelKind::QuasiStatic => {
                let $b = block::AdhesiveBlock;
                $body
            }
            ModelKind::Inertial => {
                let $b = block::InertialAdhesiveBlock;
                $body
            }
        }
    };
}

/// What every adhesive result starts with: the scene, its model decision
/// and why, its parameters and units, steady friction's extrema.
#[derive(Clone, Debug, Serialize)]
pub struct AdhesiveSetup {
    pub scene: String,
    pub law: &'static str,
    pub model: &'static str,
    pub model_reason: String,
    #[serde(skip)]
    pub model_kind: ModelKind,
    /// Whether `--model` forced it.
    #[serde(skip)]
    pub forced: bool,
    /// The scene's own model, where the command's differs from it (`branch`
    /// and `diagram`, inertial over `V_range` where `chi` crosses the
    /// threshold there, while the scene at its `V` and on its orbit is
    /// quasi-static): the model of the onset at `V` and of the operating
    /// point, the one `hopf` and `cycles` use. `null` where the same.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub scene_model: Option<&'static str>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub scene_model_reason: Option<String>,
    /// The model of the scene at its own `V` and orbit (`model_kind` but
    /// where `scene_model` differs).
    #[serde(skip)]
    pub scene_model_kind: ModelKind,
    /// On the quasi-static orbit of the scene's cycles (at its `K` below
    /// `K_c`, else at half `K_c`, where `cycles` ends its branch), the
    /// largest shift of `ln v` the dropped inertia force makes; `None`
    /// where not judged (inertial by `chi` at `V`, forced, no mass, no
    /// onset, or a `simulate`, which judges its own run).
    #[serde(skip)]
    pub orbit_inertia: Option<f64>,
    /// `chi = m lambda_n / F_u` at steady sliding at the scene's velocity
    /// ([`block::inertia_ratio`]).
    pub inertia_ratio: f64,
    pub inertia_threshold: f64,
    /// Over the swept range (`branch`, `diagram`): the largest `chi` and
    /// the velocity where `chi` crosses the threshold, um/s (`None` where it
    /// does not within the range).
    pub inertia_ratio_max: Option<f64>,
    #[serde(rename = "inertia_crossing_um_per_s")]
    pub inertia_crossing_um_s: Option<f64>,
    pub params: AdhesiveParams,
    pub units: AdhesiveUnits,
    /// The maximum of steady friction (the bell of Schallamach's pinning).
    #[serde(rename = "V_max_um_per_s")]
    pub v_max_um_s: Option<f64>,
    /// The minimum above it, where stick-slip ends (seed §III.D.2).
    #[serde(rename = "V_c_um_per_s")]
    pub v_c_um_s: Option<f64>,
    /// Steady friction at `V_max` and `V_c`, N.
    #[serde(rename = "force_at_V_max_N")]
    pub force_at_v_max_n: Option<f64>,
    #[serde(rename = "force_at_V_c_N")]
    pub force_at_v_c_n: Option<f64>,
    /// What is unusual in the scene but valid (also on stderr).
    pub warnings: Vec<String>,
    #[serde(skip)]
    pub scene_full: AdhesiveScene,
}

/// Velocities scanned for the extrema of steady friction, in `V_s`.
const EXTREMA_RANGE: (f64, f64) = (1e-6, 1e12);

/// Where `chi(nu) - threshold` changes sign in `[a, b]` (a sign change
/// given), by bisection in `ln nu` to rounding.
fn crossing(p: &AdhesiveParams, threshold: f64, a: f64, b: f64) -> f64 {
    let above = |nu: f64| {
        let mut q = *p;
        q.nu = nu;
        block::model_for(&q, threshold) == ModelKind::Inertial
    };
    let side = above(a);
    let (mut lo, mut hi) = (a.ln(), b.ln());
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if above(mid.exp()) == side {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    (0.5 * (lo + hi)).exp()
}

/// At each of the velocities `nus`, whether dropping the inertia changes
/// the onset type: the quasi-static onset degenerate or not the inertial
/// one, `None` at a velocity without onset (the factor `1 + chi > 0`
/// keeps `kappa_c`'s sign, so neither model has one there); `None` in all
/// where either model's onsets could not be computed (the decision then
/// rests on `chi`).
pub fn onset_type_changes(p: &AdhesiveParams, nus: &[f64]) -> Option<Vec<Option<bool>>> {
    let quasi = steady::diagram(block::AdhesiveBlock, p, nus, f64::INFINITY).ok()?;
    let inertial = steady::diagram(block::InertialAdhesiveBlock, p, nus, f64::INFINITY).ok()?;
    Some(
        quasi
            .iter()
            .zip(&inertial)
            .map(|(a, b)| match (a.onset, b.onset) {
                (Some(a), Some(b)) => Some(a == Criticality::Degenerate || a != b),
                _ => None,
            })
            .collect(),
    )
}

/// At how many of the velocities `nus` with an onset the onset type
/// changes without inertia ([`onset_type_changes`]), and of how many.
pub fn onset_types_differ(p: &AdhesiveParams, nus: &[f64]) -> Option<(usize, usize)> {
    let changes = onset_type_changes(p, nus)?;
    let of = changes.iter().flatten().count();
    let changed = changes.iter().flatten().filter(|c| **c).count();
    Some((changed, of))
}

/// The model by the largest inertia ratio `chi` among the velocities
/// `nus` (the scene's `V`, or a protocol's), and why.
fn by_chi_at(
    p: &AdhesiveParams,
    u: &AdhesiveUnits,
    nus: &[f64],
    threshold: f64,
) -> (ModelKind, String) {
    let (mut q, mut chi) = (*p, block::inertia_ratio(p));
    for &nu in nus {
        let mut r = *p;
        r.nu = nu;
        let c = block::inertia_ratio(&r);
        if c.is_nan() || c > chi {
            (q, chi) = (r, c);
        }
    }
    let at_v = u.velocity_um_s(q.nu);
    let mass = u.mass;
    let needed = block::model_for(&q, threshold);
    let reason = match needed {
        ModelKind::QuasiStatic => format!(
            "chi = m lambda_n / F_u = {chi:.3e} at V = {at_v:.6e} µm/s is below the inertia \
             threshold {threshold:e}: the block's inertia (M = {mass:e} kg) raises kappa_c by \
             the factor 1 + chi only, and the block without it is regular everywhere (at fixed \
             bond fraction the force rises with the slip velocity)"
        ),
        ModelKind::Inertial => format!(
            "chi = m lambda_n / F_u = {chi:.3e} at V = {at_v:.6e} µm/s is not below the inertia \
             threshold {threshold:e}: the block's inertia (M = {mass:e} kg) matters (it raises \
             kappa_c by the factor 1 + chi), m u dw/dt = s - F(n, u)"
        ),
    };
    (needed, reason)
}

/// The model by `chi` over the scene's `V_range` (`branch`, `diagram`):
/// inertial where it is not below the threshold anywhere there; with the
/// largest `chi` and where it crosses the threshold (`nu`).
fn by_chi_over_range(
    scene: &AdhesiveScene,
    threshold: f64,
) -> (ModelKind, String, f64, Option<f64>) {
    let (p, u, mass) = (scene.params, scene.units, scene.units.mass);
    let (lo, hi) = scene.nu_range;
    let nus = steady::grid(lo, hi, PER_DECADE);
    let chis: Vec<f64> = nus
        .iter()
        .map(|&nu| {
            let mut q = p;
            q.nu = nu;
            block::inertia_ratio(&q)
        })
        .collect();
    let needs = |c: f64| !(p.m == 0.0 || c < threshold);
    let (i_max, c_max) = chis
        .iter()
        .enumerate()
        .fold((0, f64::NEG_INFINITY), |a, (i, c)| {
            if c.is_nan() || *c > a.1 {
                (i, *c)
            } else {
                a
            }
        });
    let cross = (1..nus.len())
        .find(|&i| needs(chis[i]) != needs(chis[i - 1]))
        .map(|i| crossing(&p, threshold, nus[i - 1], nus[i]));
    let range = format!(
        "V_range [{:.4e}, {:.4e}] µm/s",
        u.velocity_um_s(lo),
        u.velocity_um_s(hi)
    );
    let largest = format!(
        "largest chi = m lambda_n / F_u = {c_max:.3e} at V = {:.4e} µm/s",
        u.velocity_um_s(nus[i_max])
    );
    let needed = if chis.iter().any(|c| needs(*c)) {
        ModelKind::Inertial
    } else {
        ModelKind::QuasiStatic
    };
    let reason = match (needed, cross) {
        (ModelKind::QuasiStatic, _) => format!(
            "chi stays below the inertia threshold {threshold:e} over {range} ({largest}): the \
             block's inertia (M = {mass:e} kg) is negligible at every velocity swept"
        ),
        (ModelKind::Inertial, Some(c)) => format!(
            "chi crosses the inertia threshold {threshold:e} at V = {:.6e} µm/s within {range} \
             ({largest}): the block's inertia (M = {mass:e} kg) matters there, so the inertial \
             model over the whole range (each point says where the quasi-static one would do)",
            u.velocity_um_s(c)
        ),
        (ModelKind::Inertial, None) => format!(
            "chi is not below the inertia threshold {threshold:e} over all of {range} \
             ({largest}): the block's inertia (M = {mass:e} kg) matters"
        ),
    };
    (needed, reason, c_max, cross)
}

/// As for the rate-and-state block (`inertia_decides`): where dropping
/// the inertia changes the onset type at a velocity of `nus` (the
/// quasi-static onset degenerate, or of the other sign), that inertia,
/// however small, decides it. `(kind, reason)` unchanged elsewhere.
fn by_onset_type(
    p: &AdhesiveParams,
    nus: &[f64],
    (kind, reason): (ModelKind, String),
) -> (ModelKind, String) {
    if kind != ModelKind::QuasiStatic || p.m <= 0.0 {
        return (kind, reason);
    }
    match onset_types_differ(p, nus) {
        Some((changed, of)) if changed > 0 => (
            ModelKind::Inertial,
            format!(
                "inertial: the quasi-static onset type is not the inertial one at {changed} of \
                 the {of} velocities judged (degenerate, l1 = 0 to rounding, or of the other \
                 sign), so the block's small inertia decides the onset type ({reason})"
            ),
        ),
        _ => (kind, reason),
    }
}

/// The model judged on the whole orbit, as the rate-and-state `cycles`
/// judges its orbits ([`crate::analysis::orbit_inertia`]): a block
/// quasi-static by `chi` at `V` (with a mass) is simulated where `cycles`
/// ends its branch ([`target_stiffness`]: the scene's `K` below the
/// quasi-static `K_c`, else half `K_c`), where its cycle is largest, and
/// turns inertial where the dropped inertia force shifts `ln v` there by
/// at least the threshold ([`decide_on_orbit`]). Every command but
/// `simulate` (which judges its own run) takes this one decision, so that
/// `hopf`, `diagram` and `cycles` give one `K_c`. Returns the model, why,
/// and the largest shift (`None` where not judged: inertial already, no
/// mass, or no onset at `V`, hence no cycle).
fn by_orbit(
    scene: &AdhesiveScene,
    threshold: f64,
    (kind, reason): (ModelKind, String),
) -> Result<(ModelKind, String, Option<f64>), Error> {
    let p = scene.params;
    if kind != ModelKind::QuasiStatic || p.m <= 0.0 {
        return Ok((kind, reason, None));
    }
    let OnsetOutcome::Found(onset) = find_onset(block::AdhesiveBlock, &p)? else {
        return Ok((kind, reason, None));
    };
    let mut q = p;
    q.kappa = target_stiffness(scene, onset.kappa_c);
    let start = block::steady_bonds(q.nu, q.r) * 0.99;
    let (_, _, run) = settle(block::AdhesiveBlock, &q, start, 30);
    let chi = orbit_imbalance(&q, &run);
    let at = format!(
        "at K = {:.6e} N/m{}",
        scene.units.stiffness_n_m(q.kappa),
        if q.kappa == p.kappa {
            " (the scene's)"
        } else {
            " (half the quasi-static K_c, where cycles ends its branch)"
        }
    );
    let (kind, reason) = decide_on_orbit((kind, reason), chi, threshold, &at);
    Ok((kind, reason, Some(chi)))
}

impl AdhesiveSetup {
    /// Where steady friction falls with the velocity, the only velocities
    /// where steady sliding can lose stability (`kappa_c > 0`), from the
    /// extrema that exist: between `V_max` and `V_c`; above `V_max` where
    /// friction has no minimum above it (no viscous force, `F_v = 0`, to
    /// raise it again); nowhere without a maximum.
    pub fn weakening(&self) -> String {
        let top = self.units.velocity_um_s(EXTREMA_RANGE.1);
        match (self.v_max_um_s, self.v_c_um_s) {
            (Some(a), Some(b)) => format!(
                "steady friction falls with V only between V_max = {a:.6e} µm/s and V_c = \
                 {b:.6e} µm/s: only there can steady sliding lose stability (a Hopf point)"
            ),
            (Some(a), None) => format!(
                "steady friction falls with V at every velocity above V_max = {a:.6e} µm/s: it \
                 has no minimum up to {top:.1e} µm/s{}, so steady sliding can lose stability (a \
                 Hopf point) at any velocity above V_max",
                if self.params.f_v == 0.0 {
                    " (F_v = 0: no junction viscosity raises it again)"
                } else {
                    ""
                }
            ),
            (None, _) => format!(
                "steady friction rises with V at every velocity up to {top:.1e} µm/s (no \
                 maximum): steady sliding is linearly stable at every stiffness and velocity (no \
                 Hopf point)"
            ),
        }
    }

    /// The scene's model decision and steady friction's extrema: `forced`
    /// when given (`--model`), else the scene's own decision, one for
    /// `hopf`, `cycles`, `branch` and `diagram`: quasi-static where the
    /// inertia ratio `chi` at `V` is below `inertia_threshold`
    /// ([`block::model_for`]), the onset type at `V` does not change
    /// without inertia ([`by_onset_type`]) and the dropped inertia force
    /// does not shift the scene's quasi-static orbit by the threshold
    /// ([`by_orbit`]), else inertial. `branch` and `diagram`
    /// ([`Judged::OverRange`]) also judge `chi` and the onset type at every
    /// velocity of the swept `V_range`, and run inertial where any needs
    /// it, keeping the scene's own model for its onset at `V` and its
    /// operating point (`scene_model` where the two differ). `simulate`
    /// ([`Judged::AtPulling`]) judges `chi` at every pulling velocity and
    /// its own run (`simulate_watched`).
    pub fn new(
        scene: AdhesiveScene,
        inertia_threshold: f64,
        judged: Judged,
        forced: Option<ModelKind>,
    ) -> Result<Self, Error> {
        if !(inertia_threshold >= 0.0 && inertia_threshold.is_finite()) {
            return Err(InputError::out_of_range(
                "--inertia-threshold",
                inertia_threshold,
                ">= 0 and finite",
            )
            .into());
        }
        let p = scene.params;
        let u = scene.units;
        if forced == Some(ModelKind::Inertial) && p.m == 0.0 {
            return Err(InputError::Conflict(format!(
                "{}: --model inertial needs the block's mass; the scene gives M = 0 (or none): \
                 give M [kg] > 0 (in the scene or --set M=...), or drop --model",
                scene.name
            ))
            .into());
        }
        let chi = block::inertia_ratio(&p);
        let threshold = inertia_threshold;
        // The velocities whose chi and onset type decide: the scene's, or a
        // protocol's pulling velocities.
        let pulled: Vec<f64> = match &judged {
            Judged::AtPulling(list) => list
                .iter()
                .filter(|v| **v > 0.0)
                .map(|v| u.nu_of_velocity_um_s(*v))
                .collect(),
            _ => vec![p.nu],
        };
        // Over the swept range (`branch`, `diagram`): reported, forced or not.
        let over_range =
            (judged == Judged::OverRange).then(|| by_chi_over_range(&scene, threshold));
        let chi_max = over_range.as_ref().map(|r| r.2);
        let cross = over_range
            .as_ref()
            .and_then(|r| r.3)
            .map(|c| u.velocity_um_s(c));
        let (scene_kind, scene_reason, orbit_inertia, kind, reason) = match forced {
            Some(f) => {
                let why = match &over_range {
                    Some((_, why, _, _)) => why.clone(),
                    None => by_chi_at(&p, &u, &pulled, threshold).1,
                };
                let reason = format!("forced by --model {} ({why})", f.name());
                (f, reason.clone(), None, f, reason)
            }
            None => {
                let at_v = by_onset_type(&p, &pulled, by_chi_at(&p, &u, &pulled, threshold));
                let (scene_kind, scene_reason, orbit) = match judged {
                    Judged::AtPulling(_) => (at_v.0, at_v.1, None),
                    _ => by_orbit(&scene, threshold, at_v)?,
                };
                let (kind, reason) = match over_range {
                    Some((k, why, _, _)) => {
                        let (lo, hi) = scene.nu_range;
                        let grid = steady::grid(lo, hi, PER_DECADE);
                        match (by_onset_type(&p, &grid, (k, why)), scene_kind) {
                            ((ModelKind::QuasiStatic, why), ModelKind::Inertial) => (
                                ModelKind::Inertial,
                                format!(
                                    "inertial, the scene's own model ({scene_reason}); over \
                                     V_range alone: {why}"
                                ),
                            ),
                            (range, _) => range,
                        }
                    }
                    None => (scene_kind, scene_reason.clone()),
                };
                (scene_kind, scene_reason, orbit, kind, reason)
            }
        };
        let extrema = block::steady_extrema(&p, EXTREMA_RANGE.0, EXTREMA_RANGE.1);
        let v_max = extrema.iter().find(|e| e.1).map(|e| e.0);
        let v_c = v_max.and_then(|m| extrema.iter().find(|e| !e.1 && e.0 > m).map(|e| e.0));
        let force = |nu: f64| u.force_n(block::steady_friction(nu, &p));
        let differs = scene_kind != kind;
        Ok(AdhesiveSetup {
            scene: scene.name.clone(),
            law: super::scene::LAW,
            model: kind.name(),
            model_reason: reason,
            model_kind: kind,
            forced: forced.is_some(),
            scene_model: differs.then(|| scene_kind.name()),
            scene_model_reason: differs.then_some(scene_reason),
            scene_model_kind: scene_kind,
            orbit_inertia,
            inertia_ratio: chi,
            inertia_threshold,
            inertia_ratio_max: chi_max,
            inertia_crossing_um_s: cross,
            params: p,
            units: u,
            v_max_um_s: v_max.map(|nu| u.velocity_um_s(nu)),
            v_c_um_s: v_c.map(|nu| u.velocity_um_s(nu)),
            force_at_v_max_n: v_max.map(force),
            force_at_v_c_n: v_c.map(force),
            warnings: scene.warnings.clone(),
            scene_full: scene,
        })
    }
}

/// The onset in the experimenter's units.
#[derive(Clone, Debug, Serialize)]
pub struct Critical {
    #[serde(flatten)]
    pub onset: AdhesiveOnset,
    /// `K_c = kappa_c F_a / (V_s tau_out)`, N/m.
    #[serde(rename = "K_N_per_m")]
    pub k_c_n_m: f64,
    /// `omega_c / (2 pi tau_out)`, Hz.
    pub frequency_hz: f64,
}

/// The result of `hopf`.
#[derive(Clone, Debug, Serialize)]
pub struct AdhesiveHopf {
    #[serde(flatten)]
    pub setup: AdhesiveSetup,
    /// `onset` or `stable_for_all_stiffness`.
    pub status: &'static str,
    pub critical: Option<Critical>,
    /// `dF_ss/du` at the scene's velocity where stable at every stiffness.
    pub steady_slope: Option<f64>,
    /// Steady friction at the scene's velocity, N.
    #[serde(rename = "steady_force_N")]
    pub steady_force_n: f64,
    pub steady_bonds: f64,
    /// The scene's stiffness against the onset in words: `stick-slip`,
    /// `steady sliding`, `bistable`, or `undecided: <why>` (`None` without
    /// `K`): [`Verdict::regime_words`] of `operating_point`.
    pub regime: Option<String>,
    /// The same verdict as `diagram`'s and `cycles`' ([`verdict`]).
    pub operating_point: Option<OperatingPoint>,
    /// On the quasi-static orbit of the scene's cycles, the largest shift
    /// of `ln v` the dropped inertia force makes (`null` where not judged),
    /// as in `cycles` ([`AdhesiveSetup::new`]: one decision).
    pub orbit_inertia_ratio: Option<f64>,
    pub complete: bool,
    /// Why the run ended short of the protocol's end (`null`: it delivered
    /// all): a failed integration or a stop signal, the steps before kept.
    pub stop: Option<String>,
}

/// `hopf` on an adhesive scene.
pub fn hopf(setup: AdhesiveSetup) -> Result<AdhesiveHopf, Error> {
    let p = setup.params;
    let setup_orbit = setup.orbit_inertia;
    let u = setup.units;
    let v = verdict(&setup)?;
    let regime = v.regime_words();
    let (status, critical, slope) = match v.outcome {
        OnsetOutcome::Found(onset) => (
            "onset",
            Some(Critical {
                k_c_n_m: u.stiffness_n_m(onset.kappa_c),
                frequency_hz: onset.omega_c / (2.0 * std::f64::consts::PI * u.tau_out),
                onset,
            }),
            None,
        ),
        OnsetOutcome::StableForAllStiffness { steady_slope } => {
            ("stable_for_all_stiffness", None, Some(steady_slope))
        }
    };
    Ok(AdhesiveHopf {
        steady_force_n: u.force_n(block::steady_friction(p.nu, &p)),
        steady_bonds: block::steady_bonds(p.nu, p.r),
        setup,
        status,
        critical,
        steady_slope: slope,
        regime,
        operating_point: v.operating_point,
        orbit_inertia_ratio: setup_orbit,
        complete: true,
        stop: None,
    })
}

/// The result of `branch`: steady sliding across the scene's `V_range` at
/// its stiffness.
#[derive(Clone, Debug, Serialize)]
pub struct AdhesiveBranch {
    #[serde(flatten)]
    pub setup: AdhesiveSetup,
    pub points: Vec<SteadyRecord>,
    /// The Hopf points in the driving velocity, um/s beside `nu`.
    pub hopf_points: Vec<NuHopf>,
    #[serde(rename = "hopf_points_V_um_per_s")]
    pub hopf_points_um_s: Vec<f64>,
    /// As `hopf`'s ([`AdhesiveHopf::orbit_inertia_ratio`]).
    pub orbit_inertia_ratio: Option<f64>,
    pub complete: bool,
    /// Why the run ended short of the protocol's end (`null`: it delivered
    /// all): a failed integration or a stop signal, the steps before kept.
    pub stop: Option<String>,
}

/// A point of steady sliding with its physical values beside the
/// dimensionless ones (`nu`, `s`).
#[derive(Clone, Debug, Serialize)]
pub struct SteadyRecord {
    #[serde(flatten)]
    pub point: SteadyPoint,
    #[serde(rename = "V_um_per_s")]
    pub v_um_per_s: f64,
    #[serde(rename = "steady_force_N")]
    pub steady_force_n: f64,
}

/// A point of the stability diagram with its physical values beside the
/// dimensionless ones (`nu`, `kappa_c`, `omega_c`).
#[derive(Clone, Debug, Serialize)]
pub struct OnsetRecord {
    #[serde(flatten)]
    pub point: DiagramPoint,
    #[serde(rename = "V_um_per_s")]
    pub v_um_per_s: f64,
    #[serde(rename = "K_N_per_m")]
    pub k_n_per_m: Option<f64>,
    pub frequency_hz: Option<f64>,
}

/// The steady points in the experimenter's units.
fn steady_records(points: Vec<SteadyPoint>, u: &AdhesiveUnits) -> Vec<SteadyRecord> {
    points
        .into_iter()
        .map(|point| SteadyRecord {
            v_um_per_s: u.velocity_um_s(point.nu),
            steady_force_n: u.force_n(point.s),
            point,
        })
        .collect()
}

/// Points per decade of the velocity grids.
const PER_DECADE: usize = 20;

/// `branch` on an adhesive scene (in the driving velocity `V`).
pub fn branch(setup: AdhesiveSetup) -> Result<AdhesiveBranch, Error> {
    let p = setup.params;
    if !setup.scene_full.stiffness_given {
        return Err(InputError::Conflict(format!(
            "{}: the steady branch in V is traced at the rig's stiffness, and the scene gives no \
             K [N/m]",
            setup.scene
        ))
        .into());
    }
    let (lo, hi) = setup.scene_full.nu_range;
    let nus = steady::grid(lo, hi, PER_DECADE);
    let (points, hopf_points) = with_model!(setup.model_kind, b => steady::branch(b, &p, &nus))?;
    Ok(AdhesiveBranch {
        hopf_points_um_s: hopf_points
            .iter()
            .map(|h| setup.units.velocity_um_s(h.nu))
            .collect(),
        points: steady_records(points, &setup.units),
        orbit_inertia_ratio: setup.orbit_inertia,
        setup,
        hopf_points,
        complete: true,
        stop: None,
    })
}

/// A Bautin point of the diagram with its physical values beside.
#[derive(Clone, Debug, Serialize)]
pub struct BautinRecord {
    #[serde(flatten)]
    pub point: Bautin,
    #[serde(rename = "V_um_per_s")]
    pub v_um_per_s: f64,
    #[serde(rename = "K_N_per_m")]
    pub k_n_per_m: f64,
}

/// The result of `diagram`: the critical stiffness across `V_range`.
#[derive(Clone, Debug, Serialize)]
pub struct AdhesiveDiagram {
    #[serde(flatten)]
    pub setup: AdhesiveSetup,
    pub points: Vec<OnsetRecord>,
    /// Where the onset type changes between grid points (Bautin points),
    /// located by bisection.
    pub bautin_points: Vec<BautinRecord>,
    /// The steady branch at the scene's velocities (for the friction figure).
    pub steady: Vec<SteadyRecord>,
    /// The scene's own K and V against the diagram, and the verdict
    /// (`null` without `K`): as the rate-and-state `diagram` judges it, in
    /// the scene's own model (`hopf`'s and `cycles`').
    pub operating_point: Option<OperatingPoint>,
    /// Where the diagram's model (over `V_range`) is not the scene's own
    /// (`scene_model`): `K_c` at the scene's `V` in the diagram's model,
    /// N/m, beside the operating point's in the scene's (`null` where the
    /// two models are one).
    #[serde(rename = "curve_K_c_at_V_N_per_m")]
    pub curve_k_c_at_v_n_per_m: Option<f64>,
    /// As `hopf`'s ([`AdhesiveHopf::orbit_inertia_ratio`]).
    pub orbit_inertia_ratio: Option<f64>,
    pub complete: bool,
    /// Why the run ended short of the protocol's end (`null`: it delivered
    /// all): a failed integration or a stop signal, the steps before kept.
    pub stop: Option<String>,
}

/// The onset at the scene's velocity and the scene's stiffness against it:
/// the one verdict `hopf`, `diagram` and `cycles` give ([`verdict`]).
#[derive(Clone, Debug)]
pub struct Verdict {
    /// The onset located in the setup's model ([`find_onset`]).
    pub outcome: OnsetOutcome,
    /// The scene's K against it; `None` without `K`.
    pub operating_point: Option<OperatingPoint>,
}

impl Verdict {
    /// The regime in `hopf`'s words: `stick-slip`, `steady sliding`,
    /// `bistable`, `undecided: <why>`; `None` without `K`.
    pub fn regime_words(&self) -> Option<String> {
        self.operating_point.as_ref().map(|op| match op.regime {
            Regime::StickSlip => "stick-slip".to_string(),
            Regime::Steady => "steady sliding".to_string(),
            Regime::Bistable => "bistable".to_string(),
            Regime::Undecided => format!("undecided: {}", op.reason),
        })
    }
}

/// The onset at the scene's velocity, located in the setup's model
/// ([`find_onset`]), and the scene's stiffness against it, judged as the
/// rate-and-state diagram judges its operating point ([`judge`]:
/// stick-slip below `K_c`; above it steady sliding with a supercritical
/// onset, undecided with a subcritical one, whose fold of cycles `cycles`
/// locates; without an onset, undecided ([`judge_without_onset`]): steady
/// sliding is linearly stable at every stiffness, and `cycles` simulates
/// the scene from a stick to tell whether stick-slip coexists). With the
/// quasi-static model and a mass, `K` above the quasi-static `K_c` by less
/// than the factor `1 + chi` inertia adds is undecided. Every adhesive
/// command takes its verdict from here.
pub fn verdict(setup: &AdhesiveSetup) -> Result<Verdict, Error> {
    let p = setup.params;
    let outcome = with_model!(setup.scene_model_kind, b => find_onset(b, &p))?;
    let operating_point = judge_scene(setup, &outcome, None);
    Ok(Verdict {
        outcome,
        operating_point,
    })
}

/// The scene's stiffness against `outcome` ([`verdict`]), with the fold of
/// cycles `fold` of a subcritical onset where `cycles` located one on its
/// branch (`None`: not looked for); `None` without `K`.
fn judge_scene(
    setup: &AdhesiveSetup,
    outcome: &OnsetOutcome,
    fold: Option<FoldAt>,
) -> Option<OperatingPoint> {
    let (p, u) = (setup.params, setup.units);
    if !setup.scene_full.stiffness_given {
        return None;
    }
    let (lo, hi) = setup.scene_full.nu_range;
    let mut op = OperatingPoint::unjudged(
        (u.stiffness_n_m(p.kappa), p.kappa),
        (u.velocity_um_s(p.nu), p.nu),
        lo <= p.nu && p.nu <= hi,
    );
    let onset = match outcome {
        _ if p.kappa == 0.0 => return Some(op),
        OnsetOutcome::Found(onset) => onset,
        OnsetOutcome::StableForAllStiffness { .. } => {
            let (regime, reason) = judge_without_onset(p.kappa, None);
            op.regime = regime;
            op.reason = reason;
            return Some(op);
        }
    };
    let at = StabilityAt {
        kappa_c: onset.kappa_c,
        criticality: onset.onset,
        tolerance: ((onset.kappa_c - onset.kappa_c_closed_form) / onset.kappa_c_closed_form).abs(),
        dropped_inertia: None,
        fold: fold.map(Some),
    };
    let (regime, margin, reason) = judge(p.kappa, &at);
    let chi = block::inertia_ratio(&p);
    let dropped = setup.scene_model_kind == ModelKind::QuasiStatic && p.m > 0.0;
    let (regime, reason) = if dropped && margin > 0.0 && margin <= chi + at.tolerance {
        (
            Regime::Undecided,
            format!(
                "K exceeds the quasi-static K_c by less than the factor 1 + chi the dropped \
                 inertia adds (chi = {chi:.3e}): rerun with --model inertial"
            ),
        )
    } else {
        (regime, reason)
    };
    op.regime = regime;
    op.reason = reason;
    op.margin = Some(margin);
    op.kappa_c = Some(onset.kappa_c);
    op.k_c_n_per_m = Some(u.stiffness_n_m(onset.kappa_c));
    op.model = Some(setup.scene_model_kind.name());
    op.kappa_fold = fold.map(|f| f.kappa);
    op.kappa_fold_error = fold.map(|f| f.error);
    Some(op)
}

/// `diagram` on an adhesive scene.
pub fn diagram(setup: AdhesiveSetup) -> Result<AdhesiveDiagram, Error> {
    let p = setup.params;
    let (lo, hi) = setup.scene_full.nu_range;
    let nus = steady::grid(lo, hi, PER_DECADE);
    let threshold = setup.inertia_threshold;
    let mut points = with_model!(setup.model_kind, b => steady::diagram(b, &p, &nus, threshold))?;
    // Each point's verdict is `hopf`'s there: inertia also where it
    // changes the onset type.
    if p.m > 0.0 {
        if let Some(changes) = onset_type_changes(&p, &nus) {
            for (point, change) in points.iter_mut().zip(changes) {
                point.needs_inertia |= change == Some(true);
            }
        }
    }
    let (steady, _) = with_model!(setup.model_kind, b => steady::branch(b, &p, &nus))?;
    let u = setup.units;
    let mut bautin_points = Vec::new();
    for w in points.windows(2) {
        if w[0].onset.is_some() && w[1].onset.is_some() && w[0].onset != w[1].onset {
            let located =
                with_model!(setup.model_kind, b => steady::bautin(b, &p, (&w[0], &w[1])))?;
            bautin_points.extend(located.map(|point| BautinRecord {
                v_um_per_s: u.velocity_um_s(point.nu),
                k_n_per_m: u.stiffness_n_m(point.kappa_c),
                point,
            }));
        }
    }
    // Only the diagram has a range the scene's velocity may lie outside.
    let operating_point = verdict(&setup)?.operating_point.map(|mut op| {
        op.reason = op.with_range_note(op.reason.clone());
        op
    });
    let curve_k_c = match setup.scene_model {
        Some(_) => match with_model!(setup.model_kind, b => find_onset(b, &p))? {
            OnsetOutcome::Found(onset) => Some(u.stiffness_n_m(onset.kappa_c)),
            OnsetOutcome::StableForAllStiffness { .. } => None,
        },
        None => None,
    };
    Ok(AdhesiveDiagram {
        operating_point,
        curve_k_c_at_v_n_per_m: curve_k_c,
        orbit_inertia_ratio: setup.orbit_inertia,
        bautin_points,
        points: points
            .into_iter()
            .map(|point| OnsetRecord {
                v_um_per_s: u.velocity_um_s(point.nu),
                k_n_per_m: point.kappa_c.map(|k| u.stiffness_n_m(k)),
                frequency_hz: point
                    .omega_c
                    .map(|w| w / (2.0 * std::f64::consts::PI * u.tau_out)),
                point,
            })
            .collect(),
        steady: steady_records(steady, &u),
        setup,
        complete: true,
        stop: None,
    })
}

/// The result of `cycles`.
#[derive(Clone, Debug, Serialize)]
pub struct AdhesiveCycles {
    #[serde(flatten)]
    pub setup: AdhesiveSetup,
    /// `cycles` (a branch from the onset) or `stable_for_all_stiffness`
    /// (no onset at this velocity, hence no branch: `reason` says what
    /// the simulation from a stick found).
    pub status: &'static str,
    /// The onset the branch starts from (`null` without one).
    pub onset: Option<AdhesiveOnset>,
    /// The scene's K against the onset, as `hopf` and `diagram` judge it
    /// ([`verdict`]); without an onset, what the simulation from a stick
    /// settled on decides it.
    pub operating_point: Option<OperatingPoint>,
    /// Why there is no branch (`null` with one).
    pub reason: Option<String>,
    /// On the quasi-static orbit at the branch's end, the largest shift of
    /// `ln v` the dropped inertia force makes (`null` where not judged: a
    /// block inertial at `V`, forced, or without mass); at or above the
    /// inertia threshold the branch runs inertial (`model_reason`).
    pub orbit_inertia_ratio: Option<f64>,
    pub cycles: Vec<AdhesiveCycle>,
    /// The cycle at the scene's stiffness by collocation (without `K`: at
    /// the branch's end); where the branch passes that stiffness twice
    /// (bistable, between `K_c` and the fold of cycles) the stable one.
    pub at_scene: Option<AdhesiveCycle>,
    /// Why there is no cycle at the scene's `K` (`null` with one, or
    /// without `K`): steady sliding alone there (above a supercritical
    /// `K_c` or above the fold of cycles), or the branch did not reach it.
    pub at_scene_reason: Option<String>,
    /// The folds of cycles on the branch (`lpc`).
    pub folds: Vec<CycleFold>,
    /// The same by simulation (settled stick-slip): the second method.
    pub simulated: Option<SettledCycle>,
    pub complete: bool,
    pub stop: Option<String>,
    /// Whether a stop signal ended the branch.
    #[serde(skip)]
    pub interrupted: bool,
}

/// `cycles` on an adhesive scene: from the onset down to the scene's
/// stiffness, with the limits `(max_steps, ntst_max)` of the branch.
pub fn cycles(setup: AdhesiveSetup, limits: (usize, usize)) -> Result<AdhesiveCycles, Error> {
    cycles_watched(setup, limits, &mut |_| true)
}

/// [`cycles`] with `watch` shown each cycle as it is computed; returning
/// `false` stops the branch there (a stop signal: no simulation follows,
/// and the result is partial).
pub fn cycles_watched(
    setup: AdhesiveSetup,
    limits: (usize, usize),
    watch: &mut dyn FnMut(&AdhesiveCycle) -> bool,
) -> Result<AdhesiveCycles, Error> {
    let p = setup.params;
    let judged = verdict(&setup)?;
    if let OnsetOutcome::StableForAllStiffness { steady_slope } = judged.outcome {
        return without_onset(setup, judged.operating_point, steady_slope);
    }
    let orbit_inertia = setup.orbit_inertia;
    let Verdict {
        outcome: OnsetOutcome::Found(onset),
        mut operating_point,
    } = judged
    else {
        return Err(NumericalError::Analysis(
            "the inertial block has no onset where the quasi-static one has (the factor 1 + chi \
             keeps kappa_c's sign): rerun with --model quasi-static"
                .into(),
        )
        .into());
    };
    let kind = setup.model_kind;
    let target = target_stiffness(&setup.scene_full, onset.kappa_c);
    // The scene's own K, where it has one: below K_c it is the branch's
    // end; above it the branch of a subcritical onset may pass it (rising
    // to the fold of cycles, then back down), and the cycle there is
    // located on the way. Above a supercritical onset's K_c there is
    // steady sliding only: no cycle is looked for.
    let scene_k = (setup.scene_full.stiffness_given && p.kappa > 0.0).then_some(p.kappa);
    let above = scene_k.filter(|k| *k >= onset.kappa_c);
    let wanted = match above {
        Some(_) => onset.onset == Criticality::Subcritical,
        None => true,
    };
    let at = match (above, wanted) {
        (Some(k), true) => k,
        _ => target,
    };
    let run = with_model!(kind, b => cycles::trace(b, &p, &onset, (target, at), limits, watch))?;
    let at_scene = run.at_scene.clone().filter(|_| wanted);
    let mut q = p;
    q.kappa = at_scene.as_ref().map_or(target, |c| c.kappa);
    // The second method: a simulation at the stiffness of the cycle
    // reported (below K_c from steady sliding, which is unstable there;
    // above it from a stick, every chain bonded, as a rig started from
    // rest). Its failure leaves the branch computed, the answer partial.
    let (simulated, simulation_failed) =
        if run.interrupted || (above.is_some() && at_scene.is_none()) {
            (None, None)
        } else {
            let x = with_model!(kind, b => block::AdhesiveModel::steady(&b, &q));
            let start = if q.kappa >= onset.kappa_c {
                1.0
            } else {
                x[x.len() - 1] * 0.99
            };
            match with_model!(kind, b => settle(b, &q, start, 30)) {
                (SettledRegime::Periodic, cycle, _) => (cycle, None),
                (
                    _,
                    _,
                    Run {
                        stop: Some(why), ..
                    },
                ) => (
                    None,
                    Some(format!(
                    "the simulation at K = {:.6e} N/m (the second method) did not finish: {why}",
                    setup.units.stiffness_n_m(q.kappa)
                )),
                ),
                _ => (None, None),
            }
        };
    // A subcritical onset's branch turns at a fold of cycles above K_c:
    // the scene's K is judged against the largest one (the upper edge of
    // the hysteretic band), as the rate-and-state diagram judges it.
    let fold = run
        .folds
        .iter()
        .map(|f| FoldAt {
            kappa: f.cycle.kappa,
            error: f.error_estimate.max(TOLERANCE) * f.cycle.kappa,
        })
        .max_by(|a, b| a.kappa.total_cmp(&b.kappa));
    if fold.is_some() {
        operating_point = judge_scene(&setup, &OnsetOutcome::Found(onset.clone()), fold);
    }
    // Where the scene's K has no cycle, why; a K in the bistable band the
    // branch did not pass again leaves the answer partial.
    let u = setup.units;
    let regime = operating_point.as_ref().map(|op| op.regime);
    let (at_scene_reason, missing) = match (scene_k, &at_scene) {
        (Some(k), None) => {
            let at = format!("no cycle at the scene's K = {:.6e} N/m", u.stiffness_n_m(k));
            if !wanted {
                (
                    Some(format!(
                        "{at}: K is above K_c = {:.6e} N/m of a supercritical onset, where \
                         steady sliding is stable and no cycle coexists near the onset",
                        u.stiffness_n_m(onset.kappa_c)
                    )),
                    false,
                )
            } else if regime == Some(Regime::Steady) {
                let fold = fold.map_or(String::new(), |f| {
                    format!(
                        " (the fold of cycles at K = {:.6e} N/m)",
                        u.stiffness_n_m(f.kappa)
                    )
                });
                (
                    Some(format!(
                        "{at}: K is above the largest stiffness the branch's cycles reach{fold}, \
                         so steady sliding is the only regime there"
                    )),
                    false,
                )
            } else {
                let why = run.stop.clone().unwrap_or_else(|| {
                    "the branch reached its end without passing this stiffness again".to_string()
                });
                (
                    Some(format!(
                        "{at}: the branch from the onset did not pass it on its way down ({why})"
                    )),
                    true,
                )
            }
        }
        _ => (None, false),
    };
    let stop = [
        run.stop.clone(),
        simulation_failed,
        at_scene_reason
            .clone()
            .filter(|_| missing && run.stop.is_none()),
    ]
    .into_iter()
    .flatten()
    .collect::<Vec<_>>();
    Ok(AdhesiveCycles {
        status: "cycles",
        onset: Some(onset),
        operating_point,
        reason: None,
        orbit_inertia_ratio: orbit_inertia,
        complete: stop.is_empty(),
        stop: (!stop.is_empty()).then(|| stop.join("; ")),
        interrupted: run.interrupted,
        cycles: run.cycles.into_iter().map(|c| c.in_units(&u)).collect(),
        at_scene: at_scene.map(|c| c.in_units(&u)),
        at_scene_reason,
        folds: run
            .folds
            .into_iter()
            .map(|f| CycleFold {
                cycle: f.cycle.in_units(&u),
                ..f
            })
            .collect(),
        simulated,
        setup,
    })
}

/// `cycles` where steady sliding is stable at every stiffness (steady
/// friction rises with the velocity, `dF_ss/du = steady_slope >= 0`): no
/// Hopf point, hence no branch. The scene is simulated at its stiffness
/// from a stick (every chain bonded, `n = 1`: the largest static force
/// the law allows) to tell whether stick-slip coexists with steady
/// sliding: a run that settles on steady sliding is the answer (no
/// stick-slip at this velocity); one that settles on stick-slip finds a
/// coexisting cycle this family does not continue (partial); an
/// undetermined one leaves the question open (partial).
fn without_onset(
    setup: AdhesiveSetup,
    mut operating_point: Option<OperatingPoint>,
    steady_slope: f64,
) -> Result<AdhesiveCycles, Error> {
    let (p, u) = (setup.params, setup.units);
    let stable = format!(
        "steady friction rises with the velocity at V = {:.6e} µm/s (dF_ss/du = {steady_slope:.3e} \
         F_a / V_s): steady sliding is stable at every stiffness, no Hopf point, so no cycle \
         branch is born here; {}",
        u.velocity_um_s(p.nu),
        setup.weakening()
    );
    let (simulated, reason, complete) = match operating_point.as_mut() {
        Some(op) if p.kappa > 0.0 => {
            let (regime, cycle, run) = with_model!(setup.model_kind, b => settle(b, &p, 1.0, 30));
            let stop = run.stop;
            let at = format!(
                "a simulation at K = {:.6e} N/m from a stick (n = 1) over 30 loading times",
                u.stiffness_n_m(p.kappa)
            );
            let (regime, words, complete) = match (regime, cycle, stop) {
                (SettledRegime::Steady, _, _) => (
                    Regime::Steady,
                    format!("{at} settles on steady sliding: no stick-slip at this velocity"),
                    true,
                ),
                (SettledRegime::Periodic, Some(c), _) => (
                    Regime::Bistable,
                    format!(
                        "{at} settles on stick-slip (period {:.6e} s, force drop {:.6e} N) \
                         coexisting with stable steady sliding; its branch is not traced \
                         (no Hopf point to start it from)",
                        u.time_s(c.period),
                        u.force_n(c.force_drop)
                    ),
                    false,
                ),
                (_, _, Some(why)) => (
                    Regime::Undecided,
                    format!("{at} did not finish ({why}): whether stick-slip coexists is open"),
                    false,
                ),
                _ => (
                    Regime::Undecided,
                    format!(
                        "{at} settles on neither steady sliding nor stick-slip: whether \
                         stick-slip coexists is open; try simulate --protocol with a longer run"
                    ),
                    false,
                ),
            };
            op.regime = regime;
            op.reason = format!(
                "no Hopf point at this velocity: steady sliding is linearly stable at every \
                 stiffness; {words}"
            );
            (
                cycle.filter(|_| regime == Regime::Bistable),
                format!("{stable}; {words}"),
                complete,
            )
        }
        _ => (
            None,
            format!(
                "{stable}; without a spring (K) no simulation tells whether stick-slip coexists"
            ),
            true,
        ),
    };
    Ok(AdhesiveCycles {
        status: "stable_for_all_stiffness",
        onset: None,
        operating_point,
        orbit_inertia_ratio: None,
        stop: (!complete).then(|| reason.clone()),
        reason: Some(reason),
        complete,
        interrupted: false,
        cycles: Vec::new(),
        at_scene: None,
        at_scene_reason: None,
        folds: Vec::new(),
        simulated,
        setup,
    })
}

/// The block at `p` simulated over `loadings` loading times `F_ss / (kappa
/// nu)` from steady sliding with the bond fraction set to `bonds`: what it
/// settled on ([`settled_regime`]), its settled cycle, and the run (its
/// `stop` says why it ended early).
fn settle<B: block::AdhesiveModel>(
    model: B,
    p: &AdhesiveParams,
    bonds: f64,
    loadings: usize,
) -> (SettledRegime, Option<SettledCycle>, Run) {
    let mut x = model.steady(p);
    let last = x.len() - 1;
    x[last] = bonds;
    let duration = loadings as f64 * x[0] / (p.kappa * p.nu);
    let protocol = [Segment { nu: p.nu, duration }];
    let rtol = 1e-8;
    let run = integrate(model, p, &x, &protocol, (rtol, 1_000_000), &|| false);
    let (regime, cycle) = settled_regime(&run, &protocol, rtol);
    (regime, cycle, run)
}

/// The largest [`block::state_imbalance`] over the quasi-static `run` at
/// `p` through `protocol`, each step at its segment's pulling velocity.
fn run_imbalance(p: &AdhesiveParams, run: &Run, protocol: &[Segment]) -> f64 {
    let mut chi = 0.0f64;
    for (k, segment) in protocol.iter().enumerate() {
        let from = run.segment_starts.get(k).copied().unwrap_or(run.t.len());
        let to = run
            .segment_starts
            .get(k + 1)
            .copied()
            .unwrap_or(run.t.len());
        let mut q = *p;
        q.nu = segment.nu;
        for i in from..to.max(from) {
            chi = chi.max(block::state_imbalance(&q, run.u[i], run.n[i]));
        }
    }
    chi
}

/// The largest [`block::state_imbalance`] over the second half of the
/// quasi-static `run` at `p` (its settled orbit).
fn orbit_imbalance(p: &AdhesiveParams, run: &Run) -> f64 {
    let half = run.t.len() / 2;
    run.u[half..]
        .iter()
        .zip(&run.n[half..])
        .map(|(u, n)| block::state_imbalance(p, *u, *n))
        .fold(0.0, f64::max)
}

/// The stiffness the branch is traced down to: the scene's, where it has
/// a spring below the onset `kappa_c`, else half of `kappa_c`.
fn target_stiffness(scene: &AdhesiveScene, kappa_c: f64) -> f64 {
    let p = scene.params;
    if scene.stiffness_given && p.kappa > 0.0 && p.kappa < kappa_c {
        p.kappa
    } else {
        0.5 * kappa_c
    }
}

/// `(kind, reason)` turned inertial where the dropped inertia force shifts
/// `ln u` on the quasi-static orbit `at` by `chi`
/// ([`block::state_imbalance`]), at least the inertia `threshold`, saying
/// why; the check noted where it is below.
fn decide_on_orbit(
    (kind, reason): (ModelKind, String),
    chi: f64,
    threshold: f64,
    at: &str,
) -> (ModelKind, String) {
    if chi >= threshold {
        (
            ModelKind::Inertial,
            format!(
                "inertial: on the quasi-static orbit {at} the dropped inertia force shifts ln v \
                 by up to m |du/dt| / (u F_u) = {chi:.3e}, not below the inertia threshold \
                 {threshold:e}, so the block keeps its inertia (at V alone: {reason})"
            ),
        )
    } else {
        (
            kind,
            format!(
                "{reason}; on the quasi-static orbit {at} the dropped inertia force shifts ln v \
                 by at most {chi:.3e}, below the threshold too"
            ),
        )
    }
}

/// One segment of a protocol: its velocity `nu` and duration (in
/// `tau_out`), and the same in µm/s and s.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct SegmentRecord {
    #[serde(flatten)]
    pub segment: Segment,
    #[serde(rename = "V_um_per_s")]
    pub v_um_per_s: f64,
    pub duration_s: f64,
}

/// The result of `simulate`.
#[derive(Clone, Debug, Serialize)]
pub struct AdhesiveSimulation {
    #[serde(flatten)]
    pub setup: AdhesiveSetup,
    #[serde(skip)]
    pub protocol: Vec<Segment>,
    /// The protocol in the JSON: each segment dimensionless and in the
    /// experimenter's units.
    #[serde(rename = "protocol")]
    pub protocol_record: Vec<SegmentRecord>,
    pub steps: usize,
    /// Per segment: the largest spring force, N, and steady friction at its
    /// velocity, N (a static peak after rest stands above it).
    #[serde(rename = "peak_force_N")]
    pub peak_force_n: Vec<f64>,
    #[serde(rename = "steady_force_N")]
    pub steady_force_n: Vec<f64>,
    /// What the last segment settled on.
    pub regime: SettledRegime,
    /// The settled stick-slip of the last segment, if any.
    pub settled: Option<SettledCycle>,
    pub settled_period_s: Option<f64>,
    #[serde(rename = "settled_force_drop_N")]
    pub settled_force_drop_n: Option<f64>,
    /// The largest shift of `ln v` the dropped inertia force makes on the
    /// quasi-static run (`null` where not judged: inertial at the pulling
    /// velocities, forced, or without mass); at or above the inertia
    /// threshold the run is made again with the block's inertia.
    pub orbit_inertia_ratio: Option<f64>,
    #[serde(skip)]
    pub run: Run,
    pub complete: bool,
    /// Why the run ended short of the protocol's end (`null`: it delivered
    /// all): a failed integration or a stop signal, the steps before kept.
    pub stop: Option<String>,
}

/// What the last segment of a simulation settled on (JSON `regime`, in
/// the words of the rate-and-state `simulate`'s `regime.kind`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SettledRegime {
    /// Stick-slip: a cycle between force maxima whose drop stands above
    /// the integration's error.
    Periodic,
    /// Steady sliding: over the segment's second half the spring force
    /// varies by no more than the integration's error.
    Steady,
    /// Neither can be told (too few oscillations, a run that ended early,
    /// or a stop of the drive).
    Undetermined,
}

/// The size of the integration's error in the spring force: `1e3 rtol
/// max|s|` (the relative tolerance of each step, with room for its
/// accumulation over the steps).
fn force_noise_floor(run: &Run, rtol: f64) -> f64 {
    1e3 * rtol * run.s.iter().fold(0.0f64, |a, s| a.max(s.abs()))
}

/// What the last segment of `run` (integrated at `rtol` through
/// `protocol`) settled on, and its settled cycle: the cycle only when the
/// run reached its end, and only when its force drop stands above the
/// integration's error (at steady sliding the force's extremes are
/// rounding, and a "cycle" between them is no stick-slip).
fn settled_regime(
    run: &Run,
    protocol: &[Segment],
    rtol: f64,
) -> (SettledRegime, Option<SettledCycle>) {
    let last = protocol.len() - 1;
    let floor = force_noise_floor(run, rtol);
    let settled = run
        .stop
        .is_none()
        .then(|| run.settled(last))
        .flatten()
        .filter(|c| c.force_drop > floor);
    let regime = match (&run.stop, settled) {
        (Some(_), _) => SettledRegime::Undetermined,
        (None, Some(_)) => SettledRegime::Periodic,
        (None, None) if protocol[last].nu > 0.0 && run.force_range(last, 0.5) <= floor => {
            SettledRegime::Steady
        }
        (None, None) => SettledRegime::Undetermined,
    };
    (regime, settled)
}

/// `simulate` on an adhesive scene under `protocol` (`(V [um/s], T [s])`;
/// default: the scene's velocity for 30 loading times).
pub fn simulate(
    setup: AdhesiveSetup,
    protocol: Option<Vec<(f64, f64)>>,
    perturb: f64,
    rtol: f64,
    max_steps: usize,
) -> Result<AdhesiveSimulation, Error> {
    simulate_watched(setup, protocol, (perturb, rtol, max_steps), &|| false)
}

/// [`simulate`] asking `stop` after every step whether to end there (a stop
/// signal); the steps taken are kept either way, and a run that ended
/// early (stopped, or its integration failed) is partial (`complete`
/// false, `stop` says why).
pub fn simulate_watched(
    setup: AdhesiveSetup,
    protocol: Option<Vec<(f64, f64)>>,
    (perturb, rtol, max_steps): (f64, f64, usize),
    stop: &dyn Fn() -> bool,
) -> Result<AdhesiveSimulation, Error> {
    let p = setup.params;
    let u = setup.units;
    if !setup.scene_full.stiffness_given || p.kappa == 0.0 {
        return Err(InputError::Conflict(format!(
            "{}: a simulation needs the rig's stiffness; give K [N/m] (> 0) in the scene",
            setup.scene
        ))
        .into());
    }
    if !(rtol > 1e-14 && rtol < 1.0) {
        return Err(InputError::out_of_range("--rtol", rtol, "in (1e-14, 1)").into());
    }
    let kind = setup.model_kind;
    let x_ss = block::steady_state(&p);
    let protocol: Vec<Segment> = match protocol {
        Some(list) => list
            .into_iter()
            .map(|(v, t)| Segment {
                nu: u.nu_of_velocity_um_s(v),
                duration: t / u.tau_out,
            })
            .collect(),
        None => vec![Segment {
            nu: p.nu,
            duration: 30.0 * x_ss[0] / (p.kappa * p.nu),
        }],
    };
    let mut start = p;
    start.nu = protocol
        .iter()
        .map(|s| s.nu)
        .find(|nu| *nu > 0.0)
        .unwrap_or(p.nu);
    let mut x = with_model!(kind, b => block::AdhesiveModel::steady(&b, &start));
    let last = x.len() - 1;
    x[last] *= 1.0 + perturb;
    if !(x[last] > 0.0 && x[last] <= 1.0) {
        return Err(InputError::out_of_range(
            "--perturb",
            perturb,
            "a relative change of the bond fraction that keeps it in (0, 1]",
        )
        .into());
    }
    let mut run = with_model!(kind, b => integrate(b, &p, &x, &protocol, (rtol, max_steps), stop));
    // The model judged on the whole run too ([`decide_on_orbit`]): a
    // quasi-static run the dropped inertia would change is run again with it.
    let mut setup = setup;
    let judged = kind == ModelKind::QuasiStatic && !setup.forced && p.m > 0.0;
    let orbit_inertia = (judged && !run.interrupted).then(|| {
        let chi = run_imbalance(&p, &run, &protocol);
        let reason = std::mem::take(&mut setup.model_reason);
        let threshold = setup.inertia_threshold;
        let (kind, reason) = decide_on_orbit((kind, reason), chi, threshold, "of this run");
        setup.model_kind = kind;
        setup.model = kind.name();
        setup.scene_model_kind = kind;
        setup.model_reason = reason;
        chi
    });
    if setup.model_kind != kind {
        let mut x = block::AdhesiveModel::steady(&block::InertialAdhesiveBlock, &start);
        let last = x.len() - 1;
        x[last] *= 1.0 + perturb;
        run = integrate(
            block::InertialAdhesiveBlock,
            &p,
            &x,
            &protocol,
            (rtol, max_steps),
            stop,
        );
    }
    if run.t.is_empty() {
        return Err(NumericalError::Analysis(
            run.stop
                .unwrap_or_else(|| "the integration took no step".to_string()),
        )
        .into());
    }
    let segment_of = |t: f64| {
        let mut end = 0.0;
        protocol
            .iter()
            .position(|s| {
                end += s.duration;
                t <= end
            })
            .unwrap_or(protocol.len() - 1)
    };
    let mut peak = vec![f64::NEG_INFINITY; protocol.len()];
    for (t, s) in run.t.iter().zip(&run.s) {
        let i = segment_of(*t);
        peak[i] = peak[i].max(*s);
    }
    let (regime, settled) = settled_regime(&run, &protocol, rtol);
    Ok(AdhesiveSimulation {
        protocol_record: protocol
            .iter()
            .map(|&segment| SegmentRecord {
                segment,
                v_um_per_s: u.velocity_um_s(segment.nu),
                duration_s: u.time_s(segment.duration),
            })
            .collect(),
        steps: run.t.len(),
        peak_force_n: peak.iter().map(|s| u.force_n(*s)).collect(),
        steady_force_n: protocol
            .iter()
            .map(|s| {
                if s.nu > 0.0 {
                    u.force_n(block::steady_friction(s.nu, &p))
                } else {
                    0.0
                }
            })
            .collect(),
        regime,
        settled_period_s: settled.map(|c| u.time_s(c.period)),
        settled_force_drop_n: settled.map(|c| u.force_n(c.force_drop)),
        settled,
        setup,
        protocol,
        orbit_inertia_ratio: orbit_inertia,
        complete: run.stop.is_none(),
        stop: run.stop.clone(),
        run,
    })
}
