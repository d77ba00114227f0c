//! `stickslip diagram`: the stability diagram of one or several scenes
//! (in parallel), as figures (PNG, SVG), CSV and JSON. Each scene's files and
//! summary are written as it finishes; Ctrl-C skips the scenes not started.

pub mod axes;

use super::files::OutputArgs;
use super::lpc_output::{lpc_summary, write_lpc_csv};
use super::{significant, SceneArgs, Setup, TextUnits};
use crate::analysis::diagram::{SpecialKind, StabilityDiagram, DEFAULT_CURVE_STEPS};
use crate::analysis::hopf::Criticality;
use crate::error::{Error, InputError};
use crate::file_names::with_suffix;
use crate::jobs::diagram::{onset_type, Diagram, DiagramRequest};
use crate::jobs::{self, SceneSpec};
use crate::plot::diagram::write_figures;
use crate::records::csv::{header, row};
use crate::records::diagram::{DiagramRecords, HopfCurvePoint};
use clap::Args;
use continuation::{AsIs, Wrap};
use rayon::prelude::*;
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::time::Instant;

#[derive(Args, Debug)]
pub struct DiagramArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Velocity range as LO:HI in units of V0 (dimensionless nu); default: the scene's V_range.
    // A value starting with '-' is this option's (refused by its own
    // check, naming it), not an unknown flag.
    #[arg(long, value_name = "LO:HI", allow_hyphen_values = true)]
    pub nu_range: Option<String>,
    #[command(flatten)]
    pub output: OutputArgs,
    /// Units of the stiffnesses in the text: physical (K/W in 1/m) or
    /// dimensionless (kappa). The CSV and the JSON carry both. Adhesive
    /// scenes: refused (their text gives K_c in N/m; the JSON both).
    #[arg(long, value_enum, default_value_t = TextUnits::Physical)]
    pub units: TextUnits,
    /// Print one JSON object (an array for several scenes) instead of text.
    #[arg(long)]
    pub json: bool,
    /// Most continuation steps along the Hopf curve in each direction. The
    /// default covers the built-in scenes' ranges; a curve cut short by it
    /// is kept and the command exits with status 4 (partial). Adhesive scenes: refused (their
    /// diagram samples a grid in V).
    #[arg(long, default_value_t = DEFAULT_CURVE_STEPS)]
    pub max_steps: usize,
    /// `--x P --y Q`: the diagram in a pair of control parameters.
    #[command(flatten)]
    pub axes: axes::AxesArgs,
}

fn parse_range(text: &str) -> Result<(f64, f64), InputError> {
    let (lo, hi) = axes::parse_lohi("--nu-range", text, "e.g. 0.1:100")?;
    // As `--set nu` allows: beyond it the steady state's velocity and age
    // leave the range the model is evaluated in.
    let (min, max) = crate::params::MAGNITUDE_RANGE;
    for v in [lo, hi] {
        if !(min..=max).contains(&v) {
            return Err(InputError::out_of_range(
                "--nu-range",
                v,
                "velocities of magnitude 1e-100 to 1e100 (units of V0)",
            ));
        }
    }
    Ok((lo, hi))
}

/// Runs the command.
pub fn run(args: &DiagramArgs) -> Result<(), Error> {
    run_with(args, &AsIs)
}

/// The files `diagram` may write for a scene, after its stem.
const OUTPUTS: &[&str] = &[
    "-diagram.json",
    "-hopf-curve.csv",
    "-lpc-curve.csv",
    "-stability-physical.png",
    "-stability-physical.svg",
    "-stability-dimensionless.png",
    "-stability-dimensionless.svg",
];

