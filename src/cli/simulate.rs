//! `stickslip simulate`: driven sliding in time under a driving protocol
//! (steady pulling, velocity jumps, stop-and-go), with time-series figures.
//! Rows are written as they are computed; a bar shows the simulated time on
//! a terminal; Ctrl-C stops, keeps the rows, draws them, and exits with 130
//! (SIGTERM the same, with 143).

use super::files::{create_file, LineFile, OutputArgs};
use super::{interrupt, SceneArgs, TextUnits};
use crate::analysis::decimate::Buckets;
use crate::analysis::simulate::{RegimeReached, Sample};
use crate::error::{Error, InputError};
use crate::file_names::with_suffix;
use crate::jobs::simulate::{
    unsettled_text, Observer, Plan, Shortfall, SimulateRequest, Simulation,
};
use crate::plot::simulation::figures;
use crate::records::csv::{header, row};
use crate::records::simulation::SimulationRow;
use crate::scene::Units;
use clap::Args;
use indicatif::ProgressBar;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

#[derive(Args, Debug)]
pub struct SimulateArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Driving protocol as V1:T1,V2:T2,... (velocity in µm/s, duration in s); V = 0 stops the drive.
    /// Default: the scene's velocity for 40 D0/V (adhesive scenes: for 30 loading times F_ss/(K V)).
    #[arg(long, value_name = "V:T,...", allow_hyphen_values = true)]
    pub protocol: Option<String>,
    /// Relative perturbation of the initial age away from steady sliding (adhesive scenes: of the
    /// bond fraction n, kept in (0, 1]).
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
    /// Adhesive scenes: refused (their CSV carries both, t in tau_out).
    #[arg(long, value_enum, default_value_t = TextUnits::Physical)]
    pub units: TextUnits,
    /// Print one JSON object instead of text: the run's facts (steps,
    /// times, the switch, the regime reached with its period, force drop
    /// and slip per event), `units`, `complete`, `stop` and the files.
    #[arg(long)]
    pub json: bool,
}

/// `--protocol V1:T1,...` as `(V [µm/s], T [s])` segments, each checked.
pub(super) fn parse_protocol(text: &str) -> Result<Vec<(f64, f64)>, InputError> {
    text.split(',')
        .map(|item| {
            let bad = || InputError::Malformed {
                field: "--protocol".into(),
                value: item.into(),
                expected: "V:T with V >= 0 in µm/s and T > 0 in s, e.g. 1:100,10:20,0:300".into(),
            };
            let (v, t) = item.split_once(':').ok_or_else(bad)?;
            let (v, t): (f64, f64) = (
                v.trim().parse().map_err(|_| bad())?,
                t.trim().parse().map_err(|_| bad())?,
            );
            if !(v.is_finite() && v >= 0.0 && t.is_finite() && t > 0.0) {
                return Err(bad());
            }
            Ok((v, t))
        })
        .collect()
}

