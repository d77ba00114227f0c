//! The inertial block whose stick lies below the resolution of `f64`: its
//! slips integrated with inertia, its sticks quasi-statically, joined where
//! inertia has fallen below rounding.
//!
//! With a small direct effect `A` and inertia `m` the block comes to rest
//! from a slip onto a stick velocity tens of decades below `V0`
//! (docs/hard-cases.md, "An inertial stick phase slower than f64 can
//! relax"): the inertial equation `m v d(ln v)/dt = s - mu(v, theta)`
//! (docs/model.md) then relaxes `ln v` at the rate `mu_v / (m v)`, beyond
//! `1e50 V0/D0`, onto the quasi-static manifold `s = mu(v, theta) + eta_d v`.
//! That drop of `ln v` by 50 decades and more takes less time than the
//! rounding of `t`; no integrator or collocation mesh resolves it. Below a
//! velocity `v_b` it need not be resolved:
//!
//! - **on the manifold** inertia shifts `ln v` by `chi = m v |d ln v/dt| /
//!   mu_v` ([`super::orbit_inertia`]); in the stick `d ln v/dt` is about
//!   `(kappa nu + mu_phi / theta) / mu_v`, so below
//!
//!   ```text
//!   v_b = 1e-3 eps mu_v^2 / (m (kappa nu + |B|))          (eps = 2^-52)
//!   ```
//!
//!   the quasi-static velocity is the inertial one to rounding (checked
//!   where each stick ends: [`Passage::chi_at_reentry`]);
//! - **coming to rest**, the block decelerates from `v_b` under a force gap
//!   `|s - mu| >= mu_v` within `m v_b / mu_v`, a time over which `s` and
//!   `ln theta` change by less than `eps` relative.
//!
//! The flow here integrates the inertial block (Radau IIA, [`Radau5`], in
//! the log variables of [`LogBlock::new`]) until `v` falls through `v_b`,
//! continues from the same `(s, theta)` with the quasi-static block until
//! its velocity rises through `v_b`, and from there inertially again. A
//! stick that never gets below `v_b` is never switched: the flow is then the
//! inertial block's own. [`JoinedFlow::passage`] integrates from the
//! Poincaré section `v = nu` (rising, where the spring force is at its
//! largest, `ds/dt = kappa (nu - v) = 0`) to the next crossing: the return
//! map whose fixed points are stick-slip cycles ([`super::return_map`]).

use super::orbit_inertia::state_imbalance;
use super::simulate::integration_stop;
use crate::log_model::LogBlock;
use crate::model::ModelKind;
use crate::params::Params;
use continuation::integrate::{EventDirection, EventFunction, Outcome, Output, Radau5, Settings};

/// Sticks and slips a passage may have before it is called non-returning
/// (a stick-slip cycle has one of each).
const MAX_SEGMENTS: usize = 16;

/// The joined inertial and quasi-static flow of one scene.
#[derive(Clone, Debug)]
pub struct JoinedFlow {
    slip: LogBlock,
    stick: LogBlock,
    p: Vec<f64>,
    m: f64,
    /// `ln v_b`: the switch between the models (module docs).
    pub ln_v_b: f64,
    /// `ln nu`: the section.
    ln_nu: f64,
    settings: Settings,
}

/// One passage from the section back to it.
#[derive(Clone, Debug, PartialEq)]
pub struct Passage {
    /// `(s, ln theta)` where the orbit crosses the section again.
    pub end: [f64; 2],
    /// The time it took (units of `D0/V0`).
    pub period: f64,
    /// `(t, s, ln v, ln theta)` at the accepted steps, with `t` from the
    /// start of the passage (empty unless asked for).
    pub samples: Vec<[f64; 4]>,
    /// The least spring force: where `v` falls through `nu` (`ds/dt = 0`),
    /// located as an event.
    pub s_min: f64,
    /// The largest inertial imbalance `chi` at the accepted steps of the
    /// slips (0 unless sampled).
    pub chi: f64,
    /// Quasi-static sticks on the way.
    pub sticks: usize,
    /// The largest inertial imbalance `chi` where a stick ended (0 without
    /// a stick): the error in `ln v` the quasi-static stick made there.
    pub chi_at_reentry: f64,
}

/// A state of the joined flow.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum State {
    /// Inertial: `(s, ln v, ln theta)`.
    Slipping([f64; 3]),
    /// In a stick below `v_b`: `(s, ln theta)`.
    Stuck([f64; 2]),
}

/// Why a passage could not be integrated.
#[derive(Clone, Debug, PartialEq)]
pub enum PassageError {
    /// The integrator failed (its message) at time `t` of the passage.
    Integration { t: f64, cause: String },
    /// No return to the section within `t_max` or [`MAX_SEGMENTS`]
    /// segments: the orbit settles, or runs away.
    NoReturn { t: f64, segments: usize },
}

impl std::fmt::Display for PassageError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            PassageError::Integration { t, cause } => {
                write!(f, "integrating a period, at t = {t:.6e} D0/V0: {cause}")
            }
            PassageError::NoReturn { t, segments } => write!(
                f,
                "the orbit did not return to v = nu within t = {t:.6e} D0/V0 ({segments} \
                 segments): no stick-slip cycle there"
            ),
        }
    }
}

/// `ln v_b`, below which the inertial block of `params` sticks on its
/// quasi-static manifold to rounding (module docs): `v_b = 1e-3 eps mu_v^2
/// / (m (kappa nu + |B|))`, with `mu_v` at steady sliding.
pub fn stick_threshold(params: &Params) -> f64 {
    let mu_v = params.mu_v();
    let rate = params.kappa * params.nu + params.b.abs();
    (1e-3 * f64::EPSILON * mu_v * mu_v / (params.m * rate)).ln()
}

