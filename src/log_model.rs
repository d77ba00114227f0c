//! The driven block in logarithmic variables, for periodic orbits.
//!
//! Stick-slip cycles span many decades of slip velocity and age within one
//! period; in `w = ln v` and `phi = ln theta` they stay smooth. With docs/model.md's
//! equations:
//!
//! ```text
//! ds/dt   = kappa (nu - e^w)
//! dw/dt   = (s - mu(e^w, e^phi) - eta_d e^w) / (m e^w)          (inertial)
//! dphi/dt = e^-phi - e^w           (ageing law; slip law: -e^w (w + phi))
//! ```
//!
//! and quasi-statically `(s, phi)` with `w` the root of `s = mu(e^w, e^phi)
//! + eta_d e^w` on a rising branch (`w = (s - mu0 - ageing(e^phi)) / A` without
//! `mu_vv` and `mu_vphi`).
//!
//! The state is measured from an origin `(s_o, w_o, phi_o)`
//! ([`LogBlock::origin`]): `x = (s - s_o, w - w_o, phi - phi_o)` (quasi-static
//! `(s - s_o, phi - phi_o)`). With the origin at steady sliding
//! ([`LogBlock::centered`]) a small cycle is a small state, and the right-hand
//! side is evaluated without cancelling large terms:
//!
//! ```text
//! ds/dt   = kappa ((nu - e^w_o) - e^w_o expm1(x_w))
//! dw/dt   = (x_s + c - A_s x_w - state_change(w_o, phi_o, x_phi) - eta_d e^w_o expm1(x_w)) / (m e^w)
//! dphi/dt = (e^-phi_o - e^w_o) + e^-phi_o expm1(-x_phi) - e^w_o expm1(x_w)
//!           (slip law: -(e^w_o + e^w_o expm1(x_w)) ((w_o + phi_o) + x_w + x_phi))
//! c       = s_o - mu(e^w_o, e^phi_o) - eta_d e^w_o
//! A_s     = A + mu_vv (2 w_o + x_w) + mu_vphi (phi_o + x_phi)   (the secant slope in ln v)
//! state_change = ageing_change(phi_o, x_phi) + mu_vphi w_o x_phi
//! ```
//!
//! ([`FrictionLaw::state_change`], [`FrictionLaw::rate_coefficient`]: the
//! change of `mu` from the origin, `mu_vv x_w (2 w_o + x_w) + mu_vphi
//! (phi_o x_w + w_o x_phi + x_phi x_w)` with the ageing term's, without
//! cancellation; `A_s = A` without `mu_vv` and `mu_vphi`). Quasi-statically
//! `x_w` solves `A_s x_w + eta_d e^w_o expm1(x_w) = x_s + c - state_change`,
//! a quadratic in `x_w` without damping
//! ([`FrictionLaw::ln_velocity_change`]; `x_w = (x_s + c -
//! ageing_change(phi_o, x_phi)) / A` without the corrections); where it
//! has no root on the rising branch the field is infinite (the state left
//! the model's domain). `c` and the
//! bracketed constants vanish at steady sliding; near onset a cycle of
//! amplitude `a` is then resolved relative to `a`, not to `mu0` and `ln nu`,
//! which matters because the amplitude at fixed stiffness is
//! ill-conditioned there (a relative error `delta` in the right-hand side
//! moves `Delta_s` by about `delta / (2 (kappa_c - kappa) / kappa_c)`).
//! Orbits are reported back in docs/model.md's variables (`s = s_o + x_s`,
//! `v = e^(w_o + x_w)`, `theta = e^(phi_o + x_phi)`); the period and the
//! multipliers do not depend on the choice of variables.

use crate::friction::FrictionLaw;
use crate::model::ModelKind;
use crate::params::{friction_from, Param, Params, StateLaw, N_PARAMS};
use continuation::{Scalar, VectorField};

