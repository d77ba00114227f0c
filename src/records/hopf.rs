//! The record of `hopf`: the stick-slip onset of a scene (the Hopf point,
//! its normal form, Appendix C beside it, physical units), or why there is
//! none.

use super::PhysicalPoint;
use crate::analysis::hopf::{Arithmetic, Criticality, HopfOutcome, HopfPoint};
use crate::analysis::operating_point::{judge, judge_without_onset, Regime, StabilityAt};
use crate::appendix_c;
use crate::jobs::Setup;
use crate::model::ModelKind;
use crate::params::Params;
use crate::records::{params_json, UnitsRecord};
use crate::scene::Units;
use serde::Serialize;

/// The onset of a scene: the JSON of `hopf`, and what its text shows.
#[derive(Clone, Debug, Serialize)]
pub struct HopfReport {
    pub scene: String,
    pub model: ModelKind,
    pub model_reason: String,
    /// `m nu^2 / mu_v`, which chose the model.
    pub inertia_ratio: f64,
    /// The parameters, `kappa = kappa_c` (`null` without an onset: the
    /// stiffness is what was searched for).
    pub params: serde_json::Value,
    /// The slope of the force in `ln v` at steady sliding, with the
    /// damping's `eta_d nu` (docs/model.md: the `mu_v` of Appendix C with
    /// radiation damping).
    pub mu_v: f64,
    pub mu_phi: f64,
    #[serde(flatten)]
    pub outcome: HopfStatus,
    /// Where the scene's stiffness (its `K`, or `--set K` / `--set kappa`)
    /// lies with respect to the onset; `null` when none is given, and with
    /// `--param` other than `K` or `kappa` (then `critical` places the
    /// scene's value of that parameter).
    pub operating_point: Option<OperatingPoint>,
    /// The onset in the control parameter of `hopf --param` (absent without it).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub critical: Option<Critical>,
    /// The scene's length and velocity scales.
    pub units: UnitsRecord,
    /// Always `true`: a search that does not answer is an error, with no
    /// report (the fields every command's JSON has).
    pub complete: bool,
    /// Always `null` (see `complete`).
    pub stop: Option<String>,
    /// The written point whose parameters these are (`hopf --from
    /// FILE.json --index N`); absent otherwise.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub restarted_from: Option<crate::jobs::restart::RestartRecord>,
}

/// The onset in a control parameter (`hopf --param P`): its critical value
/// with everything else at the scene's values, and the onset type there.
#[derive(Clone, Debug, Serialize)]
pub struct Critical {
    /// The control parameter (`K`, `V`, `M`, `W`, `tau`, or a dimensionless name).
    pub param: &'static str,
    /// Its critical value, in `unit`.
    pub value: f64,
    /// `N/m`, `um/s`, `kg`, `N`, `s`, or `1` (dimensionless).
    pub unit: &'static str,
    /// The dimensionless parameters it moves, at the onset (`V` gives `nu`).
    pub dimensionless: serde_json::Value,
    /// The scene's own value of the parameter (after `--set`).
    pub scene_value: f64,
    /// `(scene_value - value) / value`.
    pub margin: f64,
    /// The range searched `[lo, hi]` in `unit`; `null` for the stiffness
    /// paths, searched from a stable stiffness downward as `hopf` does.
    pub range: Option<[f64; 2]>,
    /// First Lyapunov coefficient at the onset, its bound, and the onset
    /// type, as in the report's `l1` and `criticality`.
    pub l1: f64,
    pub l1_error_bound: f64,
    pub criticality: Criticality,
    /// How the onset was located.
    pub method: String,
}

impl Critical {
    /// The onset `o` in its control, with the scene's value `scene_value`.
    pub fn new(o: &crate::analysis::control::OnsetIn, scene_value: f64) -> Self {
        let dimensionless = serde_json::Value::Object(
            o.control
                .moves(&o.units)
                .into_iter()
                .map(|p| (p.name().to_string(), serde_json::json!(o.params.get(p))))
                .collect(),
        );
        Critical {
            param: o.control.name(),
            value: o.value,
            unit: o.control.unit(),
            dimensionless,
            scene_value,
            margin: (scene_value - o.value) / o.value,
            range: o.range.map(|(lo, hi)| [lo, hi]),
            l1: o.hopf.onset.l1,
            l1_error_bound: o.hopf.onset.l1_error_bound,
            criticality: o.hopf.onset.criticality,
            method: o.method.clone(),
        }
    }
}

/// The scene's own stiffness against the onset (JSON `operating_point`).
#[derive(Clone, Debug, Serialize)]
pub struct OperatingPoint {
    /// The spring stiffness `K = kappa W / D0` [N/m].
    #[serde(rename = "K_N_per_m")]
    pub k_n_per_m: f64,
    /// The same, dimensionless.
    pub kappa: f64,
    pub regime: Regime,
    /// `(K - K_c) / K_c`; `null` without an onset.
    pub margin: Option<f64>,
    /// Why this regime, in words.
    pub reason: String,
}

