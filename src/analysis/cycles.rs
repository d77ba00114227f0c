//! Stick-slip cycles: branches of periodic orbits continued in the stiffness
//! by collocation in logarithmic variables, either born at the Hopf point or
//! started from a simulated orbit ([`super::sampled_cycle`]) and followed
//! both ways from it.

use crate::analysis::hopf::{
    find_hopf, location_error, resolved_normal_form, HopfOutcome, HopfPoint,
};
use crate::analysis::model_choice::DEFAULT_INERTIA_THRESHOLD;
use crate::analysis::orbit_inertia::{inertial_guess, inertial_imbalance, InertiaWatch};
use crate::analysis::return_map;
use crate::analysis::sampled_cycle::sampled_cycle;
use crate::analysis::settle::SettledOrbit;
use crate::error::NumericalError;
use crate::friction::FrictionLaw;
use crate::log_model::LogBlock;
use crate::model::ModelKind;
use crate::params::{friction_from, Param, Params};
use continuation::normal_form::HopfNormalForm;
use continuation::periodic::CollocationPoints;
use continuation::periodic::Cycle;
pub use continuation::periodic::Stability;
use continuation::periodic::{
    CycleBranch, CycleEvent, CyclePoint, CycleSettings, Discretization, FloquetPolicy,
    WhenUndecidable,
};
use continuation::StepControl;
pub use continuation::Stop;
use continuation::{Complex64, VectorField};

/// Which continuation a cycle comes from (JSON: `from_hopf`, `up`, `down`,
/// `longer_period`, `shorter_period`, `at_stiffness`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Leg {
    /// Born at the Hopf point, growing in amplitude.
    FromHopf,
    /// From a simulated orbit, first toward increasing stiffness.
    Up,
    /// From a simulated orbit, first toward decreasing stiffness.
    Down,
    /// From a fold of cycles restarted from (corrected at its period, where
    /// both legs go the same way in the parameter): toward longer periods.
    LongerPeriod,
    /// From a fold of cycles restarted from: toward shorter periods.
    ShorterPeriod,
    /// Not on a branch: the cycle at a given stiffness, a simulated orbit
    /// corrected there ([`cycle_through_orbit`]).
    AtStiffness,
}

/// One stick-slip cycle in docs/model.md's variables.
#[derive(Clone, Debug)]
pub struct CycleRecord {
    pub kappa: f64,
    /// The full parameter vector of the cycle ([`Param`] order): the
    /// continued parameter of a branch in another parameter than `kappa`
    /// (`cycles --param`) is read from it.
    pub params: Vec<f64>,
    /// Period in units of `D0/V0`.
    pub period: f64,
    /// Peak-to-peak spring force.
    pub delta_s: f64,
    pub s_min: f64,
    pub s_max: f64,
    /// Slowest and fastest slip velocity on the cycle (units of `V0`).
    pub v_min: f64,
    pub v_max: f64,
    /// `ln v_min`: also where `v_min` is below the range of `f64` (deep
    /// sticks of the return map, [`CycleMethod::ReturnMap`]).
    pub ln_v_min: f64,
    /// Floquet multipliers the pencil determined, by decreasing modulus
    /// (fewer than the dimension when it left some undetermined).
    pub multipliers: Vec<Complex64>,
    /// Index of the trivial multiplier in `multipliers`, when determined.
    pub trivial: Option<usize>,
    /// `min |mu - 1|`: rounding in the multipliers (amplified by the
    /// growth of perturbations along stiff cycles); `None` when the pencil
    /// did not determine the trivial multiplier ([`TRIVIAL_UNAVAILABLE`]).
    pub trivial_error: Option<f64>,
    /// Estimated discretization error of the period (relative) and of the
    /// extremes of `s` and `ln v` (relative to their amplitudes,
    /// `Delta_s` and `ln(v_max / v_min)`), at this cycle's stiffness
    /// (comparison with the orbit on half the mesh); `None` when the orbit
    /// could not be solved on half the mesh ([`ESTIMATE_UNAVAILABLE`]).
    pub error_estimate: Option<f64>,
    /// Stable, unstable, or undecidable within the multipliers' error.
    pub stability: Stability,
    /// How the cycle was computed.
    pub method: CycleMethod,
    /// The model the cycle was computed with.
    pub model: ModelKind,
    /// The inertia `m` it was computed with (0 for the quasi-static model).
    pub m: f64,
    /// The least friction coefficient `mu(v, theta)` on the orbit (over its
    /// samples); below zero the friction law has left its physical range
    /// (e.g. `mu2 < 0` at long ages), as has a spring force `s_min < 0`.
    pub friction_min: f64,
    /// The least direct effect `d mu / d ln v = A + 2 mu_vv ln v + mu_vphi
    /// ln theta` on the orbit (over its samples, [`direct_effect_min`]):
    /// where it is not positive, the corrections have taken the law out of
    /// its domain (docs/model.md).
    pub direct_effect_min: f64,
    /// How much inertia matters on this orbit: `chi = max m |dv/dt| / A`
    /// with the scene's `m` ([`super::orbit_inertia`]).
    pub inertial_imbalance: f64,
    /// The orbit sampled over one period: `(t / T, s, ln v, ln theta)` (in
    /// logarithms: a deep stick's `v` may lie below the range of `f64`).
    pub samples: Vec<[f64; 4]>,
    /// A fold of cycles (LPC) located between the previous cycle and this one.
    pub lpc: Option<Box<CycleRecord>>,
    /// A period doubling located there.
    pub pd: Option<Box<CycleRecord>>,
    /// A Neimark–Sacker (torus) bifurcation located there.
    pub ns: Option<Box<CycleRecord>>,
    /// Cycles at the requested stiffnesses (`--at-kappa`) passed since the previous cycle.
    pub user: Vec<CycleRecord>,
    /// Whether this cycle is one of the requested stiffnesses.
    pub user_point: bool,
    /// The continuation it belongs to.
    pub leg: Leg,
    /// The collocated orbit in the variables of `log` (log variables
    /// measured from its origin): to continue a fold in two parameters
    /// ([`crate::analysis::lpc_curve::lpc_curve_through`]) and to write it
    /// for a restart ([`crate::records::orbit::StoredOrbit`]). Every record
    /// is made with it; a job keeping many records drops it
    /// ([`CycleRecord::without_orbit`]).
    pub orbit: Option<Cycle>,
    /// The variables `orbit` is in: the model, the ageing form and the origin.
    pub log: LogBlock,
}

/// How a cycle was computed (JSON `method`: `collocation`, `return_map`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CycleMethod {
    /// Collocation on `ntst` mesh intervals, Floquet multipliers from the
    /// monodromy pencil.
    Collocation { ntst: usize },
    /// A fixed point of the return map of the joined inertial and
    /// quasi-static flow ([`super::return_map`]), where the stick lies
    /// below the resolution of `f64`: multipliers from the map's Jacobian.
    ReturnMap,
}

impl CycleMethod {
    /// `collocation` or `return_map`.
    pub fn name(self) -> &'static str {
        match self {
            CycleMethod::Collocation { .. } => "collocation",
            CycleMethod::ReturnMap => "return_map",
        }
    }
}

/// Why a cycle's trivial-multiplier error is not reported.
pub const TRIVIAL_UNAVAILABLE: &str = "the Floquet pencil is singular to rounding \
     (perturbations grow beyond 1/eps along the cycle) and does not determine the trivial multiplier";

/// Why a cycle of the return map has no trivial-multiplier error.
pub const TRIVIAL_REMOVED: &str = "the return map's section removes the trivial multiplier \
     (it is 1 exactly): the other multipliers are the eigenvalues of the map's Jacobian";

/// Why a cycle's discretization error estimate is not reported.
pub const ESTIMATE_UNAVAILABLE: &str =
    "the orbit could not be solved on half the mesh to compare with";

