//! The `simulate` job: driven sliding in time under a protocol of pulling
//! velocities (steady pulling, jumps, stop-and-go), from steady sliding
//! slightly perturbed; every integrator step handed to an [`Observer`] (the
//! command line writes them as CSV rows), a trajectory decimated for the
//! figures kept ([`Envelope`]), and after a complete run the regime it
//! reaches (the model judged on the whole orbit,
//! [`settled_with_inertia_judged`]).

use super::{SceneSpec, Setup};
use crate::analysis::decimate::{Envelope, ENVELOPE_MIN_CAP};
use crate::analysis::joined_flow::State;
use crate::analysis::model_choice::{choose_model, params_for, ModelChoice};
use crate::analysis::orbit_inertia::InertiaWatch;
use crate::analysis::return_map;
use crate::analysis::settle::settle;
use crate::analysis::settle::SettleError;
use crate::analysis::simulate::Unsettled;
use crate::analysis::simulate::{
    measured_regime, regime_settings, settle_failure, settled_with_inertia_judged,
    simulate_watched, RegimeReached, RunEnd, RunOptions, Sample, Segment, Trajectory,
};
use crate::error::{Error, InputError};
use crate::jobs::TextUnits;
use crate::model::ModelKind;
use crate::params::Params;
use crate::records::params_json;
use crate::records::UnitsRecord;
use crate::scene::Units;
use serde_json::json;
use std::ops::ControlFlow;

/// What `simulate` is asked.
#[derive(Clone, Debug)]
pub struct SimulateRequest {
    /// The protocol as `(V [µm/s], duration [s])` segments; `None`: the
    /// scene's velocity for `40 D0/V`.
    pub protocol: Option<Vec<(f64, f64)>>,
    /// Relative perturbation of the initial age away from steady sliding.
    pub perturb: f64,
    /// Integrator relative tolerance.
    pub rtol: f64,
    /// Most integrator steps (samples) over the whole protocol.
    pub max_steps: usize,
    /// Most points kept for the figures.
    pub plot_points: usize,
}

impl Default for SimulateRequest {
    /// The command's defaults.
    fn default() -> Self {
        SimulateRequest {
            protocol: None,
            perturb: 1e-2,
            rtol: 1e-8,
            max_steps: 200_000,
            plot_points: 20_000,
        }
    }
}

impl SimulateRequest {
    /// The request checked, each error naming its option.
    fn check(&self) -> Result<(), InputError> {
        if !(self.rtol > 1e-14 && self.rtol < 1e-2) {
            return Err(InputError::out_of_range(
                "--rtol",
                self.rtol,
                "in (1e-14, 1e-2)",
            ));
        }
        if !(self.perturb.is_finite() && self.perturb.abs() < 1.0) {
            return Err(InputError::out_of_range(
                "--perturb",
                self.perturb,
                "|perturb| < 1",
            ));
        }
        if self.max_steps < 1 {
            return Err(InputError::out_of_range(
                "--max-steps",
                self.max_steps as f64,
                ">= 1",
            ));
        }
        if self.plot_points < ENVELOPE_MIN_CAP {
            return Err(InputError::out_of_range(
                "--plot-points",
                self.plot_points as f64,
                &format!(">= {ENVELOPE_MIN_CAP}"),
            ));
        }
        Ok(())
    }
}

/// Receives the run as it goes.
pub trait Observer {
    /// Whether to stop here (a signal).
    fn stop(&mut self) -> bool {
        false
    }
    /// The simulated time reached, of `t_end` (both units `D0/V0`).
    fn progress(&mut self, _t: f64, _t_end: f64) {}
    /// Every integrator step; an error (a file that cannot be written)
    /// stops the run.
    fn sample(&mut self, _p: &Sample) -> std::io::Result<()> {
        Ok(())
    }
}

/// The model for a protocol whose fastest pulling velocity is `top`
/// (units `V0`): the one `--model` forces, else [`choose_model`] there.
fn choice_at(spec: &SceneSpec, setup: &Setup, top: f64) -> ModelChoice {
    match spec.model {
        Some(_) => setup.choice.clone(),
        None => {
            let mut at_top = setup.scene_params;
            at_top.nu = top;
            choose_model(&at_top, None, spec.inertia_threshold)
        }
    }
}

