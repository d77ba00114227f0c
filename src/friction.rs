//! Rate-and-state friction laws of docs/model.md (seed eqs. RR1–RR3, C3).
//!
//! ```text
//! mu(v, theta) = mu0 + A ln v + ageing(theta)
//! ageing(theta) = B ln theta + mu2 (ln theta)^2        (Rice–Ruina, optional ln² correction)
//!              or B ln(1 + theta/theta_c)              (short-age cutoff)
//! ```
//!
//! Velocities are in units of `V0`, ages in units of `D0/V0`. The law is generic
//! over the scalar so that the driven-block models get exact derivatives from
//! dual numbers.

use continuation::Scalar;

/// The form of the ageing (state) term. Only one of the two forms is active.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Ageing<T> {
    /// `B ln theta + mu2 (ln theta)^2`; `mu2 = 0` is the plain Rice–Ruina law.
    Log { b: T, mu2: T },
    /// `B ln(1 + theta/theta_c)`: ageing saturates for `theta << theta_c`.
    Cutoff { b: T, theta_c: T },
}

/// A friction law `mu(v, theta)`, dimensionless (docs/model.md).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrictionLaw<T> {
    /// Friction coefficient at `v = 1`, `theta = 1`.
    pub mu0: T,
    /// Direct (rate) effect `A = d mu / d ln v`.
    pub a: T,
    /// Ageing term.
    pub ageing: Ageing<T>,
}

impl<T: Scalar> FrictionLaw<T> {
    /// `mu(v, theta) = mu0 + A ln v + ageing(theta)`.
    pub fn mu(&self, v: T, theta: T) -> T {
        self.mu0 + self.a * v.ln() + self.ageing_term(theta)
    }

    /// The ageing contribution to `mu` at age `theta`.
    pub fn ageing_term(&self, theta: T) -> T {
        match self.ageing {
            Ageing::Log { b, mu2 } => {
                let l = theta.ln();
                b * l + mu2 * l * l
            }
            Ageing::Cutoff { b, theta_c } => b * (theta / theta_c).ln_1p(),
        }
    }

    /// The change of the ageing term when `ln theta` moves from `ln_theta0`
    /// by `d`, `ageing(e^(ln_theta0 + d)) - ageing(e^ln_theta0)`, written so
    /// that no two large terms cancel (it is as accurate, relatively, as `d`
    /// is small):
    ///
    /// ```text
    /// B d + mu2 d (2 ln_theta0 + d)                            (logarithmic forms)
    /// B ln_1p( e^ln_theta0 expm1(d) / (theta_c + e^ln_theta0) )   (cutoff)
    /// ```
    pub fn ageing_change(&self, ln_theta0: T, d: T) -> T {
        match self.ageing {
            Ageing::Log { b, mu2 } => b * d + mu2 * d * (ln_theta0 * 2.0 + d),
            Ageing::Cutoff { b, theta_c } => {
                let theta0 = ln_theta0.exp();
                b * (theta0 * d.exp_m1() / (theta_c + theta0)).ln_1p()
            }
        }
    }

    /// `mu_phi = d mu / d ln theta` at age `theta` (seed, Appendix C):
    /// `B + 2 mu2 ln theta`, or `B theta / (theta + theta_c)` with the cutoff.
    pub fn mu_phi(&self, theta: T) -> T {
        match self.ageing {
            Ageing::Log { b, mu2 } => b + mu2 * theta.ln() * 2.0,
            Ageing::Cutoff { b, theta_c } => b * theta / (theta + theta_c),
        }
    }

    /// `mu_v = d mu / d ln v = A` (the direct effect).
    pub fn mu_v(&self) -> T {
        self.a
    }

    /// Steady-state friction `mu_ss(nu) = mu(nu, 1/nu)` (seed eq. RR5).
    pub fn steady(&self, nu: T) -> T {
        self.mu(nu, nu.recip())
    }

    /// `d mu_ss / d ln nu = mu_v - mu_phi`: negative means velocity weakening.
    pub fn steady_slope(&self, nu: T) -> T {
        self.mu_v() - self.mu_phi(nu.recip())
    }

