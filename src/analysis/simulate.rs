//! Time integration of the driven block under a driving protocol: steady
//! pulling, velocity jumps, stop-and-go. Integrated in logarithmic variables
//! (slip velocity and age span decades) by the engine's Radau IIA method.
//!
//! [`simulate_with`] hands every sample to a sink as soon as the integrator
//! produces it (so a caller can write rows as they come, show progress and
//! stop early); [`simulate`] collects them into a [`Trajectory`].

use crate::analysis::joined_flow::stick_threshold;
use crate::analysis::orbit_inertia::{inertial_state, state_imbalance, InertiaWatch};
use crate::analysis::settle::{settle, SettleError, SettleSettings, SettledOrbit, SteadySpectrum};
use crate::error::NumericalError;
use crate::log_model::LogBlock;
use crate::model::ModelKind;
use crate::params::Params;
use continuation::integrate::{
    self, EventDirection, EventFunction, Outcome, Output, Radau5, Settings,
};
use std::ops::ControlFlow;

/// A stretch of constant driving velocity `nu` lasting `duration` (units `D0/V0`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment {
    pub nu: f64,
    pub duration: f64,
}

/// One point of a simulated trajectory in docs/model.md's variables.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    pub t: f64,
    pub s: f64,
    pub v: f64,
    pub theta: f64,
    /// Slip `x(t) - x(0)` in units of `D0`, from `s = kappa (int nu dt - x)`.
    pub slip: f64,
    /// `log10 v`, from the integrator's log variables: finite also where `v`
    /// itself underflows to 0 (below `1e-308`, e.g. a long stick).
    pub log10_v: f64,
    /// The model that computed the sample.
    pub model: ModelKind,
}

impl Sample {
    /// Whether every field is a finite number.
    pub fn is_finite(&self) -> bool {
        [self.t, self.s, self.v, self.theta, self.slip, self.log10_v]
            .iter()
            .all(|x| x.is_finite())
    }

    /// The fields that are not finite numbers, in words (never `inf` or
    /// `NaN`): a velocity beyond the range is given by its `log10`, which the
    /// log variables still hold.
    pub fn out_of_range(&self) -> Vec<String> {
        let fields = [
            ("t", self.t),
            ("s", self.s),
            ("v", self.v),
            ("theta", self.theta),
            ("slip", self.slip),
            ("log10 v", self.log10_v),
        ];
        fields
            .iter()
            .filter(|(_, x)| !x.is_finite())
            .map(|&(name, x)| match (name, x.is_nan()) {
                ("v", false) if self.log10_v.is_finite() => format!(
                    "v = 10^{:.4} V0, beyond the floating-point range",
                    self.log10_v
                ),
                (_, true) => format!("{name} is not a number"),
                (_, false) if x > 0.0 => format!("{name} is above the floating-point range"),
                (_, false) => format!("{name} is below the floating-point range (negative)"),
            })
            .collect()
    }
}

/// A simulated trajectory in docs/model.md's variables.
#[derive(Clone, Debug, Default)]
pub struct Trajectory {
    pub t: Vec<f64>,
    pub s: Vec<f64>,
    pub v: Vec<f64>,
    pub theta: Vec<f64>,
    /// Slip `x(t) - x(0)` in units of `D0`, from `s = kappa (int nu dt - x)`.
    pub slip: Vec<f64>,
    /// `log10 v` (see [`Sample::log10_v`]).
    pub log10_v: Vec<f64>,
}

impl Trajectory {
    /// Appends one sample.
    pub fn push(&mut self, p: &Sample) {
        self.t.push(p.t);
        self.s.push(p.s);
        self.v.push(p.v);
        self.theta.push(p.theta);
        self.slip.push(p.slip);
        self.log10_v.push(p.log10_v);
    }
}

/// How a run of [`simulate_with`] ended (failures are errors).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RunEnd {
    /// The simulated time reached: the end of the protocol, or the last
    /// sample handed to the sink when it stopped the run.
    pub t: f64,
    /// The end of the protocol (sum of the durations).
    pub t_end: f64,
    /// Whether the sink stopped the run before the end.
    pub stopped: bool,
    /// Where the run changed to the inertial model, if it did.
    pub switch: Option<SimulationSwitch>,
    /// The sticks below `v_b` integrated quasi-statically.
    pub sticks: DeepSticks,
}