/// Why a cycle's inertial imbalance `chi` is not reported
/// ([`crate::analysis::orbit_inertia`]).
pub const IMBALANCE_UNDEFINED: &str = "the direct effect d mu / d ln v is not positive on the \
     orbit (direct_effect_min): the friction law is outside its domain there, and the \
     quasi-static reduction whose error chi measures does not exist";

impl CycleRecord {
    /// Why the stability is not decided, or `None` when it is.
    pub fn stability_reason(&self) -> Option<String> {
        let source = match self.method {
            CycleMethod::Collocation { .. } => "10 |mu_trivial - 1|, see trivial_multiplier_error",
            CycleMethod::ReturnMap => {
                "the change of the return map's eigenvalues between difference steps h and 2 h"
            }
        };
        match self.stability {
            Stability::Stable | Stability::Unstable => None,
            Stability::Undecidable { modulus, error } => Some(format!(
                "a nontrivial Floquet multiplier of modulus {modulus:.10} lies within its error \
                 estimate {error:.1e} of the unit circle ({source})"
            )),
            Stability::Undetermined { missing } => Some(format!(
                "{missing} nontrivial Floquet multiplier(s) undetermined: {TRIVIAL_UNAVAILABLE}"
            )),
            Stability::IllConditioned { trivial_error } => Some(format!(
                "rounding swamps the Floquet multipliers: the trivial one is off by {} and \
                 another is that close to the unit circle (perturbations grow by so many decades \
                 along the orbit); the orbit itself is resolved; judge stability by time \
                 integration (`stickslip simulate`)",
                match trivial_error {
                    Some(e) => format!("{e:.1e}"),
                    None => "an undetermined amount (the pencil did not find it)".to_string(),
                }
            )),
        }
    }

    /// The record without its orbit, nor those of its requested cycles,
    /// period doubling and torus bifurcation (a fold keeps its own, for
    /// [`crate::analysis::lpc_curve::lpc_curve_through`]): what a job keeps
    /// for its figures once the orbits are written.
    pub fn without_orbit(&self) -> CycleRecord {
        let strip = |r: &CycleRecord| CycleRecord {
            orbit: None,
            ..r.clone()
        };
        CycleRecord {
            orbit: None,
            user: self.user.iter().map(strip).collect(),
            pd: self.pd.as_deref().map(|r| Box::new(strip(r))),
            ns: self.ns.as_deref().map(|r| Box::new(strip(r))),
            ..self.clone()
        }
    }

    /// Mesh intervals of a collocated cycle.
    pub fn ntst(&self) -> Option<usize> {
        match self.method {
            CycleMethod::Collocation { ntst } => Some(ntst),
            CycleMethod::ReturnMap => None,
        }
    }

    /// The bifurcations located since the previous cycle, with their kind.
    pub fn special_points(&self) -> impl Iterator<Item = (CycleBifurcation, &CycleRecord)> {
        [
            (CycleBifurcation::Lpc, &self.lpc),
            (CycleBifurcation::Pd, &self.pd),
            (CycleBifurcation::Ns, &self.ns),
        ]
        .into_iter()
        .filter_map(|(kind, r)| r.as_deref().map(|r| (kind, r)))
    }
}

/// A bifurcation of cycles located on a branch (its JSON `kind`: `lpc`,
/// `pd`, `ns`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum CycleBifurcation {
    /// Fold of cycles: a multiplier passes through 1.
    Lpc,
    /// Period doubling: a multiplier passes through -1.
    Pd,
    /// Torus (Neimark-Sacker): a complex pair crosses the unit circle.
    Ns,
}

impl CycleBifurcation {
    /// Its name in text and figures.
    pub fn name(self) -> &'static str {
        match self {
            CycleBifurcation::Lpc => "fold of cycles (LPC)",
            CycleBifurcation::Pd => "period doubling (PD)",
            CycleBifurcation::Ns => "torus bifurcation (NS)",
        }
    }
}

/// What to trace.
#[derive(Clone, Debug)]
pub struct CycleRequest {
    /// Stop when `kappa` falls below this.
    pub kappa_min: f64,
    /// Stop when `kappa` rises above this (subcritical branches first go up).
    pub kappa_max: f64,
    pub max_steps: usize,
    pub ntst: usize,
    /// Stiffnesses at which a cycle is located exactly and reported.
    pub at_kappa: Vec<f64>,
    /// Most mesh intervals the automatic refinement may use.
    pub ntst_max: usize,
    /// Collocation points; `None`: [`collocation_for`] the model.
    pub collocation: Option<CollocationPoints>,
}

impl CycleRequest {
    /// Widens `[kappa_min, kappa_max]` to include every stiffness of
    /// `at_kappa` (with a margin of 1e-3 relative), so that the branch
    /// continues until it reaches them, when it can.
    pub fn cover_requested(&mut self) {
        for &k in &self.at_kappa {
            self.kappa_min = self.kappa_min.min(k * (1.0 - 1e-3));
            self.kappa_max = self.kappa_max.max(k * (1.0 + 1e-3));
        }
    }
}

/// What became of one value asked for (`--at-kappa`, `--at P=...`).
#[derive(Clone, Debug, PartialEq)]
pub struct RequestedPoint {
    /// The value asked for, in the branch's quantity (the stiffness
    /// `kappa`, or a control in its unit).
    pub value: f64,
    /// Cycles delivered at it (a branch that turns at folds can pass a
    /// value more than once).
    pub delivered: usize,
    /// Why no cycle was delivered (`None` when one was).
    pub reason: Option<NotDelivered>,
}

/// Why no cycle was delivered at a requested value; the values in the
/// branch's quantity, as [`RequestedPoint::value`].
#[derive(Clone, Debug, PartialEq)]
pub enum NotDelivered {
    /// There is no branch at all: why, in words.
    NoBranch(String),
    /// No cycle was computed; `stop` says why the branch stopped.
    NoCycle { stop: String },
    /// The branch spans `lo .. hi` but passed this value without a cycle.
    NotLocated { lo: f64, hi: f64, stop: String },
    /// Beyond the fold of cycles at `fold`, where the branch turns back
    /// (`above` it, or below).
    BeyondFold { above: bool, fold: f64 },
    /// On the side of the Hopf point at `critical` where the cycles born
    /// there do not exist.
    NoCyclesOnThisSide { above: bool, critical: f64 },
    /// Between the Hopf point at `critical` and the branch's first cycle at
    /// `first`: the cycles there are smaller than the first one computed
    /// off the Hopf point.
    BeforeFirstCycle { first: f64, critical: f64 },
    /// The branch stopped at `end` before reaching it.
    Stopped { end: f64, stop: String },
}

/// The quantity a branch runs in, for the words of [`NotDelivered`]: the
/// stiffness ([`Quantity::STIFFNESS`]) or a control in its unit.
pub struct Quantity<'a> {
    /// Its name (`kappa`, `V`); its critical value is `<name>_c`.
    pub name: &'a str,
    /// What a value of it is called (`stiffness`, `value of V`).
    pub noun: std::borrow::Cow<'a, str>,
    /// Its unit after a value (empty when dimensionless).
    pub unit: &'a str,
}

impl Quantity<'_> {
    /// The dimensionless stiffness `kappa`.
    pub const STIFFNESS: Quantity<'static> = Quantity {
        name: "kappa",
        noun: std::borrow::Cow::Borrowed("stiffness"),
        unit: "",
    };

    /// A value `written`, followed by the unit.
    pub fn with_unit(&self, written: String) -> String {
        match self.unit {
            "" => written,
            unit => format!("{written} {unit}"),
        }
    }
}

