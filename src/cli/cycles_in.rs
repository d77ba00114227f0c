//! `stickslip cycles --param P --to VALUE`: the cycle branch in a control
//! parameter other than the stiffness ([`cycles_in`]), as CSV, text and
//! JSON (no figures: those of `cycles` are drawn against the stiffness).

use super::cycles::CyclesArgs;
use super::files::with_suffix;
use super::{params_json, Setup};
use crate::analysis::control::{choose_along, cycles_in, Control, CyclesInRequest, CyclesStart};
use crate::analysis::cycles::{CycleRecord, CycleRequest, Leg};
use crate::analysis::model_choice::params_for;
use crate::analysis::orbit_inertia::InertiaWatch;
use crate::error::{Error, InputError};
use crate::params::Param;
use crate::records::branch::ParamValue;
use crate::records::csv::{header_of, row};
use crate::records::cycle::{Cycle, CycleSpecialPoint, LegStop};
use crate::records::hopf::Critical;
use crate::scene::Units;
use serde_json::json;
use std::io::Write;

/// The CSV column of the control in its unit, where no other column gives it.
fn control_column(control: Control) -> Option<&'static str> {
    match control {
        Control::V => Some("V_um_per_s"),
        Control::M => Some("M_kg"),
        Control::W => Some("W_N"),
        Control::Tau => Some("tau_s"),
        Control::K | Control::Dimensionless(_) => None,
    }
}

/// The `--at` values for `control`: every item `NAME=V1,V2,...` must name it.
fn asked(args: &CyclesArgs, control: Control) -> Result<Vec<f64>, InputError> {
    if !args.at_kappa.is_empty() {
        return Err(InputError::Conflict(format!(
            "--at-kappa asks for stiffnesses, and --param {} continues the cycles in {}: give \
             --at {}=V1,V2,... (in {})",
            control.name(),
            control.name(),
            control.name(),
            control.unit()
        )));
    }
    let mut out = Vec::new();
    for item in &args.at {
        let (name, values) = item.split_once('=').unwrap_or(("", item));
        if name.trim() != control.name() {
            return Err(InputError::Conflict(format!(
                "--at {item}: the branch is in {} (--param); give --at {}=V1,V2,... (in {})",
                control.name(),
                control.name(),
                control.unit()
            )));
        }
        for v in values.split(',') {
            out.push(v.trim().parse::<f64>().map_err(|_| InputError::Malformed {
                field: format!("--at {}", control.name()),
                value: v.to_string(),
                expected: format!("a number in {}", control.unit()),
            })?);
        }
    }
    Ok(out)
}

/// The cycle `c` as a record, in the units at its value of the control.
fn record_of(c: &CycleRecord, control: Control, param: Param, setup: &Setup) -> Cycle {
    let (units, params) = (&setup.scene.units, &setup.scene_params);
    let x = c.params[param as usize];
    let value = control.from_dimensionless(units, params, x);
    let at: Units = control.at(units, params, value).1;
    let mut d = Cycle::new(c, &at);
    d.continued = (!matches!(param, Param::Kappa | Param::M)).then_some(ParamValue {
        name: param.name(),
        value: x,
    });
    d.control = control_column(control).map(|name| ParamValue { name, value });
    d
}

/// The control's unit as the text writes it (`µm/s`; empty when dimensionless).
fn text_unit(control: Control) -> &'static str {
    match control.unit() {
        "um/s" => "µm/s",
        "1" => "",
        u => u,
    }
}

/// One line of the text: the control's value, period [s], force drop [N].
fn line(c: &Cycle, control: Control, value: f64) -> String {
    format!(
        "{} = {value:.8e} {}  period {:.6e} s  force drop {:.6e} N  Delta_s {:.6e}  v {:.3e} .. {:.3e} µm/s  {}{}",
        control.name(),
        text_unit(control),
        c.period_s,
        c.delta_s_n,
        c.delta_s,
        c.v_min_um_per_s,
        c.v_max_um_per_s,
        c.stable.word(),
        if c.user_point { "  (requested)" } else { "" }
    )
}