/// The model a run of `protocol` from steady sliding at its first velocity
/// uses, decided as `simulate` decides it: the model for the protocol's
/// fastest pulling velocity ([`choice_at`]), and where that is
/// quasi-static, the inertial one if the run at the scene's parameters
/// under the watch of the scene's inertia hands over to it
/// ([`simulate_watched`], `chi = m |dv/dt| / A` above the threshold). A
/// run that fails keeps the first choice (its caller integrates again and
/// reports the failure).
pub fn model_of_run(spec: &SceneSpec, setup: &Setup, protocol: &[Segment]) -> ModelChoice {
    let top = protocol.iter().map(|seg| seg.nu).fold(0.0, f64::max);
    let choice = choice_at(spec, setup, top);
    let watch = InertiaWatch::new(
        &setup.scene_params,
        spec.inertia_threshold,
        spec.model.is_none(),
    );
    let Some(nu0) = protocol.first().map(|seg| seg.nu).filter(|nu| *nu > 0.0) else {
        return choice;
    };
    if choice.kind != ModelKind::QuasiStatic || !watch.switch {
        return choice;
    }
    let params = params_for(ModelKind::QuasiStatic, &setup.scene_params);
    let start = [params.friction().steady_force(nu0), nu0, nu0.recip()];
    let options = RunOptions {
        rtol: 1e-6,
        watch: Some(&watch),
        ..RunOptions::default()
    };
    let end = simulate_watched(
        ModelKind::QuasiStatic,
        &params,
        start,
        protocol,
        None,
        &options,
        |_| ControlFlow::Continue(()),
    );
    match end.ok().and_then(|e| e.switch) {
        Some(switch) => ModelChoice {
            kind: ModelKind::Inertial,
            inertia_ratio: choice.inertia_ratio,
            reason: format!(
                "inertial: the quasi-static run of the protocol hands over at t = {:.4e} D0/V0, \
                 where m |dv/dt| / A = {:.3e} exceeds {:.0e}",
                switch.t, switch.chi, watch.threshold
            ),
        },
        None => choice,
    }
}

/// A planned run: the scene set up with the model for the protocol's
/// fastest pulling velocity, the protocol in docs/model.md's units.
pub struct Plan {
    pub setup: Setup,
    pub protocol: Vec<Segment>,
    /// The fastest pulling velocity (`nu`) where the model was chosen for
    /// it (not forced).
    pub chosen_at: Option<f64>,
    request: SimulateRequest,
    watch: InertiaWatch,
}

impl Plan {
    /// Sets up `spec` and checks the request.
    pub fn new(spec: &SceneSpec, request: SimulateRequest) -> Result<Plan, Error> {
        request.check()?;
        let mut setup = spec.setup(|p| *p)?;
        let u = setup.scene.units;
        let time_unit = u.d0 / u.v0;
        let protocol = match &request.protocol {
            Some(segments) => segments
                .iter()
                .map(|&(v, t)| {
                    if !(v.is_finite() && v >= 0.0 && t.is_finite() && t > 0.0) {
                        return Err(InputError::Malformed {
                            field: "--protocol".into(),
                            value: format!("{v}:{t}"),
                            expected:
                                "V:T with V >= 0 in µm/s and T > 0 in s, e.g. 1:100,10:20,0:300"
                                    .into(),
                        });
                    }
                    Ok(Segment {
                        nu: v / (u.v0 * 1e6),
                        duration: t / time_unit,
                    })
                })
                .collect::<Result<Vec<_>, _>>()?,
            None => vec![Segment {
                nu: setup.params.nu,
                duration: 40.0 / setup.params.nu,
            }],
        };
        // The model for the fastest pulling velocity of the protocol (the
        // run starts from steady sliding at its first velocity: the scene's
        // own V is not pulled at when a protocol is given).
        let top = protocol.iter().map(|seg| seg.nu).fold(0.0, f64::max);
        let chosen_at = spec.model.is_none().then_some(top);
        setup.choice = choice_at(spec, &setup, top);
        setup.params = params_for(setup.choice.kind, &setup.scene_params);
        let watch = InertiaWatch::new(
            &setup.scene_params,
            spec.inertia_threshold,
            spec.model.is_none(),
        );
        if protocol.first().is_none_or(|s| s.nu <= 0.0) {
            return Err(InputError::Conflict(
                "--protocol must start with a positive velocity (steady sliding)".into(),
            )
            .into());
        }
        if setup.params.kappa <= 0.0 {
            return Err(InputError::Conflict(
                "simulation needs a spring: give K in the scene or --set kappa=...".into(),
            )
            .into());
        }
        Ok(Plan {
            setup,
            protocol,
            chosen_at,
            request,
            watch,
        })
    }

