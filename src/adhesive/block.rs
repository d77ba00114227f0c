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
//! **The model.** With inertia `m = M V_s / (F_a tau_out)` the block's
//! velocity is a state, `w = ln u` ([`InertialAdhesiveBlock`], state
//! `(s, w, n)`):
//!
//! ```text
//! m u dw/dt = s - F(n, u),     F(n, u) = n g(1/u) + f_v u^(1 - alpha)
//! ```
//!
//! collocated in this implicit form (`rho_w = m u`), as the rate-and-state
//! inertial block is. Without it ([`AdhesiveBlock`], state `(s, n)`) the
//! velocity is slaved by `s = F(n, u)`: at fixed bond fraction `n` the force
//! rises strictly with `u` (its slope in `ln u` is `n h_2(z) + f_v (1 -
//! alpha) u^(1 - alpha) > 0`, [`crate::exp_integral::one_minus_z_scaled_e1`])
//! from 0 at `u = 0` to infinity, so every spring force `s > 0` gives one
//! slip velocity and the quasi-static block is regular everywhere, also at
//! the extrema of the N-shaped *steady* curve. Which of the two a command
//! uses is decided by the inertia ratio `chi = m lambda_n / F_u`
//! ([`inertia_ratio`], the inertial time `m / F_u` over the bonds'
//! relaxation time, the analogue of `m nu^2 / mu_v`): quasi-static where
//! `chi` stays below the inertia threshold, inertial elsewhere
//! ([`model_for`]). Inertia raises the critical stiffness by the factor
//! `1 + chi` and leaves the onset frequency as it is
//! ([`critical_stiffness_of`]).

use super::params::{AdhesiveParam, AdhesiveParams, N_ADHESIVE_PARAMS};
use crate::exp_integral::{one_minus_z_scaled_e1, scaled_e1};
use crate::friction::{increasing_zero, reach};
use crate::model::ModelKind;
use continuation::{Scalar, VectorField};
use num_dual::Dual;

/// The quasi-static adhesive block, state `(s, n)` (the parameter `m`
/// unread).
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

/// The parameters of steady sliding and of its onset, `r`, `f_v`, `alpha`
/// and `m` ([`AdhesiveParams`]), on any scalar: the fit
/// ([`crate::adhesive::fit`]) differentiates steady friction and the
/// critical stiffness in them through dual numbers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SteadyLaw<D> {
    pub r: D,
    pub f_v: D,
    pub alpha: D,
    pub m: D,
}

impl SteadyLaw<f64> {
    /// The law of `p`, on the scalar `D`.
    pub fn of<D: Scalar>(p: &AdhesiveParams) -> SteadyLaw<D> {
        SteadyLaw {
            r: D::from(p.r),
            f_v: D::from(p.f_v),
            alpha: D::from(p.alpha),
            m: D::from(p.m),
        }
    }
}

impl<D: Scalar> SteadyLaw<D> {
    /// The same values as constants of a dual number over `D`.
    fn lifted(&self) -> SteadyLaw<Dual<D>> {
        SteadyLaw {
            r: Dual::from_re(self.r),
            f_v: Dual::from_re(self.f_v),
            alpha: Dual::from_re(self.alpha),
            m: Dual::from_re(self.m),
        }
    }
}

/// Steady friction `F_ss(u) = n_ss(u) g(1/u) + f_v u^(1 - alpha)` (eqs. D2,
/// D3, with the junction's viscosity), the parameters on any scalar.
pub fn steady_force<D: Scalar>(u: D, law: &SteadyLaw<D>) -> D {
    force(u, steady_bonds(u, law.r), law.f_v, law.alpha)
}

