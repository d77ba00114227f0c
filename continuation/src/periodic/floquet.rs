//! Floquet multipliers from the condensed collocation system, without forming
//! the monodromy matrix as a product of transition matrices.
//!
//! The linearized collocation equations of interval `i`, with the period and
//! the parameter fixed, couple its end nodes `y_i`, `y_{i+1}` and its interior
//! nodes. An orthogonal transformation (QR of the interior columns) leaves `n`
//! equations free of the interior: `A_i y_i + B_i y_{i+1} = 0` (condensation
//! of parameters). Orthogonal cyclic reduction then eliminates every other
//! node pair by pair (QR of `[B_i; A_{i+1}]`) down to `A y_0 + B y_N = 0`,
//! and a Floquet solution `y_N = mu y_0` gives the `n x n` pencil
//! `A y = mu (-B) y`, solved by the QZ algorithm (faer). No inverse and no
//! product of transition matrices is formed, so multipliers spanning many
//! decades (stiff stick-slip cycles) keep their relative accuracy. The
//! condensation and the reduction are those of the Newton solves
//! ([`super::bordered`]), without border columns.
//!
//! In the plane the nontrivial multiplier is known in closed form: by
//! Liouville's formula the product of the multipliers is
//! `exp(int_0^T tr J dt)`, and the trivial one is exactly 1, so the other is
//! `exp(int_0^T tr J dt)` (Kuznetsov 1998, §1.5). Where perturbations grow
//! by many decades during a slip, the pencil's eigenvalues carry rounding of
//! `eps` times that growth; the trace integral does not, so stability of a
//! planar cycle is always decided.

use super::bordered::{condense, reduce_pencil};
use super::collocation::Linearization;
use crate::error::ContinuationError;
use nalgebra::DMatrix;
use num_complex::Complex64;

/// Floquet multipliers of the orbit whose collocation system is linearized
/// in `lin` (state dimension `n`), sorted by decreasing modulus: those of the
/// pencil, except that in the plane (`n = 2`) the nontrivial one is
/// `exp(int_0^T tr J dt)` (Liouville).
pub fn multipliers(lin: &Linearization, n: usize) -> Result<Vec<Complex64>, ContinuationError> {
    let mut mu = pencil_multipliers(lin, n)?;
    if let (2, Some(trivial)) = (n, trivial_index(&mu)) {
        mu[1 - trivial] = Complex64::from(lin.trace_integral.exp());
        mu.sort_by(|x, y| y.norm().total_cmp(&x.norm()));
    }
    Ok(mu)
}

/// The eigenvalues of the condensed Floquet pencil, sorted by decreasing modulus.
pub fn pencil_multipliers(
    lin: &Linearization,
    n: usize,
) -> Result<Vec<Complex64>, ContinuationError> {
    let ntst = lin.local.len();
    let chain = lin
        .local
        .iter()
        .enumerate()
        .map(|(i, block)| {
            let nodes = block.columns(0, block.ncols() - 2);
            condense(nodes, &DMatrix::zeros(block.nrows(), 0), n, i, ntst).relation
        })
        .collect();
    let (a, b) = reduce_pencil(chain)?;
    let n = a.nrows();
    if a.iter().chain(b.iter()).any(|v| !v.is_finite()) {
        return Err(ContinuationError::Eigen(
            "non-finite entries in the condensed Floquet pencil".into(),
        ));
    }
    // The complex QZ path of faer (its real path mis-sizes a scratch buffer
    // for some 3 x 3 pencils in 0.24.4).
    let fa = faer::Mat::from_fn(n, n, |i, j| Complex64::from(a[(i, j)]));
    let fb = faer::Mat::from_fn(n, n, |i, j| Complex64::from(-b[(i, j)]));
    let ge = fa
        .generalized_eigen(&fb)
        .map_err(|e| ContinuationError::Eigen(format!("{e:?}")))?;
    let (sa, sb) = (ge.S_a(), ge.S_b());
    let mut mu: Vec<Complex64> = (0..n).map(|i| sa[i] / sb[i]).collect();
    mu.sort_by(|x, y| y.norm().total_cmp(&x.norm()));
    Ok(mu)
}

/// Index of the trivial multiplier of an autonomous system: the one closest to 1.
pub fn trivial_index(mu: &[Complex64]) -> Option<usize> {
    mu.iter()
        .enumerate()
        .min_by(|a, b| (a.1 - 1.0).norm().total_cmp(&(b.1 - 1.0).norm()))
        .map(|(i, _)| i)
}

/// Distance of the trivial multiplier from 1: a check on the accuracy of
/// the orbit and of the multipliers.
pub fn trivial_multiplier_error(mu: &[Complex64]) -> f64 {
    trivial_index(mu).map_or(f64::INFINITY, |i| (mu[i] - 1.0).norm())
}
