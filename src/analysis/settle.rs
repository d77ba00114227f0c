//! Settling on a stick-slip attractor by simulation: integrate the driven
//! block from a stuck state and watch the Poincaré return map until it stops
//! moving (a periodic orbit) or the orbit falls onto steady sliding.
//!
//! The section is `v = nu` crossed upward, where `ds/dt = kappa (nu - v)`
//! changes sign from positive to negative: the spring force is at a maximum.
//! With `x_k` the state (log variables of [`LogBlock`]) at the `k`-th crossing,
//! the orbit has settled on a cycle when
//!
//! ```text
//! |x_{k+1} - x_k|  <=  tol * E_k,
//! ```
//!
//! both measured in the scaled distance [`gap`] (`E_k`: the largest distance
//! from steady sliding during the `k`-th period). It has decayed to steady
//! sliding when that distance falls below `decay_tol` at any step, where
//! steady sliding attracts; where it repels (an eigenvalue with
//! `Re lambda > 0`) an orbit that close is leaving it (a run started
//! `1e-6` from steady sliding was called decayed at its first step).
//!
//! Steps are bounded by a twentieth of the period `2 pi / |Im lambda|` of
//! steady sliding's oscillatory eigenvalues: Radau IIA damps oscillations it
//! does not resolve (its stability function `|R(z)| < 1` for large `|z|`),
//! and the error estimate lets the steps grow on a small oscillation about
//! steady sliding. Unbounded, at `nu = 90, m = 1e-3, kappa = 0.364` and
//! `rtol = 1e-9` the steps reach a third of the period and the oscillation
//! decays sevenfold in 60 time units where the true one grows by 2 %
//! (`Re lambda = 4.5e-4`): a spurious decay to steady sliding.

use crate::analysis::simulate::integration_stop;
use crate::log_model::LogBlock;
use crate::model::{steady_state, DrivenBlock, ModelKind};
use crate::params::Params;
use continuation::eigenvalues;
use continuation::integrate::{EventDirection, EventFunction, Outcome, Output, Radau5, Settings};
use continuation::system::jacobian;
use std::ops::ControlFlow;
use thiserror::Error;

/// Tolerances and budget of [`settle`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SettleSettings {
    /// Relative tolerance of the Radau IIA integration.
    pub rtol: f64,
    /// Return-map tolerance relative to the orbit's extent.
    pub tol: f64,
    /// Scaled distance from steady sliding below which the orbit has decayed.
    pub decay_tol: f64,
    /// Most crossings of the section before giving up.
    pub max_periods: usize,
    /// Longest simulated time, units `D0/V0`.
    pub max_time: f64,
}

impl SettleSettings {
    /// Defaults for `params`: `rtol = 1e-10`, `tol = 1e-7` (a start for Newton's method, not the answer), `decay_tol = 1e-6`,
    /// 10 000 periods, and `max_time = 10 000 t*` with the time scale
    /// `t* = max(2 pi sqrt(m/kappa), 10 A/(kappa nu), 1/nu)` — the longest of
    /// the inertial period, the time the spring takes to load by ten
    /// direct-effect units `A` (a stick phase; with the corrections and
    /// damping, the slope `mu_v + eta_d nu`), and the memory time `D0/V`.
    pub fn for_params(p: &Params) -> Self {
        let inertial = 2.0 * std::f64::consts::PI * (p.m / p.kappa).sqrt();
        let loading = 10.0 * direct_effect(p) / (p.kappa * p.nu);
        let scale = inertial.max(loading).max(1.0 / p.nu);
        SettleSettings {
            rtol: 1e-10,
            tol: 1e-7,
            decay_tol: 1e-6,
            max_periods: 10_000,
            max_time: 10_000.0 * scale,
        }
    }
}

/// An orbit found periodic by the return map.
#[derive(Clone, Debug)]
pub struct SettledOrbit {
    /// The state on the section (`v = nu` upward), log variables of [`LogBlock`].
    pub section: Vec<f64>,
    /// Time between the last two crossings, units `D0/V0`.
    pub period: f64,
    /// Crossings simulated until the return map settled.
    pub periods: usize,
    /// Simulated time until then.
    pub time: f64,
    /// Last return-map difference relative to the orbit's extent.
    pub difference: f64,
}

