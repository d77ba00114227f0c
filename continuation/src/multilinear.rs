//! Multilinear forms of a vector field at a point, exact from dual numbers,
//! evaluated on complex vectors (Kuznetsov 1998, eq. 3.18):
//!
//! ```text
//! B(u, v)    = sum_jk  d^2 f / dx_j dx_k        u_j v_k
//! C(u, v, w) = sum_jkl d^3 f / dx_j dx_k dx_l   u_j v_k w_l
//! ```
//!
//! Real directions are differentiated with hyper-dual numbers (second order)
//! and hyper-hyper-dual numbers (third order); complex arguments are expanded
//! by multilinearity into real and imaginary parts.

use crate::system::{second_derivative, JointDirection, VectorField};
use nalgebra::DVector;
use num_complex::Complex64;
use num_dual::HyperHyperDual64;

/// A point `(x, p)` at which forms are taken.
#[derive(Clone, Copy, Debug)]
pub struct At<'a, S: VectorField> {
    pub sys: &'a S,
    pub x: &'a [f64],
    pub p: &'a [f64],
}

fn parts(u: &DVector<Complex64>) -> [(Vec<f64>, Complex64); 2] {
    [
        (u.iter().map(|z| z.re).collect(), Complex64::new(1.0, 0.0)),
        (u.iter().map(|z| z.im).collect(), Complex64::new(0.0, 1.0)),
    ]
}

fn is_zero(v: &[f64]) -> bool {
    v.iter().all(|&t| t == 0.0)
}

impl<S: VectorField> At<'_, S> {
    /// Real third derivative `D^3 f [u, v, w]`.
    pub fn third_real(&self, u: &[f64], v: &[f64], w: &[f64]) -> DVector<f64> {
        let xd: Vec<HyperHyperDual64> = (0..self.x.len())
            .map(|i| HyperHyperDual64::new(self.x[i], u[i], v[i], w[i], 0.0, 0.0, 0.0, 0.0))
            .collect();
        let pd: Vec<HyperHyperDual64> = self.p.iter().map(|&v| HyperHyperDual64::from(v)).collect();
        let mut out = vec![HyperHyperDual64::from(0.0); self.sys.dim()];
        self.sys.rhs(&xd, &pd, &mut out);
        DVector::from_iterator(out.len(), out.iter().map(|d| d.eps1eps2eps3))
    }

    /// Complex bilinear form `B(u, v)`.
    pub fn b(&self, u: &DVector<Complex64>, v: &DVector<Complex64>) -> DVector<Complex64> {
        let n = self.x.len();
        let mut out = DVector::from_element(n, Complex64::new(0.0, 0.0));
        for (ur, cu) in parts(u) {
            if is_zero(&ur) {
                continue;
            }
            for (vr, cv) in parts(v) {
                if is_zero(&vr) {
                    continue;
                }
                let d = second_derivative(
                    self.sys,
                    self.x,
                    self.p,
                    JointDirection::state(&ur),
                    JointDirection::state(&vr),
                );
                out += d.map(|t| cu * cv * t);
            }
        }
        out
    }

    /// Complex trilinear form `C(u, v, w)`.
    pub fn c(
        &self,
        u: &DVector<Complex64>,
        v: &DVector<Complex64>,
        w: &DVector<Complex64>,
    ) -> DVector<Complex64> {
        let n = self.x.len();
        let mut out = DVector::from_element(n, Complex64::new(0.0, 0.0));
        for (ur, cu) in parts(u) {
            for (vr, cv) in parts(v) {
                for (wr, cw) in parts(w) {
                    if is_zero(&ur) || is_zero(&vr) || is_zero(&wr) {
                        continue;
                    }
                    out += self.third_real(&ur, &vr, &wr).map(|t| cu * cv * cw * t);
                }
            }
        }
        out
    }
}
