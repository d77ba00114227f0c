//! What a restart reads: each collocated cycle as `cycles` computed it (a
//! line of `<run>-cycles-orbits.jsonl`, [`StoredOrbit`]), and where the run
//! came from (the JSON's `source`, [`Source`]). Numbers are written by
//! serde_json as the shortest decimals that read back to the same `f64`,
//! so a stored orbit is the computed one bit for bit.

use crate::analysis::cycles::CycleRecord;
use crate::jobs::{SceneSpec, Setup};
use crate::log_model::LogBlock;
use crate::model::ModelKind;
use crate::params::{Param, Params, StateLaw, N_PARAMS};
use continuation::periodic::Cycle;
use continuation::periodic::{CollocationPoints, Mesh};
use continuation::VectorField;
use serde::{Deserialize, Deserializer, Serialize};
use std::collections::BTreeMap;

/// Entries of the parameter vectors written before `mu_vv` and `mu_vphi`
/// existed (`kappa` to `theta_c`).
const N_PARAMS_BEFORE_CORRECTIONS: usize = 8;

/// Entries of the parameter vectors written before `eta_d` existed
/// (`kappa` to `mu_vphi`).
const N_PARAMS_BEFORE_DAMPING: usize = 10;

/// A parameter vector as written ([`StoredOrbit::params`],
/// [`Source::scene_params`]): one written before `mu_vv` and `mu_vphi`
/// existed, with [`N_PARAMS_BEFORE_CORRECTIONS`] entries, reads with both
/// corrections 0, and one written before `eta_d` existed
/// ([`N_PARAMS_BEFORE_DAMPING`]) without damping (the law it was computed
/// with).
fn parameter_vector<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<f64>, D::Error> {
    let mut v = Vec::<f64>::deserialize(d)?;
    if [N_PARAMS_BEFORE_CORRECTIONS, N_PARAMS_BEFORE_DAMPING].contains(&v.len()) {
        v.resize(N_PARAMS, 0.0);
    }
    Ok(v)
}

/// The message for a parameter vector out of shape.
fn parameter_vector_expected() -> String {
    let names: Vec<&str> = Param::ALL.iter().map(|p| p.name()).collect();
    format!(
        "expected {N_PARAMS} finite numbers ({}), or the first \
         {N_PARAMS_BEFORE_CORRECTIONS} (written before mu_vv and mu_vphi) or \
         {N_PARAMS_BEFORE_DAMPING} (written before eta_d)",
        names.join(", ")
    )
}

/// One collocated cycle, exactly: a line of the orbits file, found by its
/// `label` (the cycle's `label` in the JSON and the CSV, `#label` in the
/// text). The orbit is `x(t)`, `t = tau T` in `[0, T]`, piecewise
/// polynomial of degree `degree` on the mesh `0 = tau_0 < ... < tau_NTST =
/// 1`, with its values at the `NTST degree` nodes (`tau_i + (tau_(i+1) -
/// tau_i) l / degree`, the last node being the first) in `u`, node-major
/// (`dim` values per node); `x` is the state of docs/model.md in log
/// variables measured from `origin`: `(s - s_o, ln v - ln v_o, ln theta -
/// ln theta_o)`, without `ln v` for the quasi-static model.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StoredOrbit {
    /// The cycle's label in the run (first, so that a reader finds a line
    /// by its start).
    pub label: usize,
    /// The model the cycle was computed with.
    pub model: ModelKind,
    /// Whether the ageing has the cutoff form (`theta_c`).
    pub cutoff: bool,
    /// The evolution law of `theta` (`ageing` in files written before the
    /// slip law existed).
    #[serde(default)]
    pub state_law: StateLaw,
    /// `(s_o, ln v_o, ln theta_o)`: the point the state is measured from.
    pub origin: [f64; 3],
    /// The full parameter vector, in the order `kappa, nu, m, A, B, mu0,
    /// mu2, theta_c, mu_vv, mu_vphi, eta_d` (`theta_c` 0 without the cutoff;
    /// the last three absent in files written before them, read as 0).
    #[serde(deserialize_with = "parameter_vector")]
    pub params: Vec<f64>,
    /// Period in units of `D0/V0`.
    pub period: f64,
    /// `gauss` or `radau`: where the collocation equations were imposed.
    pub collocation: String,
    /// Polynomial degree per interval.
    pub degree: usize,
    /// The mesh points `tau_0 = 0 .. tau_NTST = 1`.
    pub mesh: Vec<f64>,
    /// State dimension: 3 (inertial) or 2 (quasi-static).
    pub dim: usize,
    /// Node values, node-major.
    pub u: Vec<f64>,
}

