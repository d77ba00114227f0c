//! The figures of a simulation (`simulate`): spring force and slip
//! velocity over time, the pulling velocity of the protocol beside it.

use super::lines::{render, vertical_marker, LineFigure, Series, SWITCH_MARKER};
use super::PlotError;
use crate::analysis::simulate::{Segment, Trajectory};
use crate::file_names::with_suffix;
use crate::scene::Units;
use plotters::style::RGBColor;
use std::path::{Path, PathBuf};

/// Whether the velocities span more than a log axis can draw (some below
/// `1e-300` µm/s): the figure then shows `log10 v` on a linear axis.
fn velocity_beyond_log_axis(traj: &Trajectory, u: &Units) -> bool {
    traj.log10_v
        .iter()
        .any(|l| l + (u.velocity_um_s(1.0)).log10() < -300.0)
}

/// The pulling velocity of `protocol` over the run's time span `t_last`
/// (dimensionless): one level per segment, from its start to its end, in
/// seconds and µm/s.
fn protocol_levels(protocol: &[Segment], t_last: f64, u: &Units) -> Vec<[(f64, f64); 2]> {
    let mut out = Vec::new();
    let mut t = 0.0;
    for seg in protocol {
        if t > t_last {
            break;
        }
        let end = (t + seg.duration).min(t_last);
        let v = u.velocity_um_s(seg.nu);
        out.push([(t * u.d0 / u.v0, v), (end * u.d0 / u.v0, v)]);
        t += seg.duration;
    }
    out
}

/// Draws the spring force and the slip velocity (with the pulling
/// velocity) over time of the trajectory `traj` under `protocol`, titled
/// with `name`, a dashed line at the `switch` to the inertial model.
pub fn figures(
    name: &str,
    traj: &Trajectory,
    protocol: &[Segment],
    u: &Units,
    stem: &Path,
    switch: Option<f64>,
) -> Result<Vec<PathBuf>, PlotError> {
    let t: Vec<f64> = traj.t.iter().map(|t| t * u.d0 / u.v0).collect();
    let line = |y: &[f64], label: &str| Series {
        label: Some(label.into()),
        points: t.iter().copied().zip(y.iter().copied()).collect(),
        color: RGBColor(31, 90, 180),
        dashed: false,
        markers: false,
    };
    let beyond = velocity_beyond_log_axis(traj, u);
    let v_um: Vec<f64> = if beyond {
        let shift = u.velocity_um_s(1.0).log10();
        traj.log10_v.iter().map(|l| l + shift).collect()
    } else {
        traj.v.iter().map(|v| u.velocity_um_s(*v)).collect()
    };
    // A vertical dashed line where the run changed to the inertial model.
    let with_switch = |mut series: Vec<Series>| -> Vec<Series> {
        if let Some(ts) = switch {
            let (color, label) = SWITCH_MARKER;
            series.push(vertical_marker(&series, ts * u.d0 / u.v0, label, color));
        }
        series
    };
    let mut files = Vec::new();
    for (suffix, fig) in [
        (
            "-spring-force",
            LineFigure {
                title: format!("Spring force, {name}"),
                x_label: "time t [s]".into(),
                y_label: "spring force K(Vt - x) [N]".into(),
                log_x: false,
                log_y: false,
                series: with_switch(vec![line(
                    &traj.s.iter().map(|s| s * u.load).collect::<Vec<f64>>(),
                    "K(Vt - x)",
                )]),
            },
        ),
        (
            "-velocity",
            LineFigure {
                title: if beyond {
                    format!("Slip velocity, {name} (below 1e-300 µm/s: log10 v on a linear axis)")
                } else {
                    format!("Slip velocity, {name}")
                },
                x_label: "time t [s]".into(),
                y_label: if beyond {
                    "log10 of slip velocity v [µm/s]".into()
                } else {
                    "slip velocity v [µm/s]".into()
                },
                log_x: false,
                log_y: !beyond,
                series: with_switch({
                    let mut series = vec![line(&v_um, if beyond { "log10 v(t)" } else { "v(t)" })];
                    // The pulling velocity (a stop, V = 0, has no place on a log axis).
                    let t_last = traj.t.last().copied().unwrap_or(0.0);
                    let levels = protocol_levels(protocol, t_last, u)
                        .into_iter()
                        .filter(|[(_, v), _]| *v > 0.0);
                    for (i, level) in levels.enumerate() {
                        series.push(Series {
                            label: (i == 0).then(|| "pulling velocity V(t)".into()),
                            points: level
                                .iter()
                                .map(|&(t, v)| (t, if beyond { v.log10() } else { v }))
                                .collect(),
                            color: RGBColor(110, 110, 110),
                            dashed: true,
                            markers: false,
                        });
                    }
                    series
                }),
            },
        ),
    ] {
        files.extend(render(&fig, &with_suffix(stem, suffix))?);
    }
    Ok(files)
}
