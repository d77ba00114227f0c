//! The command line: `stickslip hopf`, `stickslip branch`, `stickslip scenes`.
//!
//! Human-readable text by default; `--json` / `--csv` for machines. Bad input
//! exits with status 2, a numerical failure with status 3, partial results
//! (kept, but the request incomplete) with status 4, a write error with
//! status 1, Ctrl-C with 130 and SIGTERM with 143 (results kept).

pub mod branch;
pub mod csv;
pub mod cycle_start;
pub mod cycles;
pub mod cycles_in;
pub mod diagram;
pub mod files;
pub mod hopf;
pub mod interrupt;
pub mod lpc_output;
pub mod records;
pub mod simulate;

use crate::analysis::hopf::{find_hopf, Criticality, HopfOutcome};
use crate::analysis::model_choice::{
    choose_model, inertia_decides, params_for, ModelChoice, DEFAULT_INERTIA_THRESHOLD,
};
use crate::error::{Error, InputError};
use crate::model::ModelKind;
use crate::overrides::Overrides;
use crate::params::{Param, Params};
use crate::scene::{self, Scene};
use clap::{Args, Parser, Subcommand, ValueEnum};

/// Bifurcation analysis of frictional sliding: when does steady sliding of a
/// spring-driven block turn into stick-slip?
#[derive(Parser, Debug)]
#[command(
    name = "stickslip",
    version,
    about,
    long_about = None,
    after_help = "Exit status: 0 everything requested was delivered; 1 cannot write output; \
                  2 bad input (the message names the field); 3 numerical failure; \
                  4 partial results (kept, but the request is incomplete: a step limit, or a \
                  branch that failed after some results; the reason on stderr and, with \
                  --json, complete: false and stop); 130 interrupted by Ctrl-C (SIGINT), \
                  143 stopped by SIGTERM (results so far kept, the CSV ends with a \
                  '# incomplete' line)."
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

// Each analysis accepts negative numbers as option values, so that
// `--kappa-fraction -1` reaches the range check that names the field.
#[derive(Subcommand, Debug)]
pub enum Command {
    /// Locate the stick-slip onset (Hopf point) in the stiffness, or in any control parameter (--param V, M, W, ...), and compare with Appendix C.
    #[command(allow_negative_numbers = true)]
    Hopf(hopf::HopfArgs),
    /// Continue steady sliding in kappa, nu or a control parameter in its unit (K, V, M, ...); print eigenvalues and located bifurcations.
    #[command(allow_negative_numbers = true)]
    Branch(branch::BranchArgs),
    /// Trace the stability diagram (Hopf curve in stiffness and velocity) with onset types; write figures, CSV, JSON.
    #[command(allow_negative_numbers = true)]
    Diagram(diagram::DiagramArgs),
    /// Continue stick-slip cycles in the stiffness (or --param V, M, ...), from the Hopf point or from a simulated orbit; figures and data.
    #[command(allow_negative_numbers = true)]
    Cycles(cycles::CyclesArgs),
    /// Integrate driven sliding in time under a protocol of pulling velocities (jumps, stop-and-go).
    #[command(allow_negative_numbers = true)]
    Simulate(simulate::SimulateArgs),
    /// List the built-in scenes.
    Scenes,
}