/// Runs the command.
pub fn run(args: &SimulateArgs) -> Result<(), Error> {
    let adhesive = crate::scene::law_of(args.scene.scene_name())? == crate::scene::Law::Adhesive;
    let protocol = if adhesive {
        args.protocol.as_deref().map(parse_protocol).transpose()?
    } else {
        None
    };
    let judged = match &protocol {
        Some(list) => super::adhesive::Judged::AtPulling(list.iter().map(|s| s.0).collect()),
        None => super::adhesive::Judged::AtVelocity,
    };
    let unused = [("--units", args.units != TextUnits::Physical)];
    if let Some(setup) = super::adhesive::adhesive_setup(&args.scene, &unused, judged)? {
        let numbers = (args.perturb, args.rtol, args.max_steps);
        return super::adhesive::simulate(
            setup,
            &args.scene,
            &args.output,
            protocol,
            numbers,
            args.json,
        );
    }
    if args.every < 1 {
        return Err(InputError::out_of_range("--every", args.every as f64, ">= 1").into());
    }
    let request = SimulateRequest {
        protocol: args.protocol.as_deref().map(parse_protocol).transpose()?,
        perturb: args.perturb,
        rtol: args.rtol,
        max_steps: args.max_steps,
        plot_points: args.plot_points,
    };
    let plan = Plan::new(&args.scene.spec(), request)?;
    let (setup, u) = (&plan.setup, plan.setup.scene.units);
    let time_unit = u.d0 / u.v0;
    args.output.create_dir()?;
    let stem = with_suffix(
        &args
            .output
            .stem(&setup.scene.name, &args.scene, false, OUTPUTS)?,
        "-simulation",
    );
    let csv_path = with_suffix(&stem, ".csv");
    interrupt::catch_interrupts();
    let mut writer = Writer {
        rows: Rows::create(&csv_path, u)?,
        buckets: Buckets::new(args.every),
        bar: interrupt::progress_bar(TICKS as u64, "simulating"),
        time_unit,
    };
    let mut sim = plan.run(&mut writer);
    writer.bar.finish_and_clear();
    let mut rows = writer.rows;
    let mut write_error = sim.write_error.take();
    if write_error.is_none() {
        write_error = writer.buckets.finish(|q| rows.push(q)).err();
    }
    rows.flush()?;
    if let Some(e) = write_error {
        return Err(e.into());
    }
    // Whatever was computed is kept and drawn, also after Ctrl-C or a failure.
    let switch = sim.end.as_ref().ok().and_then(|end| end.switch);
    let (t_reached, t_end) = (sim.t_reached() * time_unit, sim.t_end * time_unit);
    if let Some(why) = sim.cut() {
        // A script reading the CSV alone learns that it stops short.
        rows.note(&format!(
            "# incomplete: {why} at t = {t_reached:.6e} s of {t_end:.6e} s"
        ))?;
    }
    let name = sim.figure_title();
    let figs = if sim.trajectory.t.len() >= 2 {
        figures(
            &name,
            &sim.trajectory,
            &sim.protocol,
            &u,
            &stem,
            switch.map(|s| s.t),
        )
        .map_err(|e| Error::Output(std::io::Error::other(e.to_string())))?
    } else {
        Vec::new()
    };
    rows.finish()?;
    let files: Vec<PathBuf> = figs.into_iter().chain([csv_path]).collect();
    if args.json {
        let mut record = sim.to_json();
        record["files"] = files.iter().map(|f| f.display().to_string()).collect();
        println!(
            "{}",
            serde_json::to_string_pretty(&record).map_err(std::io::Error::other)?
        );
    } else {
        print_text(&sim, args.units, &files);
    }
    let outcome = match sim.shortfall(args.units) {
        None | Some(Shortfall::Failed(_)) => Ok(()),
        Some(Shortfall::StepLimit(text) | Shortfall::Undetermined(text)) => {
            Err(Error::Partial(text))
        }
        Some(Shortfall::Interrupted { at }) => Err(interrupt::stopped(at)),
    };
    // A failed integration that kept rows is a partial answer (a run that
    // kept results never exits 3); one that failed at its start is the
    // failure.
    match sim.end {
        Err(e) if sim.steps > 1 => Err(Error::Partial(e.to_string())),
        end => end.and(outcome),
    }
}

/// Ticks of the progress bar over the protocol.
const TICKS: f64 = 10_000.0;

/// The observer of the command line: every step into the CSV (decimated
/// by --every), the simulated time on the bar, Ctrl-C.
struct Writer {
    rows: Rows,
    buckets: Buckets,
    bar: ProgressBar,
    time_unit: f64,
}

impl Observer for Writer {
    fn stop(&mut self) -> bool {
        interrupt::interrupted()
    }

    fn progress(&mut self, t: f64, t_end: f64) {
        if !self.bar.is_hidden() {
            self.bar.set_position((TICKS * t / t_end) as u64);
            self.bar.set_message(format!(
                "t = {:.4e} s of {:.4e} s",
                t * self.time_unit,
                t_end * self.time_unit
            ));
        }
    }

