//! `stickslip cycles`: runs the cycles job ([`crate::jobs::cycles`]) and
//! writes its text, CSV (row by row as the cycles come), figures and JSON.

use super::files::{create_file, LineFile, OutputArgs};
use super::interrupt;
use super::lpc_output::{lpc_summary, write_lpc_csv};
use super::{SceneArgs, TextUnits};
use crate::analysis::control::Control;
use crate::analysis::cycles::Quantity;
use crate::error::{Error, InputError};
use crate::file_names::with_suffix;
use crate::jobs::cycles::{asked_stiffnesses, Cycles, CyclesRequest, Note, Observer, Plan};
use crate::jobs::restart::{orbits_path, Restart};
use crate::plot::cycles::{branch_figures, fold_figure};
use crate::records::csv::{header, row};
use crate::records::cycle::{Cycle, CycleSpecialPoint, OperatingCycle, Requested};
use crate::records::orbit::StoredOrbit;
use clap::Args;
use continuation::periodic::CollocationPoints;
use indicatif::ProgressBar;
use std::io::Write;
use std::path::{Path, PathBuf};

#[derive(Args, Debug)]
pub struct CyclesArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Stop when the stiffness falls below this fraction of kappa_c (without a Hopf
    /// point: of the stiffness of the simulated orbit the branch starts from).
    /// [default: 0.5; not with --param K|kappa --to, which ends the branch]
    #[arg(long)]
    pub kappa_fraction: Option<f64>,
    /// Start from a simulated stick-slip orbit instead of the Hopf point (automatic
    /// when there is no Hopf point). The stiffness simulated: the scene's kappa when
    /// it gives one and a simulation from a stuck state settles on a cycle there;
    /// else 0.9 kappa_c below a Hopf point; else max(A, B) 10^-k, k = 1..5, the
    /// first that settles. The branch is followed toward larger stiffness (where a
    /// cycle coexisting with stable sliding ends at a fold of cycles, LPC) and then
    /// toward smaller stiffness.
    #[arg(long)]
    pub from_simulation: bool,
    /// Largest number of continuation steps, i.e. cycles after the first
    /// (per leg from a simulated orbit, and counted afresh after a switch to
    /// the inertial model); the branch usually ends first, at
    /// the requested range. Reaching it keeps the cycles and exits with
    /// status 4 (partial).
    #[arg(long, default_value_t = 500)]
    pub max_steps: usize,
    /// Initial number of mesh intervals (grown automatically when needed).
    #[arg(long, default_value_t = 40)]
    pub ntst: usize,
    /// Most mesh intervals the automatic refinement may use (the cost grows with it).
    #[arg(long, default_value_t = 12800)]
    pub ntst_max: usize,
    /// Collocation points instead of the model's choice (Radau IIA for the
    /// inertial block, whose velocity relaxes stiffly while it sticks; Gauss
    /// for the quasi-static one).
    #[arg(long, value_enum)]
    pub collocation: Option<Points>,
    /// Continue every fold of cycles (LPC) found on the branch in two
    /// parameters, (kappa, nu), across the scene's velocity range (widened to
    /// a factor 2 around the fold): the
    /// boundary of the hysteretic region. Writes -lpc-curve.csv and
    /// -lpc-curve.png/.svg, and `lpc_curve` in the JSON.
    #[arg(long)]
    pub lpc_curve: bool,
    /// Comma-separated stiffnesses at which cycles are located exactly and
    /// reported, as dimensionless kappa = K D0/W (the K/W of the text times
    /// D0); each is reported with both.
    #[arg(long, value_name = "K1,K2,...", value_delimiter = ',')]
    pub at_kappa: Vec<f64>,
    /// Stiffnesses at which cycles are located exactly and reported, in a
    /// unit of your choice: NAME=V1,V2,... with NAME kappa (dimensionless,
    /// as --at-kappa), K (N/m, kappa = K D0/W with the scene's D0 and W) or
    /// K_over_W (1/m, kappa = (K/W) D0). Repeatable; a value given twice
    /// (in any unit, within 1e-12 relative) is reported once. Each
    /// requested point carries the value as asked.
    #[arg(long, value_name = "NAME=V1,V2,...")]
    pub at: Vec<String>,
    /// The parameter the cycles are continued in: K (N/m), V (µm/s), M (kg),
    /// tau (s), eta (s/m), or kappa, nu, m, A, B, mu2, theta_c, mu_vv, mu_vphi, eta_d (default: the
    /// stiffness, as without it). Other than K or kappa it needs --to;
    /// the branch starts at the Hopf point in that parameter (hopf --param)
    /// or, with --from-simulation, from an orbit simulated at the scene's
    /// value; writes <run>-cycles-in-P.csv and -cycles-in-P-amplitude/-period figures (force drop in N, period in s against P) and --at P=V1,...
    /// takes values of P.
    #[arg(long, value_name = "P")]
    pub param: Option<String>,
    /// With --param: where the branch ends, in the unit of P (for K or
    /// kappa: in place of --kappa-fraction).
    #[arg(long, allow_hyphen_values = true)]
    pub to: Option<f64>,
    /// With --param other than K or kappa: the range LO:HI (unit of P)
    /// where the Hopf point in P is searched (default: the scene's V_range
    /// for V and nu, three decades either side of the scene's value
    /// otherwise, widened to include --to).
    #[arg(long, value_name = "LO:HI")]
    pub search: Option<String>,
    /// Restart from a cycle of an earlier run: the JSON that `cycles --json`
    /// printed (saved to a file), with --index N, the cycle's label (column
    /// label of the CSV, #N in the text). The orbit is read exactly from the
    /// run's <run>-cycles-orbits.jsonl (named in the JSON), corrected by
    /// Newton's method at its own parameters and continued both ways, with
    /// the options above (--to, --at, --max-steps, ...). The scene,
    /// overrides and model are the file's (--set and --model are refused).
    #[arg(long, value_name = "FILE.json", requires = "index")]
    pub from: Option<PathBuf>,
    /// With --from: the label of the cycle to restart from.
    #[arg(long, value_name = "N", requires = "from", value_parser = super::label)]
    pub index: Option<usize>,
    #[command(flatten)]
    pub output: OutputArgs,
    /// Print one JSON object instead of text.
    #[arg(long)]
    pub json: bool,
    /// Units of the text lines: physical (K/W in 1/m, period in s, slip
    /// velocity in µm/s) or dimensionless (kappa, period in D0/V0, v/V0).
    /// The CSV and the JSON carry both. Adhesive scenes: refused (their text
    /// gives N/m, s, µm/s with the dimensionless values in the JSON).
    #[arg(long, value_enum, default_value_t = TextUnits::Physical)]
    pub units: TextUnits,
}

