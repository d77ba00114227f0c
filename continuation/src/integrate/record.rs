//! What happens after an accepted step: event location on the dense output,
//! the output grid or step record, and the observer.

use super::events::{Crossing, EventFunction};
use super::step::Dense;
use super::{IntegrateError, Outcome, Output, Settings, Solution, StepView};
use crate::root::illinois;
use std::convert::Infallible;
use std::ops::ControlFlow;

/// Output and event bookkeeping of one integration, allocated once.
pub(super) struct Recorder {
    output: Output,
    /// Next grid point to emit.
    grid_pos: usize,
    /// Event function values at the current time.
    g_last: Vec<f64>,
    /// Scratch state for dense-output evaluations.
    xe: Vec<f64>,
    /// Crossings found in the current step: (time, event index, rising).
    found: Vec<(f64, usize, bool)>,
    /// +1 forward, -1 backward.
    dir: f64,
}

impl Recorder {
    /// Records the initial point and the event values there.
    pub(super) fn start(
        output: Output,
        events: &mut [EventFunction<'_>],
        t0: f64,
        x0: &[f64],
        dir: f64,
        sol: &mut Solution,
    ) -> Result<Self, IntegrateError> {
        let mut g_last = Vec::with_capacity(events.len());
        for (index, ev) in events.iter_mut().enumerate() {
            let value = ev.value(t0, x0);
            if !value.is_finite() {
                return Err(IntegrateError::NonFiniteEvent {
                    index,
                    t: t0,
                    h: 0.0,
                    value,
                });
            }
            g_last.push(value);
        }
        let mut rec = Recorder {
            output,
            grid_pos: 0,
            g_last,
            xe: vec![0.0; x0.len()],
            found: Vec::with_capacity(4 * events.len()),
            dir,
        };
        match &rec.output {
            Output::Steps => {
                sol.t.push(t0);
                sol.x.push(x0.to_vec());
            }
            Output::Grid(grid) => {
                while rec.grid_pos < grid.len() && grid[rec.grid_pos] == t0 {
                    sol.t.push(t0);
                    sol.x.push(x0.to_vec());
                    rec.grid_pos += 1;
                }
            }
            Output::Final => {}
        }
        Ok(rec)
    }

    /// Processes the accepted step `[t_prev, t_new]` of length `h` with state
    /// `y` at `t_new`. Returns the outcome if the integration must stop here
    /// (terminal event or observer), with `sol.t_final`, `sol.x_final` set.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn step(
        &mut self,
        events: &mut [EventFunction<'_>],
        settings: &Settings,
        dense: Dense<'_>,
        (t_prev, t_new, h): (f64, f64, f64),
        y: &[f64],
        sol: &mut Solution,
        observer: &mut impl FnMut(&StepView<'_>) -> ControlFlow<()>,
    ) -> Result<Option<Outcome>, IntegrateError> {
        let terminal = self.locate_events(events, settings, dense, t_prev, t_new, h, sol)?;
        let t_limit = terminal.map_or(t_new, |(t, _)| t);
        if terminal.is_some() {
            dense.eval(t_limit, &mut self.xe);
        } else {
            self.xe.copy_from_slice(y);
        }
        match &self.output {
            Output::Steps => {
                sol.t.push(t_limit);
                sol.x.push(self.xe.clone());
            }
            Output::Grid(grid) => {
                while self.grid_pos < grid.len()
                    && (grid[self.grid_pos] - t_limit) * self.dir <= 0.0
                {
                    let tg = grid[self.grid_pos];
                    let mut x = vec![0.0; y.len()];
                    dense.eval(tg, &mut x);
                    sol.t.push(tg);
                    sol.x.push(x);
                    self.grid_pos += 1;
                }
            }
            Output::Final => {}
        }
        let view = StepView {
            t_prev,
            t: t_limit,
            x: &self.xe,
            h,
            dense,
        };
        let stop = observer(&view).is_break();
        let outcome = match terminal {
            Some((_, index)) => Some(Outcome::TerminalEvent { index }),
            None if stop => Some(Outcome::ObserverStop),
            None => None,
        };
        if outcome.is_some() {
            sol.t_final = t_limit;
            sol.x_final.copy_from_slice(&self.xe);
        }
        Ok(outcome)
    }

    /// Finds the sign changes of all event functions in the step, records
    /// them in time order up to and including the first terminal one, and
    /// returns that one's `(time, index)`.
    #[allow(clippy::too_many_arguments)]
    fn locate_events(
        &mut self,
        events: &mut [EventFunction<'_>],
        settings: &Settings,
        dense: Dense<'_>,
        t_prev: f64,
        t_new: f64,
        h: f64,
        sol: &mut Solution,
    ) -> Result<Option<(f64, usize)>, IntegrateError> {
        if events.is_empty() {
            return Ok(None);
        }
        self.found.clear();
        let m = settings.event_samples.max(1);
        let xe = &mut self.xe;
        for (index, ev) in events.iter_mut().enumerate() {
            let (mut ta, mut ga) = (t_prev, self.g_last[index]);
            for k in 1..=m {
                let tb = if k == m {
                    t_new
                } else {
                    t_prev + (t_new - t_prev) * (k as f64 / m as f64)
                };
                dense.eval(tb, xe);
                let gb = ev.value(tb, xe);
                if !gb.is_finite() {
                    return Err(IntegrateError::NonFiniteEvent {
                        index,
                        t: tb,
                        h,
                        value: gb,
                    });
                }
                if let Some(rising) = ev.crossing(ga, gb) {
                    let scale = tb.abs().max(ta.abs());
                    let tol =
                        (settings.event_tol * scale.max(h.abs())).max(4.0 * f64::EPSILON * scale);
                    // The end past the sign change (on the side of tb).
                    let tc = match illinois(
                        |s| {
                            dense.eval(s, xe);
                            Ok::<_, Infallible>(ev.value(s, xe))
                        },
                        (ta, ga),
                        (tb, gb),
                        tol,
                        200,
                    ) {
                        Ok(bracket) => bracket.end_signed_like(gb),
                        Err(never) => match never {},
                    };
                    self.found.push((tc, index, rising));
                }
                (ta, ga) = (tb, gb);
            }
            self.g_last[index] = ga;
        }
        let dir = self.dir;
        self.found
            .sort_by(|a, b| (a.0 * dir).total_cmp(&(b.0 * dir)));
        for &(t, index, rising) in &self.found {
            let mut x = vec![0.0; xe.len()];
            dense.eval(t, &mut x);
            sol.events.push(Crossing {
                index,
                t,
                x,
                rising,
            });
            if events[index].is_terminal() {
                return Ok(Some((t, index)));
            }
        }
        Ok(None)
    }
}
