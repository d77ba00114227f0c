//! The step-size loop of RADAU5: Jacobian and factorisation reuse, step
//! acceptance and rejection, the end of the interval, and the failure modes.

use super::error::{IntegrateError, NewtonTrouble};
use super::record::Recorder;
use super::setup::{initial_step, validate};
use super::step::{Newton, NewtonControl, Work};
use super::{Outcome, Output, Radau5, Solution, Stats, StepView};
use crate::system::VectorField;
use std::ops::ControlFlow;

/// What the loop does next (RADAU5's labels 10, 20, 30).
#[derive(Clone, Copy, PartialEq, Eq)]
enum Next {
    /// Evaluate the Jacobian, then factor, then step.
    Jacobian,
    /// Factor the iteration matrices for the current `h`, then step.
    Factor,
    /// Step with the current factors.
    Step,
}

/// Runs the integration (see [`Radau5::solve_with`]).
pub(super) fn run<S: VectorField>(
    solver: &mut Radau5<'_, S>,
    t0: f64,
    x0: &[f64],
    t_end: f64,
    output: Output,
    mut observer: impl FnMut(&StepView<'_>) -> ControlFlow<()>,
) -> Solution {
    let mut sol = Solution {
        t: Vec::new(),
        x: Vec::new(),
        events: Vec::new(),
        t_final: t0,
        x_final: x0.to_vec(),
        outcome: Outcome::ReachedEnd,
        stats: Stats::default(),
    };
    let mut stats = Stats::default();
    let result = integrate(
        solver,
        (t0, x0, t_end),
        output,
        &mut observer,
        &mut sol,
        &mut stats,
    );
    sol.stats = stats;
    sol.outcome = match result {
        Ok(outcome) => outcome,
        Err(e) => Outcome::Failed(e),
    };
    sol
}

fn integrate<S: VectorField>(
    solver: &mut Radau5<'_, S>,
    (t0, x0, t_end): (f64, &[f64], f64),
    output: Output,
    observer: &mut impl FnMut(&StepView<'_>) -> ControlFlow<()>,
    sol: &mut Solution,
    stats: &mut Stats,
) -> Result<Outcome, IntegrateError> {
    let Radau5 {
        sys,
        p,
        settings: s,
        events,
    } = solver;
    let (sys, p, s) = (*sys, p.as_slice(), &*s);
    let atol_user = validate(sys, p, s, (t0, x0, t_end), &output)?;
    let dir = if t_end >= t0 { 1.0 } else { -1.0 };
    let mut rec = Recorder::start(output, events, t0, x0, dir, sol)?;
    let n = x0.len();
    let mut w = Work::new(n);
    w.y.copy_from_slice(x0);
    sys.rhs(&w.y, p, &mut w.f0);
    stats.rhs_evals += 1;
    if let Some(index) = w.f0.iter().position(|v| !v.is_finite()) {
        return Err(IntegrateError::NonFiniteRhs {
            t: t0,
            h: 0.0,
            index,
        });
    }
    if t0 == t_end {
        return Ok(Outcome::ReachedEnd);
    }
    // RADAU5's tolerance transformation (see the module documentation).
    let rtol = 0.1 * s.rtol.powf(2.0 / 3.0);
    let atol: Vec<f64> = atol_user.iter().map(|a| a * rtol / s.rtol).collect();
    w.update_scale(rtol, &atol);
    let nit = s.newton_max_iter;
    let mut ctl = NewtonControl {
        fnewt: (10.0 * f64::EPSILON / rtol).max(rtol.sqrt().min(0.03)),
        max_iter: nit,
        theta_keep: s.jac_reuse_theta,
        faccon: 1.0,
        theta: s.jac_reuse_theta.abs(),
    };
    let cfac = s.safety * (1 + 2 * nit) as f64;
    let h_max = s.h_max.min((t_end - t0).abs());
    let mut h =
        s.h0.map_or_else(|| initial_step(x0, &w.f0, s.rtol, &atol_user), f64::abs)
            .min(h_max)
            * dir;
    let mut last = false;
    if (t0 + h * 1.0001 - t_end) * dir >= 0.0 {
        h = t_end - t0;
        last = true;
    }
    // The time reached is `t + t_lo`: `t` is its rounding, `t_lo` the
    // rounding error, carried by compensated summation (see `advance`). A long
    // run thus never loses its steps in the rounding of `t`: at `t = 2e7` a
    // step of `4e-8` is only ten units in the last place of `t`, and many
    // such steps summed into `t` alone would be off by several percent each.
    let (mut t, mut t_lo, mut h_old) = (t0, 0.0f64, h);
    let (mut first, mut reject, mut caljac) = (true, false, false);
    let (mut n_singular, mut newton_failures) = (0usize, 0usize);
    let (mut h_acc, mut err_acc) = (0.0f64, 0.0f64);
    let mut next = Next::Jacobian;
    // On failure, report the last accepted state.
    macro_rules! fail {
        ($e:expr) => {{
            sol.t_final = t;
            sol.x_final.copy_from_slice(&w.y);
            return Err($e);
        }};
    }
    loop {
        if next == Next::Jacobian {
            sys.jacobian(&w.y, p, &mut w.jac);
            stats.jacobians += 1;
            caljac = true;
            if w.jac.iter().any(|v| !v.is_finite()) {
                fail!(IntegrateError::NonFiniteJacobian { t, h });
            }
            next = Next::Factor;
        }
        if next == Next::Factor {
            stats.factorizations += 1;
            if w.decompose(h).is_err() {
                n_singular += 1;
                if n_singular >= 5 {
                    fail!(IntegrateError::SingularMatrix {
                        t,
                        h,
                        count: n_singular
                    });
                }
                h *= 0.5;
                (reject, last) = (true, false);
                next = if caljac { Next::Factor } else { Next::Jacobian };
                continue;
            }
        }
        stats.steps += 1;
        if stats.steps > s.max_steps {
            fail!(IntegrateError::MaxSteps {
                t,
                h,
                max_steps: s.max_steps
            });
        }
        if 0.1 * h.abs() <= time_floor(t) {
            let h_min = 10.0 * time_floor(t);
            let cause = "rounding level of the compensated time";
            fail!(IntegrateError::StepSizeUnderflow { t, h, h_min, cause });
        }
        if h.abs() < s.h_min && !last {
            let cause = "h_min";
            fail!(IntegrateError::StepSizeUnderflow {
                t,
                h,
                h_min: s.h_min,
                cause
            });
        }
        w.start_values(first, h, h_old);
        let shrink = match w.newton(sys, p, h, &mut ctl, &mut stats.rhs_evals) {
            Newton::Converged(k) => Ok(k),
            Newton::Shrink(factor) => Err((factor, None)),
            Newton::Failed(trouble) => Err((0.5, Some(trouble))),
        };
        let newt = match shrink {
            Ok(k) => k,
            Err((factor, trouble)) => {
                stats.newton_failures += 1;
                if let Some(cause) = trouble {
                    newton_failures += 1;
                    if newton_failures >= s.max_newton_failures {
                        let failures = newton_failures;
                        fail!(IntegrateError::NewtonFailed {
                            t,
                            h,
                            failures,
                            cause
                        });
                    }
                }
                h *= factor;
                (reject, last) = (true, false);
                next = if caljac { Next::Factor } else { Next::Jacobian };
                continue;
            }
        };
        let err = w.error_estimate(sys, p, h, first || reject, &mut stats.rhs_evals);
        if !err.is_finite() {
            newton_failures += 1;
            stats.newton_failures += 1;
            if newton_failures >= s.max_newton_failures {
                let (failures, cause) = (newton_failures, NewtonTrouble::NonFinite);
                fail!(IntegrateError::NewtonFailed {
                    t,
                    h,
                    failures,
                    cause
                });
            }
            h *= 0.5;
            (reject, last) = (true, false);
            next = if caljac { Next::Factor } else { Next::Jacobian };
            continue;
        }
        let fac = s.safety.min(cfac / (newt + 2 * nit) as f64);
        let (q_lo, q_hi) = (1.0 / s.fac_max, 1.0 / s.fac_min);
        let mut quot = (err.powf(0.25) / fac).clamp(q_lo, q_hi);
        let mut h_new = h / quot;
        if err >= 1.0 {
            (reject, last) = (true, false);
            h = if first { 0.1 * h } else { h_new };
            stats.rejected += 1;
            next = if caljac { Next::Factor } else { Next::Jacobian };
            continue;
        }
        // Accepted.
        first = false;
        newton_failures = 0;
        stats.accepted += 1;
        if s.predictive {
            if stats.accepted > 1 {
                let facgus =
                    ((h_acc / h) * (err * err / err_acc).powf(0.25) / s.safety).clamp(q_lo, q_hi);
                quot = quot.max(facgus);
                h_new = h / quot;
            }
            h_acc = h;
            err_acc = err.max(1e-2);
        }
        let t_prev = t;
        h_old = h;
        (t, t_lo) = if last {
            (t_end, 0.0)
        } else {
            advance(t, t_lo, h)
        };
        if ((t_end - t) - t_lo).abs() <= 16.0 * f64::EPSILON * t_end.abs() {
            // Within rounding of t_end: this step ends the integration.
            (t, t_lo, last) = (t_end, 0.0, true);
        }
        w.accept();
        w.update_scale(rtol, &atol);
        let dense = w.dense(t, t_lo, h);
        if let Some(outcome) = rec.step(events, s, dense, (t_prev, t, h), &w.y, sol, observer)? {
            return Ok(outcome);
        }
        if last {
            sol.t_final = t_end;
            sol.x_final.copy_from_slice(&w.y);
            return Ok(Outcome::ReachedEnd);
        }
        caljac = false;
        sys.rhs(&w.y, p, &mut w.f0);
        stats.rhs_evals += 1;
        if let Some(index) = w.f0.iter().position(|v| !v.is_finite()) {
            fail!(IntegrateError::NonFiniteRhs { t, h, index });
        }
        h_new = dir * h_new.abs().min(h_max);
        if reject {
            h_new = dir * h_new.abs().min(h.abs());
        }
        reject = false;
        let (keep_lo, keep_hi) = s.keep_h_ratio;
        let keep_jac = ctl.theta <= s.jac_reuse_theta;
        // The rest of the interval, from the compensated time.
        let rest = (t_end - t) - t_lo;
        if (h_new / keep_lo - rest) * dir >= 0.0 {
            h = rest;
            last = true;
        } else {
            let qt = h_new / h;
            if keep_jac && qt >= keep_lo && qt <= keep_hi {
                next = Next::Step;
                continue;
            }
            h = h_new;
        }
        next = if keep_jac {
            Next::Factor
        } else {
            Next::Jacobian
        };
    }
}

/// `t + t_lo + h` as a new compensated pair `(hi, lo)`, `hi` the rounding of
/// the sum and `lo` its error: Knuth's two-sum of `t` and `h + t_lo` (the
/// latter rounded relative to `h`, so each step adds an error of the order of
/// `eps |h|`, never `eps |t|`).
fn advance(t: f64, t_lo: f64, h: f64) -> (f64, f64) {
    let inc = h + t_lo;
    let hi = t + inc;
    let back = hi - t;
    let lo = (t - (hi - back)) + (inc - back);
    (hi, lo)
}

/// The step size below which `0.1 |h|` no longer moves the compensated time
/// `t + t_lo` reliably: the rounding level of its low part, `eps^2 |t|` (at
/// least the smallest normal number, so that `h` never reaches zero).
fn time_floor(t: f64) -> f64 {
    (f64::EPSILON * f64::EPSILON * t.abs()).max(f64::MIN_POSITIVE)
}

#[cfg(test)]
mod tests {
    use super::advance;

    /// A million steps of `1.3e-8` from `t = 2e7`, each 3.5 units in the last
    /// place of `t`: the compensated time advances by the sum of the steps to
    /// rounding, where the plain sum (each step rounded to 3 units) is off by
    /// about 14 %.
    #[test]
    fn compensated_time_keeps_steps_below_the_rounding_of_t() {
        let (t0, h, n) = (2e7f64, 1.3e-8, 1_000_000u32);
        let (mut t, mut lo, mut plain) = (t0, 0.0f64, t0);
        for _ in 0..n {
            (t, lo) = advance(t, lo, h);
            plain += h;
        }
        let elapsed = f64::from(n) * h;
        let compensated = ((t - t0) + lo) / elapsed - 1.0;
        assert!(compensated.abs() <= 1e-9, "compensated: {compensated:e}");
        assert!((plain - t0) / elapsed - 1.0 < -0.1, "plain: {}", plain - t0);
    }
}
