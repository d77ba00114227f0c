//! The commands on an adhesive scene (`law = "adhesive"`): text, JSON and
//! figures of [`crate::adhesive::jobs`]. Each command's `run` hands a scene
//! whose law is adhesive here first ([`adhesive_setup`]); options of the
//! rate-and-state analyses that have no meaning for it are refused, naming
//! the option.

use super::files::{create_file, write, LineFile, OutputArgs, INCOMPLETE};
use super::interrupt;
use super::SceneArgs;
use crate::adhesive::analysis::cycles::CycleInUnits;
pub use crate::adhesive::jobs::Judged;
use crate::adhesive::jobs::{
    self, AdhesiveCycles, AdhesiveHopf, AdhesiveSetup, AdhesiveSimulation,
};
use crate::adhesive::scene;
use crate::error::{Error, InputError};
use crate::file_names::with_suffix;
use crate::model::ModelKind;
use crate::plot::lines::{render, vertical_marker, LineFigure, Series};
use plotters::style::RGBColor;
use std::io::Write;
use std::path::{Path, PathBuf};

/// The adhesive scene named by `args`, with its model decision, or `None`
/// for a scene of another law, `--set` applied to the scene's numbers
/// ([`scene::load_with`]), the model judged where `judged` says (or
/// forced by `--model`). Refuses the options named in `unused` that were
/// given.
pub fn adhesive_setup(
    args: &SceneArgs,
    unused: &[(&str, bool)],
    judged: Judged,
) -> Result<Option<AdhesiveSetup>, Error> {
    if crate::scene::law_of(args.scene_name())? != crate::scene::Law::Adhesive {
        return Ok(None);
    }
    let refuse = |option: &str, what: &str| -> Error {
        InputError::Conflict(format!(
            "{option} is not available on an adhesive scene (law = \"adhesive\", {}): {what}",
            args.scene_name()
        ))
        .into()
    };
    if let Some((option, _)) = unused.iter().find(|(_, given)| *given) {
        return Err(refuse(option, why_unused(option)));
    }
    let scene = scene::load_with(args.scene_name(), &args.set)?;
    for w in &scene.warnings {
        eprintln!("warning: {w}");
    }
    Ok(Some(AdhesiveSetup::new(
        scene,
        args.inertia_threshold,
        judged,
        args.model.map(ModelKind::from),
    )?))
}

/// Why an option of the rate-and-state commands has no meaning on an
/// adhesive scene.
fn why_unused(option: &str) -> &'static str {
    match option {
        "--units" => {
            "the adhesive text gives every value in the experimenter's units (N, N/m, µm/s, s) \
             with the dimensionless one beside it, and the JSON carries both: there is no \
             separate dimensionless text; drop --units"
        }
        "--max-steps" => {
            "the adhesive branch and diagram sample a grid of 20 velocities per decade over \
             V_range (steady sliding is explicit, eq. D2, and K_c is located at each velocity), \
             with no continuation steps to limit; narrow V_range instead"
        }
        _ => {
            "the adhesive block runs with its scene's values (see docs/model.md, \"Soft \
             adhesive contacts\")"
        }
    }
}

fn json<T: serde::Serialize>(value: &T) -> Result<String, Error> {
    Ok(serde_json::to_string_pretty(value).map_err(std::io::Error::other)?)
}

fn plot_error(e: crate::plot::PlotError) -> Error {
    Error::Output(std::io::Error::other(e.to_string()))
}

