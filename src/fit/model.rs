//! What the fitted parameters predict for each kind of data, generic over
//! the scalar so that the least squares get exact Jacobians from dual
//! numbers.
//!
//! With `nu = V / V0`, steady sliding at age `theta = 1 / nu`
//! (docs/model.md, seed eq. RR5) and the friction law of the scene:
//!
//! ```text
//! mu_ss(V)   = mu(nu, 1/nu) + eta_d nu                                     (eq. RR5)
//! (K/W)_c(V) = kappa_c / D0,  kappa_c = (mu_phi - mu_v)(1 + m nu^2 / mu_v)  (eq. C11)
//! f_c(V)     = Omega_c V0 / (2 pi D0),  Omega_c = nu sqrt(mu_phi / mu_v - 1) (eq. C13)
//! ```
//!
//! with `m = M V0^2 / (W D0)` from the scene's mass and load, for the
//! cutoff law `theta_c = tau V0 / D0`, and `mu_v`, `mu_phi` the slopes of
//! the law at steady sliding (`mu_v = A + 2 mu_vv ln nu - mu_vphi ln nu +
//! eta_d nu` with the corrections and the damping, `A` without). The
//! corrections `mu_vv`, `mu_vphi` and the damping `eta_d` are the scene's,
//! held fixed ([`Fixed`]).

use crate::friction::{Ageing, FrictionLaw};
use crate::scene::Units;
use continuation::Scalar;
use serde::Serialize;

/// A parameter the fit can determine, in its physical unit.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum Name {
    #[serde(rename = "mu0")]
    Mu0,
    A,
    B,
    /// The memory length, µm.
    D0,
    #[serde(rename = "mu2")]
    Mu2,
    /// The short-age cutoff, s.
    #[serde(rename = "tau")]
    Tau,
}

impl Name {
    pub const ALL: [Name; 6] = [Name::Mu0, Name::A, Name::B, Name::D0, Name::Mu2, Name::Tau];

    /// The scene key.
    pub fn key(self) -> &'static str {
        match self {
            Name::Mu0 => "mu0",
            Name::A => "A",
            Name::B => "B",
            Name::D0 => "D0",
            Name::Mu2 => "mu2",
            Name::Tau => "tau",
        }
    }

    /// The unit of the value (`1`: dimensionless).
    pub fn unit(self) -> &'static str {
        match self {
            Name::D0 => "um",
            Name::Tau => "s",
            _ => "1",
        }
    }

    /// Whether the value is positive: fitted as its logarithm.
    pub fn positive(self) -> bool {
        !matches!(self, Name::Mu2)
    }
}

/// The values of the law's parameters (`mu2` or `tau` by the scene's form).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Values<T> {
    pub mu0: T,
    pub a: T,
    pub b: T,
    /// µm.
    pub d0_um: T,
    /// The ln² coefficient (`Ageing::Log`) or the cutoff `tau` in s (`Ageing::Cutoff`).
    pub ageing: AgeingValue<T>,
    /// The scene's terms the fit holds at their values.
    pub fixed: Fixed,
}

/// The terms of a scene the fit does not determine but models at the
/// scene's values (docs/model.md): the corrections `(ln v)^2` and `(ln
/// theta)(ln v)` of the logarithmic law, and the radiation damping `eta_d
/// = eta V0`. All zero by default.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Fixed {
    pub mu_vv: f64,
    pub mu_vphi: f64,
    pub eta_d: f64,
}

/// The ageing form's own parameter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AgeingValue<T> {
    Mu2(T),
    Tau(T),
}

impl<T: Scalar> Values<T> {
    /// The value of `name` (`None` where the form has no such parameter).
    pub fn get(&self, name: Name) -> Option<T> {
        match (name, self.ageing) {
            (Name::Mu0, _) => Some(self.mu0),
            (Name::A, _) => Some(self.a),
            (Name::B, _) => Some(self.b),
            (Name::D0, _) => Some(self.d0_um),
            (Name::Mu2, AgeingValue::Mu2(x)) | (Name::Tau, AgeingValue::Tau(x)) => Some(x),
            _ => None,
        }
    }

    /// `self` with `name` set to `x` (ignored where the form has no such parameter).
    pub fn set(&mut self, name: Name, x: T) {
        match (name, &mut self.ageing) {
            (Name::Mu0, _) => self.mu0 = x,
            (Name::A, _) => self.a = x,
            (Name::B, _) => self.b = x,
            (Name::D0, _) => self.d0_um = x,
            (Name::Mu2, AgeingValue::Mu2(v)) | (Name::Tau, AgeingValue::Tau(v)) => *v = x,
            _ => {}
        }
    }

    /// The parameters the law has, in [`Name::ALL`]'s order.
    pub fn names(&self) -> Vec<Name> {
        Name::ALL
            .into_iter()
            .filter(|n| self.get(*n).is_some())
            .collect()
    }

