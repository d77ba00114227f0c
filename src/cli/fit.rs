//! `stickslip fit`: the friction law's parameters from laboratory data,
//! with errors; the fitted scene as `<run>-fitted.toml`, a figure per
//! dataset.

use super::files::{write_whole, OutputArgs};
use super::SceneArgs;
use crate::adhesive::fit::AdhesiveFit;
use crate::analysis::hopf::Criticality;
use crate::error::{Error, InputError};
use crate::file_names::with_suffix;
use crate::fit::data::parse_data_option;
use crate::jobs::fit::{run as fit, Fit, FitRequest, OnsetTypeAt, Outcome, Summary};
use crate::scene::Law;
use clap::Args;
use std::path::{Path, PathBuf};

#[derive(Args, Debug)]
pub struct FitArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// A dataset, KIND=FILE, repeatable: steady (CSV columns V_um_s, mu),
    /// onset (V_um_s, K_over_W_per_m, optionally frequency_hz),
    /// velocity_step (t_s, V_um_s, mu: each row's velocity holds until the
    /// next row's time, on the scene's rig), relaxation (t_s, slip_um,
    /// V_um_s: the slip after the drive stops at t = 0, one velocity per
    /// file); an optional sigma column gives each row's error
    /// (sigma_frequency_hz for the frequency), else it is estimated from
    /// the residuals. An adhesive scene (law = "adhesive") takes steady
    /// (V_um_s, F_N: the friction force in N) and onset (V_um_s, K_N_per_m:
    /// the critical stiffness).
    #[arg(long, value_name = "KIND=FILE", required = true)]
    pub data: Vec<String>,
    /// The parameters to fit, comma-separated (default: every parameter of
    /// the scene's law: mu0, A, B, D0, and mu2 or tau; adhesive: F_a, V_s,
    /// tau_on, F_v, alpha, and tau_out with onset data).
    #[arg(long, value_name = "NAME,...", value_delimiter = ',')]
    pub free: Option<Vec<String>>,
    #[command(flatten)]
    pub output: OutputArgs,
    /// Print one JSON object instead of text.
    #[arg(long)]
    pub json: bool,
}

/// The files of a fit, after the run's stem.
const OUTPUTS: &[&str] = &["-fit.json", "-fitted.toml"];

/// Runs the command.
pub fn run(args: &FitArgs) -> Result<(), Error> {
    let data: Vec<_> = args
        .data
        .iter()
        .map(|d| parse_data_option(d))
        .collect::<Result<_, _>>()?;
    let adhesive = crate::scene::law_of(args.scene.scene_name())? == Law::Adhesive;
    if adhesive && args.scene.model.is_some() {
        return Err(InputError::Conflict(format!(
            "--model is not available for fit on an adhesive scene ({}): steady friction has \
             no model to choose, and the critical stiffness is fitted with the scene's inertia \
             (the factor 1 + chi, docs/model.md)",
            args.scene.scene_name()
        ))
        .into());
    }
    let spec = args.scene.spec();
    args.output.create_dir()?;
    let stem = args.output.stem(
        &spec_name(args.scene.scene_name()),
        &args.scene,
        false,
        OUTPUTS,
    )?;
    // The fitted scene is a file of the run as its JSON is,
    // `<out>/<run>-fitted.toml` (`<out>/X-fitted.toml` with `--name X`,
    // its `name = "X"`: the files of later runs on it start with X), and an
    // earlier run's is refused or replaced as every command's files are
    // ([`OutputArgs::stem`]).
    let toml_path = with_suffix(&stem, "-fitted.toml");
    // A fit takes a fraction of a second: Ctrl-C (or SIGTERM) lets it
    // write its files whole, then the run ends as interrupted.
    super::interrupt::catch_interrupts();
    let stop = if adhesive {
        let mut result = crate::adhesive::fit::run(
            args.scene.scene_name(),
            &args.scene.set,
            &data,
            args.free.as_deref(),
        )?;
        let figures = crate::plot::fit::data_figures(&result, &stem).map_err(plot_error)?;
        rename(&mut result.outcome, args.output.name.as_deref());
        write_fitted(&mut result.outcome, figures, &toml_path, &stem)?;
        emit(&result, &stem, args.json, print_adhesive)?;
        for w in &result.warnings {
            eprintln!("warning: {w}");
        }
        result.summary.stop
    } else {
        let request = FitRequest {
            data,
            free: args.free.clone(),
            stability: true,
        };
        let mut result = fit(&spec, &request)?;
        let figures = crate::plot::fit::figures(&result, &stem).map_err(plot_error)?;
        rename(&mut result.outcome, args.output.name.as_deref());
        write_fitted(&mut result.outcome, figures, &toml_path, &stem)?;
        emit(&result, &stem, args.json, print_text)?;
        result.summary.stop
    };
    if super::interrupt::interrupted() {
        return Err(super::interrupt::stopped(
            "after the fit (its files are written whole)".into(),
        ));
    }
    match stop {
        None => Ok(()),
        Some(why) => Err(Error::Partial(why)),
    }
}

