//! `stickslip hopf`: the stick-slip onset of a scene, next to Appendix C.

use super::{describe_params, describe_params_except, from_value, SceneArgs, Setup, TextUnits};
use crate::analysis::control::Control;
use crate::analysis::hopf::{Arithmetic, Criticality};
use crate::error::Error;
use crate::jobs::restart::Restart;
use crate::jobs::{self, hopf::HopfRequest};
use crate::model::ModelKind;
use crate::params::Param;
use crate::records::hopf::{
    Critical, CycleSide, HopfReport, HopfStatus, NoOnset, Onset, OperatingPoint,
};
use clap::Args;

#[derive(Args, Debug)]
pub struct HopfArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Print one JSON object instead of text.
    #[arg(long)]
    pub json: bool,
    /// Units of the text: physical (K/W in 1/m, the frequency shift in
    /// Hz m) or dimensionless (kappa, omega in V0/D0). The table of the
    /// onset gives both, and so does the JSON. Adhesive scenes: refused
    /// (their text gives both).
    #[arg(long, value_enum, default_value_t = TextUnits::Physical)]
    pub units: TextUnits,
    /// The control parameter of the onset, with everything else at the
    /// scene's values: K (N/m) (default), V (µm/s), M (kg), W (N), tau (s), eta (s/m),
    /// or kappa, nu, m, A, B, mu2, theta_c, mu_vv, mu_vphi, eta_d. JSON: `critical`.
    #[arg(long, value_name = "P")]
    pub param: Option<String>,
    /// Low end of the range searched, in the unit of --param (default: the
    /// scene's V_range for V and nu, 1e-3 of the scene's value otherwise).
    /// With --index N: the JSON that `cycles --json` or `branch --json`
    /// printed (saved to a file): the onset at the parameters of its cycle
    /// or point labelled N, with the file's scene and overrides.
    #[arg(long, allow_hyphen_values = true, value_name = "VALUE|FILE.json")]
    pub from: Option<String>,
    /// With --from FILE.json: the label of the cycle or point whose
    /// parameters to take (`label` in the JSON and the CSV, #N in the text).
    #[arg(long, value_name = "N", requires = "from", value_parser = super::label)]
    pub index: Option<usize>,
    /// High end of the range searched (default: the top of V_range for V
    /// and nu, 1e3 times the scene's value otherwise).
    #[arg(long, allow_hyphen_values = true)]
    pub to: Option<f64>,
}

/// Writes the report as JSON or text.
fn present(args: &HopfArgs, setup: &Setup, report: &HopfReport) -> Result<(), Error> {
    if args.json {
        println!(
            "{}",
            serde_json::to_value(report)
                .and_then(|v| serde_json::to_string_pretty(&v))
                .map_err(std::io::Error::other)?
        );
    } else {
        print_text(setup, report, args.units);
    }
    Ok(())
}

/// Runs the command.
pub fn run(args: &HopfArgs) -> Result<(), Error> {
    let unused = [
        ("--param", args.param.is_some()),
        ("--from", args.from.is_some()),
        ("--to", args.to.is_some()),
        ("--units", args.units != TextUnits::Physical),
    ];
    if let Some(setup) =
        super::adhesive::adhesive_setup(&args.scene, &unused, super::adhesive::Judged::AtVelocity)?
    {
        return super::adhesive::hopf(setup, args.json);
    }
    let mut request = HopfRequest {
        param: Control::from_param(args.param.as_deref())?,
        from: None,
        to: args.to,
    };
    let hopf = match (args.index, &args.from) {
        (Some(index), Some(file)) => {
            let from = Restart {
                file: file.into(),
                index,
            };
            jobs::hopf::run_from(&args.scene.given(), &from, &request)?
        }
        (_, from) => {
            request.from = from
                .as_deref()
                .map(|t| {
                    from_value(
                    t,
                    "a cycle of `cycles --json` or a point of `branch --json` whose parameters \
                     to take",
                )
                })
                .transpose()?;
            jobs::hopf::run(&args.scene.spec(), &request)?
        }
    };
    if let Some(note) = &hopf.note {
        eprintln!("note: {note}");
    }
    present(args, &hopf.setup, &hopf.report)
}

