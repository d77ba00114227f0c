//! `stickslip branch`: steady sliding continued in `kappa` or `nu`, with the
//! eigenvalues at every point and the located bifurcations, as text (in
//! physical or dimensionless units), CSV or JSON, each point one
//! [`BranchRow`]. Text and CSV rows are written as they are computed.

use super::{describe_params, from_value, SceneArgs, Setup, TextUnits};
use crate::analysis::control::Control;
use crate::error::{Error, InputError};
use crate::jobs::branch::{BranchRequest, BranchRestart, Observer, Plan};
use crate::jobs::restart::Restart;
use crate::params::Param;
use crate::records::branch::{BranchRow, ParamValue};
use crate::records::csv::{self, header_of};
use clap::Args;
use std::io::Write;

/// The options of `stickslip branch`.
#[derive(Args, Debug)]
pub struct BranchArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// The continuation parameter: kappa or nu, or a control parameter in
    /// its unit, K (N/m), V (µm/s), M (kg), tau (s), eta (s/m), or m, A, B, mu2,
    /// theta_c, mu_vv, mu_vphi, eta_d (the rows are in the dimensionless parameter it moves: K in
    /// kappa, V in nu, M in m, or in kappa when W = M g). With --from
    /// FILE.json --index N: default the file's. Adhesive scenes: V (or nu) only, over the
    /// scene's V_range.
    #[arg(long, value_name = "P", required_unless_present = "index")]
    pub param: Option<String>,
    #[arg(allow_hyphen_values = true)]
    /// Start value, in the unit of --param (default: kappa, K — a stable stiffness; nu, V — the
    /// bottom of the scene's velocity range; others — the scene's value). With --index N: the
    /// JSON that `branch --json` printed (saved to a file), to continue from its point labelled N
    /// with the file's scene, overrides and model (docs/index.md, "Restart").
    #[arg(long, value_name = "VALUE|FILE.json")]
    pub from: Option<String>,
    /// With --from FILE.json: the label of the point to continue from
    /// (`label` in the JSON and the CSV, #N in the text).
    #[arg(long, value_name = "N", requires = "from", value_parser = super::label)]
    pub index: Option<usize>,
    #[arg(allow_hyphen_values = true)]
    /// End value, in the unit of --param (default: kappa, K — 1e-3 of the start; nu, V — the top
    /// of the scene's velocity range; others — 1e3 times the start, the stiffness 1e-3).
    #[arg(long)]
    pub to: Option<f64>,
    /// Largest number of continuation steps. A branch that ends before
    /// `--to` (this limit, or a turn) keeps its rows and exits with status 4
    /// (partial). Adhesive scenes: refused (their branch samples a grid in V).
    #[arg(long, default_value_t = 2000)]
    pub max_steps: usize,
    /// Comma-separated values instead of an aligned table: a `# scene`
    /// comment line, then the parameter, the state, the eigenvalues, the
    /// bifurcation, and the point in physical units. Adhesive scenes: V in µm/s, the steady
    /// force in N, n, the leading eigenvalue's real part, stable, then nu, s, dF_ss/du; the
    /// Hopf points as `# hopf` lines.
    #[arg(long, conflicts_with = "json")]
    pub csv: bool,
    /// Print one JSON object instead of text: the points (the CSV's rows)
    /// under `points`, `complete` and `stop`.
    #[arg(long)]
    pub json: bool,
    /// Units of the text: physical (K/W in 1/m, V in µm/s, theta in s,
    /// eigenvalues in 1/s, frequencies in Hz) or dimensionless (kappa or nu,
    /// v/V0, theta and eigenvalues in D0/V0 and V0/D0, omega). The CSV and
    /// the JSON carry both. Adhesive scenes: refused (their text gives both).
    #[arg(long, value_enum, default_value_t = TextUnits::Physical)]
    pub units: TextUnits,
}

