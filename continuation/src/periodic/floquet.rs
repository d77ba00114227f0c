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

use super::bordered::CyclicReduction;
use super::collocation::Linearization;
use crate::error::ContinuationError;
use nalgebra::DMatrix;
use num_complex::Complex64;

/// Floquet multipliers of the orbit whose collocation system is linearized
/// in `lin` (state dimension `n`), sorted by decreasing modulus: those of the
/// pencil, except that in the plane (`n = 2`) the nontrivial one is
/// `exp(int_0^T tr J dt)` (Liouville).
pub fn multipliers(lin: &Linearization, n: usize) -> Result<Vec<Complex64>, ContinuationError> {
    multipliers_and_trivial(&CyclicReduction::new(lin, n), lin.trace_integral).map(|(mu, _)| mu)
}

/// [`multipliers`] and the index of the trivial one. In the plane the
/// pencil's two eigenvalues are matched to the trivial multiplier 1 and to
/// Liouville's `e^L`, `L = int_0^T tr J dt`, by the pairing that minimizes
/// `|ln |mu_a|| + |ln |mu_b| - L|`; the one matched to `e^L` is replaced by
/// it. Elsewhere the trivial multiplier is the one closest to 1. When the
/// pencil leaves eigenvalues undetermined ([`pencil_multipliers`]) fewer
/// than `n` multipliers are returned; in the plane then only `e^L`, with no
/// trivial index.
pub fn multipliers_and_trivial(
    reduction: &CyclicReduction,
    trace_integral: f64,
) -> Result<(Vec<Complex64>, Option<usize>), ContinuationError> {
    let n = reduction.dim();
    let mut mu = pencil_multipliers(reduction)?;
    if n == 2 && mu.len() < 2 {
        // The pencil did not determine both: the nontrivial multiplier is
        // still Liouville's, the trivial one is unknown.
        return Ok((vec![Complex64::from(trace_integral.exp())], None));
    }
    if n != 2 {
        let trivial = trivial_index(&mu);
        return Ok((mu, trivial));
    }
    let l = trace_integral;
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

/// The eigenvalues of the condensed Floquet pencil that it determines,
/// sorted by decreasing modulus.
///
/// An eigenvalue `alpha / beta` of the pencil is left out when it is not
/// determined: `beta = 0` (an infinite eigenvalue, which no monodromy
/// matrix has) or `alpha` and `beta` both zero to rounding (the pencil is
/// singular to rounding: on stiff cycles perturbations grow by more than
/// `1 / eps` during the slip and both `A` and `B` lose rank). The result
/// may then hold fewer than `n` multipliers; a quotient is never NaN or
/// infinite. When the QZ iteration leaves eigenvalues out (faer 0.24
/// returns `alpha = beta = 0` for some well-conditioned 3 x 3 pencils:
/// all of them, or, near a fold of cycles with its double multiplier 1,
/// two of three), it is run again on the transposed pencil, which has the
/// same eigenvalues, and then on the pencil with `a` and `-b` exchanged
/// (reciprocal eigenvalues); the run that determines most of them is kept.
pub fn pencil_multipliers(
    reduction: &CyclicReduction,
) -> Result<Vec<Complex64>, ContinuationError> {
    let n = reduction.dim();
    let (a, b) = reduction.pencil();
    if a.iter().chain(b.iter()).any(|v| !v.is_finite()) {
        return Err(ContinuationError::Eigen(
            "non-finite entries in the condensed Floquet pencil".into(),
        ));
    }
    let mut mu = qz_eigenvalues(a, b)?;
    if mu.len() < n {
        let transposed = qz_eigenvalues(&a.transpose(), &b.transpose())?;
        if transposed.len() > mu.len() {
            mu = transposed;
        }
    }
    if mu.len() < n {
        // The roles exchanged: -b y = (1 / mu) a y.
        let reciprocal: Vec<Complex64> = qz_eigenvalues(&-b, &-a)?
            .into_iter()
            .filter(|z| z.norm() > 0.0)
            .map(|z| z.inv())
            .collect();
        if reciprocal.len() > mu.len() {
            mu = reciprocal;
        }
    }
    mu.sort_by(|x, y| y.norm().total_cmp(&x.norm()));
    Ok(mu)
}

/// The determined eigenvalues `mu` of `A y = mu (-B) y` (see [`pencil_multipliers`]).
fn qz_eigenvalues(a: &DMatrix<f64>, b: &DMatrix<f64>) -> Result<Vec<Complex64>, ContinuationError> {
    let n = a.nrows();
    // The complex QZ path of faer (its real path mis-sizes a scratch buffer
    // for some 3 x 3 pencils in 0.24.4).
    let fa = faer::Mat::from_fn(n, n, |i, j| Complex64::from(a[(i, j)]));
    let fb = faer::Mat::from_fn(n, n, |i, j| Complex64::from(-b[(i, j)]));
    let ge = fa
        .generalized_eigen(&fb)
        .map_err(|e| ContinuationError::Eigen(format!("{e:?}")))?;
    let (sa, sb) = (ge.S_a(), ge.S_b());
    // Zero to rounding, relative to the size of each matrix.
    let tiny =
        |m: &DMatrix<f64>| 64.0 * f64::EPSILON * m.iter().fold(0.0f64, |s, v| s.max(v.abs()));
    let (tiny_a, tiny_b) = (tiny(a), tiny(b));
    Ok((0..n)
        .filter(|&i| sb[i].norm() > 0.0 && (sa[i].norm() > tiny_a || sb[i].norm() > tiny_b))
        .map(|i| sa[i] / sb[i])
        .filter(|z| z.is_finite())
        .collect())
}

/// Index of the trivial multiplier of an autonomous system: the one closest to 1.
pub fn trivial_index(mu: &[Complex64]) -> Option<usize> {
    mu.iter()
        .enumerate()
        .min_by(|a, b| (a.1 - 1.0).norm().total_cmp(&(b.1 - 1.0).norm()))
        .map(|(i, _)| i)
}