impl NotDelivered {
    /// In words, with the values of the quantity `q`, each written by
    /// `value(x, decimals)` after `<name> = ` (or `<name>_c = `) and
    /// followed by its unit.
    pub fn describe(&self, q: &Quantity, value: &dyn Fn(f64, usize) -> String) -> String {
        let (name, noun) = (q.name, &q.noun);
        let v = |x: f64, decimals: usize| q.with_unit(value(x, decimals));
        match self {
            NotDelivered::NoBranch(why) => why.clone(),
            NotDelivered::NoCycle { stop } => format!("no cycle was computed ({stop})"),
            NotDelivered::NotLocated { lo, hi, stop } => format!(
                "the branch spans {name} = {} .. {} but no cycle was located at this {noun} ({stop})",
                v(*lo, 6),
                v(*hi, 6)
            ),
            NotDelivered::BeyondFold { above, fold } => format!(
                "{} the fold of cycles at {name} = {}: the branch turns back there, none of its \
                 cycles has a {} {noun}",
                if *above { "beyond" } else { "below" },
                v(*fold, 10),
                if *above { "larger" } else { "smaller" }
            ),
            NotDelivered::NoCyclesOnThisSide { above, critical } => format!(
                "{} {name}_c = {}, where no cycle exists on this side: the cycles born at the Hopf \
                 point exist for {name} {} {name}_c",
                if *above { "above" } else { "below" },
                v(*critical, 10),
                if *above { "<" } else { ">" }
            ),
            NotDelivered::BeforeFirstCycle { first, critical } => format!(
                "between {name}_c = {} and the branch's first cycle at {name} = {}: the cycles \
                 there are smaller than the first one computed off the Hopf point (their size \
                 goes as sqrt|{name} - {name}_c| near the onset; `hopf` gives the onset law)",
                v(*critical, 10),
                v(*first, 10)
            ),
            NotDelivered::Stopped { end, stop } => format!(
                "the branch stopped at {name} = {} before reaching it ({stop})",
                v(*end, 10)
            ),
        }
    }
}

/// [`NotDelivered::describe`] with the stiffnesses as `kappa` alone.
impl std::fmt::Display for NotDelivered {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.describe(&Quantity::STIFFNESS, &|kappa, decimals| {
            format!("{kappa:.decimals$e}")
        }))
    }
}

/// How the branch started and ended, for the reasons of [`requested_points`].
#[derive(Clone, Copy, Debug)]
pub struct BranchEnds<'a> {
    /// The Hopf point's value, when the branch was born there.
    pub hopf_start: Option<f64>,
    /// Why the continuation stopped (the legs' outcomes, in words).
    pub stop: &'a str,
    /// Why there is no branch at all, when there is none.
    pub no_branch: Option<&'a str>,
}

/// One end of a branch in some quantity: the value there, and whether it
/// is a fold of cycles.
pub type End = (f64, bool);

/// The least and the largest `value` over the branch `records` (its
/// cycles, not those at requested values, and the folds of cycles located
/// on it), each with whether it is a fold; `None` without cycles.
pub fn extremes(
    records: &[CycleRecord],
    value: &dyn Fn(&CycleRecord) -> f64,
) -> Option<(End, End)> {
    records
        .iter()
        .filter(|c| !c.user_point)
        .flat_map(|c| {
            std::iter::once((value(c), false)).chain(c.lpc.as_deref().map(|l| (value(l), true)))
        })
        .fold(None, |acc: Option<(End, End)>, (k, fold)| {
            let (lo, hi) = acc.unwrap_or(((k, fold), (k, fold)));
            Some((
                if k < lo.0 { (k, fold) } else { lo },
                if k > hi.0 { (k, fold) } else { hi },
            ))
        })
}

/// For each value in `requested` (of the quantity `value` gives a cycle:
/// its stiffness, or a control in its unit, monotone along the continued
/// parameter), the cycles of `records` delivered at it (user points within
/// 1e-9 relative of it), or why there is none: beyond a fold of cycles
/// where the branch turns back, on the side of the Hopf point where its
/// cycles do not exist, or the branch stopped before reaching it.
pub fn requested_points(
    requested: &[f64],
    records: &[CycleRecord],
    ends: &BranchEnds,
    value: &dyn Fn(&CycleRecord) -> f64,
) -> Vec<RequestedPoint> {
    let reached = extremes(records, value);
    requested
        .iter()
        .map(|&target| {
            let delivered = records
                .iter()
                .filter(|c| {
                    // A requested point, or a cycle of the branch at the very
                    // value asked (the simulated orbit a branch starts from).
                    let tol = if c.user_point { 1e-9 } else { 1e-12 };
                    (value(c) - target).abs() <= tol * target.abs()
                })
                .count();
            let reason = (delivered == 0).then(|| match reached {
                None => match ends.no_branch {
                    Some(why) => NotDelivered::NoBranch(why.to_string()),
                    None => NotDelivered::NoCycle {
                        stop: ends.stop.to_string(),
                    },
                },
                Some(((lo, lo_fold), (hi, hi_fold))) => {
                    let (above, end, fold) = if target > hi {
                        (true, hi, hi_fold)
                    } else if target < lo {
                        (false, lo, lo_fold)
                    } else {
                        return NotDelivered::NotLocated {
                            lo,
                            hi,
                            stop: ends.stop.to_string(),
                        };
                    };
                    match ends.hopf_start {
                        _ if fold => NotDelivered::BeyondFold { above, fold: end },
                        Some(kc)
                            if (above && target <= kc && hi <= kc * (1.0 + 1e-9))
                                || (!above && target >= kc && lo >= kc * (1.0 - 1e-9)) =>
                        {
                            NotDelivered::BeforeFirstCycle {
                                first: end,
                                critical: kc,
                            }
                        }
                        Some(kc)
                            if (above && target > kc && hi <= kc * (1.0 + 1e-9))
                                || (!above && target < kc && lo >= kc * (1.0 - 1e-9)) =>
                        {
                            NotDelivered::NoCyclesOnThisSide {
                                above,
                                critical: kc,
                            }
                        }
                        _ => NotDelivered::Stopped {
                            end,
                            stop: ends.stop.to_string(),
                        },
                    }
                }
            });
            RequestedPoint {
                value: target,
                delivered,
                reason,
            }
        })
        .collect()
}

/// The collocation points for cycles of `kind`:
///
/// - inertial: Radau IIA. While the block sticks, its velocity relaxes onto
///   the quasi-static manifold at the rate `mu_v / (m v)`, up to `1e12` for
///   `v ~ 1e-13`; Gauss collocation (not L-stable) leaves the velocity's
///   polynomials oscillating between the Gauss points there, the
///   equidistributed mesh then drains from the slip into the stick, and
///   the branch stalls. Radau points put every mesh point on the manifold.
/// - quasi-static: Gauss (no stiff component; one order more, `2m`).
pub fn collocation_for(kind: ModelKind) -> CollocationPoints {
    match kind {
        ModelKind::Inertial => CollocationPoints::Radau,
        ModelKind::QuasiStatic => CollocationPoints::Gauss,
    }
}

/// The cycles in their order along the branch: the leg toward smaller
/// stiffness ([`Leg::Down`]) reversed, then the others as computed.
pub fn along_branch(records: &[CycleRecord]) -> Vec<&CycleRecord> {
    along_branch_order(records)
        .into_iter()
        .map(|i| &records[i])
        .collect()
}

/// The indices of `records` in [`along_branch`]'s order.
pub fn along_branch_order(records: &[CycleRecord]) -> Vec<usize> {
    let second = |i: &usize| matches!(records[*i].leg, Leg::Down | Leg::ShorterPeriod);
    let down = (0..records.len()).filter(second).rev();
    down.chain((0..records.len()).filter(|i| !second(i)))
        .collect()
}