/// The sticks of an inertial run below the velocity `v_b` where inertia
/// shifts `ln v` by less than rounding, integrated quasi-statically from
/// where the block came to rest to where its velocity rose through `v_b`
/// again ([`super::joined_flow`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DeepSticks {
    /// How many.
    pub count: usize,
    /// `ln v_b` of the last one, if any.
    pub ln_v_b: Option<f64>,
    /// `Some(ln v_b)` while the run is in one.
    below: Option<f64>,
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
    let mut out = Trajectory::default();
    simulate_with(kind, params, start, protocol, rtol, grid, |p| {
        out.push(p);
        ControlFlow::Continue(())
    })?;
    Ok(out)
}

/// As [`simulate`], handing each sample to `sink` as soon as it is computed
/// (the start, then the end of every accepted step or every grid time, in
/// order, each time once). `sink` returning `ControlFlow::Break(())` stops the
/// integration there ([`RunEnd::stopped`]). A sample with a non-finite value
/// is never handed over: the run fails at it. On failure the sink has
/// received everything up to the last good step. The model is kept
/// throughout ([`simulate_watched`] may change it).
pub fn simulate_with(
    kind: ModelKind,
    params: &Params,
    start: [f64; 3],
    protocol: &[Segment],
    rtol: f64,
    grid: Option<&[f64]>,
    sink: impl FnMut(&Sample) -> ControlFlow<()>,
) -> Result<RunEnd, NumericalError> {
    let options = RunOptions {
        rtol,
        ..RunOptions::default()
    };
    simulate_watched(kind, params, start, protocol, grid, &options, sink)
}

/// How a simulation runs: the integrator's tolerance and step limit, and the
/// model watch.
#[derive(Clone, Copy, Debug)]
pub struct RunOptions<'a> {
    /// Relative tolerance of the integrator (absolute: `1e-3 rtol`).
    pub rtol: f64,
    /// Most integrator steps per protocol segment.
    pub max_steps: usize,
    /// Hand a quasi-static run over to the inertial model where it says so.
    pub watch: Option<&'a InertiaWatch>,
}

impl Default for RunOptions<'_> {
    fn default() -> Self {
        RunOptions {
            rtol: 1e-8,
            max_steps: 100_000,
            watch: None,
        }
    }
}

