//! The driven adhesive block (docs/model.md, "Soft adhesive contacts";
//! seed Appendix D), dimensionless: velocities `u = v / V_s`, time in
//! `tau_out`, forces in `F_a`, `z = 1 / u`, `g(z) = e^z E1(z)`.
//!
//! ```text
//! ds/dt = kappa (nu - u)
//! dn/dt = (1 - n) / r - n / T(u),      T(u) = z g(z) = t(v) / tau_out   (eq. D7)
//! s     = n g(z) + f_v u^(1 - alpha)                                   (eq. D1 + viscosity)
//! ```
//!
//! **The model.** The block is analysed without inertia (quasi-static),
//! state `(s, n)`, in every command. At fixed bond fraction `n` the force
//! `n g(1/u) + f_v u^(1 - alpha)` rises strictly with `u` (its slope in
//! `ln u` is `n h_2(z) + f_v (1 - alpha) u^(1 - alpha) > 0`,
//! [`crate::exp_integral::one_minus_z_scaled_e1`]) from 0 at `u = 0` to
//! infinity: every spring force `s > 0` gives one slip velocity, so the
//! quasi-static block is regular everywhere, also at the extrema of the
//! N-shaped *steady* curve (only a block slaved to the steady curve is
//! singular there). Inertia `m` is judged, not modelled: its ratio to the
//! friction's slope over the bonds' relaxation time,
//! `chi = m lambda_n / F_u` ([`inertia_ratio`], the analogue of
//! `m nu^2 / mu_v`), must stay below the inertia threshold, else the
//! commands refuse the scene naming `M`. The seed's gel experiments are
//! such inertia-free stick-slip (§III.D.2).

use super::params::{AdhesiveParam, AdhesiveParams, N_ADHESIVE_PARAMS};
use crate::exp_integral::{one_minus_z_scaled_e1, scaled_e1};
use crate::friction::{increasing_zero, reach};
use continuation::{Scalar, VectorField};

/// The quasi-static adhesive block, state `(s, n)`.
#[derive(Clone, Copy, Debug, Default)]
pub struct AdhesiveBlock;

/// The force the block meets at velocity `u` with bond fraction `n`:
/// pinning `n g(1/u)` (eq. D1: `N kappa v t = F_a n e^z E1(z)`) plus the
/// junction's viscous force `f_v u^(1 - alpha)`.
pub fn force<D: Scalar>(u: D, n: D, f_v: D, alpha: D) -> D {
    n * scaled_e1(u.recip()) + viscous(u, f_v, alpha)
}

/// The junction's viscous force `f_v u^(1 - alpha)` (`0` without `f_v`).
fn viscous<D: Scalar>(u: D, f_v: D, alpha: D) -> D {
    if f_v.re() == 0.0 && D::NDERIV == 0 {
        return D::from(0.0);
    }
    f_v * ((-alpha + 1.0) * u.ln()).exp()
}

/// The bonds' lifetime over `tau_out`, `T(u) = z g(z)`, `z = 1/u` (eq. D7).
pub fn lifetime<D: Scalar>(u: D) -> D {
    let z = u.recip();
    z * scaled_e1(z)
}

/// `dn/dt = (1 - n)/r - n / T(u)` (the bond kinetics behind eq. D2).
pub fn bond_rate<D: Scalar>(u: D, n: D, r: D) -> D {
    (-n + 1.0) / r - n / lifetime(u)
}

/// The steady bond fraction `n = T / (T + r)` (eq. D2).
pub fn steady_bonds<D: Scalar>(u: D, r: D) -> D {
    let t = lifetime(u);
    t / (t + r)
}

/// Steady friction `F_ss(u) = n_ss(u) g(1/u) + f_v u^(1 - alpha)` (eqs. D2,
/// D3, with the junction's viscosity).
pub fn steady_friction<D: Scalar>(u: D, p: &AdhesiveParams) -> D {
    force(
        u,
        steady_bonds(u, D::from(p.r)),
        D::from(p.f_v),
        D::from(p.alpha),
    )
}