/// The lines every command starts its text with.
fn print_setup(s: &AdhesiveSetup) {
    let p = &s.params;
    let u = &s.units;
    println!(
        "scene {} (law = adhesive, {} model: chi = m lambda_n / F_u = {:.2e})",
        s.scene, s.model, s.inertia_ratio
    );
    println!("  model: {} ({})", s.model, s.model_reason);
    if let (Some(m), Some(why)) = (s.scene_model, &s.scene_model_reason) {
        println!(
            "  the scene's own model, of its onset at V and its operating point (as hopf and \
             cycles): {m} ({why})"
        );
    }
    println!(
        "  F_a = {:.6e} N, V_s = {:.6e} µm/s, tau_out = {:.6e} s, tau_on / tau_out = r = {:.6e}, \
         F_v / F_a = f_v = {:.6e}, alpha = {}",
        u.f_a,
        u.v_s * 1e6,
        u.tau_out,
        p.r,
        p.f_v,
        p.alpha
    );
    println!(
        "  V = {:.6e} µm/s (nu = {:.6e}), K = {:.6e} N/m (kappa = {:.6e})",
        u.velocity_um_s(p.nu),
        p.nu,
        u.stiffness_n_m(p.kappa),
        p.kappa
    );
    if let (Some(v), Some(f)) = (s.v_max_um_s, s.force_at_v_max_n) {
        println!("  steady friction: maximum {f:.6e} N at V_max = {v:.6e} µm/s");
    }
    if let (Some(v), Some(f)) = (s.v_c_um_s, s.force_at_v_c_n) {
        println!("  steady friction: minimum {f:.6e} N at V_c = {v:.6e} µm/s");
    }
    println!("  {}", s.weakening());
}

/// `hopf` on an adhesive scene.
pub fn hopf(setup: AdhesiveSetup, as_json: bool) -> Result<(), Error> {
    let r = jobs::hopf(setup)?;
    if as_json {
        println!("{}", json(&r)?);
        return Ok(());
    }
    print_text_hopf(&r);
    Ok(())
}

fn print_text_hopf(r: &AdhesiveHopf) {
    print_setup(&r.setup);
    println!(
        "steady sliding at V: force {:.6e} N, bond fraction n = {:.6e}",
        r.steady_force_n, r.steady_bonds
    );
    match &r.critical {
        Some(c) => {
            let o = &c.onset;
            println!(
                "onset ({} model): K_c = {:.6e} N/m (kappa_c = {:.10e}; closed form {:.10e}), \
                 frequency {:.6e} Hz (omega_c = {:.6e} / tau_out)",
                r.setup.scene_model_kind.name(),
                c.k_c_n_m,
                o.kappa_c,
                o.kappa_c_closed_form,
                c.frequency_hz,
                o.omega_c
            );
            println!(
                "onset type: {} (l1 = {:.6e} +- {:.1e})",
                o.onset.name(),
                o.l1,
                o.l1_error_bound
            );
        }
        None => println!(
            "steady sliding is stable at every stiffness: steady friction rises with V here \
             (dF_ss/du = {:.3e})",
            r.steady_slope.unwrap_or(f64::NAN)
        ),
    }
    if let Some(op) = &r.operating_point {
        println!("{}", op.line());
    }
}

/// `branch` on an adhesive scene: text, `--json`, or `--csv` (a `# scene`
/// comment line, then a row per velocity in physical units and
/// dimensionless; the Hopf points as `# hopf` comment lines).
pub fn branch(setup: AdhesiveSetup, as_json: bool, as_csv: bool) -> Result<(), Error> {
    let r = jobs::branch(setup)?;
    if as_json {
        println!("{}", json(&r)?);
        return Ok(());
    }
    if as_csv {
        println!(
            "# scene {} (law = adhesive, {} model)",
            r.setup.scene, r.setup.model
        );
        println!("V_um_per_s,steady_force_N,n,re_lambda,stable,nu,s,slope");
        for p in &r.points {
            let pt = &p.point;
            println!(
                "{:e},{:e},{:e},{:e},{},{:e},{:e},{:e}",
                p.v_um_per_s,
                p.steady_force_n,
                pt.n,
                pt.eigenvalues[0][0],
                pt.stable,
                pt.nu,
                pt.s,
                pt.slope
            );
        }
        for (h, v) in r.hopf_points.iter().zip(&r.hopf_points_um_s) {
            println!("# hopf V_um_per_s={v:e} nu={:e} omega={:e}", h.nu, h.omega);
        }
        return Ok(());
    }
    print_setup(&r.setup);
    println!("steady sliding in V at the scene's K:");
    println!(
        "  {:>13} {:>13} {:>11} {:>11}  stability",
        "V [µm/s]", "force [N]", "n", "re lambda"
    );
    for r in &r.points {
        let pt = &r.point;
        println!(
            "  {:>13.6e} {:>13.6e} {:>11.4e} {:>11.3e}  {}",
            r.v_um_per_s,
            r.steady_force_n,
            pt.n,
            pt.eigenvalues[0][0],
            if pt.stable { "stable" } else { "unstable" }
        );
    }
    for (h, v) in r.hopf_points.iter().zip(&r.hopf_points_um_s) {
        println!(
            "Hopf point at V = {v:.8e} µm/s (nu = {:.8e}, omega = {:.4e} / tau_out)",
            h.nu, h.omega
        );
    }
    Ok(())
}

