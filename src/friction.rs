//! Rate-and-state friction laws of docs/model.md (seed eqs. RR1–RR3, C3,
//! and the corrections of §II.D.2).
//!
//! ```text
//! mu(v, theta) = mu0 + A ln v + ageing(theta)                         (RR3)
//!              + mu_vv (ln v)^2 + mu_vphi (ln theta)(ln v)            (§II.D.2, logarithmic form only)
//! ageing(theta) = B ln theta + mu2 (ln theta)^2        (Rice–Ruina, optional ln² correction)
//!              or B ln(1 + theta/theta_c)              (short-age cutoff)
//! ```
//!
//! With radiation damping (docs/model.md, "Radiation damping") the block
//! meets the force `mu(v, theta) + eta_d v` ([`FrictionLaw::eta`]): the
//! friction law's `mu` is unchanged, the damping adds to it in the force
//! balance, at steady sliding and in the quasi-static inversion.
//!
//! Velocities are in units of `V0`, ages in units of `D0/V0`. The law is generic
//! over the scalar so that the driven-block models get exact derivatives from
//! dual numbers.

use continuation::Scalar;

/// The form of the state dependence. Only one of the two forms is active;
/// the corrections that couple `ln v` to the state or to itself belong to
/// the logarithmic form (seed §II.D.2 names them beside the ln² term).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Ageing<T> {
    /// `B ln theta + mu2 (ln theta)^2 + mu_vv (ln v)^2 + mu_vphi (ln theta)(ln v)`;
    /// all three corrections 0 is the plain Rice–Ruina law.
    Log { b: T, mu2: T, mu_vv: T, mu_vphi: T },
    /// `B ln(1 + theta/theta_c)`: ageing saturates for `theta << theta_c`.
    Cutoff { b: T, theta_c: T },
}

/// A friction law `mu(v, theta)`, dimensionless (docs/model.md).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrictionLaw<T> {
    /// Friction coefficient at `v = 1`, `theta = 1`.
    pub mu0: T,
    /// Direct (rate) effect `A`, `d mu / d ln v` at `v = theta = 1`.
    pub a: T,
    /// Ageing term (and the logarithmic form's corrections).
    pub ageing: Ageing<T>,
    /// Radiation damping `eta_d = eta V0` (`eta = G / (2 c_s sigma)` in
    /// s/m): the force balance resists with `mu + eta_d v`. 0 without it.
    pub eta: T,
}

/// The friction law gives no slip velocity for a friction `s` at an age
/// `theta`: on the rising branch of `mu` in `ln v` (`d mu / d ln v > 0`)
/// it does not reach `s` (docs/model.md, "The quasi-static inversion").
/// Only the correction `mu_vv` (a parabola in `ln v`) or `mu_vphi` (a
/// slope `A + mu_vphi ln theta` that can vanish) make this possible.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
#[error(
    "the friction law gives no slip velocity for s = {s:e} at theta = {theta:e}: with mu_vv and \
     mu_vphi, mu(v, theta) + eta_d v does not reach s where it rises with ln v"
)]
pub struct NoSlipVelocity {
    pub s: f64,
    pub theta: f64,
}

/// The root `x` of `a x^2 + b x = c` on the rising branch, `2 a x + b > 0`
/// (the root continuous with `c / b` as `a -> 0`), written without
/// cancellation: `x = (c / b) 2 / (1 + sqrt(1 + r))`, `r = 4 a c / b^2`,
/// for `b > 0` and `|r| <= 1`; `x = (sqrt(b^2 + 4 a c) - b) / (2 a)`
/// otherwise (there `-b` and the root add, or nearly: at most a factor
/// `sqrt 2 - 1` cancels). `None` where there is none: the discriminant
/// `b^2 + 4 a c <= 0`, or `a = 0` with `b <= 0`. For `a = 0` the value is
/// `c / b` exactly (to the last bit, also in every dual part).
fn rising_root<T: Scalar>(a: T, b: T, c: T) -> Option<T> {
    if b.re() > 0.0 {
        let r = a * c * 4.0 / (b * b);
        if r.re().abs() <= 1.0 {
            return (r.re() > -1.0).then(|| c / b * 2.0 / ((r + 1.0).sqrt() + 1.0));
        }
    }
    let d = b * b + a * c * 4.0;
    (a.re() != 0.0 && d.re() > 0.0).then(|| (d.sqrt() - b) / (a * 2.0))
}

