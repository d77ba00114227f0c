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
//! `eps` times that growth; the trace integral does not (it is as accurate as
//! the collocation quadrature), so stability of a planar cycle is decided
//! even where the pencil's trivial multiplier is off by order 1.

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
    multipliers_and_trivial(lin, n).map(|(mu, _)| mu)
}

/// [`multipliers`] and the index of the trivial one. In the plane the
/// pencil's two eigenvalues are matched to the trivial multiplier 1 and to
/// Liouville's `e^L`, `L = int_0^T tr J dt`, by the pairing that minimizes
/// `|ln |mu_a|| + |ln |mu_b| - L|`; the one matched to `e^L` is replaced by
/// it. Elsewhere the trivial multiplier is the one closest to 1.
pub fn multipliers_and_trivial(
    lin: &Linearization,
    n: usize,
) -> Result<(Vec<Complex64>, Option<usize>), ContinuationError> {
    let mut mu = pencil_multipliers(lin, n)?;
    if n != 2 || mu.len() != 2 {
        let trivial = trivial_index(&mu);
        return Ok((mu, trivial));
    }
    let l = lin.trace_integral;
    let log_modulus = |z: Complex64| z.norm().ln();
    let mismatch = |t: usize| log_modulus(mu[t]).abs() + (log_modulus(mu[1 - t]) - l).abs();
    let trivial = if mismatch(0) <= mismatch(1) { 0 } else { 1 };
    mu[1 - trivial] = Complex64::from(l.exp());
    // Decreasing modulus, the trivial index following.
    let trivial = if mu[1].norm() > mu[0].norm() {
        mu.swap(0, 1);
        1 - trivial
    } else {
        trivial
    };
    Ok((mu, Some(trivial)))
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
