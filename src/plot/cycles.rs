//! The figures of a cycle branch (`cycles`): amplitude and period along
//! the branch, orbits and time series, and the curves of folds of cycles.

use super::lines::{
    render, render_family, vertical_marker, Colorbar, LineFigure, Series, SWITCH_MARKER,
};
use super::PlotError;
use crate::analysis::cycles::{CycleBifurcation, CycleRecord, Stability};
use crate::appendix_c;
use crate::file_names::with_suffix;
use crate::jobs::Setup;
use crate::records::cycle::{Cycle, Verdict};
use crate::records::diagram::FoldPoint;
use crate::records::significant;
use plotters::style::RGBColor;
use std::path::{Path, PathBuf};

/// Cycles drawn in the orbit and time-series figures (evenly along the
/// branch, and its last one).
const FAMILY_SIZE: usize = 10;

/// Marker colours of the bifurcations of cycles on amplitude and period plots.
const FOLD_COLOR: RGBColor = RGBColor(150, 60, 150);
const PD_COLOR: RGBColor = RGBColor(230, 140, 20);
const NS_COLOR: RGBColor = RGBColor(20, 150, 150);

/// The Hopf curve over the velocities of the folds, for the figure:
/// `kappa_c` of Appendix C (the Hopf condition in closed form) at 200
/// velocities, where it is positive; `None` without folds.
fn hopf_reference(setup: &Setup, folds: &[FoldPoint]) -> Option<Series> {
    let nus = folds.iter().map(|p| p.nu);
    let (lo, hi) = nus.fold((f64::INFINITY, 0.0f64), |(a, b), nu| (a.min(nu), b.max(nu)));
    if !(lo.is_finite() && hi > lo) {
        return None;
    }
    let u = setup.scene.units;
    let points = (0..200)
        .filter_map(|i| {
            let mut at = setup.params;
            at.nu = lo * (hi / lo).powf(i as f64 / 199.0);
            let kappa_c = appendix_c::critical_stiffness(&at);
            (kappa_c > 0.0).then(|| (u.velocity_um_s(at.nu), u.k_over_w(kappa_c)))
        })
        .collect();
    Some(Series {
        label: Some("Hopf curve (critical stiffness, Appendix C)".into()),
        points,
        color: RGBColor(31, 90, 180),
        dashed: false,
        markers: false,
    })
}

/// Maps a cycle's sample `(t/T, s, ln v, ln theta)` to a plotted point.
type SamplePoint<'a> = dyn Fn(&CycleRecord, &[f64; 4]) -> (f64, f64) + 'a;

