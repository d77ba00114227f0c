//! `stickslip cycles`: the stick-slip cycles born at the Hopf point (or
//! through a simulated orbit, [`super::cycle_start`]), continued in the
//! stiffness; the bifurcation diagram, orbits and time series.

use super::csv::{header, row};
use super::cycle_start::Start;
use super::files::{with_suffix, OutputArgs};
use super::lpc_output::{lpc_summary, write_lpc_csv};
use super::records::cycle::{Asked, Cycle, CycleDetail, CycleSpecialPoint, LegStop, Requested};
use super::records::diagram::FoldPoint;
use super::{params_json, SceneArgs, Setup, TextUnits};
use crate::analysis::control::Control;
use crate::analysis::cycles::{
    along_branch, collocation_for, requested_points, BranchEnds, CycleBifurcation, CycleRecord,
    CycleRequest, Stability,
};
use crate::analysis::lpc_curve::{lpc_curve_through, LpcCurves, LpcStop};
use crate::analysis::orbit_inertia::InertiaWatch;
use crate::appendix_c;
use crate::error::{Error, InputError};
use crate::model::ModelKind;
use crate::params::Param;
use crate::plot::lines::{
    render, render_family, vertical_marker, Colorbar, LineFigure, Series, SWITCH_MARKER,
};
use crate::plot::PlotError;
use crate::scene::Units;
use clap::Args;
use continuation::periodic::mesh::CollocationPoints;
use plotters::style::RGBColor;
use serde_json::json;
use std::io::Write;
use std::path::{Path, PathBuf};

#[derive(Args, Debug)]
pub struct CyclesArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Stop when the stiffness falls below this fraction of kappa_c (without a Hopf
    /// point: of the stiffness of the simulated orbit the branch starts from).
    #[arg(long, default_value_t = 0.5)]
    pub kappa_fraction: f64,
    /// Start from a simulated stick-slip orbit instead of the Hopf point (automatic
    /// when there is no Hopf point). The stiffness simulated: the scene's kappa when
    /// it gives one and a simulation from a stuck state settles on a cycle there;
    /// else 0.9 kappa_c below a Hopf point; else max(A, B) 10^-k, k = 1..5, the
    /// first that settles. The branch is followed toward larger stiffness (where a
    /// cycle coexisting with stable sliding ends at a fold of cycles, LPC) and then
    /// toward smaller stiffness.
    #[arg(long)]
    pub from_simulation: bool,
    /// Largest number of continuation steps, i.e. cycles after the first
    /// (per leg from a simulated orbit, and counted afresh after a switch to
    /// the inertial model); the branch usually ends first, at
    /// the requested range. Reaching it keeps the cycles and exits with
    /// status 4 (partial).
    #[arg(long, default_value_t = 500)]
    pub max_steps: usize,
    /// Initial number of mesh intervals (grown automatically when needed).
    #[arg(long, default_value_t = 40)]
    pub ntst: usize,
    /// Most mesh intervals the automatic refinement may use (the cost grows with it).
    #[arg(long, default_value_t = 12800)]
    pub ntst_max: usize,
    /// Collocation points instead of the model's choice (Radau IIA for the
    /// inertial block, whose velocity relaxes stiffly while it sticks; Gauss
    /// for the quasi-static one).
    #[arg(long, value_enum)]
    pub collocation: Option<Points>,
    /// Continue every fold of cycles (LPC) found on the branch in two
    /// parameters, (kappa, nu), across the scene's velocity range (widened to
    /// a factor 2 around the fold): the
    /// boundary of the hysteretic region. Writes -lpc-curve.csv and
    /// -lpc-curve.png/.svg, and `lpc_curve` in the JSON.
    #[arg(long)]
    pub lpc_curve: bool,
    /// Comma-separated stiffnesses at which cycles are located exactly and
    /// reported, as dimensionless kappa = K D0/W (the K/W of the text times
    /// D0); each is reported with both.
    #[arg(long, value_name = "K1,K2,...", value_delimiter = ',')]
    pub at_kappa: Vec<f64>,
    /// Stiffnesses at which cycles are located exactly and reported, in a
    /// unit of your choice: NAME=V1,V2,... with NAME kappa (dimensionless,
    /// as --at-kappa), K (N/m, kappa = K D0/W with the scene's D0 and W) or
    /// K_over_W (1/m, kappa = (K/W) D0). Repeatable; a value given twice
    /// (in any unit, within 1e-12 relative) is reported once. Each
    /// requested point carries the value as asked.
    #[arg(long, value_name = "NAME=V1,V2,...")]
    pub at: Vec<String>,
    /// The parameter the cycles are continued in: K [N/m], V [um/s], M [kg],
    /// tau [s], or kappa, nu, m, A, B, mu2, theta_c (default: the
    /// stiffness, as without it). Other than K or kappa it needs --to;
    /// the branch starts at the Hopf point in that parameter (hopf --param)
    /// or, with --from-simulation, from an orbit simulated at the scene's
    /// value; writes <run>-cycles-in-P.csv (no figures) and --at P=V1,...
    /// takes values of P.
    #[arg(long, value_name = "P")]
    pub param: Option<String>,
    /// With --param: where the branch ends, in the unit of P (for K or
    /// kappa: in place of --kappa-fraction).
    #[arg(long, allow_hyphen_values = true)]
    pub to: Option<f64>,
    /// With --param other than K or kappa: the range LO:HI (unit of P)
    /// where the Hopf point in P is searched (default: the scene's V_range
    /// for V and nu, three decades either side of the scene's value
    /// otherwise, widened to include --to).
    #[arg(long, value_name = "LO:HI")]
    pub search: Option<String>,
    #[command(flatten)]
    pub output: OutputArgs,
    /// Print one JSON object instead of text.
    #[arg(long)]
    pub json: bool,
    /// Units of the text lines: physical (K/W in 1/m, period in s, slip
    /// velocity in µm/s) or dimensionless (kappa, period in D0/V0, v/V0).
    /// The CSV and the JSON carry both.
    #[arg(long, value_enum, default_value_t = TextUnits::Physical)]
    pub units: TextUnits,
}

