//! The command line: `stickslip hopf`, `stickslip branch`, `stickslip scenes`.
//!
//! Human-readable text by default; `--json` / `--csv` for machines. Bad input
//! exits with status 2, a numerical failure with status 3, partial results
//! (kept, but the request incomplete) with status 4, a write error with
//! status 1, Ctrl-C with 130 and SIGTERM with 143 (results kept).

pub mod adhesive;
pub mod branch;

pub mod cycles;
pub mod cycles_in;
pub mod diagram;
pub mod files;
pub mod fit;
pub mod hopf;
pub mod interrupt;
pub mod lpc_output;

pub mod simulate;

use crate::analysis::model_choice::DEFAULT_INERTIA_THRESHOLD;
use crate::error::Error;
use crate::jobs::SceneSpec;
pub use crate::jobs::{onset_with_degeneracy_resolved, Setup, TextUnits};
use crate::model::ModelKind;
pub use crate::records::{describe_params, describe_params_except, params_json, significant};
use crate::scene;
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
    /// Fit the friction law's parameters (mu0, A, B, D0, mu2 or tau; adhesive scenes: F_a, V_s, tau_on, tau_out, F_v, alpha) to laboratory data (steady friction, the onset), with errors; write the fitted scene.
    #[command(allow_negative_numbers = true)]
    Fit(fit::FitArgs),
    /// List the built-in scenes.
    Scenes(ScenesArgs),
}

/// Options of `stickslip scenes`.
#[derive(Args, Debug, Clone)]
pub struct ScenesArgs {
    /// Print one JSON array of `{name, description, law}` instead of text.
    #[arg(long)]
    pub json: bool,
}

/// Options shared by every analysis: which scene, overrides, which model.
#[derive(Args, Debug, Clone)]
pub struct SceneArgs {
    /// A built-in scene name (see `stickslip scenes`) or a path to a TOML scene file
    /// [default: pmma; with --from, the file's]. A scene with law = "adhesive" (e.g. gel:
    /// Schallamach's soft adhesive contacts, docs/model.md) runs hopf, branch --param V,
    /// diagram, cycles, simulate and fit with its own values, quasi-static or inertial by its
    /// inertia ratio chi = m lambda_n / F_u.
    #[arg(long)]
    pub scene: Option<String>,
    /// Override a parameter, repeatable. Dimensionless (docs/model.md): kappa, nu, m, A, B,
    /// mu0, mu2, theta_c, mu_vv, mu_vphi, eta_d. Or a scene key in its physical unit, applied before the scene is made
    /// dimensionless: K (N/m), M (kg), W (N), V (µm/s), V0 (µm/s), D0 (µm), tau (s),
    /// g (m/s^2), eta (s/m) (radiation damping, eta_d = eta V0), V_range=LO:HI (µm/s) (e.g.
    /// K=2e5 gives kappa = K D0/W with the scene's D0 and W; W=600 changes kappa and m). One
    /// quantity both ways (K and kappa, M and m, V and nu, tau and theta_c, eta and eta_d) is refused. theta_c or tau selects the cutoff ageing form,
    /// mu2, mu_vv or mu_vphi the logarithmic form. On an adhesive scene (law = "adhesive") the
    /// keys are its own, in their units: F_a \[N\], V_s [µm/s], tau_out \[s\], tau_on \[s\], F_v \[N\],
    /// alpha, M \[kg\], K [N/m], V [µm/s], V_range=LO:HI [µm/s]; a key of the other law is
    /// refused as such.
    #[arg(long = "set", value_name = "NAME=VALUE")]
    pub set: Vec<String>,
    /// Force the model instead of choosing from the inertia ratio m nu^2 / mu_v (adhesive
    /// scenes: chi = m lambda_n / F_u).
    #[arg(long, value_enum)]
    pub model: Option<ModelArg>,
    /// Inertia is dropped (quasi-static model) when m nu^2 / mu_v is below this (adhesive
    /// scenes: chi = m lambda_n / F_u, at V, at a protocol's pulling velocities, or at every
    /// velocity of V_range for branch and diagram; cycles also on the quasi-static orbit,
    /// m |du/dt| / (u F_u)).
    #[arg(long, default_value_t = DEFAULT_INERTIA_THRESHOLD)]
    pub inertia_threshold: f64,
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

impl SceneArgs {
    /// The scene, overrides and model asked for.
    pub fn spec(&self) -> SceneSpec {
        SceneSpec {
            scene: self.scene_name().to_string(),
            set: self.set.clone(),
            model: self.model.map(Into::into),
            inertia_threshold: self.inertia_threshold,
        }
    }

