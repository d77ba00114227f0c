//! `stickslip cycles --param P --to VALUE`: runs the job of the cycle
//! branch in a control parameter other than the stiffness
//! ([`crate::jobs::cycles_in`]) and writes its CSV (row by row), text,
//! JSON, and the force drop and period against the control.

use super::cycles::CyclesArgs;
use super::files::{create_file, LineFile};
use super::interrupt;
use crate::analysis::control::Control;
use crate::error::{Error, InputError};
use crate::file_names::with_suffix;
use crate::jobs::cycles::{Note, Observer};
use crate::jobs::cycles_in::{asked_values, Axis, CyclesInControl, CyclesInControlRequest, Plan};
use crate::jobs::restart::orbits_path;
use crate::plot::cycles::control_figures;
use crate::records::csv::{header_of, row};
use crate::records::cycle::{Cycle, CycleSpecialPoint};
use crate::records::orbit::StoredOrbit;
use std::io::Write;
use std::path::{Path, PathBuf};

/// The control's unit as text writes it after a value (` µm/s`; nothing
/// when dimensionless).
fn unit_after(control: Control) -> String {
    match control.text_unit() {
        "" => String::new(),
        unit => format!(" {unit}"),
    }
}

/// One line of the text: the control's value, period [s], force drop [N].
fn line(c: &Cycle, control: Control, value: f64) -> String {
    format!(
        "{} = {value:.8e} {}  period {:.6e} s  force drop {:.6e} N  Delta_s {:.6e}  v {:.3e} .. {:.3e} µm/s  {}{}  #{}",
        control.name(),
        control.text_unit(),
        c.period_s,
        c.delta_s_n,
        c.delta_s,
        c.v_min_um_per_s,
        c.v_max_um_per_s,
        c.stable.word(),
        if c.user_point { "  (requested)" } else { "" },
        c.label
    )
}

/// Runs `cycles --param P` for a control other than the stiffness.
pub fn run(args: &CyclesArgs, control: Control) -> Result<(), Error> {
    let Some(to) = args.to else {
        return Err(InputError::Conflict(format!(
            "cycles --param {} needs --to VALUE (in {}): where the branch ends",
            control.name(),
            control.unit_in_words()
        ))
        .into());
    };
    if args.kappa_fraction.is_some() {
        return Err(InputError::Conflict(format!(
            "--kappa-fraction ends a branch in the stiffness; the branch in {} ends at --to",
            control.name()
        ))
        .into());
    }
    if args.lpc_curve {
        return Err(InputError::Conflict(
            "--lpc-curve continues folds of cycles in (kappa, nu) from a stiffness branch; \
             leave out --param (or --lpc-curve)"
                .into(),
        )
        .into());
    }
    let request = CyclesInControlRequest {
        control,
        to,
        at: asked_values(&args.at_kappa, &args.at, control)?,
        search: super::cycles::search_range(args)?,
        from_simulation: args.from_simulation,
        max_steps: args.max_steps,
        ntst: args.ntst,
        ntst_max: args.ntst_max,
        collocation: args.collocation.map(Into::into),
        from: super::cycles::restart_of(args),
    };
    let spec = args.scene.spec_for(request.from.is_some());
    let plan = Plan::new(&spec, &request)?;
    let setup = &plan.setup;
    let name = format!("-cycles-in-{}", control.name());
    args.output.create_dir()?;
    let csv_suffix = format!("{name}.csv");
    let outputs: Vec<String> = [
        ".csv",
        "-orbits.jsonl",
        "-amplitude.png",
        "-amplitude.svg",
        "-period.png",
        "-period.svg",
    ]
    .iter()
    .map(|end| format!("{name}{end}"))
    .collect();
    let outputs: Vec<&str> = outputs.iter().map(String::as_str).collect();
    let run = match &request.from {
        // The run restarted from, and the cycle: not the files of that run.
        Some(r) => format!("{}_restart-{}", plan.source_name(), r.index),
        None => setup.scene.name.clone(),
    };
    let stem = args.output.stem(&run, &args.scene, false, &outputs)?;
    let csv_path = with_suffix(&stem, &csv_suffix);
    let mut csv = create_file(&csv_path)?;
    let orbits_path = orbits_path(&with_suffix(&stem, &name));
    let orbits = create_file(&orbits_path)?;
    writeln!(
        csv,
        "# scene {}; cycles in {} [{}]; model at the start {} (column model: each row's)\n{}",
        setup.scene.name,
        control.name(),
        control.unit_in_words(),
        setup.choice.reason,
        header_of(&plan.header_record())?
    )?;
    if !args.json {
        println!("scene: {} — {}", setup.scene.name, setup.scene.description);
        println!("model: {}", setup.choice.reason);
        if let Some(start) = plan.describe_start() {
            println!("{start}");
        }
    }
    interrupt::catch_interrupts();
    let axis = plan.axis();
    let mut printer = Printer {
        csv,
        orbits,
        axis,
        text: !args.json,
    };
    let traced = plan.run(&mut printer);
    let mut csv = printer.csv;
    printer.orbits.finish()?;
    // A run that found no branch says so in its CSV (a later run replaces
    // it without --force).
    let mut result = match traced {
        Ok(t) => t,
        Err(e) => {
            writeln!(csv, "# incomplete: {e}")?;
            csv.finish()?;
            return Err(e);
        }
    };
    for (value, why) in result.undelivered() {
        writeln!(
            csv,
            "# requested {} = {} not delivered: {why}",
            control.name(),
            axis.in_unit(value, 15)
        )?;
    }
    if !result.complete {
        writeln!(csv, "# incomplete: {}", result.stop)?;
    }
    csv.finish()?;
    let figures = write_figures(&result, &axis, &with_suffix(&stem, &name))?;
    result.orbits_file = Some(orbits_path.display().to_string());
    result.files = figures
        .iter()
        .chain([&csv_path, &orbits_path])
        .map(|f| f.display().to_string())
        .collect();
    if args.json {
        println!(
            "{}",
            serde_json::to_string_pretty(&result).map_err(std::io::Error::other)?
        );
    } else {
        if let Some(c) = &result.critical {
            println!(
                "started at the Hopf point in {}: {} = {:.10e} {} ({})",
                control.name(),
                control.name(),
                c.value,
                control.text_unit(),
                c.criticality.name()
            );
        }
        println!("stopped: {}", result.stop);
        for (value, why) in result.undelivered() {
            println!(
                "requested {} = {value:.10e}{}: not delivered: {why}",
                control.name(),
                unit_after(control)
            );
        }
        for f in &result.files {
            println!("wrote {f}");
        }
    }
    result.status()
}

