//! Newton's method and tangents for the collocation system bordered by one
//! extra scalar equation (fixed parameter, or the pseudo-arclength condition),
//! solved with faer's sparse LU.

use super::collocation::Collocation;
use crate::error::{ContinuationError, NewtonFailure};
use crate::linalg::solve_sparse;
use crate::newton::{NewtonReport, NewtonSettings};
use crate::system::VectorField;
use faer::sparse::Triplet;

/// Arclength weight of unknown `i`: `1 / N` on the orbit's `N` values, 1 on `T` and `p`.
pub fn weights(n_orbit: usize) -> impl Fn(usize) -> f64 {
    move |i| {
        if i < n_orbit {
            1.0 / (n_orbit as f64)
        } else {
            1.0
        }
    }
}

/// Weighted inner product of two unknown vectors.
pub fn wdot(a: &[f64], b: &[f64], n_orbit: usize) -> f64 {
    let w = weights(n_orbit);
    a.iter()
        .zip(b)
        .enumerate()
        .map(|(i, (x, y))| w(i) * x * y)
        .sum()
}

/// Newton's method on the collocation system plus one extra scalar equation
/// `extra(z) = 0` whose Jacobian row (last row) `extra_row` appends.
pub fn newton_sparse<S: VectorField>(
    coll: &Collocation<S>,
    z: &mut [f64],
    settings: &NewtonSettings,
    extra_row: impl Fn(&[f64], &mut Vec<Triplet<usize, usize, f64>>),
    extra: impl Fn(&[f64]) -> f64,
) -> Result<NewtonReport, ContinuationError> {
    let nz = z.len();
    let mut last_step = f64::INFINITY;
    let mut residual = f64::INFINITY;
    for it in 0..=settings.max_iter {
        let mut lin = coll.linearize(z);
        lin.residual.push(extra(z));
        residual = lin.residual.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        if !residual.is_finite() {
            return Err(newton_error(
                it,
                residual,
                last_step,
                NewtonFailure::NonFinite,
            ));
        }
        let zmax = z.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        if last_step <= settings.step_tol * (1.0 + zmax)
            && residual <= settings.residual_tol * (1.0 + zmax)
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
        extra_row(z, &mut lin.triplets);
        let dz = solve_sparse(nz, &lin.triplets, &lin.residual)
            .map_err(|_| newton_error(it, residual, last_step, NewtonFailure::SingularJacobian))?;
        last_step = dz.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        for (zi, d) in z.iter_mut().zip(&dz) {
            *zi -= d;
        }
    }
    Err(newton_error(
        settings.max_iter,
        residual,
        last_step,
        NewtonFailure::MaxIterations,
    ))
}

fn newton_error(
    iterations: usize,
    residual: f64,
    step: f64,
    reason: NewtonFailure,
) -> ContinuationError {
    ContinuationError::Newton {
        context: " correcting a periodic orbit".into(),
        iterations,
        residual,
        step,
        hint: match reason {
            NewtonFailure::MaxIterations => "reduce the step size or refine the mesh (more NTST)",
            NewtonFailure::SingularJacobian => {
                "the orbit may be at a fold or period doubling; perturb the parameter"
            }
            NewtonFailure::NonFinite => {
                "the orbit left the model's domain; use log variables or a smaller step"
            }
        },
        reason,
    }
}

/// Unit tangent (weighted norm) of the cycle branch at `z`, oriented along `reference`.
pub fn tangent<S: VectorField>(
    coll: &Collocation<S>,
    z: &[f64],
    reference: &[f64],
    n_orbit: usize,
) -> Result<Vec<f64>, ContinuationError> {
    let nz = z.len();
    let mut lin = coll.linearize(z);
    let w = weights(n_orbit);
    lin.triplets.extend(
        (0..nz)
            .filter(|&i| reference[i] != 0.0)
            .map(|i| Triplet::new(nz - 1, i, w(i) * reference[i])),
    );
    let mut rhs = vec![0.0; nz];
    rhs[nz - 1] = 1.0;
    let t = solve_sparse(nz, &lin.triplets, &rhs)?;
    let norm = wdot(&t, &t, n_orbit).sqrt();
    let sign = if wdot(&t, reference, n_orbit) < 0.0 {
        -1.0
    } else {
        1.0
    };
    Ok(t.iter().map(|v| sign * v / norm).collect())
}

/// Predicts `z0 + sigma t` and corrects it on the collocation system plus the
/// pseudo-arclength condition `<t, z - prediction>_w = 0`.
pub fn correct_along<S: VectorField>(
    coll: &Collocation<S>,
    z0: &[f64],
    t: &[f64],
    sigma: f64,
    settings: &NewtonSettings,
) -> Result<(Vec<f64>, NewtonReport), ContinuationError> {
    let nz = z0.len();
    let w = weights(nz - 2);
    let pred: Vec<f64> = z0.iter().zip(t).map(|(z, t)| z + sigma * t).collect();
    let mut z = pred.clone();
    let rep = newton_sparse(
        coll,
        &mut z,
        settings,
        |_, row| {
            row.extend(
                (0..nz)
                    .filter(|&i| t[i] != 0.0)
                    .map(|i| Triplet::new(nz - 1, i, w(i) * t[i])),
            )
        },
        |z| (0..nz).map(|i| w(i) * t[i] * (z[i] - pred[i])).sum(),
    )?;
    Ok((z, rep))
}