impl<T: Scalar> FrictionLaw<T> {
    /// `mu(v, theta) = mu0 + rate_coefficient(ln v, ln theta) ln v + ageing(theta)`
    /// (module docs).
    pub fn mu(&self, v: T, theta: T) -> T {
        let ln_v = v.ln();
        self.mu0 + self.rate_coefficient(ln_v, theta.ln()) * ln_v + self.ageing_term(theta)
    }

    /// `mu` at `(e^ln_v, e^ln_theta)` from the logarithms: also where `v`
    /// is below the range of `f64` (a deep stick).
    pub fn mu_of_logs(&self, ln_v: T, ln_theta: T) -> T {
        self.mu0 + self.rate_coefficient(ln_v, ln_theta) * ln_v + self.ageing_term(ln_theta.exp())
    }

    /// `A + mu_vv x + mu_vphi ln_theta` (`A` for the cutoff form): with
    /// `x = ln v` the coefficient of `ln v` in `mu`; with `x = 2 ln v` the
    /// slope `mu_v = d mu / d ln v`; with `x = 2 ln v0 + d` the secant slope
    /// `(mu(ln v0 + d) - mu(ln v0)) / d` at fixed `theta`.
    pub fn rate_coefficient(&self, x: T, ln_theta: T) -> T {
        match self.ageing {
            Ageing::Log { mu_vv, mu_vphi, .. } => self.a + mu_vv * x + mu_vphi * ln_theta,
            Ageing::Cutoff { .. } => self.a,
        }
    }