/// `--collocation` values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Points {
    Gauss,
    Radau,
}

impl From<Points> for CollocationPoints {
    fn from(p: Points) -> Self {
        match p {
            Points::Gauss => CollocationPoints::Gauss,
            Points::Radau => CollocationPoints::Radau,
        }
    }
}

/// `value` in the text output (`{:.1e}`), or `n/a (why)` when unavailable.
fn or_na(value: Option<f64>, why: &str) -> String {
    value.map_or_else(|| format!("n/a ({why})"), |v| format!("{v:.1e}"))
}

/// `NTST 320` for a collocated cycle, `return map` for one of the return map.
fn method_text(cycle: &Cycle) -> String {
    cycle
        .ntst
        .map_or_else(|| "return map".to_string(), |n| format!("NTST {n}"))
}

/// Why a cycle's trivial-multiplier error is not given, in the text.
fn no_trivial_error(cycle: &Cycle) -> &'static str {
    match cycle.ntst {
        Some(_) => "Floquet pencil singular to rounding",
        None => "removed by the section",
    }
}

/// Reads `--search LO:HI`.
pub fn search_range(args: &CyclesArgs) -> Result<Option<(f64, f64)>, InputError> {
    let Some(text) = &args.search else {
        return Ok(None);
    };
    let bad = || InputError::Malformed {
        field: "--search".into(),
        value: text.clone(),
        expected: "LO:HI, two numbers > 0 in the unit of --param".into(),
    };
    let (lo, hi) = text.split_once(':').ok_or_else(bad)?;
    let (lo, hi): (f64, f64) = (
        lo.trim().parse().map_err(|_| bad())?,
        hi.trim().parse().map_err(|_| bad())?,
    );
    Ok(Some((lo, hi)))
}