/// Runs the command.
pub fn run(args: &BranchArgs) -> Result<(), Error> {
    let in_velocity = matches!(args.param.as_deref(), Some("V" | "nu"));
    let unused = [
        (
            "--param (only V or nu)",
            args.param.is_some() && !in_velocity,
        ),
        ("--from", args.from.is_some()),
        ("--to", args.to.is_some()),
        ("--max-steps", args.max_steps != 2000),
        ("--units", args.units != TextUnits::Physical),
    ];
    if let Some(setup) =
        super::adhesive::adhesive_setup(&args.scene, &unused, super::adhesive::Judged::OverRange)?
    {
        return super::adhesive::branch(setup, args.json, args.csv);
    }
    let param = args
        .param
        .as_deref()
        .map(|p| Control::parse(p, "--param"))
        .transpose()?;
    let plan =
        match (args.index, param) {
            (Some(index), _) => Plan::restart(
                &args.scene.given(),
                &BranchRestart {
                    from: Restart {
                        file: args.from.clone().unwrap_or_default().into(),
                        index,
                    },
                    param,
                    to: args.to,
                    max_steps: args.max_steps,
                },
            )?,
            (None, Some(param)) => Plan::new(
                &args.scene.spec(),
                &BranchRequest {
                    param,
                    from: args
                        .from
                        .as_deref()
                        .map(|t| from_value(t, "a point of `branch --json` to continue from"))
                        .transpose()?,
                    to: args.to,
                    max_steps: args.max_steps,
                },
            )?,
            // clap requires --param without --index.
            (None, None) => return Err(InputError::Conflict(
                "give --param P (or --from FILE.json --index N to continue from a written point)"
                    .into(),
            )
            .into()),
        };
    let (setup, range) = (&plan.setup, &plan.range);
    let format = match (args.json, args.csv) {
        (true, _) => Format::Json,
        (false, true) => Format::Csv,
        (false, false) => Format::Text {
            units: args.units,
            param: range.param,
            rate: match args.units {
                TextUnits::Physical => setup.scene.units.v0 / setup.scene.units.d0,
                TextUnits::Dimensionless => 1.0,
            },
        },
    };
    let mut out = std::io::stdout().lock();
    if let (Some(r), Format::Text { .. }) = (&plan.restarted_from, format) {
        writeln!(
            out,
            "continuing from point #{} of {} ({} model, {} = {:.10e})",
            r.label,
            r.file,
            r.model.name(),
            range.param.name(),
            range.from
        )?;
    }
    write_head(&mut out, format, setup, range.param, (range.from, range.to))?;
    if let Format::Text { units, param, .. } = format {
        // The column the rows give the continued parameter in.
        let column = match units {
            TextUnits::Physical => physical_leading(param)[0].title(param),
            TextUnits::Dimensionless => param.name(),
        };
        if plan.control.name() != param.name() && !column.starts_with(plan.control.name()) {
            let (from, to) = plan.control_range();
            writeln!(
                out,
                "--param {}: {} from {from:.6e} to {to:.6e} {} (the rows are in {column})",
                plan.control.name(),
                plan.control.name(),
                plan.control.unit_in_words(),
            )?;
        }
    }
    let mut branch = plan.run(&mut Printer {
        out: &mut out,
        format,
    });
    if matches!(format, Format::Json) {
        let text = serde_json::to_string_pretty(&branch).map_err(std::io::Error::other)?;
        writeln!(out, "{text}")?;
    }
    // The rows are kept (written, or in the JSON); a failure is then
    // reported as it is, a branch short of `--to` as partial.
    branch.status()
}

/// The observer of the command line: a text line or a CSV row per point at
/// once (JSON: the whole branch at the end).
struct Printer<'a, W: Write> {
    out: &'a mut W,
    format: Format,
}

