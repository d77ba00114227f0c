//! The critical eigenproblem of a Hopf point as a row-equilibrated pencil.
//!
//! A system with a small coefficient in front of a derivative (a mass `m` in
//! `m v' = s - mu`) has Jacobian rows of size `1/m`. Eigenvectors and
//! resolvent solves of `A = D_x f` then carry errors of order `eps/m`, which
//! swamp a normal-form coefficient of order `m` (the plain rate-and-state
//! law, whose quasi-static Hopf point is degenerate, has `l1 ~ m`).
//!
//! With the row equilibration `D = diag(d)`, `d_i = 1 / max_j |A_ij|`, the
//! scaled field `g = D f` is the right-hand side of `D x' = g(x)` and
//! `G = D A` has rows of unit size. Everything the normal form needs is
//! taken from the pencil `(G, D)`, where `1/m` never appears:
//!
//! ```text
//! A q = i w q                  <=>  (G - i w D) q = 0
//! A^T p = -i w p               <=>  p = D p~,  (G - i w D)^H p~ = 0
//! (sigma I - A)^-1 r           =    (sigma D - G)^-1 (D r)
//! <p, r> = conj(p) . r         =    conj(p~) . (D r)
//! ```
//!
//! so that `p` is Kuznetsov's adjoint vector (`A^T p = -i w p`,
//! `<p, q> = 1`) while no matrix with entries `1/m` is factored. The
//! critical vectors come from one singular value decomposition of
//! `G - i w D` (its smallest singular triple), which also measures how far
//! the point is from an exact Hopf point and how well separated the
//! critical eigenvalue is: the numbers an error bound is built from.

use crate::error::ContinuationError;
use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;

/// The critical vectors of a Hopf point and the resolvents of its pencil.
#[derive(Clone, Debug)]
pub struct HopfPencil {
    /// Angular frequency `w > 0`.
    pub omega: f64,
    /// Row equilibration `d_i = 1 / max_j |A_ij|` (1 for a zero row).
    d: DVector<f64>,
    /// `G = D A` as a complex matrix.
    g: DMatrix<Complex64>,
    /// Right critical eigenvector, `A q = i w q`, `<q, q> = 1`.
    pub q: DVector<Complex64>,
    /// Kuznetsov's adjoint vector, `A^T p = -i w p`, `<p, q> = 1`.
    pub p: DVector<Complex64>,
    /// `sigma_min / sigma_max` of `G - i w D`: the relative distance of the
    /// point from an exact Hopf point (rounding level at a located one).
    pub eigen_residual: f64,
    /// Componentwise condition of the bordered systems the critical vectors
    /// are solved from (large when another eigenvalue is close).
    pub eigen_condition: f64,
}

/// Solves `m x = b` with Skeel's componentwise condition number
/// `|| |m^-1| |m| |x| ||_inf / ||x||_inf`, the factor by which the rounding
/// of `m`'s entries (and of a backward-stable solve) grows in `x`. Unlike
/// `sigma_max / sigma_min` it does not grow with a badly scaled row.
fn solve_with_condition(
    m: DMatrix<Complex64>,
    b: &DVector<Complex64>,
) -> Result<(DVector<Complex64>, f64), ContinuationError> {
    let n = m.nrows();
    let inv = m
        .clone()
        .try_inverse()
        .filter(|i| i.iter().all(|z| z.re.is_finite() && z.im.is_finite()))
        .ok_or(ContinuationError::Singular)?;
    let x = crate::linalg::solve_complex(m.clone(), b)?;
    let abs_m = m.map(|z| z.norm());
    let abs_inv = inv.map(|z| z.norm());
    let abs_x = DVector::from_fn(n, |i, _| x[i].norm());
    let xmax = abs_x.amax();
    let cond = if xmax > 0.0 {
        (abs_inv * (abs_m * &abs_x)).amax() / xmax
    } else {
        1.0
    };
    Ok((x, cond.max(1.0)))
}