impl OperatingPoint {
    /// The stiffness `kappa` of `setup` against the onset `outcome` (the
    /// onset of `setup.params`, of the chosen model).
    pub fn new(setup: &Setup, outcome: &HopfOutcome, kappa: f64) -> Self {
        let k = setup.scene.units.stiffness(kappa);
        let (regime, margin, reason) = match outcome {
            _ if kappa == 0.0 => (
                Regime::Undecided,
                None,
                "K = 0: no spring, hence no steady sliding driven through it".to_string(),
            ),
            HopfOutcome::StableForAllStiffness { .. } => {
                let (regime, reason) = judge_without_onset(kappa, None);
                (regime, None, reason)
            }
            HopfOutcome::Found(h) => {
                // The fold of cycles is not looked for here (`diagram` and
                // `cycles` locate it): a subcritical onset above K_c is undecided.
                let onset = StabilityAt::located(
                    setup.choice.kind,
                    &setup.scene_params,
                    &setup.params,
                    (h.kappa_c, h.onset.criticality),
                    None,
                );
                let (regime, margin, reason) = judge(kappa, &onset);
                (regime, Some(margin), reason)
            }
        };
        OperatingPoint {
            k_n_per_m: k,
            kappa,
            regime,
            margin,
            reason,
        }
    }
}

/// The outcome (JSON `status`: `hopf` or `stable_for_all_stiffness`).
#[derive(Clone, Debug, Serialize)]
#[serde(tag = "status", rename_all = "snake_case")]
pub enum HopfStatus {
    Hopf(Box<Onset>),
    StableForAllStiffness(NoOnset),
}

/// A located Hopf point: the stick-slip onset.
#[derive(Clone, Debug, Serialize)]
pub struct Onset {
    /// Critical stiffness `kappa_c = K_c D0 / W`.
    pub kappa_c: f64,
    /// Angular frequency at onset (units `V0/D0`).
    pub omega_c: f64,
    /// Steady sliding at onset.
    pub state: State,
    /// `[re, im]` of the eigenvalues, by decreasing real part.
    pub eigenvalues: Vec<[f64; 2]>,
    pub appendix_c: AppendixC,
    pub physical: Physical,
    /// First Lyapunov coefficient (docs/model.md's convention).
    pub l1: f64,
    /// Size of the terms `l1` is made of.
    pub l1_term_scale: f64,
    /// Bound on the rounding error of `l1`.
    pub l1_error_bound: f64,
    pub l1_arithmetic: Arithmetic,
    pub criticality: Criticality,
    /// `C` in `Delta_s ~ C sqrt|kappa - kappa_c|`; `None` when degenerate.
    pub amplitude_coefficient: Option<f64>,
    pub onset: NormalForm,
    pub location: Location,
}

/// The steady state `(s, v, theta)`.
#[derive(Clone, Debug, Serialize)]
pub struct State {
    pub s: f64,
    pub v: f64,
    pub theta: f64,
}

/// Appendix C's closed forms beside the located point.
#[derive(Clone, Debug, Serialize)]
pub struct AppendixC {
    /// Eq. C11 (inertial) or C12 (quasi-static).
    pub kappa_c: f64,
    /// Eq. C13.
    pub omega_c: f64,
    pub kappa_c_rel_diff: f64,
    pub omega_c_rel_diff: f64,
}

/// The onset in physical units.
#[derive(Clone, Debug, Serialize)]
pub struct Physical {
    #[serde(flatten)]
    pub at: PhysicalPoint,
    /// Critical spring stiffness `K_c` [N/m].
    #[serde(rename = "K_N_per_m")]
    pub k_n_per_m: f64,
    /// `C'` in `Delta_s ~ C' sqrt|K/W - K_c/W|` [m^1/2].
    pub amplitude_coefficient_sqrt_m: Option<f64>,
    /// `d f / d(K/W)` of the emerging cycle's frequency [Hz m].
    pub frequency_slope_hz_m: Option<f64>,
}

/// The normal form at onset.
#[derive(Clone, Debug, Serialize)]
pub struct NormalForm {
    /// `[re, im]` of the cubic coefficient `c1`.
    pub c1: [f64; 2],
    /// `[re, im]` of `d lambda / d kappa` of the critical eigenvalue.
    pub dlambda_dkappa: [f64; 2],
    /// Where the emerging cycle exists; `None` when degenerate.
    pub cycle_side: Option<CycleSide>,
    /// `d Omega / d kappa` of the cycle's angular frequency (units `V0/D0`).
    pub frequency_slope: Option<f64>,
}

/// The side of `kappa_c` where the emerging cycle exists.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum CycleSide {
    /// Below `kappa_c`: the cycle is stable, the onset supercritical.
    #[serde(rename = "kappa < kappa_c")]
    Below,
    /// Above `kappa_c`: the cycle is unstable, the onset hysteretic.
    #[serde(rename = "kappa > kappa_c")]
    Above,
}

/// How the point was located.
#[derive(Clone, Debug, Serialize)]
pub struct Location {
    pub newton_iterations: usize,
    pub residual: f64,
    /// Continuation steps from a stable stiffness before the point was bracketed.
    pub continuation_steps: usize,
}

