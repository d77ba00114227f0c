//! Where `stickslip cycles` starts its branch: at the Hopf point, or from a
//! simulated stick-slip orbit when there is none (or `--from-simulation`).

use super::Setup;
use crate::analysis::cycles::{
    trace_cycles_from, trace_cycles_from_orbit, BranchEnd, CycleRecord, CycleRequest,
};
use crate::analysis::hopf::{HopfOutcome, HopfPoint};
use crate::analysis::orbit_start::{simulated_start, OrbitStart};
use crate::error::{Error, NumericalError};
use serde_json::{json, Value};

/// The start of the cycle branch.
pub enum Start {
    Hopf(HopfPoint),
    Simulation {
        orbit: OrbitStart,
        /// The Hopf point, when there is one (the simulation was asked for).
        hopf: Option<HopfPoint>,
    },
}

impl Start {
    /// The Hopf point unless `from_simulation` or there is none; then the
    /// first stiffness at which a simulation settles on a cycle.
    pub fn choose(
        setup: &Setup,
        onset: HopfOutcome,
        from_simulation: bool,
    ) -> Result<Start, NumericalError> {
        let hopf = match onset {
            HopfOutcome::Found(h) => Some(h),
            HopfOutcome::StableForAllStiffness { .. } => None,
        };
        match hopf {
            Some(h) if !from_simulation => Ok(Start::Hopf(h)),
            hopf => {
                let kappa_c = hopf.as_ref().map(|h| h.kappa_c);
                let orbit = simulated_start(setup.choice.kind, &setup.params, kappa_c)?;
                Ok(Start::Simulation { orbit, hopf })
            }
        }
    }

    /// The critical stiffness, if there is a Hopf point.
    pub fn kappa_c(&self) -> Option<f64> {
        match self {
            Start::Hopf(h) | Start::Simulation { hopf: Some(h), .. } => Some(h.kappa_c),
            Start::Simulation { hopf: None, .. } => None,
        }
    }

    /// The stiffness the branch is measured against: `kappa_c`, or the
    /// simulated orbit's stiffness without a Hopf point.
    pub fn reference_kappa(&self) -> f64 {
        match self {
            Start::Simulation { orbit, hopf: None } => orbit.params.kappa,
            _ => self.kappa_c().unwrap_or(0.0),
        }
    }

    /// What the text output says about the start (nothing for a Hopf start).
    pub fn describe(&self, setup: &Setup) -> Option<String> {
        let Start::Simulation { orbit, hopf } = self else {
            return None;
        };
        let kappa = orbit.params.kappa;
        let why = match hopf {
            None => "no Hopf point (steady sliding stable for every stiffness)",
            Some(_) => "--from-simulation",
        };
        let tried: Vec<String> = orbit
            .rejected
            .iter()
            .map(|e| format!("  tried first: {}", e.summary()))
            .collect();
        Some(format!(
            "{}{why}: starting from a simulated stick-slip orbit at kappa = {kappa:.6e} \
             (K/W = {:.6e} 1/m), settled after {} oscillations (t = {:.4e}), period {:.6e}",
            tried.iter().map(|l| format!("{l}\n")).collect::<String>(),
            setup.scene.units.k_over_w(kappa),
            orbit.orbit.periods,
            orbit.orbit.time,
            orbit.orbit.period,
        ))
    }

    /// The start as JSON.
    pub fn json(&self) -> Value {
        match self {
            Start::Hopf(h) => json!({"kind": "hopf", "kappa": h.kappa_c}),
            Start::Simulation { orbit, .. } => json!({
                "kind": "simulation", "kappa": orbit.params.kappa,
                "period": orbit.orbit.period, "oscillations": orbit.orbit.periods,
                "time": orbit.orbit.time,
            }),
        }
    }

    /// Traces the branch, handing each cycle to `sink`; returns how each leg
    /// ended, labelled (one leg from a Hopf point, two from a simulated orbit).
    /// A leg that ended without an error says why ([`BranchEnd`]).
    pub fn trace(
        &self,
        setup: &Setup,
        req: &CycleRequest,
        mut sink: impl FnMut(&CycleRecord) -> Result<(), Error>,
    ) -> Vec<(&'static str, Result<BranchEnd, Error>)> {
        let kind = setup.choice.kind;
        match self {
            Start::Hopf(h) => vec![("", trace_cycles_from(kind, &setup.params, h, req, sink))],
            Start::Simulation { orbit, .. } => {
                match trace_cycles_from_orbit(kind, &orbit.params, &orbit.orbit, req, &mut sink) {
                    Ok([up, down]) => vec![
                        ("toward larger stiffness", up),
                        ("toward smaller stiffness", down),
                    ],
                    Err(e) => vec![("", Err(e))],
                }
            }
        }
    }
}