fn record(log: &LogBlock, pt: &CyclePoint, leg: Leg, watch: &InertiaWatch) -> CycleRecord {
    let c = &pt.cycle;
    // Extremes of the observables (the spring force from the origin, ln v)
    // to the accuracy of the mesh points (`Cycle::range_of`).
    let extremes = pt.extremes(log);
    let ((x_min, x_max), (ln_v_min, ln_v_max)) = (extremes[0], extremes[1]);
    let (s_min, s_max) = (log.origin()[0] + x_min, log.origin()[0] + x_max);
    let (v_min, v_max) = (ln_v_min.exp(), ln_v_max.exp());
    let mut samples: Vec<[f64; 4]> = Vec::with_capacity(c.mesh.ntst() * 4 + 1);
    c.each_sample(4, |tau, x| {
        let phi = log.origin()[2] + x[log.dim() - 1];
        samples.push([tau, log.spring_force(x), log.ln_velocity(x, &c.p), phi]);
    });
    let law = friction_from(log.cutoff, &c.p);
    let friction_min = friction_min(&law, &samples);
    let direct_effect_min = direct_effect_min(&law, &samples);
    CycleRecord {
        kappa: c.p[Param::Kappa as usize],
        params: c.p.clone(),
        period: c.period,
        delta_s: x_max - x_min,
        s_min,
        s_max,
        v_min,
        v_max,
        ln_v_min,
        multipliers: pt.multipliers.clone(),
        trivial: pt.trivial,
        trivial_error: Some(pt.trivial_error).filter(|e| e.is_finite()),
        error_estimate: Some(pt.error_estimate).filter(|e| e.is_finite()),
        stability: pt.stability,
        method: CycleMethod::Collocation {
            ntst: c.mesh.ntst(),
        },
        model: log.kind,
        m: c.p[Param::M as usize],
        friction_min,
        direct_effect_min,
        inertial_imbalance: inertial_imbalance(log, c, watch.m),
        samples,
        lpc: pt
            .event(CycleEvent::Fold)
            .map(|l| Box::new(record(log, l, leg, watch))),
        pd: pt
            .event(CycleEvent::PeriodDoubling)
            .map(|l| Box::new(record(log, l, leg, watch))),
        ns: pt
            .event(CycleEvent::Torus)
            .map(|l| Box::new(record(log, l, leg, watch))),
        user: pt
            .user_points()
            .map(|u| CycleRecord {
                user_point: true,
                ..record(log, u, leg, watch)
            })
            .collect(),
        user_point: false,
        leg,
        orbit: Some(c.clone()),
        log: *log,
    }
}

/// The least friction coefficient over `samples` (`(t / T, s, ln v, ln
/// theta)`) under `law`.
pub fn friction_min(law: &FrictionLaw<f64>, samples: &[[f64; 4]]) -> f64 {
    samples
        .iter()
        .map(|&[_, _, ln_v, phi]| law.mu_of_logs(ln_v, phi))
        .fold(f64::INFINITY, f64::min)
}

/// The least direct effect `d mu / d ln v = A + 2 mu_vv ln v + mu_vphi ln
/// theta` (docs/model.md, "The other corrections") over an orbit's
/// `samples` `(t / T, s, ln v, ln theta)`; `A` itself without the
/// corrections. Where it is not positive, friction no longer rises with the
/// slip velocity at fixed state: the expansion in `ln v` has left its
/// domain, and the quasi-static block has no velocity for a given force.
pub fn direct_effect_min(law: &FrictionLaw<f64>, samples: &[[f64; 4]]) -> f64 {
    samples
        .iter()
        .map(|&[_, _, ln_v, ln_theta]| law.rate_coefficient(2.0 * ln_v, ln_theta))
        .fold(f64::INFINITY, f64::min)
}

/// Traces the cycles born at the Hopf point of `params` (in `kappa`), handing
/// each to `sink` as it is computed. Returns the Hopf point it started from.
/// The model is kept along the branch (no switch; see [`trace_cycles_from`]).
pub fn trace_cycles(
    kind: ModelKind,
    params: &Params,
    req: &CycleRequest,
    sink: impl FnMut(&CycleRecord) -> Result<(), crate::error::Error>,
) -> Result<HopfPoint, crate::error::Error> {
    let HopfOutcome::Found(h) = find_hopf(kind, params)? else {
        return Err(no_onset().into());
    };
    let watch = InertiaWatch::new(params, DEFAULT_INERTIA_THRESHOLD, false);
    trace_cycles_from(kind, params, &h, req, &watch, sink)?;
    Ok(h)
}

/// The error for a scene without a Hopf point: no cycles are born.
pub fn no_onset() -> NumericalError {
    NumericalError::Analysis(
        "steady sliding is stable for every stiffness here: no Hopf point, hence no cycles born from it".into(),
    )
}

/// Traces the cycles born at the already located Hopf point `h` of `params`;
/// returns why the branch ended. A quasi-static branch hands over to the
/// inertial model where `watch` says so ([`follow_switching`]).
pub fn trace_cycles_from(
    kind: ModelKind,
    params: &Params,
    h: &HopfPoint,
    req: &CycleRequest,
    watch: &InertiaWatch,
    sink: impl FnMut(&CycleRecord) -> Result<(), crate::error::Error>,
) -> Result<Stop, crate::error::Error> {
    trace_cycles_from_in(kind, params, h, Param::Kappa, req, watch, sink)
}

/// [`trace_cycles_from`] continued in the parameter `param` instead of
/// `kappa` (`cycles --param`): `h` is a Hopf point of `params` (located in
/// `kappa` at `params.kappa`, which is also a Hopf point in `param`, with
/// the same normal form), and `req`'s bounds (`kappa_min`, `kappa_max`)
/// and requested values (`at_kappa`) are values of `param`.
pub fn trace_cycles_from_in(
    kind: ModelKind,
    params: &Params,
    h: &HopfPoint,
    param: Param,
    req: &CycleRequest,
    watch: &InertiaWatch,
    mut sink: impl FnMut(&CycleRecord) -> Result<(), crate::error::Error>,
) -> Result<Stop, crate::error::Error> {
    let log = LogBlock::centered(kind, params);
    let branch = branch_at_hopf_in(
        &log,
        &log,
        params,
        h,
        param,
        CycleSettings {
            start_amplitude: start_amplitude(&log),
            ..settings(kind, req, req.ntst)
        },
    )?;
    follow_switching(
        &log,
        (None, branch),
        Leg::FromHopf,
        0,
        param,
        req,
        watch,
        &mut sink,
    )
}

/// The branch of the cycles born at the Hopf point `h` of `params`, in the
/// variables of `log` evaluated through `field` (`log` itself, or wrapped,
/// e.g. counted): its first cycle on the side the sign of `l1` gives, in
/// the arithmetic `hopf` uses ([`resolved_normal_form`]: double-double
/// where `f64` cannot resolve it, as next to a Bautin point or with a
/// small inertia on the plain law).
pub fn branch_at_hopf<'a, S: VectorField>(
    field: &'a S,
    log: &LogBlock,
    params: &Params,
    h: &HopfPoint,
    settings: CycleSettings,
) -> Result<CycleBranch<'a, S>, NumericalError> {
    branch_at_hopf_in(field, log, params, h, Param::Kappa, settings)
}

/// [`branch_at_hopf`] continued in `param`: the normal form is the point's
/// (located and resolved in `kappa`, as `hopf` does); the engine takes the
/// side of the first cycle from `l1` and `d lambda / d param`.
pub fn branch_at_hopf_in<'a, S: VectorField>(
    field: &'a S,
    log: &LogBlock,
    params: &Params,
    h: &HopfPoint,
    param: Param,
    settings: CycleSettings,
) -> Result<CycleBranch<'a, S>, NumericalError> {
    let (x0, p, nf) = hopf_with_normal_form(field, log, params, h)?;
    Ok(CycleBranch::from_hopf_normal_form(
        field,
        &x0,
        &p,
        param as usize,
        &nf,
        settings,
    )?)
}

