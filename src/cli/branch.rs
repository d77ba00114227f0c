//! `stickslip branch`: steady sliding continued in `kappa` or `nu`, with the
//! eigenvalues at every point and the located bifurcations. Rows are written
//! as they are computed.

use super::{describe_params, SceneArgs, Setup};
use crate::analysis::branch::{trace, BranchRequest};
use crate::analysis::hopf::{find_hopf, stable_stiffness, HopfOutcome};
use crate::error::{Error, InputError};
use crate::model::{full_state, DrivenBlock};
use crate::params::{Param, Params};
use clap::{Args, ValueEnum};
use continuation::{BranchPoint, EventKind};
use std::io::Write;

#[derive(ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
pub enum BranchParam {
    Kappa,
    Nu,
}

#[derive(Args, Debug)]
pub struct BranchArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// The continuation parameter.
    #[arg(long, value_enum)]
    pub param: BranchParam,
    #[arg(allow_hyphen_values = true)]
    /// Start value (default: kappa — a stable stiffness; nu — the bottom of the scene's velocity range).
    #[arg(long)]
    pub from: Option<f64>,
    #[arg(allow_hyphen_values = true)]
    /// End value (default: kappa — 1e-3 of the start; nu — the top of the scene's velocity range).
    #[arg(long)]
    pub to: Option<f64>,
    /// Largest number of continuation steps. A branch that ends before
    /// `--to` (this limit, or a turn) keeps its rows and exits with status 4
    /// (partial).
    #[arg(long, default_value_t = 2000)]
    pub max_steps: usize,
    /// Comma-separated values instead of an aligned table.
    #[arg(long)]
    pub csv: bool,
}

/// Runs the command.
pub fn run(args: &BranchArgs) -> Result<(), Error> {
    let param = match args.param {
        BranchParam::Kappa => Param::Kappa,
        BranchParam::Nu => Param::Nu,
    };
    // For a velocity branch, inertia is judged at the fastest velocity of the range.
    let scene = crate::scene::load(&args.scene.scene)?;
    let (nu_lo, nu_hi) = scene.nu_range;
    let top = args.to.unwrap_or(nu_hi).max(args.from.unwrap_or(nu_lo));
    let setup = args.scene.setup(|p| {
        let mut q = *p;
        if param == Param::Nu {
            q.nu = top;
        }
        q
    })?;
    let kind = setup.choice.kind;
    let from = match (args.from, param) {
        (Some(v), _) => v,
        (None, Param::Kappa) => {
            stable_stiffness(&DrivenBlock::new(kind, &setup.params), kind, &setup.params)?
        }
        (None, _) => nu_lo,
    };
    let to = match (args.to, param) {
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
    if param == Param::Nu && setup.params.kappa <= 0.0 {
        return Err(no_stiffness(&setup).into());
    }
    if from == to {
        return Err(InputError::Conflict(format!(
            "--from and --to are equal ({from}); give a range"
        ))
        .into());
    }
    let mut out = std::io::stdout().lock();
    let names = ["s", "v", "theta"];
    if args.csv {
        writeln!(out, "# model: {}", setup.choice.reason)?;
        writeln!(out, "{},s,v,theta,n_unstable,eig_re_1,eig_im_1,eig_re_2,eig_im_2,eig_re_3,eig_im_3,event,omega", param.name())?;
    } else {
        writeln!(
            out,
            "scene: {} — {}",
            setup.scene.name, setup.scene.description
        )?;
        writeln!(out, "model: {}", setup.choice.reason)?;
        writeln!(out, "parameters: {}", describe_params(&setup.params))?;
        writeln!(
            out,
            "continuing steady sliding in {} from {from:.6e} to {to:.6e}",
            param.name()
        )?;
        writeln!(
            out,
            "{:>14} {:>14} {:>12} {:>12} {:>3}  eigenvalues",
            param.name(),
            names[0],
            names[1],
            names[2],
            "#u"
        )?;
    }
    let req = BranchRequest {
        param,
        from,
        to,
        max_steps: args.max_steps,
    };
    let params = setup.params;
    let short = trace(kind, &params, &req, |point| {
        for e in &point.events {
            let omega = match e.kind {
                EventKind::Hopf { omega } => omega,
                EventKind::Fold { .. } => f64::NAN,
            };
            let at = params.with_vec(&e.p);
            write_row(
                &mut out,
                args.csv,
                &at,
                kind,
                param,
                &e.x,
                &e.eigenvalues,
                None,
                Some((e.kind.name(), omega)),
            )?;
        }
        let at = params.with_vec(&point.p);
        write_row(
            &mut out,
            args.csv,
            &at,
            kind,
            param,
            &point.x,
            &point.eigenvalues,
            Some(point),
            None,
        )?;
        Ok(())
    })?;
    match short {
        None => Ok(()),
        Some(last) => Err(Error::Partial(format!(
            "the branch ended at {} = {last:.10e}, before --to {to:.6e}: the step limit \
             (--max-steps {}) or a turn of the branch; raise --max-steps or check the range",
            param.name(),
            args.max_steps
        ))),
    }
}

/// The refusal of a velocity branch without a stiffness, with `kappa_c` at
/// the scene's velocity (located as by `stickslip hopf`) as a hint.
fn no_stiffness(setup: &Setup) -> InputError {
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
        "branch --param nu needs a stiffness: kappa = 0 here (the scene gives no K), and without a \
         spring steady sliding has a zero eigenvalue at every velocity (no isolated equilibrium to \
         continue); give --set kappa=... (kappa = K D0/W){hint}"
    ))
}

#[allow(clippy::too_many_arguments)]
fn write_row(
    out: &mut impl Write,
    csv: bool,
    at: &Params,
    kind: crate::model::ModelKind,
    param: Param,
    x: &[f64],
    ev: &[continuation::Complex64],
    point: Option<&BranchPoint>,
    event: Option<(&str, f64)>,
) -> Result<(), Error> {
    let state = full_state(kind, at, x);
    let value = at.get(param);
    let n_unstable = ev.iter().filter(|l| l.re > 0.0).count();
    if csv {
        let mut cells = vec![format!("{value:.15e}")];
        cells.extend(state.iter().map(|v| format!("{v:.15e}")));
        cells.push(n_unstable.to_string());
        for i in 0..3 {
            match ev.get(i) {
                Some(l) => cells.extend([format!("{:.15e}", l.re), format!("{:.15e}", l.im)]),
                None => cells.extend([String::new(), String::new()]),
            }
        }
        match event {
            Some((name, omega)) if omega.is_finite() => {
                cells.extend([name.to_string(), format!("{omega:.15e}")])
            }
            Some((name, _)) => cells.extend([name.to_string(), String::new()]),
            None => cells.extend([String::new(), String::new()]),
        }
        writeln!(out, "{}", cells.join(","))?;
    } else {
        let evs: Vec<String> = ev
            .iter()
            .map(|l| format!("{:+.4e}{:+.4e}i", l.re, l.im))
            .collect();
        let tag = match event {
            Some((name, omega)) if omega.is_finite() => {
                format!("  <- {} (omega = {omega:.10e})", name.to_uppercase())
            }
            Some((name, _)) => format!("  <- {}", name.to_uppercase()),
            None => String::new(),
        };
        let _ = point;
        writeln!(
            out,
            "{:>14.8e} {:>14.8e} {:>12.6e} {:>12.6e} {:>3}  {}{}",
            value,
            state[0],
            state[1],
            state[2],
            n_unstable,
            evs.join("  "),
            tag
        )?;
    }
    Ok(())
}
