//! The records of `cycles`: one stick-slip cycle (a row of `-cycles.csv`,
//! with its Floquet multipliers in the JSON), a bifurcation located on the
//! branch, a requested stiffness, and how each leg of the branch ended.

use super::branch::ParamValue;
use crate::analysis::cycles::{
    CycleBifurcation, CycleMethod, CycleRecord, Leg, NotDelivered, RequestedPoint, Stability,
    ESTIMATE_UNAVAILABLE, IMBALANCE_UNDEFINED, TRIVIAL_REMOVED, TRIVIAL_UNAVAILABLE,
};
use crate::analysis::operating_point::Regime;
use crate::analysis::settle::SettledOrbit;
use crate::error::Error;
use crate::model::ModelKind;
use crate::records::csv::CsvRecord;
use crate::records::hopf::OperatingPoint;
use crate::scene::Units;
use continuation::Stop;
use serde::{Serialize, Serializer};
use std::fmt;

/// A cycle's stability as presented: `true`, `false`, or undecidable within
/// the multipliers' error (JSON `null`, CSV `undecidable`). The default only
/// fills the record the CSV header is named from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Verdict {
    #[default]
    Stable,
    Unstable,
    Undecidable,
}

impl Verdict {
    /// The verdict on a cycle of stability `s`.
    pub fn of(s: Stability) -> Verdict {
        match s {
            Stability::Stable => Verdict::Stable,
            Stability::Unstable => Verdict::Unstable,
            Stability::Undecidable { .. }
            | Stability::Undetermined { .. }
            | Stability::IllConditioned { .. } => Verdict::Undecidable,
        }
    }

    /// `stable`, `unstable` or `undecidable`.
    pub fn word(self) -> &'static str {
        match self {
            Verdict::Stable => "stable",
            Verdict::Unstable => "unstable",
            Verdict::Undecidable => "undecidable",
        }
    }
}

impl Serialize for Verdict {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            Verdict::Stable => s.serialize_bool(true),
            Verdict::Unstable => s.serialize_bool(false),
            // A unit struct: `null` in JSON, its name in the CSV.
            Verdict::Undecidable => s.serialize_unit_struct("undecidable"),
        }
    }
}

/// `value`, or where it is unavailable `null` in JSON and `n/a` in the CSV
/// (the JSON gives the reason beside it).
fn or_na<S: Serializer, T: Serialize>(value: &Option<T>, s: S) -> Result<S::Ok, S::Error> {
    match value {
        Some(v) => v.serialize(s),
        None => s.serialize_unit_struct("n/a"),
    }
}

