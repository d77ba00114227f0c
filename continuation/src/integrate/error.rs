//! Typed failures of the Radau integrator. Each names the time `t` reached,
//! the step size `h` being tried, the cause and what to try.

use std::fmt;
use thiserror::Error;

/// Why the simplified Newton iteration for the stage equations failed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum NewtonTrouble {
    /// The contraction factor `theta = |dZ_k| / |dZ_{k-1}|` reached 0.99 or more.
    Diverging {
        /// The observed contraction factor.
        theta: f64,
    },
    /// The iteration limit was reached without meeting the tolerance.
    MaxIterations,
    /// `f` returned NaN or infinity at a stage value.
    NonFinite,
}

impl fmt::Display for NewtonTrouble {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            NewtonTrouble::Diverging { theta } => {
                write!(f, "diverging, contraction factor {theta:.3}")
            }
            NewtonTrouble::MaxIterations => write!(f, "iteration limit reached"),
            NewtonTrouble::NonFinite => write!(
                f,
                "f was not finite at a stage value (beyond the floating-point range)"
            ),
        }
    }
}

/// A value that is not finite, in words (no message prints `inf` or `NaN`).
fn non_finite(value: f64) -> &'static str {
    if value.is_nan() {
        "is not a number"
    } else if value > 0.0 {
        "is above the floating-point range"
    } else {
        "is below the floating-point range (negative)"
    }
}

/// A failure of [`Radau5`](super::Radau5), with the numbers that explain it.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum IntegrateError {
    /// Inconsistent dimensions, tolerances or time span.
    #[error("invalid input: {what}; {hint}")]
    InvalidInput {
        /// What is wrong, with the offending numbers.
        what: String,
        /// What to change.
        hint: &'static str,
    },
    /// The initial state has a NaN or infinite component.
    #[error(
        "non-finite initial state: x[{index}] {} at t = {t:.10e}; \
         the integrator needs finite initial values — check how x0 was computed",
        non_finite(*value)
    )]
    NonFiniteState {
        /// The initial time.
        t: f64,
        /// Offending component.
        index: usize,
        /// Its value.
        value: f64,
    },
    /// `f(x)` is NaN or infinite at an accepted state.
    #[error(
        "f(x) is not finite at t = {t:.10e} (h = {h:.3e}, component {index}); \
         the state left the model's domain — check the model (logarithms or powers of \
         non-positive values?) or tighten rtol/atol"
    )]
    NonFiniteRhs {
        /// Time of the offending state.
        t: f64,
        /// Step size at that time.
        h: f64,
        /// First offending component.
        index: usize,
    },
    /// The Jacobian has a NaN or infinite entry at an accepted state.
    #[error(
        "the Jacobian of f is not finite at t = {t:.10e} (h = {h:.3e}) although f is; \
         f is not differentiable there (sqrt or abs at 0?) — smooth the model or \
         move the initial state"
    )]
    NonFiniteJacobian {
        /// Time of the offending state.
        t: f64,
        /// Step size at that time.
        h: f64,
    },
    /// The step size fell below `h_min` or below the rounding level of the
    /// compensated time `t`.
    #[error(
        "step size underflow at t = {t:.10e}: h = {h:.3e} is below {h_min:.3e} ({cause}); \
         the solution may blow up or be non-smooth near t — check the model, \
         rescale the variables, loosen rtol/atol or lower h_min"
    )]
    StepSizeUnderflow {
        /// Time reached.
        t: f64,
        /// The step size that was too small.
        h: f64,
        /// The bound it fell below.
        h_min: f64,
        /// Which bound: the user's `h_min` or the rounding level of the
        /// compensated time, `0.1 |h| <= eps^2 |t|` (at least the smallest
        /// normal number).
        cause: &'static str,
    },
    /// The stage equations could not be solved, many times in a row.
    #[error(
        "Newton iteration for the stage equations failed {failures} times in a row at \
         t = {t:.10e}, h = {h:.3e} (last: {cause}); the step size was halved each time — \
         check that f is smooth there, lower h_max or h0, or loosen rtol"
    )]
    NewtonFailed {
        /// Time reached.
        t: f64,
        /// Last step size tried.
        h: f64,
        /// Consecutive failures.
        failures: usize,
        /// The last cause.
        cause: NewtonTrouble,
    },
    /// The iteration matrix `gamma/h I - J` (or its complex partner) was
    /// singular, or overflowed while it was factored.
    #[error(
        "the iteration matrix (gamma/h) I - J was singular or overflowed while factored {count} \
         times at t = {t:.10e}, h = {h:.3e}; the Jacobian's entries may be near the end of the \
         floating-point range at this state, or the problem may be ill-posed \
         (a differential-algebraic system?) — check the Jacobian at this state"
    )]
    SingularMatrix {
        /// Time reached.
        t: f64,
        /// Step size tried.
        h: f64,
        /// Number of singular factorisations.
        count: usize,
    },
    /// The step budget was used up.
    #[error(
        "maximum number of steps {max_steps} reached at t = {t:.10e} (h = {h:.3e}); \
         increase max_steps, loosen rtol/atol, or shorten the interval"
    )]
    MaxSteps {
        /// Time reached.
        t: f64,
        /// Current step size.
        h: f64,
        /// The limit.
        max_steps: usize,
    },
    /// An event function returned NaN or infinity.
    #[error(
        "event function {index} returned a value that {} at t = {t:.10e} (h = {h:.3e}); \
         event functions must be finite along the solution",
        non_finite(*value)
    )]
    NonFiniteEvent {
        /// Which event function.
        index: usize,
        /// Time of the evaluation.
        t: f64,
        /// Step size of the step being searched.
        h: f64,
        /// The value returned.
        value: f64,
    },
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn non_finite_values_are_named_in_words() {
        let messages = [
            IntegrateError::NonFiniteState {
                t: 0.0,
                index: 1,
                value: f64::INFINITY,
            }
            .to_string(),
            IntegrateError::NonFiniteEvent {
                index: 0,
                t: 1.0,
                h: 0.1,
                value: f64::NAN,
            }
            .to_string(),
            IntegrateError::NewtonFailed {
                t: 1.0,
                h: 1e-9,
                failures: 20,
                cause: NewtonTrouble::NonFinite,
            }
            .to_string(),
            IntegrateError::SingularMatrix {
                t: 0.0,
                h: 6.25e-8,
                count: 5,
            }
            .to_string(),
        ];
        for text in &messages {
            let words: Vec<&str> = text
                .split(|c: char| !c.is_ascii_alphanumeric())
                .filter(|w| w.eq_ignore_ascii_case("nan") || w.eq_ignore_ascii_case("inf"))
                .collect();
            assert!(words.is_empty(), "{text}");
        }
        assert!(messages[0].contains("x[1] is above the floating-point range"));
        assert!(messages[1].contains("event function 0 returned a value that is not a number"));
    }
}
