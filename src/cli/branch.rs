//! `stickslip branch`: steady sliding continued in `kappa` or `nu`, with the
//! eigenvalues at every point and the located bifurcations, as text (in
//! physical or dimensionless units), CSV or JSON, each point one
//! [`BranchRow`]. Text and CSV rows are written as they are computed.

use super::csv::{self, header_of};
use super::records::branch::{BranchRow, ParamValue};
use super::{describe_params, params_json, SceneArgs, Setup, TextUnits};
use crate::analysis::branch::{trace, BranchRequest};
use crate::analysis::control::{choose_along, Control};
use crate::analysis::hopf::{find_hopf, stable_stiffness, HopfOutcome};
use crate::analysis::model_choice::params_for;
use crate::error::{Error, InputError};
use crate::model::DrivenBlock;
use crate::model::ModelKind;
use crate::overrides::Overrides;
use crate::params::Param;
use clap::Args;
use serde_json::json;
use std::io::Write;

/// The options of `stickslip branch`.
#[derive(Args, Debug)]
pub struct BranchArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// The continuation parameter: kappa or nu, or a control parameter in
    /// its unit, K [N/m], V [um/s], M [kg], tau [s], or m, A, B, mu2,
    /// theta_c (the rows are in the dimensionless parameter it moves: K in
    /// kappa, V in nu, M in m, or in kappa when W = M g).
    #[arg(long, value_name = "P")]
    pub param: String,
    #[arg(allow_hyphen_values = true)]
    /// Start value, in the unit of --param (default: kappa, K — a stable stiffness; nu, V — the
    /// bottom of the scene's velocity range; others — the scene's value).
    #[arg(long)]
    pub from: Option<f64>,
    #[arg(allow_hyphen_values = true)]
    /// End value, in the unit of --param (default: kappa, K — 1e-3 of the start; nu, V — the top
    /// of the scene's velocity range; others — 1e3 times the start, the stiffness 1e-3).
    #[arg(long)]
    pub to: Option<f64>,
    /// Largest number of continuation steps. A branch that ends before
    /// `--to` (this limit, or a turn) keeps its rows and exits with status 4
    /// (partial).
    #[arg(long, default_value_t = 2000)]
    pub max_steps: usize,
    /// Comma-separated values instead of an aligned table: a `# scene`
    /// comment line, then the parameter, the state, the eigenvalues, the
    /// bifurcation, and the point in physical units.
    #[arg(long, conflicts_with = "json")]
    pub csv: bool,
    /// Print one JSON object instead of text: the points (the CSV's rows)
    /// under `points`, `complete` and `stop`.
    #[arg(long)]
    pub json: bool,
    /// Units of the text: physical (K/W in 1/m, V in µm/s, theta in s,
    /// eigenvalues in 1/s, frequencies in Hz) or dimensionless (kappa or nu,
    /// v/V0, theta and eigenvalues in D0/V0 and V0/D0, omega). The CSV and
    /// the JSON carry both.
    #[arg(long, value_enum, default_value_t = TextUnits::Physical)]
    pub units: TextUnits,
}