/// One stick-slip cycle: an entry of `cycles` in the JSON, a row of
/// `-cycles.csv` (its scalar fields), a line of the text.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Cycle {
    pub kappa: f64,
    /// Period in units of `D0/V0`.
    pub period: f64,
    /// Peak-to-peak spring force.
    pub delta_s: f64,
    pub s_min: f64,
    pub s_max: f64,
    /// Slowest and fastest slip velocity (units of `V0`).
    pub v_min: f64,
    pub v_max: f64,
    pub stable: Verdict,
    /// `min |mu - 1|`: the error of the trivial Floquet multiplier.
    #[serde(serialize_with = "or_na")]
    pub trivial_multiplier_error: Option<f64>,
    /// Estimated discretization error (relative).
    #[serde(serialize_with = "or_na")]
    pub error_estimate: Option<f64>,
    /// Mesh intervals (`n/a` for a cycle of the return map).
    #[serde(serialize_with = "or_na")]
    pub ntst: Option<usize>,
    /// Whether the cycle is at a requested stiffness (`--at-kappa`).
    pub user_point: bool,
    pub model: ModelKind,
    /// `chi = max m |dv/dt| / A` with the scene's inertia; `n/a` where
    /// the direct effect `d mu / d ln v` is not positive on the orbit
    /// (`inertial_imbalance_reason`).
    #[serde(serialize_with = "or_na")]
    pub inertial_imbalance: Option<f64>,
    #[serde(rename = "K_over_W_per_m")]
    pub k_over_w_per_m: f64,
    /// Period \[s\].
    pub period_s: f64,
    /// Slowest and fastest slip velocity [µm/s].
    pub v_min_um_per_s: f64,
    pub v_max_um_per_s: f64,
    /// The inertia `m` the cycle was computed with (0: quasi-static).
    pub m: f64,
    /// The least friction coefficient on the orbit; negative: outside the
    /// friction law's physical range.
    pub friction_min: f64,
    /// Spring stiffness `K = kappa W / D0` [N/m] (the scene's `W`, `D0`).
    #[serde(rename = "K_N_per_m")]
    pub k_n_per_m: f64,
    /// Peak-to-peak spring force, the force drop of a slip, `Delta_s W` \[N\].
    #[serde(rename = "delta_s_N")]
    pub delta_s_n: f64,
    /// `cycles --param`: the dimensionless parameter continued, in a column
    /// named after it (`nu` for `V`); absent without `--param` and where
    /// it is `kappa` or `m`, which have their columns.
    #[serde(flatten)]
    pub continued: Option<ParamValue>,
    /// `cycles --param`: the control parameter in its unit, in a column
    /// named with it (`V_um_per_s`, `M_kg`, `tau_s`); absent without
    /// `--param` and where another column gives it.
    #[serde(flatten)]
    pub control: Option<ParamValue>,
    /// The cycle's number in the run (`#label` in the text): what
    /// `cycles --from FILE.json --index N` restarts from. Every cycle a
    /// run writes has its own, the operating point's, the branch's, the
    /// requested ones' and the bifurcations', in the order written.
    pub label: usize,
    /// `log10` of the slowest slip velocity (units of `V0`): also where
    /// `v_min` is below the range of `f64` (written 0 there).
    pub log10_v_min: f64,
    /// `[re, im]` of each Floquet multiplier, by decreasing modulus (JSON only).
    pub multipliers: Vec<[f64; 2]>,
    /// Index of the trivial multiplier among them (JSON only).
    pub trivial_multiplier_index: Option<usize>,
    /// How the cycle was computed: `collocation` or `return_map` (JSON only).
    pub method: &'static str,
    /// Why `trivial_multiplier_error` is unavailable (JSON only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub trivial_multiplier_error_reason: Option<&'static str>,
    /// Why `error_estimate` is unavailable (JSON only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error_estimate_reason: Option<&'static str>,
    /// Why `inertial_imbalance` is unavailable (JSON only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub inertial_imbalance_reason: Option<&'static str>,
    /// Why the stability is undecidable (JSON only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stability_reason: Option<String>,
    /// The least direct effect `d mu / d ln v` on the orbit (the last CSV
    /// column); not positive: the law outside its domain.
    pub direct_effect_min: f64,
}

impl CsvRecord for Cycle {
    const DIGITS: usize = 15;
    const JSON_ONLY: &'static [&'static str] = &[
        "multipliers",
        "trivial_multiplier_index",
        "method",
        "trivial_multiplier_error_reason",
        "error_estimate_reason",
        "inertial_imbalance_reason",
        "stability_reason",
    ];
}

impl Cycle {
    /// The cycle `c` in the units `u`.
    pub fn new(c: &CycleRecord, u: &Units) -> Self {
        Cycle {
            kappa: c.kappa,
            period: c.period,
            delta_s: c.delta_s,
            s_min: c.s_min,
            s_max: c.s_max,
            v_min: c.v_min,
            v_max: c.v_max,
            stable: Verdict::of(c.stability),
            trivial_multiplier_error: c.trivial_error,
            error_estimate: c.error_estimate,
            ntst: c.ntst(),
            user_point: c.user_point,
            model: c.model,
            inertial_imbalance: Some(c.inertial_imbalance).filter(|chi| chi.is_finite()),
            k_over_w_per_m: u.k_over_w(c.kappa),
            m: c.m,
            friction_min: c.friction_min,
            period_s: c.period * u.d0 / u.v0,
            v_min_um_per_s: u.velocity_um_s(c.v_min),
            v_max_um_per_s: u.velocity_um_s(c.v_max),
            log10_v_min: c.ln_v_min / std::f64::consts::LN_10,
            k_n_per_m: u.stiffness(c.kappa),
            delta_s_n: c.delta_s * u.load,
            continued: None,
            control: None,
            label: 0,
            multipliers: c.multipliers.iter().map(|z| [z.re, z.im]).collect(),
            trivial_multiplier_index: c.trivial,
            method: c.method.name(),
            trivial_multiplier_error_reason: c.trivial_error.is_none().then_some(match c.method {
                CycleMethod::Collocation { .. } => TRIVIAL_UNAVAILABLE,
                CycleMethod::ReturnMap => TRIVIAL_REMOVED,
            }),
            error_estimate_reason: c.error_estimate.is_none().then_some(ESTIMATE_UNAVAILABLE),
            inertial_imbalance_reason: (!c.inertial_imbalance.is_finite())
                .then_some(IMBALANCE_UNDEFINED),
            stability_reason: c.stability_reason(),
            direct_effect_min: c.direct_effect_min,
        }
    }
}

