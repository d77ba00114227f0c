//! An adaptive stiff integrator for `x' = f(x, p)`: the three-stage Radau IIA
//! method of order 5, organised like Hairer & Wanner's RADAU5 code
//! (*Solving Ordinary Differential Equations II*, 2nd ed., Springer 1996,
//! §IV.8).
//!
//! # The method
//! A step of length `h` from `(t0, y0)` solves the collocation equations
//! `Z_i = h sum_j a_ij f(y0 + Z_j)`, `i = 1..3`, at the Radau nodes
//! `c = ((4 - sqrt 6)/10, (4 + sqrt 6)/10, 1)`, and takes `y1 = y0 + Z_3`.
//! The method is L-stable and stiffly accurate, of order 5 at the step ends
//! and stage order 3.
//!
//! * **Linear algebra.** Simplified Newton with the exact Jacobian
//!   `J = D_x f(y0)` from dual numbers ([`VectorField::jacobian`]). The
//!   `3n x 3n` iteration matrix is *not* formed: with the eigen-decomposition
//!   of the Butcher matrix it splits into one real `n x n` system with
//!   `(gamma/h) I - J` and one complex `n x n` system with
//!   `((alpha + i beta)/h) I - J`, each LU-factored (partial pivoting, in
//!   preallocated storage) once per step size. `J` and the factors are reused
//!   across steps while Newton contracts fast ([`Settings::jac_reuse_theta`],
//!   [`Settings::keep_h_ratio`]).
//! * **Error control.** The embedded estimate
//!   `err = ((gamma/h) I - J)^-1 (f(y0) + (d . Z)/h)` — the difference to an
//!   order-3 formula, filtered by `(I - h gamma0 J)^-1` (`gamma0 = 1/gamma`)
//!   so that it does not blow up for stiff components — measured in the RMS
//!   norm with weights `atol_i + rtol |y_i|`. The new step is
//!   `h_new = h / clamp(err^(1/4) / fac, 1/fac_max, 1/fac_min)` with
//!   `fac = min(safety, safety (2 k_max + 1)/(k + 2 k_max))` (`k` Newton
//!   iterations used), combined with Gustafsson's predictive controller on
//!   accepted steps. A step with `err >= 1` is rejected.
//! * **Tolerances.** As in RADAU5 the user's `rtol`, `atol` are mapped to the
//!   internal `rtol' = 0.1 rtol^(2/3)`, `atol' = atol rtol'/rtol` because the
//!   estimate is of lower order than the method; with that mapping the global
//!   error falls roughly in proportion to `rtol`, but the ratio depends on the
//!   problem: about `0.3–1 x rtol` on Van der Pol with `mu = 1000`
//!   (`rtol = 1e-5..1e-8`), `0.3 x rtol` on a stiff linear system at
//!   `rtol = 1e-12`, but up to several hundred times `rtol` on smooth
//!   non-stiff oscillations at `rtol <= 1e-10` (harmonic oscillator, Kepler),
//!   where the method takes few long steps.
//! * **Dense output.** The collocation polynomial of each accepted step (degree
//!   3, through `y0, y0 + Z_1, y0 + Z_2, y1`) gives the solution anywhere in
//!   the step ([`StepView::eval`], output grids, events).
//! * **Time.** The time reached is kept as a compensated sum `t + t_lo`
//!   (Knuth's two-sum at every step), so a long run resolves steps far below
//!   the rounding of `t` (`eps |t|`): a slip at `t = 2e7` that needs steps of
//!   `4e-8`, ten units in the last place of `t`, is integrated as at `t = 0`.
//!   The times handed out (records, events, [`StepView`]) are the rounded
//!   `t`; the dense output measures its offsets from the compensated step
//!   end. The step size only underflows at `0.1 |h| <= eps^2 |t|`.
//! * **Events.** Zeros of user functions `g(t, x)` are located on the dense
//!   output by the Illinois method ([`EventFunction`]).
//!
//! # Use
//! ```
//! use continuation::integrate::{Output, Radau5, Settings};
//! use continuation::{Scalar, VectorField};
//! struct Decay;
//! impl VectorField for Decay {
//!     fn dim(&self) -> usize { 1 }
//!     fn n_params(&self) -> usize { 1 }
//!     fn rhs<D: Scalar>(&self, x: &[D], p: &[D], out: &mut [D]) { out[0] = -p[0] * x[0]; }
//! }
//! let settings = Settings { rtol: 1e-10, atol: 1e-12, ..Settings::default() };
//! let sol = Radau5::new(&Decay, &[2.0], settings)
//!     .solve(0.0, &[1.0], 1.0, Output::Grid(vec![0.5, 1.0]))
//!     .into_result()
//!     .unwrap();
//! assert!((sol.x[1][0] - (-2.0f64).exp()).abs() < 1e-9);
//! ```