/// The operating point in one line: the stiffness, its margin, the regime
/// and why.
fn operating_point_line(op: &OperatingPoint, units: TextUnits) -> String {
    let at = match units {
        TextUnits::Physical => format!("K = {:.6e} N/m", op.k_n_per_m),
        TextUnits::Dimensionless => format!("kappa = {:.6e}", op.kappa),
    };
    let margin = op
        .margin
        .map(|m| format!(", (K - K_c)/K_c = {m:+.3e}"))
        .unwrap_or_default();
    format!(
        "operating point: {at}{margin}: {} ({})",
        op.regime.name(),
        op.reason
    )
}

fn print_text(setup: &Setup, report: &HopfReport, units: TextUnits) {
    let p = &setup.params;
    println!("scene: {} — {}", setup.scene.name, setup.scene.description);
    if let Some(r) = &report.restarted_from {
        println!(
            "at the parameters of {} #{} of {} ({} model there)",
            r.kind,
            r.label,
            r.file,
            r.model.name()
        );
    }
    println!("model: {}", report.model_reason);
    let mut shown = *p;
    let listed = match &report.outcome {
        HopfStatus::Hopf(o) => {
            shown.kappa = o.kappa_c;
            format!("kappa at onset): {}", describe_params(&shown))
        }
        HopfStatus::StableForAllStiffness(_) => format!(
            "no onset, hence no kappa): {}",
            describe_params_except(&shown, Some(Param::Kappa))
        ),
    };
    println!("parameters (dimensionless, docs/model.md; {listed}");
    // With radiation damping `mu_v` is the resisting force's slope: the
    // friction's direct effect plus `eta_d nu` (docs/model.md), which leaves
    // steady friction `mu_ss` itself unchanged.
    let damping = p.eta_d * p.nu;
    let slope = report.mu_v - damping - report.mu_phi;
    let (mu_v, damped) = if damping > 0.0 {
        (
            format!(
                "{:.6e} (the direct effect {:.6e} plus the damping eta_d nu = {damping:.6e})",
                report.mu_v,
                report.mu_v - damping
            ),
            format!(
                ", with the damping d (mu_ss + eta_d nu)/d ln V = {:.6e}",
                report.mu_v - report.mu_phi
            ),
        )
    } else {
        (format!("{:.6e}", report.mu_v), String::new())
    };
    println!(
        "steady sliding at V = {:.4e} µm/s: mu_v = {mu_v}, mu_phi = {:.6e}, d mu_ss/d ln V = \
         {slope:.6e}{damped}",
        setup.scene.units.velocity_um_s(p.nu),
        report.mu_phi,
    );
    match &report.outcome {
        HopfStatus::Hopf(o) => {
            print_hopf(setup, report.model, o, units);
            print_normal_form(setup, o, p.mu0, units);
            println!(
                "  located by Newton on the minimally augmented Hopf system: {} iterations, residual {:.1e}, \
                 after {} continuation steps from a stable stiffness",
                o.location.newton_iterations, o.location.residual, o.location.continuation_steps
            );
        }
        HopfStatus::StableForAllStiffness(n) => {
            println!();
            print_no_onset(report, n, units);
        }
    }
    if let Some(op) = &report.operating_point {
        println!();
        println!("{}", operating_point_line(op, units));
    }
    if let Some(c) = &report.critical {
        println!();
        println!("{}", critical_line(c));
    }
}

/// The onset in the control parameter in one line: `onset at V = 214.1
/// µm/s (nu = 214.1), supercritical (l1 = ...)`, the scene's value beside it.
fn critical_line(c: &Critical) -> String {
    let unit = match c.unit {
        "1" => String::new(),
        "um/s" => " µm/s".to_string(),
        u => format!(" {u}"),
    };
    let moved: Vec<String> = c
        .dimensionless
        .as_object()
        .map(|o| {
            o.iter()
                .filter(|(name, _)| name.as_str() != c.param)
                .map(|(name, v)| {
                    format!(
                        "{name} = {}",
                        v.as_f64().map_or("?".into(), |x| format!("{x:.6e}"))
                    )
                })
                .collect()
        })
        .unwrap_or_default();
    let moved = if moved.is_empty() {
        String::new()
    } else {
        format!(" ({})", moved.join(", "))
    };
    let range = c
        .range
        .map(|[lo, hi]| format!("; searched {} from {lo:.4e} to {hi:.4e}{unit}", c.param))
        .unwrap_or_default();
    format!(
        "onset at {} = {:.10e}{unit}{moved}: {} (l1 = {:.6e} ± {:.1e}); the scene's {} = {:.6e}{unit}, \
         (value - critical)/critical = {:+.3e}{range}",
        c.param,
        c.value,
        c.criticality.name(),
        c.l1,
        c.l1_error_bound,
        c.param,
        c.scene_value,
        c.margin
    )
}