/// Steady friction of the scene's parameters ([`steady_force`]).
pub fn steady_friction<D: Scalar>(u: D, p: &AdhesiveParams) -> D {
    steady_force(u, &SteadyLaw::of(p))
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

/// The inertial adhesive block, state `(s, w = ln u, n)` (module docs):
///
/// ```text
/// ds/dt       = kappa (nu - u)
/// m u dw/dt   = s - F(n, u),      F(n, u) = n g(1/u) + f_v u^(1 - alpha)
/// dn/dt       = (1 - n)/r - n / T(u)
/// ```
#[derive(Clone, Copy, Debug, Default)]
pub struct InertialAdhesiveBlock;

impl VectorField for InertialAdhesiveBlock {
    fn dim(&self) -> usize {
        3
    }
    fn n_params(&self) -> usize {
        N_ADHESIVE_PARAMS
    }
    fn param_name(&self, k: usize) -> String {
        AdhesiveParam::ALL[k].name().into()
    }
    fn rhs<D: Scalar>(&self, x: &[D], p: &[D], out: &mut [D]) {
        let mut rho = [D::from(1.0); 3];
        self.implicit_rhs(x, p, &mut rho, out);
        out[1] /= rho[1];
    }

    /// `w = ln u` rises by at most `ln(1 + dw)` for a Newton step `dw > 0`:
    /// the step `u <- u (1 + dw)` in the velocity, which the force balance
    /// `m u w' = m u'` holds linearly (as [`crate::log_model::LogBlock`]).
    fn newton_update(&self, x: &mut [f64], dx: &[f64]) {
        for (j, (xi, d)) in x.iter_mut().zip(dx).enumerate() {
            if j == 1 && *d < 0.0 {
                *xi += (-*d).ln_1p();
            } else {
                *xi -= d;
            }
        }
    }

    fn has_implicit_form(&self) -> bool {
        true
    }

    /// The velocity equation as the force balance `m u dw/dt = s - F(n,
    /// u)` (`rho_w = m u`, `g_w = s - F`), the others with `rho = 1`: while
    /// the block sticks `s - F` is resolved to its rounding, which `dw/dt
    /// = (s - F) / (m u)` would multiply by `1 / (m u)`.
    fn implicit_rhs<D: Scalar>(&self, x: &[D], p: &[D], rho: &mut [D], g: &mut [D]) {
        let at = |q: AdhesiveParam| p[q as usize];
        let (s, w, n) = (x[0], x[1], x[2]);
        let u = w.exp();
        rho.fill(D::from(1.0));
        g[0] = at(AdhesiveParam::Kappa) * (at(AdhesiveParam::Nu) - u);
        g[1] = s - force(u, n, at(AdhesiveParam::Fv), at(AdhesiveParam::Alpha));
        g[2] = bond_rate(u, n, at(AdhesiveParam::R));
        rho[1] = at(AdhesiveParam::M) * u;
    }
}

/// What the analyses need of either block beyond its vector field: steady
/// sliding as its state, the slip velocity and the bond fraction of a state.
pub trait AdhesiveModel: VectorField + Copy + Default {
    /// Which model this is.
    const KIND: ModelKind;
    /// Steady sliding at `p.nu` as this block's state.
    fn steady(&self, p: &AdhesiveParams) -> Vec<f64>;
    /// The slip velocity `u` of a state (infinite outside the model's domain).
    fn velocity(&self, p: &AdhesiveParams, x: &[f64]) -> f64;
    /// The bond fraction `n` of a state (its last entry).
    fn bonds(&self, x: &[f64]) -> f64 {
        x[self.dim() - 1]
    }
}

impl AdhesiveModel for AdhesiveBlock {
    const KIND: ModelKind = ModelKind::QuasiStatic;
    fn steady(&self, p: &AdhesiveParams) -> Vec<f64> {
        steady_state(p)
    }
    fn velocity(&self, p: &AdhesiveParams, x: &[f64]) -> f64 {
        velocity_of(p, x)
    }
}

impl AdhesiveModel for InertialAdhesiveBlock {
    const KIND: ModelKind = ModelKind::Inertial;
    /// `(F_ss(nu), ln nu, n_ss(nu))`.
    fn steady(&self, p: &AdhesiveParams) -> Vec<f64> {
        vec![steady_friction(p.nu, p), p.nu.ln(), steady_bonds(p.nu, p.r)]
    }
    fn velocity(&self, _: &AdhesiveParams, x: &[f64]) -> f64 {
        x[1].exp()
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

/// The quasi-static reduction's error at a state of the quasi-static
/// block with slip velocity `u` and bond fraction `n`: restoring the
/// dropped inertia force `m du/dt` shifts the balance `s = F(n, u)` by it,
/// which the force's slope in `ln u` at fixed bonds absorbs with a change
/// of `ln u` by
///
/// ```text
/// chi = m |du/dt| / (u F_u),    F_u du/dt = kappa (nu - u) - g(1/u) dn/dt
/// ```
///
/// (the balance differentiated along the flow, `g = dF/dn`, `u F_u = n (1
/// - z g(z)) + f_v (1 - alpha) u^(1 - alpha)`); 0 at steady sliding. Its
/// largest over an orbit is the adhesive block's counterpart of the
/// rate-and-state `orbit_inertia::state_imbalance`.
pub fn state_imbalance(p: &AdhesiveParams, u: f64, n: f64) -> f64 {
    let beta = 1.0 - p.alpha;
    let slope = n * one_minus_z_scaled_e1(u.recip()) + p.f_v * beta * (beta * u.ln()).exp();
    let du_dt = (p.kappa * (p.nu - u) - scaled_e1(u.recip()) * bond_rate(u, n, p.r)) * u / slope;
    p.m * du_dt.abs() / slope
}

/// The slope of the force at fixed bonds, `F_u = dF/du`, and the bonds'
/// relaxation rate `lambda_n = 1/r + 1/T` at steady sliding at `u`.
fn steady_slopes<D: Scalar>(u: D, law: &SteadyLaw<D>) -> (D, D) {
    let n = steady_bonds(u, law.r);
    let beta = -law.alpha + 1.0;
    let f_u = (n * one_minus_z_scaled_e1(u.recip()) + law.f_v * beta * (beta * u.ln()).exp()) / u;
    (f_u, law.r.recip() + lifetime(u).recip())
}

/// The slope `dF_ss / du` of steady friction at `u`, the parameters on any
/// scalar (exact, by a dual number over it).
pub fn steady_force_slope<D: Scalar>(u: D, law: &SteadyLaw<D>) -> D {
    steady_force(Dual::new(u, D::from(1.0)), &law.lifted()).eps
}

/// The slope `dF_ss / du` of steady friction at `u` (exact, by a dual number).
pub fn steady_slope(u: f64, p: &AdhesiveParams) -> f64 {
    steady_force_slope(u, &SteadyLaw::of(p))
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
    critical_stiffness_of(p, ModelKind::QuasiStatic)
}

/// The inertia ratio `chi = m lambda_n / F_u` at steady sliding: the
/// inertial time `m / F_u` over the bonds' relaxation time `1 / lambda_n`
/// (for the rate-and-state block the same ratio is `m nu^2 / mu_v`).
pub fn inertia_ratio(p: &AdhesiveParams) -> f64 {
    let (f_u, lambda) = steady_slopes(p.nu, &SteadyLaw::of(p));
    p.m * lambda / f_u
}

/// The characteristic polynomial of the inertial block linearized at
/// steady sliding, `[c0, c1, c2, c3]` of `c3 l^3 + c2 l^2 + c1 l + c0`:
/// in `(ds, du, dn)` the linearization is `ds' = -kappa du`, `m du' = ds -
/// F_u du - g dn`, `dn' = N_u du - lambda_n dn` (`g = g(1/nu) = F_n`, `N_u`
/// the slope of the bond rate in `u`), and with `F_u lambda_n + g N_u =
/// lambda_n dF_ss/du` (steady bonds `dn_ss/du = N_u / lambda_n`)
///
/// ```text
/// m l^3 + (F_u + m lambda_n) l^2 + (lambda_n dF_ss/du + kappa) l + kappa lambda_n
/// ```
///
/// (`m = 0`: the quasi-static block's `F_u` times its `l^2 - trace l + det`).
pub fn characteristic_polynomial(p: &AdhesiveParams) -> [f64; 4] {
    let (f_u, lambda) = steady_slopes(p.nu, &SteadyLaw::of(p));
    [
        p.kappa * lambda,
        lambda * steady_slope(p.nu, p) + p.kappa,
        f_u + p.m * lambda,
        p.m,
    ]
}

/// The critical stiffness of the block of `kind`, `(kappa_c, Omega_c)`.
/// Quasi-static: [`critical_stiffness`]. Inertial: the Hopf condition of the
/// cubic [`characteristic_polynomial`], `c2 c1 = c3 c0` with `Omega^2 = c1 /
/// c3 = c0 / c2`, is linear in `kappa`:
///
/// ```text
/// kappa_c = -lambda_n dF_ss/du (1 + chi),   chi = m lambda_n / F_u,
/// Omega_c^2 = kappa_c lambda_n / (F_u + m lambda_n)
/// ```
///
/// the quasi-static `kappa_c` raised by `1 + chi`, at the quasi-static
/// frequency (the limit `m -> 0` is the quasi-static closed form).
pub fn critical_stiffness_of(p: &AdhesiveParams, kind: ModelKind) -> (f64, f64) {
    critical_stiffness_at(p.nu, &SteadyLaw::of(p), kind)
}

/// [`critical_stiffness_of`] at `nu` with the parameters on any scalar.
pub fn critical_stiffness_at<D: Scalar>(nu: D, law: &SteadyLaw<D>, kind: ModelKind) -> (D, D) {
    let (f_u, lambda) = steady_slopes(nu, law);
    let kappa_0 = -lambda * steady_force_slope(nu, law);
    let omega = (kappa_0 * lambda / f_u).sqrt();
    match kind {
        ModelKind::QuasiStatic => (kappa_0, omega),
        ModelKind::Inertial => (kappa_0 * (law.m * lambda / f_u + 1.0), omega),
    }
}

/// The model at one velocity: quasi-static without mass or where `chi`
/// ([`inertia_ratio`]) is below `threshold` (inertia then raises `kappa_c`
/// by less than the threshold, relative), else inertial; a NaN `chi`
/// (outside double precision) counts as needing inertia. The rule of the
/// rate-and-state block ([`crate::analysis::model_choice`]), whose
/// exception (inertia where it changes the onset type) the commands add
/// (`jobs::onset_type_changes`).
pub fn model_for(p: &AdhesiveParams, threshold: f64) -> ModelKind {
    let chi = inertia_ratio(p);
    if p.m == 0.0 || chi < threshold {
        ModelKind::QuasiStatic
    } else {
        ModelKind::Inertial
    }
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
                let Ok(br) = continuation::illinois(
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

    #[test]
    fn the_inertial_jacobian_has_the_closed_form_characteristic_polynomial() {
        // det(l - J) = l^3 - tr l^2 + M2 l - det against c_i / c3, in the
        // variables (s, ln u, n) the engine differentiates.
        for m in [1e-9, 1e-6, 1e-3] {
            let mut p = gel();
            p.m = m;
            p.kappa = 0.02;
            let j = jacobian(
                &InertialAdhesiveBlock,
                &InertialAdhesiveBlock.steady(&p),
                &p.to_vec(),
            );
            let tr = j[(0, 0)] + j[(1, 1)] + j[(2, 2)];
            let minor = |a: usize, b: usize| j[(a, a)] * j[(b, b)] - j[(a, b)] * j[(b, a)];
            let m2 = minor(0, 1) + minor(0, 2) + minor(1, 2);
            let det = j.determinant();
            let [c0, c1, c2, c3] = characteristic_polynomial(&p);
            for (engine, closed) in [(-tr, c2 / c3), (m2, c1 / c3), (-det, c0 / c3)] {
                assert!(
                    (engine / closed - 1.0).abs() < 1e-9,
                    "m = {m}: {engine} vs {closed}"
                );
            }
            // The Hopf condition c2 c1 = c3 c0 at the closed-form kappa_c.
            let (kappa_c, omega) = critical_stiffness_of(&p, ModelKind::Inertial);
            p.kappa = kappa_c;
            let [c0, c1, c2, c3] = characteristic_polynomial(&p);
            assert!((c2 * c1 / (c3 * c0) - 1.0).abs() < 1e-12, "m = {m}");
            assert!((c1 / c3 / (omega * omega) - 1.0).abs() < 1e-12, "m = {m}");
        }
    }

    #[test]
    fn the_inertial_implicit_form_is_the_force_balance() {
        let mut p = gel();
        p.m = 1e-4;
        let x = [0.03, (1e-20f64).ln(), 0.5];
        let (mut rho, mut g, mut f) = ([0.0; 3], [0.0; 3], [0.0; 3]);
        InertialAdhesiveBlock.implicit_rhs(&x, &p.to_vec(), &mut rho, &mut g);
        InertialAdhesiveBlock.rhs(&x, &p.to_vec(), &mut f);
        let gap = 0.03 - force(1e-20, 0.5, p.f_v, p.alpha);
        assert!((rho[1] / (p.m * 1e-20) - 1.0).abs() < 1e-13, "{rho:?}");
        assert!((g[1] - gap).abs() < 1e-16, "{} vs {gap}", g[1]);
        assert_eq!([rho[0], rho[2]], [1.0, 1.0]);
        assert_eq!([g[0], g[2]], [f[0], f[2]]);
        assert!((f[1] / (gap / (p.m * 1e-20)) - 1.0).abs() < 1e-13);
        // Steady sliding is an equilibrium of the inertial block.
        let f0 = eval(
            &InertialAdhesiveBlock,
            &InertialAdhesiveBlock.steady(&p),
            &p.to_vec(),
        );
        assert!(f0.iter().all(|v| v.abs() < 1e-9), "{f0}");
    }
}
