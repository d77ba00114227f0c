//! Work against precision of one stick-slip cycle by collocation: degree
//! `m = 2..5` and `NTST = 10..400` on an adaptive (equidistributed) or a
//! uniform mesh, the period and `Delta_s` against long-time integration (a
//! different method, [`crate::reference_cycle`]).
//!
//! What is timed is one continuation point without its predictor: the
//! orbit corrected on the mesh at fixed stiffness from a good guess (a
//! finely resolved orbit interpolated onto the mesh), the branch tangent and
//! the Floquet multipliers (`CycleBranch::from_cycle` and its first point).
//! The adaptive mesh is the equidistribution of the orbit's own solution at
//! that `NTST` (two rounds of equidistributing and correcting, untimed), and
//! one equidistribution is added to its time, as the branch does at every step.

use super::{points, render_figure, time_it, Measurement};
use crate::{reference_cycle, ReferenceCycle};
use continuation::periodic::equidistribute;
use continuation::periodic::Cycle;
use continuation::periodic::Mesh;
use continuation::periodic::{CycleBranch, CycleSettings, Discretization, FloquetPolicy};
use continuation::StepControl;
use plotters::style::RGBColor;
use std::path::{Path, PathBuf};
use stickslip::analysis::hopf::{find_hopf, HopfOutcome};
use stickslip::error::{Error, NumericalError};
use stickslip::log_model::LogBlock;
use stickslip::model::ModelKind;
use stickslip::params::{Param, Params};
use stickslip::plot::lines::{LineFigure, Series};

/// Collocation degrees compared.
const DEGREES: [usize; 4] = [2, 3, 4, 5];
/// Mesh intervals, about `sqrt 2` apart.
const NTSTS: [usize; 12] = [10, 14, 20, 28, 40, 57, 80, 113, 160, 226, 320, 400];