/// [`simulate_with`] with the step limit of `options`, and a quasi-static
/// run hands over to the inertial model where `options.watch` says so: at the end of the first step whose state
/// has `m |dv/dt| / A` above the threshold
/// ([`super::orbit_inertia::state_imbalance`]), the run goes on from that
/// state (its velocity slaved, [`inertial_state`]) with the scene's inertia.
/// [`RunEnd::switch`] says where.
pub fn simulate_watched(
    kind: ModelKind,
    params: &Params,
    start: [f64; 3],
    protocol: &[Segment],
    grid: Option<&[f64]>,
    options: &RunOptions,
    mut sink: impl FnMut(&Sample) -> ControlFlow<()>,
) -> Result<RunEnd, NumericalError> {
    let (rtol, watch) = (options.rtol, options.watch);
    if let Some(g) = grid {
        if g.iter().any(|t| !t.is_finite()) || g.windows(2).any(|w| w[1] < w[0]) {
            return Err(NumericalError::Analysis(
                "simulation: the output times must be finite and increasing".into(),
            ));
        }
    }
    let mut params = *params;
    let t_end: f64 = protocol.iter().map(|seg| seg.duration).sum();
    let mut out = Emitter {
        log: LogBlock::new(kind, &params),
        start_s: start[0],
        kappa: params.kappa,
        grid: grid.map(|g| (g, 0)),
        last: None,
        bad: None,
    };
    let mut x = out.log.from_model(start[0], start[1], start[2]);
    let (mut t0, mut pulled) = (0.0, 0.0);
    let first_nu = protocol.first().map_or(params.nu, |seg| seg.nu);
    let mut p0 = params;
    p0.nu = first_nu;
    if out.start(&x, &p0.to_vec(), &mut sink).is_break() {
        return out.finish(t0, t_end, true);
    }
    let mut switch = None;
    let mut sticks = DeepSticks::default();
    for seg in protocol {
        let t1 = t0 + seg.duration;
        let drive = Drive {
            t0,
            nu: seg.nu,
            pulled,
        };
        let settings = Settings {
            rtol,
            atol: rtol * 1e-3,
            max_steps: options.max_steps,
            ..Settings::default()
        };
        // Each segment in its own time, from 0: the transient after a jump of
        // the drive can need steps far below the rounding level of the
        // absolute time (`eps t`) reached by then. The segment is resumed
        // once, in the inertial model, if the watch hands over.
        let mut local = 0.0;
        let (sol, log, pv) = loop {
            let mut p = params;
            p.nu = seg.nu;
            let pv = p.to_vec();
            let log = out.log;
            let watching = watch.filter(|w| {
                w.switch && log.kind == ModelKind::QuasiStatic && sticks.below.is_none()
            });
            let mut hand_over = None;
            // Where steady sliding repels, the steps resolve its
            // oscillation: Radau IIA's long steps damp a growing oscillation
            // they do not resolve (module docs of [`super::settle`]; a run
            // from 1e-6 off steady sliding took two steps over 60 s and
            // ended on steady sliding).
            let spectrum = SteadySpectrum::of(log.kind, &p);
            let h_max = if spectrum.growing {
                spectrum.step_bound
            } else {
                f64::INFINITY
            };
            let mut solver = Radau5::new(
                &log,
                &pv,
                Settings {
                    h_max,
                    ..settings.clone()
                },
            );
            // The inertial block comes to rest below v_b, or leaves such a
            // stick: the joined flow ([`super::joined_flow`]).
            let ln_v_b = (params.m > 0.0
                && (log.kind == ModelKind::Inertial || sticks.below.is_some()))
            .then(|| {
                let mut at = p;
                at.nu = seg.nu.max(params.nu);
                stick_threshold(&at)
            });
            if let Some(ln_v_b) = ln_v_b {
                let (log, p) = (log, pv.clone());
                let (event, direction) = if log.kind == ModelKind::Inertial {
                    (
                        EventFunction::new(move |_, y: &[f64]| y[1] - ln_v_b),
                        EventDirection::Falling,
                    )
                } else {
                    (
                        EventFunction::new(move |_, y: &[f64]| log.ln_velocity(y, &p) - ln_v_b),
                        EventDirection::Rising,
                    )
                };
                solver.add_event(event.direction(direction).terminal(true));
            }
            let sol = solver.solve_with(local, &x, seg.duration, Output::Final, |step| {
                let flow = out.step(step, &pv, drive, &mut sink);
                if let Some(w) = watching.filter(|_| flow.is_continue()) {
                    let chi = state_imbalance(&log, step.x, &pv, w.m);
                    if chi > w.threshold {
                        hand_over = Some((step.t, chi, inertial_state(&log, step.x, &pv)));
                        return ControlFlow::Break(());
                    }
                }
                flow
            });
            match (hand_over, watching, &sol.outcome, ln_v_b) {
                (Some((t, chi, state)), Some(w), _, _) => {
                    params.m = w.m;
                    out.log = LogBlock::new(ModelKind::Inertial, &params);
                    x = state.to_vec();
                    local = t;
                    switch = Some(SimulationSwitch {
                        t: drive.t0 + t,
                        chi,
                    });
                }
                (_, _, Outcome::TerminalEvent { .. }, Some(ln_v_b)) => {
                    let y = &sol.x_final;
                    local = sol.t_final;
                    if log.kind == ModelKind::Inertial {
                        // At rest below v_b: the stick, from the same (s, theta).
                        out.log = LogBlock::new(ModelKind::QuasiStatic, &params);
                        x = vec![y[0], y[2]];
                        sticks.count += 1;
                        sticks.below = Some(ln_v_b);
                    } else {
                        // Leaves the stick at v_b: inertially from the manifold.
                        out.log = LogBlock::new(ModelKind::Inertial, &params);
                        x = vec![y[0], ln_v_b, y[1]];
                        sticks.below = None;
                    }
                    sticks.ln_v_b = Some(ln_v_b);
                }
                _ => break (sol, log, pv),
            }
        };
        if let Some(bad) = out.bad.take() {
            return Err(bad);
        }
        match sol.outcome {
            Outcome::ObserverStop => {
                return out.finish(t0 + sol.t_final, t_end, true).map(|e| RunEnd {
                    switch,
                    sticks,
                    ..e
                })
            }
            Outcome::Failed(e) => {
                // Failing at once from the initial state: say where it was.
                let start = if t0 == 0.0 && sol.t_final == 0.0 {
                    format!(
                        "; no step was taken from the initial state, whose slip velocity is \
                         v = 10^{:.4} V0: {START_HINT}",
                        log.ln_velocity(&x, &pv) / std::f64::consts::LN_10
                    )
                } else {
                    String::new()
                };
                let segment = if t0 > 0.0 {
                    format!(
                        " (the segment from t = {t0:.10e}; the integrator counts time from there)"
                    )
                } else {
                    String::new()
                };
                return Err(NumericalError::Analysis(format!(
                    "simulation at nu = {}{segment}: {}{start}",
                    seg.nu,
                    integration_failure(&e, log.kind)
                )));
            }
            Outcome::ReachedEnd | Outcome::TerminalEvent { .. } => {}
        }
        pulled += seg.nu * seg.duration;
        t0 = t1;
        x = sol.x_final;
    }
    out.finish(t0, t_end, false).map(|e| RunEnd {
        switch,
        sticks,
        ..e
    })
}