/// Runs the command with the models built through `fields` (the benchmark
/// counts their evaluations).
pub fn run_with<F: Wrap>(args: &DiagramArgs, fields: &F) -> Result<(), Error> {
    let unused = [
        ("--x/--y", args.axes.parse()?.is_some()),
        ("--nu-range", args.nu_range.is_some()),
        ("--max-steps", args.max_steps != DEFAULT_CURVE_STEPS),
        ("--units", args.units != TextUnits::Physical),
    ];
    if let Some(setup) =
        super::adhesive::adhesive_setup(&args.scene, &unused, super::adhesive::Judged::OverRange)?
    {
        return super::adhesive::diagram(setup, &args.scene, &args.output, args.json);
    }
    if let Some(pair) = args.axes.parse()? {
        return axes::run(args, pair);
    }
    // Each scene once (the same scene twice would write the same files concurrently).
    let mut names: Vec<&str> = Vec::new();
    for name in args
        .scene
        .scene_name()
        .split(',')
        .map(str::trim)
        .filter(|s| !s.is_empty())
    {
        if !names.contains(&name) {
            names.push(name);
        }
    }
    let range = args.nu_range.as_deref().map(parse_range).transpose()?;
    args.output.create_dir()?;
    // Every scene's files are checked before any is computed.
    let several = names.len() > 1;
    for name in &names {
        let scene = crate::scene::load(name)?;
        args.output
            .stem(&scene.name, &args.scene, several, OUTPUTS)?;
    }
    super::interrupt::catch_interrupts();
    let bar = super::interrupt::progress(&format!("{} scene(s)", names.len()));
    let finished = std::sync::atomic::AtomicUsize::new(0);
    // A scene not started when Ctrl-C comes is skipped (None); each finished
    // scene's summary is printed at once (not with --json).
    let results: Vec<Option<Result<Diagram, Error>>> = names
        .par_iter()
        .map(|name| {
            if super::interrupt::interrupted() {
                return None;
            }
            let r = one_scene(fields, args, name, range, several);
            let done = 1 + finished.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
            bar.set_message(format!("{done} of {} scenes finished", names.len()));
            if let (Ok(r), false) = (&r, args.json) {
                bar.suspend(|| print_text(r, args.units));
            }
            Some(r)
        })
        .collect();
    bar.finish_and_clear();
    let (mut json_out, mut completed, mut skipped) = (Vec::new(), Vec::new(), Vec::new());
    let mut results_partial: Vec<String> = Vec::new();
    for (name, r) in names.iter().zip(results) {
        match r {
            Some(r) => {
                let r = r?;
                if r.diagram.lpc.incomplete {
                    let why: Vec<String> = r
                        .diagram
                        .lpc
                        .stops
                        .iter()
                        .map(ToString::to_string)
                        .collect();
                    results_partial.push(format!(
                        "scene {}: the curve of folds of cycles is incomplete: {}",
                        r.setup.scene.name,
                        why.join("; ")
                    ));
                }
                if !r.diagram.complete {
                    results_partial.push(format!(
                        "scene {}: ended at {} (V = {} µm/s)",
                        r.setup.scene.name,
                        r.stop_text(),
                        r.records
                            .curve
                            .last()
                            .map_or("-".into(), |p| significant(p.physical.v_um_per_s))
                    ));
                }
                if args.json {
                    json_out.push(r.to_json());
                }
                completed.push(*name);
            }
            None => skipped.push(*name),
        }
    }
    if args.json {
        print_json(json_out)?;
    }
    if skipped.is_empty() {
        return partial(&results_partial);
    }
    let list = |v: &[&str]| {
        if v.is_empty() {
            "none".to_string()
        } else {
            v.join(", ")
        }
    };
    Err(super::interrupt::stopped(format!(
        "after {} of {} scenes (completed: {}; skipped: {})",
        completed.len(),
        names.len(),
        list(&completed),
        list(&skipped)
    )))
}

/// The JSON of the scenes: one object, or an array for several.
fn print_json(mut all: Vec<Value>) -> Result<(), Error> {
    let v = if all.len() == 1 {
        all.remove(0)
    } else {
        Value::Array(all)
    };
    println!(
        "{}",
        serde_json::to_string_pretty(&v).map_err(std::io::Error::other)?
    );
    Ok(())
}

/// The answer of the scenes: partial when any diagram is incomplete (why:
/// `incomplete`, one entry per scene).
fn partial(incomplete: &[String]) -> Result<(), Error> {
    if incomplete.is_empty() {
        Ok(())
    } else {
        Err(Error::Partial(format!(
            "the stability diagram is incomplete: {}",
            incomplete.join("; ")
        )))
    }
}

