//! A simulated periodic orbit put on a collocation mesh: the starting guess
//! of a cycle branch that is not born at a Hopf point.
//!
//! One period `T` is integrated again from the section state `x(0)` of a
//! [`SettledOrbit`]; the mesh is built in two passes and the node values are
//! taken from the integrator's dense output (never from interpolating the
//! first guess):
//!
//! 1. mesh points at equal shares of the integrator's accepted steps,
//!    `tau_j = t(j N / NTST) / T` (`t(i)`: end of step `i`, linear between
//!    steps, `N` steps in the period) — the adaptive steps already crowd into
//!    the fast slip;
//! 2. the mesh that equidistributes the collocation error monitor of that
//!    first orbit ([`equidistribute`]), sampled again.

use super::settle::{SettleError, SettledOrbit};
use super::simulate::integration_stop;
use crate::log_model::LogBlock;
use crate::params::Params;
use continuation::integrate::{Output, Radau5, Settings, Solution};
use continuation::periodic::equidistribute;
use continuation::periodic::Cycle;
use continuation::periodic::Mesh;
use continuation::VectorField;

/// Collocation degree of the sampled cycle (the engine's default).
pub const DEGREE: usize = 4;

/// The orbit as a [`Cycle`] of `ntst` intervals (degree [`DEGREE`]) in the
/// variables of `log`, integrated at relative tolerance `rtol` in those of
/// the simulation that settled it ([`LogBlock::new`]).
pub fn sampled_cycle(
    log: &LogBlock,
    params: &Params,
    orbit: &SettledOrbit,
    ntst: usize,
    rtol: f64,
) -> Result<Cycle, SettleError> {
    let pv = params.to_vec();
    let simulated = LogBlock::new(log.kind, params);
    let period = orbit.period;
    let integrate = |output: Output| -> Result<Solution, SettleError> {
        let settings = Settings {
            rtol,
            atol: rtol * 1e-3,
            ..Settings::default()
        };
        Radau5::new(&simulated, &pv, settings)
            .solve(0.0, &orbit.section, period, output)
            .into_result()
            .map_err(|e| SettleError::Integration {
                kappa: params.kappa,
                time: period,
                cause: format!("sampling one period: {}", integration_stop(&e)),
            })
    };
    let steps = integrate(Output::Steps)?.t;
    let first = sample(&integrate, step_mesh(&steps, period, ntst), period, params)?;
    let second = sample(
        &integrate,
        equidistribute(&first, ntst).mesh,
        period,
        params,
    )?;
    let n = log.dim();
    let u = second
        .u
        .chunks(second.n)
        .flat_map(|x| log.from_other(&simulated, x, &pv))
        .collect();
    Ok(Cycle { u, n, ..second })
}

/// Mesh points at equal shares of the accepted steps `t` (from 0 to `period`),
/// each above the one before: steps shorter than the rounding of `t / period`
/// (a slip of microseconds in a period of days) share one point, so that no
/// interval has length zero (at most `ntst` intervals).
fn step_mesh(t: &[f64], period: f64, ntst: usize) -> Mesh {
    let n = t.len() - 1;
    let mut points: Vec<f64> = Vec::with_capacity(ntst + 1);
    for j in 0..ntst {
        let at = j as f64 * n as f64 / ntst as f64;
        let (i, frac) = (at.floor() as usize, at.fract());
        let tau = (t[i] + frac * (t[(i + 1).min(n)] - t[i])) / period;
        if points.last().is_none_or(|&last| tau > last) && tau < 1.0 {
            points.push(tau);
        }
    }
    points.push(1.0);
    Mesh::new(points, DEGREE)
}

/// The orbit's values at the nodes of `mesh` from the dense output.
fn sample(
    integrate: &impl Fn(Output) -> Result<Solution, SettleError>,
    mesh: Mesh,
    period: f64,
    params: &Params,
) -> Result<Cycle, SettleError> {
    let times: Vec<f64> = (0..mesh.ntst())
        .flat_map(|i| (0..mesh.degree).map(move |l| (i, l)))
        .map(|(i, l)| mesh.node_time(i, l) * period)
        .collect();
    let sol = integrate(Output::Grid(times))?;
    let n = sol.x_final.len();
    Ok(Cycle {
        mesh,
        u: sol.x.concat(),
        period,
        p: params.to_vec(),
        n,
    })
}