/// The inertial or quasi-static block in `(s, ln v, ln theta)` / `(s, ln theta)`
/// measured from an origin ([`LogBlock::origin`]).
#[derive(Clone, Copy, Debug)]
pub struct LogBlock {
    pub kind: ModelKind,
    /// Cutoff ageing form.
    pub cutoff: bool,
    /// The evolution law of `theta`.
    pub state_law: StateLaw,
    /// The point `(s_o, ln v_o, ln theta_o)` the state is measured from.
    origin: [f64; 3],
    /// `(e^w_o, e^phi_o, e^-phi_o)` of the origin, which every evaluation
    /// of the right-hand side uses: computed once.
    exps: [f64; 3],
}

impl VectorField for LogBlock {
    fn dim(&self) -> usize {
        match self.kind {
            ModelKind::Inertial => 3,
            ModelKind::QuasiStatic => 2,
        }
    }
    fn n_params(&self) -> usize {
        N_PARAMS
    }
    fn param_name(&self, k: usize) -> String {
        Param::ALL[k].name().into()
    }
    /// The spring force (measured from `s_o`: the same differences and
    /// amplitude, without rounding against `s_o`) and the logarithm of the
    /// slip velocity, whose extremes a cycle reports (`s_min`, `s_max`,
    /// `v_min`, `v_max`).
    fn n_observables(&self) -> usize {
        2
    }

    fn observable(&self, k: usize, x: &[f64], p: &[f64]) -> f64 {
        match k {
            0 => x[0],
            _ => self.ln_velocity(x, p),
        }
    }

    fn rhs<D: Scalar>(&self, x: &[D], p: &[D], out: &mut [D]) {
        let mut rho = [D::from(1.0); 3];
        self.implicit_rhs(x, p, &mut rho, out);
        if self.kind == ModelKind::Inertial {
            out[1] /= rho[1];
        }
    }

    /// The inertial block's `w = ln v` rises by at most `ln(1 + dw)` for a
    /// Newton step `dw > 0`: the step `v <- v (1 + dw)` in the velocity,
    /// which the force balance `m v w' = m v'` holds linearly (a step
    /// linearized in `e^w` from below overshoots by `e^dw - 1 - dw`).
    fn newton_update(&self, x: &mut [f64], dx: &[f64]) {
        for (j, (xi, d)) in x.iter_mut().zip(dx).enumerate() {
            if self.kind == ModelKind::Inertial && j == 1 && *d < 0.0 {
                *xi += (-*d).ln_1p();
            } else {
                *xi -= d;
            }
        }
    }

    /// The inertial block is collocated in its implicit form (see
    /// [`LogBlock::implicit_rhs`]).
    fn has_implicit_form(&self) -> bool {
        self.kind == ModelKind::Inertial
    }

    /// The inertial block's velocity equation as the force balance
    /// `m e^w dw/dt = s - mu(e^w, e^phi)` (module docs; `rho_w = m v`,
    /// `g_w = s - mu`), the other equations with `rho = 1`. While the block
    /// sticks (`v` down to 1e-40 and far below, beyond the range of `f64`
    /// where `m v` underflows to 0) `s - mu` is resolved to its rounding,
    /// which `dw/dt = (s - mu) / (m v)` would multiply by `1 / (m v)`.
    fn implicit_rhs<D: Scalar>(&self, x: &[D], p: &[D], rho: &mut [D], g: &mut [D]) {
        let law = friction_from(self.cutoff, p);
        let (kappa, nu) = (p[Param::Kappa as usize], p[Param::Nu as usize]);
        let [_, w_o, phi_o] = self.origin;
        let [ew_o, _, e_minus_phi_o] = self.exps;
        let (x_s, x_phi) = (x[0], x[self.dim() - 1]);
        // s - mu(v, theta) = gap0 - A_s x_w, and quasi-statically 0.
        let gap0 = self.offset(&law) - law.state_change(D::from(w_o), D::from(phi_o), x_phi) + x_s;
        let ln_theta = x_phi + phi_o;
        let x_w = match self.kind {
            ModelKind::Inertial => x[1],
            ModelKind::QuasiStatic => match law.ln_velocity_change(D::from(w_o), ln_theta, gap0) {
                Some(x_w) => x_w,
                None => {
                    rho.fill(D::from(1.0));
                    g.fill(D::from(f64::INFINITY));
                    return;
                }
            },
        };
        // v - e^w_o = e^w_o expm1(x_w)
        let dv = x_w.exp_m1() * ew_o;
        rho.fill(D::from(1.0));
        g[0] = kappa * ((nu - ew_o) - dv);
        g[self.dim() - 1] =
            self.state_law
                .log_rate((w_o, phi_o), (ew_o, e_minus_phi_o), x_w, x_phi, dv);
        if self.kind == ModelKind::Inertial {
            // v itself from its logarithm: relatively exact also at 1e-13.
            let v = (x_w + w_o).exp();
            g[1] = gap0 - law.rate_coefficient(x_w + 2.0 * w_o, ln_theta) * x_w - law.damping(dv);
            rho[1] = p[Param::M as usize] * v;
        }
    }
}