/// An integrator failure in this program's terms: where it stopped (time
/// in `D0/V0`), without a remedy (see [`integration_failure`]). The
/// step-size failures are how a slip that blows up or jumps shows.
pub fn integration_stop(e: &integrate::IntegrateError) -> String {
    use integrate::IntegrateError as E;
    match e {
        E::StepSizeUnderflow { t, h, .. }
        | E::NewtonFailed { t, h, .. }
        | E::SingularMatrix { t, h, .. } => format!(
            "the integrator could not go on past t = {t:.10e} D0/V0 (step size down to \
             {h:.3e}): the slip velocity blows up or jumps there"
        ),
        E::MaxSteps { t, .. } => {
            format!("the integrator's step limit was reached at t = {t:.10e} D0/V0")
        }
        other => other.to_string(),
    }
}

/// [`integration_stop`] and which of `simulate`'s options can help with the
/// model `kind`: a quasi-static block has no solution once its spring
/// cannot follow the slip it asks for, so the inertial model is advised
/// only to a quasi-static run.
fn integration_failure(e: &integrate::IntegrateError, kind: ModelKind) -> String {
    use integrate::IntegrateError as E;
    let stop = integration_stop(e);
    match (e, kind) {
        (
            E::StepSizeUnderflow { .. } | E::NewtonFailed { .. } | E::SingularMatrix { .. },
            ModelKind::QuasiStatic,
        ) => format!(
            "{stop}; try a tighter --rtol, a shorter protocol, or --model inertial with a mass M \
             in the scene (the quasi-static block has no solution where its spring cannot \
             follow the slip)"
        ),
        (
            E::StepSizeUnderflow { .. } | E::NewtonFailed { .. } | E::SingularMatrix { .. },
            ModelKind::Inertial,
        ) => {
            format!("{stop}; try a tighter --rtol or a shorter protocol")
        }
        (E::MaxSteps { .. }, _) => format!("{stop}; raise --max-steps or shorten the protocol"),
        _ => stop,
    }
}

/// Where a quasi-static simulation handed over to the inertial model.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SimulationSwitch {
    /// The time (units `D0/V0`).
    pub t: f64,
    /// `m |dv/dt| / A` at that state.
    pub chi: f64,
}

/// What to try when the initial state is the trouble.
const START_HINT: &str = "for `simulate` it is steady sliding with the age perturbed by \
     --perturb, which in the quasi-static model changes the slip velocity by a factor of about \
     (1 + perturb)^(-mu_phi/A); try a smaller |--perturb|";

/// The drive of the current segment: its start, velocity, and the spring
/// end's displacement before it.
#[derive(Clone, Copy)]
struct Drive {
    t0: f64,
    nu: f64,
    pulled: f64,
}

