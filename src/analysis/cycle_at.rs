//! The stick-slip cycle at a given stiffness, directly, without continuing
//! a branch to it: the way an experiment finds it, then corrected.
//!
//! 1. **Simulate** at the stiffness from a stuck start
//!    ([`settled_at`]: Radau IIA until the return map on `v = nu`
//!    settles) in the model chosen at onset.
//! 2. **Decide the model on the whole orbit**, as `simulate` does
//!    (`settled_with_inertia_judged`): a quasi-static orbit is followed
//!    under the inertia watch (`chi = m |dv/dt| / A` against the threshold,
//!    docs/cycles.md "Which model") and, where it hands over, settled again
//!    with the scene's inertia.
//! 3. **Correct by collocation** at the stiffness ([`cycle_through_orbit`]):
//!    the orbit on a mesh from the integrator's steps, equidistributed,
//!    Newton at fixed `kappa`, the mesh refined until the error estimate
//!    meets the branch's tolerance, and the Floquet multipliers.
//!
//! Continuing the branch from the Hopf point to a stiffness far below
//! `kappa_c` takes hundreds of steps (the rig at 1 µm/s: 28 s); this takes
//! one simulation and one corrected orbit. It finds the stable cycle a
//! stuck start settles on; where that fails the error says which step and
//! why ([`CycleAtError`]).

use crate::analysis::cycles::{cycle_through_orbit, CycleRecord, CycleRequest};
use crate::analysis::orbit_inertia::InertiaWatch;
use crate::analysis::orbit_start::settled_at;
use crate::analysis::settle::SettleError;
use crate::analysis::simulate::JudgedOrbit;
use crate::model::ModelKind;
use crate::params::Params;
use thiserror::Error;

/// The cycle at a stiffness and the simulated orbit it was corrected from.
#[derive(Clone, Debug)]
pub struct CycleAt {
    pub record: CycleRecord,
    /// The settled orbit: its model, parameters, period and how long it
    /// took to settle.
    pub simulated: JudgedOrbit,
}

/// Why the direct start gave no cycle, by step.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum CycleAtError {
    /// No periodic orbit by simulation (decayed to steady sliding, did not
    /// settle, or the integration failed).
    #[error("simulating from a stuck start: {0}")]
    Simulation(SettleError),
    /// The settled orbit did not correct by collocation.
    #[error(
        "the simulated orbit ({model}, period {period:.6e} D0/V0, settled after {periods} \
         oscillations) did not correct by collocation at kappa = {kappa:.6e}: {cause}"
    )]
    Collocation {
        kappa: f64,
        model: &'static str,
        period: f64,
        periods: usize,
        cause: String,
    },
}

/// The cycle at the stiffness `kappa` of the scene `scene` (its parameters,
/// inertia kept), simulated in the model `kind` (the one chosen at onset)
/// and judged on the whole orbit under `watch`; corrected with `req`'s mesh
/// settings (`req.ntst`, `ntst_max`, collocation points).
pub fn cycle_at(
    scene: &Params,
    kind: ModelKind,
    kappa: f64,
    watch: &InertiaWatch,
    req: &CycleRequest,
) -> Result<CycleAt, CycleAtError> {
    let simulated = settled_at(kind, scene, kappa, watch).map_err(CycleAtError::Simulation)?;
    let record = cycle_through_orbit(
        simulated.kind,
        &simulated.params,
        &simulated.orbit,
        req,
        watch,
    )
    .map_err(|e| CycleAtError::Collocation {
        kappa,
        model: simulated.kind.name(),
        period: simulated.orbit.period,
        periods: simulated.orbit.periods,
        cause: e.to_string(),
    })?;
    Ok(CycleAt { record, simulated })
}