/// A bifurcation of cycles located on the branch, with the cycle there (an
/// entry of `special_points`).
#[derive(Clone, Debug, Serialize)]
pub struct CycleSpecialPoint {
    pub kind: CycleBifurcation,
    #[serde(flatten)]
    pub cycle: Cycle,
}

/// How a stiffness was asked for (`--at NAME=...` or `--at-kappa`): the
/// name, the value as given and its unit.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Asked {
    /// `kappa`, `K` or `K_over_W`.
    pub name: &'static str,
    /// The value as given.
    pub value: f64,
    /// Its unit: `1` (dimensionless), `N/m` or `1/m`.
    pub unit: &'static str,
}

impl Asked {
    /// The names `--at` takes, with their units.
    pub const NAMES: [(&'static str, &'static str); 3] =
        [("kappa", "1"), ("K", "N/m"), ("K_over_W", "1/m")];

    /// The stiffness asked for, as `kappa`, in the units `u`: `K D0 / W`
    /// for `K`, `(K/W) D0` for `K_over_W`.
    pub fn kappa(&self, u: &Units) -> f64 {
        match self.name {
            "K" => self.value * u.d0 / u.load,
            "K_over_W" => self.value * u.d0,
            _ => self.value,
        }
    }

    /// `K = 2.0000000000e5 N/m` (the value as given, in its unit).
    pub fn describe(&self) -> String {
        match self.name {
            "K" => format!("K = {:.10e} N/m", self.value),
            "K_over_W" => format!("K/W = {:.10e} 1/m", self.value),
            _ => format!("kappa = {:.10e}", self.value),
        }
    }
}

/// A stiffness asked for with `--at` or `--at-kappa`: an entry of
/// `requested_points`, a line of the text, a comment of the CSV when not
/// delivered.
#[derive(Clone, Debug, Serialize)]
pub struct Requested {
    pub kappa: f64,
    #[serde(rename = "K_over_W_per_m")]
    pub k_over_w_per_m: f64,
    /// `K = kappa W / D0` [N/m] (the scene's `W` and `D0`).
    #[serde(rename = "K_N_per_m")]
    pub k_n_per_m: f64,
    /// As asked: name, value and unit.
    pub asked: Asked,
    /// Whether a cycle was delivered at it.
    pub delivered: bool,
    /// How many (a branch that turns at folds passes some stiffnesses twice).
    pub cycles: usize,
    /// Why none was delivered (JSON: in words, the stiffnesses as kappa).
    #[serde(skip_serializing_if = "Option::is_none", serialize_with = "in_words")]
    pub reason: Option<NotDelivered>,
}

/// The reason in words.
fn in_words<S: Serializer>(reason: &Option<NotDelivered>, s: S) -> Result<S::Ok, S::Error> {
    match reason {
        Some(why) => s.collect_str(why),
        None => s.serialize_none(),
    }
}

impl Requested {
    /// What became of `r`, asked for as `asked`, in the units `u`.
    pub fn new(r: &RequestedPoint, asked: Asked, u: &Units) -> Self {
        Requested {
            kappa: r.value,
            k_over_w_per_m: u.k_over_w(r.value),
            k_n_per_m: u.stiffness(r.value),
            asked,
            delivered: r.delivered > 0,
            cycles: r.delivered,
            reason: r.reason.clone(),
        }
    }
}