/// Turns integrator states into samples for the sink: at the step ends or at
/// the grid times, each time once, checked finite.
struct Emitter<'a> {
    /// The model integrated (it may change once, quasi-static to inertial).
    log: LogBlock,
    start_s: f64,
    kappa: f64,
    /// The output times and the index of the next one.
    grid: Option<(&'a [f64], usize)>,
    /// Time of the last sample handed over.
    last: Option<f64>,
    /// A non-finite sample that stopped the run.
    bad: Option<NumericalError>,
}

impl Emitter<'_> {
    fn sample(&self, t: f64, y: &[f64], pv: &[f64], drive: Drive) -> Sample {
        let [s, v, theta] = self.log.to_model(y, pv);
        let slip = drive.pulled + drive.nu * (t - drive.t0) - (s - self.start_s) / self.kappa;
        Sample {
            t,
            s,
            v,
            theta,
            slip,
            log10_v: self.log.ln_velocity(y, pv) / std::f64::consts::LN_10,
            model: self.log.kind,
        }
    }

    /// Hands over `p` unless its time was already handed over.
    fn emit(
        &mut self,
        p: Sample,
        sink: &mut impl FnMut(&Sample) -> ControlFlow<()>,
    ) -> ControlFlow<()> {
        if self.last.is_some_and(|t| p.t <= t) {
            return ControlFlow::Continue(());
        }
        if !p.is_finite() {
            let hint = if p.t == 0.0 {
                format!("this is the initial state: {START_HINT}")
            } else {
                "try a tighter --rtol or a shorter protocol".to_string()
            };
            self.bad = Some(NumericalError::Analysis(format!(
                "simulation: the state leaves the floating-point range at t = {:e} ({}); {hint}",
                p.t,
                p.out_of_range().join(", ")
            )));
            return ControlFlow::Break(());
        }
        self.last = Some(p.t);
        sink(&p)
    }

    /// The initial state at `t = 0` (with the grid: only if 0 is a grid time).
    fn start(
        &mut self,
        y: &[f64],
        pv: &[f64],
        sink: &mut impl FnMut(&Sample) -> ControlFlow<()>,
    ) -> ControlFlow<()> {
        let drive = Drive {
            t0: 0.0,
            nu: 0.0,
            pulled: 0.0,
        };
        if let Some((g, pos)) = &mut self.grid {
            // Times before the start are never reached.
            while *pos < g.len() && g[*pos] < 0.0 {
                *pos += 1;
            }
            if !(*pos < g.len() && g[*pos] == 0.0) {
                return ControlFlow::Continue(());
            }
            *pos += 1;
        }
        let p = self.sample(0.0, y, pv, drive);
        self.emit(p, sink)
    }

    /// An accepted step: its end, or the grid times inside it.
    fn step(
        &mut self,
        step: &integrate::StepView<'_>,
        pv: &[f64],
        drive: Drive,
        sink: &mut impl FnMut(&Sample) -> ControlFlow<()>,
    ) -> ControlFlow<()> {
        // The integrator counts time from the start of the segment.
        let t = drive.t0 + step.t;
        let Some((g, mut pos)) = self.grid else {
            let p = self.sample(t, step.x, pv, drive);
            return self.emit(p, sink);
        };
        let mut y = vec![0.0; step.x.len()];
        let mut flow = ControlFlow::Continue(());
        while flow.is_continue() && pos < g.len() && g[pos] <= t {
            step.eval(g[pos] - drive.t0, &mut y);
            let p = self.sample(g[pos], &y, pv, drive);
            pos += 1;
            flow = self.emit(p, sink);
        }
        self.grid = Some((g, pos));
        flow
    }

    fn finish(&mut self, t: f64, t_end: f64, stopped: bool) -> Result<RunEnd, NumericalError> {
        match self.bad.take() {
            Some(e) => Err(e),
            None => Ok(RunEnd {
                t: if stopped { self.last.unwrap_or(t) } else { t },
                t_end,
                stopped,
                switch: None,
                sticks: DeepSticks::default(),
            }),
        }
    }
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
    let log = LogBlock::new(kind, params);
    let pv = params.to_vec();
    let ln_nu = params.nu.ln();
    let settings = Settings {
        rtol,
        atol: rtol * 1e-3,
        ..Settings::default()
    };
    let fail = |e: integrate::IntegrateError| {
        NumericalError::Analysis(format!("simulation: {}", integration_failure(&e, kind)))
    };
    let x0 = log.from_model(start[0], start[1], start[2]);
    let warm = Radau5::new(&log, &pv, settings.clone())
        .solve(0.0, &x0, transient, Output::Final)
        .into_result()
        .map_err(fail)?;
    // Slip velocity through nu (ds/dt = kappa (nu - v) changes sign): rising
    // marks a maximum of s, falling a minimum.
    let mut solver = Radau5::new(&log, &pv, settings).with_event(
        EventFunction::new(|_, x| log.ln_velocity(x, &pv) - ln_nu).direction(EventDirection::Any),
    );
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

