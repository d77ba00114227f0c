//! Normal-form coefficients of a Hopf point (Kuznetsov 1998, §3.5 and §10.2).
//!
//! With `A = D_x f`, `A q = i w q`, `A^T p = -i w p`, `<q, q> = 1`,
//! `<p, q> = 1` (`<a, b> = conj(a) . b`):
//!
//! ```text
//! c1 = 1/2 <p, C(q,q,qbar)> - <p, B(q, A^-1 B(q,qbar))> + 1/2 <p, B(qbar, (2iw - A)^-1 B(q,q))>
//! l1 = Re(c1) / w                                              (Kuznetsov 1998, eq. 3.20)
//! ```
//!
//! so that `l1 < 0` is a supercritical Hopf bifurcation. The restriction to
//! the centre manifold reads `z' = (alpha + i w) z + c1 z |z|^2` with
//! `x = x0 + 2 Re(z q) + ...`; hence, with `lambda'` the derivative of the
//! critical eigenvalue along a parameter, the emerging cycle has
//! `|z|^2 = -Re(lambda') (p - p_c) / Re(c1)` and component `j` oscillates with
//! peak-to-peak amplitude `4 |q_j| |z|`.

pub use crate::hopf_extended::{hopf_normal_form_extended, ExtendedHopf};
pub use crate::hopf_series::{hopf_series, HopfSeries};

use crate::error::ContinuationError;
use crate::hopf_pencil::HopfPencil;
use crate::linalg::eigenpair_near;
use crate::multilinear::At;
use crate::system::{jacobian, param_derivative, second_derivative, JointDirection, VectorField};
use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;

/// The first normal-form coefficient at a Hopf point and what it is made of.
#[derive(Clone, Debug)]
pub struct HopfNormalForm {
    /// Angular frequency `w > 0`.
    pub omega: f64,
    /// Right critical eigenvector, `<q, q> = 1`.
    pub q: DVector<Complex64>,
    /// Adjoint critical eigenvector, `<p, q> = 1`.
    pub p: DVector<Complex64>,
    /// Cubic normal-form coefficient `c1`.
    pub c1: Complex64,
    /// First Lyapunov coefficient `l1 = Re(c1) / w`.
    pub l1: f64,
    /// Sum of the moduli of the three terms of `c1`, divided by `w`: the scale
    /// against which a vanishing `l1` is judged.
    pub term_scale: f64,
    /// Bound on the rounding error of `l1` (see [`hopf_normal_form`]): where
    /// `|l1| <= l1_error_bound` its sign is not known.
    pub l1_error_bound: f64,
}

impl HopfNormalForm {
    /// Whether `|l1|` does not exceed its error bound: the sign of `l1` is
    /// rounding, the Hopf point degenerate to working precision.
    pub fn is_degenerate(&self) -> bool {
        self.l1.abs() <= self.l1_error_bound
    }
}

/// Factor on `eps` for the rounding of one derivative evaluation, product
/// and sum of length `n`: a generous `8 n` (Higham's `gamma_n` is `n eps`
/// for a dot product; derivatives by dual numbers add a few roundings per
/// entry).
pub(crate) fn rounding_factor(n: usize) -> f64 {
    8.0 * n as f64 * f64::EPSILON
}

/// Computes `c1` and `l1` at the Hopf point `(x, p)` with frequency `omega`,
/// with a bound on the rounding error of `l1`.
///
/// The critical vectors and resolvents come from the row-equilibrated pencil
/// (`HopfPencil`), so that rows of size `1/m` (small inertia) never enter a
/// factorization. With `S_k = sum_i |p_i| |r_k,i|` the size of the `k`-th
/// term before its own cancellation, `kappa_0`, `kappa_2` the componentwise
/// condition numbers of the two resolvents and `e_q` the relative error of
/// the critical vectors (`eigen_error`),
///
/// ```text
/// |error(c1)| <= (g (1 + kappa_0) + e_q) (S_1 + S_2 + S_3) + g (kappa_0 S_2 + kappa_2 S_3),   g = 8 n eps
/// ```
///
/// and `l1_error_bound = |error(c1)| / w`: first-order rounding of every
/// input of the cancelling sum, amplified by the solve it goes through; the
/// term `g kappa_0` covers the rounding of the point itself (an equilibrium
/// located to `eps kappa_0` moves every derivative by as much).
pub fn hopf_normal_form<S: VectorField>(
    sys: &S,
    x: &[f64],
    p: &[f64],
    omega: f64,
) -> Result<HopfNormalForm, ContinuationError> {
    let a = jacobian(sys, x, p);
    let pencil = HopfPencil::new(&a, omega)?;
    let omega = pencil.omega;
    let q = pencil.q.clone();
    let at = At { sys, x, p };
    let qb = q.map(|z| z.conj());
    let (h11, kappa0) = pencil.resolve(Complex64::from(0.0), &at.b(&q, &qb))?;
    let h11 = -h11;
    let (h20, kappa2) = pencil.resolve(Complex64::new(0.0, 2.0 * omega), &at.b(&q, &q))?;
    let (t1, s1) = pencil.project(&at.c(&q, &q, &qb));
    let (t2, s2) = pencil.project(&at.b(&q, &h11));
    let (t3, s3) = pencil.project(&at.b(&qb, &h20));
    let (t1, t2, t3) = (t1 * 0.5, -t2, t3 * 0.5);
    let (s1, s3) = (0.5 * s1, 0.5 * s3);
    let c1 = t1 + t2 + t3;
    let g = rounding_factor(x.len());
    let error = (g * (1.0 + kappa0) + pencil.eigen_error()) * (s1 + s2 + s3)
        + g * (kappa0 * s2 + kappa2 * s3);
    Ok(HopfNormalForm {
        omega,
        q,
        p: pencil.p,
        c1,
        l1: c1.re / omega,
        term_scale: (t1.norm() + t2.norm() + t3.norm()) / omega,
        l1_error_bound: error / omega,
    })
}