    /// The dimensionless friction law (docs/model.md) with the reference
    /// velocity `v0_um_s`, the fixed terms at their values.
    fn law(&self, v0_um_s: f64) -> FrictionLaw<T> {
        FrictionLaw {
            mu0: self.mu0,
            a: self.a,
            eta: T::from(self.fixed.eta_d),
            ageing: match self.ageing {
                AgeingValue::Mu2(mu2) => Ageing::Log {
                    b: self.b,
                    mu2,
                    mu_vv: T::from(self.fixed.mu_vv),
                    mu_vphi: T::from(self.fixed.mu_vphi),
                },
                AgeingValue::Tau(tau) => Ageing::Cutoff {
                    b: self.b,
                    theta_c: tau * v0_um_s / self.d0_um,
                },
            },
        }
    }
}

/// The rig the data were taken on: its reference velocity, mass and load
/// (the onset's inertia term `m nu^2 / A`).
#[derive(Clone, Copy, Debug)]
pub struct Rig {
    /// `V0`, µm/s.
    pub v0_um_s: f64,
    /// `M / W`, kg/N.
    pub mass_over_load: f64,
}

impl Rig {
    /// The rig of a scene's units.
    pub fn of(u: &Units) -> Rig {
        Rig {
            v0_um_s: u.v0 * 1e6,
            mass_over_load: u.mass / u.load,
        }
    }

    /// The steady force over the load at `V` µm/s, `mu_ss + eta_d nu`
    /// (seed eq. RR5, with the damping the spring also balances).
    pub fn steady<T: Scalar>(&self, p: &Values<T>, v_um_s: f64) -> T {
        p.law(self.v0_um_s)
            .steady_force(T::from(v_um_s / self.v0_um_s))
    }

    /// `(kappa_c, mu_phi, mu_v)` at `V` µm/s (eq. C11; `mu_v` with the
    /// damping's `eta_d nu`).
    fn onset<T: Scalar>(&self, p: &Values<T>, v_um_s: f64) -> (T, T, T) {
        let nu = v_um_s / self.v0_um_s;
        let (nu_t, theta) = (T::from(nu), T::from(1.0 / nu));
        let law = p.law(self.v0_um_s);
        let mu_phi = law.mu_phi(nu_t, theta);
        let mu_v = law.mu_v(nu_t, theta) + p.fixed.eta_d * nu;
        // m = M V0^2 / (W D0), V0 in m/s and D0 in m.
        let m = (p.d0_um * 1e-6).recip() * (self.mass_over_load * (self.v0_um_s * 1e-6).powi(2));
        let kappa_c = (mu_phi - mu_v) * (m * nu * nu / mu_v + 1.0);
        (kappa_c, mu_phi, mu_v)
    }

    /// The critical stiffness over load `(K/W)_c` [1/m] at `V` µm/s.
    pub fn k_over_w_c<T: Scalar>(&self, p: &Values<T>, v_um_s: f64) -> T {
        self.onset(p, v_um_s).0 / (p.d0_um * 1e-6)
    }

    /// The onset frequency `f_c` \[Hz\] at `V` µm/s (eq. C13); NaN where
    /// steady friction is not velocity weakening (no onset).
    pub fn frequency_hz<T: Scalar>(&self, p: &Values<T>, v_um_s: f64) -> T {
        let nu = v_um_s / self.v0_um_s;
        let (_, mu_phi, mu_v) = self.onset(p, v_um_s);
        let omega = (mu_phi / mu_v - 1.0).sqrt() * nu;
        omega * (self.v0_um_s * 1e-6) / (p.d0_um * 1e-6 * 2.0 * std::f64::consts::PI)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::Params;

    /// The fit's formulas against the ones the analyses use (Appendix C on
    /// the scene's dimensionless parameters, `appendix_c` with
    /// `Params::mu_v_damped`): the same numbers, without and with the
    /// corrections and the damping.
    #[test]
    fn equals_appendix_c_on_the_scene() {
        let scene = crate::scene::load("examples/scenes/rig.toml").unwrap();
        let rig = Rig::of(&scene.units);
        let plain = scene.params;
        let terms = Params {
            mu_vv: 2e-4,
            mu_vphi: -3e-4,
            eta_d: 1e-4,
            ..plain
        };
        for p in [plain, terms] {
            let values = Values {
                mu0: p.mu0,
                a: p.a,
                b: p.b,
                d0_um: scene.units.d0 * 1e6,
                ageing: AgeingValue::Mu2(p.mu2),
                fixed: Fixed {
                    mu_vv: p.mu_vv,
                    mu_vphi: p.mu_vphi,
                    eta_d: p.eta_d,
                },
            };
            // (At 200 µm/s the terms leave steady sliding velocity strengthening.)
            for v in [0.1, 3.0, 10.0] {
                let mut q = p;
                q.nu = v / rig.v0_um_s;
                let kappa_c = crate::appendix_c::critical_stiffness(&q);
                let omega = crate::appendix_c::critical_frequency(&q).unwrap();
                let rel = |x: f64, y: f64| ((x - y) / y).abs();
                let k_c = scene.units.k_over_w(kappa_c);
                assert!(rel(rig.k_over_w_c(&values, v), k_c) < 1e-13, "{v}");
                let f_c = scene.units.frequency_hz(omega);
                assert!(rel(rig.frequency_hz(&values, v), f_c) < 1e-13, "{v}");
                let steady = q.friction().steady(q.nu) + q.eta_d * q.nu;
                assert!(rel(rig.steady(&values, v), steady) < 1e-15, "{v}");
            }
        }
    }
}