/// The branch's CSV at `path`, created with its comment line (the scene,
/// the model, the collocation and what the words in it mean) and header.
fn csv_with_header(path: &Path, plan: &Plan) -> Result<LineFile, Error> {
    let mut csv = create_file(path)?;
    writeln!(
        csv,
        "# scene {}; model at the start {} (column model: each row's); collocation {}; stable: \
         true, false, or undecidable (a nontrivial multiplier within its error of the unit \
         circle); n/a: not available (the JSON gives the reason)\n{}",
        plan.setup.scene.name,
        plan.setup.choice.reason,
        plan.points_name(),
        header::<Cycle>()?
    )?;
    Ok(csv)
}

/// Runs the command.
pub fn run(args: &CyclesArgs) -> Result<(), Error> {
    let unused = [
        ("--kappa-fraction", args.kappa_fraction.is_some()),
        ("--from-simulation", args.from_simulation),
        ("--lpc-curve", args.lpc_curve),
        ("--at-kappa", !args.at_kappa.is_empty()),
        ("--at", !args.at.is_empty()),
        ("--param", args.param.is_some()),
        ("--to", args.to.is_some()),
        ("--search", args.search.is_some()),
        ("--from", args.from.is_some()),
        ("--collocation", args.collocation.is_some()),
        ("--units", args.units != TextUnits::Physical),
    ];
    if let Some(setup) =
        super::adhesive::adhesive_setup(&args.scene, &unused, super::adhesive::Judged::AtVelocity)?
    {
        let output = &args.output;
        let limits = (args.max_steps, args.ntst_max);
        return super::adhesive::cycles(setup, &args.scene, output, limits, args.json);
    }
    let control = Control::from_param(args.param.as_deref())?;
    if let Some(c) = control.filter(|c| !c.is_stiffness()) {
        return super::cycles_in::run(args, c);
    }
    let spec = args.scene.spec_for(args.from.is_some());
    let plan = Plan::new(&spec, request(args, control)?)?;
    if !args.json {
        plan.describe(args.units)
            .iter()
            .for_each(|l| println!("{l}"));
    }
    args.output.create_dir()?;
    let name = match &plan.request.from {
        // The run restarted from, and the cycle: not the files of that run.
        Some(r) => format!("{}_restart-{}", plan.source_name(), r.index),
        None => plan.setup.scene.name.clone(),
    };
    let stem = args.output.stem(&name, &args.scene, false, OUTPUTS)?;
    let stem = with_suffix(&stem, "-cycles");
    let csv_path = with_suffix(&stem, ".csv");
    let csv = csv_with_header(&csv_path, &plan)?;
    let orbits_path = orbits_path(&stem);
    let orbits = create_file(&orbits_path)?;
    interrupt::catch_interrupts();
    let mut printer = Printer {
        csv,
        orbits,
        text: (!args.json).then_some(args.units),
        bar: interrupt::progress("continuing cycles"),
    };
    let mut result = plan.run(&mut printer);
    printer.bar.finish_and_clear();
    let mut files = write_figures(&result, &stem, args.lpc_curve)?;
    if args.lpc_curve && !args.json {
        lpc_summary(&result.lpc_curve, &result.lpc_stops, args.units)
            .iter()
            .for_each(|l| println!("{l}"));
    }
    let mut csv = printer.csv;
    write_requested_csv(&mut csv, &result.requested_points)?;
    if !result.complete {
        // A script reading the CSV alone learns that it is not the whole branch.
        writeln!(csv, "# incomplete: {}", result.stop)?;
    }
    csv.finish()?;
    files.push(csv_path);
    printer.orbits.finish()?;
    result.orbits_file = Some(orbits_path.display().to_string());
    files.push(orbits_path);
    result.files = files.iter().map(|f| f.display().to_string()).collect();
    if args.json {
        println!(
            "{}",
            serde_json::to_string_pretty(&result).map_err(std::io::Error::other)?
        );
    } else {
        print_end(&result, &files);
    }
    result.status()
}

