//! `stickslip simulate`: driven sliding in time under a driving protocol
//! (steady pulling, velocity jumps, stop-and-go), with time-series figures.
//! Rows are written as they are computed; a bar shows the simulated time on
//! a terminal; Ctrl-C stops, keeps the rows, draws them, and exits with 130
//! (SIGTERM the same, with 143).

use super::files::OutputArgs;
use super::{SceneArgs, TextUnits};
use crate::analysis::decimate::{Buckets, Envelope, ENVELOPE_MIN_CAP};
use crate::analysis::model_choice::{choose_model, params_for};
use crate::analysis::orbit_inertia::InertiaWatch;
use crate::analysis::simulate::{
    regime_reached, simulate_watched, RegimeReached, RunOptions, Sample, Segment, Trajectory,
};
use crate::error::{Error, InputError};
use crate::plot::lines::{render, vertical_marker, LineFigure, Series, SWITCH_MARKER};
use crate::records::csv::{header, row};
use crate::records::simulation::SimulationRow;
use crate::scene::Units;
use clap::Args;
use plotters::style::RGBColor;
use std::io::Write;
use std::ops::ControlFlow;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

#[derive(Args, Debug)]
pub struct SimulateArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Driving protocol as V1:T1,V2:T2,... (velocity in um/s, duration in s); V = 0 stops the drive.
    /// Default: the scene's velocity for 40 D0/V.
    #[arg(long, value_name = "V:T,...")]
    pub protocol: Option<String>,
    /// Relative perturbation of the initial age away from steady sliding.
    #[arg(long, default_value_t = 1e-2)]
    pub perturb: f64,
    /// Integrator relative tolerance.
    #[arg(long, default_value_t = 1e-8)]
    pub rtol: f64,
    #[command(flatten)]
    pub output: OutputArgs,
    /// Most integrator steps (CSV rows) over the whole protocol; a run cut
    /// short by it keeps its rows and figures and exits with status 4
    /// (partial). Also bounds the CSV: about 100 bytes per row.
    #[arg(long, default_value_t = 200_000)]
    pub max_steps: usize,
    /// Most points kept for the figures: a longer run is decimated keeping
    /// the extremes of s and v of every stretch of steps, so that no slip
    /// loses its tip (the CSV keeps every step, or see --every).
    #[arg(long, default_value_t = 20_000)]
    pub plot_points: usize,
    /// Decimate the CSV: from each run of N integrator steps keep its first
    /// and last rows and those of its least and greatest s and v (2 to 6
    /// rows per N steps; slips keep their tips). 1 keeps every step.
    #[arg(long, default_value_t = 1, value_name = "N")]
    pub every: usize,
    /// Units of the text lines: physical (times in s, velocities in µm/s)
    /// or dimensionless (t in D0/V0, nu). The CSV carries both times.
    #[arg(long, value_enum, default_value_t = TextUnits::Physical)]
    pub units: TextUnits,
}

fn parse_protocol(text: &str, v0_um_s: f64, time_unit_s: f64) -> Result<Vec<Segment>, InputError> {
    text.split(',')
        .map(|item| {
            let bad = || InputError::Malformed {
                field: "--protocol".into(),
                value: item.into(),
                expected: "V:T with V >= 0 in um/s and T > 0 in s, e.g. 1:100,10:20,0:300".into(),
            };
            let (v, t) = item.split_once(':').ok_or_else(bad)?;
            let (v, t): (f64, f64) = (
                v.trim().parse().map_err(|_| bad())?,
                t.trim().parse().map_err(|_| bad())?,
            );
            if !(v.is_finite() && v >= 0.0 && t.is_finite() && t > 0.0) {
                return Err(bad());
            }
            Ok(Segment {
                nu: v / v0_um_s,
                duration: t / time_unit_s,
            })
        })
        .collect()
}

