//! Closed forms of the seed's Appendix C (linear stability of steady sliding),
//! in docs/model.md's dimensionless units. They are the reference the continuation
//! results are compared with; the analyses never use them to get their answers,
//! except to say, where a search found no onset, that no value of a control can
//! give one (`analysis::control::onset_excluded`, from C11 and C12), and to
//! start Newton's method on the Hopf system where the search from a stable
//! stiffness failed (`analysis::hopf::find_hopf_with`).
//!
//! With radiation damping the linearized force balance meets the slope
//! `mu_v + eta_d nu` in `ln v` instead of `mu_v` (the state law is
//! unchanged): every closed form below takes `mu_v` as
//! [`Params::mu_v_damped`] (docs/model.md, "Linear stability").

use crate::params::Params;
use num_complex::Complex64;

/// Critical stiffness with inertia, seed eq. C11:
/// `kappa_c = (mu_phi - mu_v) (1 + m nu^2 / mu_v)`, `mu_v` with damping
/// ([`Params::mu_v_damped`]).
pub fn critical_stiffness(p: &Params) -> f64 {
    (p.mu_phi() - p.mu_v_damped()) * (1.0 + p.inertia_ratio())
}

/// Critical stiffness without inertia, seed eq. C12: `kappa_c = mu_phi -
/// mu_v`, `mu_v` with damping.
pub fn critical_stiffness_quasi_static(p: &Params) -> f64 {
    p.mu_phi() - p.mu_v_damped()
}

/// Critical angular frequency, seed eq. C13: `omega_c = nu sqrt(mu_phi/mu_v - 1)`
/// (units `V0/D0`), `mu_v` with damping; `None` when steady friction (with
/// the damping) is not velocity weakening.
pub fn critical_frequency(p: &Params) -> Option<f64> {
    let r = p.mu_phi() / p.mu_v_damped() - 1.0;
    (r > 0.0).then(|| p.nu * r.sqrt())
}

/// Coefficients `[a3, a2, a1, a0]` of the characteristic polynomial of the
/// inertial block at steady sliding, `a3 l^3 + a2 l^2 + a1 l + a0 = 0`:
/// `m l^3 + (mu_v/nu + m nu) l^2 + (kappa + mu_v - mu_phi) l + kappa nu`,
/// `mu_v` with damping.
///
/// This is seed eq. C9 with `i Omega = l` (growth rate) in docs/model.md units; at
/// `m = 0` it reduces to the quasi-static quadratic.
pub fn characteristic_polynomial(p: &Params) -> [f64; 4] {
    let (mu_v, mu_phi, nu, m, kappa) = (p.mu_v_damped(), p.mu_phi(), p.nu, p.m, p.kappa);
    [m, mu_v / nu + m * nu, kappa + mu_v - mu_phi, kappa * nu]
}

/// Large-stiffness roots of the characteristic cubic (corrected seed eq. C10,
/// docs/model.md): one real root `-> -nu` and a pair
/// `-> -mu_v/(2 m nu) +- i sqrt(kappa/m)`. Returns `(real, upper)`, the upper
/// member of the pair having positive imaginary part. Requires `m > 0`.
///
/// The seed prints the pair with a `(1 + 3i)` factor, which breaks the
/// conjugate symmetry of a real polynomial's roots; these are the leading
/// terms of the roots of [`characteristic_polynomial`] as `kappa -> inf`.
pub fn large_stiffness_roots(p: &Params) -> (f64, Complex64) {
    let real = -p.nu;
    let pair = Complex64::new(
        -p.mu_v_damped() / (2.0 * p.m * p.nu),
        (p.kappa / p.m).sqrt(),
    );
    (real, pair)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p() -> Params {
        Params {
            kappa: 0.0,
            nu: 3.0,
            m: 0.1,
            a: 0.01,
            b: 0.02,
            mu0: 0.6,
            mu2: 5e-4,
            theta_c: None,
            state_law: Default::default(),
            mu_vv: 0.0,
            mu_vphi: 0.0,
            eta_d: 0.0,
        }
    }

    #[test]
    fn hopf_condition_of_the_cubic_holds_at_c11_c13() {
        // l = i w is a root of a3 l^3 + a2 l^2 + a1 l + a0 iff a1 = a3 w^2 and a0 = a2 w^2.
        // A consistency check of the closed forms with each other; the independent
        // checks (eigenvalues against the cubic's roots, continuation against C11/C13)
        // are in tests/appendix_c.rs.
        let mut q = p();
        q.kappa = critical_stiffness(&q);
        let w = critical_frequency(&q).unwrap();
        let [a3, a2, a1, a0] = characteristic_polynomial(&q);
        assert!((a1 - a3 * w * w).abs() < 1e-14 * a1.abs());
        assert!((a0 - a2 * w * w).abs() < 1e-14 * a0.abs());
    }

    #[test]
    fn quasi_static_limit_of_c11_is_c12() {
        let mut q = p();
        q.m = 0.0;
        assert_eq!(critical_stiffness(&q), critical_stiffness_quasi_static(&q));
    }
}