/// The job's request from the options, each checked where it is parsed.
fn request(args: &CyclesArgs, control: Option<Control>) -> Result<CyclesRequest, Error> {
    if args.to.is_some() && control.is_none() {
        return Err(InputError::Conflict(
            "--to ends a branch in --param; without it the branch is in the stiffness and ends \
             at --kappa-fraction of its start"
                .into(),
        )
        .into());
    }
    if let (Some(_), Some(_)) = (args.kappa_fraction, args.to) {
        return Err(InputError::Conflict(
            "--kappa-fraction and --to both end the stiffness branch; give one".into(),
        )
        .into());
    }
    if args.search.is_some() {
        return Err(InputError::Conflict(
            "--search is where the Hopf point in --param V, M, tau, nu, m, ... is searched; \
             the onset in the stiffness is searched from a stable stiffness downward"
                .into(),
        )
        .into());
    }
    Ok(CyclesRequest {
        kappa_fraction: args
            .kappa_fraction
            .unwrap_or(CyclesRequest::default().kappa_fraction),
        from_simulation: args.from_simulation,
        max_steps: args.max_steps,
        ntst: args.ntst,
        ntst_max: args.ntst_max,
        collocation: args.collocation.map(Into::into),
        lpc_curve: args.lpc_curve,
        at: asked_stiffnesses(&args.at_kappa, &args.at)?,
        to: control.zip(args.to),
        from: restart_of(args),
    })
}

/// `--from FILE.json --index N` (clap requires both or neither).
pub fn restart_of(args: &CyclesArgs) -> Option<Restart> {
    Some(Restart {
        file: args.from.clone()?,
        index: args.index?,
    })
}

/// The observer of the command line: each cycle a CSV row (flushed at once,
/// so an interrupted run keeps it) and, unless `--json`, text lines.
struct Printer {
    csv: LineFile,
    /// One line per orbit ([`StoredOrbit`]), flushed at once.
    orbits: LineFile,
    /// The text's units; `None` with `--json`.
    text: Option<TextUnits>,
    bar: ProgressBar,
}

impl Observer for Printer {
    fn stop(&mut self, at: &dyn Fn() -> String) -> Option<Error> {
        interrupt::interrupted().then(|| interrupt::stopped(at()))
    }

    fn progress(&mut self, what: &str) {
        self.bar.set_message(what.to_string());
    }

    fn cycle(&mut self, cycle: &Cycle, found: &[CycleSpecialPoint]) -> Result<(), Error> {
        write_row(&mut self.csv, cycle)?;
        if let Some(units) = self.text {
            print_cycle(units, cycle, found);
        }
        Ok(())
    }

    fn orbit(&mut self, orbit: &StoredOrbit) -> Result<(), Error> {
        orbit.write_line(&mut self.orbits)
    }

    fn operating_point(&mut self, op: &OperatingCycle) {
        if let Some(units) = self.text {
            operating_text(units, op)
                .iter()
                .for_each(|l| println!("{l}"));
        }
        // A CSV write error shows again, and stops the run, at the next row.
        let _ = write_operating_csv(&mut self.csv, op);
    }

    fn note(&mut self, note: Note) {
        print_note(note, self.text.is_some());
    }
}

/// A note of a cycle branch: a line of the text (none with `--json`,
/// `text` false), a warning on stderr either way.
pub fn print_note(note: Note, text: bool) {
    match note {
        Note::Switch(line) | Note::Regime(line) if text => println!("{line}"),
        Note::Switch(_) | Note::Regime(_) => {}
        Note::Warning(w) => eprintln!("warning: {w}"),
    }
}

/// The figures of the branch and, with `--lpc-curve`, the CSV and figure of
/// the fold-of-cycles curves; whatever was computed is drawn, also when
/// the branch stopped short, and then the titles say so.
fn write_figures(result: &Cycles, stem: &Path, lpc_curve: bool) -> Result<Vec<PathBuf>, Error> {
    let plot_error =
        |e: crate::plot::PlotError| Error::Output(std::io::Error::other(e.to_string()));
    let cut = if result.interrupted() {
        Some(" — interrupted")
    } else if !result.leg_stops.iter().all(|l| l.complete()) {
        Some(" — stopped before the requested range (see the stop reason)")
    } else {
        None
    };
    let mut files = Vec::new();
    if !result.records.is_empty() {
        files =
            branch_figures(&result.setup, &result.along_branch(), stem, cut).map_err(plot_error)?;
    }
    if lpc_curve && !result.lpc_curve.is_empty() {
        files.push(write_lpc_csv(
            stem,
            &result.scene,
            &result.lpc_curve,
            &result.lpc_stops,
        )?);
        files.extend(fold_figure(&result.setup, &result.lpc_curve, stem).map_err(plot_error)?);
    }
    Ok(files)
}