/// A unit of the JSON (`um/s`, `um`) as the text writes it (`µm/s`, `µm`).
fn text_unit(unit: &str) -> &str {
    match unit {
        "um/s" => "µm/s",
        "um" => "µm",
        u => u,
    }
}

fn plot_error(e: crate::plot::PlotError) -> Error {
    Error::Output(std::io::Error::other(e.to_string()))
}

/// Gives the fitted scene the run's `--name`: its top-level `name = ...`
/// line (the first, written by the fit) replaced; unchanged without one.
fn rename<V, U>(outcome: &mut Outcome<V, U>, name: Option<&str>) {
    let Some(name) = name else {
        return;
    };
    let quoted = toml::Value::String(name.to_string()).to_string();
    outcome.fitted_toml = outcome
        .fitted_toml
        .lines()
        .scan(false, |done, line| {
            Some(if !*done && line.starts_with("name = ") {
                *done = true;
                format!("name = {quoted}")
            } else {
                line.to_string()
            })
        })
        .collect::<Vec<_>>()
        .join("\n")
        + "\n";
}

/// Writes the fitted scene to `toml_path`, and lists the files of the fit
/// in `outcome`: its figures, the fitted scene and the JSON (written by
/// [`emit`]).
fn write_fitted<V, U>(
    outcome: &mut Outcome<V, U>,
    mut files: Vec<PathBuf>,
    toml_path: &Path,
    stem: &Path,
) -> Result<(), Error> {
    write_whole(toml_path, &outcome.fitted_toml)?;
    files.push(toml_path.to_path_buf());
    files.push(with_suffix(stem, "-fit.json"));
    outcome.files = files.iter().map(|f| f.display().to_string()).collect();
    Ok(())
}

/// Writes the JSON `<stem>-fit.json`, and prints it (`as_json`) or the
/// text `print` makes.
fn emit<T: serde::Serialize>(
    result: &T,
    stem: &Path,
    as_json: bool,
    print: fn(&T),
) -> Result<(), Error> {
    let json = serde_json::to_string_pretty(result).map_err(std::io::Error::other)?;
    write_whole(&with_suffix(stem, "-fit.json"), &json)?;
    if as_json {
        println!("{json}");
    } else {
        print(result);
    }
    Ok(())
}

/// The scene's name (of its file, or built in), for the run's name.
fn spec_name(scene: &str) -> String {
    crate::scene::load(scene)
        .map(|s| s.name)
        .or_else(|_| crate::adhesive::scene::load(scene).map(|s| s.name))
        .unwrap_or_else(|_| scene.to_string())
}

/// The adhesive fit as text: the parameters with their errors, what is
/// held and why, the datasets' residuals, the files.
fn print_adhesive(fit: &AdhesiveFit) {
    println!("scene: {} ({} law)", fit.scene, fit.law);
    print_parameters(&fit.summary);
    for h in &fit.held {
        println!(
            "{} held at the scene's {:.6e}: {}",
            h.name, h.value, h.reason
        );
    }
    let r = &fit.ratio_tau_on_over_tau_out;
    println!(
        "tau_on / tau_out = {:.6e}{} (scene {:.6e})",
        r.value,
        r.std_error
            .map_or(" (not fitted)".into(), |e| format!(" +- {e:.3e}")),
        r.start
    );
    print_residuals(&fit.summary, fit.outcome.iterations);
    for f in &fit.outcome.files {
        println!("wrote {f}");
    }
}