/// The stem of the files of `command`'s run, `<out>/<run>-<command>`
/// (its JSON record `<stem>.json`, the figures `<stem>-<figure>.png`),
/// refused when an earlier run's files exist ([`OutputArgs::stem`]).
fn stem(
    output: &OutputArgs,
    args: &SceneArgs,
    setup: &AdhesiveSetup,
    command: &str,
    figures: &[&str],
) -> Result<PathBuf, Error> {
    output.create_dir()?;
    // The record an earlier run is judged by comes first (files.rs,
    // `unfinished`): the CSV where the command writes one (it ends with
    // `# incomplete` when that run did not finish), else the JSON.
    let record = if WRITES_CSV.contains(&command) {
        [format!("-{command}.csv"), format!("-{command}.json")]
    } else {
        [format!("-{command}.json"), format!("-{command}.csv")]
    };
    let outputs: Vec<String> = record
        .into_iter()
        .chain(figures.iter().map(|f| format!("-{command}-{f}.png")))
        .collect();
    let outputs: Vec<&str> = outputs.iter().map(String::as_str).collect();
    let stem = output.stem(&setup.scene, args, false, &outputs)?;
    Ok(with_suffix(&stem, &format!("-{command}")))
}

/// The adhesive commands that write a CSV as they compute.
const WRITES_CSV: [&str; 2] = ["cycles", "simulation"];

fn line(points: Vec<(f64, f64)>, label: &str, color: RGBColor, dashed: bool) -> Series {
    Series {
        label: Some(label.into()),
        points,
        color,
        dashed,
        markers: false,
    }
}

const BLUE: RGBColor = RGBColor(31, 90, 180);
const RED: RGBColor = RGBColor(200, 50, 40);
const GREY: RGBColor = RGBColor(110, 110, 110);

/// Writes the JSON record and names the files.
fn finish(
    stem: &Path,
    record: String,
    mut files: Vec<PathBuf>,
    as_json: bool,
) -> Result<(), Error> {
    let path = with_suffix(stem, ".json");
    write(&path, &record)?;
    files.insert(0, path);
    if as_json {
        println!("{record}");
    } else {
        for f in files {
            println!("wrote {}", f.display());
        }
    }
    Ok(())
}

