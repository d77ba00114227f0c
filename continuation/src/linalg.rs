//! Dense linear algebra for small systems: eigenvalues and eigenvectors
//! (faer, in reused per-thread buffers), real and complex solves (nalgebra LU).

use crate::error::ContinuationError;
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;
use std::cell::RefCell;

/// Reused buffers of the eigenvalue routines: the matrix as faer holds it,
/// the real Schur vectors, the eigenvalues and faer's workspace. faer's
/// convenience calls (`Mat::eigenvalues`, `Mat::eigen`) allocate all of these
/// on every call, which dominates for the 2x2 and 3x3 Jacobians here; the
/// same routine ([`faer::linalg::evd::evd_real`]) is called with the same
/// inputs, so the results are identical.
struct EvdWork {
    a: faer::Mat<f64>,
    u: faer::Mat<f64>,
    s_re: faer::diag::Diag<f64>,
    s_im: faer::diag::Diag<f64>,
    mem: MemBuffer,
    req: StackReq,
}

thread_local! {
    static EVD_WORK: RefCell<EvdWork> = RefCell::new(EvdWork {
        a: faer::Mat::zeros(0, 0),
        u: faer::Mat::zeros(0, 0),
        s_re: faer::diag::Diag::zeros(0),
        s_im: faer::diag::Diag::zeros(0),
        mem: MemBuffer::new(StackReq::EMPTY),
        req: StackReq::EMPTY,
    });
}

/// The diagonal balancing of `a` (Parlett & Reinsch 1969; LAPACK's
/// `gebal` without permutations): powers of two `d_i` such that the rows
/// and columns of `D^-1 a D` have comparable sizes. The similarity is exact
/// (powers of two) and leaves the eigenvalues as they are, but a
/// backward-stable eigenvalue routine errs by `eps` times the norm of the
/// matrix it is given: a Jacobian in variables of very different sizes (the
/// age `phi = 1/nu` is 1e7 at nu = 1e-7, where the frequency is 1e-7) has
/// entries far larger than its slow eigenvalues, which balancing brings
/// down. An already balanced matrix keeps `d = 1`.
fn balancing(a: &DMatrix<f64>) -> Vec<f64> {
    let n = a.nrows();
    let mut b = a.clone();
    let mut d = vec![1.0; n];
    for _sweep in 0..64 {
        let mut done = true;
        for i in 0..n {
            let (mut c, mut r) = (0.0, 0.0);
            for j in (0..n).filter(|&j| j != i) {
                c += b[(j, i)].abs();
                r += b[(i, j)].abs();
            }
            if c == 0.0 || r == 0.0 || !(c + r).is_finite() {
                continue;
            }
            let total = c + r;
            let mut f = 1.0;
            while c < r / 2.0 {
                f *= 2.0;
                c *= 4.0;
            }
            while c >= 2.0 * r {
                f /= 2.0;
                c /= 4.0;
            }
            if (c + r) / f < 0.95 * total {
                done = false;
                d[i] *= f;
                b.row_mut(i).iter_mut().for_each(|v| *v /= f);
                b.column_mut(i).iter_mut().for_each(|v| *v *= f);
            }
        }
        if done {
            break;
        }
    }
    d
}

