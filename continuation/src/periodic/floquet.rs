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
//! decades (stiff stick-slip cycles) keep their relative accuracy.

use crate::error::ContinuationError;
use nalgebra::DMatrix;
use num_complex::Complex64;

/// `(A_i, B_i)` of every interval from the collocation blocks
/// (`blocks[i (m + 1) + l]` is `d r_i / d u_{i,l}`, `(m n) x n`, column-major).
pub fn condense(blocks: &[Vec<f64>], n: usize, m: usize) -> Vec<(DMatrix<f64>, DMatrix<f64>)> {
    let rows = m * n;
    blocks
        .chunks(m + 1)
        .map(|b| {
            let block = |l: usize| DMatrix::from_column_slice(rows, n, &b[l]);
            let mut ends = DMatrix::zeros(rows, 2 * n);
            ends.view_mut((0, 0), (rows, n)).copy_from(&block(0));
            ends.view_mut((0, n), (rows, n)).copy_from(&block(m));
            if m > 1 {
                let mut interior = DMatrix::zeros(rows, (m - 1) * n);
                for l in 1..m {
                    interior
                        .view_mut((0, (l - 1) * n), (rows, n))
                        .copy_from(&block(l));
                }
                interior.qr().q_tr_mul(&mut ends);
            }
            let tail = ends.rows(rows - n, n);
            (
                tail.columns(0, n).into_owned(),
                tail.columns(n, n).into_owned(),
            )
        })
        .collect()
}

/// Eliminates the shared node of two consecutive relations.
fn combine(
    first: &(DMatrix<f64>, DMatrix<f64>),
    second: &(DMatrix<f64>, DMatrix<f64>),
) -> (DMatrix<f64>, DMatrix<f64>) {
    let n = first.0.nrows();
    let mut middle = DMatrix::zeros(2 * n, n);
    middle.view_mut((0, 0), (n, n)).copy_from(&first.1);
    middle.view_mut((n, 0), (n, n)).copy_from(&second.0);
    let mut outer = DMatrix::zeros(2 * n, 2 * n);
    outer.view_mut((0, 0), (n, n)).copy_from(&first.0);
    outer.view_mut((n, n), (n, n)).copy_from(&second.1);
    middle.qr().q_tr_mul(&mut outer);
    let tail = outer.rows(n, n);
    (
        tail.columns(0, n).into_owned(),
        tail.columns(n, n).into_owned(),
    )
}

/// Floquet multipliers of the relations `A_i y_i + B_i y_{i+1} = 0` closed
/// periodically, sorted by decreasing modulus.
pub fn multipliers(
    mut pairs: Vec<(DMatrix<f64>, DMatrix<f64>)>,
) -> Result<Vec<Complex64>, ContinuationError> {
    while pairs.len() > 1 {
        let mut next = Vec::with_capacity(pairs.len().div_ceil(2));
        for chunk in pairs.chunks(2) {
            next.push(if chunk.len() == 2 {
                combine(&chunk[0], &chunk[1])
            } else {
                chunk[0].clone()
            });
        }
        pairs = next;
    }
    let (a, b) = pairs.pop().ok_or(ContinuationError::Singular)?;
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

/// Distance of the multiplier closest to 1 (the trivial multiplier of an
/// autonomous system) from 1: a check on the accuracy of the orbit.
pub fn trivial_multiplier_error(mu: &[Complex64]) -> f64 {
    mu.iter()
        .map(|z| (z - 1.0).norm())
        .fold(f64::INFINITY, f64::min)
}
