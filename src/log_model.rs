//! The driven block in logarithmic variables, for periodic orbits.
//!
//! Stick-slip cycles span many decades of slip velocity and age within one
//! period; in `w = ln v` and `phi = ln theta` they stay smooth. With docs/model.md's
//! equations:
//!
//! ```text
//! ds/dt   = kappa (nu - e^w)
//! dw/dt   = (s - mu(e^w, e^phi)) / (m e^w)          (inertial)
//! dphi/dt = e^-phi - e^w
//! ```
//!
//! and quasi-statically `(s, phi)` with `w = (s - mu0 - ageing(e^phi)) / A`.
//! Orbits are reported back in docs/model.md's variables (`v = e^w`,
//! `theta = e^phi`); the spring force `s`, the period and the multipliers do
//! not depend on the choice of variables.

use crate::model::ModelKind;
use crate::params::{friction_from, Param, Params, N_PARAMS};
use continuation::{Scalar, VectorField};

/// The inertial or quasi-static block in `(s, ln v, ln theta)` / `(s, ln theta)`.
#[derive(Clone, Copy, Debug)]
pub struct LogBlock {
    pub kind: ModelKind,
    /// Cutoff ageing form.
    pub cutoff: bool,
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
    fn rhs<D: Scalar>(&self, x: &[D], p: &[D], out: &mut [D]) {
        crate::model::count_eval::<D>();
        let law = friction_from(self.cutoff, p);
        let (kappa, nu) = (p[Param::Kappa as usize], p[Param::Nu as usize]);
        match self.kind {
            ModelKind::Inertial => {
                let (s, w, phi) = (x[0], x[1], x[2]);
                let v = w.exp();
                let mu = law.mu0 + law.a * w + law.ageing_term(phi.exp());
                out[0] = kappa * (nu - v);
                out[1] = (s - mu) / (p[Param::M as usize] * v);
                out[2] = (-phi).exp() - v;
            }
            ModelKind::QuasiStatic => {
                let (s, phi) = (x[0], x[1]);
                let w = (s - law.mu0 - law.ageing_term(phi.exp())) / law.a;
                let v = w.exp();
                out[0] = kappa * (nu - v);
                out[1] = (-phi).exp() - v;
            }
        }
    }
}

impl LogBlock {
    /// The block of `kind` with the ageing form of `params`.
    pub fn new(kind: ModelKind, params: &Params) -> Self {
        LogBlock {
            kind,
            cutoff: params.theta_c.is_some(),
        }
    }

    /// A state in docs/model.md's variables `(s, v, theta)` as this model's state.
    pub fn from_model(&self, s: f64, v: f64, theta: f64) -> Vec<f64> {
        match self.kind {
            ModelKind::Inertial => vec![s, v.ln(), theta.ln()],
            ModelKind::QuasiStatic => vec![s, theta.ln()],
        }
    }

    /// `ln v` of this model's state: the state's second entry when inertial,
    /// `(s - mu0 - ageing(theta)) / A` when quasi-static.
    pub fn ln_velocity(&self, x: &[f64], p: &[f64]) -> f64 {
        match self.kind {
            ModelKind::Inertial => x[1],
            ModelKind::QuasiStatic => {
                let law = friction_from(self.cutoff, p);
                (x[0] - law.mu0 - law.ageing_term(x[1].exp())) / law.a
            }
        }
    }

    /// This model's state as `(s, v, theta)` (the slaved velocity when quasi-static).
    pub fn to_model(&self, x: &[f64], p: &[f64]) -> [f64; 3] {
        match self.kind {
            ModelKind::Inertial => [x[0], x[1].exp(), x[2].exp()],
            ModelKind::QuasiStatic => {
                let law = friction_from(self.cutoff, p);
                let theta = x[1].exp();
                [x[0], law.slip_velocity(x[0], theta), theta]
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{DrivenBlock, ModelKind};
    use crate::params::Params;
    use continuation::system::eval;

    #[test]
    fn log_model_is_the_model_in_other_variables() {
        // x_log' = (dx_log/dx) x': w' = v'/v, phi' = theta'/theta.
        let p = Params {
            kappa: 0.02,
            nu: 3.0,
            m: 0.1,
            a: 0.01,
            b: 0.02,
            mu0: 0.6,
            mu2: 5e-4,
            theta_c: None,
        };
        for kind in [ModelKind::Inertial, ModelKind::QuasiStatic] {
            let log = LogBlock {
                kind,
                cutoff: false,
            };
            let lin = DrivenBlock::new(kind, &p);
            let (s, v, theta) = (0.55, 0.7, 2.3);
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
                ModelKind::QuasiStatic => assert!((fl[1] - fm[1] / theta).abs() < 1e-13),
            }
            assert!((fl[0] - fm[0]).abs() < 1e-15);
            assert!((m[2] - theta).abs() < 1e-13);
        }
    }
}