/// How a leg of the branch ended (JSON `reason`, snake case).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum StopReason {
    /// The leg covered the requested range.
    EndOfRange,
    /// `--max-steps` continuation steps were taken first.
    StepLimit,
    /// The period grew beyond the engine's limit.
    PeriodLimit,
    /// The cycles shrank to steady sliding at a Hopf point, where they are born.
    HopfPoint,
    /// A numerical failure (the message says which).
    Failed,
    /// Ctrl-C (SIGINT) or SIGTERM.
    Interrupted,
}

/// How one leg of the branch ended: an entry of `leg_stops`; in words, a
/// part of `stop`.
#[derive(Clone, Debug, Serialize)]
pub struct LegStop {
    /// The leg; `None` when the simulated orbit to start from failed.
    pub leg: Option<Leg>,
    pub reason: StopReason,
    /// The reason in words.
    pub message: String,
}

impl LegStop {
    /// The end `outcome` of the leg `leg` traced with the step limit `max_steps`.
    pub fn new(leg: Option<Leg>, outcome: &Result<Stop, Error>, max_steps: usize) -> Self {
        let (reason, message) = match outcome {
            Ok(Stop::Bound { .. }) => {
                (StopReason::EndOfRange, "end of the requested range".into())
            }
            Ok(Stop::MaxSteps { .. }) => (
                StopReason::StepLimit,
                format!(
                    "step limit: {max_steps} continuation steps (--max-steps) taken; the range is not covered"
                ),
            ),
            Ok(Stop::MaxPeriod { .. }) => (
                StopReason::PeriodLimit,
                "period limit reached; the range is not covered".into(),
            ),
            Ok(Stop::HopfPoint { .. }) => (
                StopReason::HopfPoint,
                "the cycles shrink to steady sliding at the Hopf point, where they are born".into(),
            ),
            // Not the stop of a cycle branch.
            Ok(stop) => (StopReason::Failed, stop.to_string()),
            Err(e @ Error::Interrupted(_)) => (StopReason::Interrupted, e.to_string()),
            Err(e) => (StopReason::Failed, e.to_string()),
        };
        LegStop {
            leg,
            reason,
            message,
        }
    }

    /// Whether the leg ended where it had to: at the end of the requested
    /// range, or where its cycles end (at a Hopf point).
    pub fn complete(&self) -> bool {
        matches!(self.reason, StopReason::EndOfRange | StopReason::HopfPoint)
    }
}

/// The message, after the leg's direction when the branch has two legs.
impl fmt::Display for LegStop {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.leg {
            Some(Leg::Up) => write!(f, "toward larger stiffness: {}", self.message),
            Some(Leg::Down) => write!(f, "toward smaller stiffness: {}", self.message),
            Some(Leg::LongerPeriod) => write!(f, "toward longer periods: {}", self.message),
            Some(Leg::ShorterPeriod) => write!(f, "toward shorter periods: {}", self.message),
            Some(Leg::FromHopf | Leg::AtStiffness) | None => f.write_str(&self.message),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::records::csv::{header, row, CsvRecord};