/// The slip velocity `u` at which the block meets the force `s` with bond
/// fraction `n`: the root of `n g(e^-w) + f_v e^((1 - alpha) w) = s` in
/// `w = ln u`, rising in `w` (bracketed safeguarded Newton, exact to
/// rounding; the dual parts by Newton steps in the scalar, each doubling
/// the order carried exactly). `None` where there is none (`s <= 0`, or
/// neither bonds nor viscosity: `n <= 0` and `f_v = 0`).
pub fn slip_velocity<D: Scalar>(s: D, n: D, f_v: D, alpha: D) -> Option<D> {
    let beta = -alpha + 1.0;
    let phi = |w: D| -> (D, D) {
        let u = w.exp();
        let z = u.recip();
        let visc = f_v * (beta * w).exp();
        (
            n * scaled_e1(z) + visc - s,
            n * one_minus_z_scaled_e1(z) + visc * beta,
        )
    };
    let real = |w: f64| {
        let (v, d) = phi(D::from(w));
        (v.re(), d.re())
    };
    if !(s.re() > 0.0 && (n.re() > 0.0 || f_v.re() > 0.0) && n.re() >= 0.0) {
        return None;
    }
    let lo = reach(0.0, -1.0, |w| real(w).0 <= 0.0)?;
    let hi = reach(0.0, 1.0, |w| real(w).0 > 0.0)?;
    let (lo, hi) = if lo > hi { (hi, lo) } else { (lo, hi) };
    let w = increasing_zero(real, lo, hi);
    let mut w = D::from(w);
    let mut exact = 0;
    while exact < D::NDERIV {
        let (v, d) = phi(w);
        w -= v / d;
        exact = 2 * exact + 1;
    }
    Some(w.exp())
}

impl VectorField for AdhesiveBlock {
    fn dim(&self) -> usize {
        2
    }
    fn n_params(&self) -> usize {
        N_ADHESIVE_PARAMS
    }
    fn param_name(&self, k: usize) -> String {
        AdhesiveParam::ALL[k].name().into()
    }
    fn rhs<D: Scalar>(&self, x: &[D], p: &[D], out: &mut [D]) {
        let at = |q: AdhesiveParam| p[q as usize];
        let (s, n) = (x[0], x[1]);
        let Some(u) = slip_velocity(s, n, at(AdhesiveParam::Fv), at(AdhesiveParam::Alpha)) else {
            out.fill(D::from(f64::INFINITY));
            return;
        };
        out[0] = at(AdhesiveParam::Kappa) * (at(AdhesiveParam::Nu) - u);
        out[1] = bond_rate(u, n, at(AdhesiveParam::R));
    }
}

/// Steady sliding at `nu`: `(s, n) = (F_ss(nu), n_ss(nu))`.
pub fn steady_state(p: &AdhesiveParams) -> Vec<f64> {
    vec![steady_friction(p.nu, p), steady_bonds(p.nu, p.r)]
}

/// The slip velocity of a state `(s, n)` (infinite outside the model's
/// domain, as the field is there).
pub fn velocity_of(p: &AdhesiveParams, x: &[f64]) -> f64 {
    slip_velocity(x[0], x[1], p.f_v, p.alpha).unwrap_or(f64::INFINITY)
}

/// The slope of the force at fixed bonds, `F_u = dF/du`, and the bonds'
/// relaxation rate `lambda_n = 1/r + 1/T` at steady sliding.
fn steady_slopes(p: &AdhesiveParams) -> (f64, f64) {
    let u = p.nu;
    let n = steady_bonds(u, p.r);
    let f_u =
        (n * one_minus_z_scaled_e1(1.0 / u) + p.f_v * (1.0 - p.alpha) * u.powf(1.0 - p.alpha)) / u;
    (f_u, 1.0 / p.r + 1.0 / lifetime(u))
}

/// The slope `dF_ss / du` of steady friction at `u` (exact, by a dual number).
pub fn steady_slope(u: f64, p: &AdhesiveParams) -> f64 {
    use num_dual::Dual64;
    steady_friction(Dual64::from(u).derivative(), p).eps
}