/// Runs the command.
pub fn run(args: &SimulateArgs) -> Result<(), Error> {
    if !(args.rtol > 1e-14 && args.rtol < 1e-2) {
        return Err(InputError::out_of_range("--rtol", args.rtol, "in (1e-14, 1e-2)").into());
    }
    if !(args.perturb.is_finite() && args.perturb.abs() < 1.0) {
        return Err(InputError::out_of_range("--perturb", args.perturb, "|perturb| < 1").into());
    }
    if args.max_steps < 1 {
        return Err(InputError::out_of_range("--max-steps", args.max_steps as f64, ">= 1").into());
    }
    if args.plot_points < ENVELOPE_MIN_CAP {
        return Err(InputError::out_of_range(
            "--plot-points",
            args.plot_points as f64,
            &format!(">= {ENVELOPE_MIN_CAP}"),
        )
        .into());
    }
    if args.every < 1 {
        return Err(InputError::out_of_range("--every", args.every as f64, ">= 1").into());
    }
    let mut setup = args.scene.setup(|p| *p)?;
    let u = setup.scene.units;
    let time_unit = u.d0 / u.v0;
    let protocol = match &args.protocol {
        Some(text) => parse_protocol(text, u.v0 * 1e6, time_unit)?,
        None => vec![Segment {
            nu: setup.params.nu,
            duration: 40.0 / setup.params.nu,
        }],
    };
    // The model for the fastest pulling velocity of the protocol.
    let top = protocol
        .iter()
        .map(|seg| seg.nu)
        .fold(setup.scene_params.nu, f64::max);
    if args.scene.model.is_none() {
        let mut at_top = setup.scene_params;
        at_top.nu = top;
        setup.choice = choose_model(&at_top, None, args.scene.inertia_threshold);
        setup.choice.reason = format!(
            "{} (at the protocol's fastest pulling velocity, {})",
            setup.choice.reason,
            match args.units {
                TextUnits::Physical => format!("{:.4e} µm/s", u.velocity_um_s(top)),
                TextUnits::Dimensionless => format!("nu = {top:.4e}"),
            }
        );
        setup.params = params_for(setup.choice.kind, &setup.scene_params);
    }
    let watch = InertiaWatch::new(
        &setup.scene_params,
        args.scene.inertia_threshold,
        args.scene.model.is_none(),
    );
    let nu0 = protocol[0].nu;
    if nu0 <= 0.0 {
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
    let mut start_params = setup.params;
    start_params.nu = nu0;
    let s0 = start_params.friction().steady(nu0);
    let start = [s0, nu0, (1.0 + args.perturb) / nu0];
    args.output.create_dir()?;
    let stem = super::files::with_suffix(
        &args
            .output
            .stem(&setup.scene.name, &args.scene, false, OUTPUTS)?,
        "-simulation",
    );
    let csv_path = super::files::with_suffix(&stem, ".csv");
    super::interrupt::catch_interrupts();
    let mut rows = Rows::create(&csv_path, u)?;
    let t_end: f64 = protocol.iter().map(|seg| seg.duration).sum();
    const TICKS: f64 = 10_000.0;
    let bar = super::interrupt::progress_bar(TICKS as u64, "simulating");
    let mut envelope = Envelope::new(args.plot_points);
    let mut csv_buckets = Buckets::new(args.every);
    let (mut count, mut step_limit) = (0usize, false);
    let mut last: Option<Sample> = None;
    let mut write_error = None;
    // The integrator's own limit well above --max-steps, which the rows
    // enforce (status 4): the integrator also counts its rejected steps, and
    // at a limit of --max-steps + 1 it stopped first (status 3, 199 001
    // steps for 197 146 rows).
    let options = RunOptions {
        rtol: args.rtol,
        max_steps: args.max_steps.saturating_mul(4).saturating_add(1000),
        watch: Some(&watch),
    };
    let run = simulate_watched(
        setup.choice.kind,
        &setup.params,
        start,
        &protocol,
        None,
        &options,
        |p| {
            if let Err(e) = csv_buckets.push(p, |q| rows.push(q)) {
                write_error = Some(e);
                return ControlFlow::Break(());
            }
            envelope.push(p);
            last = Some(*p);
            count += 1;
            if count >= args.max_steps {
                step_limit = true;
                return ControlFlow::Break(());
            }
            if !bar.is_hidden() {
                bar.set_position((TICKS * p.t / t_end) as u64);
                bar.set_message(format!(
                    "t = {:.4e} s of {:.4e} s",
                    p.t * time_unit,
                    t_end * time_unit
                ));
            }
            if super::interrupt::interrupted() {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        },
    );
    bar.finish_and_clear();
    if write_error.is_none() {
        write_error = csv_buckets.finish(|q| rows.push(q)).err();
    }
    rows.flush()?;
    let stride = envelope.stride();
    let traj = envelope.into_trajectory();
    if let Some(e) = write_error {
        return Err(e.into());
    }
    // Whatever was computed is kept and drawn, also after Ctrl-C or a failure.
    let switch = run.as_ref().ok().and_then(|end| end.switch);
    // A run that did not reach the end of its protocol says so in its figures.
    let t_reached = traj.t.last().copied().unwrap_or(0.0) * time_unit;
    let cut = match &run {
        Ok(end) if end.stopped && step_limit => Some("stopped by --max-steps"),
        Ok(end) if end.stopped => Some("interrupted"),
        Ok(_) => None,
        Err(_) => Some("failed"),
    };
    if let Some(why) = cut {
        // A script reading the CSV alone learns that it stops short.
        rows.note(&format!(
            "# incomplete: {why} at t = {t_reached:.6e} s of {:.6e} s",
            t_end * time_unit
        ))?;
    }
    let name = match cut {
        Some(why) => format!(
            "{} — {why} at t = {t_reached:.4e} s of {:.4e} s",
            setup.label,
            t_end * time_unit
        ),
        None => setup.label.clone(),
    };
    let figs = if traj.t.len() >= 2 {
        figures(&name, &traj, &protocol, &u, &stem, switch.map(|s| s.t))?
    } else {
        Vec::new()
    };
    rows.finish()?;
    // A time `t` (units D0/V0) in the text's units.
    let time = |t: f64| match args.units {
        TextUnits::Physical => format!("{:.6e} s", t * time_unit),
        TextUnits::Dimensionless => format!("{t:.6e} (units D0/V0)"),
    };
    println!("model: {}", setup.choice.reason);
    if let Some(sw) = switch {
        println!(
            "switched to the inertial model at t = {}: there inertia would shift ln v by \
             m |dv/dt| / A = {:.3e} > {:.0e} (--inertia-threshold); the rows say which model (column model)",
            time(sw.t),
            sw.chi,
            watch.threshold
        );
    }
    println!(
        "{count} steps over {}{}",
        time(traj.t.last().copied().unwrap_or(0.0)),
        if stride > 1 {
            format!(" (figures: the extremes of every {stride} steps, --plot-points)")
        } else {
            String::new()
        }
    );
    if let (Ok(end), Some(at), Some(seg)) = (&run, last, protocol.last()) {
        if !end.stopped && !super::interrupt::interrupted() {
            // The model of the run's last sample (inertial after a switch).
            let kind = at.model;
            let mut params = params_for(kind, &setup.scene_params);
            params.nu = seg.nu;
            let reached = regime_reached(kind, &params, [at.s, at.v, at.theta]);
            println!("{}", regime_line(&reached, &u, args.units, seg.nu));
        }
    }
    for f in figs.iter().chain([&csv_path]) {
        println!("wrote {}", f.display());
    }
    match run {
        Ok(end) if end.stopped && step_limit => Err(Error::Partial(format!(
            "step limit: {} steps (--max-steps) at simulated time t = {:.6e} s of {:.6e} s",
            count,
            end.t * time_unit,
            end.t_end * time_unit,
        ))),
        Ok(end) if end.stopped => Err(super::interrupt::stopped(format!(
            "at simulated time t = {:.6e} s of {:.6e} s ({} rows)",
            end.t * time_unit,
            end.t_end * time_unit,
            count
        ))),
        Ok(_) => Ok(()),
        Err(e) => Err(e.into()),
    }
}

/// The files `simulate` may write, after the run's stem.
const OUTPUTS: &[&str] = &[
    "-simulation.csv",
    "-simulation-spring-force.png",
    "-simulation-spring-force.svg",
    "-simulation-velocity.png",
    "-simulation-velocity.svg",
];

/// The CSV of the time series, written row by row as the integrator produces
/// them; flushed at least every 0.1 s, so a killed run keeps its rows; whole
/// rows only, and a `# incomplete` line when the run does not finish it
/// ([`LineFile`](super::files::LineFile)).
struct Rows {
    w: super::files::LineFile,
    units: Units,
    flushed: Instant,
}

impl Rows {
    fn create(path: &Path, units: Units) -> std::io::Result<Rows> {
        let mut w = crate::cli::files::create_file(path)?;
        writeln!(w, "{}", header::<SimulationRow>()?)?;
        w.flush()?;
        Ok(Rows {
            w,
            units,
            flushed: Instant::now(),
        })
    }

    fn push(&mut self, p: &Sample) -> std::io::Result<()> {
        let mut line = row(&SimulationRow::new(p, &self.units))?;
        line.push('\n');
        self.w.write_all(line.as_bytes())?;
        if self.flushed.elapsed() > Duration::from_millis(100) {
            self.flush()?;
        }
        Ok(())
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.flushed = Instant::now();
        self.w.flush()
    }

    /// A comment line after the rows, written at once.
    fn note(&mut self, line: &str) -> std::io::Result<()> {
        writeln!(self.w, "{line}")?;
        self.flush()
    }

    /// Writes the rows gathered; the file is as the run meant it.
    fn finish(self) -> std::io::Result<()> {
        self.w.finish()
    }
}

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

fn figures(
    name: &str,
    traj: &Trajectory,
    protocol: &[Segment],
    u: &Units,
    stem: &std::path::Path,
    switch: Option<f64>,
) -> Result<Vec<PathBuf>, Error> {
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
                y_label: "spring force s = K(Vt - x)/W".into(),
                log_x: false,
                log_y: false,
                series: with_switch(vec![line(&traj.s, "s(t)")]),
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
        let mut s = stem.as_os_str().to_owned();
        s.push(suffix);
        files.extend(
            render(&fig, &PathBuf::from(s))
                .map_err(|e| Error::Output(std::io::Error::other(e.to_string())))?,
        );
    }
    Ok(files)
}

/// The regime reached at the end of the run, in words and the text's units:
/// period, force drop `Delta_s W` and slip per event of a stick-slip cycle.
fn regime_line(reached: &RegimeReached, u: &Units, units: TextUnits, nu: f64) -> String {
    let time_unit = u.d0 / u.v0;
    let at = match units {
        TextUnits::Physical => format!("V = {:.4e} µm/s", u.velocity_um_s(nu)),
        TextUnits::Dimensionless => format!("nu = {nu:.4e}"),
    };
    let head =
        format!("regime reached at {at} (continued from the end of the run until it settles)");
    match reached {
        RegimeReached::Periodic {
            period,
            delta_s,
            slip,
        } => match units {
            TextUnits::Physical => format!(
                "{head}: stick-slip, period {:.6e} s, force drop {:.6e} N (Delta_s = {delta_s:.6e}), \
                 slip per event {:.6e} µm",
                period * time_unit,
                delta_s * u.load,
                slip * u.d0 * 1e6
            ),
            TextUnits::Dimensionless => format!(
                "{head}: stick-slip, period {period:.6e} (D0/V0), Delta_s = {delta_s:.6e}, \
                 slip per event {slip:.6e} (D0)"
            ),
        },
        RegimeReached::Steady => format!("{head}: steady sliding (the oscillation decays)"),
        RegimeReached::Unsettled(why) => format!("{head}: not settled — {why}"),
    }
}