    /// The end of the protocol (units `D0/V0`).
    pub fn t_end(&self) -> f64 {
        self.protocol.iter().map(|seg| seg.duration).sum()
    }

    /// Integrates the protocol from steady sliding at its first velocity
    /// with the age perturbed; stops at `--max-steps` samples, at an
    /// error of the observer, or when it says so; then, after a complete
    /// run, follows the last state until it settles (in the model the
    /// whole orbit needs, [`settled_with_inertia_judged`]).
    pub fn run(self, observer: &mut dyn Observer) -> Simulation {
        let Plan {
            setup,
            protocol,
            chosen_at,
            request,
            watch,
        } = self;
        let nu0 = protocol[0].nu;
        let mut start_params = setup.params;
        start_params.nu = nu0;
        let s0 = start_params.friction().steady_force(nu0);
        let start = [s0, nu0, (1.0 + request.perturb) / nu0];
        let t_end: f64 = protocol.iter().map(|seg| seg.duration).sum();
        let mut envelope = Envelope::new(request.plot_points);
        let (mut steps, mut step_limit, mut interrupted) = (0usize, false, false);
        let mut last: Option<Sample> = None;
        let mut write_error = None;
        // The integrator's own limit well above max_steps, which the samples
        // enforce (partial): the integrator also counts its rejected steps,
        // and at a limit of max_steps + 1 it stopped first (a failure, 199 001
        // steps for 197 146 samples).
        let options = RunOptions {
            rtol: request.rtol,
            max_steps: request.max_steps.saturating_mul(4).saturating_add(1000),
            watch: Some(&watch),
        };
        let end = simulate_watched(
            setup.choice.kind,
            &setup.params,
            start,
            &protocol,
            None,
            &options,
            |p| {
                if let Err(e) = observer.sample(p) {
                    write_error = Some(e);
                    return ControlFlow::Break(());
                }
                envelope.push(p);
                last = Some(*p);
                steps += 1;
                if steps >= request.max_steps {
                    step_limit = true;
                    return ControlFlow::Break(());
                }
                observer.progress(p.t, t_end);
                if observer.stop() {
                    interrupted = true;
                    ControlFlow::Break(())
                } else {
                    ControlFlow::Continue(())
                }
            },
        );
        let stride = envelope.stride();
        let regime = match (&end, last, protocol.last()) {
            (Ok(e), Some(_), Some(seg)) if !e.stopped && seg.nu == 0.0 => Some(RegimeReached::Held),
            // Sticks below v_b: the run continued by the joined flow.
            (Ok(e), Some(at), Some(seg)) if !e.stopped && e.sticks.count > 0 => {
                let mut params = params_for(ModelKind::Inertial, &setup.scene_params);
                params.nu = seg.nu;
                let (ln_v, phi) = (at.log10_v * std::f64::consts::LN_10, at.theta.ln());
                let state = match at.model {
                    ModelKind::QuasiStatic => State::Stuck([at.s, phi]),
                    ModelKind::Inertial => State::Slipping([at.s, ln_v, phi]),
                };
                Some(return_map::regime(
                    &params,
                    state,
                    &regime_settings(&params),
                ))
            }
            (Ok(e), Some(at), Some(seg)) if !e.stopped => Some(regime_with_inertia_judged(
                at,
                seg.nu,
                &setup.scene_params,
                &watch,
                request.rtol,
            )),
            _ => None,
        };
        Simulation {
            setup,
            protocol,
            trajectory: envelope.into_trajectory(),
            stride,
            steps,
            t_end,
            end: end.map_err(Error::from),
            step_limit,
            interrupted,
            write_error,
            regime,
            threshold: watch.threshold,
            chosen_at,
        }
    }
}