impl HopfPencil {
    /// The pencil of the Jacobian `a` at a Hopf point of frequency `omega`.
    pub fn new(a: &DMatrix<f64>, omega: f64) -> Result<Self, ContinuationError> {
        let n = a.nrows();
        if n < 2 || !omega.is_finite() || omega == 0.0 {
            return Err(ContinuationError::Eigen(format!(
                "no Hopf pencil for a {n}x{n} Jacobian at frequency {omega}"
            )));
        }
        let omega = omega.abs();
        let d = crate::linalg::row_equilibration(a);
        let g = DMatrix::from_fn(n, n, |i, j| Complex64::from(d[i] * a[(i, j)]));
        let iw = Complex64::new(0.0, omega);
        let k = DMatrix::from_fn(n, n, |i, j| {
            g[(i, j)]
                - if i == j {
                    iw * d[i]
                } else {
                    Complex64::from(0.0)
                }
        });
        let svd = k.clone().svd(true, true);
        let (u, v_t) = match (svd.u, svd.v_t) {
            (Some(u), Some(v_t)) => (u, v_t),
            _ => {
                return Err(ContinuationError::Eigen(
                    "SVD of the Hopf pencil failed".into(),
                ))
            }
        };
        let s = &svd.singular_values;
        if s.iter().any(|x| !x.is_finite()) {
            return Err(ContinuationError::Eigen(
                "the Hopf pencil has non-finite entries".into(),
            ));
        }
        let order: Vec<usize> = {
            let mut o: Vec<usize> = (0..n).collect();
            o.sort_by(|&a, &b| s[b].total_cmp(&s[a]));
            o
        };
        let (smax, s2, smin) = (s[order[0]], s[order[n - 2]], s[order[n - 1]]);
        // Scale-free test of a simple critical eigenvalue; its conditioning
        // is measured below, componentwise.
        if s2 <= 0.0 || smax <= 0.0 {
            return Err(ContinuationError::Eigen(
                "the critical eigenvalue of the Hopf pencil is not simple".into(),
            ));
        }
        let last = order[n - 1];
        // First approximations: the smallest singular triple (right null
        // vector: conjugate of the last row of V^H; left: the column of U).
        let q0: DVector<Complex64> = DVector::from_fn(n, |i, _| v_t[(last, i)].conj());
        let u0: DVector<Complex64> = u.column(last).into_owned();
        // Refined by the bordered systems [[K, u0], [q0^H, 0]] (q, with
        // q0^H q = 1) and its adjoint (p~): their componentwise condition
        // bounds the error of every component, small ones included (the SVD
        // vector is accurate only relative to the largest component).
        let border =
            |m: &DMatrix<Complex64>, col: &DVector<Complex64>, row: &DVector<Complex64>| {
                let mut b = DMatrix::<Complex64>::zeros(n + 1, n + 1);
                b.view_mut((0, 0), (n, n)).copy_from(m);
                for i in 0..n {
                    b[(i, n)] = col[i];
                    b[(n, i)] = row[i].conj();
                }
                let mut e = DVector::<Complex64>::zeros(n + 1);
                e[n] = Complex64::from(1.0);
                solve_with_condition(b, &e)
            };
        let (qb, cond_q) = border(&k, &u0, &q0)?;
        let (pb, cond_p) = border(&k.adjoint(), &q0, &u0)?;
        let q = qb.rows(0, n).into_owned();
        let q = &q / Complex64::from(q.norm());
        let pt = pb.rows(0, n).into_owned();
        // p = D p~ with p~^H D q = 1.
        let dq = DVector::from_fn(n, |i, _| q[i] * d[i]);
        let scale = pt.dotc(&dq);
        if scale.norm() == 0.0 || !scale.re.is_finite() {
            return Err(ContinuationError::Eigen(
                "adjoint and critical eigenvector of the Hopf pencil are orthogonal".into(),
            ));
        }
        let ptilde = &pt / scale.conj();
        let p = DVector::from_fn(n, |i, _| ptilde[i] * d[i]);
        Ok(HopfPencil {
            omega,
            d,
            g,
            q,
            p,
            eigen_residual: smin / smax,
            eigen_condition: cond_q.max(cond_p),
        })
    }

    /// Relative error of the critical vectors: `(n eps + delta) kappa_q`
    /// with `delta` the relative distance from an exact Hopf point
    /// ([`eigen_residual`](Self::eigen_residual)) and `kappa_q` the
    /// eigenvector condition ([`eigen_condition`](Self::eigen_condition)).
    pub fn eigen_error(&self) -> f64 {
        (self.dim() as f64 * f64::EPSILON + self.eigen_residual) * self.eigen_condition
    }

    /// Dimension of the state.
    pub fn dim(&self) -> usize {
        self.d.len()
    }

    /// `sigma D - G`, the scaled form of `sigma I - A`.
    fn shifted(&self, sigma: Complex64) -> DMatrix<Complex64> {
        let n = self.dim();
        DMatrix::from_fn(n, n, |i, j| {
            let diag = if i == j {
                sigma * self.d[i]
            } else {
                Complex64::from(0.0)
            };
            diag - self.g[(i, j)]
        })
    }