/// The stability diagram's figure in the rate-and-state diagram's
/// convention ([`crate::plot::stability`]): the critical stiffness located
/// by the engine, solid where the onset is supercritical, dashed red where
/// it is subcritical, the closed form as dots, a marker where the onset
/// type changes between grid points (a Bautin point), vertical lines where
/// `K_c -> 0` (the friction maximum and minimum) and where `chi` crosses
/// the inertia threshold, and the scene's operating point with its verdict.
fn stability_figure(r: &jobs::AdhesiveDiagram) -> crate::plot::stability::StabilityFigure {
    use crate::plot::stability::{segments, OperatingMarker, StabilityFigure};
    let s = &r.setup;
    let u = &s.units;
    let (lo, hi) = s.scene_full.nu_range;
    let x_range = (u.velocity_um_s(lo), u.velocity_um_s(hi));
    // The curve with each located Bautin point closing the stretch of the
    // type below it, so that the next stretch starts there.
    let mut curve: Vec<(f64, f64, crate::analysis::hopf::Criticality)> = Vec::new();
    for p in &r.points {
        let (Some(k), Some(onset)) = (p.k_n_per_m, p.point.onset) else {
            continue;
        };
        if let Some(b) = r.bautin_points.iter().find(|b| {
            curve.last().is_some_and(|l| l.0 < b.v_um_per_s) && b.v_um_per_s < p.v_um_per_s
        }) {
            curve.push((b.v_um_per_s, b.k_n_per_m, b.point.below));
        }
        curve.push((p.v_um_per_s, k, onset));
    }
    let reference = r
        .points
        .iter()
        .step_by(4)
        .filter_map(|p| {
            let mut q = s.params;
            q.nu = p.point.nu;
            let (k, _) = crate::adhesive::block::critical_stiffness_of(&q, s.model_kind);
            (k > 0.0).then(|| (p.v_um_per_s, u.stiffness_n_m(k)))
        })
        .collect();
    let markers = r
        .bautin_points
        .iter()
        .map(|b| {
            (
                format!(
                    "Bautin (l1 = 0): {} below, {} above",
                    b.point.below.name(),
                    b.point.above.name()
                ),
                b.v_um_per_s,
                b.k_n_per_m,
            )
        })
        .collect();
    // The vertical lines that fall inside the figure's velocity range.
    let vlines: Vec<(String, f64)> = [(s.v_max_um_s, "maximum V_max"), (s.v_c_um_s, "minimum V_c")]
        .into_iter()
        .filter_map(|(v, what)| Some((format!("K_c → 0: friction {what}"), v?)))
        .chain(s.inertia_crossing_um_s.map(|v| {
            (
                format!("chi = {:.0e} (inertia threshold)", s.inertia_threshold),
                v,
            )
        }))
        .filter(|(_, v)| x_range.0 <= *v && *v <= x_range.1)
        .collect();
    StabilityFigure {
        title: format!(
            "Stability diagram, {} (adhesive, {} model)",
            s.scene, s.model
        ),
        x_label: "driving velocity V [µm/s]".into(),
        y_label: "critical stiffness K_c [N/m]".into(),
        segments: segments(&curve),
        reference,
        reference_label: "closed form, kappa_c = -lambda_n dF_ss/du (1 + chi)".into(),
        markers,
        operating_point: r
            .operating_point
            .as_ref()
            .filter(|op| op.in_range)
            .map(|op| OperatingMarker {
                label: format!(
                    "operating point: K = {} N/m at V = {} µm/s ({})",
                    crate::records::significant(op.k_n_per_m),
                    crate::records::significant(op.v_um_per_s),
                    op.regime.name()
                ),
                x: op.v_um_per_s,
                y: op.k_n_per_m,
                margin: op.margin,
            }),
        vlines,
        lpc: Vec::new(),
        bistable: Vec::new(),
        unknown: Vec::new(),
        x_range,
        notes: Vec::new(),
        stable_above: true,
    }
}

