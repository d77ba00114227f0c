//! Period doubling and Neimark–Sacker (torus) bifurcations of cycles, from
//! test functions of the Floquet multipliers (Kuznetsov 1998, §10.3.3):
//!
//! - period doubling: `prod_i (1 + mu_i)`, which changes sign when a real
//!   multiplier passes through -1 (complex pairs contribute `|1 + mu|^2`);
//! - Neimark–Sacker: `prod_{i<j} (mu_i mu_j - 1)` over the nontrivial
//!   multipliers, which changes sign when a complex pair crosses the unit
//!   circle, and also at neutral saddles (real `mu_i mu_j = 1`), which are
//!   discarded after location.
//!
//! Each sign change is located on the branch like a fold (regula falsi on
//! the arclength, each trial corrected onto the branch).

use super::{CycleBranch, CyclePoint, Reading};
use crate::error::ContinuationError;
use crate::periodic::collocation::Collocation;
use crate::periodic::floquet::{multipliers, trivial_index};
use crate::system::VectorField;
use num_complex::Complex64;

/// `prod_i (1 + mu_i)`.
pub fn period_doubling_test(mu: &[Complex64]) -> f64 {
    mu.iter()
        .fold(Complex64::new(1.0, 0.0), |a, m| a * (1.0 + m))
        .re
}

/// `prod_{i<j} (mu_i mu_j - 1)` over the nontrivial multipliers.
pub fn torus_test(mu: &[Complex64]) -> f64 {
    let t = trivial_index(mu);
    let others: Vec<Complex64> = mu
        .iter()
        .enumerate()
        .filter(|(i, _)| Some(*i) != t)
        .map(|(_, m)| *m)
        .collect();
    let mut product = Complex64::new(1.0, 0.0);
    for i in 0..others.len() {
        for j in i + 1..others.len() {
            product *= others[i] * others[j] - 1.0;
        }
    }
    product.re
}

/// Whether a complex pair (not real) lies within `tol` of the unit circle.
fn has_complex_pair_on_circle(mu: &[Complex64], tol: f64) -> bool {
    mu.iter()
        .any(|m| m.im.abs() > tol && (m.norm() - 1.0).abs() <= tol)
}

impl<S: VectorField> CycleBranch<'_, S> {
    /// Locates period doublings and torus bifurcations between the orbit
    /// `(z0, t0)` (collocation `coll0`) and `pt`, the orbit `ds` further.
    pub(super) fn detect_multiplier_crossings(
        &self,
        pt: &mut CyclePoint,
        coll0: &Collocation<'_, S>,
        (z0, t0): (&[f64], &[f64]),
        ds: f64,
    ) -> Result<(), ContinuationError> {
        let n = self.sys.dim();
        // In the plane neither can happen: the one nontrivial multiplier,
        // exp(int_0^T tr J dt), is real and positive (and the pencil's
        // trivial eigenvalue, possibly far from 1 on stiff planar cycles,
        // must not flip the test functions).
        if self.previous_mu.is_empty() || n < 3 {
            return Ok(());
        }
        let at = |z: &[f64]| multipliers(&coll0.linearize(z), n);
        let (pd0, pd1) = (
            period_doubling_test(&self.previous_mu),
            period_doubling_test(&pt.multipliers),
        );
        if pd0 * pd1 < 0.0 {
            let pd = self.estimated(
                self.locate(coll0, z0, t0, (pd0, pd1), ds, |z, _| {
                    Ok(period_doubling_test(&at(z)?))
                })?,
                Reading::AtParameter,
            );
            pt.pd = Some(Box::new(pd));
        }
        let (ns0, ns1) = (torus_test(&self.previous_mu), torus_test(&pt.multipliers));
        if ns0 * ns1 < 0.0 {
            let ns = self.estimated(
                self.locate(coll0, z0, t0, (ns0, ns1), ds, |z, _| {
                    Ok(torus_test(&at(z)?))
                })?,
                Reading::AtParameter,
            );
            if has_complex_pair_on_circle(&ns.multipliers, 1e-6) {
                pt.ns = Some(Box::new(ns));
            }
        }
        Ok(())
    }
}
