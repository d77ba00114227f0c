//! The stick-slip onset: the Hopf point of steady sliding in the stiffness.
//!
//! The steady branch is continued in `kappa` from a stable stiffness downward;
//! the Hopf test function's sign change is located by Newton's method on the
//! minimally augmented Hopf system (engine, [`continuation::events`]). The
//! closed forms of Appendix C are not used to find the point.

use crate::error::NumericalError;
use crate::model::{full_state, steady_state, DrivenBlock, ModelKind};
use crate::params::{Param, Params};
use continuation::linalg::{count_unstable, eigenvalues};
use continuation::system::jacobian;
use continuation::{Branch, Complex64, ContinuationSettings, Direction, EventKind};

/// A located Hopf point of steady sliding.
#[derive(Clone, Debug)]
pub struct HopfPoint {
    /// Critical stiffness `kappa_c = K_c D0 / W`.
    pub kappa_c: f64,
    /// Angular frequency at onset, units `V0/D0`.
    pub omega_c: f64,
    /// The steady state at onset as `(s, v, theta)`.
    pub state: [f64; 3],
    /// Eigenvalues at onset, by decreasing real part.
    pub eigenvalues: Vec<Complex64>,
    /// Newton iterations of the location and its final residual.
    pub newton_iterations: usize,
    pub residual: f64,
    /// Accepted continuation steps before the point was bracketed.
    pub steps: usize,
}

/// What the search for the stick-slip onset found.
#[derive(Clone, Debug)]
pub enum HopfOutcome {
    /// Steady sliding loses stability at a Hopf point.
    Found(HopfPoint),
    /// Steady sliding stays linearly stable down to `kappa_min` (e.g. for
    /// velocity-strengthening friction, `B <= A`).
    StableForAllStiffness { kappa_min: f64 },
}

/// A stiffness at which steady sliding is linearly stable, found by doubling
/// from a scale built from the friction coefficients. Errors when none is
/// found (the steady state is unstable at every stiffness tried).
pub fn stable_stiffness(block: &DrivenBlock, params: &Params) -> Result<f64, NumericalError> {
    let scale = (params.b + params.a + params.mu2.abs() * (1.0 + params.nu.ln().abs()))
        * (1.0 + params.inertia_ratio());
    let x = steady_state(block.kind(), params);
    let mut kappa = 4.0 * scale;
    for _ in 0..60 {
        let mut p = *params;
        p.kappa = kappa;
        let ev = eigenvalues(&jacobian(block, &x, &p.to_vec())).map_err(NumericalError::from)?;
        if count_unstable(&ev) == 0 {
            return Ok(kappa);
        }
        kappa *= 2.0;
    }
    Err(NumericalError::Analysis(format!(
        "steady sliding is unstable at every stiffness up to kappa = {kappa:.3e}; \
         check the friction parameters (is A > 0?)"
    )))
}

/// Continues steady sliding in `kappa` downward from a stable stiffness and
/// locates the first Hopf point.
pub fn find_hopf(kind: ModelKind, params: &Params) -> Result<HopfOutcome, NumericalError> {
    let block = DrivenBlock::new(kind, params);
    let k0 = stable_stiffness(&block, params)?;
    let mut p = *params;
    p.kappa = k0;
    let kappa_min = 1e-12 * k0;
    let settings = ContinuationSettings {
        ds: 0.02 * k0,
        ds_max: 0.1 * k0,
        ds_min: 1e-12 * k0,
        p_min: kappa_min,
        direction: Direction::Decreasing,
        max_steps: 10_000,
        ..Default::default()
    };
    let x0 = steady_state(kind, &p);
    let branch = Branch::new(&block, &x0, &p.to_vec(), Param::Kappa as usize, settings)
        .map_err(NumericalError::from)?;
    for (steps, point) in branch.enumerate() {
        let point = point.map_err(NumericalError::from)?;
        let hopf = point.events.iter().find_map(|e| match e.kind {
            EventKind::Hopf { omega } => Some((e, omega)),
            EventKind::Fold => None,
        });
        if let Some((e, omega)) = hopf {
            return Ok(HopfOutcome::Found(HopfPoint {
                kappa_c: e.param(),
                omega_c: omega,
                state: full_state(kind, params, &e.x),
                eigenvalues: e.eigenvalues.clone(),
                newton_iterations: e.newton.iterations,
                residual: e.newton.residual,
                steps,
            }));
        }
        if point.n_unstable > 0 {
            return Err(NumericalError::Analysis(format!(
                "steady sliding became unstable at kappa = {:.6e} without a Hopf point \
                 ({} unstable eigenvalues): a real eigenvalue crossed zero",
                point.param(),
                point.n_unstable
            )));
        }
    }
    Ok(HopfOutcome::StableForAllStiffness { kappa_min })
}