/// Draws the branch `records` of scene `setup`: amplitude and period
/// (force drop in N, period in s) against K/W (stability by line style, bifurcations of cycles as
/// markers, the model switch as a dashed line), a family of orbits in the
/// (s, v) plane and of spring-force time series; `cut` ends the titles
/// (why the branch is incomplete). Returns the files written.
pub fn branch_figures(
    setup: &Setup,
    records: &[&CycleRecord],
    stem: &Path,
    cut: Option<&str>,
) -> Result<Vec<PathBuf>, PlotError> {
    let u = setup.scene.units;
    let blue = RGBColor(31, 90, 180);
    let red = RGBColor(200, 40, 40);
    let grey = RGBColor(130, 130, 130);
    // Stable cycles solid blue, unstable dashed red, undecidable dashed grey;
    // each stretch starts at the last point of the one before.
    let style = |c: &CycleRecord| match c.stability {
        Stability::Stable => ("stable cycles", blue, false),
        Stability::Unstable => ("unstable cycles", red, true),
        _ => ("stability undecidable", grey, true),
    };
    let by_stability = |f: &dyn Fn(&CycleRecord) -> f64| -> Vec<Series> {
        let mut out: Vec<Series> = Vec::new();
        let mut labelled: Vec<&str> = Vec::new();
        let mut current = None;
        for c in records {
            let pt = (u.k_over_w(c.kappa), f(c));
            let (label, color, dashed) = style(c);
            match out.last_mut() {
                Some(s) if current == Some(label) => s.points.push(pt),
                _ => {
                    let mut points = out
                        .last()
                        .and_then(|s| s.points.last().copied())
                        .into_iter()
                        .collect::<Vec<_>>();
                    points.push(pt);
                    let label_text = (!labelled.contains(&label)).then(|| label.to_string());
                    labelled.push(label);
                    current = Some(label);
                    out.push(Series {
                        label: label_text,
                        points,
                        color,
                        dashed,
                        markers: false,
                    });
                }
            }
        }
        out
    };
    // Where the branch handed over from the quasi-static to the inertial model.
    let switch = records
        .windows(2)
        .find(|w| w[0].model != w[1].model)
        .map(|w| w[1].kappa);
    let title = match switch {
        Some(k) => format!(
            "Stick-slip cycles, {} (quasi-static → inertial model at K/W = {:.4e} 1/m){}",
            setup.label,
            u.k_over_w(k),
            cut.unwrap_or_default()
        ),
        None => format!(
            "Stick-slip cycles, {} ({} model){}",
            setup.label,
            records
                .first()
                .map_or(setup.choice.kind, |c| c.model)
                .name(),
            cut.unwrap_or_default()
        ),
    };
    // A vertical dashed line at the switch, over the data's range, and the
    // bifurcations located on the branch as markers.
    let with_marks = |mut series: Vec<Series>, f: &dyn Fn(&CycleRecord) -> f64| -> Vec<Series> {
        if let Some(k) = switch {
            let (color, label) = SWITCH_MARKER;
            series.push(vertical_marker(&series, u.k_over_w(k), label, color));
        }
        for (kind, color) in [
            (CycleBifurcation::Lpc, FOLD_COLOR),
            (CycleBifurcation::Pd, PD_COLOR),
            (CycleBifurcation::Ns, NS_COLOR),
        ] {
            let points: Vec<(f64, f64)> = records
                .iter()
                .flat_map(|c| c.special_points())
                .filter(|(k, _)| *k == kind)
                .map(|(_, c)| (u.k_over_w(c.kappa), f(c)))
                .collect();
            if !points.is_empty() {
                series.push(Series {
                    label: Some(kind.name().into()),
                    points,
                    color,
                    dashed: false,
                    markers: true,
                });
            }
        }
        series
    };
    let figures = [
        (
            "-amplitude",
            LineFigure {
                title: title.clone(),
                x_label: "K/W [1/m]".into(),
                y_label: format!(
                    "force drop per slip ΔF = Δ(K x) = Δs W [N]  (W = {} N)",
                    significant(u.load)
                ),
                log_x: false,
                log_y: false,
                series: with_marks(by_stability(&|c| c.delta_s * u.load), &|c| {
                    c.delta_s * u.load
                }),
            },
        ),
        (
            "-period",
            LineFigure {
                title: title.clone(),
                x_label: "K/W [1/m]".into(),
                y_label: "period [s]".into(),
                log_x: false,
                log_y: false,
                series: with_marks(by_stability(&|c| c.period * u.d0 / u.v0), &|c| {
                    c.period * u.d0 / u.v0
                }),
            },
        ),
    ];
    // Every `step`-th cycle, the last one (the end of the branch) and the
    // cycles asked for (`--at-kappa`), in their order along the branch.
    let picks: Vec<&CycleRecord> = {
        let step = records.len().div_ceil(FAMILY_SIZE).max(1);
        let last = records.len().saturating_sub(1);
        records
            .iter()
            .enumerate()
            .filter(|(i, c)| i % step == 0 || *i == last || c.user_point)
            .map(|(_, c)| *c)
            .collect()
    };
    let bar = Colorbar::over("K/W [1/m]", picks.iter().map(|c| u.k_over_w(c.kappa)));
    // One curve per picked cycle, mapping each sample (t/T, s, ln v, ln theta) to
    // a point, coloured by its stiffness; unstable cycles dashed (not those
    // whose stability the multipliers cannot decide).
    let per_cycle = |point: &SamplePoint| -> Vec<Series> {
        picks
            .iter()
            .map(|c| Series {
                label: None,
                points: c.samples.iter().map(|p| point(c, p)).collect(),
                color: bar.color(u.k_over_w(c.kappa)),
                dashed: c.stability == Stability::Unstable,
                markers: false,
            })
            .collect()
    };
    // Sticks below 1e-300 µm/s (the return map's, down to 1e-800 and
    // beyond): log10 v on a linear axis, as `simulate` draws them.
    let log10_v0 = u.velocity_um_s(1.0).log10();
    let beyond = picks
        .iter()
        .any(|c| c.ln_v_min / std::f64::consts::LN_10 + log10_v0 < -300.0);
    let orbit = LineFigure {
        title: format!(
            "Cycles in the (K(Vt - x), v) plane, {}{}",
            setup.label,
            cut.unwrap_or_default()
        ),
        x_label: "spring force K(Vt - x) [N]".into(),
        y_label: if beyond {
            "log10 of the slip velocity v [µm/s] (below 1e-300 µm/s)".into()
        } else {
            "slip velocity v [µm/s]".into()
        },
        log_x: false,
        log_y: !beyond,
        series: per_cycle(&|_, p| {
            let log10_v = p[2] / std::f64::consts::LN_10 + log10_v0;
            (
                p[1] * u.load,
                if beyond { log10_v } else { 10f64.powf(log10_v) },
            )
        }),
    };
    let series = LineFigure {
        title: format!(
            "Spring force over one period, {}{}",
            setup.label,
            cut.unwrap_or_default()
        ),
        x_label: "time t [s]".into(),
        y_label: "spring force K(Vt - x) [N]".into(),
        log_x: false,
        log_y: false,
        series: per_cycle(&|c, p| (p[0] * c.period * u.d0 / u.v0, p[1] * u.load)),
    };
    let mut files = Vec::new();
    for (suffix, fig) in &figures {
        files.extend(render(fig, &with_suffix(stem, suffix))?);
    }
    for (suffix, fig) in [("-orbits", orbit), ("-time-series", series)] {
        files.extend(render_family(&fig, &bar, &with_suffix(stem, suffix))?);
    }
    Ok(files)
}

