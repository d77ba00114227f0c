//! `diagram --x P --y Q`: the stability diagram in a pair of control
//! parameters ([`crate::analysis::axes`]); writes its JSON, CSV and figures.

use super::super::significant;
use super::DiagramArgs;
use crate::analysis::axes::Axes;
use crate::error::{Error, InputError};
use crate::file_names::with_suffix;
use crate::jobs::diagram::DiagramRequest;
use crate::jobs::{self, SceneSpec};
use crate::plot::axes::axes_figure;
use serde_json::json;
use std::time::Instant;

/// The options of a diagram in a pair of control parameters.
#[derive(clap::Args, Clone, Debug, Default)]
pub struct AxesArgs {
    /// x axis: the control parameter varied along the curve, in its unit
    /// (K, V, M, W, tau, kappa, nu, m, A, B, mu2, theta_c, mu_vv, mu_vphi, eta_d); default V.
    #[arg(long)]
    pub x: Option<String>,
    /// y axis: the control parameter whose critical value is plotted;
    /// default K with --x (without --x and --y: K/M or K/W, as always).
    #[arg(long)]
    pub y: Option<String>,
    /// Range of the x parameter as LO:HI in its unit (with --x/--y).
    #[arg(long, value_name = "LO:HI")]
    pub x_range: Option<String>,
    /// Bounds of the y parameter as LO:HI in its unit (with --x/--y).
    #[arg(long, value_name = "LO:HI")]
    pub y_range: Option<String>,
}

impl AxesArgs {
    /// The pair `--x`, `--y` name; `None` for the default diagram.
    pub fn parse(&self) -> Result<Option<Axes>, InputError> {
        let axes = Axes::parse(self.x.as_deref(), self.y.as_deref())?;
        let ranges = [("--x-range", &self.x_range), ("--y-range", &self.y_range)];
        if let (None, Some((field, _))) = (axes, ranges.iter().find(|(_, r)| r.is_some())) {
            return Err(InputError::Conflict(format!(
                "{field} is the range of a pair --x P --y Q; without them the diagram is in \
                 (V, K) over --nu-range"
            )));
        }
        Ok(axes)
    }
}

/// `LO:HI` of the option `field`, both finite and positive, `LO < HI`;
/// `hint` ends the message of a malformed one.
pub(super) fn parse_lohi(field: &str, text: &str, hint: &str) -> Result<(f64, f64), InputError> {
    let bad = || InputError::Malformed {
        field: field.into(),
        value: text.into(),
        expected: format!("LO:HI with 0 < LO < HI, {hint}"),
    };
    let (a, b) = text.split_once(':').ok_or_else(bad)?;
    let (lo, hi): (f64, f64) = (
        a.trim().parse().map_err(|_| bad())?,
        b.trim().parse().map_err(|_| bad())?,
    );
    if !(lo.is_finite() && hi.is_finite() && lo > 0.0 && hi > lo) {
        return Err(bad());
    }
    Ok((lo, hi))
}