mod driver;
mod error;
mod events;
mod lu;
mod record;
mod setup;
mod step;
mod tableau;

pub use error::{IntegrateError, NewtonTrouble};
pub use events::{Crossing, EventDirection, EventFunction};

use crate::system::VectorField;

/// Tolerances and limits of [`Radau5`]. All fields have defaults.
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    /// Relative tolerance. Default `1e-6`. Must exceed `1e-14`.
    pub rtol: f64,
    /// Absolute tolerance for every component. Default `1e-9`.
    pub atol: f64,
    /// Per-component absolute tolerances (length `n`), overriding `atol`.
    /// Default `None`.
    pub atol_components: Option<Vec<f64>>,
    /// Initial step size. Default `None`: `0.01 |x0|_w / |f(x0)|_w` in the
    /// weighted RMS norm (or `1e-6` if either is tiny), capped by `h_max`.
    pub h0: Option<f64>,
    /// Smallest step size before [`IntegrateError::StepSizeUnderflow`].
    /// Default `0` (only the rounding bound `0.1 |h| <= eps^2 |t|` of the
    /// compensated time applies, see the module documentation).
    pub h_min: f64,
    /// Largest step size. Default `inf` (bounded by the interval length).
    pub h_max: f64,
    /// Maximum number of step attempts. Default `100_000`.
    pub max_steps: usize,
    /// Safety factor of the step-size controller. Default `0.9`.
    pub safety: f64,
    /// Smallest ratio `h_new / h`. Default `0.2`.
    pub fac_min: f64,
    /// Largest ratio `h_new / h`. Default `8`.
    pub fac_max: f64,
    /// Gustafsson's predictive step-size controller on accepted steps
    /// (Hairer & Wanner II, eq. IV.8.25). Default `true`.
    pub predictive: bool,
    /// Newton iteration limit per step attempt. Default `7`.
    pub newton_max_iter: usize,
    /// Consecutive Newton failures (each halves `h`) before
    /// [`IntegrateError::NewtonFailed`]. Default `20`.
    pub max_newton_failures: usize,
    /// The Jacobian is kept for the next step if the Newton contraction factor
    /// was at most this. Default `0.001`; a negative value recomputes it on
    /// every step.
    pub jac_reuse_theta: f64,
    /// The LU factors are kept (and `h` unchanged) when `h_new / h` lies in
    /// this interval and the Jacobian is kept. Default `(1.0, 1.2)`.
    pub keep_h_ratio: (f64, f64),
    /// Relative width of the final bracket of an event time:
    /// `|dt| <= event_tol * max(|t|, |h|)`. Default `1e-12`.
    pub event_tol: f64,
    /// Points per step at which the event functions are sampled (the step end
    /// plus `event_samples - 1` equally spaced interior points). More samples
    /// catch pairs of zeros inside one step. Default `1`.
    pub event_samples: usize,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            rtol: 1e-6,
            atol: 1e-9,
            atol_components: None,
            h0: None,
            h_min: 0.0,
            h_max: f64::INFINITY,
            max_steps: 100_000,
            safety: 0.9,
            fac_min: 0.2,
            fac_max: 8.0,
            predictive: true,
            newton_max_iter: 7,
            max_newton_failures: 20,
            jac_reuse_theta: 0.001,
            keep_h_ratio: (1.0, 1.2),
            event_tol: 1e-12,
            event_samples: 1,
        }
    }
}

/// What the integrator records in [`Solution::t`] and [`Solution::x`].
#[derive(Clone, Debug, PartialEq)]
pub enum Output {
    /// The initial point and the end of every accepted step.
    Steps,
    /// The solution at these times (monotone in the direction of integration,
    /// inside the interval), from the dense output.
    Grid(Vec<f64>),
    /// Nothing but the final state ([`Solution::t_final`], [`Solution::x_final`]).
    Final,
}

/// Why the integration stopped.
#[derive(Clone, Debug, PartialEq)]
pub enum Outcome {
    /// `t_end` was reached.
    ReachedEnd,
    /// A terminal event fired; the crossing is the last of [`Solution::events`].
    TerminalEvent {
        /// Index of the event function.
        index: usize,
    },
    /// The observer asked to stop after an accepted step.
    ObserverStop,
    /// The integration failed; the solution holds everything up to the last
    /// accepted step.
    Failed(IntegrateError),
}

