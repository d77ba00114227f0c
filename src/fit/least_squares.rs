//! Weighted nonlinear least squares by Levenberg–Marquardt (Marquardt's
//! scaling by the diagonal of `J^T J`, Nielsen's update of the damping),
//! with the Jacobian exact from dual numbers, the covariance of the
//! estimate and the directions the data do not determine.
//!
//! The problem gives weighted residuals `r_i(x) = (model_i(x) - y_i) /
//! sigma_i`; the estimate minimises `|r|^2`, and its covariance is
//! `(J^T J)^-1` at the minimum (the Gauss–Newton approximation, exact to
//! first order in the errors: Press et al., *Numerical Recipes*, §15.5).

use continuation::Scalar;
use nalgebra::{DMatrix, DVector};
use num_dual::Dual64;

/// A least-squares problem in `n` unknowns.
pub trait Problem {
    /// The number of unknowns.
    fn unknowns(&self) -> usize;
    /// The weighted residuals at `x`; `None` where the model is undefined
    /// there (a trial step is then rejected).
    fn residuals<T: Scalar>(&self, x: &[T]) -> Option<Vec<T>>;
}

/// `x` in dual numbers along the direction of its `k`-th entry.
pub fn seeded(x: &[f64], k: usize) -> Vec<Dual64> {
    x.iter()
        .enumerate()
        .map(|(i, &v)| Dual64::new(v, if i == k { 1.0 } else { 0.0 }))
        .collect()
}

/// The residuals at `x` and their Jacobian, one forward-mode dual pass per
/// unknown.
pub fn jacobian<P: Problem>(p: &P, x: &[f64]) -> Option<(DVector<f64>, DMatrix<f64>)> {
    let r = DVector::from_vec(p.residuals(x)?);
    let mut j = DMatrix::zeros(r.len(), x.len());
    for k in 0..x.len() {
        for (i, ri) in p.residuals(&seeded(x, k))?.iter().enumerate() {
            j[(i, k)] = ri.eps;
        }
    }
    Some((r, j))
}

/// The minimum found.
#[derive(Clone, Debug)]
pub struct Minimum {
    pub x: Vec<f64>,
    pub residuals: DVector<f64>,
    pub jacobian: DMatrix<f64>,
    pub iterations: usize,
}

/// The last iterate `x` after `iteration + 1` iterations (the minimum, or
/// where the iteration limit left it).
fn last_iterate(
    x: Vec<f64>,
    residuals: DVector<f64>,
    jacobian: DMatrix<f64>,
    iteration: usize,
) -> Minimum {
    Minimum {
        x,
        residuals,
        jacobian,
        iterations: iteration + 1,
    }
}

/// Why the minimisation failed.
#[derive(Clone, Debug, thiserror::Error, PartialEq)]
pub enum LeastSquaresError {
    #[error("the model is undefined at the start (e.g. no onset: steady friction not velocity weakening there)")]
    UndefinedStart,
    #[error("no convergence in {0} iterations")]
    NoConvergence(usize),
}

/// Iterations allowed.
const MAX_ITERATIONS: usize = 500;

/// Minimises `|r(x)|^2` from `x0`: the minimum with `true`, or, where the
/// iterations end without converging, the last iterate with `false` (the
/// caller can ask there what the data leave undetermined: a flat valley
/// the iterations creep along).
pub fn minimize<P: Problem>(p: &P, x0: &[f64]) -> Result<(Minimum, bool), LeastSquaresError> {
    let (mut r, mut j) = jacobian(p, x0).ok_or(LeastSquaresError::UndefinedStart)?;
    let mut x = x0.to_vec();
    let mut cost = r.norm_squared();
    let (mut lambda, mut grow) = (1e-3, 2.0);
    for iteration in 0..MAX_ITERATIONS {
        let a = j.transpose() * &j;
        let g = j.transpose() * &r;
        let scale = DVector::from_iterator(a.nrows(), a.diagonal().iter().map(|d| d.max(1e-300)));
        let mut damped = a.clone();
        for k in 0..scale.len() {
            damped[(k, k)] += lambda * scale[k];
        }
        let Some(step) = damped.cholesky().map(|c| c.solve(&(-&g))) else {
            lambda *= grow;
            grow *= 2.0;
            continue;
        };
        let trial: Vec<f64> = x.iter().zip(step.iter()).map(|(a, b)| a + b).collect();
        // The Jacobian only at a step that lowers the cost (a rejected step
        // costs one evaluation, not n + 1).
        let lower = p
            .residuals(&trial)
            .map(|r| r.iter().map(|v| v * v).sum::<f64>())
            .is_some_and(|c| c < cost);
        let accepted = lower
            .then(|| jacobian(p, &trial))
            .flatten()
            .filter(|(rt, jt)| {
                rt.iter().all(|v| v.is_finite()) && jt.iter().all(|v| v.is_finite())
            });
        // Predicted decrease of |r|^2 by the linear model.
        let predicted = step.dot(&(step.component_mul(&scale) * lambda - &g));
        match accepted {
            Some((rt, jt)) if rt.norm_squared() < cost => {
                let new_cost = rt.norm_squared();
                let rho = (cost - new_cost) / predicted.max(f64::MIN_POSITIVE);
                let small_step = step
                    .iter()
                    .zip(&x)
                    .all(|(s, v)| s.abs() <= 1e-12 * (1.0 + v.abs()));
                let flat = cost - new_cost <= 1e-14 * cost;
                x = trial;
                r = rt;
                j = jt;
                cost = new_cost;
                lambda *= (1.0f64 / 3.0).max(1.0 - (2.0 * rho - 1.0).powi(3));
                grow = 2.0;
                if small_step || flat {
                    return Ok((last_iterate(x, r, j, iteration), true));
                }
            }
            _ => {
                // At the minimum to rounding: no step decreases the cost.
                let gradient_small = g.amax() <= 1e-12 * (1.0 + cost.sqrt()) * j.amax().max(1.0);
                if gradient_small || lambda > 1e16 {
                    return Ok((last_iterate(x, r, j, iteration), true));
                }
                lambda *= grow;
                grow *= 2.0;
            }
        }
    }
    Ok((last_iterate(x, r, j, MAX_ITERATIONS - 1), false))
}

