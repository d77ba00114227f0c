//! What the fitted parameters predict for each kind of data, generic over
//! the scalar so that the least squares get exact Jacobians from dual
//! numbers.
//!
//! With `nu = V / V0`, steady sliding at age `theta = 1 / nu`
//! (docs/model.md, seed eq. RR5) and the friction law of the scene:
//!
//! ```text
//! mu_ss(V)   = mu0 + A ln nu + ageing(1/nu)
//! (K/W)_c(V) = kappa_c / D0,  kappa_c = (mu_phi - A)(1 + m nu^2 / A)     (eq. C11)
//! f_c(V)     = Omega_c V0 / (2 pi D0),  Omega_c = nu sqrt(mu_phi / A - 1) (eq. C13)
//! ```
//!
//! with `m = M V0^2 / (W D0)` from the scene's mass and load and, for the
//! cutoff law, `theta_c = tau V0 / D0`.

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
    /// velocity `v0_um_s`; without `mu_vv`, `mu_vphi` and `eta_d`, which the fit
    /// does not model (it refuses a scene that has them, `jobs::fit`).
    fn law(&self, v0_um_s: f64) -> FrictionLaw<T> {
        FrictionLaw {
            mu0: self.mu0,
            a: self.a,
            eta: T::from(0.0),
            ageing: match self.ageing {
                AgeingValue::Mu2(mu2) => Ageing::Log {
                    b: self.b,
                    mu2,
                    mu_vv: T::from(0.0),
                    mu_vphi: T::from(0.0),
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

    /// Steady friction `mu_ss` at `V` µm/s (seed eq. RR5).
    pub fn steady<T: Scalar>(&self, p: &Values<T>, v_um_s: f64) -> T {
        p.law(self.v0_um_s).steady(T::from(v_um_s / self.v0_um_s))
    }

    /// `(kappa_c, mu_phi)` at `V` µm/s (eq. C11).
    fn onset<T: Scalar>(&self, p: &Values<T>, v_um_s: f64) -> (T, T) {
        let nu = v_um_s / self.v0_um_s;
        let mu_phi = p.law(self.v0_um_s).mu_phi(T::from(nu), T::from(1.0 / nu));
        // m = M V0^2 / (W D0), V0 in m/s and D0 in m.
        let m = (p.d0_um * 1e-6).recip() * (self.mass_over_load * (self.v0_um_s * 1e-6).powi(2));
        let kappa_c = (mu_phi - p.a) * (m * nu * nu / p.a + 1.0);
        (kappa_c, mu_phi)
    }

    /// The critical stiffness over load `(K/W)_c` [1/m] at `V` µm/s.
    pub fn k_over_w_c<T: Scalar>(&self, p: &Values<T>, v_um_s: f64) -> T {
        self.onset(p, v_um_s).0 / (p.d0_um * 1e-6)
    }

    /// The onset frequency `f_c` [Hz] at `V` µm/s (eq. C13); NaN where
    /// steady friction is not velocity weakening (no onset).
    pub fn frequency_hz<T: Scalar>(&self, p: &Values<T>, v_um_s: f64) -> T {
        let nu = v_um_s / self.v0_um_s;
        let (_, mu_phi) = self.onset(p, v_um_s);
        let omega = (mu_phi / p.a - 1.0).sqrt() * nu;
        omega * (self.v0_um_s * 1e-6) / (p.d0_um * 1e-6 * 2.0 * std::f64::consts::PI)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::Params;

    /// The fit's formulas against the ones the analyses use (Appendix C on
    /// the scene's dimensionless parameters): the same numbers.
    #[test]
    fn equals_appendix_c_on_the_scene() {
        let scene = crate::scene::load("examples/scenes/rig.toml").unwrap();
        let p: &Params = &scene.params;
        let rig = Rig::of(&scene.units);
        let values = Values {
            mu0: p.mu0,
            a: p.a,
            b: p.b,
            d0_um: scene.units.d0 * 1e6,
            ageing: AgeingValue::Mu2(p.mu2),
        };
        for v in [0.1, 3.0, 10.0, 200.0] {
            let mut q = *p;
            q.nu = v / rig.v0_um_s;
            let kappa_c = crate::appendix_c::critical_stiffness(&q);
            let omega = crate::appendix_c::critical_frequency(&q).unwrap();
            let rel = |x: f64, y: f64| ((x - y) / y).abs();
            assert!(rel(rig.k_over_w_c(&values, v), scene.units.k_over_w(kappa_c)) < 1e-14);
            assert!(
                rel(
                    rig.frequency_hz(&values, v),
                    scene.units.frequency_hz(omega)
                ) < 1e-14
            );
            assert!(rel(rig.steady(&values, v), q.friction().steady(q.nu)) < 1e-15);
        }
    }
}