/// Draws the curves of folds of cycles `folds` (the hysteresis boundary)
/// in (V, K/W) with the Hopf curve of Appendix C over their velocities.
pub fn fold_figure(
    setup: &Setup,
    folds: &[FoldPoint],
    stem: &Path,
) -> Result<Vec<PathBuf>, PlotError> {
    let figure = LineFigure {
        title: format!(
            "Folds of cycles (hysteresis boundary), {}: stick-slip coexists with steady sliding below",
            setup.label
        ),
        x_label: "driving velocity V [µm/s]".into(),
        y_label: "K/W [1/m]".into(),
        log_x: true,
        log_y: true,
        series: folds
            .chunk_by(|a, b| a.curve == b.curve)
            .enumerate()
            .map(|(i, curve)| Series {
                label: (i == 0).then(|| "fold of cycles (LPC)".to_string()),
                points: curve
                    .iter()
                    .map(|p| (p.physical.v_um_per_s, p.physical.k_over_w_per_m))
                    .collect(),
                color: FOLD_COLOR,
                dashed: false,
                markers: false,
            })
            .chain(hopf_reference(setup, folds))
            .collect(),
    };
    render(&figure, &with_suffix(stem, "-lpc-curve"))
}

/// The figures of a cycle branch in a control parameter (`cycles --param
/// P`): the force drop per slip \[N\] and the period \[s\] against the control
/// in its unit, `points` its value and the cycle along the branch (the
/// cycles at requested values left out: they repeat the branch); stable
/// cycles solid blue, unstable dashed red, undecidable dashed grey; the
/// switch from the quasi-static to the inertial model, at the control's
/// value `switch`, as a dashed line (as [`branch_figures`] marks it). The x
/// axis is logarithmic where the values span more than a decade.
pub fn control_figures(
    title: &str,
    x_label: &str,
    points: &[(f64, &Cycle)],
    switch: Option<f64>,
    stem: &Path,
) -> Result<Vec<PathBuf>, PlotError> {
    let along: Vec<&(f64, &Cycle)> = points.iter().filter(|(_, c)| !c.user_point).collect();
    let (lo, hi) = along
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(a, b), (x, _)| {
            (a.min(*x), b.max(*x))
        });
    let log_x = lo > 0.0 && hi > 10.0 * lo;
    let style = |v: Verdict| match v {
        Verdict::Stable => ("stable cycles", RGBColor(31, 90, 180), false),
        Verdict::Unstable => ("unstable cycles", RGBColor(200, 40, 40), true),
        Verdict::Undecidable => ("stability undecidable", RGBColor(130, 130, 130), true),
    };
    // One series per stretch of one stability, each starting at the last
    // point of the one before.
    let series = |y: &dyn Fn(&Cycle) -> f64| -> Vec<Series> {
        let mut out: Vec<Series> = Vec::new();
        let mut labelled: Vec<&str> = Vec::new();
        let mut current = None;
        for (x, c) in &along {
            let (label, color, dashed) = style(c.stable);
            let pt = (*x, y(c));
            match out.last_mut() {
                Some(s) if current == Some(label) => s.points.push(pt),
                _ => {
                    let mut pts: Vec<(f64, f64)> = out
                        .last()
                        .and_then(|s| s.points.last().copied())
                        .into_iter()
                        .collect();
                    pts.push(pt);
                    out.push(Series {
                        label: (!labelled.contains(&label)).then(|| label.to_string()),
                        points: pts,
                        color,
                        dashed,
                        markers: false,
                    });
                    labelled.push(label);
                    current = Some(label);
                }
            }
        }
        out
    };
    let mut files = Vec::new();
    for (suffix, y_label, y) in [
        (
            "-amplitude",
            "force drop per slip ΔF = Δ(K x) [N]",
            &(|c: &Cycle| c.delta_s_n) as &dyn Fn(&Cycle) -> f64,
        ),
        ("-period", "period [s]", &|c: &Cycle| c.period_s),
    ] {
        let mut series = series(y);
        if let Some(x) = switch {
            let (color, label) = SWITCH_MARKER;
            series.push(vertical_marker(&series, x, label, color));
        }
        let fig = LineFigure {
            title: title.to_string(),
            x_label: x_label.to_string(),
            y_label: y_label.to_string(),
            log_x,
            log_y: false,
            series,
        };
        files.extend(render(&fig, &with_suffix(stem, suffix))?);
    }
    Ok(files)
}