/// Runs the command.
pub fn run(args: &BranchArgs) -> Result<(), Error> {
    let control = Control::parse(&args.param, "--param")?;
    let overrides = Overrides::parse(&args.scene.set)?;
    let scene = crate::scene::load_with(&args.scene.scene, &overrides.physical())?;
    let mut scene_params = scene.params;
    overrides.apply_dimensionless(&mut scene_params)?;
    let param = control.continued(&scene.units)?;
    control.check_form(&scene_params)?;
    let (nu_lo, nu_hi) = scene.nu_range;
    // kappa and nu as always (the scene's velocity range as given in the
    // scene); other controls in their unit, converted.
    let (arg_from, arg_to) = match control {
        Control::Dimensionless(Param::Kappa | Param::Nu) => (args.from, args.to),
        _ => control.branch_range(
            &scene.units,
            &scene_params,
            scene.nu_range,
            (args.from, args.to),
        )?,
    };
    // For a velocity branch, inertia is judged at the fastest velocity of the range.
    let top = arg_to.unwrap_or(nu_hi).max(arg_from.unwrap_or(nu_lo));
    let mut setup = args.scene.setup(|p| {
        let mut q = *p;
        if param == Param::Nu {
            q.nu = top;
        }
        if param == Param::M {
            q.m = arg_to.unwrap_or(q.m).max(arg_from.unwrap_or(q.m));
        }
        q
    })?;
    if control.moves_inertia(&setup.scene.units) && setup.choice.kind == ModelKind::QuasiStatic {
        if args.scene.model.is_some() {
            return Err(InputError::Conflict(format!(
                "branch --param {} moves the inertia m, which the quasi-static model drops; \
                 leave out --model quasi-static",
                control.name()
            ))
            .into());
        }
        setup.choice = choose_along(
            control,
            &setup.scene.units,
            &setup.scene_params,
            None,
            None,
            args.scene.inertia_threshold,
        );
        setup.params = params_for(setup.choice.kind, &setup.scene_params);
    }
    let kind = setup.choice.kind;
    let from = match (arg_from, param) {
        (Some(v), _) => v,
        (None, Param::Kappa) => {
            stable_stiffness(&DrivenBlock::new(kind, &setup.params), kind, &setup.params)?
        }
        (None, _) => nu_lo,
    };
    let to = match (arg_to, param) {
        (Some(v), _) => v,
        (None, Param::Kappa) => 1e-3 * from,
        (None, _) => nu_hi,
    };
    for (name, v) in [("--from", from), ("--to", to)] {
        // kappa = 0 is no end point: without a spring steady sliding has a
        // zero eigenvalue (a0 = kappa nu in the characteristic polynomial).
        if !(v.is_finite() && v > 0.0) {
            return Err(InputError::out_of_range(
                name,
                v,
                "a finite value > 0 (kappa = 0 has no isolated steady state: the spring holds \
                 nothing; for kappa use e.g. 1e-3 of the start, as the default --to does)",
            )
            .into());
        }
    }
    if param != Param::Kappa && setup.params.kappa <= 0.0 {
        return Err(no_stiffness(&setup, control).into());
    }
    if from == to {
        return Err(InputError::Conflict(format!(
            "--from and --to are equal ({from}); give a range"
        ))
        .into());
    }
    let format = match (args.json, args.csv) {
        (true, _) => Format::Json,
        (false, true) => Format::Csv,
        (false, false) => Format::Text {
            units: args.units,
            rate: match args.units {
                TextUnits::Physical => setup.scene.units.v0 / setup.scene.units.d0,
                TextUnits::Dimensionless => 1.0,
            },
        },
    };
    let mut out = std::io::stdout().lock();
    write_head(&mut out, format, &setup, param, (from, to))?;
    if matches!(format, Format::Text { .. }) && control.name() != param.name() {
        let in_unit =
            |x: f64| control.from_dimensionless(&setup.scene.units, &setup.scene_params, x);
        writeln!(
            out,
            "--param {}: {} from {:.6e} to {:.6e} {} (the rows are in {})",
            control.name(),
            control.name(),
            in_unit(from),
            in_unit(to),
            control.unit(),
            param.name()
        )?;
    }
    let req = BranchRequest {
        param,
        from,
        to,
        max_steps: args.max_steps,
    };
    let (params, scene_params, scene_units) = (setup.params, setup.scene_params, setup.scene.units);
    // The units at a point: M and the load follow a branch in M.
    let units = |x: f64| {
        let value = control.from_dimensionless(&scene_units, &scene_params, x);
        control.at(&scene_units, &scene_params, value).1
    };
    let mut points = Vec::new();
    let traced = trace(kind, &params, &req, |point| {
        for e in &point.events {
            let (event, e) = (&e.kind, &e.point);
            let at = params.with_vec(&e.p);
            let row = BranchRow::new(
                kind,
                &at,
                param,
                &e.x,
                &e.eigenvalues,
                Some(event),
                &units(at.get(param)),
            );
            present(&mut out, format, row, &mut points)?;
        }
        let at = params.with_vec(&point.p);
        let row = BranchRow::new(
            kind,
            &at,
            param,
            &point.x,
            &point.eigenvalues,
            None,
            &units(at.get(param)),
        );
        present(&mut out, format, row, &mut points)
    });
    let stop = match &traced {
        Ok(None) => None,
        Ok(Some(last)) => Some(format!(
            "the branch ended at {} = {last:.10e}, before --to {to:.6e}: the step limit \
             (--max-steps {}) or a turn of the branch; raise --max-steps or check the range",
            param.name(),
            args.max_steps
        )),
        Err(e) => Some(e.to_string()),
    };
    if matches!(format, Format::Json) {
        print_json(&mut out, &setup, &req, control, &points, stop.as_deref())?;
    }
    // The rows are kept (written, or in the JSON); a failure is then
    // reported as it is, a branch short of `--to` as partial.
    match (traced?, stop) {
        (Some(_), Some(why)) => Err(Error::Partial(why)),
        _ => Ok(()),
    }
}