/// `diagram` on an adhesive scene: the critical stiffness against `V`
/// (stability diagram) and steady friction against `V`.
pub fn diagram(
    setup: AdhesiveSetup,
    args: &SceneArgs,
    output: &OutputArgs,
    as_json: bool,
) -> Result<(), Error> {
    let stem = stem(
        output,
        args,
        &setup,
        "diagram",
        &["stability", "steady-friction"],
    )?;
    let r = jobs::diagram(setup)?;
    let s = &r.setup;
    if !as_json {
        print_setup(s);
        println!("stability diagram: K_c against V (stick-slip below K_c)");
        for record in &r.points {
            let pt = &record.point;
            match (record.k_n_per_m, pt.onset) {
                (Some(k), Some(o)) => println!(
                    "  V = {:>12.5e} µm/s  K_c = {:>12.5e} N/m  {}  (chi = {:.2e}{})",
                    record.v_um_per_s,
                    k,
                    o.name(),
                    pt.inertia_ratio,
                    if pt.needs_inertia {
                        ", needs inertia"
                    } else {
                        ""
                    }
                ),
                _ => println!(
                    "  V = {:>12.5e} µm/s  stable at every stiffness",
                    record.v_um_per_s
                ),
            }
        }
    }
    if !as_json {
        for b in &r.bautin_points {
            println!(
                "Bautin point (l1 = 0): V = {:.6e} µm/s (nu = {:.6e}), K_c = {:.6e} N/m: {} \
                 below, {} above",
                b.v_um_per_s,
                b.point.nu,
                b.k_n_per_m,
                b.point.below.name(),
                b.point.above.name()
            );
        }
        if let Some(op) = &r.operating_point {
            println!("{}", op.line());
        }
        if let Some(k) = r.curve_k_c_at_v_n_per_m {
            println!(
                "  the diagram's curve ({} model over V_range) gives K_c = {} N/m at the scene's \
                 V; the operating point's K_c above is the scene's own ({} model)",
                s.model,
                crate::records::significant(k),
                s.scene_model_kind.name()
            );
        }
    }
    let stability = stability_figure(&r);
    let friction: Vec<(f64, f64)> = r
        .steady
        .iter()
        .map(|p| (p.v_um_per_s, p.steady_force_n))
        .collect();
    let mut series = vec![line(friction, "steady friction F_ss(V)", BLUE, false)];
    for (v, label) in [(s.v_max_um_s, "V_max"), (s.v_c_um_s, "V_c")] {
        if let Some(v) = v {
            let marker = vertical_marker(&series, v, &format!("{label} = {v:.3e} µm/s"), GREY);
            series.push(marker);
        }
    }
    let steady = LineFigure {
        title: format!(
            "Steady friction, {} (Schallamach bonds + junction viscosity)",
            s.scene
        ),
        x_label: "driving velocity V [µm/s]".into(),
        y_label: "steady friction force [N]".into(),
        log_x: true,
        log_y: false,
        series,
    };
    // No empty frame: without an onset anywhere in the range there is no
    // K_c to draw, and the text says so instead.
    let mut files = if stability.segments.is_empty() {
        let (lo, hi) = stability.x_range;
        let note = format!(
            "no stability figure: steady sliding is stable at every stiffness across V_range \
             [{lo:.4e}, {hi:.4e}] µm/s (steady friction nowhere falls with V there), so there is \
             no K_c to draw; the steady friction figure shows why"
        );
        if as_json {
            eprintln!("note: {note}");
        } else {
            println!("{note}");
        }
        Vec::new()
    } else {
        crate::plot::stability::render(&stability, &with_suffix(&stem, "-stability"))
            .map_err(plot_error)?
    };
    files.extend(render(&steady, &with_suffix(&stem, "-steady-friction")).map_err(plot_error)?);
    finish(&stem, json(&r)?, files, as_json)
}

