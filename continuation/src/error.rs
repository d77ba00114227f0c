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
    /// The step stopped shrinking above the tolerance (within `1e3` of it):
    /// the rounding floor of an ill-conditioned system, which smaller
    /// continuation steps do not lower.
    Stalled,
}

/// `{:.3e}` of a finite value, `otherwise` for a value that is not (a step
/// never taken because the linear solve failed, a residual that overflowed),
/// so that no message prints `inf` or `NaN`.
fn finite_or(v: f64, otherwise: &str) -> String {
    if v.is_finite() {
        format!("{v:.3e}")
    } else {
        otherwise.to_string()
    }
}

/// Why the multipliers of [`ContinuationError::FloquetIllConditioned`]
/// cannot decide: the trivial multiplier's error, or, when the pencil left it
/// undetermined (`trivial_error` infinite), that fact instead of `inf`.
fn trivial_multiplier_off(trivial_error: f64) -> String {
    if trivial_error.is_finite() {
        format!(
            "the trivial multiplier is off by {trivial_error:.2e} and another multiplier is that \
             close to the unit circle"
        )
    } else {
        "the Floquet pencil is singular to rounding and does not determine the trivial \
         multiplier (the eigenvalue 1)"
            .to_string()
    }
}

/// `; hint`, or nothing without one.
fn advice(hint: &str) -> String {
    if hint.is_empty() {
        String::new()
    } else {
        format!("; {hint}")
    }
}

/// An engine failure, with the last good state and the numbers that explain it.
#[derive(Debug, Error)]
pub enum ContinuationError {
    #[error(
        "Newton did not converge{context} after {iterations} iterations \
         (residual {}, last step {}, {reason:?}){}",
        finite_or(*residual, "beyond the floating-point range"),
        finite_or(*step, "none"),
        advice(hint)
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
         normal form does not say on which side the cycles are; start the branch from a \
         computed orbit instead"
    )]
    DegenerateHopf { l1: f64, scale: f64 },
    #[error(
        "the periodic orbit at {param_name} = {param:.10e} is no longer resolved: its estimated discretization \
         error is {} (tolerance {tol:.0e}) with {ntst} mesh intervals, the limit; the cycle \
         has become too stiff for this mesh — raise the interval limit, or stop here",
        finite_or(*error, "unknown (the orbit could not be solved on half the mesh)")
    )]
    Unresolved {
        param_name: String,
        ntst: usize,
        /// Estimated discretization error; infinite when the orbit could
        /// not be solved on half the mesh to compare with.
        error: f64,
        tol: f64,
        param: f64,
    },
    #[error(
        "the Floquet multipliers of the periodic orbit at {param_name} = {param:.10e} can no longer decide its \
         stability: {}; perturbations grow by so many decades along the orbit that \
         rounding dominates (the orbit itself is resolved); judge stability by time integration \
         from here on",
        trivial_multiplier_off(*trivial_error)
    )]
    FloquetIllConditioned {
        param_name: String,
        param: f64,
        /// Distance of the computed trivial multiplier from 1; infinite when
        /// the Floquet pencil did not determine it.
        trivial_error: f64,
    },
    #[error(
        "the located point p = {found:.10e} is not the crossing bracketed by [{from:.10e}, {to:.10e}] \
         (outside it, or with a vanishing frequency): Newton converged to another solution"
    )]
    OutsideBracket { found: f64, from: f64, to: f64 },
    #[error(
        "internal error: {what} has length {found} where the system has {expected} \
         (a vector from another mesh?); please report"
    )]
    Shape {
        what: &'static str,
        expected: usize,
        found: usize,
    },
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
    #[error(
        "the Hopf point at {param_name} = {at:.10e} beside the Bautin point at {bautin:.10e} \
         is not subcritical beyond rounding (l1 = {l1:.3e}, rounding bound {bound:.1e}): its \
         cycles do not fold back; the folds of a Bautin point with l2 < 0 lie where l1 > 0, so \
         start from a Hopf point on that side, farther from the Bautin point where l1 is within \
         its bound"
    )]
    NotSubcritical {
        param_name: String,
        /// The second parameter at the Hopf point beside, and at the Bautin point.
        at: f64,
        bautin: f64,
        l1: f64,
        bound: f64,
    },
    #[error(
        "the cycles born at the Hopf point at {param_name} = {at:.10e} beside the Bautin point \
         at {bautin:.10e} did not fold back before their branch ended{}",
        stop.map_or(String::new(), |s| format!(" ({s})"))
    )]
    NoFoldOfCycles {
        param_name: String,
        /// The second parameter at the Hopf point beside, and at the Bautin point.
        at: f64,
        bautin: f64,
        /// How the branch of cycles ended (set by the driver whenever its
        /// iteration ended without an error).
        stop: Option<crate::driver::Stop>,
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

impl ContinuationError {
    /// The failure without the engine's advice on what to try (a Newton
    /// failure's `hint`, also as the cause of a location): for a caller
    /// that has no such knob to offer and says what to do itself.
    pub fn without_hint(self) -> Self {
        match self {
            ContinuationError::Newton {
                context,
                iterations,
                residual,
                step,
                reason,
                ..
            } => ContinuationError::Newton {
                context,
                iterations,
                residual,
                step,
                reason,
                hint: "",
            },
            ContinuationError::Location {
                kind,
                param_name,
                from,
                to,
                cause,
            } => ContinuationError::Location {
                kind,
                param_name,
                from,
                to,
                cause: Box::new(cause.without_hint()),
            },
            other => other,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The words of `text` that spell a non-finite number.
    fn non_finite_words(text: &str) -> Vec<&str> {
        text.split(|c: char| !c.is_ascii_alphanumeric())
            .filter(|w| w.eq_ignore_ascii_case("nan") || w.eq_ignore_ascii_case("inf"))
            .collect()
    }

    #[test]
    fn messages_with_non_finite_numbers_say_what_they_mean() {
        // Each seen by the property test (tests/property_edges.rs) as `inf`.
        let newton = ContinuationError::Newton {
            context: " correcting a periodic orbit".into(),
            iterations: 1,
            residual: f64::INFINITY,
            step: 3.784e6,
            reason: NewtonFailure::NonFinite,
            hint: "a smaller step may stay inside it",
        }
        .to_string();
        assert!(
            newton.contains("residual beyond the floating-point range"),
            "{newton}"
        );
        let floquet = ContinuationError::FloquetIllConditioned {
            param_name: "p[0]".into(),
            param: 289.9,
            trivial_error: f64::INFINITY,
        }
        .to_string();
        assert!(
            floquet.contains("does not determine the trivial multiplier"),
            "{floquet}"
        );
        let unresolved = ContinuationError::Unresolved {
            param_name: "p[0]".into(),
            ntst: 640,
            error: f64::INFINITY,
            tol: 1e-6,
            param: 0.01,
        }
        .to_string();
        assert!(unresolved.contains("error is unknown"), "{unresolved}");
        for text in [newton, floquet, unresolved] {
            assert!(non_finite_words(&text).is_empty(), "{text}");
        }
        // Finite values are printed as numbers.
        let floquet = ContinuationError::FloquetIllConditioned {
            param_name: "p[0]".into(),
            param: 289.9,
            trivial_error: 0.25,
        }
        .to_string();
        assert!(floquet.contains("off by 2.50e-1"), "{floquet}");
    }
}