/// The text after the branch: how it stopped, each requested stiffness,
/// the files written.
fn print_end(result: &Cycles, files: &[PathBuf]) {
    println!("stopped: {}", result.stop);
    let units = &result.setup.scene.units;
    // Stiffnesses as kappa (as asked) and as K/W (as the cycles' lines).
    let both = |kappa: f64, decimals: usize| {
        format!(
            "{kappa:.decimals$e} (K/W = {:.decimals$e} 1/m)",
            units.k_over_w(kappa)
        )
    };
    for r in &result.requested_points {
        let asked = match r.asked.name {
            "kappa" => format!(
                "requested kappa = {:.10e} (K/W = {:.8e} 1/m)",
                r.kappa, r.k_over_w_per_m
            ),
            _ => format!(
                "requested {} (kappa = {:.10e}, K/W = {:.8e} 1/m, K = {:.8e} N/m)",
                r.asked.describe(),
                r.kappa,
                r.k_over_w_per_m,
                r.k_n_per_m
            ),
        };
        match &r.reason {
            None => println!(
                "{asked}: delivered ({} cycle{})",
                r.cycles,
                if r.cycles == 1 { "" } else { "s" }
            ),
            Some(why) => println!(
                "{asked}: not delivered: {}",
                why.describe(&Quantity::STIFFNESS, &both)
            ),
        }
    }
    for f in files {
        println!("wrote {}", f.display());
    }
}

/// The text lines of a cycle: a cycle at a requested stiffness on one
/// line; else the cycle, its stability and errors, and the bifurcations
/// `found` since the previous cycle.
fn print_cycle(units: TextUnits, cycle: &Cycle, found: &[CycleSpecialPoint]) {
    if cycle.user_point {
        println!(
            "  user point {}  #{}",
            cycle_text(units, cycle),
            cycle.label
        );
        return;
    }
    println!(
        "{}  {}  |mu_1 - 1| {}  err {}  {}  #{}",
        cycle_text(units, cycle),
        cycle.stable.word(),
        or_na(cycle.trivial_multiplier_error, no_trivial_error(cycle)),
        or_na(cycle.error_estimate, "no solution on half the mesh"),
        method_text(cycle),
        cycle.label
    );
    for s in found {
        println!(
            "  {} at {}  #{}",
            s.kind.name(),
            cycle_text(units, &s.cycle),
            s.cycle.label
        );
    }
}

/// A cycle in the text units `units`: stiffness, period, the force drop
/// in N (physical units), `Delta_s` (a friction coefficient either way) and
/// the range of the slip velocity.
/// The slowest slip velocity `v` of `c` (in a unit `10^log10_v0 V0`), or
/// below the range of `f64` (a deep stick of the return map) its power of ten.
fn slowest(c: &Cycle, v: f64, log10_v0: f64) -> String {
    if v >= 1e-300 {
        format!("{v:.3e}")
    } else {
        format!("10^{:.1}", c.log10_v_min + log10_v0)
    }
}

fn cycle_text(units: TextUnits, c: &Cycle) -> String {
    let slowest = |v: f64, log10_v0: f64| slowest(c, v, log10_v0);
    match units {
        TextUnits::Physical => format!(
            "K/W {:.8e} 1/m  period {:.6e} s  force drop {:.6e} N  Delta_s {:.6e}  v {} .. \
             {:.3e} µm/s",
            c.k_over_w_per_m,
            c.period_s,
            c.delta_s_n,
            c.delta_s,
            slowest(c.v_min_um_per_s, (c.v_max_um_per_s / c.v_max).log10()),
            c.v_max_um_per_s
        ),
        TextUnits::Dimensionless => format!(
            "kappa {:.8e}  period {:.6e}  Delta_s {:.6e}  v {} .. {:.3e}",
            c.kappa,
            c.period,
            c.delta_s,
            slowest(c.v_min, 0.0),
            c.v_max
        ),
    }
}

