//! The engine's one root finder: the Illinois variant of regula falsi
//! (Dowell & Jarratt 1971, BIT 11, 168–174) on a bracket.
//!
//! Each trial replaces the latest end; where it lands on the same side of
//! the root as the latest end, the value kept at the stale end is halved,
//! which makes regula falsi superlinear (order about 1.44) instead of
//! sliding along one end. A trial outside the bracket (rounding, or values
//! of wildly different sizes) falls back to bisection.
//!
//! The function may fail (a trial point that must first be corrected onto a
//! curve): its error ends the search and is returned. A value of exactly
//! zero ends it too, so a caller can stop where the value is below its own
//! rounding bound by returning `0.0` there.
//!
//! Used for events of time integration, folds, multiplier crossings and
//! user points on cycle branches, and Bautin points on Hopf curves.

/// A bracket `(x, f(x))` at both ends, `b` the latest trial.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bracket {
    pub a: (f64, f64),
    pub b: (f64, f64),
}

impl Bracket {
    /// The end whose value has the sign of `reference` (or is zero): after
    /// the search, the side of the root the caller asks for.
    pub fn end_signed_like(&self, reference: f64) -> f64 {
        let same = |f: f64| f == 0.0 || (f > 0.0) == (reference > 0.0);
        if same(self.b.1) {
            self.b.0
        } else {
            self.a.0
        }
    }
}

/// Narrows the bracket `a`, `b` (values of opposite signs, or one zero) of
/// `f` until its width is at most `tol`, the latest value is exactly zero, the two
/// ends are adjacent floating-point numbers, a value is not finite, or
/// after `max_iter` trials. Returns the final bracket; `b` is the latest
/// trial. `a.0` may exceed `b.0`.
pub fn illinois<E>(
    mut f: impl FnMut(f64) -> Result<f64, E>,
    a: (f64, f64),
    b: (f64, f64),
    tol: f64,
    max_iter: usize,
) -> Result<Bracket, E> {
    let mut br = Bracket { a, b };
    for _ in 0..max_iter {
        let ((xa, fa), (xb, fb)) = (br.a, br.b);
        if fb == 0.0 || (xb - xa).abs() <= tol {
            break;
        }
        let (lo, hi) = if xa < xb { (xa, xb) } else { (xb, xa) };
        let mut x = xb - fb * (xb - xa) / (fb - fa);
        if !(x > lo && x < hi) {
            x = 0.5 * (xa + xb);
            if !(x > lo && x < hi) {
                break; // adjacent floating-point numbers
            }
        }
        let fx = f(x)?;
        if !fx.is_finite() {
            break;
        }
        if (fx > 0.0) == (fb > 0.0) {
            // Same side as the latest end: the stale end's value is halved.
            br.a.1 *= 0.5;
        } else {
            br.a = br.b;
        }
        br.b = (x, fx);
    }
    Ok(br)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::convert::Infallible;

    fn root(f: impl Fn(f64) -> f64, a: f64, b: f64, tol: f64) -> (Bracket, usize) {
        let mut calls = 0;
        let br = illinois(
            |x| {
                calls += 1;
                Ok::<_, Infallible>(f(x))
            },
            (a, f(a)),
            (b, f(b)),
            tol,
            200,
        )
        .unwrap();
        (br, calls)
    }

    /// `cos t = t` (root 0.7390851332151607, Dottie's number) from either
    /// end, and a triple root, where plain regula falsi crawls.
    #[test]
    fn finds_roots_from_either_side_and_superlinearly() {
        let f = |t: f64| t.cos() - t;
        let dottie = 0.739_085_133_215_160_6;
        for (a, b) in [(0.0, 1.0), (1.0, 0.0)] {
            let (br, calls) = root(f, a, b, 1e-14);
            assert!((br.b.0 - dottie).abs() < 2e-14, "{br:?}");
            assert!(calls < 12, "{calls} calls");
        }
        let g = |t: f64| (t - 0.3).powi(3);
        let (br, _) = root(g, 0.0, 2.0, 1e-13);
        assert!((br.b.0 - 0.3).abs() < 1e-13, "{br:?}");
    }

    #[test]
    fn returns_the_end_on_the_asked_side() {
        let f = |t: f64| t - 0.5;
        let (br, _) = root(f, 0.0, 1.0, 1e-3);
        assert!(br.end_signed_like(1.0) >= 0.5);
        assert!(br.end_signed_like(-1.0) <= 0.5);
    }

    #[test]
    fn an_error_of_the_function_ends_the_search() {
        let r = illinois(
            |x| {
                if (x - 0.5).abs() < 0.1 {
                    Err("diverged")
                } else {
                    Ok(x - 0.5)
                }
            },
            (0.0, -0.5),
            (1.0, 0.5),
            1e-12,
            50,
        );
        assert_eq!(r, Err("diverged"));
    }
}
