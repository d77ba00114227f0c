//! The jobs: one per command (`hopf`, `branch`, `diagram`, `cycles`,
//! `simulate`), each a request in and a typed record out
//! ([`crate::records`]), shared by the command line and the Python package.
//! This module holds what every job starts from: a scene with its
//! overrides applied and the model chosen ([`Setup`]), and the onset located
//! with the model decision that every command shares
//! ([`onset_with_degeneracy_resolved`]).

pub mod branch;
pub mod cycle_start;
pub mod cycles;
pub mod cycles_in;
pub mod diagram;
pub mod fit;
pub mod hopf;
pub mod restart;
pub mod simulate;

use crate::analysis::hopf::{find_hopf, Criticality, HopfOutcome};
use crate::analysis::model_choice::{
    choose_model, inertia_decides, params_for, ModelChoice, DEFAULT_INERTIA_THRESHOLD,
};
use crate::error::{Error, InputError};
use crate::model::ModelKind;
use crate::overrides::{canonical_overrides, Overrides};
use crate::params::Params;
use crate::scene::{self, Scene};

/// Which scene, with which overrides and which model: what every job
/// starts from (the command line's `--scene`, `--set`, `--model`,
/// `--inertia-threshold`).
#[derive(Clone, Debug)]
pub struct SceneSpec {
    /// A built-in scene name ([`scene::builtin_names`]) or a path to a TOML scene file.
    pub scene: String,
    /// Overrides `NAME=VALUE`, physical or dimensionless ([`Overrides`]).
    pub set: Vec<String>,
    /// The model, forced; `None` chooses it from the inertia ratio.
    pub model: Option<ModelKind>,
    /// Inertia is dropped (quasi-static model) when `m nu^2 / mu_v` is below this.
    pub inertia_threshold: f64,
}

impl SceneSpec {
    /// The scene `scene` as it is: no overrides, the model chosen.
    pub fn named(scene: &str) -> Self {
        SceneSpec {
            scene: scene.to_string(),
            set: Vec::new(),
            model: None,
            inertia_threshold: DEFAULT_INERTIA_THRESHOLD,
        }
    }
}

/// Units of the text output.
#[derive(clap::ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
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

/// A scene with overrides applied and the model chosen.
#[derive(Clone)]
pub struct Setup {
    pub scene: Scene,
    /// The scene's parameters after `--set` (inertia kept).
    pub scene_params: Params,
    /// The parameters the chosen model uses (`m = 0` when quasi-static).
    pub params: Params,
    pub choice: ModelChoice,
    /// The scene's name with its overrides, for figure titles:
    /// `pmma (kappa=0.009, m=0.01)` ([`canonical_overrides`]).
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

impl SceneSpec {
    /// Loads the scene, applies `--set`, validates, and chooses the model for `params_at`
    /// (a hook to evaluate the choice at another velocity, e.g. the top of a range).
    pub fn setup(&self, params_at: impl Fn(&Params) -> Params) -> Result<Setup, Error> {
        if !(self.inertia_threshold.is_finite() && self.inertia_threshold >= 0.0) {
            return Err(InputError::out_of_range(
                "--inertia-threshold",
                self.inertia_threshold,
                "a finite number >= 0",
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
            self.model,
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
        let shown: Vec<String> = canonical_overrides(&self.set)
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
