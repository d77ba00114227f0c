//! Where `stickslip cycles` starts its branch: at the Hopf point, or from a
//! simulated stick-slip orbit when there is none (or `--from-simulation`).

use super::restart::Restarted;
use super::{Setup, TextUnits};
use crate::analysis::cycles::{
    trace_cycles_from, trace_cycles_from_orbit, trace_cycles_through, CycleRecord, CycleRequest,
    Leg, Stop, Through,
};
use crate::analysis::hopf::{velocity_strengthening, Criticality, HopfOutcome, HopfPoint};
use crate::analysis::orbit_inertia::InertiaWatch;
use crate::analysis::orbit_start::{simulated_start, NoCycleFound, OrbitStart};
use crate::analysis::settle::SettleError;
use crate::error::{Error, NumericalError};
use crate::model::ModelKind;
use crate::params::Param;
use serde_json::{json, Value};

/// The start of the cycle branch.
pub enum Start {
    Hopf(HopfPoint),
    Simulation {
        orbit: OrbitStart,
        /// The Hopf point, when there is one (the simulation was asked for).
        hopf: Option<HopfPoint>,
    },
    /// No branch: steady sliding is velocity strengthening (stable for every
    /// stiffness, no Hopf point) and no simulation settled on a cycle.
    NoCycle {
        /// Why, in words: the friction slopes and each stiffness simulated.
        reason: String,
        /// The simulations tried.
        tried: NoCycleFound,
    },
    /// A cycle written by an earlier run (`--from FILE.json --index N`),
    /// continued both ways as it was computed.
    Stored(Box<Restarted>),
}

impl Start {
    /// The Hopf point unless `from_simulation`, there is none or it is
    /// degenerate; then the
    /// first stiffness at which a simulation settles on a cycle, in the
    /// model the orbit needs (judged under `watch`).
    pub fn choose(
        setup: &Setup,
        onset: HopfOutcome,
        from_simulation: bool,
        watch: &InertiaWatch,
    ) -> Result<Start, NumericalError> {
        let hopf = match onset {
            HopfOutcome::Found(h) => Some(h),
            HopfOutcome::StableForAllStiffness { .. } => None,
        };
        match hopf {
            // At a degenerate Hopf point (l1 = 0 within its bound: the
            // quasi-static Rice–Ruina law, a Bautin point) the normal form
            // does not say on which side the cycles are: start from a
            // simulated orbit instead.
            Some(h) if !from_simulation && h.onset.criticality != Criticality::Degenerate => {
                Ok(Start::Hopf(h))
            }
            hopf => {
                let kappa_c = hopf.as_ref().map(|h| h.kappa_c);
                match simulated_start(setup.choice.kind, &setup.scene_params, kappa_c, watch) {
                    Ok(orbit) => Ok(Start::Simulation { orbit, hopf }),
                    // Linearly stable for every stiffness and no cycle by simulation:
                    // an answer (an empty branch), not a failure.
                    Err(tried) if hopf.is_none() && velocity_strengthening(&setup.params) => {
                        Ok(Start::NoCycle {
                            reason: no_cycle_reason(setup, &tried),
                            tried,
                        })
                    }
                    // Its message names every stiffness tried and why it failed.
                    Err(e) => Err(NumericalError::Analysis(e.to_string())),
                }
            }
        }
    }

    /// The model of the branch's first cycles: the simulated orbit's (it may
    /// need the inertia the onset drops) or the stored one's, else the
    /// onset's `onset_kind`.
    pub fn first_model(&self, onset_kind: ModelKind) -> ModelKind {
        match self {
            Start::Simulation { orbit, .. } => orbit.kind,
            Start::Stored(restarted) => restarted.log.kind,
            Start::Hopf(_) | Start::NoCycle { .. } => onset_kind,
        }
    }

    /// The critical stiffness, if there is a Hopf point.
    pub fn kappa_c(&self) -> Option<f64> {
        match self {
            Start::Hopf(h) | Start::Simulation { hopf: Some(h), .. } => Some(h.kappa_c),
            Start::Stored(r) => r.kappa_c,
            Start::Simulation { hopf: None, .. } | Start::NoCycle { .. } => None,
        }
    }

    /// Why there is no branch at all ([`Start::NoCycle`]).
    pub fn reason(&self) -> Option<&str> {
        match self {
            Start::NoCycle { reason, .. } => Some(reason),
            _ => None,
        }
    }

    /// Whether the search for a start was conclusive: false when a
    /// simulation neither decayed nor settled (or failed), so a cycle may
    /// have been missed.
    pub fn conclusive(&self) -> bool {
        match self {
            Start::NoCycle { tried, .. } => tried
                .tries
                .iter()
                .all(|t| matches!(t, SettleError::Decayed { .. })),
            _ => true,
        }
    }