    /// The ageing contribution to `mu` at age `theta` (`B ln theta + mu2
    /// (ln theta)^2`, or the cutoff's): the part of `mu - mu0` that stays at
    /// `v = 1`.
    pub fn ageing_term(&self, theta: T) -> T {
        match self.ageing {
            Ageing::Log { b, mu2, .. } => {
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
            Ageing::Log { b, mu2, .. } => b * d + mu2 * d * (ln_theta0 * 2.0 + d),
            Ageing::Cutoff { b, theta_c } => {
                let theta0 = ln_theta0.exp();
                b * (theta0 * d.exp_m1() / (theta_c + theta0)).ln_1p()
            }
        }
    }

    /// The change of `mu` at fixed `v = e^ln_v0` when `ln theta` moves from
    /// `ln_theta0` by `d`, without cancellation: [`Self::ageing_change`]
    /// plus `mu_vphi ln_v0 d`. With the secant slope at the new age, the
    /// change of `mu` from `(ln_v0, ln_theta0)` by `(dw, d)` is
    ///
    /// ```text
    /// dw rate_coefficient(2 ln_v0 + dw, ln_theta0 + d) + state_change(ln_v0, ln_theta0, d)
    ///   = dw (A + mu_vv (2 ln_v0 + dw) + mu_vphi (ln_theta0 + d))
    ///     + ageing_change(ln_theta0, d) + mu_vphi ln_v0 d
    /// ```
    pub fn state_change(&self, ln_v0: T, ln_theta0: T, d: T) -> T {
        let ageing = self.ageing_change(ln_theta0, d);
        match self.ageing {
            Ageing::Log { mu_vphi, .. } => ageing + mu_vphi * ln_v0 * d,
            Ageing::Cutoff { .. } => ageing,
        }
    }

    /// `mu_phi = d mu / d ln theta` at `(v, theta)` (seed, Appendix C):
    /// `B + 2 mu2 ln theta + mu_vphi ln v`, or `B theta / (theta + theta_c)`
    /// with the cutoff.
    pub fn mu_phi(&self, v: T, theta: T) -> T {
        match self.ageing {
            Ageing::Log {
                b, mu2, mu_vphi, ..
            } => b + mu2 * theta.ln() * 2.0 + mu_vphi * v.ln(),
            Ageing::Cutoff { b, theta_c } => b * theta / (theta + theta_c),
        }
    }

    /// `mu_v = d mu / d ln v` at `(v, theta)` (seed, Appendix C):
    /// `A + 2 mu_vv ln v + mu_vphi ln theta` (`A`, the direct effect, for
    /// the plain law and the cutoff).
    pub fn mu_v(&self, v: T, theta: T) -> T {
        self.rate_coefficient(v.ln() * 2.0, theta.ln())
    }

    /// Steady-state friction `mu_ss(nu) = mu(nu, 1/nu)` (seed eq. RR5).
    pub fn steady(&self, nu: T) -> T {
        self.mu(nu, nu.recip())
    }

    /// The radiation-damping force `eta_d v` over the load (docs/model.md,
    /// "Radiation damping"); exactly 0 without damping, also where `v`
    /// overflowed (where `0 * inf` would be NaN).
    pub fn damping(&self, v: T) -> T {
        if self.eta.re() == 0.0 && !v.re().is_finite() {
            T::from(0.0)
        } else {
            self.eta * v
        }
    }

    /// The spring force at steady sliding, `s = mu_ss(nu) + eta_d nu`
    /// (docs/model.md: `m v' = s - mu - eta_d v` vanishes at `v = nu`,
    /// `theta = 1/nu`); `mu_ss(nu)` to the last bit without damping.
    pub fn steady_force(&self, nu: T) -> T {
        self.steady(nu) + self.damping(nu)
    }

    /// `d mu_ss / d ln nu = mu_v - mu_phi` at steady sliding (`v = nu`,
    /// `theta = 1/nu`): negative means velocity weakening. With the
    /// logarithmic form, `(A - B) + 2 (mu2 + mu_vv - mu_vphi) ln nu`.
    pub fn steady_slope(&self, nu: T) -> T {
        let theta = nu.recip();
        self.mu_v(nu, theta) - self.mu_phi(nu, theta)
    }

    /// The change `x = ln v - ln_v0` of the slip velocity's logarithm at
    /// which the force `mu + eta_d v` at age `e^ln_theta` exceeds its value
    /// at `(e^ln_v0, e^ln_theta)` by `gap`: the root of
    ///
    /// ```text
    /// mu_vv x^2 + (A + 2 mu_vv ln_v0 + mu_vphi ln_theta) x + eta_d e^ln_v0 expm1(x) = gap
    /// ```
    ///
    /// on a rising branch of the left-hand side in `x` (docs/model.md, "The
    /// quasi-static inversion"). Without damping it is the quadratic's root
    /// continuous with the linear law's `gap / A`, without cancellation
    /// (to the last bit as before damping existed); with damping the
    /// smallest root where the left-hand side rises ([`damped_root`], a
    /// bracketed safeguarded Newton iteration in `x`, exact to rounding;
    /// the dual parts by Newton steps in the scalar). `None` where the law
    /// has none: without damping the discriminant is not positive, or the
    /// slope `A + mu_vphi ln theta` is not positive without `mu_vv`; with
    /// it, the left-hand side does not reach `gap` on a rising branch.
    pub fn ln_velocity_change(&self, ln_v0: T, ln_theta: T, gap: T) -> Option<T> {
        let (a, b) = match self.ageing {
            Ageing::Log { mu_vv, .. } => (mu_vv, self.rate_coefficient(ln_v0 * 2.0, ln_theta)),
            Ageing::Cutoff { .. } => (T::from(0.0), self.a),
        };
        // The damping's slope scale eta_d v_0: the term is eta_d (v - v_0).
        let e = self.eta * ln_v0.exp();
        let lhs = |x: T| a * x * x + b * x + e * x.exp_m1();
        if e.re() == 0.0 {
            let x_q = match self.ageing {
                Ageing::Log { mu_vv, .. } => rising_root(mu_vv, b, gap)?,
                Ageing::Cutoff { .. } => gap / self.a,
            };
            if T::NDERIV == 0 || x_q.re().exp_m1().is_infinite() {
                return Some(x_q);
            }
            // eta_d has no value but may carry derivatives (a parameter of
            // a continuation from eta_d = 0): the root x_q + d of
            // Q'(x_q) d + mu_vv d^2 + e expm1(x_q + d) = 0 (Q the quadratic,
            // Q(x_q) = 0), one order of e per step; d = 0 to the last bit
            // where e carries none.
            let slope = a * x_q * 2.0 + b;
            let mut d = T::from(0.0);
            for _ in 0..T::NDERIV {
                d = -(e * (x_q + d).exp_m1() + a * d * d) / slope;
            }
            return Some(x_q + d);
        }
        let x = damped_root(a.re(), b.re(), e.re(), gap.re())?;
        // Newton steps in the scalar: each doubles the order of the
        // derivatives carried exactly.
        let mut x = T::from(x);
        let mut exact = 0;
        while exact < T::NDERIV {
            x -= (lhs(x) - gap) / (a * x * 2.0 + b + e * x.exp());
            exact = 2 * exact + 1;
        }
        Some(x)
    }

    /// Inverse of the force `mu + eta_d v` in `v`: the velocity at which
    /// the block meets the force `s` at age `theta`, `v = exp(L)` with `L`
    /// the root of `mu_vv L^2 + (A + mu_vphi ln theta) L + eta_d (e^L - 1)
    /// = s - mu0 - ageing(theta) - eta_d` ([`Self::ln_velocity_change`]
    /// from `v = 1`; `L = (s - mu0 - ageing(theta)) / A` without the
    /// corrections and damping). This slaves `v` in the quasi-static limit;
    /// [`NoSlipVelocity`] where the law reaches no `s`.
    pub fn slip_velocity(&self, s: T, theta: T) -> Result<T, NoSlipVelocity> {
        let one = T::from(1.0);
        let gap = s - self.mu0 - self.ageing_term(theta) - self.damping(one);
        self.ln_velocity_change(T::from(0.0), theta.ln(), gap)
            .map(|l| l.exp())
            .ok_or(NoSlipVelocity {
                s: s.re(),
                theta: theta.re(),
            })
    }
}

/// The root `x` of `F(x) = a x^2 + b x + e expm1(x) - gap` (`e > 0`, the
/// damping's slope scale) on a rising branch of `F` (docs/model.md, "The
/// quasi-static inversion"), in `x`, a logarithm, so that nothing
/// overflows that matters (`F = inf` beyond `x = 709` only brackets). With
/// `F' = 2 a x + b + e e^x`, `F'' = 2 a + e e^x`:
///
/// - `a >= 0`: `F` is convex; it rises everywhere (`a = 0`, `b > 0`) or
///   beyond the zero `x1` of `F'` (`a = 0`, `b <= 0`: `F' = b + e e^x`), and has a root there iff `F(x1) < 0`;
/// - `a < 0`: `F'` is lowest at `x_c = ln(-2a / e)`; `F` rises everywhere
///   if `F'(x_c) > 0`, else on `x < x1` and `x > x2` (the zeros of `F'`):
///   the root below `x1` (the branch of the undamped law) if `F(x1) > 0`,
///   else the one above `x2` (where damping holds the force).
///
/// The root, as every zero of `F'`, by [`increasing_zero`]. `None` where
/// there is none (or no bracket within `|x| < 1e300`).
fn damped_root(a: f64, b: f64, e: f64, gap: f64) -> Option<f64> {
    if !(e > 0.0 && e.is_finite() && a.is_finite() && b.is_finite() && gap.is_finite()) {
        return None;
    }
    let f = |x: f64| {
        (
            a * x * x + b * x + e * x.exp_m1() - gap,
            2.0 * a * x + b + e * x.exp(),
        )
    };
    let df = |x: f64| (2.0 * a * x + b + e * x.exp(), 2.0 * a + e * x.exp());
    let (lo, hi) = if a >= 0.0 {
        if a == 0.0 && b >= 0.0 {
            (f64::NEG_INFINITY, f64::INFINITY)
        } else {
            let lo = reach(0.0, -1.0, |x| df(x).0 < 0.0)?;
            let hi = reach(0.0, 1.0, |x| df(x).0 > 0.0)?;
            let x1 = increasing_zero(df, lo, hi);
            if !below_zero(f(x1).0) {
                return None;
            }
            (x1, f64::INFINITY)
        }
    } else {
        let x_c = (-2.0 * a).ln() - e.ln();
        if df(x_c).0 > 0.0 {
            (f64::NEG_INFINITY, f64::INFINITY)
        } else {
            let neg = |x: f64| {
                let (v, d) = df(x);
                (-v, -d)
            };
            let x1 = increasing_zero(neg, reach(x_c, -1.0, |x| df(x).0 > 0.0)?, x_c);
            if f(x1).0 > 0.0 {
                (f64::NEG_INFINITY, x1)
            } else {
                let x2 = increasing_zero(df, x_c, reach(x_c, 1.0, |x| df(x).0 > 0.0)?);
                if !below_zero(f(x2).0) {
                    return None;
                }
                (x2, f64::INFINITY)
            }
        }
    };
    let below = |x: f64| f(x).0 <= 0.0;
    let above = |x: f64| !below_zero(f(x).0);
    let (lo, hi) = match (lo.is_finite(), hi.is_finite()) {
        (true, true) => (lo, hi),
        (false, true) => (reach(hi, -1.0, below)?, hi),
        (true, false) => (lo, reach(lo, 1.0, above)?),
        (false, false) if below(0.0) => (0.0, reach(0.0, 1.0, above)?),
        (false, false) => (reach(0.0, -1.0, below)?, 0.0),
    };
    Some(increasing_zero(f, lo, hi))
}

/// Whether `F` at a point is below 0 (and a number): a root lies beyond it
/// on a rising branch.
fn below_zero(f: f64) -> bool {
    f < 0.0
}

/// The first `x = from + dir 2^k` (`k = 0, 1, ...`, `|x| < 1e300`) where
/// `holds(x)`: one end of a bracket.
pub(crate) fn reach(from: f64, dir: f64, holds: impl Fn(f64) -> bool) -> Option<f64> {
    let mut step = 1.0;
    while step < 1e300 {
        let x = from + dir * step;
        if holds(x) {
            return Some(x);
        }
        step *= 2.0;
    }
    None
}

/// The zero of `g` (value and derivative), increasing on `[lo, hi]` with
/// `g(lo) <= 0 <= g(hi)`: Newton's method kept inside the bracket, which
/// every value shrinks, bisection where a step leaves it (or is not a
/// number: `g = inf` far out). It ends where the step is below rounding or
/// the bracket is a few ulps wide: exact to rounding.
pub(crate) fn increasing_zero(g: impl Fn(f64) -> (f64, f64), mut lo: f64, mut hi: f64) -> f64 {
    let mut x = 0.5 * lo + 0.5 * hi;
    for _ in 0..3000 {
        let (v, d) = g(x);
        if v == 0.0 {
            return x;
        }
        if v < 0.0 {
            lo = x;
        } else {
            hi = x;
        }
        let newton = x - v / d;
        let next = if newton > lo && newton < hi {
            newton
        } else {
            0.5 * lo + 0.5 * hi
        };
        if next == x || hi - lo <= 4.0 * f64::EPSILON * next.abs() {
            return next;
        }
        x = next;
    }
    x
}

impl FrictionLaw<f64> {
    /// Velocity of minimal steady friction in units of `V0` (docs/model.md),
    /// where [`FrictionLaw::steady_slope`] vanishes and rises: for the cutoff
    /// law `V_min = (B - A) / (A theta_c)` (`None` when `B <= A`: no
    /// weakening range); for the logarithmic form, whose `mu_ss` is a
    /// parabola in `ln nu`, `exp((B - A) / (2 c))` with `c = mu2 + mu_vv -
    /// mu_vphi` (`None` when `c <= 0`: no minimum).
    pub fn v_min(&self) -> Option<f64> {
        match self.ageing {
            Ageing::Cutoff { b, theta_c } if b > self.a => Some((b - self.a) / (self.a * theta_c)),
            Ageing::Log {
                b,
                mu2,
                mu_vv,
                mu_vphi,
            } => {
                let c = mu2 + mu_vv - mu_vphi;
                (c > 0.0).then(|| ((b - self.a) / (2.0 * c)).exp())
            }
            Ageing::Cutoff { .. } => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The ln² law of the PMMA scene with the corrections of seed §II.D.2.
    fn log_law(mu_vv: f64, mu_vphi: f64) -> FrictionLaw<f64> {
        FrictionLaw {
            mu0: 0.6,
            a: 0.012,
            eta: 0.0,
            ageing: Ageing::Log {
                b: 0.023,
                mu2: 2.4e-4,
                mu_vv,
                mu_vphi,
            },
        }
    }

    fn ln2_law() -> FrictionLaw<f64> {
        log_law(0.0, 0.0)
    }

    fn cutoff_law() -> FrictionLaw<f64> {
        FrictionLaw {
            mu0: 0.6,
            a: 0.012,
            eta: 0.0,
            ageing: Ageing::Cutoff {
                b: 0.023,
                theta_c: 0.3,
            },
        }
    }

    /// The ln² law with both corrections of seed §II.D.2.
    fn corrected_law() -> FrictionLaw<f64> {
        log_law(3e-4, -2e-4)
    }

    #[test]
    fn mu_phi_and_mu_v_are_the_log_derivatives_of_mu() {
        // Central differences in ln(theta) and ln(v) with an O(h^2) error, h = 1e-4.
        let h: f64 = 1e-4;
        for law in [ln2_law(), cutoff_law(), corrected_law()] {
            for theta in [1e-3, 0.7, 5.0, 1e3] {
                for v in [1e-4, 1.0, 30.0] {
                    let d_theta =
                        (law.mu(v, theta * h.exp()) - law.mu(v, theta * (-h).exp())) / (2.0 * h);
                    let d_v =
                        (law.mu(v * h.exp(), theta) - law.mu(v * (-h).exp(), theta)) / (2.0 * h);
                    for (fd, exact) in [(d_theta, law.mu_phi(v, theta)), (d_v, law.mu_v(v, theta))]
                    {
                        assert!(
                            (fd - exact).abs() <= 1e-8 * exact.abs().max(1e-3),
                            "{fd} vs {exact}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn ageing_change_is_the_difference_of_ageing_terms() {
        // Against the plain difference where it does not cancel (d of order
        // one), and for small d against d * mu_phi(theta0) + d^2/2 * the
        // second log-derivative (d = 1e-9: the plain difference would keep
        // only 7 digits there); mu_phi at v = 1 is the ageing term's slope.
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
                let slope = |l: f64| law.mu_phi(1.0, l.exp());
                let second = (slope(ln0 + h) - slope(ln0 - h)) / (2.0 * h);
                let taylor = d * slope(ln0) + 0.5 * d * d * second;
                assert!(
                    (law.ageing_change(ln0, d) / taylor - 1.0).abs() < 1e-14,
                    "{ln0}: {} vs {taylor}",
                    law.ageing_change(ln0, d)
                );
            }
        }
    }

    #[test]
    fn secant_and_state_change_are_the_change_of_mu() {
        // mu(w0 + dw, p0 + d) - mu(w0, p0) = dw rate_coefficient(2 w0 + dw, p0 + d)
        // + state_change(w0, p0, d): against the plain difference for steps of
        // order one, and for steps of 1e-9 against the first-order change
        // dw mu_v + d mu_phi (relative 1e-8: the second order).
        for law in [ln2_law(), cutoff_law(), corrected_law()] {
            let change = |w0: f64, p0: f64, dw: f64, d: f64| {
                dw * law.rate_coefficient(2.0 * w0 + dw, p0 + d) + law.state_change(w0, p0, d)
            };
            for (w0, p0) in [(-4.0f64, 3.0f64), (0.0, 0.0), (2.0, -1.5)] {
                for (dw, d) in [(-1.5, 0.7), (0.9, -1.1)] {
                    let plain =
                        law.mu((w0 + dw).exp(), (p0 + d).exp()) - law.mu(w0.exp(), p0.exp());
                    assert!((change(w0, p0, dw, d) - plain).abs() < 1e-14, "{w0} {p0}");
                }
                let (dw, d) = (1e-9, -2e-9);
                let (v, theta) = (w0.exp(), p0.exp());
                let first = dw * law.mu_v(v, theta) + d * law.mu_phi(v, theta);
                assert!((change(w0, p0, dw, d) / first - 1.0).abs() < 1e-8);
            }
        }
    }

    #[test]
    fn slip_velocity_inverts_mu() {
        for law in [ln2_law(), corrected_law()] {
            for (v, theta) in [(1e-6, 1e6), (1.0, 1.0), (3e3, 2e-4)] {
                let s = law.mu(v, theta);
                assert!((law.slip_velocity(s, theta).unwrap() / v - 1.0).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn without_mu_vv_the_rising_root_is_the_linear_one_to_the_last_bit() {
        for (b, c) in [(0.012, 0.3), (0.012, -7.1e-3), (3.0, 1e-300), (1e-90, -2.0)] {
            assert_eq!(rising_root(0.0, b, c), Some(c / b));
        }
        // No root where the slope is not positive.
        assert_eq!(rising_root(0.0, -0.01, 1.0), None);
        assert_eq!(rising_root(0.0, 0.0, 1.0), None);
    }

    #[test]
    fn the_rising_root_solves_the_quadratic_on_its_rising_branch() {
        // Both formulas (|4ac/b^2| <= 1 and beyond, b of either sign):
        // a x^2 + b x = c with 2 a x + b > 0.
        for (a, b, c) in [
            (3e-4, 0.012, 0.05),
            (3e-4, 0.012, -0.11),
            (-3e-4, 0.012, 0.1),
            (3e-4, -0.012, 0.02),
            (3e-4, -0.012, -0.1),
            (-3e-4, -0.012, -0.1),
            (3e-4, 1e-9, 0.2),
        ] {
            let x: f64 = rising_root(a, b, c).unwrap();
            assert!(2.0 * a * x + b > 0.0, "{a} {b} {c}");
            let size = (a * x * x).abs() + (b * x).abs() + c.abs();
            assert!((a * x * x + b * x - c).abs() < 1e-15 * size, "{a} {b} {c}");
        }
        // No root: beyond the vertex of the parabola (discriminant < 0).
        assert_eq!(rising_root(3e-4, 0.012, -0.2), None);
        assert_eq!(rising_root(-3e-4, 0.012, 0.2), None);
    }

    #[test]
    fn the_damped_root_is_the_smallest_on_a_rising_branch() {
        // F(x) = a x^2 + b x + e expm1(x) - gap; each case's root checked
        // by its residual (relative to the terms) and its rising slope.
        let check = |a: f64, b: f64, e: f64, gap: f64| {
            let x = damped_root(a, b, e, gap).unwrap();
            let f = a * x * x + b * x + e * x.exp_m1() - gap;
            // The terms' rounding, and x's own (its ulp times the slope).
            let slope = 2.0 * a * x + b + e * x.exp();
            let size = (a * x * x).abs() + (b * x).abs() + (e * x.exp_m1()).abs() + gap.abs();
            let bound = 8.0 * f64::EPSILON * (size + slope * x.abs());
            assert!(f.abs() <= bound, "{a} {b} {e} {gap}: {f:e}");
            assert!(slope > 0.0, "{a} {b} {e} {gap}");
            x
        };
        // a = 0, b > 0 and b = 0: monotone everywhere; b < 0: beyond x1.
        check(0.0, 0.012, 1e-3, 0.3);
        check(0.0, 0.0, 1e-3, 2.0);
        let x = check(0.0, -0.01, 1e-3, 0.5);
        assert!(x > (0.01f64 / 1e-3).ln());
        assert_eq!(damped_root(0.0, 0.0, 1e-3, -2e-3), None);
        // a > 0: convex, the larger root; none below the minimum.
        let x = check(3e-4, 0.012, 1e-6, -0.05);
        assert!(2.0 * 3e-4 * x + 0.012 > -1e-6 * x.exp());
        assert_eq!(damped_root(3e-4, 0.012, 1e-6, -0.2), None);
        // a < 0, two rising branches (F'(x_c) = -2.3e-3 < 0 at x_c =
        // ln(-2a/e) = 24.8; F(x1) = 0.12 near the undamped vertex x = 20):
        // the low one (the undamped law's) while F(x1) > gap, else the high.
        let (a, b, e) = (-3e-4, 0.012, 1e-14);
        assert!(check(a, b, 1e-6, 0.2) > 0.0, "monotone: one root");
        let low = check(a, b, e, 0.1);
        assert!(low < (-2.0 * a / e).ln() && low < -b / (2.0 * a));
        let high = check(a, b, e, 0.2);
        assert!(high > (-2.0 * a / e).ln());
        // Huge forces: ln v of a few hundred, no overflow.
        let x = check(0.0, 0.012, 1e-6, 1e300);
        assert!((x - (1e306f64).ln()).abs() < 1e-9, "{x}");
        assert_eq!(damped_root(0.0, 0.012, f64::NAN, 0.1), None);
    }

    #[test]
    fn the_damped_inversion_carries_exact_derivatives() {
        // d ln v / d eta_d = -e^L... by implicit differentiation of
        // b L + eta (e^L - 1) = c: dL/deta = -(e^L - 1) / (b + eta e^L),
        // dL/dc = 1 / (b + eta e^L); at eta = 1e-3 and at eta = 0 (the
        // quadratic's root with the damping's derivative).
        use num_dual::Dual64;
        for eta in [1e-3, 0.0] {
            let law = FrictionLaw {
                eta: Dual64::new(eta, 1.0),
                mu0: Dual64::from(0.6),
                a: Dual64::from(0.012),
                ageing: Ageing::Log {
                    b: Dual64::from(0.023),
                    mu2: Dual64::from(0.0),
                    mu_vv: Dual64::from(0.0),
                    mu_vphi: Dual64::from(0.0),
                },
            };
            let gap = Dual64::new(0.05, 0.0);
            let l = law
                .ln_velocity_change(Dual64::from(0.0), Dual64::from(0.0), gap)
                .unwrap();
            let el = l.re.exp();
            assert!((0.012 * l.re + eta * (el - 1.0) - 0.05).abs() < 1e-16);
            let expect = -(el - 1.0) / (0.012 + eta * el);
            assert!(
                (l.eps / expect - 1.0).abs() < 1e-12,
                "{eta}: {} vs {expect}",
                l.eps
            );
        }
        // Without damping the inversion is the quadratic's, to the last bit.
        let plain = corrected_law();
        for (w, p, gap) in [(0.3, -1.2, 0.02), (-2.0, 4.0, -0.03)] {
            assert_eq!(
                plain.ln_velocity_change(w, p, gap),
                rising_root(3e-4, plain.rate_coefficient(2.0 * w, p), gap)
            );
        }
    }

    #[test]
    fn a_friction_beyond_the_law_has_no_slip_velocity() {
        // mu_vv > 0: mu(., theta = 1) = mu0 + A L + mu_vv L^2 is lowest at
        // L = -A / (2 mu_vv) = -20, mu0 - A^2 / (4 mu_vv) = 0.48.
        let law = corrected_law();
        let e = law.slip_velocity(0.47, 1.0).unwrap_err();
        assert_eq!(
            e,
            NoSlipVelocity {
                s: 0.47,
                theta: 1.0
            }
        );
        assert!(e.to_string().contains("mu_vv"), "{e}");
        assert!(law.slip_velocity(0.481, 1.0).is_ok());
    }

    #[test]
    fn cutoff_steady_friction_is_minimal_at_v_min() {
        let law = FrictionLaw {
            mu0: 0.4,
            a: 0.012,
            eta: 0.0,
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

    #[test]
    fn log_steady_friction_is_minimal_at_v_min() {
        // (A - B) + 2 (mu2 + mu_vv - mu_vphi) ln nu = 0 at ln nu = 0.011 / 1.48e-3.
        let law = corrected_law();
        let v_min = law.v_min().unwrap();
        assert!((v_min.ln() - 0.011 / 1.48e-3).abs() < 1e-13);
        assert!(law.steady_slope(v_min).abs() < 1e-15);
        assert!(law.steady_slope(0.5 * v_min) < 0.0 && law.steady_slope(2.0 * v_min) > 0.0);
        let ln2_min = ln2_law().v_min().unwrap().ln();
        assert!((ln2_min - 0.011 / 4.8e-4).abs() < 1e-13, "{ln2_min}");
    }
}