/// Runs `diagram` with `--x`/`--y` for every scene named, one after another.
pub(super) fn run(args: &DiagramArgs, axes: Axes) -> Result<(), Error> {
    let x_range = args
        .axes
        .x_range
        .as_deref()
        .map(|t| parse_lohi("--x-range", t, "in the axis parameter's unit"))
        .transpose()?;
    let y_range = args
        .axes
        .y_range
        .as_deref()
        .map(|t| parse_lohi("--y-range", t, "in the axis parameter's unit"))
        .transpose()?;
    let nu_range = args
        .nu_range
        .as_deref()
        .map(super::parse_range)
        .transpose()?;
    let names: Vec<&str> = args
        .scene
        .scene_name()
        .split(',')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .collect();
    let pair = format!("-{}-vs-{}", axes.y.name(), axes.x.name());
    let outputs: Vec<String> = ["-diagram", "-hopf-curve", "-stability", "-stability"]
        .iter()
        .zip([".json", ".csv", ".png", ".svg"])
        .map(|(a, b)| format!("{a}{pair}{b}"))
        .collect();
    let outputs: Vec<&str> = outputs.iter().map(String::as_str).collect();
    args.output.create_dir()?;
    let several = names.len() > 1;
    let (mut all, mut partial) = (Vec::new(), Vec::new());
    for name in names {
        let t0 = Instant::now();
        let spec = SceneSpec {
            scene: name.to_string(),
            ..args.scene.spec()
        };
        let request = DiagramRequest {
            nu_range,
            max_steps: args.max_steps,
        };
        let pair_diagram = jobs::diagram::run_pair(&spec, axes, x_range, y_range, &request)?;
        let (setup, d) = (&pair_diagram.setup, &pair_diagram.diagram);
        let choice = &d.choice;
        let stem = args
            .output
            .stem(&setup.scene.name, &args.scene, several, &outputs)?;
        let head = format!(
            "# scene {}; model {}; {}\n",
            setup.scene.name,
            choice.kind.name(),
            choice.reason
        );
        let csv = with_suffix(&stem, outputs[1]);
        crate::cli::files::write(&csv, d.csv(&head))?;
        let mut files = vec![csv];
        files.extend(
            crate::plot::stability::render(
                &axes_figure(d, &setup.label),
                &with_suffix(&stem, &format!("-stability{pair}")),
            )
            .map_err(|e| Error::Output(std::io::Error::other(e.to_string())))?,
        );
        let json_path = with_suffix(&stem, outputs[0]);
        files.push(json_path.clone());
        let mut v = pair_diagram.to_json();
        v["files"] = json!(files
            .iter()
            .map(|f| f.display().to_string())
            .collect::<Vec<_>>());
        v["elapsed_s"] = json!(t0.elapsed().as_secs_f64());
        crate::cli::files::write(
            &json_path,
            serde_json::to_string_pretty(&v).map_err(std::io::Error::other)?,
        )?;
        if !d.complete {
            partial.push(format!(
                "scene {}: ended at {}",
                setup.scene.name,
                d.stop.words()
            ));
        }
        if args.json {
            all.push(v);
            continue;
        }
        let (x, y) = (axes.x, axes.y);
        println!("scene: {} — {}", setup.scene.name, setup.scene.description);
        println!("model: {}", choice.reason);
        println!(
            "Hopf curve in ({}, {}) over {} = {} .. {} {}: {} points, ended at {}",
            x.name(),
            y.name(),
            x.name(),
            significant(d.x_range.0),
            significant(d.x_range.1),
            x.unit_in_words(),
            d.points.len(),
            d.stop.words()
        );
        if let Some(why) = &d.reason {
            println!("  {why}");
        }
        if let (Some(a), Some(b)) = (d.points.first(), d.points.last()) {
            println!(
                "  critical {} from {} {} ({} = {}) to {} {} ({} = {}); steady sliding stable {} the curve",
                y.name(),
                significant(a.y),
                y.unit_in_words(),
                x.name(),
                significant(a.x),
                significant(b.y),
                y.unit_in_words(),
                x.name(),
                significant(b.x),
                if d.stable_above == Some(false) { "below" } else { "above" }
            );
            println!(
                "  onset type: {}",
                d.onset_type()
                    .map_or("mixed (see the Bautin points)", |c| c.name())
            );
        }
        for b in &d.bautin {
            println!(
                "  bautin    at {} = {:.10e}, {} = {:.10e} (nu = {:.6e}, kappa = {:.6e}), l2 = {:.6e}",
                x.name(),
                b.x,
                y.name(),
                b.y,
                b.nu,
                b.kappa,
                b.l2
            );
        }
        if let Some((px, py)) = d.operating {
            println!(
                "  the scene's operating point: {} = {} {}, {} = {} {}{}",
                x.name(),
                significant(px),
                x.unit_in_words(),
                y.name(),
                significant(py),
                y.unit_in_words(),
                pair_diagram
                    .regime
                    .as_ref()
                    .map_or(String::new(), |op| format!(
                        ": {} ({})",
                        op.regime.name(),
                        op.reason
                    ))
            );
        }
        for f in &files {
            println!("  wrote {}", f.display());
        }
    }
    if args.json {
        super::print_json(all)?;
    }
    super::partial(&partial)
}