/// The critical stiffness of the quasi-static block, the analogue of
/// Appendix C's C12: linearized at steady sliding the trace of the 2x2
/// Jacobian is `(kappa_c - kappa) / F_u` and its determinant
/// `kappa lambda_n / F_u > 0`, with
///
/// ```text
/// kappa_c = -lambda_n dF_ss/du,   lambda_n = 1/r + 1/T(nu),   Omega_c^2 = kappa_c lambda_n / F_u
/// ```
///
/// (`F_u` the slope at fixed bonds). Steady sliding loses stability at
/// `kappa_c` where steady friction falls with the velocity (between
/// `V_max` and `V_c`), and is stable at every stiffness elsewhere.
/// `(kappa_c, Omega_c)`; `Omega_c` is NaN where `kappa_c <= 0`.
pub fn critical_stiffness(p: &AdhesiveParams) -> (f64, f64) {
    let (f_u, lambda) = steady_slopes(p);
    let kappa_c = -lambda * steady_slope(p.nu, p);
    (kappa_c, (kappa_c * lambda / f_u).sqrt())
}

/// The inertia ratio `chi = m lambda_n / F_u` at steady sliding: the
/// inertial time `m / F_u` over the bonds' relaxation time `1 / lambda_n`
/// (for the rate-and-state block the same ratio is `m nu^2 / mu_v`).
pub fn inertia_ratio(p: &AdhesiveParams) -> f64 {
    let (f_u, lambda) = steady_slopes(p);
    p.m * lambda / f_u
}

/// The extrema of steady friction over `[lo, hi]`: the zeros of
/// `dF_ss / d ln u`, as `(u, is_maximum)`, located to rounding
/// (`root::illinois` on a log grid of 40 points per decade).
pub fn steady_extrema(p: &AdhesiveParams, lo: f64, hi: f64) -> Vec<(f64, bool)> {
    let slope = |w: f64| steady_slope(w.exp(), p) * w.exp();
    let (a, b) = (lo.ln(), hi.ln());
    let n = ((b - a) / std::f64::consts::LN_10 * 40.0).ceil().max(2.0) as usize;
    let grid: Vec<f64> = (0..=n).map(|i| a + (b - a) * i as f64 / n as f64).collect();
    grid.windows(2)
        .filter_map(|w| {
            let (f0, f1) = (slope(w[0]), slope(w[1]));
            (f0.signum() != f1.signum() && f0 != 0.0).then(|| {
                let ok = |w: f64| Ok::<f64, std::convert::Infallible>(slope(w));
                let Ok(br) = continuation::root::illinois(
                    ok,
                    (w[0], f0),
                    (w[1], f1),
                    1e-15 * w[0].abs().max(1.0),
                    200,
                );
                let root = if br.a.1.abs() < br.b.1.abs() {
                    br.a.0
                } else {
                    br.b.0
                };
                (root.exp(), f0 > 0.0)
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use continuation::system::{eval, jacobian};

    fn gel() -> AdhesiveParams {
        AdhesiveParams {
            kappa: 0.01,
            nu: 800.0,
            r: 0.1,
            f_v: 0.01,
            alpha: 0.6,
            m: 0.0,
        }
    }

    #[test]
    fn the_inversion_round_trips_and_steady_sliding_is_an_equilibrium() {
        let p = gel();
        for (u, n) in [
            (1e-6, 0.9),
            (0.3, 0.5),
            (800.0, 0.07),
            (1e7, 1e-4),
            (5.0, 0.0),
        ] {
            let s = force(u, n, p.f_v, p.alpha);
            let back = slip_velocity(s, n, p.f_v, p.alpha).unwrap();
            assert!((back / u - 1.0).abs() < 1e-13, "u = {u}: {back}");
        }
        assert!(slip_velocity(-1.0, 0.5, p.f_v, p.alpha).is_none());
        assert!(slip_velocity(1.0, 0.0, 0.0, 0.0).is_none());
        let f = eval(&AdhesiveBlock, &steady_state(&p), &p.to_vec());
        assert!(f.iter().all(|v| v.abs() < 1e-12), "{f}");
    }

    #[test]
    fn the_jacobian_has_the_closed_form_trace_and_determinant() {
        let p = gel();
        let (kappa_c, omega_c) = critical_stiffness(&p);
        let mut q = p;
        q.kappa = kappa_c;
        let j = jacobian(&AdhesiveBlock, &steady_state(&q), &q.to_vec());
        let trace = j[(0, 0)] + j[(1, 1)];
        let det = j[(0, 0)] * j[(1, 1)] - j[(0, 1)] * j[(1, 0)];
        assert!(trace.abs() < 1e-9 * j[(1, 1)].abs(), "trace {trace}");
        assert!(
            (det / (omega_c * omega_c) - 1.0).abs() < 1e-9,
            "{det} {omega_c}"
        );
    }
}