    fn sample(&mut self, p: &Sample) -> std::io::Result<()> {
        let rows = &mut self.rows;
        self.buckets.push(p, |q| rows.push(q))
    }
}

/// The text after the run: the model, a switch, the steps, the regime
/// reached, the files.
fn print_text(sim: &Simulation, units: TextUnits, files: &[PathBuf]) {
    let u = &sim.setup.scene.units;
    let time_unit = u.d0 / u.v0;
    // A time `t` (units D0/V0) in the text's units.
    let time = |t: f64| match units {
        TextUnits::Physical => format!("{:.6e} s", t * time_unit),
        TextUnits::Dimensionless => format!("{t:.6e} (units D0/V0)"),
    };
    println!("model: {}", sim.model_reason(units));
    if let Some(sw) = sim.end.as_ref().ok().and_then(|end| end.switch) {
        println!(
            "switched to the inertial model at t = {}: there inertia would shift ln v by \
             m |dv/dt| / A = {:.3e} > {:.0e} (--inertia-threshold); the rows say which model (column model)",
            time(sw.t),
            sw.chi,
            sim.threshold
        );
    }
    if let Some(line) = sim.sticks_text() {
        println!("{line}");
    }
    println!(
        "{} steps over {}{}",
        sim.steps,
        time(sim.t_reached()),
        if sim.stride > 1 {
            format!(
                " (figures: the extremes of every {} steps, --plot-points)",
                sim.stride
            )
        } else {
            String::new()
        }
    );
    if let (Some(reached), Some(seg)) = (&sim.regime, sim.protocol.last()) {
        if !interrupt::interrupted() {
            println!(
                "{}",
                regime_line(reached, u, units, &sim.setup.params, seg.nu)
            );
            if let RegimeReached::Periodic { period, .. } = reached {
                let shown = seg.duration / period;
                if shown < FEW_PERIODS {
                    println!(
                        "  the last segment covers {shown:.2} of its periods, so the figures and \
                         the CSV hardly show it: lengthen it (--protocol VELOCITY:DURATION, e.g. \
                         {} for {FEW_PERIODS:.0} periods)",
                        protocol_example(u, seg.nu, FEW_PERIODS * period)
                    );
                }
            }
        }
    }
    for f in files {
        println!("wrote {}", f.display());
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
    w: LineFile,
    units: Units,
    flushed: Instant,
}

impl Rows {
    fn create(path: &Path, units: Units) -> std::io::Result<Rows> {
        let mut w = create_file(path)?;
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

/// Periods of the regime reached that the last segment should cover for
/// the figures to show it; fewer are pointed out.
const FEW_PERIODS: f64 = 3.0;

/// A `--protocol` segment `V:DURATION` at `nu` lasting at least
/// `duration` (units of `D0/V0`), in the protocol's units (µm/s, and whole
/// seconds rounded up, or 4 digits below one second).
fn protocol_example(u: &Units, nu: f64, duration: f64) -> String {
    let seconds = duration * u.d0 / u.v0;
    let seconds = if seconds >= 1.0 {
        seconds.ceil().to_string()
    } else {
        format!("{seconds:.4e}")
    };
    format!("{}:{seconds}", u.velocity_um_s(nu))
}

/// The regime reached at the end of the run, in words and the text's units:
/// period, force drop `Delta_s W` and slip per event of a stick-slip cycle.
fn regime_line(
    reached: &RegimeReached,
    u: &Units,
    units: TextUnits,
    p: &crate::params::Params,
    nu: f64,
) -> String {
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
            ..
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
        RegimeReached::Held => format!(
            "regime at the end ({at}): the drive is stopped; the block creeps toward rest (no \
             steady sliding or cycle to settle on)"
        ),
        RegimeReached::Unsettled(why) => {
            format!("{head}: undetermined — {}", unsettled_text(why, u, units, p))
        }
    }
}