/// The Hopf point `h` of `params` in the variables of `log` (state and
/// parameter vector) and its normal form in the arithmetic `hopf` uses
/// ([`resolved_normal_form`]).
pub fn hopf_with_normal_form<S: VectorField>(
    field: &S,
    log: &LogBlock,
    params: &Params,
    h: &HopfPoint,
) -> Result<(Vec<f64>, Vec<f64>, HopfNormalForm), NumericalError> {
    let (x0, p) = hopf_start(log, params, h);
    let kappa_error = location_error(log.kind, params, h.kappa_c);
    let (nf, _) = resolved_normal_form(field, &x0, &p, h.omega_c, kappa_error)?;
    Ok((x0, p, nf))
}

/// Mesh intervals of the first cycle sampled from a simulation: stick-slip
/// orbits span decades of slip velocity, so at least this many.
pub const SAMPLED_NTST: usize = 200;

/// Traces the cycles through the simulated orbit `orbit` of `params` (at
/// `params.kappa`): the orbit is put on a mesh of `max(req.ntst,`
/// [`SAMPLED_NTST`]`)` intervals (more where Newton's method needs them,
/// `sampled_branch`), corrected by collocation, and continued
/// first toward increasing stiffness ([`Leg::Up`]: a fold of cycles, LPC,
/// where the branch turns back, lies that way for a cycle coexisting with
/// stable sliding) and then toward decreasing stiffness ([`Leg::Down`]),
/// each leg within `req`'s bounds and step limit. The starting cycle is
/// handed to `sink` once. A leg that stops on a numerical failure does not
/// prevent the other; how each leg ended is returned (`[up, down]`).
pub fn trace_cycles_from_orbit(
    kind: ModelKind,
    params: &Params,
    orbit: &SettledOrbit,
    req: &CycleRequest,
    watch: &InertiaWatch,
    sink: impl FnMut(&CycleRecord) -> Result<(), crate::error::Error>,
) -> Result<[LegOutcome; 2], crate::error::Error> {
    trace_cycles_from_orbit_in(kind, params, orbit, Param::Kappa, req, watch, sink)
}

/// [`trace_cycles_from_orbit`] continued in `param` (its legs [`Leg::Up`]
/// and [`Leg::Down`] toward larger and smaller values of `param`); `req`'s
/// bounds and requested values are values of `param`.
pub fn trace_cycles_from_orbit_in(
    kind: ModelKind,
    params: &Params,
    orbit: &SettledOrbit,
    param: Param,
    req: &CycleRequest,
    watch: &InertiaWatch,
    sink: impl FnMut(&CycleRecord) -> Result<(), crate::error::Error>,
) -> Result<[LegOutcome; 2], crate::error::Error> {
    let through = Through::Simulated {
        log: LogBlock::centered(kind, params),
        params,
        orbit,
    };
    trace_cycles_through(&through, param, req, watch, sink)
}

/// A known orbit a branch is traced through, both ways.
#[derive(Clone, Copy)]
pub enum Through<'a> {
    /// A simulated orbit of `params`, put on a mesh and corrected in the
    /// variables of `log` ([`LogBlock::centered`] on `params`).
    Simulated {
        log: LogBlock,
        params: &'a Params,
        orbit: &'a SettledOrbit,
    },
    /// A collocated orbit in the variables of `log`, as an earlier run
    /// wrote it ([`crate::records::orbit::StoredOrbit`]): corrected by
    /// Newton's method on its own mesh at its own parameters, nothing else
    /// (a restart). `fold`: the orbit is a fold of cycles in the
    /// parameter continued, corrected at its period instead.
    Stored {
        log: LogBlock,
        cycle: &'a Cycle,
        fold: bool,
    },
}

impl Through<'_> {
    /// The variables the branch is traced in.
    pub fn log(&self) -> &LogBlock {
        match self {
            Through::Simulated { log, .. } | Through::Stored { log, .. } => log,
        }
    }
}

/// How a leg of a branch ended, with the leg.
pub type LegOutcome = (Leg, Result<Stop, crate::error::Error>);

/// Traces the cycles through the orbit `through`: first toward larger
/// `param` ([`Leg::Up`]: a fold of cycles, LPC, where the branch turns
/// back, lies that way for a cycle coexisting with stable sliding), then
/// toward smaller ([`Leg::Down`]), each leg within `req`'s bounds and step
/// limit (values of `param`); from a stored fold of cycles toward longer
/// and shorter periods ([`Leg::LongerPeriod`], [`Leg::ShorterPeriod`]),
/// the start handed out as that fold (its `lpc`, for `--lpc-curve` and the
/// figures). The starting cycle is handed to `sink` once.
/// A leg that stops on a numerical failure does not prevent the other; how
/// each leg ended is returned (a signal ends the leg it came in, and the
/// one after it as not started).
pub fn trace_cycles_through(
    through: &Through,
    param: Param,
    req: &CycleRequest,
    watch: &InertiaWatch,
    mut sink: impl FnMut(&CycleRecord) -> Result<(), crate::error::Error>,
) -> Result<[LegOutcome; 2], crate::error::Error> {
    let log = through.log();
    let fold = matches!(through, Through::Stored { fold: true, .. });
    let (first_leg, second_leg) = if fold {
        (Leg::LongerPeriod, Leg::ShorterPeriod)
    } else {
        (Leg::Up, Leg::Down)
    };
    // Both overwritten below.
    let mut legs = [
        (first_leg, Ok(Stop::MaxSteps { steps: 0 })),
        (second_leg, Ok(Stop::MaxSteps { steps: 0 })),
    ];
    // The start of a fold restart is that fold.
    let mut start_handed = false;
    let mut sink = |rec: &CycleRecord| {
        if fold && !start_handed {
            start_handed = true;
            let mut start = rec.clone();
            start.lpc = Some(Box::new(rec.clone()));
            return sink(&start);
        }
        sink(rec)
    };
    // The second leg starts on the intervals the first one's start needed.
    let mut ntst = req.ntst.max(SAMPLED_NTST);
    for (i, (leg, sign)) in [(first_leg, 1.0), (second_leg, -1.0)]
        .into_iter()
        .enumerate()
    {
        let outcome = match (first_cycle(through, param, sign, ntst, req), through) {
            (Ok((first, branch, used)), _) => {
                ntst = used;
                let started = (Some(first), branch);
                follow_switching(log, started, leg, i, param, req, watch, &mut sink)
            }
            // An inertial orbit collocation cannot correct (a slip of
            // microseconds in a period of days): by the return map.
            (Err(e), Through::Simulated { params, orbit, .. })
                if log.kind == ModelKind::Inertial && param == Param::Kappa =>
            {
                return_map::branch_through_orbit(
                    log,
                    params,
                    orbit,
                    sign,
                    &e.to_string(),
                    req,
                    leg,
                    i == 0,
                    &mut sink,
                )
            }
            (Err(e), _) => Err(e.into()),
        };
        match outcome {
            // A signal ends this leg and the ones not run; the legs before
            // keep how they ended.
            Err(crate::error::Error::Interrupted(at)) => {
                for later in &mut legs[i + 1..] {
                    later.1 = Err(crate::error::Error::Interrupted(
                        crate::error::Interruption {
                            signal: at.signal,
                            at: "before the leg started".into(),
                        },
                    ));
                }
                legs[i].1 = Err(crate::error::Error::Interrupted(at));
                return Ok(legs);
            }
            other => legs[i].1 = other,
        }
    }
    Ok(legs)
}

