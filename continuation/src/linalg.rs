//! Dense linear algebra for small systems: eigenvalues and eigenvectors
//! (faer), real and complex solves (nalgebra LU).

use crate::error::ContinuationError;
use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;

/// Eigenvalues of a real square matrix, sorted by decreasing real part.
pub fn eigenvalues(a: &DMatrix<f64>) -> Result<Vec<Complex64>, ContinuationError> {
    let m = to_faer(a);
    let mut ev = m
        .eigenvalues()
        .map_err(|e| ContinuationError::Eigen(format!("{e:?}")))?;
    ev.sort_by(|x, y| y.re.total_cmp(&x.re).then(y.im.total_cmp(&x.im)));
    Ok(ev)
}

/// The eigenpair of `a` whose eigenvalue is closest to `target`; the
/// eigenvector is normalised to unit Euclidean length.
pub fn eigenpair_near(
    a: &DMatrix<f64>,
    target: Complex64,
) -> Result<(Complex64, DVector<Complex64>), ContinuationError> {
    let m = to_faer(a);
    let evd = m
        .eigen()
        .map_err(|e| ContinuationError::Eigen(format!("{e:?}")))?;
    let s = evd.S();
    let u = evd.U();
    let n = a.nrows();
    let k = (0..n)
        .min_by(|&i, &j| (s[i] - target).norm().total_cmp(&(s[j] - target).norm()))
        .ok_or_else(|| ContinuationError::Eigen("empty matrix".into()))?;
    let v = DVector::from_iterator(n, (0..n).map(|i| u[(i, k)]));
    let norm = v.norm();
    Ok((s[k], v / Complex64::from(norm)))
}

/// Number of eigenvalues with positive real part.
pub fn count_unstable(eigenvalues: &[Complex64]) -> usize {
    eigenvalues.iter().filter(|l| l.re > 0.0).count()
}

/// Solves `a x = b` for a real square `a` by LU with partial pivoting.
pub fn solve(a: DMatrix<f64>, b: &DVector<f64>) -> Result<DVector<f64>, ContinuationError> {
    a.lu()
        .solve(b)
        .filter(|x| x.iter().all(|v| v.is_finite()))
        .ok_or(ContinuationError::Singular)
}

/// Solves `a x = b` for a complex square `a` by LU with partial pivoting.
pub fn solve_complex(
    a: DMatrix<Complex64>,
    b: &DVector<Complex64>,
) -> Result<DVector<Complex64>, ContinuationError> {
    a.lu()
        .solve(b)
        .filter(|x| x.iter().all(|v| v.re.is_finite() && v.im.is_finite()))
        .ok_or(ContinuationError::Singular)
}

/// Solves the sparse system given by `triplets` (duplicates are summed)
/// by faer's sparse LU; used for collocation systems, whose Jacobians are
/// block-banded with a few dense rows and columns.
pub fn solve_sparse(
    dim: usize,
    triplets: &[faer::sparse::Triplet<usize, usize, f64>],
    rhs: &[f64],
) -> Result<Vec<f64>, ContinuationError> {
    use faer::linalg::solvers::Solve;
    let a = faer::sparse::SparseColMat::<usize, f64>::try_new_from_triplets(dim, dim, triplets)
        .map_err(|e| ContinuationError::Sparse(format!("assembly: {e:?}")))?;
    let lu = a.sp_lu().map_err(|_| ContinuationError::Singular)?;
    let mut b = faer::Mat::from_fn(dim, 1, |i, _| rhs[i]);
    lu.solve_in_place(b.as_mut());
    let x: Vec<f64> = (0..dim).map(|i| b[(i, 0)]).collect();
    if x.iter().all(|v| v.is_finite()) {
        Ok(x)
    } else {
        Err(ContinuationError::Singular)
    }
}

fn to_faer(a: &DMatrix<f64>) -> faer::Mat<f64> {
    faer::Mat::from_fn(a.nrows(), a.ncols(), |i, j| a[(i, j)])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eigenvalues_of_a_rotation_with_decay() {
        // [[a, -w], [w, a]] has eigenvalues a +- i w.
        let a = DMatrix::from_row_slice(2, 2, &[-0.5, -2.0, 2.0, -0.5]);
        let ev = eigenvalues(&a).unwrap();
        assert!((ev[0] - Complex64::new(-0.5, 2.0)).norm() < 1e-14);
        assert!((ev[1] - Complex64::new(-0.5, -2.0)).norm() < 1e-14);
        let (l, v) = eigenpair_near(&a, Complex64::new(0.0, 2.0)).unwrap();
        let av = a.map(Complex64::from) * &v;
        assert!((av - &v * l).norm() < 1e-14);
        assert!((v.norm() - 1.0).abs() < 1e-15);
    }
}