/// The JSON object of the branch `req` of `setup`: the run, its `points`,
/// and whether it reached `--to` (`complete`; else why not, `stop`).
fn print_json(
    out: &mut impl Write,
    setup: &Setup,
    req: &BranchRequest,
    control: Control,
    points: &[BranchRow],
    stop: Option<&str>,
) -> Result<(), Error> {
    let units = setup.scene.units;
    let in_unit = |x: f64| control.from_dimensionless(&units, &setup.scene_params, x);
    let mut v = json!({
        "scene": setup.scene.name,
        "model": setup.choice.kind,
        "model_reason": setup.choice.reason,
        "params": params_json(&setup.params),
        "param": req.param.name(),
        "from": req.from,
        "to": req.to,
        "units": {"D0_um": units.d0 * 1e6, "V0_um_per_s": units.velocity_um_s(1.0)},
        "points": points,
        "complete": stop.is_none(),
        "stop": stop,
    });
    // The control of --param when it is not the continued parameter itself.
    if control.name() != req.param.name() {
        v["control"] = json!({
            "param": control.name(),
            "unit": control.unit(),
            "from": in_unit(req.from),
            "to": in_unit(req.to),
        });
    }
    let text = serde_json::to_string_pretty(&v).map_err(std::io::Error::other)?;
    writeln!(out, "{text}")?;
    Ok(())
}

/// How the points are presented: text lines in some units, CSV rows, or
/// entries of one JSON object printed at the end.
#[derive(Clone, Copy, Debug)]
enum Format {
    /// Text in `units`, the eigenvalues in units of `1/rate` (1/s or `V0/D0`).
    Text {
        units: TextUnits,
        rate: f64,
    },
    Csv,
    Json,
}

/// What comes before the points: the CSV's comment and header lines, or the
/// text's scene, model, range and column titles (nothing for JSON).
fn write_head(
    out: &mut impl Write,
    format: Format,
    setup: &Setup,
    param: Param,
    (from, to): (f64, f64),
) -> Result<(), Error> {
    let units = match format {
        Format::Json => return Ok(()),
        Format::Csv => {
            writeln!(
                out,
                "# scene {}; model {}; {}",
                setup.scene.name,
                setup.choice.kind.name(),
                setup.choice.reason
            )?;
            let named = BranchRow {
                param: ParamValue {
                    name: param.name(),
                    value: 0.0,
                },
                ..BranchRow::default()
            };
            writeln!(out, "{}", header_of(&named)?)?;
            return Ok(());
        }
        Format::Text { units, .. } => units,
    };
    writeln!(
        out,
        "scene: {} — {}",
        setup.scene.name, setup.scene.description
    )?;
    writeln!(out, "model: {}", setup.choice.reason)?;
    writeln!(out, "parameters: {}", describe_params(&setup.params))?;
    let u = &setup.scene.units;
    let range = match (units, param) {
        (TextUnits::Dimensionless, _) => format!("{} from {from:.6e} to {to:.6e}", param.name()),
        (TextUnits::Physical, Param::Nu) => format!(
            "V from {:.6e} µm/s to {:.6e} µm/s",
            u.velocity_um_s(from),
            u.velocity_um_s(to)
        ),
        (TextUnits::Physical, _) => format!(
            "K/W from {:.6e} 1/m to {:.6e} 1/m",
            u.k_over_w(from),
            u.k_over_w(to)
        ),
    };
    writeln!(out, "continuing steady sliding in {range}")?;
    let titles = match units {
        TextUnits::Physical => [
            "K/W [1/m]",
            "V [µm/s]",
            "s",
            "theta [s]",
            "eigenvalues [1/s]",
        ],
        TextUnits::Dimensionless => [param.name(), "s", "v", "theta", "eigenvalues"],
    };
    writeln!(
        out,
        "{:>14} {:>14} {:>12} {:>12} {:>3}  {}",
        titles[0], titles[1], titles[2], titles[3], "#u", titles[4]
    )?;
    Ok(())
}