/// The regime a run reaches, continued from its last state at its last
/// driving velocity (`simulate`: the return map settled, then measured, [`measured_regime`]).
#[derive(Clone, Debug, PartialEq)]
pub enum RegimeReached {
    /// A stick-slip cycle: its period (units `D0/V0`), peak-to-peak spring
    /// force `Delta_s` and slip per event `nu T` (units `D0`: over one period
    /// the block slides as far as the drive moves, the spring returning to
    /// its extension).
    Periodic {
        period: f64,
        delta_s: f64,
        slip: f64,
        /// A state on the cycle, `(s, v, theta)`.
        on_cycle: [f64; 3],
    },
    /// The oscillation decays onto steady sliding.
    Steady,
    /// The drive is stopped (`V = 0` in the last segment): the block creeps
    /// toward rest, which it reaches only as `t -> infinity`; there is no
    /// steady sliding or cycle to settle on.
    Held,
    /// Neither within the settling budget, or the integration failed.
    Unsettled(Unsettled),
}

/// Why the regime a run reaches was not determined.
#[derive(Clone, Debug, PartialEq)]
pub enum Unsettled {
    /// The return map still moves after [`REGIME_PERIODS`] periods, or the
    /// integration failed while settling.
    Settle(SettleError),
    /// The period between extremes of `s` and the return map's differ by
    /// more than `1e-6` relative (units `D0/V0`).
    Periods { extremes: f64, return_map: f64 },
    /// The integration over the settled cycle failed.
    Integration(String),
}

/// Most periods the regime a run reaches is settled for ([`regime_settings`]).
pub const REGIME_PERIODS: usize = 300;

/// The settling budget of the regime a run reaches (`simulate`) for `params`: a report after
/// the run, not a search, so a few hundred periods at most (a cycle near its
/// bifurcation that settles more slowly is reported unsettled, with how far
/// its return map still moves).
pub fn regime_settings(params: &Params) -> SettleSettings {
    SettleSettings {
        max_periods: REGIME_PERIODS,
        ..SettleSettings::for_params(params)
    }
}

/// A failed settling as a regime: a decay is steady sliding, anything else
/// leaves the regime unsettled.
pub fn settle_failure(e: SettleError) -> RegimeReached {
    match e {
        SettleError::Decayed { .. } => RegimeReached::Steady,
        e => RegimeReached::Unsettled(Unsettled::Settle(e)),
    }
}

/// The regime of the settled orbit `orbit` of `params`: the period and
/// `Delta_s` from the extremes of `s` located as events over five and a
/// half periods from its section ([`cycle_by_integration`], averaged over
/// the last three); that period and the return map's must agree to `1e-6`
/// relative, else the orbit is reported unsettled.
pub fn measured_regime(kind: ModelKind, params: &Params, orbit: &SettledOrbit) -> RegimeReached {
    let log = LogBlock::new(kind, params);
    let on_section = log.to_model(&orbit.section, &params.to_vec());
    match cycle_by_integration(
        kind,
        params,
        on_section,
        0.0,
        5.5 * orbit.period,
        3,
        regime_settings(params).rtol,
    ) {
        Ok((period, delta_s)) if (period / orbit.period - 1.0).abs() <= 1e-6 => {
            RegimeReached::Periodic {
                period,
                delta_s,
                slip: params.nu * period,
                on_cycle: on_section,
            }
        }
        Ok((period, _)) => RegimeReached::Unsettled(Unsettled::Periods {
            extremes: period,
            return_map: orbit.period,
        }),
        Err(e) => RegimeReached::Unsettled(Unsettled::Integration(e.to_string())),
    }
}