/// Why there is no onset.
fn print_no_onset(report: &HopfReport, n: &NoOnset, units: TextUnits) {
    let weakening = report.mu_phi - report.mu_v;
    if weakening <= 0.0 {
        println!(
            "steady sliding is linearly stable for every stiffness: steady friction{} is velocity \
             strengthening here (mu_phi - mu_v = {weakening:.4e} <= 0). Finite-amplitude (hysteretic) \
             stick-slip may still exist with inertia.",
            if report.params["eta_d"].as_f64().is_some_and(|e| e > 0.0) {
                " with the radiation damping eta_d nu"
            } else {
                ""
            }
        );
    } else {
        println!(
            "no Hopf point down to {}, although steady friction weakens slightly \
             (mu_phi - mu_v = {weakening:.4e}): the critical stiffness, if any, lies below the searched range.",
            units.stiffness(n.kappa_min_checked, n.k_over_w_min_checked_per_m, 3)
        );
    }
}

/// The onset beside Appendix C, in both unit systems.
fn print_hopf(setup: &Setup, model: ModelKind, o: &Onset, units: TextUnits) {
    let u = &setup.scene.units;
    let eq = if model == ModelKind::Inertial {
        "C11"
    } else {
        "C12"
    };
    println!();
    println!(
        "Hopf point (stick-slip onset): steady sliding is stable for {}",
        match units {
            TextUnits::Physical => "K/W > K_c/W",
            TextUnits::Dimensionless => "kappa > kappa_c",
        }
    );
    println!(
        "  {:<24} {:>22} {:>28} {:>10}",
        "", "continuation", "Appendix C", "rel. diff"
    );
    println!(
        "  {:<24} {:>22.14e} {:>17.14e} ({eq}) {:>9.1e}",
        "kappa_c = K_c D0/W", o.kappa_c, o.appendix_c.kappa_c, o.appendix_c.kappa_c_rel_diff
    );
    println!(
        "  {:<24} {:>22.14e} {:>17.14e} (C13) {:>9.1e}",
        "omega_c [V0/D0]", o.omega_c, o.appendix_c.omega_c, o.appendix_c.omega_c_rel_diff
    );
    let physical = &o.physical;
    println!(
        "  {:<24} {:>22.8e}",
        "K_c/W [1/m]", physical.at.k_over_w_per_m
    );
    match physical.at.k_over_m_per_s2 {
        Some(km) => println!(
            "  {:<24} {:>22.8e}   (W = {:.4e} N, M = {:.4e} kg)",
            "K_c/M [1/s^2]", km, u.load, u.mass
        ),
        None => println!("  {:<24} {:>22}", "K_c/M [1/s^2]", "— (massless block)"),
    }
    println!("  {:<24} {:>22.8e}", "K_c [N/m]", physical.k_n_per_m);
    println!("  {:<24} {:>22.8e}", "f_c [Hz]", physical.at.frequency_hz);
}