impl JoinedFlow {
    /// The flow of `params`, integrated at relative tolerance `rtol`.
    pub fn new(params: &Params, rtol: f64) -> Self {
        JoinedFlow {
            slip: LogBlock::new(ModelKind::Inertial, params),
            stick: LogBlock::new(ModelKind::QuasiStatic, params),
            p: params.to_vec(),
            m: params.m,
            ln_v_b: stick_threshold(params),
            ln_nu: params.nu.ln(),
            settings: Settings {
                rtol,
                atol: rtol * 1e-3,
                event_tol: 1e-14,
                ..Settings::default()
            },
        }
    }

    /// The inertial state `(s, ln v, ln theta)` on the section at `(s, ln theta)`.
    pub fn on_section(&self, x: [f64; 2]) -> [f64; 3] {
        [x[0], self.ln_nu, x[1]]
    }

    /// From `(s, ln theta)` on the section to the next crossing, within
    /// the time `t_max`; with the accepted steps when `sample`.
    pub fn passage(&self, x0: [f64; 2], t_max: f64, sample: bool) -> Result<Passage, PassageError> {
        self.run(State::Slipping(self.on_section(x0)), t_max, sample)
    }

    /// From any state of the joined flow to the first crossing of the
    /// section within `t_max`: its `(s, ln theta)` there.
    pub fn to_section(&self, start: State, t_max: f64) -> Result<[f64; 2], PassageError> {
        self.run(start, t_max, false).map(|p| p.end)
    }

    /// From `start` to the first crossing of the section (not counting one
    /// at the start itself).
    fn run(&self, start: State, t_max: f64, sample: bool) -> Result<Passage, PassageError> {
        let output = if sample { Output::Steps } else { Output::Final };
        let (mut x, mut slipping) = match start {
            State::Slipping(x) => (x.to_vec(), true),
            State::Stuck(x) => (x.to_vec(), false),
        };
        let (mut t, mut samples, mut sticks) = (0.0f64, Vec::new(), 0);
        let (mut chi_at_reentry, mut chi, mut s_min) = (0.0f64, 0.0f64, f64::INFINITY);
        for segment in 0..MAX_SEGMENTS {
            let sol = if slipping {
                let ln_nu = self.ln_nu;
                let ln_v_b = self.ln_v_b;
                let section = EventFunction::new(move |_, y: &[f64]| y[1] - ln_nu)
                    .direction(EventDirection::Rising)
                    .terminal(true);
                let rest = EventFunction::new(move |_, y: &[f64]| y[1] - ln_v_b)
                    .direction(EventDirection::Falling)
                    .terminal(true);
                let slowing = EventFunction::new(move |_, y: &[f64]| y[1] - ln_nu)
                    .direction(EventDirection::Falling);
                Radau5::new(&self.slip, &self.p, self.settings.clone())
                    .with_event(section)
                    .with_event(rest)
                    .with_event(slowing)
                    .solve(0.0, &x, t_max - t, output.clone())
            } else {
                let stick = self.stick;
                let p = &self.p;
                let ln_v_b = self.ln_v_b;
                let moves =
                    EventFunction::new(move |_, y: &[f64]| stick.ln_velocity(y, p) - ln_v_b)
                        .direction(EventDirection::Rising)
                        .terminal(true);
                Radau5::new(&self.stick, &self.p, self.settings.clone())
                    .with_event(moves)
                    .solve(0.0, &x, t_max - t, output.clone())
            };
            if slipping {
                for c in sol.events.iter().filter(|c| c.index == 2) {
                    s_min = s_min.min(c.x[0]);
                }
                for y in &sol.x {
                    chi = chi.max(state_imbalance(&self.slip, y, &self.p, self.m));
                }
            }
            if sample {
                samples.extend(sol.t.iter().zip(&sol.x).map(|(&ts, y)| {
                    let ln_v = if slipping {
                        y[1]
                    } else {
                        self.stick.ln_velocity(y, &self.p)
                    };
                    [t + ts, y[0], ln_v, y[y.len() - 1]]
                }));
            }
            let fired = match &sol.outcome {
                Outcome::TerminalEvent { index } => *index,
                Outcome::Failed(e) => {
                    return Err(PassageError::Integration {
                        t: t + sol.t_final,
                        cause: integration_stop(e),
                    })
                }
                Outcome::ReachedEnd | Outcome::ObserverStop => {
                    return Err(PassageError::NoReturn {
                        t: t + sol.t_final,
                        segments: segment + 1,
                    })
                }
            };
            t += sol.t_final;
            let y = sol.x_final;
            match (slipping, fired) {
                (true, 0) => {
                    return Ok(Passage {
                        end: [y[0], y[2]],
                        period: t,
                        samples,
                        s_min,
                        chi,
                        sticks,
                        chi_at_reentry,
                    })
                }
                // Comes to rest below v_b: the stick, from the same (s, theta).
                (true, _) => x = vec![y[0], y[2]],
                // Leaves the stick at v_b: inertially from the manifold.
                (false, _) => {
                    chi_at_reentry =
                        chi_at_reentry.max(state_imbalance(&self.stick, &y, &self.p, self.m));
                    sticks += 1;
                    x = vec![y[0], self.ln_v_b, y[1]];
                }
            }
            slipping = !slipping;
        }
        Err(PassageError::NoReturn {
            t,
            segments: MAX_SEGMENTS,
        })
    }
}