/// What a run did not deliver ([`Simulation::shortfall`]).
#[derive(Debug)]
pub enum Shortfall<'a> {
    /// Stopped at `--max-steps` (a partial answer): where.
    StepLimit(String),
    /// Stopped by a signal or the observer: where.
    Interrupted { at: String },
    /// The integration failed.
    Failed(&'a Error),
    /// The time series is whole but its regime undetermined (partial): why.
    Undetermined(String),
}

impl std::fmt::Display for Shortfall<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Shortfall::StepLimit(text) | Shortfall::Undetermined(text) => f.write_str(text),
            Shortfall::Interrupted { at } => write!(f, "interrupted {at}"),
            Shortfall::Failed(e) => write!(f, "{e}"),
        }
    }
}

/// The regime reached from the sample `at` at the velocity `nu`, in the
/// model of the sample, with the model the whole orbit needs decided on it
/// ([`settled_with_inertia_judged`] under `watch`, the run's own model
/// decision): where inertia would matter on a quasi-static cycle the regime
/// is the inertial one.
fn regime_with_inertia_judged(
    at: Sample,
    nu: f64,
    scene: &crate::params::Params,
    watch: &InertiaWatch,
    rtol: f64,
) -> RegimeReached {
    let params_of = |kind| {
        let mut p = params_for(kind, scene);
        p.nu = nu;
        p
    };
    let kind = at.model;
    let params = params_of(kind);
    settle(
        kind,
        &params,
        [at.s, at.v, at.theta],
        &regime_settings(&params),
    )
    .and_then(|orbit| {
        settled_with_inertia_judged(kind, params_of, orbit, watch, rtol, regime_settings)
    })
    .map_or_else(settle_failure, |j| {
        measured_regime(j.kind, &j.params, &j.orbit)
    })
}

/// Why the regime is undetermined, in the text's units and with what a
/// user of the rig can do.
pub fn unsettled_text(why: &Unsettled, u: &Units, units: TextUnits, p: &Params) -> String {
    let time = |t: f64| match units {
        TextUnits::Physical => format!("{:.4e} s", t * u.d0 / u.v0),
        TextUnits::Dimensionless => format!("{t:.4e} (D0/V0)"),
    };
    match why {
        Unsettled::Settle(SettleError::NotSettled {
            time: t,
            periods,
            difference,
            ..
        }) => format!(
            "after {periods} oscillations (t = {}) the return map still moves by {difference:.2e} \
             of the orbit's size: a slowly attracting cycle or a slow decay near a bifurcation; \
             a longer --protocol gives it time",
            time(*t)
        ),
        Unsettled::Settle(SettleError::Integration { time: t, cause, .. }) => format!(
            "the integration failed at t = {}: {cause}{}",
            time(*t),
            law_range(p, u)
        ),
        Unsettled::Settle(e @ SettleError::Decayed { .. }) => e.summary(),
        Unsettled::Periods {
            extremes,
            return_map,
        } => format!(
            "the period between extremes of the spring force ({}) differs from the return map's \
             ({}) by more than 1e-6 relative",
            time(*extremes),
            time(*return_map)
        ),
        Unsettled::Integration(cause) => format!(
            "the integration over the cycle failed: {cause}{}",
            law_range(p, u)
        ),
    }
}