/// An orbit settled in the model the whole orbit needs
/// ([`settled_with_inertia_judged`]).
#[derive(Clone, Debug)]
pub struct JudgedOrbit {
    /// The model of the orbit.
    pub kind: ModelKind,
    /// That model's parameters (the scene's inertia when inertial).
    pub params: Params,
    pub orbit: SettledOrbit,
    /// Where the quasi-static orbit handed over to the inertial model
    /// (`chi = m |dv/dt| / A` there above the threshold; its time counted
    /// from the quasi-static orbit's section), if it did.
    pub switch: Option<SimulationSwitch>,
}

/// The one model decision on a settled orbit, shared by `simulate` (the
/// regime a run reaches) and `cycles` (the cycle at a given stiffness): a
/// quasi-static orbit `orbit` of `params_of(QuasiStatic)` is followed for
/// three of its periods from its section under `watch` ([`simulate_watched`]
/// at `rtol`, the run's own switch: `chi = m |dv/dt| / A` above the
/// threshold, docs/cycles.md "Which model"); where it hands over, the orbit
/// is settled again in the inertial model (`params_of(Inertial)`, budget
/// `settings_of`) from the state where it switched. An orbit already
/// inertial, a watch that does not switch, or a follow that fails keep the
/// orbit as it is. So the answer does not depend on whether the run that
/// led to the orbit got far enough to switch.
pub fn settled_with_inertia_judged(
    kind: ModelKind,
    params_of: impl Fn(ModelKind) -> Params,
    orbit: SettledOrbit,
    watch: &InertiaWatch,
    rtol: f64,
    settings_of: impl Fn(&Params) -> SettleSettings,
) -> Result<JudgedOrbit, SettleError> {
    let params = params_of(kind);
    let kept = |orbit| JudgedOrbit {
        kind,
        params,
        orbit,
        switch: None,
    };
    if kind != ModelKind::QuasiStatic || !watch.switch {
        return Ok(kept(orbit));
    }
    let on_cycle = LogBlock::new(kind, &params).to_model(&orbit.section, &params.to_vec());
    let mut switched: Option<Sample> = None;
    let options = RunOptions {
        rtol,
        max_steps: 1_000_000,
        watch: Some(watch),
    };
    let three_periods = [Segment {
        nu: params.nu,
        duration: 3.0 * orbit.period,
    }];
    let run = simulate_watched(
        kind,
        &params,
        on_cycle,
        &three_periods,
        None,
        &options,
        |p| {
            if p.model == ModelKind::Inertial {
                switched = Some(*p);
                return ControlFlow::Break(());
            }
            ControlFlow::Continue(())
        },
    );
    match (run, switched) {
        (Ok(end), Some(p)) => {
            let inertial = params_of(ModelKind::Inertial);
            let orbit = settle(
                ModelKind::Inertial,
                &inertial,
                [p.s, p.v, p.theta],
                &settings_of(&inertial),
            )?;
            Ok(JudgedOrbit {
                kind: ModelKind::Inertial,
                params: inertial,
                orbit,
                switch: end.switch,
            })
        }
        _ => Ok(kept(orbit)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_stopped_integration_advises_only_what_the_run_does_not_already_do() {
        let e = integrate::IntegrateError::StepSizeUnderflow {
            t: 2.0,
            h: 1e-30,
            h_min: 1e-29,
            cause: "h_min",
        };
        let inertial = integration_failure(&e, ModelKind::Inertial);
        assert!(!inertial.contains("--model inertial"), "{inertial}");
        let quasi_static = integration_failure(&e, ModelKind::QuasiStatic);
        assert!(quasi_static.contains("--model inertial"), "{quasi_static}");
        // No integrator knob the command line does not have.
        for text in [&inertial, &quasi_static, &integration_stop(&e)] {
            assert!(!text.contains("h_min") && !text.contains("atol"), "{text}");
        }
    }
}