/// The branch in `param` through `through`, its tangent oriented by `sign`
/// (`1`: toward larger `param`): its first cycle, the branch after it, and
/// the intervals it started on. A stored orbit is corrected on its own mesh
/// ([`CycleBranch::from_cycle`] at fixed `param`, then refined only where
/// its error estimate exceeds the tolerance, like any first cycle); a
/// simulated one goes through [`sampled_branch`] on `ntst` intervals.
fn first_cycle<'a>(
    through: &'a Through,
    param: Param,
    sign: f64,
    ntst: usize,
    req: &CycleRequest,
) -> Result<(CyclePoint, CycleBranch<'a, LogBlock>, usize), NumericalError> {
    match through {
        Through::Simulated { log, params, orbit } => {
            sampled_branch(log, params, orbit, param, sign, ntst, req)
        }
        Through::Stored { log, cycle, fold } => {
            let ntst = cycle.mesh.ntst();
            let start =
                |unknown| started_branch(log, (*cycle).clone(), param, unknown, sign, ntst, req);
            // At a fold of cycles the orbit is singular at fixed `param`:
            // corrected there at fixed period instead, the legs toward
            // longer and shorter periods (also where the correction at
            // fixed `param` fails, near a fold the run did not locate).
            let (first, second) = if *fold {
                (PERIOD_UNKNOWN, PARAM_UNKNOWN)
            } else {
                (PARAM_UNKNOWN, PERIOD_UNKNOWN)
            };
            start(first)
                .or_else(|e| start(second).map_err(|_| e))
                .map(|(first, branch)| (first, branch, ntst))
                .map_err(|e| {
                    NumericalError::Analysis(format!(
                        "correcting the stored orbit at {} = {:.10e} on its {ntst} mesh \
                         intervals: {e}",
                        param.name(),
                        cycle.p[param as usize]
                    ))
                })
        }
    }
}

/// The position from the end of the unknowns of the continued parameter
/// and of the period ([`started_branch`]).
const PARAM_UNKNOWN: usize = 1;
const PERIOD_UNKNOWN: usize = 2;

/// The branch in `param` through `guess` (on `ntst` intervals, in the
/// variables of `log`), its tangent oriented by `sign` along the unknown
/// `unknown` ([`PARAM_UNKNOWN`] or [`PERIOD_UNKNOWN`]): the guess corrected
/// with that unknown fixed, as its first cycle, and the branch after it.
fn started_branch<'a>(
    log: &'a LogBlock,
    guess: Cycle,
    param: Param,
    unknown: usize,
    sign: f64,
    ntst: usize,
    req: &CycleRequest,
) -> Result<(CyclePoint, CycleBranch<'a, LogBlock>), NumericalError> {
    // The last unknowns are the period and the parameter: the seed orients the tangent.
    let nz = guess.u.len() + 2;
    let mut seed = vec![0.0; nz];
    seed[nz - unknown] = sign;
    let settings = settings(log.kind, req, ntst);
    CycleBranch::from_cycle(log, guess, param as usize, Some(seed), settings)
        .map_err(NumericalError::from)
        .and_then(|mut branch| match branch.next() {
            Some(first) => Ok((first?, branch)),
            // A driver hands out its start (or the start's error) first.
            None => Err(NumericalError::Analysis(
                "the branch through the orbit handed out no first cycle".into(),
            )),
        })
}

/// Most doublings of the intervals of a sampled orbit whose first
/// correction fails ([`sampled_branch`]).
const SAMPLED_DOUBLINGS: usize = 4;

/// The branch in `param` through the simulated orbit `orbit` of `params`,
/// in the variables of `log` ([`LogBlock::centered`]), its tangent oriented
/// by `sign` (`1`: toward larger `param`): its first cycle, the branch after
/// it, and the intervals it started on. The orbit is put on `ntst`
/// intervals ([`sampled_cycle`]: the mesh from the integrator's steps, then
/// equidistributing the collocation error monitor), corrected at fixed
/// `param` and its mesh refined for the error tolerance (the branch's first
/// cycle). Where Newton's method fails on the way the intervals are doubled, up to `req.ntst_max` and at
/// most [`SAMPLED_DOUBLINGS`] times: an orbit whose slip velocity spans many
/// decades needs more intervals to start from than to be resolved (the rig
/// of docs/index.md at 1 µm/s, `v` from 1e-9 to 1e5 µm/s: Newton diverges
/// in the refinement from 200 intervals and converges from 400).
fn sampled_branch<'a>(
    log: &'a LogBlock,
    params: &Params,
    orbit: &SettledOrbit,
    param: Param,
    sign: f64,
    mut ntst: usize,
    req: &CycleRequest,
) -> Result<(CyclePoint, CycleBranch<'a, LogBlock>, usize), NumericalError> {
    let mut tried: Vec<String> = Vec::new();
    loop {
        let guess = sampled_cycle(log, params, orbit, ntst, 1e-10)
            .map_err(|e| NumericalError::Analysis(e.to_string()))?;
        match started_branch(log, guess, param, PARAM_UNKNOWN, sign, ntst, req) {
            Ok((first, branch)) => return Ok((first, branch, ntst)),
            Err(e) => {
                tried.push(ntst.to_string());
                if tried.len() > SAMPLED_DOUBLINGS || 2 * ntst > req.ntst_max {
                    return Err(NumericalError::Analysis(format!(
                        "correcting the simulated orbit on {} mesh intervals: {}",
                        tried.join(", "),
                        e
                    )));
                }
                ntst *= 2;
            }
        }
    }
}

/// The cycle through the simulated orbit `orbit` of `params` at its own
/// stiffness `params.kappa`, not continued: the orbit on a mesh, corrected
/// by collocation at fixed stiffness (`sampled_branch`), its mesh refined
/// until the error estimate meets the branch's tolerance, and its Floquet
/// multipliers; the first cycle of a branch through it (the same settings
/// as every cycle of a branch, `settings`), recorded as
/// [`Leg::AtStiffness`].
pub fn cycle_through_orbit(
    kind: ModelKind,
    params: &Params,
    orbit: &SettledOrbit,
    req: &CycleRequest,
    watch: &InertiaWatch,
) -> Result<CycleRecord, NumericalError> {
    let log = LogBlock::centered(kind, params);
    let ntst = req.ntst.max(SAMPLED_NTST);
    match sampled_branch(&log, params, orbit, Param::Kappa, 1.0, ntst, req) {
        Ok((first, _, _)) => Ok(record(&log, &first, Leg::AtStiffness, watch)),
        // An inertial orbit collocation cannot correct: by the return map.
        Err(e) if kind == ModelKind::Inertial => {
            return_map::cycle_through_orbit(&log, params, orbit, Leg::AtStiffness)
                .map_err(|m| NumericalError::Analysis(format!("{e}; by the return map: {m}")))
        }
        Err(e) => Err(e),
    }
}

/// Relative amplitude of the first cycle off the Hopf point
/// ([`CycleSettings::start_amplitude`], relative to `1 + |x0|`) in the
/// variables of `log`: `1e-3 (1 + max |origin|)`, so that the first cycle is
/// the engine's default `1e-3 (1 + |x*|)` of steady sliding `x*` in the log
/// variables themselves, whatever the origin the state is measured from.
pub fn start_amplitude(log: &LogBlock) -> f64 {
    1e-3 * (1.0 + log.origin().iter().fold(0.0f64, |a, v| a.max(v.abs())))
}

/// Continuation settings for `req`, starting on `ntst` intervals.
fn settings(kind: ModelKind, req: &CycleRequest, ntst: usize) -> CycleSettings {
    CycleSettings {
        mesh: Discretization {
            points: req.collocation.unwrap_or(collocation_for(kind)),
            ntst,
            ntst_max: req.ntst_max.max(ntst),
            // Relative to the amplitudes, at the cycle's stiffness: with it the
            // period and Delta_s agree with an independent reference to 2e-10 from
            // (kappa_c - kappa)/kappa_c = 1e-5 to 0.5 (tests/onset_accuracy.rs,
            // docs/cycles.md); 1e-7 left errors up to 3e-9.
            mesh_tol: Some(1e-9),
            mesh_accept: Some(1e-4),
            ..Default::default()
        },
        // A first cycle whose multipliers rounding swamps is still a
        // resolved cycle: delivered with its stability undecidable (and
        // why); the branch ends at the next such cycle.
        floquet: FloquetPolicy {
            when_undecidable: WhenUndecidable::KeepFirst,
            ..Default::default()
        },
        p_min: req.kappa_min,
        p_max: req.kappa_max,
        max_steps: req.max_steps,
        step: StepControl {
            ds: 1e-3,
            ds_max: 0.2,
            // On stick-slip cycles the slip front moves in time from one cycle to
            // the next, and Newton takes 5 to 7 iterations even on short steps
            // (the first ones move ln v near the front by about one unit each):
            // steps grow after up to 5 (the stiff PMMA branch to kappa = 1e-4:
            // 334 steps, 36 s; after up to 3 or 4: 504 and 494 steps).
            easy_iterations: 5,
            ..CycleSettings::default().step
        },
        user_points: req.at_kappa.clone(),
        // Relative steps in kappa down to the smallest stiffness asked for.
        param_floor: 0.5 * req.kappa_min.max(1e-12),
        ..Default::default()
    }
}