/// The figures of the branch `result` in the control of `axis`, named
/// after `stem`: whatever was computed is drawn, also when the branch
/// stopped short (then the title says so), with the switch to the inertial
/// model where there was one. Returns the files written.
fn write_figures(
    result: &CyclesInControl,
    axis: &Axis,
    stem: &Path,
) -> Result<Vec<PathBuf>, Error> {
    let control = axis.control;
    let points: Vec<(f64, &Cycle)> = result
        .along_branch
        .iter()
        .map(|&i| &result.cycles[i])
        .map(|c| (axis.value_of(c), c))
        .collect();
    if points.is_empty() {
        return Ok(Vec::new());
    }
    let cut = if result.complete {
        ""
    } else {
        " — stopped short (see the stop reason)"
    };
    let model = match &result.model_switch {
        Some(s) => format!(
            "quasi-static → inertial model at {} = {:.4e}{}",
            control.name(),
            s.value,
            unit_after(control)
        ),
        None => format!("{} model", result.model.name()),
    };
    control_figures(
        &format!(
            "Stick-slip cycles in {}, {} ({model}){cut}",
            control.name(),
            result.setup.label
        ),
        &match control.text_unit() {
            "" => control.name().to_string(),
            unit => format!("{} [{unit}]", control.name()),
        },
        &points,
        result.model_switch.as_ref().map(|s| s.value),
        stem,
    )
    .map_err(|e| Error::Output(std::io::Error::other(e.to_string())))
}

/// The observer of the command line: each cycle a CSV row at once and,
/// unless `--json`, a text line with the control in its unit.
struct Printer {
    csv: LineFile,
    /// One line per orbit, as `cycles` writes them.
    orbits: LineFile,
    axis: Axis,
    text: bool,
}

impl Observer for Printer {
    fn stop(&mut self, at: &dyn Fn() -> String) -> Option<Error> {
        interrupt::interrupted().then(|| interrupt::stopped(at()))
    }

    fn cycle(&mut self, cycle: &Cycle, found: &[CycleSpecialPoint]) -> Result<(), Error> {
        writeln!(self.csv, "{}", row(cycle)?)?;
        self.csv.flush()?;
        if self.text {
            let control = self.axis.control;
            println!("{}", line(cycle, control, self.axis.value_of(cycle)));
            for s in found {
                let v = self.axis.value_of(&s.cycle);
                println!("  {} at {}", s.kind.name(), line(&s.cycle, control, v));
            }
        }
        Ok(())
    }

    fn note(&mut self, note: Note) {
        super::cycles::print_note(note, self.text);
    }

    fn orbit(&mut self, orbit: &StoredOrbit) -> Result<(), Error> {
        orbit.write_line(&mut self.orbits)
    }
}