fn one_scene<F: Wrap>(
    fields: &F,
    args: &DiagramArgs,
    name: &str,
    range: Option<(f64, f64)>,
    several: bool,
) -> Result<Diagram, Error> {
    let t0 = Instant::now();
    let spec = SceneSpec {
        scene: name.to_string(),
        ..args.scene.spec()
    };
    let request = DiagramRequest {
        nu_range: range,
        max_steps: args.max_steps,
    };
    let mut result = jobs::diagram::run_with(fields, &spec, &request)?;
    let stem = args
        .output
        .stem(&result.setup.scene.name, &args.scene, several, OUTPUTS)?;
    let mut files = write_csv(&result.setup, &result.diagram, &result.records, &stem)?;
    files.extend(
        write_figures(
            &result.setup,
            &result.diagram,
            result.range,
            result.operating.as_ref(),
            &stem,
        )
        .map_err(|e| Error::Output(std::io::Error::other(e.to_string())))?,
    );
    result.files = files;
    let json_path = with_suffix(&stem, "-diagram.json");
    result.seconds = t0.elapsed().as_secs_f64();
    crate::cli::files::write(
        &json_path,
        serde_json::to_string_pretty(&result.to_json()).map_err(std::io::Error::other)?,
    )?;
    result.files.push(json_path);
    Ok(result)
}

/// Writes `-hopf-curve.csv` (and `-lpc-curve.csv` with fold curves) from
/// the records.
fn write_csv(
    setup: &Setup,
    d: &StabilityDiagram,
    records: &DiagramRecords,
    stem: &Path,
) -> Result<Vec<PathBuf>, Error> {
    let path = with_suffix(stem, "-hopf-curve.csv");
    // Written in full or not at all.
    let mut w = format!(
        "# scene {}; model {}; {}\n",
        setup.scene.name,
        setup.choice.kind.name(),
        setup.choice.reason
    );
    if let Some(why) = &d.reason {
        w.push_str(&format!("# {why}\n"));
    }
    w.push_str(&header::<HopfCurvePoint>()?);
    w.push('\n');
    for p in &records.curve {
        w.push_str(&row(p)?);
        w.push('\n');
    }
    crate::cli::files::write(&path, w)?;
    let mut files = vec![path];
    if !d.lpc.points.is_empty() {
        files.push(write_lpc_csv(
            stem,
            &setup.scene.name,
            &records.folds,
            &d.lpc.stops,
        )?);
    }
    Ok(files)
}

/// The onset type along the curve in words: the one type where every point
/// has it (with what it means), else where it changes.
fn onset_type_line(records: &DiagramRecords) -> Option<String> {
    let n = records.curve.len();
    if n == 0 {
        return None;
    }
    Some(match onset_type(records) {
        Some(Criticality::Supercritical) => format!(
            "onset supercritical (continuous: stick-slip grows from zero amplitude below the \
             critical stiffness) at all {n} points of the curve"
        ),
        Some(Criticality::Subcritical) => format!(
            "onset subcritical (hysteretic: stick-slip coexists with steady sliding above the \
             critical stiffness) at all {n} points of the curve"
        ),
        Some(Criticality::Degenerate) => format!(
            "onset type undecided (l1 within its rounding bound) at all {n} points of the curve"
        ),
        None => {
            let count =
                |c: Criticality| records.curve.iter().filter(|p| p.criticality == c).count();
            format!(
                "onset type changes along the curve: supercritical at {} points, subcritical at {}, \
                 undecided at {} (the Bautin points below separate them)",
                count(Criticality::Supercritical),
                count(Criticality::Subcritical),
                count(Criticality::Degenerate)
            )
        }
    })
}