    /// What a cycle lacks is `null` in its JSON and a word in its CSV row,
    /// and the CSV's columns are the JSON's fields.
    #[test]
    fn missing_values_are_null_in_json_and_words_in_csv() {
        let c = Cycle {
            kappa: 0.01,
            stable: Verdict::Undecidable,
            trivial_multiplier_error: None,
            error_estimate: Some(2.5e-11),
            ..Cycle::default()
        };
        let json = serde_json::to_value(&c).unwrap();
        let names = header::<Cycle>().unwrap();
        let names: Vec<&str> = names.split(',').collect();
        let mut fields: Vec<&str> = json
            .as_object()
            .unwrap()
            .keys()
            .map(|k| k.as_str())
            .filter(|k| !Cycle::JSON_ONLY.contains(k))
            .collect();
        let mut columns = names.clone();
        fields.sort_unstable();
        columns.sort_unstable();
        assert_eq!(columns, fields);
        let line = row(&c).unwrap();
        let cell = |name: &str| {
            line.split(',')
                .nth(names.iter().position(|n| *n == name).unwrap())
        };
        assert_eq!(cell("stable"), Some("undecidable"));
        assert_eq!(cell("trivial_multiplier_error"), Some("n/a"));
        assert!(json["stable"].is_null() && json["trivial_multiplier_error"].is_null());
        let estimate: f64 = cell("error_estimate").unwrap().parse().unwrap();
        assert_eq!(Some(estimate), json["error_estimate"].as_f64());
        assert_eq!(cell("model"), json["model"].as_str());
    }
}

/// The cycle at the scene's own stiffness, delivered before the branch
/// (JSON `operating_point`; only where the scene or `--set` gives K): the
/// rig's regime there as `hopf` reports it, and, unless that is steady
/// sliding, the cycle.
#[derive(Clone, Debug, Serialize)]
pub struct OperatingCycle {
    /// `K_N_per_m`, `kappa`, `regime`, `margin`, `reason` as `hopf`'s.
    #[serde(flatten)]
    pub point: OperatingPoint,
    /// Whether a cycle is looked for: not where steady sliding is the
    /// regime (or there is no spring).
    pub wanted: bool,
    pub delivered: bool,
    /// How the cycle was obtained: `simulation` (a simulated orbit
    /// corrected by collocation at K), `continuation` (along the branch
    /// from the Hopf point, where the first failed), `branch_start` (the
    /// start of a branch from a simulated orbit at K); `null` without one.
    pub method: Option<&'static str>,
    pub cycle: Option<Cycle>,
    /// The slip per event, `V T` \[µm\] (the block slides as far as the
    /// drive moves in a period).
    pub slip_um: Option<f64>,
    /// The simulated orbit the cycle was corrected from (`simulation`).
    pub simulation: Option<SimulatedOrbit>,
    /// Why the direct start failed, where the continuation delivered instead.
    pub fallback_reason: Option<String>,
    /// Why no cycle was delivered where one was wanted.
    pub not_delivered: Option<String>,
}

/// A settled simulated orbit in the scene's units.
#[derive(Clone, Debug, Serialize)]
pub struct SimulatedOrbit {
    pub model: ModelKind,
    pub oscillations: usize,
    /// Simulated time until it settled \[s\].
    pub time_s: f64,
    /// Its period from the return map \[s\].
    pub period_s: f64,
}

impl SimulatedOrbit {
    /// The orbit `o` of model `model` in the units `u`.
    pub fn new(model: ModelKind, o: &SettledOrbit, u: &Units) -> Self {
        SimulatedOrbit {
            model,
            oscillations: o.periods,
            time_s: o.time * u.d0 / u.v0,
            period_s: o.period * u.d0 / u.v0,
        }
    }
}

impl OperatingCycle {
    /// The operating point `point`, its cycle still to come.
    pub fn new(point: OperatingPoint) -> Self {
        OperatingCycle {
            wanted: point.regime != Regime::Steady && point.kappa > 0.0,
            point,
            delivered: false,
            method: None,
            cycle: None,
            slip_um: None,
            simulation: None,
            fallback_reason: None,
            not_delivered: None,
        }
    }

    /// Whether the run is short of its request without the cycle: where
    /// one exists for sure (stick-slip below K_c, or bistable); where the
    /// regime is undecided a missing cycle is reported, not a shortfall.
    pub fn missing(&self) -> bool {
        self.wanted
            && !self.delivered
            && matches!(self.point.regime, Regime::StickSlip | Regime::Bistable)
    }

    /// The cycle `c` (at the velocity `nu`) delivered by `method`.
    pub fn deliver(&mut self, c: &CycleRecord, method: &'static str, u: &Units) {
        let nu = c.params[crate::params::Param::Nu as usize];
        self.delivered = true;
        self.method = Some(method);
        self.slip_um = Some(nu * c.period * u.d0 * 1e6);
        self.cycle = Some(Cycle::new(c, u));
    }
}
