//! Time integration of the driven block under a driving protocol: steady
//! pulling, velocity jumps, stop-and-go. Integrated in logarithmic variables
//! (slip velocity and age span decades) by the engine's Radau IIA method.

use crate::error::NumericalError;
use crate::log_model::LogBlock;
use crate::model::ModelKind;
use crate::params::Params;
use continuation::integrate::{self, EventDirection, EventFunction, Output, Radau5, Settings};

/// A stretch of constant driving velocity `nu` lasting `duration` (units `D0/V0`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment {
    pub nu: f64,
    pub duration: f64,
}

/// A simulated trajectory in MODEL.md's variables.
#[derive(Clone, Debug, Default)]
pub struct Trajectory {
    pub t: Vec<f64>,
    pub s: Vec<f64>,
    pub v: Vec<f64>,
    pub theta: Vec<f64>,
    /// Slip `x(t) - x(0)` in units of `D0`, from `s = kappa (int nu dt - x)`.
    pub slip: Vec<f64>,
}

/// Integrates from the state `(s, v, theta)` through the protocol, recording
/// every accepted step, or the dense output at the times of `grid` when given
/// (absolute times from 0). `rtol` is the integrator's relative tolerance.
pub fn simulate(
    kind: ModelKind,
    params: &Params,
    start: [f64; 3],
    protocol: &[Segment],
    rtol: f64,
    grid: Option<&[f64]>,
) -> Result<Trajectory, NumericalError> {
    let log = LogBlock {
        kind,
        cutoff: params.theta_c.is_some(),
    };
    let mut x = log.from_model(start[0], start[1], start[2]);
    let (mut t0, mut pulled) = (0.0, 0.0);
    let mut out = Trajectory::default();
    for seg in protocol {
        let mut p = *params;
        p.nu = seg.nu;
        let pv = p.to_vec();
        let settings = Settings {
            rtol,
            atol: rtol * 1e-3,
            ..Settings::default()
        };
        let t1 = t0 + seg.duration;
        let output = match grid {
            Some(g) => Output::Grid(g.iter().copied().filter(|&t| t >= t0 && t <= t1).collect()),
            None => Output::Steps,
        };
        let sol = Radau5::new(&log, &pv, settings).solve(t0, &x, t1, output);
        let sol = sol
            .into_result()
            .map_err(|e| NumericalError::Analysis(format!("simulation at nu = {}: {e}", seg.nu)))?;
        for (t, y) in sol.t.iter().zip(&sol.x) {
            if t == &t0 && !out.t.is_empty() {
                continue;
            }
            let [s, v, theta] = log.to_model(y, &pv);
            out.t.push(*t);
            out.s.push(s);
            out.v.push(v);
            out.theta.push(theta);
            out.slip
                .push(pulled + seg.nu * (t - t0) - (s - start[0]) / params.kappa);
        }
        pulled += seg.nu * seg.duration;
        t0 = sol.t_final;
        x = sol.x_final;
    }
    Ok(out)
}

/// Period and peak-to-peak spring force of the attractor reached from `start`
/// at fixed parameters, by integration: after `transient` time, over
/// `horizon` more, the extremes of `s` are located as events `v = nu` (where
/// `ds/dt = 0`) and the period as the time between successive maxima.
/// Returns `(period, delta_s)` averaged over the last `periods` cycles.
pub fn cycle_by_integration(
    kind: ModelKind,
    params: &Params,
    start: [f64; 3],
    transient: f64,
    horizon: f64,
    periods: usize,
    rtol: f64,
) -> Result<(f64, f64), NumericalError> {
    let log = LogBlock {
        kind,
        cutoff: params.theta_c.is_some(),
    };
    let pv = params.to_vec();
    let ln_nu = params.nu.ln();
    let settings = Settings {
        rtol,
        atol: rtol * 1e-3,
        ..Settings::default()
    };
    let fail = |e: integrate::IntegrateError| NumericalError::Analysis(format!("simulation: {e}"));
    let x0 = log.from_model(start[0], start[1], start[2]);
    let warm = Radau5::new(&log, &pv, settings.clone())
        .solve(0.0, &x0, transient, Output::Final)
        .into_result()
        .map_err(fail)?;
    // Slip velocity through nu (ds/dt = kappa (nu - v) changes sign): rising
    // marks a maximum of s, falling a minimum.
    let velocity = |x: &[f64]| -> f64 {
        match kind {
            ModelKind::Inertial => x[1] - ln_nu,
            ModelKind::QuasiStatic => log.to_model(x, &pv)[1].ln() - ln_nu,
        }
    };
    let mut solver = Radau5::new(&log, &pv, settings)
        .with_event(EventFunction::new(move |_, x| velocity(x)).direction(EventDirection::Any));
    let sol = solver
        .solve(0.0, &warm.x_final, horizon, Output::Final)
        .into_result()
        .map_err(fail)?;
    let s_at = |c: &integrate::Crossing| c.x[0];
    let maxima: Vec<&integrate::Crossing> = sol.events.iter().filter(|c| c.rising).collect();
    let minima: Vec<&integrate::Crossing> = sol.events.iter().filter(|c| !c.rising).collect();
    if maxima.len() < periods + 2 || minima.len() < periods + 1 {
        return Err(NumericalError::Analysis(format!(
            "only {} oscillations in the simulated time; the attractor may be steady sliding",
            maxima.len()
        )));
    }
    let last = &maxima[maxima.len() - periods - 1..];
    let period = (last[periods].t - last[0].t) / periods as f64;
    let smax = last.iter().map(|c| s_at(c)).sum::<f64>() / last.len() as f64;
    let lows = &minima[minima.len() - periods..];
    let smin = lows.iter().map(|c| s_at(c)).sum::<f64>() / lows.len() as f64;
    Ok((period, smax - smin))
}