    /// The scene named by `--scene`, else the default.
    pub fn scene_name(&self) -> &str {
        self.scene.as_deref().unwrap_or(scene::DEFAULT_SCENE)
    }

    /// What was asked beside `--from` (a restart, whose scene is the
    /// file's): [`Self::spec`] with the scene empty when `--scene` was not
    /// given ([`crate::jobs::restart::Restart::scene_setup`] refuses any
    /// other scene than the file's, the default's name included).
    pub fn given(&self) -> SceneSpec {
        SceneSpec {
            scene: self.scene.clone().unwrap_or_default(),
            ..self.spec()
        }
    }

    /// [`Self::given`] for a restart (`--from`), else [`Self::spec`].
    pub fn spec_for(&self, restart: bool) -> SceneSpec {
        if restart {
            self.given()
        } else {
            self.spec()
        }
    }

    /// [`SceneSpec::setup`] of [`Self::spec`].
    pub fn setup(
        &self,
        params_at: impl Fn(&crate::params::Params) -> crate::params::Params,
    ) -> Result<Setup, Error> {
        self.spec().setup(params_at)
    }
}

/// A value of `--index`: a label as the runs write them (`label` in the
/// JSON and the CSV, `#N` in the text), a whole number from 0.
pub fn label(text: &str) -> Result<usize, String> {
    text.trim().parse().map_err(|_| {
        format!(
            "'{text}' is no label: labels are whole numbers from 0 (the `label` of each \
             entry in the JSON and the CSV, #N in the text)"
        )
    })
}

/// Runs the parsed command line, writing to standard output.
/// `--from VALUE` without `--index` (of `branch` and `hopf`): a number in
/// the unit of `--param`; with `--index` it is a file, `FILE.json`, holding
/// `what`.
pub fn from_value(text: &str, what: &str) -> Result<f64, Error> {
    text.trim().parse().map_err(|_| {
        crate::error::InputError::Malformed {
            field: "--from".into(),
            value: text.to_string(),
            expected: format!(
                "a number in the unit of --param, or FILE.json with --index N ({what})"
            ),
        }
        .into()
    })
}

pub fn run(cli: Cli) -> Result<(), Error> {
    match cli.command {
        Command::Hopf(args) => hopf::run(&args),
        Command::Branch(args) => branch::run(&args),
        Command::Diagram(args) => diagram::run(&args),
        Command::Cycles(args) => cycles::run(&args),
        Command::Simulate(args) => simulate::run(&args),
        Command::Fit(args) => fit::run(&args),
        Command::Scenes(args) => {
            let mut listed: Vec<(String, String, &str)> = scene::builtin_names()
                .iter()
                .filter_map(|name| scene::builtin(name))
                .map(|s| (s.name, s.description, "rate-and-state"))
                .collect();
            for name in crate::adhesive::scene::builtin_names() {
                let s = crate::adhesive::scene::load(name)?;
                listed.push((s.name, s.description, "adhesive"));
            }
            if args.json {
                let records: Vec<serde_json::Value> = listed
                    .iter()
                    .map(|(name, description, law)| {
                        serde_json::json!({"name": name, "description": description, "law": law})
                    })
                    .collect();
                let text = serde_json::to_string_pretty(&records).map_err(std::io::Error::other)?;
                println!("{text}");
                return Ok(());
            }
            for (name, description, law) in &listed {
                match *law {
                    "adhesive" => println!("{name:10} {description} (law = adhesive)"),
                    _ => println!("{name:10} {description}"),
                }
            }
            Ok(())
        }
    }
}