/// The onset type and what the normal form predicts for the emerging cycle.
/// What makes a degenerate onset decidable, naming only what the scene
/// does not already have: for the quasi-static plain Rice–Ruina law the
/// degeneracy is exact (Ranjith & Rice 1999), and the ln² term, either
/// correction in `ln v` (docs/model.md) or inertia lifts it; elsewhere (a Bautin point) the cycles come from a simulation.
fn degeneracy_remedy(setup: &Setup) -> String {
    let p = &setup.params;
    let plain = p.theta_c.is_none() && [p.mu2, p.mu_vv, p.mu_vphi] == [0.0; 3];
    let mut lifts = Vec::new();
    if plain {
        lifts.push("the ln² term (mu2) or a correction in ln v (mu_vv, mu_vphi)");
    }
    if setup.scene_params.m <= 0.0 {
        lifts.push("inertia (a mass M)");
    } else if setup.choice.kind == ModelKind::QuasiStatic {
        lifts.push("the scene's own inertia (without --model quasi-static)");
    }
    let exact = if plain && setup.choice.kind == ModelKind::QuasiStatic {
        " For the quasi-static Rice–Ruina law this is exact (Ranjith & Rice 1999): at kappa = \
         kappa_c a whole family of cycles exists."
    } else {
        " l1 changes sign here (a Bautin point, where l2 decides)."
    };
    let remedy = if lifts.is_empty() {
        " `cycles` starts its branch from a simulated orbit.".to_string()
    } else {
        format!(" Add {}.", lifts.join(" or "))
    };
    format!("{exact}{remedy}")
}

fn print_normal_form(setup: &Setup, o: &Onset, mu0: f64, units: TextUnits) {
    println!();
    println!(
        "Onset type: {} (first Lyapunov coefficient l1 = {:.10e} ± {:.1e}, docs/model.md convention{})",
        o.criticality.name(),
        o.l1,
        o.l1_error_bound,
        match o.l1_arithmetic {
            Arithmetic::Double => "",
            Arithmetic::DoubleDouble => "; computed in double-double, f64 could not resolve it",
        }
    );
    match (o.criticality, o.amplitude_coefficient, o.onset.cycle_side) {
        (Criticality::Degenerate, ..) => println!(
            "  degenerate within rounding: |l1| < {:.2e}, the bound on its rounding error (its terms are of \
             size {:.2e}): the cubic normal form does not decide.{}",
            o.l1_error_bound,
            o.l1_term_scale,
            degeneracy_remedy(setup)
        ),
        (_, Some(c), Some(side)) => {
            let (k, kc) = match units {
                TextUnits::Physical => ("K/W", "K_c/W"),
                TextUnits::Dimensionless => ("kappa", "kappa_c"),
            };
            let (where_, hyst) = match side {
                CycleSide::Below => (
                    format!("below {kc} ({k} < {kc})"),
                    "stable: stick-slip grows continuously as K decreases",
                ),
                CycleSide::Above => (
                    format!("above {kc} ({k} > {kc})"),
                    "unstable: it bounds the basin of steady sliding; the onset is hysteretic",
                ),
            };
            println!("  emerging cycle exists {where_}; it is {hyst}");
            let (coefficient, unit) = match (units, o.physical.amplitude_coefficient_sqrt_m) {
                (TextUnits::Physical, Some(c_m)) => (c_m, " m^1/2"),
                _ => (c, ""),
            };
            println!(
                "  peak-to-peak spring force: Delta_s ~ C sqrt|{k} - {kc}|, C = {coefficient:.10e}{unit} \
                 (Delta(K x / W) in units of the friction coefficient)"
            );
            let example = c * (0.01 * o.kappa_c).sqrt();
            match units {
                TextUnits::Physical => println!(
                    "  e.g. 1 % from onset: Delta_s ~ {example:.4e} (a force drop of {:.4e} N)",
                    example * setup.scene.units.load
                ),
                TextUnits::Dimensionless => {
                    println!("  e.g. 1 % from onset: Delta_s ~ {example:.4e}")
                }
            }
            if example > mu0.abs() {
                println!(
                    "  (more than mu0 = {mu0:.3e}, the friction level itself: far beyond what the expansion \
                     near onset can promise; `stickslip cycles` computes the cycles themselves)"
                );
            }
            match (units, o.physical.frequency_slope_hz_m, o.onset.frequency_slope) {
                (TextUnits::Physical, Some(fs), _) => println!(
                    "  frequency shift on the cycle: d f / d(K/W) = {fs:.6e} Hz m"
                ),
                (_, _, Some(fs)) => println!(
                    "  frequency shift on the cycle: d Omega / d kappa = {fs:.6e} (units V0/D0)"
                ),
                _ => {}
            }
        }
        _ => {}
    }
}