/// No onset: steady sliding is stable for every stiffness searched.
#[derive(Clone, Debug, Serialize)]
pub struct NoOnset {
    /// Always `None`: there is no critical stiffness.
    pub kappa_c: Option<f64>,
    /// Always `None`.
    pub omega_c: Option<f64>,
    /// The smallest stiffness searched.
    pub kappa_min_checked: f64,
    #[serde(rename = "K_over_W_min_checked_per_m")]
    pub k_over_w_min_checked_per_m: f64,
    pub appendix_c: AppendixCBound,
}

/// Appendix C without an onset.
#[derive(Clone, Debug, Serialize)]
pub struct AppendixCBound {
    /// Eq. C11/C12 where steady friction weakens (`mu_phi > mu_v`); else
    /// `None`, no onset rather than a negative one.
    pub kappa_c: Option<f64>,
}

/// Relative difference `|a - b| / |b|`.
fn rel_diff(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

impl HopfReport {
    /// The outcome of the onset search on `setup`.
    pub fn new(setup: &Setup, outcome: &HopfOutcome) -> Self {
        let mut at = setup.params;
        if let HopfOutcome::Found(h) = outcome {
            at.kappa = h.kappa_c;
        }
        let mut params = params_json(&at);
        let u = &setup.scene.units;
        let given = setup.stiffness_given();
        let operating_point =
            given.then(|| OperatingPoint::new(setup, outcome, setup.scene_params.kappa));
        let outcome = match outcome {
            HopfOutcome::Found(h) => HopfStatus::Hopf(Box::new(Onset::new(h, &at, u))),
            HopfOutcome::StableForAllStiffness { kappa_min } => {
                params["kappa"] = serde_json::Value::Null;
                let kappa_ref = appendix_c::critical_stiffness(&at);
                HopfStatus::StableForAllStiffness(NoOnset {
                    kappa_c: None,
                    omega_c: None,
                    kappa_min_checked: *kappa_min,
                    k_over_w_min_checked_per_m: u.k_over_w(*kappa_min),
                    appendix_c: AppendixCBound {
                        kappa_c: (kappa_ref > 0.0).then_some(kappa_ref),
                    },
                })
            }
        };
        HopfReport {
            operating_point,
            critical: None,
            scene: setup.scene.name.clone(),
            model: setup.choice.kind,
            model_reason: setup.choice.reason.clone(),
            inertia_ratio: setup.choice.inertia_ratio,
            params,
            mu_v: at.mu_v_damped(),
            mu_phi: at.mu_phi(),
            outcome,
            units: UnitsRecord::of(u),
            complete: true,
            stop: None,
            restarted_from: None,
        }
    }
}

impl Onset {
    /// The Hopf point `h` of `p` (at `kappa = kappa_c`) in the units `u`.
    pub fn new(h: &HopfPoint, p: &Params, u: &Units) -> Self {
        let o = &h.onset;
        let kappa_ref = appendix_c::critical_stiffness(p);
        let omega_ref = appendix_c::critical_frequency(p).unwrap_or(f64::NAN);
        Onset {
            kappa_c: h.kappa_c,
            omega_c: h.omega_c,
            state: State {
                s: h.state[0],
                v: h.state[1],
                theta: h.state[2],
            },
            eigenvalues: h.eigenvalues.iter().map(|l| [l.re, l.im]).collect(),
            appendix_c: AppendixC {
                kappa_c: kappa_ref,
                omega_c: omega_ref,
                kappa_c_rel_diff: rel_diff(h.kappa_c, kappa_ref),
                omega_c_rel_diff: rel_diff(h.omega_c, omega_ref),
            },
            physical: Physical {
                at: PhysicalPoint::new(u, p.nu, h.kappa_c, h.omega_c),
                k_n_per_m: u.stiffness(h.kappa_c),
                // kappa = D0 K/W: sqrt|kappa - kappa_c| = sqrt(D0) sqrt|K/W - K_c/W|.
                amplitude_coefficient_sqrt_m: o.amplitude_coefficient.map(|c| c * u.d0.sqrt()),
                // d f / d(K/W) = D0 d f / d kappa.
                frequency_slope_hz_m: o.frequency_slope.map(|s| u.frequency_hz(s) * u.d0),
            },
            l1: o.l1,
            l1_term_scale: o.l1_scale,
            l1_error_bound: o.l1_error_bound,
            l1_arithmetic: o.arithmetic,
            criticality: o.criticality,
            amplitude_coefficient: o.amplitude_coefficient,
            onset: NormalForm {
                c1: [o.c1.re, o.c1.im],
                dlambda_dkappa: [o.dlambda_dkappa.re, o.dlambda_dkappa.im],
                cycle_side: o.side.map(|s| {
                    if s < 0.0 {
                        CycleSide::Below
                    } else {
                        CycleSide::Above
                    }
                }),
                frequency_slope: o.frequency_slope,
            },
            location: Location {
                newton_iterations: h.newton_iterations,
                residual: h.residual,
                continuation_steps: h.steps,
            },
        }
    }
}
