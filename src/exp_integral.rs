//! The exponential integral `E1` and Schallamach's lifetime function
//! `g(z) = e^z E1(z)` (seed Appendix D, eq. D7: the mean bond lifetime is
//! `t = tau_out z g(z)`), exact on every scalar of the engine.
//!
//! With `h_n(z) = e^z E_n(z)` (`E_n` the generalized exponential integral,
//! `E_n(z) = int_1^inf e^(-z t) t^(-n) dt`) and `g = h_1`,
//!
//! ```text
//! g(z)       = int_0^inf e^(-t) / (z + t) dt,
//! g^(k)(z)   = (-1)^k k! z^(-k) h_(k+1)(z),        (g' = g - 1/z)
//! ```
//!
//! the second line being the recurrence `g' = g - 1/z` (`E_n' = -E_(n-1)`)
//! carried to every order. A dual number `z = z0 + d` (`d` nilpotent of
//! order `NDERIV + 1`) gets the Taylor series `sum_k (-d / z0)^k h_(k+1)(z0)`
//! to its last nonvanishing term: all its derivatives are exact to
//! rounding, whatever the order.
//!
//! `h_n` is computed without cancellation: for `z <= 1` the series of `E1`
//! and the upward recurrence `h_(n+1) = (1 - z h_n) / n` (stable there);
//! for `z > 1` the continued fraction of `E_n` (modified Lentz), which
//! needs no recurrence. Tested against 40-digit mpmath values for
//! `1e-8 <= z <= 1e3` (`docs/reference/exp_integral.py`,
//! `tests/adhesive.rs`).

use continuation::Scalar;

/// Euler's constant `gamma`.
const EULER_GAMMA: f64 = 0.577_215_664_901_532_9;

/// `h_n(z) = e^z E_n(z)` for `n >= 1`, `z > 0` (NaN otherwise: the callers
/// pass `z = V_s / v` with `v > 0`).
pub fn scaled_en(n: usize, z: f64) -> f64 {
    if z.is_nan() || z <= 0.0 || n == 0 {
        return f64::NAN;
    }
    if z.is_infinite() {
        return 0.0;
    }
    if z <= 1.0 {
        let mut h = z.exp() * e1_series(z);
        for k in 1..n {
            h = (1.0 - z * h) / k as f64;
        }
        h
    } else {
        continued_fraction(n, z)
    }
}

/// `E1(z)` for `0 < z <= 1`: `-gamma - ln z - sum_(k>=1) (-z)^k / (k k!)`.
fn e1_series(z: f64) -> f64 {
    let (mut sum, mut term) = (0.0, 1.0);
    for k in 1..60 {
        term *= -z / k as f64;
        let add = term / k as f64;
        sum += add;
        if add.abs() <= 1e-18 * sum.abs() {
            break;
        }
    }
    -EULER_GAMMA - z.ln() - sum
}

/// `e^z E_n(z)` for `z > 1` by the continued fraction
/// `1 / (z + n - 1 n / (z + n + 2 - 2 (n + 1) / (z + n + 4 - ...)))`,
/// evaluated by the modified Lentz method.
fn continued_fraction(n: usize, z: f64) -> f64 {
    const TINY: f64 = 1e-300;
    let nm1 = (n - 1) as f64;
    let mut b = z + n as f64;
    let mut c = 1.0 / TINY;
    let mut d = 1.0 / b;
    let mut h = d;
    for i in 1..10_000 {
        let a = -(i as f64) * (nm1 + i as f64);
        b += 2.0;
        d = 1.0 / (a * d + b);
        c = b + a / c;
        let del = c * d;
        h *= del;
        if (del - 1.0).abs() <= f64::EPSILON {
            break;
        }
    }
    h
}

/// The exponential integral `E1(z) = int_z^inf e^(-t) / t dt`, `z > 0`
/// (underflows to 0 beyond `z` of about 740; use [`scaled_e1`] there).
pub fn e1(z: f64) -> f64 {
    (-z).exp() * scaled_en(1, z)
}

/// `g(z) = e^z E1(z)` on any scalar, with exact derivatives of every order
/// (module documentation).
pub fn scaled_e1<D: Scalar>(z: D) -> D {
    taylor(z, |k, z0| scaled_en(k + 1, z0))
}

/// `1 - z g(z) = -z g'(z) = h_2(z)` on any scalar, computed without the
/// cancellation of its left-hand form at large `z`: the Taylor coefficients
/// of `-z g'` are `(-1/z0)^k ((k + 1) h_(k+2) - k h_(k+1))`.
pub fn one_minus_z_scaled_e1<D: Scalar>(z: D) -> D {
    taylor(z, |k, z0| {
        (k as f64 + 1.0) * scaled_en(k + 2, z0) - k as f64 * scaled_en(k + 1, z0)
    })
}

/// `sum_(k=0)^NDERIV c_k(z0) (-(z - z0) / z0)^k` by Horner's rule, with
/// `c_k` given: the Taylor series of a function whose `k`-th derivative is
/// `(-1)^k k! z0^(-k) c_k(z0)`, to the dual number's last order.
fn taylor<D: Scalar>(z: D, c: impl Fn(usize, f64) -> f64) -> D {
    let z0 = z.re();
    let step = -(z - z0) / z0;
    let mut sum = D::from(c(D::NDERIV, z0));
    for k in (0..D::NDERIV).rev() {
        sum = sum * step + c(k, z0);
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::*;
    use num_dual::{Dual2_64, Dual64};

    #[test]
    fn the_recurrence_g_prime_is_g_minus_one_over_z_holds_on_duals() {
        for z0 in [1e-6, 0.3, 1.0, 1.5, 40.0, 900.0] {
            let g = scaled_e1(Dual64::from(z0).derivative());
            // g - 1/z cancels at large z: its rounding is that of g and 1/z.
            let expected = g.re - 1.0 / z0;
            let rounding = 4.0 * f64::EPSILON * (g.re.abs() + 1.0 / z0);
            assert!(
                (g.eps - expected).abs() <= rounding + 1e-14 * expected.abs(),
                "z = {z0}: {} vs {expected}",
                g.eps
            );
            let q = one_minus_z_scaled_e1(Dual2_64::from(z0).derivative());
            // (1 - z g)' = -g - z g' = -g - z (g - 1/z) = 1 - (1 + z) g.
            let g0 = scaled_en(1, z0);
            let slope = 1.0 - (1.0 + z0) * g0;
            assert!(
                (q.v1 - slope).abs() <= 1e-9 * slope.abs().max(1e-300),
                "z = {z0}"
            );
        }
    }

    #[test]
    fn outside_the_domain_is_nan_not_a_number_that_looks_right() {
        assert!(scaled_en(1, 0.0).is_nan() && scaled_en(1, -1.0).is_nan());
        assert_eq!(scaled_en(3, f64::INFINITY), 0.0);
    }
}