impl<W: Write> Observer for Printer<'_, W> {
    fn point(&mut self, row: &BranchRow) -> Result<(), Error> {
        match self.format {
            Format::Json => {}
            Format::Csv => writeln!(self.out, "{}", csv::row(row)?)?,
            Format::Text { units, param, rate } => {
                writeln!(self.out, "{}", text_line(row, units, param, rate))?
            }
        }
        Ok(())
    }
}

/// How the points are presented: text lines in some units, CSV rows, or
/// entries of one JSON object printed at the end.
#[derive(Clone, Copy, Debug)]
enum Format {
    /// Text in `units` for a branch in `param`, the eigenvalues in units of
    /// `1/rate` (1/s or `V0/D0`).
    Text {
        units: TextUnits,
        param: Param,
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
        (TextUnits::Physical, Param::Nu) => format!(
            "V from {:.6e} µm/s to {:.6e} µm/s",
            u.velocity_um_s(from),
            u.velocity_um_s(to)
        ),
        (TextUnits::Physical, Param::Kappa) => format!(
            "K/W from {:.6e} 1/m to {:.6e} 1/m",
            u.k_over_w(from),
            u.k_over_w(to)
        ),
        _ => format!("{} from {from:.6e} to {to:.6e}", param.name()),
    };
    writeln!(out, "continuing steady sliding in {range}")?;
    let titles = match units {
        TextUnits::Physical => {
            let [first, second] = physical_leading(param).map(|c| c.title(param));
            [first, second, "s", "age [s]", "eigenvalues [1/s]"]
        }
        TextUnits::Dimensionless => [param.name(), "s", "v", "theta", "eigenvalues"],
    };
    writeln!(
        out,
        "{:>14} {:>14} {:>12} {:>12} {:>3}  {}",
        titles[0], titles[1], titles[2], titles[3], "#u", titles[4]
    )?;
    Ok(())
}

/// A leading column of the physical text: the stiffness over the load,
/// the driving velocity, or the continued parameter itself (dimensionless,
/// as in the JSON rows).
#[derive(Clone, Copy)]
enum Leading {
    StiffnessOverLoad,
    Velocity,
    Param,
}

impl Leading {
    fn title(self, param: Param) -> &'static str {
        match self {
            Leading::StiffnessOverLoad => "K/W [1/m]",
            Leading::Velocity => "V [µm/s]",
            Leading::Param => param.name(),
        }
    }

    fn value(self, r: &BranchRow) -> f64 {
        match self {
            Leading::StiffnessOverLoad => r.k_over_w_per_m,
            Leading::Velocity => r.v_um_per_s,
            Leading::Param => r.param.value,
        }
    }
}

/// The two leading columns of the physical text for a branch in `param`:
/// the one it moves first (K/W for `kappa`, V for `nu`, else the
/// parameter), then the driving velocity (the stiffness for a branch in V).
fn physical_leading(param: Param) -> [Leading; 2] {
    match param {
        Param::Kappa => [Leading::StiffnessOverLoad, Leading::Velocity],
        Param::Nu => [Leading::Velocity, Leading::StiffnessOverLoad],
        _ => [Leading::Param, Leading::Velocity],
    }
}

/// A point as a line of the text: the parameter, the state, `#u`, the
/// eigenvalues and the bifurcation located there, in `units` (physical:
/// the leading columns of [`physical_leading`], theta in s, the frequency
/// in Hz), the eigenvalues times `rate`.
fn text_line(r: &BranchRow, units: TextUnits, param: Param, rate: f64) -> String {
    let (columns, tag) = match units {
        TextUnits::Physical => (
            {
                let [first, second] = physical_leading(param).map(|c| c.value(r));
                format!(
                    "{first:>14.8e} {second:>14.8e} {:>12.6e} {:>12.6e}",
                    r.s, r.theta_s
                )
            },
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
    format!(
        "{columns} {:>3}  {}{tag}  #{}",
        r.n_unstable,
        evs.join("  "),
        r.label
    )
}