/// A branch to follow, with its first cycle when it was already taken from
/// it ([`sampled_branch`]).
type Started<'a> = (Option<CyclePoint>, CycleBranch<'a, LogBlock>);

/// How [`follow`] ended: the branch's own end, or a quasi-static orbit on
/// which inertia stopped being negligible.
enum FollowEnd {
    End(Stop),
    /// Hand over to the inertial model from `cycle`, continuing in the
    /// direction of `dp_ds`'s sign.
    Switch {
        cycle: Box<Cycle>,
        dp_ds: f64,
        /// The quasi-static orbit before it (its `chi` below the threshold),
        /// to hand over from when `cycle` is already too far from inertial.
        previous: Option<Box<Cycle>>,
    },
}

/// What a leg [`follow`]ed ends with: a [`Stop`] for a leg that stays in its
/// model (an inertial one), a [`FollowEnd`] for a leg that may hand over.
trait LegEnd: Sized {
    /// The branch's own end.
    fn stopped(stop: Stop) -> Self;
    /// The hand-over after the cycle `pt` (its record `rec`; `previous` the
    /// cycle before it), if this leg hands over there.
    fn handover(
        watch: &InertiaWatch,
        kind: ModelKind,
        rec: &CycleRecord,
        pt: &CyclePoint,
        previous: &mut Option<Box<Cycle>>,
    ) -> Option<Self>;
}

impl LegEnd for Stop {
    fn stopped(stop: Stop) -> Self {
        stop
    }
    fn handover(
        _: &InertiaWatch,
        _: ModelKind,
        _: &CycleRecord,
        _: &CyclePoint,
        _: &mut Option<Box<Cycle>>,
    ) -> Option<Self> {
        None
    }
}

impl LegEnd for FollowEnd {
    fn stopped(stop: Stop) -> Self {
        FollowEnd::End(stop)
    }
    /// A quasi-static leg hands over where `watch` switches and the cycle's
    /// inertial imbalance `chi` exceeds its threshold.
    fn handover(
        watch: &InertiaWatch,
        kind: ModelKind,
        rec: &CycleRecord,
        pt: &CyclePoint,
        previous: &mut Option<Box<Cycle>>,
    ) -> Option<Self> {
        (watch.switch && kind == ModelKind::QuasiStatic && rec.inertial_imbalance > watch.threshold)
            .then(|| FollowEnd::Switch {
                cycle: Box::new(pt.cycle.clone()),
                dp_ds: pt.dp_ds,
                previous: previous.take(),
            })
    }
}

/// [`follow`], and where a quasi-static branch hands over: the last
/// quasi-static orbit is corrected in the inertial model at the same
/// stiffness ([`inertial_guess`]) and the branch continues from it, with
/// Radau collocation unless `req` fixes the points.
#[allow(clippy::too_many_arguments)]
fn follow_switching(
    log: &LogBlock,
    branch: Started<'_>,
    leg: Leg,
    skip: usize,
    param: Param,
    req: &CycleRequest,
    watch: &InertiaWatch,
    sink: &mut impl FnMut(&CycleRecord) -> Result<(), crate::error::Error>,
) -> Result<Stop, crate::error::Error> {
    let (cycle, dp_ds, previous) =
        match follow::<FollowEnd>(log, branch, leg, skip, param, req, watch, sink)? {
            FollowEnd::End(end) => return Ok(end),
            FollowEnd::Switch {
                cycle,
                dp_ds,
                previous,
            } => (cycle, dp_ds, previous),
        };
    let inertial = LogBlock::at(ModelKind::Inertial, log.cutoff, log.state_law, log.origin());
    // From the orbit where chi first exceeds the threshold, corrected at its
    // stiffness. Where the branch is nearly vertical in the stiffness (a
    // canard-like growth of the slip: chi jumps by decades in one step),
    // inertia shifts that growth in kappa and no inertial orbit of that
    // size exists at the same stiffness: then corrected at its period,
    // continuing toward longer periods (deeper stick-slip); last, the orbit
    // before it.
    let start = |from: &Cycle, unknown: usize, sign: f64| {
        let guess = inertial_guess(log, from, watch.m);
        let nz = guess.u.len() + 2;
        let mut seed = vec![0.0; nz];
        seed[nz - unknown] = sign;
        let ntst = guess.mesh.ntst();
        CycleBranch::from_cycle(
            &inertial,
            guess,
            param as usize,
            Some(seed),
            settings(ModelKind::Inertial, req, ntst),
        )
    };
    const KAPPA: usize = 1;
    const PERIOD: usize = 2;
    let branch = start(&cycle, KAPPA, dp_ds.signum())
        .or_else(|_| start(&cycle, PERIOD, 1.0))
        .or_else(|e| match &previous {
            Some(before) => start(before, KAPPA, dp_ds.signum()),
            None => Err(e),
        })
        .map_err(|e| {
            NumericalError::Analysis(format!(
            "switching to the inertial model at kappa = {:.6e}: the quasi-static orbit did not \
             correct to an inertial one ({e}); try --model quasi-static or --model inertial",
            cycle.p[Param::Kappa as usize]
        ))
        })?;
    let watch = InertiaWatch {
        switch: false,
        ..*watch
    };
    // A failure before the first inertial cycle is said to follow the
    // switch (no inertial record shows that it happened).
    let mut delivered = 0usize;
    let mut counted = |r: &CycleRecord| {
        delivered += 1;
        sink(r)
    };
    match follow::<Stop>(&inertial, (None, branch), leg, 0, param, req, &watch, &mut counted) {
        Ok(end) => Ok(end),
        Err(crate::error::Error::Numerical(e)) if delivered == 0 => Err(NumericalError::Analysis(format!(
            "the branch switched to the inertial model at kappa = {:.6e} (inertia would shift ln v \
             by chi > {:.0e} on the last quasi-static cycle), and the first inertial cycle failed: {e}",
            cycle.p[Param::Kappa as usize],
            watch.threshold
        ))
        .into()),
        Err(e) => Err(e),
    }
}

