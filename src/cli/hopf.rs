//! `stickslip hopf`: the stick-slip onset of a scene, next to Appendix C.

use super::{
    describe_params, describe_params_except, onset_with_degeneracy_resolved, params_json,
    SceneArgs, Setup,
};
use crate::analysis::hopf::{HopfOutcome, HopfPoint};
use crate::appendix_c;
use crate::error::{Error, NumericalError};
use crate::model::ModelKind;
use crate::params::Param;
use clap::Args;
use serde_json::json;

#[derive(Args, Debug)]
pub struct HopfArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Print one JSON object instead of text.
    #[arg(long)]
    pub json: bool,
}

/// Relative difference `|a - b| / |b|`.
fn rel_diff(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// Runs the command.
pub fn run(args: &HopfArgs) -> Result<(), Error> {
    let mut setup = args.scene.setup(|p| *p)?;
    let kappa_set = args.scene.set.iter().any(|s| {
        s.split_once('=')
            .is_some_and(|(name, _)| Param::parse(name.trim()).is_ok_and(|p| p == Param::Kappa))
    });
    if kappa_set || setup.scene.stiffness_given {
        eprintln!(
            "note: hopf finds the stiffness at onset itself; the given kappa = {:e} ({}) is not used",
            setup.scene_params.kappa,
            if kappa_set { "--set" } else { "the scene's K" }
        );
    }
    let outcome = onset_with_degeneracy_resolved(&mut setup, args.scene.model.is_some())?;
    if let HopfOutcome::Found(h) = &outcome {
        let values = [h.kappa_c, h.omega_c].into_iter().chain(h.state);
        if values.clone().any(|v| !v.is_finite()) {
            return Err(NumericalError::Analysis(format!(
                "the located Hopf point has non-finite values (kappa_c = {}, omega_c = {})",
                h.kappa_c, h.omega_c
            ))
            .into());
        }
    }
    if args.json {
        println!(
            "{}",
            serde_json::to_string_pretty(&to_json(&setup, &outcome))
                .map_err(std::io::Error::other)?
        );
    } else {
        print_text(&setup, &outcome);
    }
    Ok(())
}

fn to_json(setup: &Setup, outcome: &HopfOutcome) -> serde_json::Value {
    let mut at = setup.params;
    if let HopfOutcome::Found(h) = outcome {
        at.kappa = h.kappa_c;
    }
    let p = &at;
    let units = &setup.scene.units;
    let mut out = json!({
        "scene": setup.scene.name,
        "model": setup.choice.kind.name(),
        "model_reason": setup.choice.reason,
        "inertia_ratio": setup.choice.inertia_ratio,
        "params": params_json(p),
        "mu_v": p.mu_v(),
        "mu_phi": p.mu_phi(),
    });
    if !matches!(outcome, HopfOutcome::Found(_)) {
        // No onset: the stiffness is what was searched for, not a parameter.
        out["params"]["kappa"] = serde_json::Value::Null;
    }
    let kappa_ref = appendix_c::critical_stiffness(p);
    match outcome {
        HopfOutcome::Found(h) => {
            let omega_ref = appendix_c::critical_frequency(p).unwrap_or(f64::NAN);
            let extra = json!({
                "status": "hopf",
                "kappa_c": h.kappa_c,
                "omega_c": h.omega_c,
                "state": { "s": h.state[0], "v": h.state[1], "theta": h.state[2] },
                "eigenvalues": h.eigenvalues.iter().map(|l| [l.re, l.im]).collect::<Vec<_>>(),
                "appendix_c": {
                    "kappa_c": kappa_ref,
                    "omega_c": omega_ref,
                    "kappa_c_rel_diff": rel_diff(h.kappa_c, kappa_ref),
                    "omega_c_rel_diff": rel_diff(h.omega_c, omega_ref),
                },
                "physical": {
                    "V_um_per_s": units.velocity_um_s(p.nu),
                    "K_over_W_per_m": units.k_over_w(h.kappa_c),
                    "K_over_M_per_s2": units.k_over_m(h.kappa_c),
                    "K_N_per_m": units.stiffness(h.kappa_c),
                    "frequency_hz": units.frequency_hz(h.omega_c),
                },
                "l1": h.onset.l1,
                "l1_term_scale": h.onset.l1_scale,
                "l1_error_bound": h.onset.l1_error_bound,
                "l1_arithmetic": h.onset.arithmetic.name(),
                "criticality": h.onset.criticality.name(),
                "amplitude_coefficient": h.onset.amplitude_coefficient,
                "onset": {
                    "c1": [h.onset.c1.re, h.onset.c1.im],
                    "dlambda_dkappa": [h.onset.dlambda_dkappa.re, h.onset.dlambda_dkappa.im],
                    "cycle_side": h.onset.side.map(|s| if s < 0.0 { "kappa < kappa_c" } else { "kappa > kappa_c" }),
                    "frequency_slope": h.onset.frequency_slope,
                },
                "location": { "newton_iterations": h.newton_iterations, "residual": h.residual, "continuation_steps": h.steps },
            });
            merge(&mut out, extra);
        }
        HopfOutcome::StableForAllStiffness { kappa_min } => {
            merge(
                &mut out,
                json!({
                    "status": "stable_for_all_stiffness",
                    "kappa_c": null,
                    "omega_c": null,
                    "kappa_min_checked": kappa_min,
                    // Eq. C11 gives a stiffness only where steady friction
                    // weakens (mu_phi > mu_v); else no onset, not a negative one.
                    "appendix_c": { "kappa_c": (kappa_ref > 0.0).then_some(kappa_ref) },
                }),
            );
        }
    }
    out
}

fn merge(into: &mut serde_json::Value, from: serde_json::Value) {
    if let (Some(a), serde_json::Value::Object(b)) = (into.as_object_mut(), from) {
        a.extend(b);
    }
}

fn print_text(setup: &Setup, outcome: &HopfOutcome) {
    let p = &setup.params;
    let units = &setup.scene.units;
    println!("scene: {} — {}", setup.scene.name, setup.scene.description);
    println!("model: {}", setup.choice.reason);
    let mut shown = *p;
    let listed = if let HopfOutcome::Found(h) = outcome {
        shown.kappa = h.kappa_c;
        format!("kappa at onset): {}", describe_params(&shown))
    } else {
        format!(
            "no onset, hence no kappa): {}",
            describe_params_except(&shown, Some(Param::Kappa))
        )
    };
    println!("parameters (dimensionless, docs/model.md; {listed}");
    println!(
        "steady sliding at V = {:.4e} um/s: mu_v = {:.6e}, mu_phi = {:.6e}, d mu_ss/d ln V = {:.6e}",
        units.velocity_um_s(p.nu),
        p.mu_v(),
        p.mu_phi(),
        p.mu_v() - p.mu_phi()
    );
    match outcome {
        HopfOutcome::Found(h) => print_hopf(setup, h),
        HopfOutcome::StableForAllStiffness { kappa_min } => {
            println!();
            let weakening = p.mu_phi() - p.mu_v();
            if weakening <= 0.0 {
                println!(
                    "steady sliding is linearly stable for every stiffness: steady friction is velocity \
                     strengthening here (mu_phi - mu_v = {weakening:.4e} <= 0). Finite-amplitude (hysteretic) \
                     stick-slip may still exist with inertia."
                );
            } else {
                println!(
                    "no Hopf point down to kappa = {kappa_min:.3e}, although steady friction weakens slightly \
                     (mu_phi - mu_v = {weakening:.4e}): the critical stiffness, if any, lies below the searched range."
                );
            }
        }
    }
}

fn print_hopf(setup: &Setup, h: &HopfPoint) {
    let p = &setup.params;
    let units = &setup.scene.units;
    let kappa_ref = appendix_c::critical_stiffness(p);
    let omega_ref = appendix_c::critical_frequency(p).unwrap_or(f64::NAN);
    let eq = if setup.choice.kind == ModelKind::Inertial {
        "C11"
    } else {
        "C12"
    };
    println!();
    println!("Hopf point (stick-slip onset): steady sliding is stable for kappa > kappa_c");
    println!(
        "  {:<24} {:>22} {:>28} {:>10}",
        "", "continuation", "Appendix C", "rel. diff"
    );
    println!(
        "  {:<24} {:>22.14e} {:>17.14e} ({eq}) {:>9.1e}",
        "kappa_c = K_c D0/W",
        h.kappa_c,
        kappa_ref,
        rel_diff(h.kappa_c, kappa_ref)
    );
    println!(
        "  {:<24} {:>22.14e} {:>17.14e} (C13) {:>9.1e}",
        "omega_c [V0/D0]",
        h.omega_c,
        omega_ref,
        rel_diff(h.omega_c, omega_ref)
    );
    println!(
        "  {:<24} {:>22.8e}",
        "K_c/W [1/m]",
        units.k_over_w(h.kappa_c)
    );
    match units.k_over_m(h.kappa_c) {
        Some(km) => println!(
            "  {:<24} {:>22.8e}   (W = {:.4e} N, M = {:.4e} kg)",
            "K_c/M [1/s^2]", km, units.load, units.mass
        ),
        None => println!("  {:<24} {:>22}", "K_c/M [1/s^2]", "— (massless block)"),
    }
    println!(
        "  {:<24} {:>22.8e}",
        "K_c [N/m]",
        units.stiffness(h.kappa_c)
    );
    println!(
        "  {:<24} {:>22.8e}",
        "f_c [Hz]",
        units.frequency_hz(h.omega_c)
    );
    print_onset(&h.onset, h.kappa_c, p.mu0);
    println!(
        "  located by Newton on the minimally augmented Hopf system: {} iterations, residual {:.1e}, \
         after {} continuation steps from a stable stiffness",
        h.newton_iterations, h.residual, h.steps
    );
}

fn print_onset(o: &crate::analysis::hopf::Onset, kappa_c: f64, mu0: f64) {
    use crate::analysis::hopf::Criticality;
    println!();
    println!(
        "Onset type: {} (first Lyapunov coefficient l1 = {:.10e} ± {:.1e}, docs/model.md convention{})",
        o.criticality.name(),
        o.l1,
        o.l1_error_bound,
        match o.arithmetic {
            crate::analysis::hopf::Arithmetic::Double => "",
            crate::analysis::hopf::Arithmetic::DoubleDouble => "; computed in double-double, f64 could not resolve it",
        }
    );
    match (o.criticality, o.amplitude_coefficient, o.side) {
        (Criticality::Degenerate, ..) => println!(
            "  degenerate within rounding: |l1| < {:.2e}, the bound on its rounding error (its terms are of \
             size {:.2e}): the cubic normal form does not decide. For the quasi-static Rice–Ruina law this is \
             exact (Ranjith & Rice 1999): at kappa = kappa_c a whole family of cycles exists; add the ln² term \
             (mu2) or inertia.",
            o.l1_error_bound,
            o.l1_scale
        ),
        (_, Some(c), Some(side)) => {
            let (where_, hyst) = if side < 0.0 {
                ("below kappa_c (kappa < kappa_c)", "stable: stick-slip grows continuously as K decreases")
            } else {
                ("above kappa_c (kappa > kappa_c)", "unstable: it bounds the basin of steady sliding; the onset is hysteretic")
            };
            println!("  emerging cycle exists {where_}; it is {hyst}");
            println!(
                "  peak-to-peak spring force: Delta_s ~ C sqrt|kappa - kappa_c|, C = {c:.10e} \
                 (Delta(K x / W) in units of the friction coefficient)"
            );
            let example = c * (0.01 * kappa_c).sqrt();
            println!("  e.g. 1 % from onset: Delta_s ~ {example:.4e}");
            if example > mu0.abs() {
                println!(
                    "  (more than mu0 = {mu0:.3e}, the friction level itself: far beyond what the expansion \
                     near onset can promise; `stickslip cycles` computes the cycles themselves)"
                );
            }
            if let Some(fs) = o.frequency_slope {
                println!("  frequency shift on the cycle: d Omega / d kappa = {fs:.6e} (units V0/D0)");
            }
        }
        _ => {}
    }
}
