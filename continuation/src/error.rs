//! Typed errors of the engine. Each carries the numbers needed to judge the
//! failure and its message says what to try.

use thiserror::Error;

/// Why Newton's method stopped without converging.
#[derive(Clone, Debug, PartialEq)]
pub enum NewtonFailure {
    /// The iteration limit was reached.
    MaxIterations,
    /// The Jacobian of the (augmented) system was singular.
    SingularJacobian,
    /// A residual or an iterate was NaN or infinite.
    NonFinite,
}

/// `{:.3e}` of a finite value, `none` for a step that was never taken
/// (infinite or NaN: the linear solve failed), so that no message prints
/// `inf` or `NaN`.
fn finite_or_none(v: f64) -> String {
    if v.is_finite() {
        format!("{v:.3e}")
    } else {
        "none".to_string()
    }
}

/// An engine failure, with the last good state and the numbers that explain it.
#[derive(Debug, Error)]
pub enum ContinuationError {
    #[error(
        "Newton did not converge{context} after {iterations} iterations \
         (residual {residual:.3e}, last step {}, {reason:?}); {hint}",
        finite_or_none(*step)
    )]
    Newton {
        context: String,
        iterations: usize,
        residual: f64,
        step: f64,
        reason: NewtonFailure,
        hint: &'static str,
    },
    #[error(
        "continuation stalled at {param_name} = {param:.10e}: step size {ds:.3e} fell below \
         the minimum {ds_min:.3e} ({cause}); the branch may end, fold sharply, or need a \
         smaller ds_min or rescaled variables"
    )]
    StepTooSmall {
        param_name: String,
        param: f64,
        ds: f64,
        ds_min: f64,
        cause: String,
    },
    #[error("the starting point is not an equilibrium: {0}")]
    BadStart(Box<ContinuationError>),
    #[error(
        "a singular linear system was met (the Jacobian or its bordered form is not invertible)"
    )]
    Singular,
    #[error(
        "degenerate Hopf point: l1 = {l1:.3e} vanishes against its terms ({scale:.3e}), so the \
         normal form does not say on which side the cycles are (for the quasi-static Rice–Ruina \
         law a whole family of cycles exists at the critical parameter); add the ln² term or \
         inertia, or start from a simulated orbit"
    )]
    DegenerateHopf { l1: f64, scale: f64 },
    #[error(
        "the periodic orbit at p = {param:.10e} is no longer resolved: its estimated discretization \
         error is {error:.2e} (tolerance {tol:.0e}) with {ntst} mesh intervals, the limit; the cycle \
         has become too stiff for this mesh — raise the interval limit (`cycles --ntst-max`), or stop here"
    )]
    Unresolved {
        ntst: usize,
        error: f64,
        tol: f64,
        param: f64,
    },
    #[error(
        "the Floquet multipliers of the periodic orbit at p = {param:.10e} can no longer decide its \
         stability: the trivial multiplier is off by {trivial_error:.2e} and another multiplier is \
         that close to the unit circle; perturbations grow by so many decades along the orbit that \
         rounding dominates (the orbit itself is resolved); judge stability by simulation \
         (`stickslip simulate`) from here on"
    )]
    FloquetIllConditioned { param: f64, trivial_error: f64 },
    #[error(
        "the located point p = {found:.10e} is not the crossing bracketed by [{from:.10e}, {to:.10e}] \
         (outside it, or with a vanishing frequency): Newton converged to another solution"
    )]
    OutsideBracket { found: f64, from: f64, to: f64 },
    #[error("sparse linear algebra failed: {0}")]
    Sparse(String),
    #[error("eigenvalue computation failed: {0}")]
    Eigen(String),
    #[error("non-finite value {what} at {param_name} = {param:.10e}; check the model's domain (logarithms of non-positive values?)")]
    NonFinite {
        what: String,
        param_name: String,
        param: f64,
    },
    #[error("{kind} location failed between {param_name} = {from:.10e} and {to:.10e}: {cause}")]
    Location {
        kind: &'static str,
        param_name: String,
        from: f64,
        to: f64,
        cause: Box<ContinuationError>,
    },
}