/// Runs `cycles --param P` for a control other than the stiffness.
pub fn run(args: &CyclesArgs, control: Control) -> Result<(), Error> {
    let Some(to) = args.to else {
        return Err(InputError::Conflict(format!(
            "cycles --param {} needs --to VALUE (in {}): where the branch ends",
            control.name(),
            control.unit()
        ))
        .into());
    };
    if args.lpc_curve {
        return Err(InputError::Conflict(
            "--lpc-curve continues folds of cycles in (kappa, nu) from a stiffness branch; \
             leave out --param (or --lpc-curve)"
                .into(),
        )
        .into());
    }
    let at = asked(args, control)?;
    let mut setup = args.scene.setup(|p| *p)?;
    let (units, scene_params) = (setup.scene.units, setup.scene_params);
    control.continued(&units)?;
    // The model is judged over the search range and --to, where the
    // inertia ratio is largest (the Hopf point lies in the search range).
    let search = super::cycles::search_range(args)?;
    let judged = search
        .or_else(|| control.default_range(&units, &scene_params, setup.scene.nu_range))
        .map_or((to, to), |(lo, hi)| (lo.min(to), hi.max(to)));
    setup.choice = choose_along(
        control,
        &units,
        &scene_params,
        Some(judged).filter(|(lo, _)| *lo > 0.0),
        args.scene.model.map(Into::into),
        args.scene.inertia_threshold,
    );
    let kind = setup.choice.kind;
    setup.params = params_for(kind, &scene_params);
    let req = CyclesInRequest {
        control,
        to,
        search,
        nu_range: setup.scene.nu_range,
        at: at.clone(),
        from_simulation: args.from_simulation,
        cycles: CycleRequest {
            kappa_min: 0.0,
            kappa_max: 0.0,
            max_steps: args.max_steps,
            ntst: args.ntst,
            at_kappa: Vec::new(),
            ntst_max: args.ntst_max,
            collocation: args.collocation.map(Into::into),
        },
    };
    let name = format!("-cycles-in-{}", control.name());
    args.output.create_dir()?;
    let csv_suffix = format!("{name}.csv");
    let stem = args.output.stem(
        &setup.scene.name,
        &args.scene,
        false,
        &[csv_suffix.as_str()],
    )?;
    let csv_path = with_suffix(&stem, &csv_suffix);
    let mut csv = crate::cli::files::create_file(&csv_path)?;
    let param = control.continued(&units)?;
    let named = Cycle {
        continued: (!matches!(param, Param::Kappa | Param::M)).then_some(ParamValue {
            name: param.name(),
            value: 0.0,
        }),
        control: control_column(control).map(|name| ParamValue { name, value: 0.0 }),
        ..Cycle::default()
    };
    writeln!(
        csv,
        "# scene {}; cycles in {} [{}]; model {}",
        setup.scene.name,
        control.name(),
        control.unit(),
        setup.choice.reason
    )?;
    writeln!(csv, "{}", header_of(&named)?)?;
    if !args.json {
        println!("scene: {} — {}", setup.scene.name, setup.scene.description);
        println!("model: {}", setup.choice.reason);
    }
    let watch = InertiaWatch::new(
        &scene_params,
        args.scene.inertia_threshold,
        args.scene.model.is_none(),
    );
    let mut details: Vec<Cycle> = Vec::new();
    let mut records: Vec<CycleRecord> = Vec::new();
    let mut specials: Vec<CycleSpecialPoint> = Vec::new();
    let traced = cycles_in(kind, &scene_params, &units, &req, &watch, |c| {
        for rec in c.user.iter().chain([c]) {
            let d = record_of(rec, control, param, &setup);
            writeln!(csv, "{}", row(&d)?)?;
            csv.flush()?;
            let value =
                control.from_dimensionless(&units, &scene_params, rec.params[param as usize]);
            if !args.json {
                println!("{}", line(&d, control, value));
            }
            for (kind, l) in rec.special_points() {
                let cycle = record_of(l, control, param, &setup);
                if !args.json {
                    let v =
                        control.from_dimensionless(&units, &scene_params, l.params[param as usize]);
                    println!("  {} at {}", kind.name(), line(&cycle, control, v));
                }
                specials.push(CycleSpecialPoint { kind, cycle });
            }
            details.push(d);
            records.push(rec.clone());
        }
        Ok(())
    });
    // A run that found no branch says so in its CSV (a later run replaces
    // it without --force).
    let traced = match traced {
        Ok(t) => t,
        Err(e) => {
            writeln!(csv, "# incomplete: {e}")?;
            csv.finish()?;
            return Err(e);
        }
    };
    let leg_stops: Vec<LegStop> = traced
        .legs
        .iter()
        .map(|(leg, o)| LegStop::new(Some(*leg), o, args.max_steps))
        .collect();
    let value_of = |x: f64| control.from_dimensionless(&units, &scene_params, x);
    let delivered = traced.delivered(&records);
    let mut stop: Vec<String> = leg_stops
        .iter()
        .map(|l| match l.leg {
            Some(Leg::Up) => format!("toward larger {}: {}", param.name(), l.message),
            Some(Leg::Down) => format!("toward smaller {}: {}", param.name(), l.message),
            _ => l.message.clone(),
        })
        .collect();
    let missing = delivered.iter().filter(|d| !**d).count();
    if missing > 0 {
        stop.push(format!(
            "{missing} of the {} requested values not delivered: no cycle of the branch there \
             (it spans {} = {:.6e} .. {:.6e} {}; none may exist at the others)",
            at.len(),
            control.name(),
            value_of(traced.bounds.0).min(value_of(traced.bounds.1)),
            value_of(traced.bounds.0).max(value_of(traced.bounds.1)),
            control.unit()
        ));
    }
    let complete = leg_stops.iter().all(LegStop::complete) && missing == 0;
    let stop = stop.join("; ");
    if !complete {
        writeln!(csv, "# incomplete: {stop}")?;
    }
    csv.finish()?;
    let (start, critical) = match &traced.start {
        CyclesStart::Hopf(o) => {
            let scene_value = control.value(&units, &scene_params);
            ("hopf", Some(Critical::new(o, scene_value)))
        }
        CyclesStart::Simulation => ("simulation", None),
    };
    if args.json {
        let v = json!({
            "scene": setup.scene.name,
            "model": kind,
            "model_reason": setup.choice.reason,
            "params": params_json(&setup.params),
            "control": {"param": control.name(), "unit": control.unit(), "to": to,
                        "continued": param.name()},
            "start": start,
            "critical": critical,
            "units": {"D0_um": units.d0 * 1e6, "V0_um_per_s": units.velocity_um_s(1.0)},
            "cycles": details,
            "special_points": specials,
            "requested_points": at.iter().zip(&delivered).map(|(v, d)| json!({
                "value": v, "unit": control.unit(), "delivered": d})).collect::<Vec<_>>(),
            "complete": complete,
            "stop": stop,
            "leg_stops": leg_stops,
            "files": [csv_path.display().to_string()],
        });
        println!(
            "{}",
            serde_json::to_string_pretty(&v).map_err(std::io::Error::other)?
        );
    } else {
        if let Some(c) = &critical {
            println!(
                "started at the Hopf point in {}: {} = {:.10e} {} ({})",
                control.name(),
                control.name(),
                c.value,
                text_unit(control),
                c.criticality.name()
            );
        }
        println!("stopped: {stop}");
        println!("wrote {}", csv_path.display());
    }
    let first_error = traced.legs.into_iter().find_map(|(_, o)| o.err());
    match first_error {
        Some(e @ (Error::Interrupted(_) | Error::Output(_))) => Err(e),
        Some(e) if details.is_empty() => Err(e),
        _ if !complete => Err(Error::Partial(format!(
            "{} cycles written; stopped: {stop}",
            details.len()
        ))),
        _ => Ok(()),
    }
}