/// Presents one point: a text line or a CSV row at once, a JSON entry kept.
fn present(
    out: &mut impl Write,
    format: Format,
    row: BranchRow,
    points: &mut Vec<BranchRow>,
) -> Result<(), Error> {
    match format {
        Format::Json => points.push(row),
        Format::Csv => writeln!(out, "{}", csv::row(&row)?)?,
        Format::Text { units, rate } => writeln!(out, "{}", text_line(&row, units, rate))?,
    }
    Ok(())
}

/// A point as a line of the text: the parameter, the state, `#u`, the
/// eigenvalues and the bifurcation located there, in `units` (physical:
/// K/W, V, theta in s, the frequency in Hz), the eigenvalues times `rate`.
fn text_line(r: &BranchRow, units: TextUnits, rate: f64) -> String {
    let (columns, tag) = match units {
        TextUnits::Physical => (
            format!(
                "{:>14.8e} {:>14.8e} {:>12.6e} {:>12.6e}",
                r.k_over_w_per_m, r.v_um_per_s, r.s, r.theta_s
            ),
            r.frequency_hz.map(|f| format!("f = {f:.10e} Hz")),
        ),
        TextUnits::Dimensionless => (
            format!(
                "{:>14.8e} {:>14.8e} {:>12.6e} {:>12.6e}",
                r.param.value, r.s, r.v, r.theta
            ),
            r.omega.map(|w| format!("omega = {w:.10e}")),
        ),
    };
    let evs: Vec<String> = r
        .eigenvalues
        .0
        .iter()
        .flatten()
        .map(|l| format!("{:+.4e}{:+.4e}i", rate * l.re, rate * l.im))
        .collect();
    let tag = match (r.event, tag) {
        (Some(e), Some(t)) => format!("  <- {} ({t})", e.name().to_uppercase()),
        (Some(e), None) => format!("  <- {}", e.name().to_uppercase()),
        (None, _) => String::new(),
    };
    format!("{columns} {:>3}  {}{tag}", r.n_unstable, evs.join("  "))
}

/// The refusal of a velocity branch without a stiffness, with `kappa_c` at
/// the scene's velocity (located as by `stickslip hopf`) as a hint.
fn no_stiffness(setup: &Setup, control: Control) -> InputError {
    let p = &setup.params;
    let hint = match find_hopf(setup.choice.kind, p) {
        Ok(HopfOutcome::Found(h)) => format!(
            "; at the scene's velocity nu = {:.6e} steady sliding is stable above kappa_c = {:.6e} \
             ({} model, as for this branch), e.g. --set kappa={:.4e} crosses the onset on the branch",
            p.nu,
            h.kappa_c,
            setup.choice.kind.name(),
            h.kappa_c
        ),
        Ok(HopfOutcome::StableForAllStiffness { .. }) => format!(
            "; at the scene's velocity nu = {:.6e} steady sliding is stable for every stiffness",
            p.nu
        ),
        Err(_) => String::new(),
    };
    InputError::Conflict(format!(
        "branch --param {} needs a stiffness: kappa = 0 here (the scene gives no K), and without a \
         spring steady sliding has a zero eigenvalue at every velocity (no isolated equilibrium to \
         continue); give --set kappa=... (kappa = K D0/W){hint}",
        control.name()
    ))
}