/// `--collocation` values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Points {
    Gauss,
    Radau,
}

impl From<Points> for CollocationPoints {
    fn from(p: Points) -> Self {
        match p {
            Points::Gauss => CollocationPoints::Gauss,
            Points::Radau => CollocationPoints::Radau,
        }
    }
}

/// `value` in the text output (`{:.1e}`), or `n/a (why)` when unavailable.
fn or_na(value: Option<f64>, why: &str) -> String {
    value.map_or_else(|| format!("n/a ({why})"), |v| format!("{v:.1e}"))
}

/// Reads `--search LO:HI`.
pub fn search_range(args: &CyclesArgs) -> Result<Option<(f64, f64)>, InputError> {
    let Some(text) = &args.search else {
        return Ok(None);
    };
    let bad = || InputError::Malformed {
        field: "--search".into(),
        value: text.clone(),
        expected: "LO:HI, two numbers > 0 in the unit of --param".into(),
    };
    let (lo, hi) = text.split_once(':').ok_or_else(bad)?;
    let (lo, hi): (f64, f64) = (
        lo.trim().parse().map_err(|_| bad())?,
        hi.trim().parse().map_err(|_| bad())?,
    );
    Ok(Some((lo, hi)))
}

/// Runs the command.
pub fn run(args: &CyclesArgs) -> Result<(), Error> {
    let control = Control::from_param(args.param.as_deref())?;
    if let Some(c) = control.filter(|c| !c.is_stiffness()) {
        return super::cycles_in::run(args, c);
    }
    if args.to.is_some() && control.is_none() {
        return Err(InputError::Conflict(
            "--to ends a branch in --param; without it the branch is in the stiffness and ends \
             at --kappa-fraction of its start"
                .into(),
        )
        .into());
    }
    if args.search.is_some() {
        return Err(InputError::Conflict(
            "--search is where the Hopf point in --param V, M, tau, nu, m, ... is searched; \
             the onset in the stiffness is searched from a stable stiffness downward"
                .into(),
        )
        .into());
    }
    if !(args.kappa_fraction > 0.0 && args.kappa_fraction < 1.0) {
        return Err(
            InputError::out_of_range("--kappa-fraction", args.kappa_fraction, "in (0, 1)").into(),
        );
    }
    if let Some(k) = args.at_kappa.iter().find(|k| !(k.is_finite() && **k > 0.0)) {
        return Err(InputError::out_of_range("--at-kappa", *k, "> 0").into());
    }
    let asked = asked_stiffnesses(&args.at_kappa, &args.at)?;
    if args.ntst < 4 {
        return Err(InputError::out_of_range("--ntst", args.ntst as f64, ">= 4").into());
    }
    if args.ntst_max < args.ntst {
        return Err(InputError::out_of_range(
            "--ntst-max",
            args.ntst_max as f64,
            &format!(">= --ntst ({})", args.ntst),
        )
        .into());
    }
    let mut setup = args.scene.setup(|p| *p)?;
    let onset = super::onset_with_degeneracy_resolved(&mut setup, args.scene.model.is_some())?;
    let start = Start::choose(&setup, onset, args.from_simulation)?;
    if !args.json {
        // What is computed, as `hopf` and `diagram` open: the scene, the
        // model, and where the branch starts.
        println!("scene: {} — {}", setup.scene.name, setup.scene.description);
        println!("model: {}", setup.choice.reason);
        println!("{}", start.describe(&setup, args.units));
    }
    let points = args
        .collocation
        .map_or(collocation_for(setup.choice.kind), Into::into);
    args.output.create_dir()?;
    let stem = with_suffix(
        &args
            .output
            .stem(&setup.scene.name, &args.scene, false, OUTPUTS)?,
        "-cycles",
    );
    if !args.json {
        println!("{}", numerics(points, args.collocation.is_some(), &setup));
    }
    let csv_path = with_suffix(&stem, ".csv");
    let units = setup.scene.units;
    let mut csv = crate::cli::files::create_file(&csv_path)?;
    writeln!(
        csv,
        "# scene {}; model at the start {} (column model: each row's); collocation {}; stable: \
         true, false, or undecidable (a nontrivial multiplier within its error of the unit \
         circle); n/a: not available (the JSON gives the reason)",
        setup.scene.name,
        setup.choice.reason,
        points_name(points)
    )?;
    writeln!(csv, "{}", header::<Cycle>()?)?;
    let (at_kappa, asked) = requested_once(&asked, &units);
    let kappa_ref = start.reference_kappa();
    // --param K or kappa with --to: the branch ends there (kappa).
    let to = match (control, args.to) {
        (Some(c), Some(t)) if t.is_finite() && t > 0.0 => {
            Some(c.to_dimensionless(&units, &setup.scene_params, t))
        }
        (Some(_), Some(t)) => {
            return Err(InputError::out_of_range("--to", t, "> 0 (unit of --param)").into())
        }
        _ => None,
    };
    let mut req = CycleRequest {
        kappa_min: to.map_or(args.kappa_fraction * kappa_ref, |t| t.min(kappa_ref)),
        kappa_max: to.map_or(10.0 * kappa_ref, |t| t.max(10.0 * kappa_ref)),
        max_steps: args.max_steps,
        ntst: args.ntst,
        at_kappa,
        ntst_max: args.ntst_max,
        // Each model's own points unless forced (the branch may change model).
        collocation: args.collocation.map(Into::into),
    };
    let threshold = args.scene.inertia_threshold;
    let watch = InertiaWatch::new(&setup.scene_params, threshold, args.scene.model.is_none());
    let mut switch: Option<ModelSwitch> = None;
    // Requested stiffnesses outside the default range extend the branch to them.
    req.cover_requested();
    let mut records: Vec<CycleRecord> = Vec::new();
    // Their records, built once for the CSV, the text and the JSON.
    let mut details: Vec<CycleDetail> = Vec::new();
    let mut specials: Vec<CycleSpecialPoint> = Vec::new();
    super::interrupt::catch_interrupts();
    let bar = super::interrupt::progress("continuing cycles");
    let outcomes = start.trace(&setup, &req, &watch, |c| {
        if super::interrupt::interrupted() {
            return Err(super::interrupt::stopped(match records.last() {
                Some(r) => format!(
                    "after {} cycles, the last at kappa = {:.10e}",
                    records.len(),
                    r.kappa
                ),
                None => "before the first cycle".to_string(),
            }));
        }
        bar.set_message(format!(
            "{} cycles, kappa = {:.6e}, NTST {}",
            records.len() + 1,
            c.kappa,
            c.ntst
        ));
        if let Some(prev) = records.last().filter(|p| p.model != c.model) {
            let sw = ModelSwitch {
                kappa: c.kappa,
                inertial_imbalance: prev.inertial_imbalance,
                threshold,
            };
            if !args.json {
                println!("{}", sw.describe());
            }
            switch = Some(sw);
        }
        // The cycles at requested stiffnesses passed since the last one, then it.
        for rec in c.user.iter().chain([c]) {
            let detail = CycleDetail::new(rec, &units);
            let cycle = &detail.cycle;
            write_row(&mut csv, cycle)?;
            let found: Vec<CycleSpecialPoint> = rec
                .special_points()
                .map(|(kind, l)| CycleSpecialPoint {
                    kind,
                    cycle: Cycle::new(l, &units),
                })
                .collect();
            if !args.json {
                print_cycle(args.units, cycle, &found);
            }
            specials.extend(found);
            details.push(detail);
            records.push(rec.clone());
        }
        Ok(())
    });
    bar.finish_and_clear();
    if let Some(warning) = validity_warning(&records, &setup, &watch, args.scene.model.is_some()) {
        eprintln!("warning: {warning}");
    }
    let unphysical = NegativeFriction::of(&records);
    if let Some(n) = &unphysical {
        eprintln!("warning: {}", n.describe());
    }
    let leg_stops: Vec<LegStop> = outcomes
        .iter()
        .map(|(leg, outcome)| LegStop::new(*leg, outcome, args.max_steps))
        .collect();
    let legs_complete = leg_stops.iter().all(LegStop::complete);
    let stop = leg_stops
        .iter()
        .map(ToString::to_string)
        .collect::<Vec<_>>()
        .join("; ");
    // Whatever was computed is kept and drawn, even when the branch stopped
    // on an error; then the figures say so.
    let cut = if super::interrupt::interrupted() {
        Some(" — interrupted")
    } else if !legs_complete {
        Some(" — stopped before the requested range (see the stop reason)")
    } else {
        None
    };
    let files = if records.is_empty() {
        Vec::new()
    } else {
        write_figures(&setup, &along_branch(&records), &stem, cut)?
    };
    let mut lpc = if args.lpc_curve {
        fold_curves(&setup, &records, &stem, args)?
    } else {
        FoldCurves::default()
    };
    let files: Vec<PathBuf> = files.into_iter().chain(lpc.files.drain(..)).collect();
    let stop = match start.reason() {
        Some(_) => {
            "no branch: no Hopf point and no cycle found by simulation (see reason)".to_string()
        }
        None => stop,
    };
    let requested: Vec<Requested> = requested_points(
        &req.at_kappa,
        &records,
        &BranchEnds {
            hopf_start: match &start {
                Start::Hopf(h) => Some(h.kappa_c),
                _ => None,
            },
            stop: &stop,
            no_branch: start.reason(),
        },
    )
    .iter()
    .zip(&asked)
    .map(|(r, a)| Requested::new(r, *a, &units))
    .collect();
    // Partial: a leg ended short of its range, or the search for a start was
    // inconclusive. A requested value the branch did not reach is then among
    // what is missing; one where no cycle exists (above kappa_c, beyond a
    // fold, no branch at all) is answered by its reason.
    let undelivered = requested.iter().filter(|r| r.reason.is_some()).count();
    let complete = start.conclusive() && legs_complete && !lpc.incomplete && undelivered == 0;
    let mut stop = stop;
    if lpc.incomplete {
        let why: Vec<String> = lpc.stops.iter().map(ToString::to_string).collect();
        stop = format!(
            "{stop}; the fold-of-cycles curve is incomplete: {}",
            why.join("; ")
        );
    }
    if undelivered > 0 {
        stop = format!(
            "{stop}; {undelivered} of the {} requested stiffnesses not delivered (see requested_points)",
            requested.len()
        );
    }
    write_requested_csv(&mut csv, &requested)?;
    if !complete {
        // A script reading the CSV alone learns that it is not the whole branch.
        writeln!(csv, "# incomplete: {stop}")?;
        csv.flush()?;
    }
    csv.finish()?;
    if args.json {
        let v = json!({
            "scene": setup.scene.name,
            "model": setup.choice.kind,
            // The parameters of the last model used (the scene's inertia
            // after a switch to the inertial model).
            "params": params_json(&match switch {
                Some(_) => setup.scene_params,
                None => setup.params,
            }),
            "kappa_c": start.kappa_c(),
            "start": start.json(),
            "collocation": points_name(points),
            "units": {"D0_um": units.d0 * 1e6, "V0_um_per_s": units.velocity_um_s(1.0)},
            "cycles": details,
            "special_points": specials,
            "complete": complete,
            "stop": stop,
            "leg_stops": leg_stops,
            "model_switch": switch.as_ref().map(|s| json!({
                "kappa": s.kappa, "inertial_imbalance": s.inertial_imbalance, "threshold": s.threshold,
                "from": "quasi-static", "to": "inertial", "reason": s.describe(),
            })),
            "requested_points": requested,
            "lpc_curve": lpc.folds,
            "lpc_stops": lpc.stops,
            "files": files.iter().chain([&csv_path]).map(|f| f.display().to_string()).collect::<Vec<_>>(),
        });
        let mut v = v;
        if let Some(why) = start.reason() {
            v["reason"] = json!(why);
        }
        if let Some(n) = &unphysical {
            v["negative_friction"] = json!({
                "cycles": n.cycles, "of": records.len(), "kappa_range": [n.kappa_lo, n.kappa_hi],
                "friction_min": n.friction_min, "s_min": n.s_min, "reason": n.describe(),
            });
        }
        println!(
            "{}",
            serde_json::to_string_pretty(&v).map_err(std::io::Error::other)?
        );
    } else {
        println!("stopped: {stop}");
        // Stiffnesses as kappa (as asked) and as K/W (as the cycles' lines).
        let both = |kappa: f64, decimals: usize| {
            format!(
                "{kappa:.decimals$e} (K/W = {:.decimals$e} 1/m)",
                units.k_over_w(kappa)
            )
        };
        for r in &requested {
            let asked = match r.asked.name {
                "kappa" => format!(
                    "requested kappa = {:.10e} (K/W = {:.8e} 1/m)",
                    r.kappa, r.k_over_w_per_m
                ),
                _ => format!(
                    "requested {} (kappa = {:.10e}, K/W = {:.8e} 1/m, K = {:.8e} N/m)",
                    r.asked.describe(),
                    r.kappa,
                    r.k_over_w_per_m,
                    r.k_n_per_m
                ),
            };
            match &r.reason {
                None => println!(
                    "{asked}: delivered ({} cycle{})",
                    r.cycles,
                    if r.cycles == 1 { "" } else { "s" }
                ),
                Some(why) => println!("{asked}: not delivered: {}", why.describe(&both)),
            }
        }
        for f in files.iter().chain([&csv_path]) {
            println!("wrote {}", f.display());
        }
    }
    let mut errors = outcomes.into_iter().filter_map(|(_, o)| o.err());
    match errors.next() {
        // A signal, or a file that could not be written, is the run's answer.
        Some(e @ (Error::Interrupted(_) | Error::Output(_))) => Err(e),
        // Nothing kept: the failure is the answer (status 3); a run that
        // kept a cycle is partial (status 4).
        Some(e) if records.is_empty() => Err(e),
        _ if !complete => Err(Error::Partial(format!(
            "{} cycles written; stopped: {stop}",
            records.len()
        ))),
        _ => Ok(()),
    }
}