/// Where an integration failure may come from the friction law itself:
/// with `mu_vv` its direct effect vanishes at a velocity
/// ([`Params::direct_effect_bound`]), beyond which the law has no slip
/// velocity, and stick phases reach far below the driving velocity.
fn law_range(p: &Params, u: &Units) -> String {
    match p.direct_effect_bound() {
        Some((v, floor)) => format!(
            "; note that with mu_vv = {:e} the direct effect A + 2 mu_vv ln v + mu_vphi ln theta \
             of the law vanishes at v = {:.3e} µm/s (at the steady age) and is negative {} it, \
             where the law gives no slip velocity for a friction level: a cycle that slides \
             {} it leaves the law's range (a smaller |mu_vv| moves the bound away)",
            p.mu_vv,
            u.velocity_um_s(v),
            if floor { "below" } else { "above" },
            if floor { "slower than" } else { "faster than" }
        ),
        None => String::new(),
    }
}

/// A run: what was computed, how far and how it ended.
pub struct Simulation {
    pub setup: Setup,
    pub protocol: Vec<Segment>,
    /// The samples kept for the figures (every step up to the cap, then
    /// the extremes of every `stride` steps).
    pub trajectory: Trajectory,
    pub stride: usize,
    /// Integrator steps taken (samples handed to the observer).
    pub steps: usize,
    /// The end of the protocol (units `D0/V0`).
    pub t_end: f64,
    /// How the integration ended.
    pub end: Result<RunEnd, Error>,
    /// Stopped at `max_steps`.
    pub step_limit: bool,
    /// Stopped by the observer.
    pub interrupted: bool,
    /// The observer's error, which stopped the run.
    pub write_error: Option<std::io::Error>,
    /// The regime reached after a complete run.
    pub regime: Option<RegimeReached>,
    /// The inertia threshold of a switch to the inertial model.
    pub threshold: f64,
    /// The fastest pulling velocity (`nu`) where the model was chosen for
    /// it ([`Plan::chosen_at`]).
    pub chosen_at: Option<f64>,
}

