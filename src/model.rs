//! The driven block of docs/model.md (seed §II.D.2, eqs. RR4, C1–C2), dimensionless.
//!
//! Inertial model, state `(s, v, theta)`:
//! ```text
//! ds/dt     = kappa (nu - v)
//! m dv/dt   = s - mu(v, theta) - eta_d v
//! dtheta/dt = 1 - v theta          (ageing law; slip law: -v theta ln(v theta))
//! ```
//! with the radiation damping `eta_d v` (docs/model.md, "Radiation
//! damping"; 0 by default). Quasi-static model (`m = 0`), state `(s,
//! theta)`, with `v` slaved to the force balance, `s = mu(v, theta) +
//! eta_d v` on its rising branch in `ln v`
//! ([`crate::friction::FrictionLaw::slip_velocity`]; `v = exp((s - mu0 -
//! ageing(theta)) / A)` without `mu_vv` and `mu_vphi`). Where the law gives
//! no velocity the field is infinite: the state has left the model's
//! domain, which the engine reports as such.
//!
//! Both take the parameter vector of [`crate::params::Param`].

use crate::params::{friction_from, Param, Params, StateLaw, N_PARAMS};
use continuation::{Scalar, VectorField};

/// Which driven-block model an analysis uses (JSON and CSV: its [`name`](ModelKind::name)).
/// The default only fills the record a CSV header is named from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ModelKind {
    /// State `(s, v, theta)` with the inertia `m`.
    #[default]
    Inertial,
    /// State `(s, theta)`, inertia dropped.
    QuasiStatic,
}

impl ModelKind {
    /// `inertial` or `quasi-static` (the name used in JSON and on the command line).
    pub fn name(self) -> &'static str {
        match self {
            ModelKind::Inertial => "inertial",
            ModelKind::QuasiStatic => "quasi-static",
        }
    }
}

/// The inertial driven block, state `(s, v, theta)`.
#[derive(Clone, Copy, Debug)]
pub struct InertialBlock {
    /// Use the cutoff ageing form `B ln(1 + theta/theta_c)`.
    pub cutoff: bool,
    /// The evolution law of `theta`.
    pub state_law: StateLaw,
}

impl VectorField for InertialBlock {
    fn dim(&self) -> usize {
        3
    }
    fn n_params(&self) -> usize {
        N_PARAMS
    }
    fn param_name(&self, k: usize) -> String {
        Param::ALL[k].name().into()
    }
    fn rhs<D: Scalar>(&self, x: &[D], p: &[D], out: &mut [D]) {
        let law = friction_from(self.cutoff, p);
        let (s, v, theta) = (x[0], x[1], x[2]);
        let (kappa, nu, m) = (
            p[Param::Kappa as usize],
            p[Param::Nu as usize],
            p[Param::M as usize],
        );
        out[0] = kappa * (nu - v);
        out[1] = (s - law.mu(v, theta) - law.damping(v)) / m;
        out[2] = self.state_law.rate(v, theta);
    }
}

/// The quasi-static driven block, state `(s, theta)`.
#[derive(Clone, Copy, Debug)]
pub struct QuasiStaticBlock {
    /// Use the cutoff ageing form `B ln(1 + theta/theta_c)`.
    pub cutoff: bool,
    /// The evolution law of `theta`.
    pub state_law: StateLaw,
}

impl VectorField for QuasiStaticBlock {
    fn dim(&self) -> usize {
        2
    }
    fn n_params(&self) -> usize {
        N_PARAMS
    }
    fn param_name(&self, k: usize) -> String {
        Param::ALL[k].name().into()
    }
    fn rhs<D: Scalar>(&self, x: &[D], p: &[D], out: &mut [D]) {
        let law = friction_from(self.cutoff, p);
        let (s, theta) = (x[0], x[1]);
        let Ok(v) = law.slip_velocity(s, theta) else {
            out.fill(D::from(f64::INFINITY));
            return;
        };
        let (kappa, nu) = (p[Param::Kappa as usize], p[Param::Nu as usize]);
        out[0] = kappa * (nu - v);
        out[1] = self.state_law.rate(v, theta);
    }
}

/// Either driven-block model, chosen at run time.
#[derive(Clone, Copy, Debug)]
pub enum DrivenBlock {
    Inertial(InertialBlock),
    QuasiStatic(QuasiStaticBlock),
}

impl DrivenBlock {
    /// The model of the given kind for the ageing form of `params`.
    pub fn new(kind: ModelKind, params: &Params) -> Self {
        let (cutoff, state_law) = (params.theta_c.is_some(), params.state_law);
        match kind {
            ModelKind::Inertial => DrivenBlock::Inertial(InertialBlock { cutoff, state_law }),
            ModelKind::QuasiStatic => {
                DrivenBlock::QuasiStatic(QuasiStaticBlock { cutoff, state_law })
            }
        }
    }

    /// Which model this is.
    pub fn kind(&self) -> ModelKind {
        match self {
            DrivenBlock::Inertial(_) => ModelKind::Inertial,
            DrivenBlock::QuasiStatic(_) => ModelKind::QuasiStatic,
        }
    }
}