/// Work counters.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Stats {
    /// Step attempts (accepted + rejected + Newton failures).
    pub steps: usize,
    /// Accepted steps.
    pub accepted: usize,
    /// Steps rejected by the error test.
    pub rejected: usize,
    /// Step attempts abandoned because Newton failed or converged too slowly.
    pub newton_failures: usize,
    /// Evaluations of `f`.
    pub rhs_evals: usize,
    /// Evaluations of the Jacobian.
    pub jacobians: usize,
    /// Pairs of LU factorisations (real + complex).
    pub factorizations: usize,
}

/// The result of an integration: the recorded trajectory, the events, the
/// final state and why it stopped.
#[must_use = "check `outcome` (or call `into_result`): the integration may have failed"]
#[derive(Clone, Debug, PartialEq)]
pub struct Solution {
    /// Recorded times (see [`Output`]).
    pub t: Vec<f64>,
    /// Recorded states, one per entry of `t`.
    pub x: Vec<Vec<f64>>,
    /// All located event crossings, in order of time.
    pub events: Vec<Crossing>,
    /// The time reached (`t_end`, the terminal event, or the last accepted step).
    pub t_final: f64,
    /// The state at `t_final`.
    pub x_final: Vec<f64>,
    /// Why the integration stopped.
    pub outcome: Outcome,
    /// Work counters.
    pub stats: Stats,
}

impl Solution {
    /// `Err` if the integration failed, else the solution.
    pub fn into_result(self) -> Result<Solution, IntegrateError> {
        match self.outcome {
            Outcome::Failed(e) => Err(e),
            _ => Ok(self),
        }
    }
}

/// An accepted step as shown to the observer of [`Radau5::solve_with`].
pub struct StepView<'s> {
    /// Start of the step.
    pub t_prev: f64,
    /// End of the step (the terminal event time if one fired in this step).
    pub t: f64,
    /// State at `t`.
    pub x: &'s [f64],
    /// Length of the step taken (`t_new - t_prev` before any event truncation).
    pub h: f64,
    dense: step::Dense<'s>,
}

impl StepView<'_> {
    /// Writes the dense-output solution at `t` (inside `[t_prev, t]`) into `out`.
    pub fn eval(&self, t: f64, out: &mut [f64]) {
        self.dense.eval(t, out);
    }
}

/// The Radau IIA (order 5) integrator for one system and parameter vector,
/// with its event functions. See the [module documentation](self).
pub struct Radau5<'a, S: VectorField> {
    sys: &'a S,
    p: Vec<f64>,
    settings: Settings,
    events: Vec<EventFunction<'a>>,
}

impl<'a, S: VectorField> Radau5<'a, S> {
    /// An integrator for `x' = f(x, p)` with these settings.
    pub fn new(sys: &'a S, p: &[f64], settings: Settings) -> Self {
        Radau5 {
            sys,
            p: p.to_vec(),
            settings,
            events: Vec::new(),
        }
    }

    /// Adds an event function (builder style); its index is its position.
    pub fn with_event(mut self, event: EventFunction<'a>) -> Self {
        self.events.push(event);
        self
    }

    /// Adds an event function; returns its index.
    pub fn add_event(&mut self, event: EventFunction<'a>) -> usize {
        self.events.push(event);
        self.events.len() - 1
    }

    /// The settings.
    pub fn settings(&self) -> &Settings {
        &self.settings
    }

    /// Integrates from `(t0, x0)` to `t_end` (which may be smaller than `t0`),
    /// recording as `output` says. Never panics on bad input: failures are
    /// reported in [`Solution::outcome`].
    pub fn solve(&mut self, t0: f64, x0: &[f64], t_end: f64, output: Output) -> Solution {
        self.solve_with(t0, x0, t_end, output, |_| {
            std::ops::ControlFlow::Continue(())
        })
    }

    /// As [`solve`](Self::solve), calling `observer` after every accepted step
    /// (after the events and the output of that step); returning
    /// `ControlFlow::Break(())` stops with [`Outcome::ObserverStop`].
    pub fn solve_with(
        &mut self,
        t0: f64,
        x0: &[f64],
        t_end: f64,
        output: Output,
        observer: impl FnMut(&StepView<'_>) -> std::ops::ControlFlow<()>,
    ) -> Solution {
        driver::run(self, t0, x0, t_end, output, observer)
    }
}

/// Integrates `x' = f(x, p)` from `(t0, x0)` to `t_end` with the given
/// settings, recording every accepted step. Shorthand for
/// `Radau5::new(sys, p, settings).solve(t0, x0, t_end, Output::Steps)`.
pub fn solve<S: VectorField>(
    sys: &S,
    p: &[f64],
    t0: f64,
    x0: &[f64],
    t_end: f64,
    settings: Settings,
) -> Solution {
    Radau5::new(sys, p, settings).solve(t0, x0, t_end, Output::Steps)
}