impl Simulation {
    /// Why the run stopped short of the end of its protocol, if it did.
    pub fn cut(&self) -> Option<&'static str> {
        match &self.end {
            Ok(end) if end.stopped && self.step_limit => Some("stopped by --max-steps"),
            Ok(end) if end.stopped => Some("interrupted"),
            Ok(_) => None,
            Err(_) => Some("failed"),
        }
    }

    /// The simulated time reached (units `D0/V0`).
    pub fn t_reached(&self) -> f64 {
        self.trajectory.t.last().copied().unwrap_or(0.0)
    }

    /// The figures' title: the run's label, and where it stopped short.
    pub fn figure_title(&self) -> String {
        let time_unit = self.setup.scene.units.d0 / self.setup.scene.units.v0;
        match self.cut() {
            Some(why) => format!(
                "{} — {why} at t = {:.4e} s of {:.4e} s",
                self.setup.label,
                self.t_reached() * time_unit,
                self.t_end * time_unit
            ),
            None => self.setup.label.clone(),
        }
    }

    /// Why the model is the one it is (where it was chosen for the
    /// protocol's fastest pulling velocity, that velocity).
    pub fn model_reason(&self, units: TextUnits) -> String {
        let reason = &self.setup.choice.reason;
        match self.chosen_at {
            None => reason.clone(),
            Some(top) => format!(
                "{reason} (at the protocol's fastest pulling velocity, {})",
                match units {
                    TextUnits::Physical => {
                        format!("{:.4e} µm/s", self.setup.scene.units.velocity_um_s(top))
                    }
                    TextUnits::Dimensionless => format!("nu = {top:.4e}"),
                }
            ),
        }
    }

    /// What was asked and not delivered, if anything: the step limit, an
    /// interruption, a failed integration, or a whole time series whose
    /// regime is undetermined. Times in seconds.
    pub fn shortfall(&self, units: TextUnits) -> Option<Shortfall<'_>> {
        let u = &self.setup.scene.units;
        let time_unit = u.d0 / u.v0;
        match &self.end {
            Ok(end) if end.stopped && self.step_limit => Some(Shortfall::StepLimit(format!(
                "step limit: {} steps (--max-steps) at simulated time t = {:.6e} s of {:.6e} s",
                self.steps,
                end.t * time_unit,
                end.t_end * time_unit,
            ))),
            Ok(end) if end.stopped => Some(Shortfall::Interrupted {
                at: format!(
                    "at simulated time t = {:.6e} s of {:.6e} s ({} integrator steps)",
                    end.t * time_unit,
                    end.t_end * time_unit,
                    self.steps
                ),
            }),
            // The time series is whole; the regime it reaches, part of the
            // answer, is not determined.
            Ok(_) => match &self.regime {
                Some(RegimeReached::Unsettled(why)) => Some(Shortfall::Undetermined(format!(
                    "the regime the run reaches is undetermined: {}",
                    unsettled_text(why, u, units, &self.setup.params)
                ))),
                _ => None,
            },
            Err(e) => Some(Shortfall::Failed(e)),
        }
    }

    /// The sticks below `v_b` the run integrated quasi-statically, in
    /// words (text; JSON `quasi_static_sticks`), if there were any.
    pub fn sticks_text(&self) -> Option<String> {
        let sticks = self.end.as_ref().ok()?.sticks;
        let ln_v_b = sticks.ln_v_b.filter(|_| sticks.count > 0)?;
        Some(format!(
            "{} stick(s) below v_b = 10^{:.1} V0 integrated quasi-statically (rows with model \
             quasi-static): there inertia shifts ln v by less than rounding, and the block's \
             stop onto its stick velocity, dozens of decades lower, is faster than the rounding \
             of t (docs/cycles.md, \"Sticks below the resolution of f64\")",
            sticks.count,
            ln_v_b / std::f64::consts::LN_10
        ))
    }

    /// The run's JSON (`simulate --json`, Python's `to_dict()`): the
    /// scene, model and parameters, the protocol, steps and times in
    /// seconds, the switch to the inertial model, the regime reached with
    /// its period, force drop and slip per event in the scene's units,
    /// `complete` and `stop`.
    pub fn to_json(&self) -> serde_json::Value {
        let u = &self.setup.scene.units;
        let time_unit = u.d0 / u.v0;
        let switch = self.end.as_ref().ok().and_then(|end| end.switch);
        let regime = self.regime.as_ref().map(|r| match r {
            RegimeReached::Periodic {
                period,
                delta_s,
                slip,
                ..
            } => json!({
                "kind": "periodic",
                "period": period,
                "delta_s": delta_s,
                "slip": slip,
                "period_s": period * time_unit,
                "force_drop_N": delta_s * u.load,
                "slip_um": slip * u.d0 * 1e6,
            }),
            RegimeReached::Steady => json!({"kind": "steady"}),
            RegimeReached::Held => json!({"kind": "held"}),
            RegimeReached::Unsettled(why) => json!({
                "kind": "unsettled",
                "reason": unsettled_text(why, u, TextUnits::Physical, &self.setup.params),
            }),
        });
        let stop = self.shortfall(TextUnits::Physical).map(|s| s.to_string());
        json!({
            "scene": self.setup.scene.name,
            "label": self.setup.label,
            "model": self.setup.choice.kind,
            "model_reason": self.model_reason(TextUnits::Physical),
            "params": params_json(&self.setup.params),
            "units": UnitsRecord::of(u),
            "protocol": self.protocol.iter().map(|seg| json!({
                "V_um_per_s": u.velocity_um_s(seg.nu),
                "duration_s": seg.duration * time_unit,
                "nu": seg.nu,
                "duration": seg.duration,
            })).collect::<Vec<_>>(),
            "steps": self.steps,
            "t_end_s": self.t_end * time_unit,
            "t_reached_s": self.t_reached() * time_unit,
            "plot_stride": self.stride,
            "switch": switch.map(|s| json!({
                "t_s": s.t * time_unit,
                "t": s.t,
                "chi": s.chi,
                "inertia_threshold": self.threshold,
            })),
            "regime": regime,
            "quasi_static_sticks": self.end.as_ref().ok().map(|e| e.sticks).filter(|s| s.count > 0).map(|s| json!({
                "count": s.count,
                "v_b": s.ln_v_b.map(f64::exp),
                "log10_v_b": s.ln_v_b.map(|l| l / std::f64::consts::LN_10),
                "reason": self.sticks_text(),
            })),
            "complete": stop.is_none(),
            "stop": stop,
        })
    }
}