impl VectorField for DrivenBlock {
    fn dim(&self) -> usize {
        match self {
            DrivenBlock::Inertial(b) => b.dim(),
            DrivenBlock::QuasiStatic(b) => b.dim(),
        }
    }
    fn n_params(&self) -> usize {
        N_PARAMS
    }
    fn param_name(&self, k: usize) -> String {
        Param::ALL[k].name().into()
    }
    fn rhs<D: Scalar>(&self, x: &[D], p: &[D], out: &mut [D]) {
        match self {
            DrivenBlock::Inertial(b) => b.rhs(x, p, out),
            DrivenBlock::QuasiStatic(b) => b.rhs(x, p, out),
        }
    }
}

/// Steady sliding (seed eq. RR5): `v = nu`, `theta = 1/nu`, `s = mu(nu,
/// 1/nu) + eta_d nu`, as the state vector of the given model.
pub fn steady_state(kind: ModelKind, params: &Params) -> Vec<f64> {
    let nu = params.nu;
    let s = params.friction().steady_force(nu);
    match kind {
        ModelKind::Inertial => vec![s, nu, 1.0 / nu],
        ModelKind::QuasiStatic => vec![s, 1.0 / nu],
    }
}

/// Names of the state variables of a model, in order.
pub fn state_names(kind: ModelKind) -> &'static [&'static str] {
    match kind {
        ModelKind::Inertial => &["s", "v", "theta"],
        ModelKind::QuasiStatic => &["s", "theta"],
    }
}

/// The state of either model written as `(s, v, theta)`: in the quasi-static
/// model `v` is the slaved velocity (of a state where the field is finite,
/// as every state an analysis reports; infinite outside the law's domain).
pub fn full_state(kind: ModelKind, params: &Params, x: &[f64]) -> [f64; 3] {
    match kind {
        ModelKind::Inertial => [x[0], x[1], x[2]],
        ModelKind::QuasiStatic => {
            let v = params.friction().slip_velocity(x[0], x[1]);
            [x[0], v.unwrap_or(f64::INFINITY), x[1]]
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use continuation::system::{eval, jacobian};

    fn params() -> Params {
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

    #[test]
    fn steady_state_is_an_equilibrium_of_both_models() {
        for p in [
            params(),
            Params {
                eta_d: 2e-3,
                ..params()
            },
        ] {
            steady_state_is_an_equilibrium(&p);
        }
    }

    fn steady_state_is_an_equilibrium(p: &Params) {
        let p = *p;
        for (kind, f) in [
            (
                ModelKind::Inertial,
                eval(
                    &InertialBlock {
                        cutoff: false,
                        state_law: Default::default(),
                    },
                    &steady_state(ModelKind::Inertial, &p),
                    &p.to_vec(),
                ),
            ),
            (
                ModelKind::QuasiStatic,
                eval(
                    &QuasiStaticBlock {
                        cutoff: false,
                        state_law: Default::default(),
                    },
                    &steady_state(ModelKind::QuasiStatic, &p),
                    &p.to_vec(),
                ),
            ),
        ] {
            assert!(f.amax() < 1e-14, "{kind:?}: {f}");
        }
    }

    #[test]
    fn inertial_jacobian_matches_the_linearisation_of_appendix_c() {
        // Linearising at steady sliding (seed eqs. C6–C7 in docs/model.md units):
        // J = [[0, -kappa, 0], [1/m, -mu_v/(m nu), -mu_phi nu/m], [0, -1/nu, -nu]],
        // with the slopes of docs/model.md: mu_v = A + (2 mu_vv - mu_vphi) ln nu,
        // mu_phi = B + (mu_vphi - 2 mu2) ln nu.
        let corrected = Params {
            mu_vv: 1e-3,
            mu_vphi: -5e-4,
            ..params()
        };
        // With radiation damping mu_v is mu_v + eta_d nu there.
        let damped = Params {
            eta_d: 2e-3,
            ..corrected
        };
        for p in [params(), corrected, damped] {
            check_inertial_jacobian(&p);
        }
    }

    fn check_inertial_jacobian(p: &Params) {
        let ln_nu = p.nu.ln();
        let mu_v = p.a + (2.0 * p.mu_vv - p.mu_vphi) * ln_nu + p.eta_d * p.nu;
        let mu_phi = p.b + (p.mu_vphi - 2.0 * p.mu2) * ln_nu;
        let j = jacobian(
            &InertialBlock {
                cutoff: false,
                state_law: Default::default(),
            },
            &steady_state(ModelKind::Inertial, p),
            &p.to_vec(),
        );
        let expect = [
            [0.0, -p.kappa, 0.0],
            [1.0 / p.m, -mu_v / (p.m * p.nu), -mu_phi * p.nu / p.m],
            [0.0, -1.0 / p.nu, -p.nu],
        ];
        for i in 0..3 {
            for k in 0..3 {
                let scale = expect[i][k].abs().max(1.0);
                assert!(
                    (j[(i, k)] - expect[i][k]).abs() < 1e-13 * scale,
                    "J[{i},{k}] = {} vs {}",
                    j[(i, k)],
                    expect[i][k]
                );
            }
        }
    }
}
