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

use super::{multiplier_error, CycleEvent, CyclePoint, Cycles, Reading, FOLD_MULTIPLIER};
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

/// The nontrivial real multipliers of an orbit on either side of `-1`:
/// `(below, above)` count those `< -1 - error` and in `(-1 + error, 0)`;
/// `None` when one lies within `error` of `-1`, where the sign of `1 + mu`
/// is rounding. Real: an imaginary part within `error` of zero.
fn negative_real(mu: &[Complex64], error: f64) -> Option<(usize, usize)> {
    let t = trivial_index(mu);
    let mut counts = (0, 0);
    for (i, m) in mu.iter().enumerate() {
        if Some(i) == t || m.im.abs() > error || m.re >= 0.0 {
            continue;
        }
        if (m.re + 1.0).abs() <= error {
            return None;
        }
        if m.re < -1.0 {
            counts.0 += 1;
        } else {
            counts.1 += 1;
        }
    }
    Some(counts)
}

/// Whether a real multiplier passes through `-1` between two orbits whose
/// multipliers are `mu0`, `mu1` with errors `e0`, `e1`
/// ([`multiplier_error`](super::multiplier_error)): as many negative real
/// multipliers on both, one fewer or more of them below `-1`, and none
/// within its error of `-1` (a sign of `1 + mu` decided on both sides, by
/// more than its error). A real multiplier that changes sign through
/// infinity (a huge multiplier of a stiff orbit whose sign is rounding)
/// changes the period-doubling test function too, but it is not a period
/// doubling: the count of negative multipliers changes.
pub fn crosses_minus_one(mu0: &[Complex64], e0: f64, mu1: &[Complex64], e1: f64) -> bool {
    match (negative_real(mu0, e0), negative_real(mu1, e1)) {
        (Some((b0, a0)), Some((b1, a1))) => b0 + a0 == b1 + a1 && b0.abs_diff(b1) % 2 == 1,
        _ => false,
    }
}

/// Whether a real nontrivial multiplier lies within `band` of `-1`: a
/// located period doubling is accepted only then.
fn has_real_multiplier_at_minus_one(pt: &CyclePoint, band: f64) -> bool {
    pt.multipliers
        .iter()
        .enumerate()
        .any(|(i, m)| Some(i) != pt.trivial && m.im.abs() <= band && (m.re + 1.0).abs() <= band)
}

/// The complex multipliers of an orbit outside the unit circle by more
/// than `error`; `None` when a complex one lies within `error` of it.
fn complex_outside(mu: &[Complex64], error: f64) -> Option<usize> {
    let mut outside = 0;
    for m in mu.iter().filter(|m| m.im.abs() > error) {
        let r = m.norm();
        if (r - 1.0).abs() <= error {
            return None;
        }
        if r > 1.0 {
            outside += 1;
        }
    }
    Some(outside)
}

/// Whether a complex pair crosses the unit circle between two orbits:
/// the count of complex multipliers outside it, decided on both sides by
/// more than the multipliers' error, differs.
fn pair_crosses_circle(mu0: &[Complex64], e0: f64, mu1: &[Complex64], e1: f64) -> bool {
    matches!(
        (complex_outside(mu0, e0), complex_outside(mu1, e1)),
        (Some(a), Some(b)) if a != b
    )
}

/// Whether a complex pair (not real) lies within `tol` of the unit circle.
fn has_complex_pair_on_circle(mu: &[Complex64], tol: f64) -> bool {
    mu.iter()
        .any(|m| m.im.abs() > tol && (m.norm() - 1.0).abs() <= tol)
}

impl<S: VectorField> Cycles<'_, S> {
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
        let (e0, e1) = (
            multiplier_error(n, self.previous_trivial_error),
            multiplier_error(n, pt.trivial_error),
        );
        if pd0 * pd1 < 0.0 && crosses_minus_one(&self.previous_mu, e0, &pt.multipliers, e1) {
            let pd = self.estimated(
                self.locate(coll0, z0, t0, (pd0, pd1), ds, |z, _| {
                    Ok(period_doubling_test(&at(z)?))
                })?
                .0,
                Reading::AtParameter,
            );
            let band = multiplier_error(n, pd.trivial_error).max(FOLD_MULTIPLIER);
            if has_real_multiplier_at_minus_one(&pd, band) {
                pt.attach(CycleEvent::PeriodDoubling, pd);
            }
        }
        let (ns0, ns1) = (torus_test(&self.previous_mu), torus_test(&pt.multipliers));
        if ns0 * ns1 < 0.0 && pair_crosses_circle(&self.previous_mu, e0, &pt.multipliers, e1) {
            let ns = self.estimated(
                self.locate(coll0, z0, t0, (ns0, ns1), ds, |z, _| {
                    Ok(torus_test(&at(z)?))
                })?
                .0,
                Reading::AtParameter,
            );
            if has_complex_pair_on_circle(&ns.multipliers, 1e-6) {
                pt.attach(CycleEvent::Torus, ns);
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mu(values: &[(f64, f64)]) -> Vec<Complex64> {
        values
            .iter()
            .map(|&(re, im)| Complex64::new(re, im))
            .collect()
    }

    #[test]
    fn a_real_multiplier_through_minus_one_is_a_period_doubling() {
        let before = mu(&[(1.0, 0.0), (-0.9, 0.0), (0.2, 0.0)]);
        let after = mu(&[(1.0, 0.0), (-1.1, 0.0), (0.2, 0.0)]);
        assert!(crosses_minus_one(&before, 1e-9, &after, 1e-9));
        assert!(crosses_minus_one(&after, 1e-9, &before, 1e-9));
    }

    #[test]
    fn a_multiplier_changing_sign_through_infinity_is_not() {
        // The test function prod(1 + mu) changes sign, yet no multiplier
        // passes -1: a stiff orbit's huge multiplier whose sign is rounding.
        let before = mu(&[(1.0, 0.0), (3.0e11, 0.0), (1e-12, 0.0)]);
        let after = mu(&[(1.0, 0.0), (-2.0e11, 0.0), (1e-12, 0.0)]);
        assert!(period_doubling_test(&before) * period_doubling_test(&after) < 0.0);
        assert!(!crosses_minus_one(&before, 1e-9, &after, 1e-9));
        assert!(!crosses_minus_one(&after, 1e-9, &before, 1e-9));
    }

    #[test]
    fn a_sign_within_the_multipliers_error_decides_nothing() {
        let before = mu(&[(1.0, 0.0), (-0.9999, 0.0), (0.2, 0.0)]);
        let after = mu(&[(1.0, 0.0), (-1.1, 0.0), (0.2, 0.0)]);
        assert!(crosses_minus_one(&before, 1e-6, &after, 1e-6));
        assert!(!crosses_minus_one(&before, 1e-3, &after, 1e-3));
    }

    #[test]
    fn a_complex_pair_crossing_the_circle_is_counted_once_decided() {
        let inside = mu(&[(1.0, 0.0), (0.5, 0.8), (0.5, -0.8)]);
        let outside = mu(&[(1.0, 0.0), (0.6, 0.9), (0.6, -0.9)]);
        assert!(pair_crosses_circle(&inside, 1e-9, &outside, 1e-9));
        // |0.6 + 0.8 i| = 1: on the circle within any error.
        let on = mu(&[(1.0, 0.0), (0.6, 0.8), (0.6, -0.8)]);
        assert!(!pair_crosses_circle(&on, 1e-6, &outside, 1e-9));
    }
}