/// Options shared by every analysis: which scene, overrides, which model.
#[derive(Args, Debug, Clone)]
pub struct SceneArgs {
    /// A built-in scene name (see `stickslip scenes`) or a path to a TOML scene file.
    #[arg(long, default_value = scene::DEFAULT_SCENE)]
    pub scene: String,
    /// Override a parameter, repeatable. Dimensionless (docs/model.md): kappa, nu, m, A, B,
    /// mu0, mu2, theta_c. Or a scene key in its physical unit, applied before the scene is made
    /// dimensionless: K [N/m], M [kg], W [N], V [um/s], V0 [um/s], D0 [um], tau [s],
    /// g [m/s^2], V_range=LO:HI [um/s] (e.g. K=2e5 gives kappa = K D0/W with the scene's D0
    /// and W; W=600 changes kappa and m). One quantity both ways (K and kappa, M and m, V
    /// and nu, tau and theta_c) is refused. theta_c or tau selects the cutoff ageing form,
    /// mu2 the ln² form.
    #[arg(long = "set", value_name = "NAME=VALUE")]
    pub set: Vec<String>,
    /// Force the model instead of choosing from the inertia ratio m nu^2 / mu_v.
    #[arg(long, value_enum)]
    pub model: Option<ModelArg>,
    /// Inertia is dropped (quasi-static model) when m nu^2 / mu_v is below this.
    #[arg(long, default_value_t = DEFAULT_INERTIA_THRESHOLD)]
    pub inertia_threshold: f64,
}

/// Units of the text output.
#[derive(ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
pub enum TextUnits {
    /// K/W in 1/m, periods in s, slip velocities in µm/s.
    Physical,
    /// kappa, periods in D0/V0, v/V0 (docs/model.md).
    Dimensionless,
}

impl TextUnits {
    /// A stiffness given as `kappa` and as `K/W` (a record's two fields) in
    /// these units, `K/W = ... 1/m` or `kappa = ...`, with `digits` decimals.
    pub fn stiffness(self, kappa: f64, k_over_w: f64, digits: usize) -> String {
        match self {
            TextUnits::Physical => format!("K/W = {k_over_w:.digits$e} 1/m"),
            TextUnits::Dimensionless => format!("kappa = {kappa:.digits$e}"),
        }
    }
}

#[derive(ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
pub enum ModelArg {
    Inertial,
    QuasiStatic,
}

impl From<ModelArg> for ModelKind {
    fn from(m: ModelArg) -> Self {
        match m {
            ModelArg::Inertial => ModelKind::Inertial,
            ModelArg::QuasiStatic => ModelKind::QuasiStatic,
        }
    }
}

/// A scene with overrides applied and the model chosen.
pub struct Setup {
    pub scene: Scene,
    /// The scene's parameters after `--set` (inertia kept).
    pub scene_params: Params,
    /// The parameters the chosen model uses (`m = 0` when quasi-static).
    pub params: Params,
    pub choice: ModelChoice,
    /// The scene's name with its overrides, for figure titles:
    /// `pmma (kappa=0.009, m=0.01)` ([`files::canonical_overrides`]).
    pub label: String,
    /// The `--set` overrides, parsed (both kinds).
    pub overrides: Overrides,
}

impl Setup {
    /// Whether the rig's own stiffness is given (by the scene's `K` or a
    /// `--set` of `K` or `kappa`): the commands then place it against the onset.
    pub fn stiffness_given(&self) -> bool {
        self.scene.stiffness_given || self.overrides.sets_stiffness()
    }
}

impl SceneArgs {
    /// Loads the scene, applies `--set`, validates, and chooses the model for `params_at`
    /// (a hook to evaluate the choice at another velocity, e.g. the top of a range).
    pub fn setup(&self, params_at: impl Fn(&Params) -> Params) -> Result<Setup, Error> {
        if !(self.inertia_threshold.is_finite() && self.inertia_threshold >= 0.0) {
            return Err(InputError::out_of_range(
                "--inertia-threshold",
                self.inertia_threshold,
                ">= 0",
            )
            .into());
        }
        let overrides = Overrides::parse(&self.set)?;
        let scene = scene::load_with(&self.scene, &overrides.physical())?;
        for warning in scene.implausible() {
            eprintln!("warning: scene {}: {warning}", scene.name);
        }
        let mut scene_params = scene.params;
        overrides.apply_dimensionless(&mut scene_params)?;
        let choice = choose_model(
            &params_at(&scene_params),
            self.model.map(Into::into),
            self.inertia_threshold,
        );
        if choice.kind == ModelKind::Inertial && scene_params.m <= 0.0 {
            let why = if overrides.sets("m") {
                "--set m=0; give m > 0"
            } else if overrides.sets("M") {
                "--set M=0; give M > 0"
            } else {
                "M = 0 in the scene; give M > 0 or --set m=..."
            };
            return Err(InputError::Conflict(format!(
                "the inertial model needs inertia: m = 0 here ({why}), or use --model quasi-static"
            ))
            .into());
        }
        let params = params_for(choice.kind, &scene_params);
        let shown: Vec<String> = files::canonical_overrides(&self.set)
            .into_iter()
            .map(|(k, v)| format!("{k}={v}"))
            .collect();
        let label = if shown.is_empty() {
            scene.name.clone()
        } else {
            format!("{} ({})", scene.name, shown.join(", "))
        };
        Ok(Setup {
            scene,
            scene_params,
            params,
            choice,
            label,
            overrides,
        })
    }
}