    /// `D r`, the scaled form of a derivative `r` of `f`.
    fn scaled(&self, r: &DVector<Complex64>) -> DVector<Complex64> {
        DVector::from_fn(self.dim(), |i, _| r[i] * self.d[i])
    }

    /// `(sigma I - A)^-1 r`, solved as `(sigma D - G)^-1 (D r)`, with the
    /// solve's componentwise condition number.
    pub fn resolve(
        &self,
        sigma: Complex64,
        r: &DVector<Complex64>,
    ) -> Result<(DVector<Complex64>, f64), ContinuationError> {
        solve_with_condition(self.shifted(sigma), &self.scaled(r))
    }

    /// The solution `a` of `(i w I - A) a = r - q <p, r>` with `<p, a> = 0`
    /// (the resonant equation of the centre-manifold expansion), from the
    /// bordered pencil `[[i w D - G, D q], [p^H, 0]]`, with the solve's
    /// componentwise condition number.
    pub fn resolve_resonant(
        &self,
        r: &DVector<Complex64>,
    ) -> Result<(DVector<Complex64>, f64), ContinuationError> {
        let n = self.dim();
        let c = self.p.dotc(r);
        let mut m = DMatrix::<Complex64>::zeros(n + 1, n + 1);
        m.view_mut((0, 0), (n, n))
            .copy_from(&self.shifted(Complex64::new(0.0, self.omega)));
        for i in 0..n {
            m[(i, n)] = self.q[i] * self.d[i];
            m[(n, i)] = self.p[i].conj();
        }
        let rhs = self.scaled(&(r - &self.q * c));
        let b = DVector::from_iterator(n + 1, rhs.iter().copied().chain([Complex64::from(0.0)]));
        let (x, cond) = solve_with_condition(m, &b)?;
        Ok((x.rows(0, n).into_owned(), cond))
    }

    /// `<p, r>` and its size `sum_i |p_i| |r_i|`, the scale against which
    /// the rounding of a cancelling sum is judged.
    pub fn project(&self, r: &DVector<Complex64>) -> (Complex64, f64) {
        let size = self
            .p
            .iter()
            .zip(r.iter())
            .map(|(a, b)| a.norm() * b.norm())
            .sum();
        (self.p.dotc(r), size)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// At a Hopf point of a matrix with a row of size `1/m`, the pencil's
    /// vectors solve the plain eigenproblems and its resolvent is that of `A`.
    #[test]
    fn pencil_vectors_solve_the_plain_eigenproblems() {
        // A = S B S^-1, S = diag(1, 1e8, 1): eigenvalues +-2i and -3.
        let b = DMatrix::from_row_slice(3, 3, &[0.0, -2.0, 0.0, 2.0, 0.0, 0.0, 0.0, 1.0, -3.0]);
        let s = [1.0, 1e8, 1.0];
        let a = DMatrix::from_fn(3, 3, |i, j| s[i] * b[(i, j)] / s[j]);
        let pencil = HopfPencil::new(&a, 2.0).unwrap();
        let ac = a.map(Complex64::from);
        let iw = Complex64::new(0.0, 2.0);
        let (q, p) = (&pencil.q, &pencil.p);
        assert!((&ac * q - q * iw).norm() < 1e-14 * ac.norm());
        assert!((ac.transpose() * p + p * iw).norm() < 1e-14 * ac.norm() * p.norm());
        assert!((q.norm() - 1.0).abs() < 1e-15);
        assert!((p.dotc(q) - Complex64::from(1.0)).norm() < 1e-14);
        assert!(pencil.eigen_residual < 1e-15);
        let r = DVector::from_vec(vec![
            Complex64::new(1.0, 0.5),
            Complex64::new(-2.0, 0.0),
            Complex64::new(0.25, -1.0),
        ]);
        let sigma = Complex64::new(0.3, 4.0);
        let (x, cond) = pencil.resolve(sigma, &r).unwrap();
        let lhs = (DMatrix::<Complex64>::identity(3, 3) * sigma - &ac) * &x;
        assert!((lhs - &r).norm() < 1e-14 * ac.norm() * x.norm());
        assert!(cond.is_finite() && cond >= 1.0);
        let (y, _) = pencil.resolve_resonant(&r).unwrap();
        let rhs = &r - q * p.dotc(&r);
        let lhs = (DMatrix::<Complex64>::identity(3, 3) * iw - &ac) * &y;
        assert!((lhs - rhs).norm() < 1e-13 * ac.norm() * y.norm().max(1.0));
        assert!(p.dotc(&y).norm() < 1e-13 * y.norm().max(1.0));
    }
}
