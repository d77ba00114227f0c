//! A stick-slip cycle by a different method than collocation: long-time
//! integration (Radau IIA) from perturbed steady sliding onto the attractor.
//! The reference of the cycle-branch jobs and of the work-precision study.

use stickslip::analysis::simulate::{cycle_by_integration, simulate_with, Segment};
use stickslip::error::Error;
use stickslip::model::{full_state, steady_state, ModelKind};
use stickslip::params::Params;

/// How [`reference_cycle`] computes, in one line.
pub const REFERENCE: &str = "Radau IIA, rtol 1e-13, 150 periods from steady sliding with the age 10 % off, 8 periods averaged";

/// Relative tolerance of the reference integration.
const RTOL: f64 = 1e-13;
/// Periods of transient before the measurement: the start is forgotten at
/// the rate of the largest nontrivial multiplier (below 0.8 per period on
/// the cycles measured here, and `0.8^150 ~ 3e-15`).
const TRANSIENT_PERIODS: f64 = 150.0;
/// Periods per integration segment (each is limited to 100 000 steps; a
/// quasi-static PMMA period takes about 1 600 at `rtol = 1e-13`).
const SEGMENT_PERIODS: f64 = 30.0;
/// Periods averaged.
const MEASURED_PERIODS: usize = 8;

/// Period and peak-to-peak spring force of a stick-slip cycle by integration.
#[derive(Clone, Copy, Debug)]
pub struct ReferenceCycle {
    /// Period, averaged over the measured periods.
    pub period: f64,
    /// Peak-to-peak spring force.
    pub delta_s: f64,
    /// The period's own uncertainty (relative): the largest change when the
    /// tolerance is loosened to `1e-12` or the transient shortened by a third.
    pub period_spread: f64,
    /// The same for `delta_s`.
    pub delta_s_spread: f64,
}

/// The attractor of `params` (model `kind`) by long-time integration
/// ([`REFERENCE`]); `period` (of the cycle to be checked) sets the time
/// scale of the transient and of the measurement.
pub fn reference_cycle(
    kind: ModelKind,
    params: &Params,
    period: f64,
) -> Result<ReferenceCycle, Error> {
    let measure = |rtol: f64, transient: f64| integrate(kind, params, period, rtol, transient);
    let (period, delta_s) = measure(RTOL, TRANSIENT_PERIODS)?;
    let variants = [
        measure(10.0 * RTOL, TRANSIENT_PERIODS)?,
        measure(RTOL, TRANSIENT_PERIODS * 2.0 / 3.0)?,
    ];
    let spread = |value: fn(&(f64, f64)) -> f64, reference: f64| {
        variants
            .iter()
            .map(|v| (value(v) / reference - 1.0).abs())
            .fold(0.0, f64::max)
    };
    Ok(ReferenceCycle {
        period,
        delta_s,
        period_spread: spread(|v| v.0, period),
        delta_s_spread: spread(|v| v.1, delta_s),
    })
}

/// Period and `Delta_s` by integration at `rtol`, after `transient` periods
/// from steady sliding with the age 10 % off (see [`cycle_by_integration`]).
fn integrate(
    kind: ModelKind,
    p: &Params,
    period: f64,
    rtol: f64,
    transient: f64,
) -> Result<(f64, f64), Error> {
    let steady = full_state(kind, p, &steady_state(kind, p));
    let mut state = [steady[0], steady[1], 1.1 * steady[2]];
    let segment = Segment {
        nu: p.nu,
        duration: SEGMENT_PERIODS * period,
    };
    let segments = vec![segment; (transient / SEGMENT_PERIODS).ceil() as usize];
    simulate_with(kind, p, state, &segments, rtol, None, |x| {
        state = [x.s, x.v, x.theta];
        std::ops::ControlFlow::Continue(())
    })?;
    Ok(cycle_by_integration(
        kind,
        p,
        state,
        period,
        (MEASURED_PERIODS as f64 + 2.0) * period,
        MEASURED_PERIODS,
        rtol,
    )?)
}