/// Hands the cycles of `branch` to `sink`, skipping the first `skip` (the
/// starting cycle of a second leg); returns why the branch ended, or the
/// quasi-static orbit at which `watch` hands over to the inertial model (that
/// orbit is handed to `sink` too). A failure after the cycles have shrunk
/// below [`SHRUNK`] of the largest `Delta_s` on the leg is reported as what
/// it is: the branch reached steady sliding at a Hopf point, where the
/// collocation system is singular (zero amplitude).
#[allow(clippy::too_many_arguments)]
fn follow<E: LegEnd>(
    log: &LogBlock,
    (first, mut branch): Started<'_>,
    leg: Leg,
    skip: usize,
    param: Param,
    req: &CycleRequest,
    watch: &InertiaWatch,
    sink: &mut impl FnMut(&CycleRecord) -> Result<(), crate::error::Error>,
) -> Result<E, crate::error::Error> {
    let (mut largest, mut last) = (0.0f64, None);
    // The last cycle handed out and the stiffness of the one before: where
    // the return map takes over ([`return_map::continue_branch`]).
    let (mut last_rec, mut kappa_before, mut delivered): (Option<CycleRecord>, Option<f64>, usize) =
        (None, None, 0);
    // The last three cycles' (parameter, Delta_s).
    let mut recent: Vec<(f64, f64)> = Vec::with_capacity(3);
    let (mut slowest, mut fastest) = (f64::INFINITY, f64::INFINITY);
    let mut previous: Option<Box<Cycle>> = None;
    let mut to_skip = skip;
    for pt in first.map(Ok).into_iter().chain(branch.by_ref()) {
        // Only cycles are skipped: a failure of the start is the leg's answer.
        if to_skip > 0 && pt.is_ok() {
            to_skip -= 1;
            continue;
        }
        // Cycles that shrank onto steady sliding end the leg where they are
        // born, at a Hopf point, through which collocation cannot continue:
        // the leg's natural end, not a failure.
        // So do cycles that shrink by the Hopf normal form's square-root
        // law onto a zero amplitude one step ahead: the step toward it met
        // the singular limit of collocation before SHRUNK.
        if let (Err(_), Some((p, delta_s))) = (&pt, recent.last()) {
            if *delta_s < SHRUNK * largest {
                return Ok(E::stopped(Stop::HopfPoint { param: *p }));
            }
            if let Some(p_h) = square_root_law_zero(&recent) {
                return Ok(E::stopped(Stop::HopfPoint { param: p_h }));
            }
        }
        let deep_stop = log.kind == ModelKind::Inertial
            && watch.m > 0.0
            && watch.a / (watch.m * slowest) > STIFF_BEYOND_F64;
        let pt = match pt {
            Ok(pt) => pt,
            Err(
                e @ (continuation::ContinuationError::Newton { .. }
                | continuation::ContinuationError::StepTooSmall { .. }
                | continuation::ContinuationError::FloquetIllConditioned { .. }),
            ) => {
                // The engine's advice (a smaller step, more intervals) is
                // what the branch already did; what failed, in numbers.
                let failed = match &e {
                    continuation::ContinuationError::StepTooSmall { ds, .. } => format!(
                        "the continuation stalled (steps down to ds = {ds:.1e} failed to correct)"
                    ),
                    continuation::ContinuationError::Newton {
                        iterations,
                        residual,
                        ..
                    } => format!(
                        "Newton did not converge correcting a cycle ({iterations} iterations, \
                         residual {})",
                        if residual.is_finite() {
                            format!("{residual:.1e}")
                        } else {
                            "beyond the floating-point range".to_string()
                        }
                    ),
                    other => other.to_string(),
                };
                let kappa = last.map_or(f64::NAN, |(k, _)| k);
                let why = if deep_stop {
                    format!(
                        "{failed}: near kappa = {kappa:.6e} the block comes to rest from v_max = \
                         {fastest:.3e} V0 onto its stick velocity v = {slowest:.3e} V0, {:.0} \
                         decades, in a time no mesh resolves (the inertial model's velocity \
                         relaxes there at the rate A/(m v) = {:.3e} V0/D0): ln v at the mesh \
                         points of that stop is left ill-determined by the collocation equations",
                        (fastest / slowest).log10(),
                        watch.a / (watch.m * slowest)
                    )
                } else {
                    format!("collocation failed after kappa = {kappa:.6e}: {failed}")
                };
                // An inertial branch in kappa goes on by the return map
                // from its last cycle: where collocation no longer resolves
                // the stop into the stick, fails otherwise, or its
                // multipliers are swamped by rounding (the map's Jacobian
                // decides stability).
                match (&last_rec, kappa_before) {
                    (Some(rec), Some(before))
                        if log.kind == ModelKind::Inertial
                            && param == Param::Kappa
                            && rec.kappa != before =>
                    {
                        return return_map::continue_branch(
                            log,
                            rec,
                            rec.kappa - before,
                            &why,
                            req,
                            req.max_steps.saturating_sub(delivered),
                            leg,
                            sink,
                        )
                        .map(E::stopped);
                    }
                    _ if deep_stop && last.is_some() => {
                        return Err(NumericalError::Analysis(format!(
                            "{why}; Newton's corrections there no longer converge, and the \
                             inertial branch ends here"
                        ))
                        .into())
                    }
                    _ => return Err(NumericalError::from(e).into()),
                }
            }
            Err(e) => return Err(NumericalError::from(e).into()),
        };
        let rec = record(log, &pt, leg, watch);
        largest = largest.max(rec.delta_s);
        last = Some((rec.kappa, rec.delta_s));
        if recent.len() == 3 {
            recent.remove(0);
        }
        recent.push((rec.params[param as usize], rec.delta_s));
        (slowest, fastest) = (rec.v_min, rec.v_max);
        sink(&rec)?;
        delivered += 1;
        if let Some(end) = E::handover(watch, log.kind, &rec, &pt, &mut previous) {
            return Ok(end);
        }
        kappa_before = last_rec.as_ref().map(|r| r.kappa);
        last_rec = Some(rec);
        previous = Some(Box::new(pt.cycle));
    }
    // An iterator that ended without an error has a reason (the driver
    // keeps it); without one the leg is not called complete.
    branch.stop().map(E::stopped).ok_or_else(|| {
        NumericalError::Analysis(
            "the cycle branch ended without a reason from the engine; the cycles so far are kept"
                .into(),
        )
        .into()
    })
}

/// The Hopf point `h` of `params` in the log variables of `log`: the state
/// and the parameter vector (with `kappa = kappa_c`) to start cycles from.
pub fn hopf_start(log: &LogBlock, params: &Params, h: &HopfPoint) -> (Vec<f64>, Vec<f64>) {
    let mut p = *params;
    p.kappa = h.kappa_c;
    (
        log.from_model(h.state[0], h.state[1], h.state[2]),
        p.to_vec(),
    )
}

/// Relaxation rate `A/(m v)` of the inertial block's velocity at the stick
/// (units `V0/D0`) beyond which a failed correction is explained by the stop
/// into the stick: the velocity falls there by tens of decades (linearly in
/// time under the inertial deceleration, down to the stick's quasi-static
/// value) within a time no mesh resolves, and the collocation equations
/// leave `ln v` at the mesh points of that stop ill-determined (seen at
/// `v_min ~ 5e-51`, `m = 1e-6`, `A = 1e-4`: `2e52`; before the force
/// balance was collocated in its implicit form, rounding amplified by that
/// rate ended the branch at `v_min ~ 6e-42`).
const STIFF_BEYOND_F64: f64 = 1e30;

/// Where the last three cycles of a leg `(p, Delta_s)` reach zero amplitude
/// by the Hopf normal form's square-root law, `Delta_s^2` linear in `p`
/// near a Hopf point `p_h` (`Delta_s^2 ∝ (p_h - p)`, docs/model.md's
/// normal form): `Some(p_h)` when the amplitudes fall monotonically, the two
/// slopes of `Delta_s^2` against `p` agree to 10 % (the law holds), and the
/// zero lies within two of the last parameter steps ahead.
fn square_root_law_zero(recent: &[(f64, f64)]) -> Option<f64> {
    let [(p0, d0), (p1, d1), (p2, d2)] = *recent else {
        return None;
    };
    let slope = |(pa, da): (f64, f64), (pb, db): (f64, f64)| (db * db - da * da) / (pb - pa);
    let (s1, s2) = (slope((p0, d0), (p1, d1)), slope((p1, d1), (p2, d2)));
    let shrinking = d2 < d1 && d1 < d0 && (p2 - p1) * (p1 - p0) > 0.0;
    let law = s1.is_finite() && s2.is_finite() && (s1 / s2 - 1.0).abs() < 0.1;
    let p_h = p2 - d2 * d2 / s2;
    (shrinking && law && (p_h - p2).abs() <= 2.0 * (p2 - p1).abs()).then_some(p_h)
}

/// Fraction of a leg's largest `Delta_s` below which a cycle counts as
/// shrunk onto steady sliding.
const SHRUNK: f64 = 0.05;