    /// Inverse of the direct effect: the velocity at which the law gives
    /// friction `s` at age `theta`, `v = exp((s - mu0 - ageing(theta)) / A)`.
    /// This slaves `v` in the quasi-static limit.
    pub fn slip_velocity(&self, s: T, theta: T) -> T {
        ((s - self.mu0 - self.ageing_term(theta)) / self.a).exp()
    }
}

impl FrictionLaw<f64> {
    /// Velocity of minimal steady friction for the cutoff law,
    /// `V_min = (B - A) / (A theta_c)` in units of `V0` (docs/model.md); `None` for
    /// the logarithmic ageing forms or when `B <= A` (no weakening range).
    pub fn v_min(&self) -> Option<f64> {
        match self.ageing {
            Ageing::Cutoff { b, theta_c } if b > self.a => Some((b - self.a) / (self.a * theta_c)),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ln2_law() -> FrictionLaw<f64> {
        FrictionLaw {
            mu0: 0.6,
            a: 0.012,
            ageing: Ageing::Log {
                b: 0.023,
                mu2: 2.4e-4,
            },
        }
    }

    fn cutoff_law() -> FrictionLaw<f64> {
        FrictionLaw {
            mu0: 0.6,
            a: 0.012,
            ageing: Ageing::Cutoff {
                b: 0.023,
                theta_c: 0.3,
            },
        }
    }

    #[test]
    fn mu_phi_is_the_log_derivative_of_ageing() {
        // Central difference in ln(theta) with an O(h^2) error, h = 1e-4.
        for law in [ln2_law(), cutoff_law()] {
            for theta in [1e-3, 0.7, 5.0, 1e3] {
                let h: f64 = 1e-4;
                let fd = (law.ageing_term(theta * h.exp()) - law.ageing_term(theta * (-h).exp()))
                    / (2.0 * h);
                let exact = law.mu_phi(theta);
                assert!(
                    (fd - exact).abs() <= 1e-8 * exact.abs().max(1e-3),
                    "{fd} vs {exact}"
                );
            }
        }
    }

    #[test]
    fn ageing_change_is_the_difference_of_ageing_terms() {
        // Against the plain difference where it does not cancel (d of order
        // one), and for small d against d * mu_phi(theta0) + d^2/2 * the
        // second log-derivative (d = 1e-9: the plain difference would keep
        // only 7 digits there).
        for law in [ln2_law(), cutoff_law()] {
            for ln0 in [-3.0f64, 0.0, 2.5] {
                for d in [-1.5, 0.7] {
                    let plain = law.ageing_term((ln0 + d).exp()) - law.ageing_term(ln0.exp());
                    assert!(
                        (law.ageing_change(ln0, d) - plain).abs() < 1e-14,
                        "{ln0} {d}"
                    );
                }
                let d = 1e-9;
                let h: f64 = 1e-4;
                let second =
                    (law.mu_phi((ln0 + h).exp()) - law.mu_phi((ln0 - h).exp())) / (2.0 * h);
                let taylor = d * law.mu_phi(ln0.exp()) + 0.5 * d * d * second;
                assert!(
                    (law.ageing_change(ln0, d) / taylor - 1.0).abs() < 1e-14,
                    "{ln0}: {} vs {taylor}",
                    law.ageing_change(ln0, d)
                );
            }
        }
    }

    #[test]
    fn slip_velocity_inverts_mu() {
        let law = ln2_law();
        for (v, theta) in [(1e-6, 1e6), (1.0, 1.0), (3e3, 2e-4)] {
            let s = law.mu(v, theta);
            assert!((law.slip_velocity(s, theta) / v - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn cutoff_steady_friction_is_minimal_at_v_min() {
        let law = FrictionLaw {
            mu0: 0.4,
            a: 0.012,
            ageing: Ageing::Cutoff {
                b: 0.023,
                theta_c: 0.05,
            },
        };
        let v_min = law.v_min().unwrap();
        assert!((v_min - 0.011 / (0.012 * 0.05)).abs() < 1e-12 * v_min);
        assert!(law.steady_slope(v_min).abs() < 1e-15);
        assert!(law.steady_slope(0.5 * v_min) < 0.0 && law.steady_slope(2.0 * v_min) > 0.0);
    }
}