/// `cycles` on an adhesive scene.
pub fn cycles(
    setup: AdhesiveSetup,
    args: &SceneArgs,
    output: &OutputArgs,
    limits: (usize, usize),
    as_json: bool,
) -> Result<(), Error> {
    let stem = stem(output, args, &setup, "cycles", &["period", "orbits"])?;
    // The table as the branch computes it: a stop signal (or a failure)
    // keeps every row written and ends the file with `# incomplete`.
    let csv_path = with_suffix(&stem, ".csv");
    let mut csv = create_file(&csv_path)?;
    let units = setup.units;
    writeln!(csv, "{CYCLES_HEADER}")?;
    interrupt::catch_interrupts();
    let mut written = Ok(());
    let r = jobs::cycles_watched(setup, limits, &mut |c| {
        if written.is_ok() {
            written = cycles_row(&mut csv, &units, c);
        }
        written.is_ok() && !interrupt::interrupted()
    })?;
    written?;
    if let Some(why) = &r.stop {
        writeln!(csv, "{INCOMPLETE} {why}")?;
    }
    csv.finish()?;
    if !as_json {
        print_cycles(&r);
    }
    let u = r.setup.units;
    let by_k =
        |f: &dyn Fn(&crate::adhesive::analysis::cycles::AdhesiveCycle) -> f64| -> Vec<(f64, f64)> {
            r.cycles
                .iter()
                .map(|c| (u.stiffness_n_m(c.kappa), f(c)))
                .collect()
        };
    let mut series = vec![
        line(by_k(&|c| u.time_s(c.period)), "period [s]", BLUE, false),
        line(
            by_k(&|c| 1e3 * u.force_n(c.s_max - c.s_min)),
            "force drop [mN]",
            RED,
            true,
        ),
    ];
    for f in &r.folds {
        let k = u.stiffness_n_m(f.cycle.kappa);
        let label = format!("fold of cycles (lpc), K = {k:.4e} N/m");
        let marker = vertical_marker(&series, k, &label, GREY);
        series.push(marker);
    }
    let period = LineFigure {
        title: format!(
            "Stick-slip cycles, {}: period and force drop",
            r.setup.scene
        ),
        x_label: "stiffness K [N/m]".into(),
        y_label: "period [s]; force drop [N] x 1000".into(),
        log_x: true,
        log_y: true,
        series,
    };
    let picks: Vec<&crate::adhesive::analysis::cycles::AdhesiveCycle> = {
        let n = r.cycles.len();
        let mut idx: Vec<usize> = (0..5).map(|i| i * n.saturating_sub(1) / 4).collect();
        idx.dedup();
        idx.into_iter()
            .filter_map(|i| r.cycles.get(i))
            .chain(r.at_scene.iter())
            .collect()
    };
    let orbits = LineFigure {
        title: format!("Cycles in the force-velocity plane, {}", r.setup.scene),
        x_label: "slip velocity v [µm/s]".into(),
        y_label: "spring force [N]".into(),
        log_x: true,
        log_y: false,
        series: picks
            .iter()
            .enumerate()
            .map(|(i, c)| {
                let shade = (200.0 * i as f64 / picks.len().max(1) as f64) as u8;
                line(
                    c.orbit
                        .iter()
                        .map(|o| (u.velocity_um_s(o[2]), u.force_n(o[1])))
                        .collect(),
                    &format!("K = {:.3e} N/m", u.stiffness_n_m(c.kappa)),
                    RGBColor(shade, 60, 200 - shade),
                    false,
                )
            })
            .collect(),
    };
    let mut files = vec![csv_path];
    if !r.cycles.is_empty() {
        files.extend(render(&period, &with_suffix(&stem, "-period")).map_err(plot_error)?);
        files.extend(render(&orbits, &with_suffix(&stem, "-orbits")).map_err(plot_error)?);
    }
    finish(&stem, json(&r)?, files, as_json)?;
    match &r.stop {
        None => Ok(()),
        Some(_) if r.interrupted => Err(interrupt::stopped(format!(
            "after {} cycles, down to K = {:.6e} N/m",
            r.cycles.len(),
            r.cycles
                .last()
                .map_or(f64::NAN, |c| u.stiffness_n_m(c.kappa))
        ))),
        Some(why) if r.onset.is_none() => Err(Error::Partial(format!("no cycle branch: {why}"))),
        Some(why) => Err(Error::Partial(format!("the cycles are incomplete: {why}"))),
    }
}

/// The columns of the adhesive `cycles` CSV: physical units, then the
/// dimensionless values (docs/model.md, "Soft adhesive contacts").
const CYCLES_HEADER: &str = "K_N_per_m,period_s,force_drop_N,s_min_N,s_max_N,v_min_um_per_s,\
v_max_um_per_s,n_min,n_max,stable,kappa,period,delta_s,u_min,u_max";

/// One cycle's row of the `cycles` CSV.
fn cycles_row(
    csv: &mut LineFile,
    u: &crate::adhesive::scene::AdhesiveUnits,
    c: &crate::adhesive::analysis::cycles::AdhesiveCycle,
) -> std::io::Result<()> {
    let p = CycleInUnits::of(c, u);
    writeln!(
        csv,
        "{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{},{:e},{:e},{:e},{:e},{:e}",
        p.k_n_per_m,
        p.period_s,
        p.force_drop_n,
        p.s_min_n,
        p.s_max_n,
        p.v_min_um_per_s,
        p.v_max_um_per_s,
        c.n_min,
        c.n_max,
        c.stable,
        c.kappa,
        c.period,
        c.s_max - c.s_min,
        c.u_min,
        c.u_max
    )?;
    csv.flush()
}