/// Locates the onset; when the scene has some inertia that the automatic
/// choice dropped and dropping it changes the onset type (the quasi-static
/// onset degenerate, as for the plain RR law, or of the other sign), that
/// inertia decides ([`inertia_decides`]): the inertial onset is the answer
/// and the reason says so. An inertial onset that cannot be located leaves
/// the quasi-static one.
pub fn onset_with_degeneracy_resolved(
    setup: &mut Setup,
    model_forced: bool,
) -> Result<HopfOutcome, Error> {
    let outcome = find_hopf(setup.choice.kind, &setup.params)?;
    let mut inertial = None;
    let choice = inertia_decides(&setup.choice, model_forced, setup.scene_params.m, || {
        let HopfOutcome::Found(h) = &outcome else {
            return None;
        };
        let HopfOutcome::Found(hi) = find_hopf(ModelKind::Inertial, &setup.scene_params).ok()?
        else {
            return None;
        };
        let changed = h.onset.criticality == Criticality::Degenerate
            || hi.onset.criticality != h.onset.criticality;
        inertial = Some(hi);
        Some((usize::from(changed), 1))
    });
    match (choice, inertial) {
        (Some(choice), Some(h)) => {
            setup.choice = choice;
            setup.params = setup.scene_params;
            Ok(HopfOutcome::Found(h))
        }
        _ => Ok(outcome),
    }
}

/// Runs the parsed command line, writing to standard output.
pub fn run(cli: Cli) -> Result<(), Error> {
    match cli.command {
        Command::Hopf(args) => hopf::run(&args),
        Command::Branch(args) => branch::run(&args),
        Command::Diagram(args) => diagram::run(&args),
        Command::Cycles(args) => cycles::run(&args),
        Command::Simulate(args) => simulate::run(&args),
        Command::Scenes => {
            for name in scene::builtin_names() {
                if let Some(s) = scene::builtin(name) {
                    println!("{name:10} {}", s.description);
                }
            }
            Ok(())
        }
    }
}

/// `v` with five significant digits: fixed notation between `1e-3` and
/// `1e6`, scientific outside (a small velocity is never printed as `0.0000`).
pub fn significant(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 || !a.is_finite() {
        return format!("{v}");
    }
    if (1e-3..1e6).contains(&a) {
        let decimals = (4 - a.log10().floor() as i32).max(0) as usize;
        format!("{v:.decimals$}")
    } else {
        format!("{v:.4e}")
    }
}

/// Formats parameters as `name = value` pairs on one line.
pub fn describe_params(p: &Params) -> String {
    describe_params_except(p, None)
}

/// [`describe_params`] without the parameter `left_out`.
pub fn describe_params_except(p: &Params, left_out: Option<Param>) -> String {
    let left_out = left_out.map(Param::name);
    p.named()
        .iter()
        .filter(|(n, _)| Some(*n) != left_out)
        .map(|(n, v)| format!("{n} = {v:.6e}"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Parameters as a JSON object (names of docs/model.md).
pub fn params_json(p: &Params) -> serde_json::Value {
    serde_json::Value::Object(
        p.named()
            .into_iter()
            .map(|(n, v)| (n.to_string(), serde_json::json!(v)))
            .collect(),
    )
}