/// Runs faer's real eigenvalue decomposition of `a` in the thread's reused
/// buffers (with the right eigenvectors if `vectors`), then hands the buffers
/// to `read`. The decomposition is of the balanced matrix `D^-1 a D`
/// ([`balancing`]), its eigenvectors `v` turned back into `a`'s, `D v`.
fn with_evd<R>(
    a: &DMatrix<f64>,
    vectors: bool,
    read: impl FnOnce(&EvdWork) -> R,
) -> Result<R, ContinuationError> {
    use faer::linalg::evd::{evd_real, evd_scratch, ComputeEigenvectors};
    let n = a.nrows();
    EVD_WORK.with(|work| {
        let mut guard = work.borrow_mut();
        let w = &mut *guard;
        if w.a.nrows() != n {
            w.a = faer::Mat::zeros(n, n);
            w.u = faer::Mat::zeros(n, n);
            w.s_re = faer::diag::Diag::zeros(n);
            w.s_im = faer::diag::Diag::zeros(n);
        }
        // Same inputs as faer's convenience calls: the (balanced) matrix, and
        // zeroed outputs.
        let d = balancing(a);
        for j in 0..n {
            for i in 0..n {
                w.a[(i, j)] = a[(i, j)] / d[i] * d[j];
                w.u[(i, j)] = 0.0;
            }
            w.s_re[j] = 0.0;
            w.s_im[j] = 0.0;
        }
        let par = faer::get_global_parallelism();
        let right = if vectors {
            ComputeEigenvectors::Yes
        } else {
            ComputeEigenvectors::No
        };
        let req = evd_scratch::<f64>(n, ComputeEigenvectors::No, right, par, Default::default());
        if req.size_bytes() > w.req.size_bytes() || req.align_bytes() > w.req.align_bytes() {
            w.req = req.or(w.req);
            w.mem = MemBuffer::new(w.req);
        }
        evd_real(
            w.a.as_ref(),
            w.s_re.as_mut(),
            w.s_im.as_mut(),
            None,
            vectors.then(|| w.u.as_mut()),
            par,
            MemStack::new(&mut w.mem),
            Default::default(),
        )
        .map_err(|e| ContinuationError::Eigen(format!("{e:?}")))?;
        if vectors {
            for (i, di) in d.iter().enumerate() {
                for j in 0..n {
                    w.u[(i, j)] *= di;
                }
            }
        }
        Ok(read(w))
    })
}

/// The row equilibration of `a`: `d_i = 1 / max_j |a_ij|` (1 for a zero or
/// non-finite row), so that `D a` has rows of unit size.
pub fn row_equilibration(a: &DMatrix<f64>) -> DVector<f64> {
    DVector::from_fn(a.nrows(), |i, _| match a.row(i).amax() {
        s if s > 0.0 && s.is_finite() => 1.0 / s,
        _ => 1.0,
    })
}

/// Spread `max d_i / min d_i` of the row scales above which the slow
/// eigenvalues come from the inverse rather than from `a` itself.
const ROW_SPREAD_FOR_PENCIL: f64 = 1e6;

/// Eigenvalues of a real square matrix, sorted by decreasing real part.
///
/// A matrix whose rows differ in size by more than a factor
/// `ROW_SPREAD_FOR_PENCIL` (a small coefficient in front of a derivative:
/// rows of size `1/m`) has eigenvalues of very different sizes, and a
/// backward-stable eigenvalue routine gives each an absolute error of order
/// `eps |a|`: the slow ones, of order one, then carry errors `eps / m`. So
/// the slow ones come from the inverse instead, `a^-1 = (D a)^-1 D` with `D`
/// the row equilibration (`row_equilibration`): `D a` has rows of unit
/// size and is well conditioned where the stiffness comes from the scaling,
/// and `a^-1` has the slow eigenvalues as its largest ones, `1/lambda`, each
/// with an error of order `eps |a^-1|` — relative `eps` for the slowest. An
/// eigenvalue is taken from `a^-1` when that is the smaller error,
/// `|lambda|^2 eps |a^-1| < eps |a|`, from `a` itself otherwise (the fast
/// ones, accurate relative to their own size there). A singular `D a` (a
/// zero eigenvalue) leaves the plain eigenvalues.
pub fn eigenvalues(a: &DMatrix<f64>) -> Result<Vec<Complex64>, ContinuationError> {
    let n = a.nrows();
    let plain = |m: &DMatrix<f64>| {
        with_evd(m, false, |w| {
            (0..n)
                .map(|i| Complex64::new(w.s_re[i], w.s_im[i]))
                .collect::<Vec<_>>()
        })
    };
    let mut ev = plain(a)?;
    let d = row_equilibration(a);
    if d.max() / d.min() > ROW_SPREAD_FOR_PENCIL {
        let g = DMatrix::from_fn(n, n, |i, j| d[i] * a[(i, j)]);
        let inverse = g
            .lu()
            .solve(&DMatrix::from_diagonal(&d))
            .filter(|x| x.iter().all(|v| v.is_finite()));
        if let Some(x) = inverse {
            let split = (a.amax() / x.amax()).sqrt();
            let slow: Vec<Complex64> = plain(&x)?
                .into_iter()
                .filter(|mu| mu.norm() > 1.0 / split)
                .map(|mu| mu.inv())
                .collect();
            ev.sort_by(|x, y| y.norm().total_cmp(&x.norm()));
            ev.truncate(n - slow.len());
            ev.extend(slow);
        }
    }
    ev.sort_by(|x, y| y.re.total_cmp(&x.re).then(y.im.total_cmp(&x.im)));
    Ok(ev)
}