    /// The stiffness the branch is measured against: `kappa_c`, or the
    /// simulated orbit's stiffness without a Hopf point.
    pub fn reference_kappa(&self) -> f64 {
        match self {
            Start::Simulation { orbit, hopf: None } => orbit.params.kappa,
            Start::NoCycle { tried, .. } => tried.tries.first().map_or(0.0, SettleError::kappa),
            Start::Stored(r) => r.reference_kappa.unwrap_or(r.orbit.param(Param::Kappa)),
            _ => self.kappa_c().unwrap_or(0.0),
        }
    }

    /// What the text output says about the start, stiffnesses in `units`.
    pub fn describe(&self, setup: &Setup, units: TextUnits) -> String {
        let (orbit, hopf) = match self {
            Start::Simulation { orbit, hopf } => (orbit, hopf),
            Start::NoCycle { reason, .. } => return format!("no cycles: {reason}"),
            Start::Stored(r) => {
                let u = &setup.scene.units;
                let kappa = r.orbit.param(Param::Kappa);
                let (stiffness, period) = match units {
                    TextUnits::Physical => (
                        format!("K = {:.10e} N/m", u.stiffness(kappa)),
                        format!("{:.10e} s", r.orbit.period * u.d0 / u.v0),
                    ),
                    TextUnits::Dimensionless => (
                        format!("kappa = {kappa:.10e}"),
                        format!("{:.10e} D0/V0", r.orbit.period),
                    ),
                };
                let (what, corrected) = r.correction_words();
                return format!(
                    "restarting from cycle #{} of {}{what} ({} model, {stiffness}, period {period}, \
                     NTST {}), corrected on its own mesh {corrected}, continued both ways",
                    r.from.index,
                    r.from.file.display(),
                    r.orbit.model.name(),
                    r.orbit.mesh.len() - 1
                );
            }
            Start::Hopf(h) => {
                let k_over_w = setup.scene.units.k_over_w(h.kappa_c);
                return format!(
                    "from the Hopf point at {}",
                    units.stiffness(h.kappa_c, k_over_w, 10)
                );
            }
        };
        let kappa = orbit.params.kappa;
        let why = match hopf {
            None => "no Hopf point (steady sliding stable for every stiffness)".to_string(),
            Some(h) if h.onset.criticality == Criticality::Degenerate => format!(
                "degenerate Hopf point (l1 = {:.3e} within its error bound {:.1e}: the normal form \
                 does not say on which side the cycles are)",
                h.onset.l1, h.onset.l1_error_bound
            ),
            Some(_) => "--from-simulation".to_string(),
        };
        let tried: Vec<String> = orbit
            .rejected
            .iter()
            .map(|e| format!("  tried first: {}", e.summary()))
            .collect();
        // Times in the text's units: seconds, or D0/V0.
        let u = &setup.scene.units;
        let time = |t: f64| match units {
            TextUnits::Physical => format!("{:.4e} s", t * u.d0 / u.v0),
            TextUnits::Dimensionless => format!("{t:.4e} D0/V0"),
        };
        // Said only where the orbit needed another model than the onset's.
        let model = if orbit.kind == setup.choice.kind {
            String::new()
        } else {
            format!(
                ", {} (inertia matters on the {} orbit)",
                orbit.kind.name(),
                setup.choice.kind.name()
            )
        };
        format!(
            "{}{why}: starting from a simulated stick-slip orbit at kappa = {kappa:.6e} \
             (K/W = {:.6e} 1/m), settled after {} (t = {}), period {}{model}",
            tried.iter().map(|l| format!("{l}\n")).collect::<String>(),
            u.k_over_w(kappa),
            oscillations(orbit.orbit.periods),
            time(orbit.orbit.time),
            time(orbit.orbit.period),
        )
    }

    /// The start as JSON.
    pub fn json(&self) -> Value {
        match self {
            Start::Hopf(h) => json!({"kind": "hopf", "kappa": h.kappa_c}),
            Start::Simulation { orbit, hopf } => json!({
                "kind": "simulation", "kappa": orbit.params.kappa,
                "period": orbit.orbit.period, "oscillations": orbit.orbit.periods,
                "time": orbit.orbit.time,
                // Stiffnesses simulated first that did not settle on a cycle.
                "rejected": orbit.rejected.iter().map(|t| json!({
                    "kappa": t.kappa(), "outcome": t.summary(),
                })).collect::<Vec<_>>(),
                "degenerate_hopf": hopf.as_ref().is_some_and(|h| h.onset.criticality == Criticality::Degenerate),
            }),
            Start::Stored(r) => json!({
                "kind": "restart", "file": r.from.file.display().to_string(),
                "label": r.from.index, "kappa": r.orbit.param(Param::Kappa),
                "period": r.orbit.period, "model": r.orbit.model,
                "lpc": r.fold_in.is_some(),
                "reference_kappa": self.reference_kappa(),
            }),
            Start::NoCycle { tried, .. } => json!({
                "kind": "none",
                "simulated": tried.tries.iter().map(|t| json!({
                    "kappa": t.kappa(), "outcome": t.summary(),
                })).collect::<Vec<_>>(),
            }),
        }
    }