/// Why no periodic orbit was found.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum SettleError {
    #[error(
        "the simulated orbit at kappa = {kappa:.6e} decayed to steady sliding after t = {time:.4e} \
         ({periods} oscillation(s)): no stick-slip cycle coexists with steady sliding at this stiffness \
         reachable from a stuck start; try a smaller stiffness (--set kappa=...)"
    )]
    Decayed {
        kappa: f64,
        time: f64,
        periods: usize,
    },
    #[error(
        "the simulated orbit at kappa = {kappa:.6e} did not settle within t = {time:.4e} \
         ({periods} oscillations): the return map still moves by {difference:.2e} of the orbit's size \
         (extent {extent_first:.3e} in the first period, {extent_last:.3e} in the last); \
         a slowly attracting cycle or a slow decay near a bifurcation — try another stiffness"
    )]
    NotSettled {
        kappa: f64,
        time: f64,
        periods: usize,
        difference: f64,
        extent_first: f64,
        extent_last: f64,
    },
    #[error("the simulation at kappa = {kappa:.6e} failed at t = {time:.4e}: {cause}")]
    Integration {
        kappa: f64,
        time: f64,
        cause: String,
    },
}

impl SettleError {
    /// The stiffness simulated.
    pub fn kappa(&self) -> f64 {
        match self {
            SettleError::Decayed { kappa, .. }
            | SettleError::NotSettled { kappa, .. }
            | SettleError::Integration { kappa, .. } => *kappa,
        }
    }

    /// The outcome in a few words (a decay without the advice).
    pub fn summary(&self) -> String {
        match self {
            SettleError::Decayed { kappa, periods, .. } => format!(
                "at kappa = {kappa:.3e} the orbit decayed to steady sliding after {periods} oscillations"
            ),
            other => other.to_string(),
        }
    }
}

/// Steady sliding in docs/model.md's variables and the scale of `s`.
struct Steady {
    s: f64,
    ln_v: f64,
    ln_theta: f64,
    /// Force changes are measured in units of the direct effect
    /// ([`direct_effect`]).
    a: f64,
}

impl Steady {
    fn of(p: &Params) -> Self {
        Steady {
            // With radiation damping the spring also balances eta_d nu.
            s: p.friction().steady_force(p.nu),
            ln_v: p.nu.ln(),
            ln_theta: -p.nu.ln(),
            a: direct_effect(p),
        }
    }
}

/// The direct effect at steady sliding, the scale of force changes: the
/// slope `mu_v + eta_d nu` (`A` with neither the corrections in `ln v`
/// nor damping), or `A` where that slope is not positive (the law outside
/// its range there).
fn direct_effect(p: &Params) -> f64 {
    Some(p.mu_v_damped())
        .filter(|x| *x > 0.0 && x.is_finite())
        .unwrap_or(p.a)
}

/// Scaled distance between two states `(s, v, theta)`:
/// `max(|Delta s| / A, |Delta ln v|, |Delta ln theta|)`.
fn gap(a: [f64; 3], b: [f64; 3], scale_s: f64) -> f64 {
    let d_s = (a[0] - b[0]).abs() / scale_s;
    let d_v = (a[1].ln() - b[1].ln()).abs();
    let d_theta = (a[2].ln() - b[2].ln()).abs();
    d_s.max(d_v).max(d_theta)
}

/// What an integration near steady sliding at `params` needs to know of
/// its eigenvalues `lambda`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SteadySpectrum {
    /// A twentieth of the shortest period `2 pi / |Im lambda|` (infinite
    /// when they are all real, or when the eigenvalue solver fails: the
    /// steps are then bounded by the tolerance alone, as everywhere else).
    pub step_bound: f64,
    /// Some `Re lambda > 0`: steady sliding repels, and an orbit near it
    /// has not decayed onto it (false where the solver fails).
    pub growing: bool,
}

impl SteadySpectrum {
    /// The spectrum of steady sliding of the model `kind` at `params`.
    pub fn of(kind: ModelKind, params: &Params) -> Self {
        let block = DrivenBlock::new(kind, params);
        let x = steady_state(kind, params);
        let ev = eigenvalues(&jacobian(&block, &x, &params.to_vec()));
        let omega = ev
            .as_ref()
            .map_or(0.0, |ev| ev.iter().fold(0.0f64, |w, l| w.max(l.im.abs())));
        SteadySpectrum {
            step_bound: if omega > 0.0 {
                2.0 * std::f64::consts::PI / (20.0 * omega)
            } else {
                f64::INFINITY
            },
            growing: ev.is_ok_and(|ev| ev.iter().any(|l| l.re > 0.0)),
        }
    }
}