/// Cycles on which the friction coefficient, or the spring force that
/// balances it, falls below zero: the friction law outside its physical
/// range (a block pulled forward by friction), reported, not hidden.
struct NegativeFriction {
    cycles: usize,
    kappa_lo: f64,
    kappa_hi: f64,
    friction_min: f64,
    s_min: f64,
}

impl NegativeFriction {
    /// `None` when friction and spring force stay non-negative on every cycle.
    fn of(records: &[CycleRecord]) -> Option<Self> {
        let bad: Vec<&CycleRecord> = records
            .iter()
            .filter(|c| c.friction_min < 0.0 || c.s_min < 0.0)
            .collect();
        if bad.is_empty() {
            return None;
        }
        let least =
            |g: fn(&CycleRecord) -> f64| bad.iter().map(|c| g(c)).fold(f64::INFINITY, f64::min);
        Some(NegativeFriction {
            cycles: bad.len(),
            kappa_lo: least(|c| c.kappa),
            kappa_hi: -least(|c| -c.kappa),
            friction_min: least(|c| c.friction_min),
            s_min: least(|c| c.s_min),
        })
    }

    fn describe(&self) -> String {
        format!(
            "negative friction on {} cycles (kappa = {:.6e} .. {:.6e}): the friction coefficient \
             falls to {:.4e} and the spring force s to {:.4e}; the friction law is outside its \
             physical range there (e.g. mu2 < 0 makes mu fall without bound at long ages), so \
             these cycles are the model's, not a real interface's",
            self.cycles, self.kappa_lo, self.kappa_hi, self.friction_min, self.s_min
        )
    }
}