    /// Traces the branch, handing each cycle to `sink`; returns how each leg
    /// ended, with the leg (one from a Hopf point, two from a simulated orbit;
    /// none when the simulated orbit itself failed).
    /// A quasi-static branch hands over to the inertial model where `watch`
    /// says so.
    /// A leg that ended without an error says why ([`Stop`]).
    pub fn trace(
        &self,
        setup: &Setup,
        req: &CycleRequest,
        watch: &InertiaWatch,
        mut sink: impl FnMut(&CycleRecord) -> Result<(), Error>,
    ) -> Vec<(Option<Leg>, Result<Stop, Error>)> {
        let kind = setup.choice.kind;
        match self {
            Start::Hopf(h) => vec![(
                Some(Leg::FromHopf),
                trace_cycles_from(kind, &setup.params, h, req, watch, sink),
            )],
            Start::Simulation { orbit, .. } => {
                match trace_cycles_from_orbit(
                    orbit.kind,
                    &orbit.params,
                    &orbit.orbit,
                    req,
                    watch,
                    &mut sink,
                ) {
                    Ok(legs) => legs.map(|(leg, end)| (Some(leg), end)).into(),
                    Err(e) => vec![(None, Err(e))],
                }
            }
            Start::Stored(r) => {
                let through = Through::Stored {
                    log: r.log,
                    cycle: &r.cycle,
                    fold: r.fold_in == Some(Param::Kappa),
                };
                match trace_cycles_through(&through, Param::Kappa, req, watch, &mut sink) {
                    Ok(legs) => legs.map(|(leg, end)| (Some(leg), end)).into(),
                    Err(e) => vec![(None, Err(e))],
                }
            }
            Start::NoCycle { .. } => Vec::new(),
        }
    }
}

/// The words for [`Start::NoCycle`]: the friction slopes that make steady
/// sliding stable for every stiffness, and what each simulation gave.
fn no_cycle_reason(setup: &Setup, tried: &NoCycleFound) -> String {
    let p = &setup.params;
    let kappas: Vec<String> = tried
        .tries
        .iter()
        .map(|t| format!("{:.3e}", t.kappa()))
        .collect();
    format!(
        "steady sliding is stable and no stick-slip cycle was found by simulation at kappa = {} ({}); \
         velocity strengthening at nu = {:.6e}: mu_phi - mu_v = {:.4e} <= 0 (mu_phi = {:.6e}, mu_v = {:.6e}, \
         slopes of the friction law at steady sliding), so steady sliding is linearly stable for every \
         stiffness and no cycle is born at a Hopf point. Finite-amplitude cycles coexisting with it, if \
         any, were not reached from a stuck start{}",
        kappas.join(", "),
        tried.tries.iter().map(SettleError::summary).collect::<Vec<_>>().join("; "),
        p.nu,
        p.mu_phi() - p.mu_v_damped(),
        p.mu_phi(),
        p.mu_v_damped(),
        no_cycle_advice(p, tried),
    )
}

/// What else may reach a coexisting cycle, leaving out what was tried: a
/// smaller stiffness only where the search stopped above its floor,
/// `max(A, B) 1e-5` (see `orbit_start`), a velocity nearer the friction minimum only where
/// steady friction has one ([`crate::friction::FrictionLaw::v_min`]: the cutoff law's
/// `V_min`; the logarithmic form's at `ln nu = (B - A)/(2 (mu2 + mu_vv - mu_vphi))`
/// where that sum is positive).
fn no_cycle_advice(p: &crate::params::Params, tried: &NoCycleFound) -> String {
    let smallest = tried
        .tries
        .iter()
        .map(SettleError::kappa)
        .fold(f64::INFINITY, f64::min);
    let mut tries = Vec::new();
    if smallest > 1.001e-5 * p.a.max(p.b) {
        tries.push("--set kappa=... smaller".to_string());
    }
    if let Some(v) = p.friction().v_min().filter(|v| v.is_finite() && *v > 0.0) {
        tries.push(format!(
            "--set nu=... closer to the friction minimum (nu = {v:.4e})"
        ));
    }
    if tries.is_empty() {
        String::new()
    } else {
        format!(": try {}", tries.join(", or "))
    }
}

/// `n oscillation(s)`, in the singular for one.
fn oscillations(n: usize) -> String {
    if n == 1 {
        "1 oscillation".into()
    } else {
        format!("{n} oscillations")
    }
}