fn print_cycles(r: &AdhesiveCycles) {
    print_setup(&r.setup);
    let u = r.setup.units;
    match (&r.onset, &r.reason) {
        (Some(o), _) => println!(
            "onset ({} model): K_c = {:.6e} N/m (kappa_c = {:.6e}), {}",
            r.setup.scene_model_kind.name(),
            u.stiffness_n_m(o.kappa_c),
            o.kappa_c,
            o.onset.name()
        ),
        (None, Some(reason)) => println!("no cycles: {reason}"),
        (None, None) => {}
    }
    let kappa_c = r.onset.as_ref().map_or(f64::NAN, |o| o.kappa_c);
    for c in r.folds.iter().map(|f| &f.cycle) {
        // Above K_c the cycles up to the fold coexist with stable steady
        // sliding; below it the branch turns back toward larger K, two
        // cycles on either side of the turn, with steady sliding unstable.
        let meaning = if c.kappa > kappa_c {
            "the cycles coexist with stable steady sliding between K_c and this stiffness"
        } else {
            "below K_c, the branch turns back toward larger K here: two of its cycles coexist \
             just above this stiffness (the table's stable column tells them apart), with \
             steady sliding unstable"
        };
        let p = CycleInUnits::of(c, &u);
        println!(
            "fold of cycles (lpc) at K = {:.6e} N/m (kappa = {:.6e}): period {:.6e} s, force \
             drop {:.6e} N; {meaning}",
            p.k_n_per_m, c.kappa, p.period_s, p.force_drop_n
        );
    }
    if !r.cycles.is_empty() {
        println!(
            "  {:>12} {:>12} {:>12} {:>13} {:>9}",
            "K [N/m]", "period [s]", "drop [N]", "v_max [µm/s]", "stable"
        );
    }
    for c in &r.cycles {
        let p = CycleInUnits::of(c, &u);
        println!(
            "  {:>12.5e} {:>12.5e} {:>12.5e} {:>13.5e} {:>9}",
            p.k_n_per_m, p.period_s, p.force_drop_n, p.v_max_um_per_s, c.stable
        );
    }
    if let Some(c) = &r.at_scene {
        let which = match r.operating_point.as_ref().filter(|op| op.kappa > 0.0) {
            Some(op) if op.regime == crate::analysis::operating_point::Regime::Bistable => {
                "the scene's K; the stable one of the two the branch passes there"
            }
            Some(_) => "the scene's K",
            None => "the branch's end, 0.5 K_c: the scene gives no K",
        };
        let p = CycleInUnits::of(c, &u);
        println!(
            "the cycle at K = {:.6e} N/m ({which}; collocation): period {:.6e} s, force drop \
             {:.6e} N (from {:.6e} to {:.6e} N), slip velocity up to {:.4e} µm/s, {}",
            p.k_n_per_m,
            p.period_s,
            p.force_drop_n,
            p.s_min_n,
            p.s_max_n,
            p.v_max_um_per_s,
            if c.stable { "stable" } else { "unstable" }
        );
    }
    if let Some(why) = &r.at_scene_reason {
        println!("{why}");
    }
    if let Some(c) = &r.simulated {
        println!(
            "the same by simulation (settled): period {:.6e} s, force drop {:.6e} N",
            u.time_s(c.period),
            u.force_n(c.force_drop)
        );
    }
    if let Some(op) = &r.operating_point {
        println!("{}", op.line());
    }
}