impl LogBlock {
    /// The block of `kind` with the ageing form of `params`, in the log
    /// variables themselves (origin 0), as the simulations integrate it.
    pub fn new(kind: ModelKind, params: &Params) -> Self {
        LogBlock::at(kind, params.theta_c.is_some(), params.state_law, [0.0; 3])
    }

    /// The block of `kind` (`cutoff` ageing form, `state_law`) measured from
    /// `origin = (s_o, ln v_o, ln theta_o)`.
    pub fn at(kind: ModelKind, cutoff: bool, state_law: StateLaw, origin: [f64; 3]) -> Self {
        let [_, w_o, phi_o] = origin;
        LogBlock {
            kind,
            cutoff,
            state_law,
            origin,
            exps: [w_o.exp(), phi_o.exp(), (-phi_o).exp()],
        }
    }

    /// The point `(s_o, ln v_o, ln theta_o)` the state is measured from.
    pub fn origin(&self) -> [f64; 3] {
        self.origin
    }

    /// The block measured from steady sliding of `params`,
    /// `(mu(nu, 1/nu) + eta_d nu, ln nu, -ln nu)`: the variables of the cycle branches,
    /// where a cycle near onset is a small oscillation about that point.
    pub fn centered(kind: ModelKind, params: &Params) -> Self {
        let law = friction_from(params.theta_c.is_some(), &params.to_vec());
        let ln_nu = params.nu.ln();
        LogBlock::at(
            kind,
            params.theta_c.is_some(),
            params.state_law,
            [law.steady_force(params.nu), ln_nu, -ln_nu],
        )
    }

    /// `c = s_o - mu0 - (A + mu_vv w_o + mu_vphi phi_o) w_o -
    /// ageing(e^phi_o) - eta_d e^w_o`: the force gap `s - mu - eta_d v` at
    /// the origin (zero at steady sliding, up to rounding).
    fn offset<D: Scalar>(&self, law: &FrictionLaw<D>) -> D {
        let [s_o, w_o, phi_o] = self.origin;
        let [ew_o, ephi_o, _] = self.exps;
        let damping = law.damping(D::from(ew_o));
        let (w_o, phi_o) = (D::from(w_o), D::from(phi_o));
        -law.mu0 - law.rate_coefficient(w_o, phi_o) * w_o - law.ageing_term(D::from(ephi_o)) + s_o
            - damping
    }

    /// A state in docs/model.md's variables `(s, v, theta)` as this model's state.
    pub fn from_model(&self, s: f64, v: f64, theta: f64) -> Vec<f64> {
        let [s_o, w_o, phi_o] = self.origin;
        match self.kind {
            ModelKind::Inertial => vec![s - s_o, v.ln() - w_o, theta.ln() - phi_o],
            ModelKind::QuasiStatic => vec![s - s_o, theta.ln() - phi_o],
        }
    }