/// Integrates the block at `params` from `start` (docs/model.md's `(s, v, theta)`)
/// until the return map on `v = nu` (upward) settles; see the module docs.
pub fn settle(
    kind: ModelKind,
    params: &Params,
    start: [f64; 3],
    settings: &SettleSettings,
) -> Result<SettledOrbit, SettleError> {
    let log = LogBlock::new(kind, params);
    let pv = params.to_vec();
    let steady = Steady::of(params);
    let rest = [steady.s, steady.ln_v.exp(), steady.ln_theta.exp()];
    let distance = |x: &[f64]| gap(log.to_model(x, &pv), rest, steady.a);
    let spectrum = SteadySpectrum::of(kind, params);
    let integration = Settings {
        rtol: settings.rtol,
        atol: settings.rtol * 1e-3,
        h_max: spectrum.step_bound,
        ..Settings::default()
    };
    let kappa = params.kappa;
    let (mut x, mut t) = (log.from_model(start[0], start[1], start[2]), 0.0);
    let mut previous: Option<Vec<f64>> = None;
    let (mut extent_first, mut periods) = (None, 0);
    let mut difference = f64::INFINITY;
    let mut extent = 0.0;
    while periods < settings.max_periods && t < settings.max_time {
        let ln_nu = steady.ln_v;
        let section = EventFunction::new(|_, y: &[f64]| log.ln_velocity(y, &pv) - ln_nu)
            .direction(EventDirection::Rising)
            .terminal(true);
        let mut solver = Radau5::new(&log, &pv, integration.clone()).with_event(section);
        extent = 0.0f64;
        let mut decayed = false;
        let sol = solver.solve_with(t, &x, settings.max_time, Output::Final, |step| {
            let d = distance(step.x);
            extent = extent.max(d);
            // Near a repelling steady sliding the orbit is only passing.
            decayed = !spectrum.growing && d < settings.decay_tol;
            if decayed {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        });
        let t_start = t;
        (t, x) = (sol.t_final, sol.x_final);
        match sol.outcome {
            Outcome::Failed(e) => {
                return Err(SettleError::Integration {
                    kappa,
                    time: t,
                    cause: integration_stop(&e),
                })
            }
            _ if decayed => {
                return Err(SettleError::Decayed {
                    kappa,
                    time: t,
                    periods,
                })
            }
            Outcome::ReachedEnd | Outcome::ObserverStop => break,
            Outcome::TerminalEvent { .. } => {}
        }
        periods += 1;
        extent_first.get_or_insert(extent);
        if let Some(prev) = previous.replace(x.clone()) {
            difference = gap(log.to_model(&x, &pv), log.to_model(&prev, &pv), steady.a)
                / extent.max(f64::MIN_POSITIVE);
            if difference <= settings.tol {
                return Ok(SettledOrbit {
                    section: x,
                    period: t - t_start,
                    periods,
                    time: t,
                    difference,
                });
            }
        }
    }
    Err(SettleError::NotSettled {
        kappa,
        time: t,
        periods,
        difference,
        extent_first: extent_first.unwrap_or(extent),
        extent_last: extent,
    })
}

/// A stuck start for `params`: the interface aged `theta = 100 t*` with
/// `t* = max(1/nu, 10 A/(kappa nu))` (the memory time, or the time the
/// spring takes to load by ten direct-effect units, [`direct_effect`]),
/// creeping at `v = 1e-3 nu`, and the spring force balancing friction and
/// damping, `s = mu(v, theta) + eta_d v`. Far from steady sliding: the
/// first slip is a large one.
pub fn stuck_start(params: &Params) -> [f64; 3] {
    let loading = 10.0 * direct_effect(params) / (params.kappa * params.nu);
    let age = 100.0 * (1.0 / params.nu).max(loading);
    let v = 1e-3 * params.nu;
    let law = params.friction();
    [law.mu(v, age) + law.damping(v), v, age]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn params(b: f64) -> Params {
        Params {
            kappa: 0.01,
            nu: 1.0,
            m: 0.01,
            a: 0.012,
            b,
            mu0: 0.5,
            mu2: 0.0,
            theta_c: None,
            state_law: Default::default(),
            mu_vv: 0.0,
            mu_vphi: 0.0,
            eta_d: 0.0,
        }
    }

    #[test]
    fn velocity_strengthening_friction_decays_to_steady_sliding() {
        // B < A: steady friction strengthens with velocity and ageing cannot
        // hold the block; every start ends in steady sliding.
        let p = params(0.005);
        let out = settle(
            ModelKind::Inertial,
            &p,
            stuck_start(&p),
            &SettleSettings::for_params(&p),
        );
        assert!(matches!(out, Err(SettleError::Decayed { .. })), "{out:?}");
    }

    #[test]
    fn a_short_budget_is_reported_as_not_settled() {
        // Velocity weakening below kappa_c = B - A: stick-slip, but three
        // crossings of the section cannot show the return map settling.
        let p = params(0.023);
        let settings = SettleSettings {
            max_periods: 3,
            ..SettleSettings::for_params(&p)
        };
        let out = settle(ModelKind::Inertial, &p, stuck_start(&p), &settings);
        assert!(
            matches!(out, Err(SettleError::NotSettled { periods: 3, .. })),
            "{out:?}"
        );
    }
}