/// `simulate` on an adhesive scene.
pub fn simulate(
    setup: AdhesiveSetup,
    args: &SceneArgs,
    output: &OutputArgs,
    protocol: Option<Vec<(f64, f64)>>,
    (perturb, rtol, max_steps): (f64, f64, usize),
    as_json: bool,
) -> Result<(), Error> {
    let stem = stem(
        output,
        args,
        &setup,
        "simulation",
        &["spring-force", "velocity", "bonds"],
    )?;
    interrupt::catch_interrupts();
    let r = jobs::simulate_watched(
        setup,
        protocol,
        (perturb, rtol, max_steps),
        &interrupt::interrupted,
    )?;
    let u = r.setup.units;
    // The time series, every accepted step; a run that ended early ends
    // the file with `# incomplete`.
    let csv_path = with_suffix(&stem, ".csv");
    let mut csv = create_file(&csv_path)?;
    writeln!(csv, "t_s,spring_force_N,v_um_per_s,n,t,s,u")?;
    for (((t, s), v), n) in r.run.t.iter().zip(&r.run.s).zip(&r.run.u).zip(&r.run.n) {
        writeln!(
            csv,
            "{:e},{:e},{:e},{:e},{t:e},{s:e},{v:e}",
            u.time_s(*t),
            u.force_n(*s),
            u.velocity_um_s(*v),
            n
        )?;
    }
    if let Some(why) = &r.stop {
        writeln!(csv, "{INCOMPLETE} {why}")?;
    }
    csv.finish()?;
    if !as_json {
        print_simulation(&r);
    }
    let t: Vec<f64> = r.run.t.iter().map(|t| u.time_s(*t)).collect();
    let series = |y: Vec<f64>, label: &str| {
        vec![line(t.iter().copied().zip(y).collect(), label, BLUE, false)]
    };
    let force = LineFigure {
        title: format!("Spring force, {} (adhesive)", r.setup.scene),
        x_label: "time t [s]".into(),
        y_label: "spring force K(Vt - x) [N]".into(),
        log_x: false,
        log_y: false,
        series: series(r.run.s.iter().map(|s| u.force_n(*s)).collect(), "K(Vt - x)"),
    };
    let mut v_series = series(
        r.run.u.iter().map(|v| u.velocity_um_s(*v)).collect(),
        "v(t)",
    );
    let mut t0 = 0.0;
    for seg in &r.protocol {
        let t1 = t0 + u.time_s(seg.duration);
        if seg.nu > 0.0 {
            let v = u.velocity_um_s(seg.nu);
            let mut level = line(vec![(t0, v), (t1, v)], "pulling velocity V(t)", GREY, true);
            if v_series.len() > 1 {
                level.label = None;
            }
            v_series.push(level);
        }
        t0 = t1;
    }
    let velocity = LineFigure {
        title: format!("Slip velocity, {} (adhesive)", r.setup.scene),
        x_label: "time t [s]".into(),
        y_label: "slip velocity v [µm/s]".into(),
        log_x: false,
        log_y: true,
        series: v_series,
    };
    let bonds = LineFigure {
        title: format!("Bonded fraction, {} (adhesive)", r.setup.scene),
        x_label: "time t [s]".into(),
        y_label: "fraction of bonded chains n".into(),
        log_x: false,
        log_y: false,
        series: series(r.run.n.clone(), "n(t)"),
    };
    let mut files = vec![csv_path];
    files.extend(render(&force, &with_suffix(&stem, "-spring-force")).map_err(plot_error)?);
    files.extend(render(&velocity, &with_suffix(&stem, "-velocity")).map_err(plot_error)?);
    files.extend(render(&bonds, &with_suffix(&stem, "-bonds")).map_err(plot_error)?);
    finish(&stem, json(&r)?, files, as_json)?;
    match &r.stop {
        None => Ok(()),
        Some(_) if r.run.interrupted => Err(interrupt::stopped(format!(
            "at t = {:.6e} s",
            r.run.t.last().map_or(0.0, |t| u.time_s(*t))
        ))),
        Some(why) => Err(Error::Partial(format!(
            "the simulation did not reach the protocol's end: {why}"
        ))),
    }
}

fn print_simulation(r: &AdhesiveSimulation) {
    print_setup(&r.setup);
    let u = r.setup.units;
    println!("{} steps", r.steps);
    for (i, seg) in r.protocol.iter().enumerate() {
        println!(
            "  segment {}: V = {:.4e} µm/s for {:.4e} s: largest force {:.6e} N (steady friction {:.6e} N)",
            i + 1,
            u.velocity_um_s(seg.nu),
            u.time_s(seg.duration),
            r.peak_force_n[i],
            r.steady_force_n[i]
        );
    }
    match (r.settled_period_s, r.settled_force_drop_n, r.settled) {
        (Some(p), Some(d), Some(c)) => println!(
            "settled stick-slip in the last segment: period {p:.6e} s, force drop {d:.6e} N \
             (period changed by {:.1e} over the cycle before)",
            c.period_change
        ),
        _ if r.regime == jobs::SettledRegime::Steady => println!(
            "steady sliding in the last segment: over its second half the spring force varies \
             by less than the integration's error"
        ),
        _ => println!(
            "no settled regime in the last segment (fewer than three force maxima above the \
             integration's error, and the force still varies)"
        ),
    }
}