/// The stiffnesses asked for by `--at-kappa` (first) and `--at NAME=...`
/// (in the order given), as asked: each name one of [`Asked::NAMES`], each
/// value a finite number `> 0`; errors name the option and the name.
fn asked_stiffnesses(at_kappa: &[f64], at: &[String]) -> Result<Vec<Asked>, InputError> {
    let mut asked: Vec<Asked> = at_kappa
        .iter()
        .map(|&value| Asked {
            name: "kappa",
            value,
            unit: "1",
        })
        .collect();
    let allowed = || {
        Asked::NAMES
            .iter()
            .map(|(n, u)| format!("{n} [{u}]"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    for item in at {
        let (name, values) = item.split_once('=').ok_or_else(|| InputError::Malformed {
            field: "--at".into(),
            value: item.clone(),
            expected: format!("NAME=V1,V2,... with NAME one of {}", allowed()),
        })?;
        let name = name.trim();
        let Some(&(name, unit)) = Asked::NAMES.iter().find(|(n, _)| *n == name) else {
            return Err(InputError::UnknownName {
                what: "--at stiffness",
                name: name.to_string(),
                suggestion: crate::error::closest(name, Asked::NAMES.iter().map(|(n, _)| *n)),
                allowed: allowed(),
            });
        };
        let field = format!("--at {name}");
        for text in values.split(',') {
            let value: f64 = text.trim().parse().map_err(|_| InputError::Malformed {
                field: field.clone(),
                value: text.to_string(),
                expected: format!("a number ({unit})"),
            })?;
            if !(value.is_finite() && value > 0.0) {
                return Err(InputError::out_of_range(
                    &field,
                    value,
                    &format!("> 0 ({unit})"),
                ));
            }
            asked.push(Asked { name, value, unit });
        }
    }
    Ok(asked)
}

/// The stiffnesses asked for, each once (the first of values whose `kappa`
/// lie within `1e-12` relative of each other, in whatever unit each was
/// asked), in the order given: their `kappa` in the units `u`, and how
/// each was asked.
fn requested_once(asked: &[Asked], u: &Units) -> (Vec<f64>, Vec<Asked>) {
    let mut once: (Vec<f64>, Vec<Asked>) = (Vec::new(), Vec::new());
    for a in asked {
        let k = a.kappa(u);
        if !once.0.iter().any(|&q| (q - k).abs() <= 1e-12 * k.abs()) {
            once.0.push(k);
            once.1.push(*a);
        }
    }
    once
}

/// Where a quasi-static branch handed over to the inertial model.
struct ModelSwitch {
    /// The stiffness of the last quasi-static and the first inertial cycle.
    kappa: f64,
    /// `chi` on the last quasi-static cycle.
    inertial_imbalance: f64,
    threshold: f64,
}

impl ModelSwitch {
    fn describe(&self) -> String {
        format!(
            "switching to the inertial model at kappa = {:.8e}: on the last quasi-static cycle \
             inertia would shift ln v by chi = max m |dv/dt| / A = {:.3e} > {:.0e} (--inertia-threshold); \
             the same orbit, corrected with the scene's inertia, continues the branch",
            self.kappa, self.inertial_imbalance, self.threshold
        )
    }
}

/// Under `--model`, where the forced model is outside its validity: a
/// quasi-static model on cycles whose `chi` exceeds the threshold, or an
/// inertial one where inertia is negligible on every cycle.
fn validity_warning(
    records: &[CycleRecord],
    setup: &Setup,
    watch: &InertiaWatch,
    forced: bool,
) -> Option<String> {
    if !forced || records.is_empty() || setup.scene_params.m <= 0.0 {
        return None;
    }
    let outside: Vec<&CycleRecord> = records
        .iter()
        .filter(|c| c.model == ModelKind::QuasiStatic && c.inertial_imbalance > watch.threshold)
        .collect();
    if let (Some(first), Some(last)) = (outside.first(), outside.last()) {
        return Some(format!(
            "--model quasi-static is outside its validity on {} of {} cycles (kappa = {:.6e} .. {:.6e}): \
             there the scene's inertia would shift ln v by chi = max m |dv/dt| / A up to {:.3e} > {:.0e}; \
             without --model the branch switches to the inertial model",
            outside.len(),
            records.len(),
            first.kappa,
            last.kappa,
            outside.iter().map(|c| c.inertial_imbalance).fold(0.0, f64::max),
            watch.threshold
        ));
    }
    let largest = records
        .iter()
        .map(|c| c.inertial_imbalance)
        .fold(0.0, f64::max);
    (setup.choice.kind == ModelKind::Inertial
        && largest < watch.threshold
        && setup.choice.inertia_ratio < watch.threshold)
        .then(|| {
            format!(
                "inertia is negligible on every cycle (chi = max m |dv/dt| / A <= {largest:.3e} < {:.0e}, \
                 inertia ratio at onset {:.3e}): the quasi-static model would give the same cycles",
                watch.threshold, setup.choice.inertia_ratio
            )
        })
}

/// The requested stiffnesses without a cycle, as comment lines at the end of the CSV.
fn write_requested_csv(csv: &mut impl Write, requested: &[Requested]) -> Result<(), Error> {
    for r in requested {
        if let Some(why) = &r.reason {
            let asked = match r.asked.name {
                "kappa" => String::new(),
                _ => format!(" (asked as {})", r.asked.describe()),
            };
            writeln!(
                csv,
                "# requested kappa = {:.15e}{asked} not delivered: {why}",
                r.kappa
            )?;
        }
    }
    csv.flush()?;
    Ok(())
}

/// The curves of folds of cycles through the folds of a branch.
#[derive(Default)]
struct FoldCurves {
    /// Their points.
    folds: Vec<FoldPoint>,
    /// Why their ends stopped.
    stops: Vec<LpcStop>,
    /// Their CSV and figure.
    files: Vec<PathBuf>,
    /// Whether a curve did not start, or stopped short of its range other
    /// than at a Bautin point: the request (`--lpc-curve`) is incomplete.
    incomplete: bool,
}

/// The curves of folds of cycles through every fold on the branch, with
/// their files; the text output reports each curve.
fn fold_curves(
    setup: &Setup,
    records: &[CycleRecord],
    stem: &Path,
    args: &CyclesArgs,
) -> Result<FoldCurves, Error> {
    let mut curves = LpcCurves::default();
    let folds = records
        .iter()
        .flat_map(CycleRecord::special_points)
        .filter_map(|(kind, r)| {
            (kind == CycleBifurcation::Lpc)
                .then_some(r.orbit.as_ref())
                .flatten()
        });
    for fold in folds {
        // The scene's velocity range, widened to a factor 2 around the fold.
        let nu = fold.p[Param::Nu as usize];
        let (lo, hi) = setup.scene.nu_range;
        let range = (lo.min(0.5 * nu), hi.max(2.0 * nu));
        let c = lpc_curve_through(setup.choice.kind, &setup.params, fold, range);
        curves.points.extend(c.points);
        curves.stops.extend(c.stops);
        curves.incomplete |= c.incomplete;
    }
    let folds = FoldPoint::all(&curves, &setup.scene.units);
    if !args.json {
        for line in lpc_summary(&folds, &curves.stops, args.units) {
            println!("{line}");
        }
    }
    if folds.is_empty() {
        return Ok(FoldCurves {
            folds,
            stops: curves.stops,
            files: Vec::new(),
            incomplete: curves.incomplete,
        });
    }
    let mut files = vec![write_lpc_csv(stem, &setup.scene.name, &folds)?];
    let figure = LineFigure {
        title: format!(
            "Folds of cycles (hysteresis boundary), {}: stick-slip coexists with steady sliding below",
            setup.label
        ),
        x_label: "driving velocity V [µm/s]".into(),
        y_label: "K/W [1/m]".into(),
        log_x: true,
        log_y: true,
        series: folds
            .chunk_by(|a, b| a.curve == b.curve)
            .enumerate()
            .map(|(i, curve)| Series {
                label: (i == 0).then(|| "fold of cycles (LPC)".to_string()),
                points: curve
                    .iter()
                    .map(|p| (p.physical.v_um_per_s, p.physical.k_over_w_per_m))
                    .collect(),
                color: FOLD_COLOR,
                dashed: false,
                markers: false,
            })
            .chain(hopf_reference(setup, &folds))
            .collect(),
    };
    files.extend(
        render(&figure, &with_suffix(stem, "-lpc-curve"))
            .map_err(|e| Error::Output(std::io::Error::other(e.to_string())))?,
    );
    Ok(FoldCurves {
        folds,
        stops: curves.stops,
        files,
        incomplete: curves.incomplete,
    })
}

/// The Hopf curve over the velocities of the folds, for the figure:
/// `kappa_c` of Appendix C (the Hopf condition in closed form) at 200
/// velocities, where it is positive; `None` without folds.
fn hopf_reference(setup: &Setup, folds: &[FoldPoint]) -> Option<Series> {
    let nus = folds.iter().map(|p| p.nu);
    let (lo, hi) = nus.fold((f64::INFINITY, 0.0f64), |(a, b), nu| (a.min(nu), b.max(nu)));
    if !(lo.is_finite() && hi > lo) {
        return None;
    }
    let u = setup.scene.units;
    let points = (0..200)
        .filter_map(|i| {
            let mut at = setup.params;
            at.nu = lo * (hi / lo).powf(i as f64 / 199.0);
            let kappa_c = appendix_c::critical_stiffness(&at);
            (kappa_c > 0.0).then(|| (u.velocity_um_s(at.nu), u.k_over_w(kappa_c)))
        })
        .collect();
    Some(Series {
        label: Some("Hopf curve (critical stiffness, Appendix C)".into()),
        points,
        color: RGBColor(31, 90, 180),
        dashed: false,
        markers: false,
    })
}

/// `gauss` or `radau`.
fn points_name(points: CollocationPoints) -> &'static str {
    match points {
        CollocationPoints::Gauss => "gauss",
        CollocationPoints::Radau => "radau",
    }
}

/// What the numerics are and why: the collocation points, and how stability
/// is decided.
fn numerics(points: CollocationPoints, forced: bool, setup: &Setup) -> String {
    let why = match (forced, points) {
        (true, _) => "as asked (--collocation)",
        (false, CollocationPoints::Radau) => {
            "L-stable, for the stiff relaxation of the velocity while the block sticks"
        }
        (false, CollocationPoints::Gauss) => "no stiff component in the quasi-static model",
    };
    let stability = match setup.choice.kind {
        ModelKind::QuasiStatic => {
            "stability from the nontrivial multiplier exp(int_0^T tr J dt) (Liouville's formula \
             in the plane, as accurate as the collocation quadrature); |mu_1 - 1| checks the \
             Floquet pencil only"
        }
        ModelKind::Inertial => {
            "stability from the Floquet pencil; |mu_1 - 1| is its error at the trivial multiplier"
        }
    };
    format!(
        "collocation: {} points, degree {} ({why}); {stability}",
        match points {
            CollocationPoints::Gauss => "Gauss-Legendre",
            CollocationPoints::Radau => "Radau IIA",
        },
        continuation::periodic::branch::Discretization::default().degree
    )
}

/// One CSV row per cycle, flushed at once so an interrupted run keeps it.
fn write_row(csv: &mut impl Write, c: &Cycle) -> Result<(), Error> {
    writeln!(csv, "{}", row(c)?)?;
    csv.flush()?;
    Ok(())
}
/// The files `cycles` may write, after the run's stem.
const OUTPUTS: &[&str] = &[
    "-cycles.csv",
    "-cycles-amplitude.png",
    "-cycles-amplitude.svg",
    "-cycles-period.png",
    "-cycles-period.svg",
    "-cycles-orbits.png",
    "-cycles-orbits.svg",
    "-cycles-time-series.png",
    "-cycles-time-series.svg",
    "-cycles-lpc-curve.csv",
    "-cycles-lpc-curve.png",
    "-cycles-lpc-curve.svg",
];

/// Cycles drawn in the orbit and time-series figures (evenly along the
/// branch, and its last one).
const FAMILY_SIZE: usize = 10;

/// Marker colours of the bifurcations of cycles on amplitude and period plots.
const FOLD_COLOR: RGBColor = RGBColor(150, 60, 150);
const PD_COLOR: RGBColor = RGBColor(230, 140, 20);
const NS_COLOR: RGBColor = RGBColor(20, 150, 150);

/// The text lines of a cycle: a cycle at a requested stiffness on one
/// line; else the cycle, its stability and errors, and the bifurcations
/// `found` since the previous cycle.
fn print_cycle(units: TextUnits, cycle: &Cycle, found: &[CycleSpecialPoint]) {
    if cycle.user_point {
        println!("  user point {}", cycle_text(units, cycle));
        return;
    }
    println!(
        "{}  {}  |mu_1 - 1| {}  err {}  NTST {}",
        cycle_text(units, cycle),
        cycle.stable.word(),
        or_na(
            cycle.trivial_multiplier_error,
            "Floquet pencil singular to rounding"
        ),
        or_na(cycle.error_estimate, "no solution on half the mesh"),
        cycle.ntst
    );
    for s in found {
        println!("  {} at {}", s.kind.name(), cycle_text(units, &s.cycle));
    }
}

/// A cycle in the text units `units`: stiffness, period, `Delta_s` (a
/// friction coefficient either way) and the range of the slip velocity.
fn cycle_text(units: TextUnits, c: &Cycle) -> String {
    match units {
        TextUnits::Physical => format!(
            "K/W {:.8e} 1/m  period {:.6e} s  Delta_s {:.6e}  v {:.3e} .. {:.3e} µm/s",
            c.k_over_w_per_m, c.period_s, c.delta_s, c.v_min_um_per_s, c.v_max_um_per_s
        ),
        TextUnits::Dimensionless => format!(
            "kappa {:.8e}  period {:.6e}  Delta_s {:.6e}  v {:.3e} .. {:.3e}",
            c.kappa, c.period, c.delta_s, c.v_min, c.v_max
        ),
    }
}

/// Maps a cycle's sample `(t/T, s, v, theta)` to a plotted point.
type SamplePoint<'a> = dyn Fn(&CycleRecord, &[f64; 4]) -> (f64, f64) + 'a;

fn write_figures(
    setup: &Setup,
    records: &[&CycleRecord],
    stem: &Path,
    cut: Option<&str>,
) -> Result<Vec<PathBuf>, Error> {
    let u = setup.scene.units;
    let blue = RGBColor(31, 90, 180);
    let red = RGBColor(200, 40, 40);
    let grey = RGBColor(130, 130, 130);
    // Stable cycles solid blue, unstable dashed red, undecidable dashed grey;
    // each stretch starts at the last point of the one before.
    let style = |c: &CycleRecord| match c.stability {
        Stability::Stable => ("stable cycles", blue, false),
        Stability::Unstable => ("unstable cycles", red, true),
        _ => ("stability undecidable", grey, true),
    };
    let by_stability = |f: &dyn Fn(&CycleRecord) -> f64| -> Vec<Series> {
        let mut out: Vec<Series> = Vec::new();
        let mut labelled: Vec<&str> = Vec::new();
        let mut current = None;
        for c in records {
            let pt = (u.k_over_w(c.kappa), f(c));
            let (label, color, dashed) = style(c);
            match out.last_mut() {
                Some(s) if current == Some(label) => s.points.push(pt),
                _ => {
                    let mut points = out
                        .last()
                        .and_then(|s| s.points.last().copied())
                        .into_iter()
                        .collect::<Vec<_>>();
                    points.push(pt);
                    let label_text = (!labelled.contains(&label)).then(|| label.to_string());
                    labelled.push(label);
                    current = Some(label);
                    out.push(Series {
                        label: label_text,
                        points,
                        color,
                        dashed,
                        markers: false,
                    });
                }
            }
        }
        out
    };
    // Where the branch handed over from the quasi-static to the inertial model.
    let switch = records
        .windows(2)
        .find(|w| w[0].model != w[1].model)
        .map(|w| w[1].kappa);
    let title = match switch {
        Some(k) => format!(
            "Stick-slip cycles, {} (quasi-static → inertial model at K/W = {:.4e} 1/m){}",
            setup.label,
            u.k_over_w(k),
            cut.unwrap_or_default()
        ),
        None => format!(
            "Stick-slip cycles, {} ({} model){}",
            setup.label,
            records
                .first()
                .map_or(setup.choice.kind, |c| c.model)
                .name(),
            cut.unwrap_or_default()
        ),
    };
    // A vertical dashed line at the switch, over the data's range, and the
    // bifurcations located on the branch as markers.
    let with_marks = |mut series: Vec<Series>, f: &dyn Fn(&CycleRecord) -> f64| -> Vec<Series> {
        if let Some(k) = switch {
            let (color, label) = SWITCH_MARKER;
            series.push(vertical_marker(&series, u.k_over_w(k), label, color));
        }
        for (kind, color) in [
            (CycleBifurcation::Lpc, FOLD_COLOR),
            (CycleBifurcation::Pd, PD_COLOR),
            (CycleBifurcation::Ns, NS_COLOR),
        ] {
            let points: Vec<(f64, f64)> = records
                .iter()
                .flat_map(|c| c.special_points())
                .filter(|(k, _)| *k == kind)
                .map(|(_, c)| (u.k_over_w(c.kappa), f(c)))
                .collect();
            if !points.is_empty() {
                series.push(Series {
                    label: Some(kind.name().into()),
                    points,
                    color,
                    dashed: false,
                    markers: true,
                });
            }
        }
        series
    };
    let figures = [
        (
            "-amplitude",
            LineFigure {
                title: title.clone(),
                x_label: "K/W [1/m]".into(),
                y_label: "peak-to-peak spring force Δs = Δ(K x)/W".into(),
                log_x: false,
                log_y: false,
                series: with_marks(by_stability(&|c| c.delta_s), &|c| c.delta_s),
            },
        ),
        (
            "-period",
            LineFigure {
                title: title.clone(),
                x_label: "K/W [1/m]".into(),
                y_label: "period [s]".into(),
                log_x: false,
                log_y: false,
                series: with_marks(by_stability(&|c| c.period * u.d0 / u.v0), &|c| {
                    c.period * u.d0 / u.v0
                }),
            },
        ),
    ];
    let picks: Vec<&CycleRecord> = {
        let step = records.len().div_ceil(FAMILY_SIZE).max(1);
        let mut picks: Vec<&CycleRecord> = records.iter().step_by(step).copied().collect();
        // The last cycle (the end of the branch) is always shown.
        if let Some(&last) = records.last() {
            if !picks.last().is_some_and(|p| std::ptr::eq(*p, last)) {
                picks.push(last);
            }
        }
        picks
    };
    let bar = Colorbar::over("K/W [1/m]", picks.iter().map(|c| u.k_over_w(c.kappa)));
    // One curve per picked cycle, mapping each sample (t/T, s, v, theta) to
    // a point, coloured by its stiffness; unstable cycles dashed (not those
    // whose stability the multipliers cannot decide).
    let per_cycle = |point: &SamplePoint| -> Vec<Series> {
        picks
            .iter()
            .map(|c| Series {
                label: None,
                points: c.samples.iter().map(|p| point(c, p)).collect(),
                color: bar.color(u.k_over_w(c.kappa)),
                dashed: c.stability == Stability::Unstable,
                markers: false,
            })
            .collect()
    };
    let orbit = LineFigure {
        title: format!("Cycles in the (s, v) plane, {}", setup.label),
        x_label: "spring force s = K(Vt - x)/W".into(),
        y_label: "slip velocity v [µm/s]".into(),
        log_x: false,
        log_y: true,
        series: per_cycle(&|_, p| (p[1], u.velocity_um_s(p[2]))),
    };
    let series = LineFigure {
        title: format!("Spring force over one period, {}", setup.label),
        x_label: "time t [s]".into(),
        y_label: "spring force s".into(),
        log_x: false,
        log_y: false,
        series: per_cycle(&|c, p| (p[0] * c.period * u.d0 / u.v0, p[1])),
    };
    let plot_error = |e: PlotError| Error::Output(std::io::Error::other(e.to_string()));
    let mut files = Vec::new();
    for (suffix, fig) in &figures {
        files.extend(render(fig, &with_suffix(stem, suffix)).map_err(plot_error)?);
    }
    for (suffix, fig) in [("-orbits", orbit), ("-time-series", series)] {
        files.extend(render_family(&fig, &bar, &with_suffix(stem, suffix)).map_err(plot_error)?);
    }
    Ok(files)
}