/// The text of the operating point: the scene's K and its regime, then
/// the cycle there (period in s, force drop in N, slip per event in µm,
/// the slip velocity's range, stability) or why there is none.
fn operating_text(units: TextUnits, op: &OperatingCycle) -> Vec<String> {
    let p = &op.point;
    let mut lines = vec![format!(
        "operating point: K = {:.6e} N/m (kappa = {:.6e}): {} ({})",
        p.k_n_per_m,
        p.kappa,
        p.regime.name(),
        p.reason
    )];
    let how = match (op.method, &op.simulation) {
        (Some("simulation"), Some(s)) => format!(
            "simulated in the {} model (settled after {} oscillations), {}",
            s.model.name(),
            s.oscillations,
            match op.cycle.as_ref().and_then(|c| c.ntst) {
                Some(_) => "corrected by collocation",
                None => "located by the return map",
            }
        ),
        (Some("continuation"), _) => "reached along the branch from the Hopf point".to_string(),
        _ => "the start of the branch".to_string(),
    };
    match (&op.cycle, op.slip_um) {
        (Some(c), Some(slip)) => {
            let at = match units {
                TextUnits::Physical => format!(
                    "period {:.6e} s  force drop {:.6e} N  slip per event {slip:.6e} µm  v {} .. {:.3e} µm/s",
                    c.period_s,
                    c.delta_s_n,
                    slowest(c, c.v_min_um_per_s, (c.v_max_um_per_s / c.v_max).log10()),
                    c.v_max_um_per_s
                ),
                TextUnits::Dimensionless => format!(
                    "period {:.6e}  Delta_s {:.6e}  v {} .. {:.3e}",
                    c.period,
                    c.delta_s,
                    slowest(c, c.v_min, 0.0),
                    c.v_max
                ),
            };
            lines.push(format!(
                "  the cycle at the scene's K, {how}:\n    {at}  {}  err {}  {}  #{}",
                c.stable.word(),
                or_na(c.error_estimate, "no solution on half the mesh"),
                method_text(c),
                c.label
            ));
            if let Some(why) = &op.fallback_reason {
                lines.push(format!("  (the direct start failed: {why})"));
            }
        }
        _ if !op.wanted => lines.push("  no stick-slip cycle at the scene's K; the branch:".into()),
        _ => lines.push(format!(
            "  no cycle at the scene's K: {}",
            op.not_delivered.as_deref().unwrap_or("")
        )),
    }
    lines
}

/// The operating point's cycle as the first CSV row, after a comment that
/// says what it is (the branch's rows follow).
fn write_operating_csv(csv: &mut impl Write, op: &OperatingCycle) -> Result<(), Error> {
    let Some(c) = &op.cycle else {
        return Ok(());
    };
    let k = op.point.k_n_per_m;
    if op.method == Some("branch_start") {
        writeln!(
            csv,
            "# the first row is the cycle at the scene's K = {k:.6e} N/m"
        )?;
        return Ok(());
    }
    writeln!(
        csv,
        "# the cycle at the scene's K = {k:.6e} N/m ({}: {}), before the branch",
        op.point.regime.name(),
        op.method.unwrap_or("")
    )?;
    write_row(csv, c)
}

/// One CSV row per cycle, flushed at once so an interrupted run keeps it.
fn write_row(csv: &mut impl Write, c: &Cycle) -> Result<(), Error> {
    writeln!(csv, "{}", row(c)?)?;
    csv.flush()?;
    Ok(())
}
/// The files `cycles` may write, after the run's stem.
const OUTPUTS: &[&str] = &[
    "-cycles.csv",
    "-cycles-orbits.jsonl",
    "-cycles-amplitude.png",
    "-cycles-amplitude.svg",
    "-cycles-period.png",
    "-cycles-period.svg",
    "-cycles-orbits.png",
    "-cycles-orbits.svg",
    "-cycles-time-series.png",
    "-cycles-time-series.svg",
    "-cycles-lpc-curve.csv",
    "-cycles-lpc-curve.png",
    "-cycles-lpc-curve.svg",
];

/// The requested stiffnesses without a cycle, as comment lines at the end of the CSV.
fn write_requested_csv(csv: &mut impl Write, requested: &[Requested]) -> Result<(), Error> {
    for r in requested {
        if let Some(why) = &r.reason {
            let asked = match r.asked.name {
                "kappa" => String::new(),
                _ => format!(" (asked as {})", r.asked.describe()),
            };
            writeln!(
                csv,
                "# requested kappa = {:.15e}{asked} not delivered: {why}",
                r.kappa
            )?;
        }
    }
    csv.flush()?;
    Ok(())
}