/// The singular values of `J` with its columns scaled to unit length, in
/// decreasing order, and the right singular vectors (columns, same order):
/// a direction of the unknowns the data do not determine has a singular
/// value at rounding level relative to the largest. `None` where `J` has
/// an entry that is not finite or the iterations of the decomposition do
/// not converge ([`SVD_ITERATIONS`]; nalgebra's unbounded `svd` loops
/// forever on such input).
pub fn scaled_svd(j: &DMatrix<f64>) -> Option<(Vec<f64>, DMatrix<f64>)> {
    if !j.iter().all(|v| v.is_finite()) {
        return None;
    }
    let mut scaled = j.clone();
    for mut c in scaled.column_iter_mut() {
        let n = c.norm();
        if n > 0.0 {
            c /= n;
        }
    }
    let svd = scaled.try_svd(false, true, f64::EPSILON, SVD_ITERATIONS)?;
    let v_t = svd
        .v_t
        .unwrap_or_else(|| DMatrix::identity(j.ncols(), j.ncols()));
    let mut order: Vec<usize> = (0..svd.singular_values.len()).collect();
    order.sort_by(|&a, &b| svd.singular_values[b].total_cmp(&svd.singular_values[a]));
    let values = order.iter().map(|&k| svd.singular_values[k]).collect();
    let vectors = DMatrix::from_fn(j.ncols(), order.len(), |i, c| v_t[(order[c], i)]);
    Some((values, vectors))
}

/// Sweeps [`scaled_svd`] allows (a handful per singular value converge a
/// Jacobian of a few columns).
const SVD_ITERATIONS: usize = 1000;

/// `(J^T J)^-1`, the covariance of the unknowns for weighted residuals.
pub fn covariance(j: &DMatrix<f64>) -> Option<DMatrix<f64>> {
    (j.transpose() * j).try_inverse()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `y = a exp(b t)` sampled without noise: the minimum is the truth,
    /// and the covariance of a linear problem is the closed form.
    struct Exponential {
        t: Vec<f64>,
        y: Vec<f64>,
    }

    impl Problem for Exponential {
        fn unknowns(&self) -> usize {
            2
        }
        fn residuals<T: Scalar>(&self, x: &[T]) -> Option<Vec<T>> {
            Some(
                self.t
                    .iter()
                    .zip(&self.y)
                    .map(|(&t, &y)| x[0] * (x[1] * t).exp() - y)
                    .collect(),
            )
        }
    }

    #[test]
    fn finds_an_exponential_from_far() {
        let t: Vec<f64> = (0..20).map(|i| i as f64 * 0.1).collect();
        let y = t.iter().map(|t| 2.5 * (-1.3 * t).exp()).collect();
        let (m, converged) = minimize(&Exponential { t, y }, &[1.0, 0.5]).unwrap();
        assert!(converged);
        assert!(
            (m.x[0] - 2.5).abs() < 1e-12 && (m.x[1] + 1.3).abs() < 1e-12,
            "{:?}",
            m.x
        );
    }

    /// A straight line `y = c0 + c1 t` with unit weights: the covariance is
    /// `(X^T X)^-1` of the design matrix, in closed form
    /// `var c1 = 1 / sum (t - mean t)^2`.
    struct Line {
        t: Vec<f64>,
    }

    impl Problem for Line {
        fn unknowns(&self) -> usize {
            2
        }
        fn residuals<T: Scalar>(&self, x: &[T]) -> Option<Vec<T>> {
            Some(self.t.iter().map(|&t| x[0] + x[1] * t).collect())
        }
    }

    #[test]
    fn covariance_of_a_line_is_the_closed_form() {
        let t = vec![0.0, 1.0, 2.0, 4.0];
        let (_, j) = jacobian(&Line { t: t.clone() }, &[0.0, 0.0]).unwrap();
        let c = covariance(&j).unwrap();
        let mean = t.iter().sum::<f64>() / 4.0;
        let sxx: f64 = t.iter().map(|t| (t - mean).powi(2)).sum();
        assert!((c[(1, 1)] - 1.0 / sxx).abs() < 1e-14);
        assert!((c[(0, 0)] - (1.0 / 4.0 + mean * mean / sxx)).abs() < 1e-14);
        // Two equal columns: one direction undetermined.
        let mut j2 = j.clone();
        j2.set_column(1, &j.column(0).clone_owned());
        let (s, v) = scaled_svd(&j2).unwrap();
        assert!(s[1] < 1e-12 * s[0]);
        // Not finite: no decomposition (nalgebra's unbounded one loops).
        j2[(0, 0)] = f64::NAN;
        assert!(scaled_svd(&j2).is_none());
        assert!((v[(0, 1)].abs() - v[(1, 1)].abs()).abs() < 1e-12);
    }
}