    /// `ln v` of this model's state: `w_o` plus the state's second entry when
    /// inertial, `w_o + x_w` with `x_w` the root of `A_s x_w = x_s + c -
    /// state_change(w_o, phi_o, x_phi)` when quasi-static (module docs;
    /// `w_o + (x_s + c - ageing_change(phi_o, x_phi)) / A` without `mu_vv`
    /// and `mu_vphi`), infinite outside the law's domain.
    pub fn ln_velocity(&self, x: &[f64], p: &[f64]) -> f64 {
        let [_, w_o, phi_o] = self.origin;
        match self.kind {
            ModelKind::Inertial => w_o + x[1],
            ModelKind::QuasiStatic => {
                let law = friction_from(self.cutoff, p);
                let gap = x[0] + self.offset(&law) - law.state_change(w_o, phi_o, x[1]);
                law.ln_velocity_change(w_o, phi_o + x[1], gap)
                    .map_or(f64::INFINITY, |x_w| w_o + x_w)
            }
        }
    }

    /// The spring force `s = s_o + x_s` of this model's state.
    pub fn spring_force(&self, x: &[f64]) -> f64 {
        self.origin[0] + x[0]
    }

    /// This model's state as `(s, v, theta)` (the slaved velocity when quasi-static).
    pub fn to_model(&self, x: &[f64], p: &[f64]) -> [f64; 3] {
        let phi = self.origin[2] + x[self.dim() - 1];
        [
            self.spring_force(x),
            self.ln_velocity(x, p).exp(),
            phi.exp(),
        ]
    }