/// Coefficient `a` of the fold normal form `y' = beta + a y^2` on the centre
/// manifold of a limit point: `a = 1/2 <p, B(q, q)>` with `A q = 0`,
/// `A^T p = 0`, `<q, q> = 1`, `<p, q> = 1` (Kuznetsov 1998, §3.2 and §5.4,
/// projection method); `a != 0` makes the fold nondegenerate.
pub fn fold_coefficient<S: VectorField>(
    sys: &S,
    x: &[f64],
    p: &[f64],
) -> Result<f64, ContinuationError> {
    let a = jacobian(sys, x, p);
    let zero = Complex64::new(0.0, 0.0);
    let q = eigenpair_near(&a, zero)?.1.map(|z| z.re);
    let q = &q / q.norm();
    let pt = eigenpair_near(&a.transpose(), zero)?.1.map(|z| z.re);
    let padj = &pt / pt.dot(&q);
    let b = second_derivative(
        sys,
        x,
        p,
        JointDirection::state(q.as_slice()),
        JointDirection::state(q.as_slice()),
    );
    Ok(0.5 * padj.dot(&b))
}

/// Derivative of the critical eigenvalue along parameter `k`,
/// `lambda' = <p, (D_pk A + B(., x_pk)) q>` with `x_pk = -A^-1 D_pk f` the
/// motion of the equilibrium (Kuznetsov 1998, §3.5, transversality).
pub fn eigenvalue_derivative<S: VectorField>(
    sys: &S,
    x: &[f64],
    par: &[f64],
    k: usize,
    nf: &HopfNormalForm,
) -> Result<Complex64, ContinuationError> {
    let a = jacobian(sys, x, par);
    let fp = param_derivative(sys, x, par, k);
    // Rows equilibrated before the solve (rows of size 1/m, small inertia).
    let d = crate::linalg::row_equilibration(&a);
    let a_eq = DMatrix::from_fn(a.nrows(), a.ncols(), |i, j| d[i] * a[(i, j)]);
    let f_eq = DVector::from_fn(fp.len(), |i, _| -d[i] * fp[i]);
    let xp = crate::linalg::solve(a_eq, &f_eq)?;
    let mut ek = vec![0.0; par.len()];
    ek[k] = 1.0;
    let mut dq = DVector::from_element(x.len(), Complex64::new(0.0, 0.0));
    let qr: Vec<f64> = nf.q.iter().map(|z| z.re).collect();
    let qi: Vec<f64> = nf.q.iter().map(|z| z.im).collect();
    let dir = JointDirection {
        x: xp.as_slice(),
        p: &ek,
    };
    for (v, c) in [
        (qr, Complex64::new(1.0, 0.0)),
        (qi, Complex64::new(0.0, 1.0)),
    ] {
        dq += second_derivative(sys, x, par, JointDirection::state(&v), dir).map(|t| c * t);
    }
    Ok(nf.p.dotc(&dq))
}

/// The cycle born at a Hopf point, to leading order in `p - p_c`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OnsetLaw {
    /// Peak-to-peak amplitude of component `j`: `Delta_j ~ coefficient sqrt|p - p_c|`,
    /// `coefficient = 4 |q_j| sqrt|Re(lambda') / Re(c1)|`.
    pub coefficient: f64,
    /// `+1` if the cycle exists for `p > p_c`, `-1` for `p < p_c`.
    pub side: f64,
    /// Frequency shift on the cycle, `d w / d p = Im(lambda') - Im(c1) Re(lambda') / Re(c1)`.
    pub frequency_slope: f64,
}

/// Leading-order amplitude and frequency of the emerging cycle in component `j`.
pub fn onset_law(nf: &HopfNormalForm, dlambda: Complex64, j: usize) -> OnsetLaw {
    let ratio = dlambda.re / nf.c1.re;
    OnsetLaw {
        coefficient: 4.0 * nf.q[j].norm() * ratio.abs().sqrt(),
        side: if ratio < 0.0 { 1.0 } else { -1.0 },
        frequency_slope: dlambda.im - nf.c1.im * ratio,
    }
}
