//! Newton's method with a typed outcome.
//!
//! The caller supplies one closure that writes the residual `G(z)` and its
//! Jacobian `DG(z)`; the corrector iterates `z <- z - DG^{-1} G` until the step
//! is below `step_tol (1 + |z|)` and the residual below
//! `residual_tol (1 + |DG| |z|)` (max norms: a backward-error test, so that a
//! badly scaled system is judged against its own rounding level).

use crate::error::{ContinuationError, NewtonFailure};
use nalgebra::{DMatrix, DVector};

/// Tolerances and limits of the corrector.
#[derive(Clone, Copy, Debug)]
pub struct NewtonSettings {
    /// Relative step tolerance (max norm). Default `1e-11`.
    pub step_tol: f64,
    /// Residual tolerance relative to `1 + |DG| |z|` (max norms). Default `1e-10`.
    pub residual_tol: f64,
    /// Iteration limit. Default `12`.
    pub max_iter: usize,
}

impl Default for NewtonSettings {
    fn default() -> Self {
        NewtonSettings {
            step_tol: 1e-11,
            residual_tol: 1e-10,
            max_iter: 12,
        }
    }
}

/// What a converged Newton run did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NewtonReport {
    /// Iterations taken.
    pub iterations: usize,
    /// Max norm of the final residual.
    pub residual: f64,
    /// Max norm of the last step.
    pub step: f64,
}

/// Runs Newton's method from `z`, which is overwritten with the solution.
///
/// `system(z, g, dg)` writes the residual into `g` and the Jacobian into `dg`.
pub fn solve<F>(
    z: &mut DVector<f64>,
    settings: &NewtonSettings,
    context: &str,
    mut system: F,
) -> Result<NewtonReport, ContinuationError>
where
    F: FnMut(&DVector<f64>, &mut DVector<f64>, &mut DMatrix<f64>),
{
    let n = z.len();
    let mut g = DVector::zeros(n);
    let mut dg = DMatrix::zeros(n, n);
    let mut last_step = f64::INFINITY;
    let mut residual = f64::INFINITY;
    let fail = |iterations, residual, step, reason: NewtonFailure| ContinuationError::Newton {
        context: context.to_string(),
        iterations,
        residual,
        step,
        hint: match reason {
            NewtonFailure::MaxIterations | NewtonFailure::Stalled => {
                "reduce the step size or improve the initial guess"
            }
            NewtonFailure::SingularJacobian => {
                "the point may be a bifurcation of higher codimension; perturb a parameter"
            }
            NewtonFailure::NonFinite => "the iterate left the model's domain; reduce the step size",
        },
        reason,
    };
    for it in 0..=settings.max_iter {
        system(z, &mut g, &mut dg);
        residual = g.amax();
        if !residual.is_finite() {
            return Err(fail(it, residual, last_step, NewtonFailure::NonFinite));
        }
        // Backward-error scale: rounding in G is ~ eps |DG| |z|, so the
        // residual tolerance is relative to that for badly scaled systems.
        let scale = 1.0
            + dg.row_iter()
                .map(|r| r.iter().fold(0.0, |acc, v| acc + v.abs()))
                .fold(0.0, f64::max)
                * z.amax();
        if last_step <= settings.step_tol * (1.0 + z.amax())
            && residual <= settings.residual_tol * scale
        {
            return Ok(NewtonReport {
                iterations: it,
                residual,
                step: last_step,
            });
        }
        if it == settings.max_iter {
            break;
        }
        let Some(dz) = dg.clone().lu().solve(&g) else {
            return Err(fail(
                it,
                residual,
                last_step,
                NewtonFailure::SingularJacobian,
            ));
        };
        last_step = dz.amax();
        if !last_step.is_finite() {
            return Err(fail(
                it,
                residual,
                last_step,
                NewtonFailure::SingularJacobian,
            ));
        }
        *z -= dz;
    }
    Err(fail(
        settings.max_iter,
        residual,
        last_step,
        NewtonFailure::MaxIterations,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn converges_quadratically_on_a_scalar_root() {
        let mut z = DVector::from_element(1, 1.0);
        let rep = solve(&mut z, &NewtonSettings::default(), "", |z, g, dg| {
            g[0] = z[0] * z[0] - 2.0;
            dg[(0, 0)] = 2.0 * z[0];
        })
        .unwrap();
        assert!((z[0] - 2f64.sqrt()).abs() < 1e-15);
        assert!(rep.iterations <= 7);
    }

    #[test]
    fn reports_a_singular_jacobian() {
        let mut z = DVector::from_element(1, 0.0);
        let err = solve(
            &mut z,
            &NewtonSettings::default(),
            " at test",
            |z, g, dg| {
                g[0] = z[0] * z[0] + 1.0;
                dg[(0, 0)] = 2.0 * z[0];
            },
        )
        .unwrap_err();
        assert!(matches!(
            err,
            ContinuationError::Newton {
                reason: NewtonFailure::SingularJacobian,
                ..
            }
        ));
    }
}