fn print_text(r: &Diagram, units: TextUnits) {
    // One scene's lines together, also when scenes finish at the same time.
    let _whole = std::io::stdout().lock();
    let u = &r.setup.scene.units;
    let d = &r.diagram;
    let records = &r.records;
    println!(
        "scene: {} — {}",
        r.setup.scene.name, r.setup.scene.description
    );
    println!("model: {}", r.setup.choice.reason);
    println!(
        "Hopf curve over V = {} .. {} µm/s: {} points, ended at {}",
        significant(u.velocity_um_s(r.range.0)),
        significant(u.velocity_um_s(r.range.1)),
        records.curve.len(),
        r.stop_text()
    );
    if let Some(why) = &d.reason {
        println!("  {why}");
    }
    for s in records
        .strengthening
        .iter()
        .filter(|_| !records.curve.is_empty())
    {
        println!(
            "  velocity strengthening for V = {:.6e} .. {:.6e} µm/s: steady sliding stable for every stiffness",
            s.v_from_um_per_s, s.v_to_um_per_s
        );
    }
    if let (Some(a), Some(b)) = (records.curve.first(), records.curve.last()) {
        // Where the curve ends at kappa_c -> 0 its last computed point is only
        // where the continuation stopped (1e-6 of its start): the end is the
        // friction minimum, located on the law itself.
        let end = match records
            .special
            .iter()
            .find(|s| s.kind == SpecialKind::Endpoint)
        {
            Some(e) => format!(
                "0 at the friction minimum V_min = {} µm/s",
                significant(e.physical.v_um_per_s)
            ),
            None => format!(
                "{} (V = {} µm/s)",
                units.stiffness(b.kappa, b.physical.k_over_w_per_m, 6),
                significant(b.physical.v_um_per_s)
            ),
        };
        println!(
            "  critical stiffness from {} (V = {} µm/s) to {end}",
            units.stiffness(a.kappa, a.physical.k_over_w_per_m, 6),
            significant(a.physical.v_um_per_s),
        );
        // Relative to the largest kappa_c on the curve where kappa_c -> 0 (an end point).
        let scale = records
            .curve
            .iter()
            .map(|p| p.kappa.abs())
            .fold(0.0, f64::max);
        let max_rel = records
            .curve
            .iter()
            .map(|p| {
                let k = p.kappa_appendix_c;
                (p.kappa - k).abs() / k.abs().max(1e-6 * scale)
            })
            .fold(0.0, f64::max);
        let max_rel_omega = records
            .curve
            .iter()
            .filter_map(|p| p.omega_appendix_c.map(|w| (p.omega / w - 1.0).abs()))
            .fold(0.0, f64::max);
        println!(
            "  largest relative difference from Appendix C along the curve: {max_rel:.1e} \
             (kappa_c), {max_rel_omega:.1e} (omega_c)"
        );
    }
    if let Some(line) = onset_type_line(records) {
        println!("  {line}");
    }
    if let Some(op) = &r.operating {
        println!("  {}", op.line());
    }
    for s in &records.special {
        let l2 =
            s.l2.map(|l2| format!(", l2 = {l2:.6e} ± {:.1e}", s.l2_error_bound.unwrap_or(0.0)))
                .unwrap_or_default();
        println!(
            "  {:<9} at V = {:.10e} µm/s (nu = {:.10e}), {}, omega = {:.6e}{l2}",
            s.kind.name(),
            s.physical.v_um_per_s,
            s.nu,
            units.stiffness(s.kappa, s.physical.k_over_w_per_m, 10),
            s.omega
        );
    }
    for line in lpc_summary(&records.folds, &d.lpc.stops, units) {
        println!("{line}");
    }
    let subcritical = records
        .curve
        .iter()
        .any(|p| p.criticality == Criticality::Subcritical);
    // With a Bautin point in the range, the stops above say why its curve
    // of folds is missing, if one was started.
    let bautin = records
        .special
        .iter()
        .any(|s| s.kind == SpecialKind::Bautin);
    if subcritical && records.folds.is_empty() && bautin && d.lpc.stops.is_empty() {
        println!(
            "  no curve of folds of cycles was started from the Bautin points: no subcritical \
             point of the Hopf curve lies far enough from them (2 % in V) to start from"
        );
    } else if subcritical && records.folds.is_empty() && !bautin {
        println!(
            "  the onset is subcritical (hysteretic) but no Bautin point lies in the range, and the \
             curves of folds of cycles bounding the hysteretic region are traced from Bautin \
             points: for the fold at one velocity, stickslip cycles --set nu=... --lpc-curve"
        );
    }
    for f in &r.files {
        println!("  wrote {}", f.display());
    }
    println!("  {:.3} s", r.seconds);
}