/// One cycle of the study: a scene variant at a fraction of its `kappa_c`.
struct Case {
    /// Job names of the period and of `Delta_s`, in the order of [`QUANTITIES`].
    jobs: [&'static str; 2],
    title: &'static str,
    kind: ModelKind,
    m: f64,
    fraction: f64,
}

const CASES: [Case; 2] = [
    Case {
        jobs: ["cycle_quasi_static_period", "cycle_quasi_static_delta_s"],
        title: "quasi-static PMMA cycle at 0.95 kappa_c",
        kind: ModelKind::QuasiStatic,
        m: 0.0,
        fraction: 0.95,
    },
    Case {
        jobs: ["cycle_inertial_period", "cycle_inertial_delta_s"],
        title: "PMMA cycle with m = 0.01 at 0.5 kappa_c",
        kind: ModelKind::Inertial,
        m: 0.01,
        fraction: 0.5,
    },
];

/// The quantities compared with the reference, as they are named in figures.
const QUANTITIES: [&str; 2] = ["period", "Delta_s"];

/// The method label of degree `m` on an adaptive or uniform mesh.
fn method(m: usize, adaptive: bool) -> String {
    let mesh = if adaptive { "adaptive" } else { "uniform" };
    format!("degree {m} {mesh} mesh")
}

/// Method label of the reference's own uncertainty (a horizontal line).
const SPREAD: &str = "reference spread";

/// Runs the study on both cases.
pub(super) fn study() -> Result<Vec<Measurement>, Error> {
    let mut out = Vec::new();
    for case in &CASES {
        out.extend(study_case(case)?);
    }
    Ok(out)
}

/// The model of `case`, its finely resolved cycle and the reference.
fn prepare(case: &Case) -> Result<(LogBlock, Cycle, ReferenceCycle), Error> {
    let mut params = stickslip::scene::load(stickslip::scene::DEFAULT_SCENE)?.params;
    params.m = case.m;
    let log = LogBlock::centered(case.kind, &params);
    let fine = resolved_orbit(&log, &params, case.fraction)?;
    let mut at = params;
    at.kappa = fine.p[Param::Kappa as usize];
    let reference = reference_cycle(case.kind, &at, fine.period)?;
    Ok((log, fine, reference))
}

fn study_case(case: &Case) -> Result<Vec<Measurement>, Error> {
    let (log, fine, reference) = prepare(case)?;
    let [period_job, delta_s_job] = case.jobs;
    let mut out = Vec::new();
    for (job, spread) in case
        .jobs
        .into_iter()
        .zip([reference.period_spread, reference.delta_s_spread])
    {
        out.push(Measurement {
            job,
            method: SPREAD.into(),
            knob: 0.0,
            seconds: f64::NAN,
            error: spread,
        });
    }
    for m in DEGREES {
        // The resolved orbit as a polynomial of degree m on its own mesh.
        let fine_m = fine.remesh(Mesh::new(fine.mesh.t.clone(), m));
        for adaptive in [true, false] {
            for ntst in NTSTS {
                // A failure (no convergence on a coarse mesh) is kept as NaN.
                let (seconds, errors) = match solve(&log, &fine_m, ntst, adaptive) {
                    Ok((seconds, period, delta_s)) => (
                        seconds,
                        [
                            (period / reference.period - 1.0).abs(),
                            (delta_s / reference.delta_s - 1.0).abs(),
                        ],
                    ),
                    Err(_) => (f64::NAN, [f64::NAN; 2]),
                };
                for (job, error) in [period_job, delta_s_job].into_iter().zip(errors) {
                    out.push(Measurement {
                        job,
                        method: method(m, adaptive),
                        knob: ntst as f64,
                        seconds,
                        // Exact agreement still shows on a log axis.
                        error: if error == 0.0 { 1e-17 } else { error },
                    });
                }
            }
        }
    }
    Ok(out)
}

/// The cycle at `fraction kappa_c`, finely resolved (mesh refined to an
/// error estimate of 1e-9), from the Hopf point: the starting guess.
fn resolved_orbit(log: &LogBlock, params: &Params, fraction: f64) -> Result<Cycle, Error> {
    let HopfOutcome::Found(h) = find_hopf(log.kind, params)? else {
        return Err(stickslip::analysis::cycles::no_onset().into());
    };
    let target = fraction * h.kappa_c;
    let mut at = *params;
    at.kappa = h.kappa_c;
    let settings = CycleSettings {
        p_min: 0.9 * target,
        user_points: vec![target],
        step: StepControl {
            ds_max: 0.2,
            ..CycleSettings::default().step
        },
        param_floor: 0.5 * target,
        mesh: Discretization {
            mesh_tol: Some(1e-9),
            ntst_max: 1600,
            ..Default::default()
        },
        ..Default::default()
    };
    let x0 = log.from_model(h.state[0], h.state[1], h.state[2]);
    let branch = CycleBranch::from_hopf(
        log,
        &x0,
        h.omega_c,
        &at.to_vec(),
        Param::Kappa as usize,
        settings,
    )
    .map_err(NumericalError::from)?;
    for pt in branch {
        let pt = pt.map_err(NumericalError::from)?;
        if let Some(user) = pt.user_points().last() {
            return Ok(user.cycle.clone());
        }
    }
    Err(
        NumericalError::Analysis(format!("the cycle branch did not reach kappa = {target:e}"))
            .into(),
    )
}

/// Seconds per solve, period and `Delta_s` of the orbit on `ntst` intervals
/// of the degree of `fine`, adaptive or uniform mesh.
fn solve(
    log: &LogBlock,
    fine: &Cycle,
    ntst: usize,
    adaptive: bool,
) -> Result<(f64, f64, f64), NumericalError> {
    let mesh_for = |orbit: &Cycle| {
        if adaptive {
            equidistribute(orbit, ntst).mesh
        } else {
            Mesh::uniform(ntst, fine.mesh.degree, fine.mesh.points)
        }
    };
    // Corrected at fixed stiffness, with tangent and multipliers, on the
    // given mesh (no refinement: the mesh is the knob measured).
    let correct = |guess: Cycle| -> Result<Cycle, NumericalError> {
        let settings = CycleSettings {
            mesh: Discretization {
                ntst,
                ntst_max: ntst,
                points: fine.mesh.points,
                mesh_tol: None,
                mesh_accept: None,
                ..Default::default()
            },
            floquet: FloquetPolicy {
                trivial_tol: None,
                ..Default::default()
            },
            ..CycleSettings::default()
        };
        let mut branch =
            CycleBranch::from_cycle(log, guess, Param::Kappa as usize, None, settings)?;
        let pt = branch
            .next()
            .ok_or_else(|| NumericalError::Analysis("no orbit".into()))??;
        Ok(pt.cycle)
    };
    let mut orbit = fine.clone();
    if adaptive {
        // The mesh the branch converges to: equidistributed for its own orbit.
        for _ in 0..2 {
            orbit = correct(fine.remesh(mesh_for(&orbit)))?;
        }
    }
    let run = || correct(fine.remesh(mesh_for(&orbit)));
    let solved = run()?;
    let seconds = time_it(run);
    let (lo, hi) = solved.range(log, 0);
    Ok((seconds, solved.period, hi - lo))
}

/// One figure per job: error against time, one line per method (colour by
/// degree, solid on the adaptive mesh, dashed on the uniform one), the
/// reference's spread as a grey line.
pub(super) fn figures(measurements: &[Measurement], out: &Path) -> Result<Vec<PathBuf>, Error> {
    let colors = [
        RGBColor(200, 40, 40),
        RGBColor(230, 140, 20),
        RGBColor(31, 90, 180),
        RGBColor(40, 150, 60),
    ];
    let mut files = Vec::new();
    for case in &CASES {
        for (job, quantity) in case.jobs.into_iter().zip(QUANTITIES) {
            let mut series = Vec::new();
            for (m, color) in DEGREES.into_iter().zip(colors) {
                for adaptive in [true, false] {
                    // Milliseconds: plain tick labels on the time axis.
                    let pts: Vec<(f64, f64)> = points(measurements, job, &method(m, adaptive))
                        .into_iter()
                        .map(|(t, e)| (1e3 * t, e))
                        .collect();
                    series.push(Series {
                        label: adaptive.then(|| format!("degree {m}")),
                        points: pts.clone(),
                        color,
                        dashed: !adaptive,
                        markers: false,
                    });
                    series.push(Series {
                        label: None,
                        points: pts,
                        color,
                        dashed: false,
                        markers: true,
                    });
                }
            }
            let data = series.iter().flat_map(|s| s.points.iter());
            let (t_lo, t_hi, e_hi) = data.fold((f64::INFINITY, 0.0f64, 0.0f64), |(a, b, c), p| {
                (a.min(p.0), b.max(p.0), c.max(p.1))
            });
            if let Some(spread) = measurements
                .iter()
                .find(|m| m.job == job && m.method == SPREAD)
            {
                series.push(Series {
                    label: Some(format!("{SPREAD} (rtol 1e-12; shorter transient)")),
                    points: vec![(t_lo, spread.error), (t_hi, spread.error)],
                    color: RGBColor(120, 120, 120),
                    dashed: true,
                    markers: false,
                });
            }
            // Headroom for the legend, which plot::lines puts in the upper
            // right, where the uniform meshes (slow and inaccurate) lie: an
            // invisible point four decades above the largest error.
            series.push(Series {
                label: None,
                points: vec![(t_lo, 1e4 * e_hi)],
                color: RGBColor(255, 255, 255),
                dashed: false,
                markers: true,
            });
            let fig = LineFigure {
                title: format!(
                    "{quantity} of the {}: collocation against Radau IIA",
                    case.title
                ),
                x_label: "CPU time per cycle (correction, tangent, Floquet multipliers) [ms]; \
                          solid: adaptive mesh, dashed: uniform mesh"
                    .into(),
                y_label: format!("relative error of {quantity}"),
                log_x: true,
                log_y: true,
                series,
            };
            files.extend(render_figure(&fig, out, job)?);
        }
    }
    Ok(files)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_stiff_quasi_static_cycle_needs_the_adaptive_mesh() {
        // Degree 4 on 80 intervals: equidistributed, the period agrees with
        // long-time integration to 1e-7; uniform, the short slip is not
        // resolved (no convergence, or an error above 1e-3).
        let (log, fine, reference) = prepare(&CASES[0]).unwrap();
        let error = |adaptive| {
            solve(&log, &fine, 80, adaptive).map_or(f64::INFINITY, |(_, t, _)| {
                (t / reference.period - 1.0).abs()
            })
        };
        let (adaptive, uniform) = (error(true), error(false));
        assert!(adaptive < 1e-7, "adaptive: {adaptive:e}");
        assert!(uniform > 1e-3, "uniform: {uniform:e}");
        assert!(reference.period_spread < 1e-10, "{reference:?}");
    }
}