/// The fit as text: the parameters with their errors, the seed's
/// closed-form route beside them, the datasets' residuals, the files.
fn print_text(fit: &Fit) {
    println!("scene: {} ({} law)", fit.scene, fit.law);
    print_parameters(&fit.summary);
    print_residuals(&fit.summary, fit.outcome.iterations);
    if let Some(c) = &fit.closed_form {
        let mut line = format!(
            "closed forms ({}): B - A = {:.4e}, mu0 = {:.5}",
            // + 0.0: a zero slope prints as 0, not -0.
            c.from,
            c.b_minus_a + 0.0,
            c.mu0
        );
        if let Some(d0) = c.d0_um {
            line += &format!(", D0 = {d0:.4} µm");
        }
        if let Some(a) = c.a {
            line += &format!(", A = {a:.4e}");
        }
        println!("{line}");
    }
    if let (Some(first), Some(last)) = (fit.band.first(), fit.band.last()) {
        let widest = fit
            .band
            .iter()
            .max_by(|a, b| (a.std_error / a.k_over_w).total_cmp(&(b.std_error / b.k_over_w)))
            .unwrap_or(first);
        println!(
            "stability boundary of the fitted scene from {:.4e} to {:.4e} µm/s: (K/W)_c = {:.4e} to {:.4e} 1/m, 95 % band at most ±{:.2} % (at {:.4e} µm/s)",
            first.v_um_s,
            last.v_um_s,
            first.k_over_w,
            last.k_over_w,
            196.0 * widest.std_error / widest.k_over_w,
            widest.v_um_s
        );
    }
    // The onset type in stretches of one type, with the least share of the
    // drawn parameter sets that agree within each.
    let mut stretches: Vec<(&OnsetTypeAt, &OnsetTypeAt, f64)> = Vec::new();
    for o in &fit.onset_type {
        let agree = |o: &OnsetTypeAt| match o.criticality {
            Criticality::Supercritical => o.share_supercritical,
            _ => 1.0 - o.share_supercritical,
        };
        match stretches.last_mut() {
            Some((_, last, least)) if last.criticality == o.criticality => {
                *last = o;
                *least = least.min(agree(o));
            }
            _ => stretches.push((o, o, agree(o))),
        }
    }
    for (first, last, least) in stretches {
        let agreement = if least >= 1.0 {
            "every parameter set drawn from the fit agrees".to_string()
        } else {
            format!(
                "at least {:.0} % of the parameter sets drawn from the fit agree at each velocity",
                100.0 * least
            )
        };
        println!(
            "onset {} from {:.4e} to {:.4e} µm/s (l1 = {:.3e} to {:.3e}); {agreement}",
            first.criticality.name(),
            first.v_um_s,
            last.v_um_s,
            first.l1,
            last.l1,
        );
    }
    for f in &fit.outcome.files {
        println!("wrote {f}");
    }
}

/// The parameters' table (value, standard error, unit, status, start), the
/// undetermined ones with what to add, and the correlations.
fn print_parameters(summary: &Summary) {
    let (parameters, not_determined, correlation) = (
        &summary.parameters,
        &summary.not_determined,
        &summary.correlation,
    );
    // The names' column: at least 5 wide (`tau_out` needs 7).
    let w = parameters.keys().map(|k| k.len()).max().unwrap_or(0).max(5);
    println!(
        "{:<w$} {:>14} {:>12} {:>6}  {:<15} {:>14}",
        "", "value", "std. error", "unit", "", "scene (start)"
    );
    for (name, e) in parameters {
        let error = e.std_error.map_or("-".into(), |s| format!("{s:.3e}"));
        let status = if e.given.is_empty() {
            e.status.to_string()
        } else {
            format!("{} (given {})", e.status, e.given.join(", "))
        };
        println!(
            "{name:<w$} {:>14.6e} {error:>12} {:>6}  {status:<15} {:>14.6e}",
            e.value,
            text_unit(e.unit),
            e.start
        );
    }
    for n in not_determined {
        let with = if n.with.len() > 1 {
            format!(
                " (only a combination of {} is determined)",
                n.with.join(", ")
            )
        } else {
            String::new()
        };
        println!(
            "{} is not determined by these data{with}: {}; kept at the scene's {:.6e}",
            n.name, n.remedy, n.kept_at
        );
    }
    if correlation.names.len() > 1 {
        println!("correlation ({}):", correlation.names.join(", "));
        for row in &correlation.matrix {
            let cells: Vec<String> = row.iter().map(|c| format!("{c:>7.3}")).collect();
            println!("  {}", cells.join(" "));
        }
    }
}

/// chi2 with its degrees of freedom and the residuals of each dataset.
fn print_residuals(summary: &Summary, iterations: usize) {
    let (chi2, dof, chi2_per_dof, datasets) = (
        summary.chi2,
        summary.dof,
        summary.chi2_per_dof,
        &summary.datasets,
    );
    println!(
        "chi2 = {:.4e} for {} degrees of freedom (chi2/dof = {:.3}), {} iteration{}",
        chi2,
        dof,
        chi2_per_dof,
        iterations,
        if iterations == 1 { "" } else { "s" }
    );
    for d in datasets {
        println!(
            "  {} {} ({} rows): {} rms residual {:.3e}{}",
            d.kind.name(),
            d.file,
            d.rows,
            d.quantity,
            d.rms,
            d.sigma_estimated
                .map_or(" (errors given)".into(), |s| format!(
                    " (error per row estimated from the residuals: {s:.3e})"
                ))
        );
        if let (Some(model), Some(why)) = (d.model, &d.model_reason) {
            println!("    integrated in the {model} model: {why}");
        }
        if let Some(w) = &d.warning {
            eprintln!("warning: {} {}: {w}", d.kind.name(), d.file);
        }
    }
}
