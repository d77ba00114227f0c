//! Driven sliding of the adhesive block in time (Radau IIA, the engine's
//! integrator) under a protocol of pulling velocities, with the extremes of
//! the spring force located as events: the maxima where the slip velocity
//! rises through the pulling velocity (`ds/dt = kappa (nu - u) = 0`), the
//! minima where it falls through it.

use crate::adhesive::block::AdhesiveModel;
use crate::adhesive::params::AdhesiveParams;
use continuation::integrate::{EventDirection, EventFunction, Outcome, Output, Radau5, Settings};
use std::ops::ControlFlow;

/// One stretch of the protocol, dimensionless: pulling velocity `nu`
/// (0 stops the drive) for `duration` (units `tau_out`).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Segment {
    pub nu: f64,
    pub duration: f64,
}

/// A simulated run, dimensionless: every accepted step, the force extremes.
#[derive(Clone, Debug, Default)]
pub struct Run {
    pub t: Vec<f64>,
    pub s: Vec<f64>,
    pub u: Vec<f64>,
    pub n: Vec<f64>,
    /// Maxima and minima of the spring force, `(t, s)`, each with the index
    /// of its segment.
    pub maxima: Vec<(f64, f64, usize)>,
    pub minima: Vec<(f64, f64, usize)>,
    /// Why the run ended before the protocol's end (the integration failed,
    /// or `stop` asked it to); `None` when it ran to the end.
    pub stop: Option<String>,
    /// Whether `stop` ended it (a stop signal).
    pub interrupted: bool,
    /// The index in `t` of each segment's first step.
    pub segment_starts: Vec<usize>,
}

/// The settled stick-slip of the last segment: the last full cycle between
/// two force maxima.
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct SettledCycle {
    /// Period (units `tau_out`): between the last two maxima.
    pub period: f64,
    /// Force drop `s_max - s_min` over that cycle.
    pub force_drop: f64,
    /// The change of the period over the cycle before, relative: how
    /// settled the run is.
    pub period_change: f64,
}

/// Integrates `model` from `x0` (its state) through `protocol` at relative tolerance `rtol`,
/// with at most `max_steps` steps in all. `stop` is asked after every step
/// and ends the run there when it says so (a stop signal); a failed
/// integration ends it too. Either way the steps taken are kept and
/// [`Run::stop`] says why.
pub fn simulate<B: AdhesiveModel>(
    model: B,
    p: &AdhesiveParams,
    x0: &[f64],
    protocol: &[Segment],
    (rtol, max_steps): (f64, usize),
    stop: &dyn Fn() -> bool,
) -> Run {
    let mut run = Run::default();
    let (mut t0, mut x) = (0.0, x0.to_vec());
    for (index, seg) in protocol.iter().enumerate() {
        let mut q = *p;
        q.nu = seg.nu;
        let nu = seg.nu;
        let v = |_: f64, x: &[f64]| model.velocity(&q, x) - nu;
        let settings = Settings {
            rtol,
            atol: 1e-12,
            max_steps: max_steps.saturating_sub(run.t.len()).max(1),
            ..Settings::default()
        };
        let mut radau = Radau5::new(&model, &q.to_vec(), settings)
            .with_event(EventFunction::new(v).direction(EventDirection::Rising));
        radau.add_event(EventFunction::new(v).direction(EventDirection::Falling));
        run.segment_starts.push(run.t.len());
        let sol = radau.solve_with(t0, &x, t0 + seg.duration, Output::Steps, |_| {
            if stop() {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        });
        for (t, xs) in sol.t.iter().zip(&sol.x).skip(usize::from(index > 0)) {
            run.t.push(*t);
            run.s.push(xs[0]);
            run.n.push(model.bonds(xs));
            run.u.push(model.velocity(&q, xs));
        }
        for c in &sol.events {
            let list = if c.index == 0 {
                &mut run.maxima
            } else {
                &mut run.minima
            };
            list.push((c.t, c.x[0], index));
        }
        match sol.outcome {
            Outcome::Failed(e) => {
                run.stop = Some(format!(
                    "the integration stopped at t = {:.6e} tau_out in segment {} (V = {:e} V_s): \
                     {e}; try a larger --max-steps or a looser --rtol",
                    sol.t_final,
                    index + 1,
                    seg.nu
                ));
                return run;
            }
            Outcome::ObserverStop => {
                run.stop = Some(format!(
                    "stopped by a signal at t = {:.6e} tau_out in segment {}",
                    sol.t_final,
                    index + 1
                ));
                run.interrupted = true;
                return run;
            }
            _ => {}
        }
        t0 = sol.t_final;
        x = sol.x_final;
    }
    run
}

impl Run {
    /// The range `max s - min s` of the spring force over the last
    /// `fraction` of segment `segment`'s time (0 when it has no step).
    pub fn force_range(&self, segment: usize, fraction: f64) -> f64 {
        let Some((t0, t1)) = self.segment_times(segment) else {
            return 0.0;
        };
        let from = t1 - fraction * (t1 - t0);
        let (lo, hi) = self
            .t
            .iter()
            .zip(&self.s)
            .filter(|(t, _)| **t >= from && **t <= t1)
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), (_, s)| {
                (lo.min(*s), hi.max(*s))
            });
        if lo <= hi {
            hi - lo
        } else {
            0.0
        }
    }

    /// The first and last step times of segment `segment`.
    fn segment_times(&self, segment: usize) -> Option<(f64, f64)> {
        let starts = self.segment_starts.get(segment)?;
        let end = self
            .segment_starts
            .get(segment + 1)
            .copied()
            .unwrap_or(self.t.len());
        let range = &self.t[*starts..end];
        Some((*range.first()?, *range.last()?))
    }

    /// The last full cycle of segment `segment`, `None` with fewer than
    /// three force maxima there (no settled stick-slip to read).
    pub fn settled(&self, segment: usize) -> Option<SettledCycle> {
        let peaks: Vec<(f64, f64)> = self
            .maxima
            .iter()
            .filter(|m| m.2 == segment)
            .map(|m| (m.0, m.1))
            .collect();
        let [.., a, b, c] = peaks.as_slice() else {
            return None;
        };
        let low = self
            .minima
            .iter()
            .filter(|m| m.2 == segment && m.0 > b.0 && m.0 < c.0)
            .map(|m| m.1)
            .fold(f64::INFINITY, f64::min);
        let (period, before) = (c.0 - b.0, b.0 - a.0);
        low.is_finite().then(|| SettledCycle {
            period,
            force_drop: b.1.max(c.1) - low,
            period_change: (period - before).abs() / period,
        })
    }
}