/// `gauss` or `radau`.
pub fn points_name(points: CollocationPoints) -> &'static str {
    match points {
        CollocationPoints::Gauss => "gauss",
        CollocationPoints::Radau => "radau",
    }
}

impl StoredOrbit {
    /// The orbit of `rec` labelled `label`; `None` when the record was made
    /// without it.
    pub fn of(label: usize, rec: &CycleRecord) -> Option<StoredOrbit> {
        let c = rec.orbit.as_ref()?;
        Some(StoredOrbit {
            label,
            model: rec.log.kind,
            cutoff: rec.log.cutoff,
            state_law: rec.log.state_law,
            origin: rec.log.origin(),
            params: c.p.clone(),
            period: c.period,
            collocation: points_name(c.mesh.points).to_string(),
            degree: c.mesh.degree,
            mesh: c.mesh.t.clone(),
            dim: c.n,
            u: c.u.clone(),
        })
    }

    /// Writes the orbit as one line of an orbits file, flushed at once so
    /// that an interrupted run keeps it.
    pub fn write_line(&self, file: &mut impl std::io::Write) -> Result<(), crate::error::Error> {
        let line = serde_json::to_string(self).map_err(std::io::Error::other)?;
        writeln!(file, "{line}")?;
        file.flush()?;
        Ok(())
    }

    /// The continued parameter's value on this orbit.
    pub fn param(&self, p: Param) -> f64 {
        self.params[p as usize]
    }

    /// The collocation points the orbit was computed with.
    pub fn points(&self) -> Result<CollocationPoints, String> {
        match self.collocation.as_str() {
            "gauss" => Ok(CollocationPoints::Gauss),
            "radau" => Ok(CollocationPoints::Radau),
            other => Err(format!("collocation '{other}': expected gauss or radau")),
        }
    }

    /// The model and the orbit back, checked for shape: the variables
    /// (`LogBlock`) and the cycle on its mesh. The error names the field
    /// that is out of shape (a file edited by hand).
    pub fn cycle(&self) -> Result<(LogBlock, Cycle), (&'static str, String)> {
        let log = LogBlock::at(self.model, self.cutoff, self.state_law, self.origin);
        let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
        if self.dim != log.dim() {
            return Err((
                "dim",
                format!(
                    "{} for the {} model, which has {}",
                    self.dim,
                    self.model.name(),
                    log.dim()
                ),
            ));
        }
        if self.params.len() != N_PARAMS || !finite(&self.params) {
            return Err(("params", parameter_vector_expected()));
        }
        if self.cutoff != (self.param(Param::ThetaC) > 0.0) {
            return Err((
                "cutoff",
                "disagrees with theta_c in params (the cutoff form has theta_c > 0)".into(),
            ));
        }
        if !finite(&self.origin) {
            return Err(("origin", "expected 3 finite numbers".into()));
        }
        if !(self.period.is_finite() && self.period > 0.0) {
            return Err(("period", format!("{}: expected a number > 0", self.period)));
        }
        if !(1..=20).contains(&self.degree) {
            return Err(("degree", format!("{}: expected 1 to 20", self.degree)));
        }
        let t = &self.mesh;
        if t.len() < 3 || t[0] != 0.0 || t[t.len() - 1] != 1.0 || t.windows(2).any(|w| w[1] <= w[0])
        {
            return Err((
                "mesh",
                "expected at least 3 points rising strictly from 0 to 1".into(),
            ));
        }
        let ntst = t.len() - 1;
        if self.u.len() != ntst * self.degree * self.dim || !finite(&self.u) {
            return Err((
                "u",
                format!(
                    "expected {} finite numbers (NTST {ntst} x degree {} x dim {}), found {}",
                    ntst * self.degree * self.dim,
                    self.degree,
                    self.dim,
                    self.u.len()
                ),
            ));
        }
        let points = self.points().map_err(|e| ("collocation", e))?;
        Ok((
            log,
            Cycle {
                mesh: Mesh::with_points(t.clone(), self.degree, points),
                u: self.u.clone(),
                period: self.period,
                p: self.params.clone(),
                n: self.dim,
            },
        ))
    }
}

