//! Input validation and the initial step size.

use super::{IntegrateError, Output, Settings};
use crate::system::VectorField;

fn invalid(what: String, hint: &'static str) -> IntegrateError {
    IntegrateError::InvalidInput { what, hint }
}

/// Checks the input and returns the per-component absolute tolerances.
pub(super) fn validate<S: VectorField>(
    sys: &S,
    p: &[f64],
    s: &Settings,
    (t0, x0, t_end): (f64, &[f64], f64),
    output: &Output,
) -> Result<Vec<f64>, IntegrateError> {
    let n = sys.dim();
    if x0.len() != n {
        return Err(invalid(
            format!(
                "x0 has length {} but the system has dimension {n}",
                x0.len()
            ),
            "pass one initial value per state variable",
        ));
    }
    if p.len() != sys.n_params() {
        return Err(invalid(
            format!(
                "p has length {} but the system has {} parameters",
                p.len(),
                sys.n_params()
            ),
            "pass one value per parameter",
        ));
    }
    if let Some((index, &value)) = x0.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(IntegrateError::NonFiniteState {
            t: t0,
            index,
            value,
        });
    }
    if !t0.is_finite() || !t_end.is_finite() {
        return Err(invalid(
            format!("the time span [{t0}, {t_end}] is not finite"),
            "give finite start and end times",
        ));
    }
    if !(s.rtol > 1e-14 && s.rtol < 1.0 && s.atol >= 0.0 && s.atol.is_finite()) {
        return Err(invalid(
            format!("rtol = {:e}, atol = {:e}", s.rtol, s.atol),
            "use 1e-14 < rtol < 1 and a finite atol >= 0",
        ));
    }
    let atol = match &s.atol_components {
        Some(a) if a.len() != n || a.iter().any(|v| !(*v >= 0.0 && v.is_finite())) => {
            return Err(invalid(
                format!("atol_components = {a:?} for dimension {n}"),
                "give n finite non-negative absolute tolerances",
            ))
        }
        Some(a) => a.clone(),
        None => vec![s.atol; n],
    };
    let ok = s.safety > 0.0
        && s.safety < 1.0
        && s.fac_min > 0.0
        && s.fac_min <= 1.0
        && s.fac_max >= 1.0
        && s.newton_max_iter >= 1
        && s.max_newton_failures >= 1
        && s.h_min >= 0.0
        && s.h_max > 0.0
        && s.event_tol > 0.0
        && s.h0.is_none_or(|h| h.is_finite() && h != 0.0);
    if !ok {
        return Err(invalid(
            format!("settings out of range: {s:?}"),
            "use 0 < safety < 1, 0 < fac_min <= 1 <= fac_max, newton_max_iter >= 1, \
             max_newton_failures >= 1, h_min >= 0, h_max > 0, event_tol > 0, h0 finite non-zero",
        ));
    }
    if let Output::Grid(grid) = output {
        let dir = if t_end >= t0 { 1.0 } else { -1.0 };
        let inside = |t: f64| (t - t0) * dir >= 0.0 && (t_end - t) * dir >= 0.0;
        if grid.iter().any(|&t| !inside(t)) || grid.windows(2).any(|w| (w[1] - w[0]) * dir < 0.0) {
            return Err(invalid(
                format!("the output grid is not monotone inside [{t0}, {t_end}]"),
                "sort the grid in the direction of integration and keep it inside the interval",
            ));
        }
    }
    Ok(atol)
}

/// The initial step: `0.01 |x0|_w / |f(x0)|_w` (weighted RMS norms with the
/// user's tolerances), or `1e-6` when either norm is tiny.
pub(super) fn initial_step(x0: &[f64], f0: &[f64], rtol: f64, atol: &[f64]) -> f64 {
    let norm = |v: &[f64]| {
        let s: f64 = v
            .iter()
            .zip(x0)
            .zip(atol)
            .map(|((vi, xi), ai)| (vi / (ai + rtol * xi.abs())).powi(2))
            .sum();
        (s / v.len().max(1) as f64).sqrt()
    };
    let (d0, d1) = (norm(x0), norm(f0));
    let h = if d0 < 1e-5 || d1 < 1e-5 {
        1e-6
    } else {
        0.01 * d0 / d1
    };
    if h.is_finite() && h > 0.0 {
        h
    } else {
        1e-6
    }
}