    /// The state `x` of `other` (the same block measured from another
    /// origin) in this block's variables.
    pub fn from_other(&self, other: &LogBlock, x: &[f64], p: &[f64]) -> Vec<f64> {
        let [s, v, theta] = other.to_model(x, p);
        self.from_model(s, v, theta)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{DrivenBlock, ModelKind};
    use crate::params::Params;
    use continuation::system::eval;

    fn ln2_params() -> Params {
        Params {
            kappa: 0.02,
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

    /// With both corrections in `ln v` (docs/model.md): `mu_vv < 0`, so that
    /// the quasi-static law has a velocity at `(s, theta) = (0.55, 2.3)`.
    fn corrected_params() -> Params {
        Params {
            mu_vv: -1e-3,
            mu_vphi: -5e-4,
            ..ln2_params()
        }
    }

    #[test]
    fn log_model_is_the_model_in_other_variables() {
        // x_log' = (dx_log/dx) x': w' = v'/v, phi' = theta'/theta, from either
        // origin, for both ageing forms.
        let ln2 = ln2_params();
        let cutoff = Params {
            mu2: 0.0,
            theta_c: Some(0.4),
            ..ln2
        };
        for p in [ln2, cutoff, corrected_params()] {
            for kind in [ModelKind::Inertial, ModelKind::QuasiStatic] {
                for log in [LogBlock::new(kind, &p), LogBlock::centered(kind, &p)] {
                    let lin = DrivenBlock::new(kind, &p);
                    let (s, theta) = (0.55, 2.3);
                    // The quasi-static velocity is slaved to s and theta.
                    let v = match kind {
                        ModelKind::Inertial => 0.7,
                        ModelKind::QuasiStatic => friction_from(p.theta_c.is_some(), &p.to_vec())
                            .slip_velocity(s, theta)
                            .unwrap(),
                    };
                    let xl = log.from_model(s, v, theta);
                    let fl = eval(&log, &xl, &p.to_vec());
                    let xm: Vec<f64> = match kind {
                        ModelKind::Inertial => vec![s, v, theta],
                        ModelKind::QuasiStatic => vec![s, theta],
                    };
                    let fm = eval(&lin, &xm, &p.to_vec());
                    let m = log.to_model(&xl, &p.to_vec());
                    match kind {
                        ModelKind::Inertial => {
                            assert!((fl[1] - fm[1] / v).abs() < 1e-12 * fl[1].abs().max(1.0));
                            assert!((fl[2] - fm[2] / theta).abs() < 1e-13);
                        }
                        ModelKind::QuasiStatic => {
                            assert!((fl[1] - fm[1] / theta).abs() < 1e-13)
                        }
                    }
                    assert!((fl[0] - fm[0]).abs() < 1e-15);
                    assert!((m[0] - s).abs() < 1e-15);
                    assert!((m[1] / v - 1.0).abs() < 1e-13);
                    assert!((m[2] / theta - 1.0).abs() < 1e-13);
                }
            }
        }
    }

    #[test]
    fn the_implicit_form_is_the_force_balance_and_a_rise_of_ln_v_a_step_in_v() {
        let p = ln2_params();
        let log = LogBlock::centered(ModelKind::Inertial, &p);
        let x = log.from_model(0.55, 1e-30, 2.3);
        let (mut rho, mut g, mut f) = ([0.0; 3], [0.0; 3], [0.0; 3]);
        log.implicit_rhs(&x, &p.to_vec(), &mut rho, &mut g);
        log.rhs(&x, &p.to_vec(), &mut f);
        // rho_w = m v, g_w = s - mu(v, theta), the others as they are.
        let law = friction_from(false, &p.to_vec());
        let gap = 0.55 - law.mu(1e-30, 2.3);
        assert!((rho[1] / (p.m * 1e-30) - 1.0).abs() < 1e-13, "{rho:?}");
        assert!((g[1] - gap).abs() < 1e-15, "{} vs {gap}", g[1]);
        assert_eq!([rho[0], rho[2]], [1.0, 1.0]);
        assert_eq!([g[0], g[2]], [f[0], f[2]]);
        // A Newton step dx (subtracted): ln v rises by ln(1 + 3), falls by 3.
        for (dw, rise) in [(-3.0, 4f64.ln()), (3.0, -3.0)] {
            let mut y = x.clone();
            log.newton_update(&mut y, &[1e-3, dw, -2e-3]);
            assert!(
                (y[1] - x[1] - rise).abs() < 1e-12,
                "{} vs {rise}",
                y[1] - x[1]
            );
            assert_eq!([y[0], y[2]], [x[0] - 1e-3, x[2] + 2e-3]);
        }
    }

    #[test]
    fn steady_sliding_is_the_origin_of_the_centered_block() {
        // The vector field vanishes there up to rounding, and a small
        // deviation changes it by a small amount, resolved relative to the
        // deviation: against the Jacobian at the origin for deviations of
        // 1e-12 (with the log variables themselves, nu - e^w and
        // e^-phi - e^w would lose all but 4 digits of it).
        for (p, kind) in [ln2_params(), corrected_params()]
            .into_iter()
            .flat_map(|p| [(p, ModelKind::Inertial), (p, ModelKind::QuasiStatic)])
        {
            let log = LogBlock::centered(kind, &p);
            let n = log.dim();
            let zero = vec![0.0; n];
            let f0 = eval(&log, &zero, &p.to_vec());
            assert!(f0.iter().all(|v| v.abs() < 1e-14), "{f0:?}");
            let jac = continuation::system::jacobian(&log, &zero, &p.to_vec());
            let dx: Vec<f64> = (0..n).map(|j| 1e-12 * (j as f64 + 1.0)).collect();
            let f = eval(&log, &dx, &p.to_vec());
            for i in 0..n {
                let lin: f64 = (0..n).map(|j| jac[(i, j)] * dx[j]).sum();
                let change = f[i] - f0[i];
                assert!(
                    (change - lin).abs() < 1e-9 * lin.abs(),
                    "{i}: {change} vs {lin}"
                );
            }
        }
    }
}