/// Where a run came from, for a restart (the JSON's `source`): the scene as
/// given (a built-in name, or the absolute path of its TOML file), the
/// overrides, the model forced, the inertia threshold, and the parameters
/// they gave, to check that they still give them.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Source {
    /// `stickslip` and its version.
    pub written_by: String,
    pub scene: String,
    pub set: Vec<String>,
    /// The model forced (`--model`); absent when it was chosen from the
    /// inertia ratio (every number of a command's JSON is finite and no
    /// field of a complete result is null).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub model: Option<ModelKind>,
    pub inertia_threshold: f64,
    /// The scene's parameters after `--set` (inertia kept), in the order of
    /// [`StoredOrbit::params`].
    #[serde(deserialize_with = "parameter_vector")]
    pub scene_params: Vec<f64>,
    /// The scene's state law (`ageing` in files written before the slip
    /// law existed).
    #[serde(default)]
    pub state_law: StateLaw,
    /// Parameters a restarted run took from the point it restarted from,
    /// by name, on top of `scene_params` (`branch --from`; absent
    /// otherwise).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub at: BTreeMap<String, f64>,
}

impl Source {
    /// The source of a run of `spec` set up as `setup`.
    pub fn new(spec: &SceneSpec, setup: &Setup) -> Source {
        // A file by its absolute path, so that a restart from elsewhere finds it.
        let scene = if crate::scene::builtin_names().contains(&spec.scene.as_str()) {
            spec.scene.clone()
        } else {
            std::fs::canonicalize(&spec.scene)
                .map_or_else(|_| spec.scene.clone(), |p| p.display().to_string())
        };
        Source {
            written_by: format!("stickslip {}", env!("CARGO_PKG_VERSION")),
            scene,
            set: spec.set.clone(),
            model: spec.model,
            inertia_threshold: spec.inertia_threshold,
            scene_params: setup.scene_params.to_vec(),
            state_law: setup.scene_params.state_law,
            at: BTreeMap::new(),
        }
    }

    /// The run's name for the scene named `scene` ([`crate::file_names::run_name`]).
    pub fn run_name(&self, scene: &str) -> String {
        crate::file_names::run_name(scene, &self.set, self.model.map(|m| m.name()))
    }

    /// The scene's parameters as written (`theta_c > 0`: the cutoff form),
    /// with those of `at`, or why they are out of shape.
    pub fn params(&self) -> Result<Params, String> {
        let v = &self.scene_params;
        if v.len() != N_PARAMS || !v.iter().all(|x| x.is_finite()) {
            return Err(parameter_vector_expected());
        }
        let theta_c = v[Param::ThetaC as usize];
        let mut params = Params {
            kappa: v[Param::Kappa as usize],
            nu: v[Param::Nu as usize],
            m: v[Param::M as usize],
            a: v[Param::A as usize],
            b: v[Param::B as usize],
            mu0: v[Param::Mu0 as usize],
            mu2: v[Param::Mu2 as usize],
            theta_c: (theta_c > 0.0).then_some(theta_c),
            state_law: self.state_law,
            mu_vv: v[Param::MuVv as usize],
            mu_vphi: v[Param::MuVphi as usize],
            eta_d: v[Param::EtaD as usize],
        };
        for (name, v) in &self.at {
            let q = Param::parse(name).map_err(|e| format!("at: {e}"))?;
            if !v.is_finite() {
                return Err(format!("at: {name} = {v}: expected a finite number"));
            }
            params.set(q, *v);
        }
        Ok(params)
    }

    /// The scene, overrides and model to set up again.
    pub fn spec(&self) -> SceneSpec {
        SceneSpec {
            scene: self.scene.clone(),
            set: self.set.clone(),
            model: self.model,
            inertia_threshold: self.inertia_threshold,
        }
    }
}