/// The eigenpair of `a` whose eigenvalue is closest to `target`; the
/// eigenvector is normalised to unit Euclidean length.
pub fn eigenpair_near(
    a: &DMatrix<f64>,
    target: Complex64,
) -> Result<(Complex64, DVector<Complex64>), ContinuationError> {
    let n = a.nrows();
    if n == 0 {
        return Err(ContinuationError::Eigen("empty matrix".into()));
    }
    let (l, v) = with_evd(a, true, |w| {
        // Complex eigenpairs from the real ones, as faer's `Eigen::new_from_real`
        // forms them: a complex pair is stored as (re, im) columns.
        let mut s = Vec::with_capacity(n);
        let mut col = Vec::with_capacity(n);
        let mut j = 0;
        while j < n {
            if w.s_im[j] == 0.0 {
                s.push(Complex64::new(w.s_re[j], 0.0));
                col.push((j, None));
                j += 1;
            } else {
                s.push(Complex64::new(w.s_re[j], w.s_im[j]));
                s.push(Complex64::new(w.s_re[j], -w.s_im[j]));
                col.push((j, Some(1.0)));
                col.push((j, Some(-1.0)));
                j += 2;
            }
        }
        let k = (0..n)
            .min_by(|&i, &j| (s[i] - target).norm().total_cmp(&(s[j] - target).norm()))
            .unwrap_or(0);
        let v = DVector::from_fn(n, |i, _| match col[k] {
            (c, None) => Complex64::new(w.u[(i, c)], 0.0),
            (c, Some(sign)) => Complex64::new(w.u[(i, c)], sign * w.u[(i, c + 1)]),
        });
        (s[k], v)
    })?;
    let norm = v.norm();
    Ok((l, v / Complex64::from(norm)))
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

#[cfg(test)]
mod tests {
    use super::*;

    /// `m x'' + c x' + k x = 0` as a first-order system: eigenvalues
    /// `(-c +- sqrt(c^2 - 4 m k)) / (2m)`, the slow one computed without
    /// cancellation as `-2k / (c + sqrt(c^2 - 4 m k))`. At `m = 1e-14` the
    /// plain eigenvalue routine gets the slow one wrong by about
    /// `eps / m = 2e-2`; from the inverse it is right to rounding, and the
    /// fast one from the matrix itself.
    #[test]
    fn stiff_rows_keep_their_slow_eigenvalues_accurate() {
        for m in [1e-8f64, 1e-14, 1e-20] {
            let (c, k) = (1.5f64, 0.75f64);
            let a = DMatrix::from_row_slice(2, 2, &[0.0, 1.0, -k / m, -c / m]);
            let root = (c * c - 4.0 * m * k).sqrt();
            let slow = -2.0 * k / (c + root);
            let fast = -(c + root) / (2.0 * m);
            let ev = eigenvalues(&a).unwrap();
            assert!(
                (ev[0].re / slow - 1.0).abs() < 1e-14 && ev[0].im == 0.0,
                "m = {m}: {ev:?}"
            );
            assert!(
                (ev[1].re / fast - 1.0).abs() < 1e-12 && ev[1].im == 0.0,
                "m = {m}: {ev:?}"
            );
        }
    }

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
