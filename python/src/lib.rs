//! `stickslip._native`: the library jobs of `stickslip` for Python. Each
//! function takes the scene as plain values (a built-in name or a TOML
//! text, the `--set` overrides, the model options) and the job's options
//! by the command line's names, runs the job with the GIL released, and
//! returns the record serialized exactly as the command's `--json` prints
//! it, with the column data the JSON leaves out (orbit samples) as numpy
//! arrays. The pure-Python layer (`python/stickslip/__init__.py`) wraps
//! these in `Scene` and result objects.

use continuation::periodic::CollocationPoints;
use continuation::AsIs;
use numpy::ndarray::Array2;
use numpy::IntoPyArray;
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::{Duration, Instant};
use stickslip::analysis::axes::Axes;
use stickslip::analysis::control::Control;
use stickslip::analysis::cycles::along_branch;
use stickslip::analysis::diagram::DEFAULT_CURVE_STEPS;
use stickslip::analysis::simulate::Sample;
use stickslip::error::{Error, InputError};
use stickslip::error::{Interruption, StopSignal};
use stickslip::file_names::{run_name, stem as files_stem, with_suffix};
use stickslip::fit::data::Kind;
use stickslip::jobs::branch::{BranchRequest, BranchRestart, Plan as BranchPlan};
use stickslip::jobs::cycles::{asked_stiffnesses, CyclesRequest, Observer, Plan};
use stickslip::jobs::cycles_in::{asked_values, CyclesInControlRequest};
use stickslip::jobs::diagram::{run_pair, DiagramRequest};
use stickslip::jobs::fit::FitRequest;
use stickslip::jobs::hopf::HopfRequest;
use stickslip::jobs::restart::Restart;
use stickslip::jobs::simulate::SimulateRequest;
use stickslip::jobs::SceneSpec;
use stickslip::model::ModelKind;
use stickslip::params::Param;
use stickslip::plot::axes::axes_figure;
use stickslip::plot::cycles::{branch_figures, fold_figure};
use stickslip::plot::diagram::write_figures;
use stickslip::plot::simulation::figures as sim_figures;
use stickslip::plot::stability::render;
use stickslip::plot::PlotError;
use stickslip::records::branch::BranchRow;
use stickslip::records::csv::{header, header_of};
use stickslip::records::cycle::Cycle;
use stickslip::records::orbit::StoredOrbit;
use stickslip::records::simulation::SimulationRow;
use stickslip::scene::{self, Units};

/// The texts of the built-in scenes (`examples/scenes/NAME.toml`), for `to_toml`.
const BUILTIN_TEXTS: [(&str, &str); 3] = [
    ("pmma", include_str!("../../examples/scenes/pmma.toml")),
    (
        "pmma-rr",
        include_str!("../../examples/scenes/pmma-rr.toml"),
    ),
    (
        "brockley",
        include_str!("../../examples/scenes/brockley.toml"),
    ),
];

/// TOML texts of scenes made in Python, written once each to a file the
/// jobs load (a job reads a scene by built-in name or path); the file is
/// named `<stem>.toml` so that a scene without a `name` key is named as the
/// file it came from.
static WRITTEN: Mutex<Option<HashMap<(String, String), PathBuf>>> = Mutex::new(None);

fn scene_file(text: &str, stem: &str) -> PyResult<PathBuf> {
    let mut written = WRITTEN.lock().unwrap_or_else(|e| e.into_inner());
    let map = written.get_or_insert_with(HashMap::new);
    let key = (text.to_string(), stem.to_string());
    if let Some(p) = map.get(&key) {
        if p.exists() {
            return Ok(p.clone());
        }
    }
    let dir = std::env::temp_dir()
        .join(format!("stickslip-python-{}", std::process::id()))
        .join(map.len().to_string());
    std::fs::create_dir_all(&dir)
        .map_err(|e| PyRuntimeError::new_err(format!("cannot write a scene file: {e}")))?;
    let path = dir.join(format!("{stem}.toml"));
    std::fs::write(&path, text)
        .map_err(|e| PyRuntimeError::new_err(format!("cannot write a scene file: {e}")))?;
    map.insert(key, path.clone());
    Ok(path)
}

/// The scene as Python hands it over: a built-in name, or a TOML text with
/// the name (`origin`) its errors are reported under and its file stem.
#[derive(FromPyObject)]
#[pyo3(from_item_all)]
struct SceneArg {
    builtin: Option<String>,
    toml: Option<String>,
    origin: String,
    stem: String,
    set: Vec<String>,
    model: Option<String>,
    inertia_threshold: f64,
}

impl SceneArg {
    /// The job's scene, and the path to show instead of a written file's in messages.
    fn spec(&self) -> PyResult<(SceneSpec, Option<(String, String)>)> {
        let model = match self.model.as_deref() {
            None => None,
            Some("inertial") => Some(ModelKind::Inertial),
            Some("quasi-static" | "quasi_static") => Some(ModelKind::QuasiStatic),
            Some(other) => {
                return Err(InputError::UnknownName {
                    what: "model",
                    name: other.to_string(),
                    suggestion: None,
                    allowed: "inertial, quasi-static".into(),
                }
                .into_py())
            }
        };
        let (name, shown) = match (&self.builtin, &self.toml) {
            (Some(b), _) => (b.clone(), None),
            (None, Some(text)) => {
                let path = scene_file(text, &self.stem)?.display().to_string();
                (path.clone(), Some((path, self.origin.clone())))
            }
            (None, None) => return Err(PyRuntimeError::new_err("a scene needs a name or a text")),
        };
        Ok((
            SceneSpec {
                scene: name,
                set: self.set.clone(),
                model,
                inertia_threshold: self.inertia_threshold,
            },
            shown,
        ))
    }
}

/// The Python exception of an error: `stickslip.InputError(message,
/// field)`, `stickslip.NumericalError(message)`, or a `RuntimeError`.
trait IntoPy {
    fn into_py(self) -> PyErr;
}

impl IntoPy for InputError {
    fn into_py(self) -> PyErr {
        Error::Input(self).into_py()
    }
}

impl IntoPy for Error {
    fn into_py(self) -> PyErr {
        to_py(self, None)
    }
}

/// The field an input error names, as the command line names it.
fn field_of(e: &InputError) -> Option<String> {
    match e {
        InputError::OutOfRange { field, .. } | InputError::Malformed { field, .. } => {
            Some(field.clone())
        }
        InputError::UnknownName { what, .. } => Some(what.to_string()),
        InputError::OtherLaw { field, .. } => Some(field.clone()),
        InputError::File { path, .. } => Some(path.clone()),
        InputError::Restart { field, .. } => Some(field.clone()),
        InputError::Conflict(_) => None,
    }
}

/// `e` as a Python exception of the pure-Python layer (`stickslip._errors`),
/// a written scene file's path replaced by where the scene came from.
fn to_py(e: Error, shown: Option<&(String, String)>) -> PyErr {
    let fix = |s: String| match shown {
        Some((path, origin)) => s.replace(path.as_str(), origin),
        None => s,
    };
    Python::attach(|py| {
        let class = |name: &str| {
            py.import("stickslip._errors")
                .and_then(|m| m.getattr(name))
                .expect("stickslip._errors defines the exceptions")
        };
        let made = match &e {
            Error::Input(i) => {
                let field = field_of(i).map(fix);
                class("InputError").call1((fix(i.to_string()), field))
            }
            Error::Numerical(n) => class("NumericalError").call1((fix(n.to_string()),)),
            other => return PyRuntimeError::new_err(fix(other.to_string())),
        };
        match made {
            Ok(err) => PyErr::from_value(err),
            Err(err) => err,
        }
    })
}

fn to_json(value: &impl serde::Serialize) -> PyResult<String> {
    serde_json::to_string(value).map_err(|e| PyRuntimeError::new_err(e.to_string()))
}

/// The built-in scenes: `(name, description)`.
#[pyfunction]
fn scenes() -> Vec<(String, String)> {
    let adhesive = stickslip::adhesive::scene::builtin_names()
        .filter_map(|n| stickslip::adhesive::scene::load(n).ok())
        .map(|s| (s.name, s.description));
    scene::builtin_names()
        .iter()
        .filter_map(|n| scene::builtin(n))
        .map(|s| (s.name, s.description))
        .chain(adhesive)
        .collect()
}

/// The TOML text of a built-in scene.
#[pyfunction]
fn builtin_toml(name: &str) -> PyResult<String> {
    let rate_and_state = BUILTIN_TEXTS
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(_, t)| *t);
    match rate_and_state.or(stickslip::adhesive::scene::builtin_text(name)) {
        Some(text) => Ok(text.to_string()),
        None => Err(scene::load(name)
            .err()
            .map(IntoPy::into_py)
            .unwrap_or_else(|| PyRuntimeError::new_err(format!("no text for scene {name}")))),
    }
}

/// The scene set up as every job starts (overrides applied, validated,
/// model chosen): what it is, as a dict; errors name the field.
#[pyfunction]
fn setup<'py>(py: Python<'py>, scene: SceneArg) -> PyResult<Bound<'py, PyDict>> {
    let (spec, shown) = scene.spec()?;
    let law = scene::law_of(&spec.scene).map_err(|e| to_py(e.into(), shown.as_ref()))?;
    if law == scene::Law::Adhesive {
        let s = stickslip::adhesive::scene::load_with(&spec.scene, &spec.set)
            .map_err(|e| to_py(e.into(), shown.as_ref()))?;
        let d = PyDict::new(py);
        d.set_item("name", &s.name)?;
        d.set_item("description", &s.description)?;
        d.set_item("law", "adhesive")?;
        d.set_item("stiffness_given", s.stiffness_given)?;
        let params = PyDict::new(py);
        let p = &s.params;
        for (name, value) in [
            ("kappa", p.kappa),
            ("nu", p.nu),
            ("r", p.r),
            ("f_v", p.f_v),
            ("alpha", p.alpha),
            ("m", p.m),
        ] {
            params.set_item(name, value)?;
        }
        d.set_item("params", params)?;
        let u = &s.units;
        d.set_item(
            "V_range_um_per_s",
            (u.velocity_um_s(s.nu_range.0), u.velocity_um_s(s.nu_range.1)),
        )?;
        return Ok(d);
    }
    let s = py
        .detach(|| spec.setup(|p| *p))
        .map_err(|e| to_py(e, shown.as_ref()))?;
    let d = PyDict::new(py);
    d.set_item("name", &s.scene.name)?;
    d.set_item("description", &s.scene.description)?;
    d.set_item("label", &s.label)?;
    d.set_item("model", s.choice.kind.name())?;
    d.set_item("model_reason", &s.choice.reason)?;
    d.set_item("stiffness_given", s.stiffness_given())?;
    let params = PyDict::new(py);
    for (name, value) in s.scene_params.named() {
        params.set_item(name, value)?;
    }
    params.set_item("state_law", s.scene_params.state_law.name())?;
    d.set_item("params", params)?;
    let u = &s.scene.units;
    d.set_item("D0_um", u.d0 * 1e6)?;
    d.set_item("V0_um_per_s", u.velocity_um_s(1.0))?;
    d.set_item("M_kg", u.mass)?;
    d.set_item("W_N", u.load)?;
    d.set_item(
        "V_range_um_per_s",
        (
            u.velocity_um_s(s.scene.nu_range.0),
            u.velocity_um_s(s.scene.nu_range.1),
        ),
    )?;
    Ok(d)
}

/// The scene's TOML with the physical overrides (`K=2e5`) written as its
/// keys; the dimensionless ones are returned beside it (no scene key holds them).
#[pyfunction]
fn scene_toml(scene: SceneArg) -> PyResult<(String, Vec<String>)> {
    let text = match (&scene.builtin, &scene.toml) {
        (Some(b), _) => builtin_toml(b)?,
        (None, Some(t)) => t.clone(),
        (None, None) => return Err(PyRuntimeError::new_err("a scene needs a name or a text")),
    };
    let mut t: toml::Table = text
        .parse()
        .map_err(|e: toml::de::Error| PyRuntimeError::new_err(e.to_string()))?;
    // An adhesive scene's overrides are all its own keys, in their units.
    if t.get("law").and_then(|l| l.as_str()) == Some(stickslip::adhesive::scene::LAW) {
        if scene.set.is_empty() {
            return Ok((text, Vec::new()));
        }
        stickslip::adhesive::scene::insert_overrides(&mut t, &scene.set)
            .map_err(|e| e.into_py())?;
        if !t.contains_key("name") {
            t.insert("name".into(), toml::Value::String(scene.stem.clone()));
        }
        let text = toml::to_string(&t).map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
        return Ok((text, Vec::new()));
    }
    let overrides = stickslip::overrides::Overrides::parse(&scene.set).map_err(|e| e.into_py())?;
    let physical = overrides.physical();
    let dimensionless: Vec<String> = scene
        .set
        .iter()
        .filter(|s| {
            let name = s.split_once('=').map_or(s.as_str(), |(n, _)| n).trim();
            !physical.iter().any(|o| o.key == name)
        })
        .cloned()
        .collect();
    if physical.is_empty() {
        return Ok((text, dimensionless));
    }
    if !t.contains_key("name") {
        t.insert("name".into(), toml::Value::String(scene.stem.clone()));
    }
    for o in &physical {
        stickslip::scene::insert_override(&mut t, o);
    }
    let text = toml::to_string(&t).map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    Ok((text, dimensionless))
}

/// The friction law a scene follows: `rate-and-state` or `adhesive` (its
/// `law` key, docs/model.md).
#[pyfunction]
fn law(scene: SceneArg) -> PyResult<&'static str> {
    let (spec, shown) = scene.spec()?;
    match scene::law_of(&spec.scene).map_err(|e| to_py(e.into(), shown.as_ref()))? {
        scene::Law::Adhesive => Ok("adhesive"),
        scene::Law::RateAndState => Ok("rate-and-state"),
    }
}

/// An adhesive scene's job (`command`: hopf, branch, diagram, cycles or
/// simulate), what `stickslip COMMAND --scene ... --json` prints (no files
/// written); the model as the command line decides it.
#[pyfunction]
#[pyo3(signature = (scene, command, protocol=None, perturb=0.0, rtol=1e-8, max_steps=500, ntst_max=12800))]
#[allow(clippy::too_many_arguments)]
fn adhesive(
    py: Python<'_>,
    scene: SceneArg,
    command: &str,
    protocol: Option<Vec<(f64, f64)>>,
    perturb: f64,
    rtol: f64,
    max_steps: usize,
    ntst_max: usize,
) -> PyResult<String> {
    use stickslip::adhesive::jobs::{self as adhesive_jobs, AdhesiveSetup, Judged};
    let (spec, shown) = scene.spec()?;
    let job = || -> Result<String, Error> {
        let loaded = stickslip::adhesive::scene::load_with(&spec.scene, &spec.set)?;
        // Where inertia is judged, as the command line judges it.
        let judged = match (command, &protocol) {
            ("branch" | "diagram", _) => Judged::OverRange,
            ("simulate", Some(list)) => Judged::AtPulling(list.iter().map(|s| s.0).collect()),
            _ => Judged::AtVelocity,
        };
        let setup = AdhesiveSetup::new(loaded, spec.inertia_threshold, judged, spec.model)?;
        match command {
            "hopf" => text(&adhesive_jobs::hopf(setup)?),
            "branch" => text(&adhesive_jobs::branch(setup)?),
            "diagram" => text(&adhesive_jobs::diagram(setup)?),
            "cycles" => text(&adhesive_jobs::cycles(setup, (max_steps, ntst_max))?),
            "simulate" => text(&adhesive_jobs::simulate(
                setup, protocol, perturb, rtol, max_steps,
            )?),
            other => Err(InputError::UnknownName {
                what: "command",
                name: other.to_string(),
                suggestion: None,
                allowed: "hopf, branch, diagram, cycles, simulate".into(),
            }
            .into()),
        }
    };
    py.detach(job).map_err(|e| to_py(e, shown.as_ref()))
}

/// A job's record as its JSON text.
fn text(value: &impl serde::Serialize) -> Result<String, Error> {
    Ok(serde_json::to_string(value).map_err(std::io::Error::other)?)
}

/// `from_file` with `index` (a restart's file and label), both or neither.
fn restart_of(
    from_file: Option<PathBuf>,
    index: Option<usize>,
    command: &str,
) -> Result<Option<Restart>, InputError> {
    match (from_file, index) {
        (Some(file), Some(index)) => Ok(Some(Restart { file, index })),
        (None, None) => Ok(None),
        _ => Err(InputError::Conflict(format!(
            "from_file and index go together: the JSON of `stickslip {command} --json` (saved \
             to a file) and the label of one of its entries"
        ))),
    }
}

/// `stickslip hopf`: the JSON the command prints, and its note.
#[pyfunction]
#[pyo3(signature = (scene, param=None, from_=None, to=None, from_file=None, index=None))]
fn hopf(
    py: Python<'_>,
    scene: SceneArg,
    param: Option<String>,
    from_: Option<f64>,
    to: Option<f64>,
    from_file: Option<PathBuf>,
    index: Option<usize>,
) -> PyResult<(String, Option<String>)> {
    let (spec, shown) = scene.spec()?;
    let result = py.detach(|| {
        let request = HopfRequest {
            param: Control::from_param(param.as_deref())?,
            from: from_,
            to,
        };
        match restart_of(from_file, index, "cycles` or `stickslip branch")? {
            Some(r) => stickslip::jobs::hopf::run_from(&spec, &r, &request),
            None => stickslip::jobs::hopf::run(&spec, &request),
        }
    });
    let hopf = result.map_err(|e| to_py(e, shown.as_ref()))?;
    let value =
        serde_json::to_value(&hopf.report).map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    Ok((to_json(&value)?, hopf.note))
}

/// The observer of a job run from Python: Ctrl-C (a Python signal handler
/// raising, checked between cycles, points or every 20 ms of a simulation)
/// stops the job and keeps what it computed.
struct Signals {
    /// The exception a signal handler raised.
    raised: Option<PyErr>,
    /// When the signals were last checked.
    checked: Instant,
    /// Where a `cycles` run writes each cycle's orbit (`orbits_file=`).
    orbits: Option<std::fs::File>,
}

impl Signals {
    fn new() -> Signals {
        Signals {
            raised: None,
            checked: Instant::now(),
            orbits: None,
        }
    }

    /// Signals that also write each cycle's orbit to `path` (created or
    /// replaced), as the command line's `<run>-cycles-orbits.jsonl`; its
    /// absolute path, for the result's `orbits_file`.
    fn writing_orbits(path: Option<PathBuf>) -> Result<(Signals, Option<String>), Error> {
        let mut signals = Signals::new();
        let Some(path) = path else {
            return Ok((signals, None));
        };
        let file = std::fs::File::create(&path).map_err(|e| {
            InputError::Conflict(format!("orbits_file: cannot write {}: {e}", path.display()))
        })?;
        signals.orbits = Some(file);
        let shown = std::fs::canonicalize(&path).unwrap_or(path);
        Ok((signals, Some(shown.display().to_string())))
    }

    /// Whether a signal handler raised (checked at most every 20 ms).
    fn raised_now(&mut self) -> bool {
        if self.raised.is_some() {
            return true;
        }
        if self.checked.elapsed() < Duration::from_millis(20) {
            return false;
        }
        self.checked = Instant::now();
        self.raised = Python::attach(|py| py.check_signals().err());
        self.raised.is_some()
    }

    fn interruption(at: String) -> Error {
        Error::Interrupted(Interruption {
            signal: StopSignal::Interrupt,
            at,
        })
    }

    /// The exception a handler raised, unless it is KeyboardInterrupt (the
    /// job stopped and its result is returned).
    fn reraise(&mut self, py: Python<'_>) -> PyResult<()> {
        match self.raised.take() {
            Some(e) if !e.is_instance_of::<pyo3::exceptions::PyKeyboardInterrupt>(py) => Err(e),
            _ => Ok(()),
        }
    }
}

impl Observer for Signals {
    fn stop(&mut self, at: &dyn Fn() -> String) -> Option<Error> {
        // Between cycles (each takes long enough): always checked.
        self.checked = Instant::now() - Duration::from_secs(1);
        self.raised_now().then(|| Signals::interruption(at()))
    }

    fn orbit(&mut self, orbit: &StoredOrbit) -> Result<(), Error> {
        match &mut self.orbits {
            Some(file) => orbit.write_line(file),
            None => Ok(()),
        }
    }
}

impl stickslip::jobs::branch::Observer for Signals {
    fn point(&mut self, row: &BranchRow) -> Result<(), Error> {
        if self.raised_now() {
            let name = row.param.name;
            return Err(Signals::interruption(format!(
                "at {name} = {:.6e}",
                row.param.value
            )));
        }
        Ok(())
    }
}

/// `stickslip cycles` in the stiffness: a dict with the JSON the command
/// prints (`files` empty), the orbit samples of each cycle (an `n x 4`
/// array of `t/T, s, v, theta`), the CSV columns, whether the run was
/// interrupted, and the failure that ended a leg (`(kind, message)`).
#[pyfunction]
#[pyo3(signature = (scene, kappa_fraction, from_simulation, max_steps, ntst, ntst_max, collocation, lpc_curve, at_kappa, at, param, to, search=None, from_file=None, index=None, orbits_file=None))]
#[allow(clippy::too_many_arguments)]
fn cycles<'py>(
    py: Python<'py>,
    scene: SceneArg,
    kappa_fraction: f64,
    from_simulation: bool,
    max_steps: usize,
    ntst: usize,
    ntst_max: usize,
    collocation: Option<String>,
    lpc_curve: bool,
    at_kappa: Vec<f64>,
    at: Vec<String>,
    param: Option<String>,
    to: Option<f64>,
    search: Option<(f64, f64)>,
    from_file: Option<std::path::PathBuf>,
    index: Option<usize>,
    orbits_file: Option<PathBuf>,
) -> PyResult<Bound<'py, PyDict>> {
    let (spec, shown) = scene.spec()?;
    let err = |e: Error| to_py(e, shown.as_ref());
    let (mut observer, orbits_file) = Signals::writing_orbits(orbits_file).map_err(err)?;
    let from = restart_of(from_file, index, "cycles").map_err(|e| err(e.into()))?;
    let control = Control::from_param(param.as_deref()).map_err(|e| err(e.into()))?;
    let collocation = collocation_of(collocation.as_deref()).map_err(|e| err(e.into()))?;
    if let Some(c) = control.filter(|c| !c.is_stiffness()) {
        let Some(to) = to else {
            return Err(err(InputError::Conflict(format!(
                "cycles --param {} needs --to VALUE (in {}): where the branch ends",
                c.name(),
                c.unit()
            ))
            .into()));
        };
        if lpc_curve {
            return Err(err(InputError::Conflict(
                "--lpc-curve continues folds of cycles in (kappa, nu) from a stiffness branch; \
                 leave out --param (or --lpc-curve)"
                    .into(),
            )
            .into()));
        }
        let request = CyclesInControlRequest {
            control: c,
            to,
            at: asked_values(&at_kappa, &at, c).map_err(|e| err(e.into()))?,
            search,
            from_simulation,
            max_steps,
            ntst,
            ntst_max,
            collocation,
            from,
        };
        return cycles_in_control(py, &spec, shown.as_ref(), &request, observer, orbits_file);
    }
    if search.is_some() {
        return Err(err(InputError::Conflict(
            "--search is where the Hopf point in --param V, M, tau, nu, m, ... is searched; \
             the onset in the stiffness is searched from a stable stiffness downward"
                .into(),
        )
        .into()));
    }
    if to.is_some() && control.is_none() {
        return Err(err(InputError::Conflict(
            "--to ends a branch in --param; without it the branch is in the stiffness and ends \
             at --kappa-fraction of its start"
                .into(),
        )
        .into()));
    }
    let request = CyclesRequest {
        kappa_fraction,
        from_simulation,
        max_steps,
        ntst,
        ntst_max,
        collocation,
        lpc_curve,
        at: asked_stiffnesses(&at_kappa, &at).map_err(|e| err(e.into()))?,
        to: control.zip(to),
        from,
    };
    let result = py.detach(|| Plan::new(&spec, request).map(|plan| plan.run(&mut observer)));
    let mut result = result.map_err(err)?;
    observer.reraise(py)?;
    result.orbits_file = orbits_file;
    let d = PyDict::new(py);
    d.set_item("json", to_json(&result)?)?;
    let orbits = PyList::empty(py);
    for r in &result.records {
        // (t/T, s, v, theta) from the record's logarithms.
        let flat: Vec<f64> = r
            .samples
            .iter()
            .flat_map(|&[tau, s, ln_v, phi]| [tau, s, ln_v.exp(), phi.exp()])
            .collect();
        let a = Array2::from_shape_vec((r.samples.len(), 4), flat)
            .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
        orbits.append(a.into_pyarray(py))?;
    }
    d.set_item("orbits", orbits)?;
    let columns = header::<Cycle>().map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    d.set_item("columns", columns.split(',').collect::<Vec<_>>())?;
    let interrupted = result.interrupted();
    d.set_item("interrupted", interrupted)?;
    d.set_item("failure", failure_of(result.failure.take()))?;
    // The CLI's figures: the branch, and the folds of cycles with lpc_curve.
    let cut = if interrupted {
        Some(" — interrupted")
    } else if !result.leg_stops.iter().all(|l| l.complete()) {
        Some(" — stopped before the requested range (see the stop reason)")
    } else {
        None
    };
    let stickslip::jobs::cycles::Cycles {
        records,
        setup,
        lpc_curve: folds,
        ..
    } = result;
    let draw = move |stem: &Path| {
        let stem = with_suffix(stem, "-cycles");
        let mut files = Vec::new();
        if !records.is_empty() {
            files = branch_figures(&setup, &along_branch(&records), &stem, cut)?;
        }
        if lpc_curve && !folds.is_empty() {
            files.extend(fold_figure(&setup, &folds, &stem)?);
        }
        Ok(files)
    };
    d.set_item("figures", Figures::new(&spec, draw))?;
    Ok(d)
}

/// A failure that ended a job after it kept results, as `(kind, message)`
/// (kind `numerical` or `other`); none for a signal.
fn failure_of(e: Option<Error>) -> Option<(&'static str, String)> {
    match e {
        Some(Error::Interrupted(_)) | None => None,
        Some(e @ Error::Numerical(_)) => Some(("numerical", e.to_string())),
        Some(e) => Some(("other", e.to_string())),
    }
}

/// The drawing of a result's figures, kept with it (`result.figures(out_dir)`).
type Draw = Box<dyn Fn(&Path) -> Result<Vec<PathBuf>, PlotError> + Send + Sync>;

/// The figures the command line draws for a result, drawn on demand into a
/// directory under the command line's file name (`<scene>_<overrides>`).
#[pyclass(frozen, module = "stickslip._native")]
struct Figures {
    draw: Draw,
    name: String,
}

impl Figures {
    fn new(
        spec: &SceneSpec,
        draw: impl Fn(&Path) -> Result<Vec<PathBuf>, PlotError> + Send + Sync + 'static,
    ) -> Figures {
        let scene = spec
            .setup(|p| *p)
            .map(|s| s.scene.name)
            .or_else(|_| stickslip::adhesive::scene::load(&spec.scene).map(|s| s.name))
            .unwrap_or_else(|_| "scene".into());
        Figures {
            draw: Box::new(draw),
            name: run_name(&scene, &spec.set, spec.model.map(ModelKind::name)),
        }
    }
}

#[pymethods]
impl Figures {
    /// Draws the figures into `out_dir` (created); returns the files written.
    fn write(&self, py: Python<'_>, out_dir: PathBuf) -> PyResult<Vec<PathBuf>> {
        std::fs::create_dir_all(&out_dir).map_err(|e| {
            PyRuntimeError::new_err(format!("cannot create {}: {e}", out_dir.display()))
        })?;
        let stem = files_stem(&out_dir, &self.name);
        py.detach(|| (self.draw)(&stem))
            .map_err(|e| PyRuntimeError::new_err(format!("cannot draw the figures: {e}")))
    }

    /// The file name the figures start with.
    #[getter]
    fn name(&self) -> &str {
        &self.name
    }
}

/// `--collocation`: gauss, radau, or the model's choice.
fn collocation_of(name: Option<&str>) -> Result<Option<CollocationPoints>, InputError> {
    match name {
        None => Ok(None),
        Some("gauss") => Ok(Some(CollocationPoints::Gauss)),
        Some("radau") => Ok(Some(CollocationPoints::Radau)),
        Some(other) => Err(InputError::UnknownName {
            what: "--collocation",
            name: other.into(),
            suggestion: None,
            allowed: "gauss, radau".into(),
        }),
    }
}

/// `stickslip cycles --param P --to V` for a control other than the
/// stiffness: the dict of `cycles` (no orbit samples: the job keeps the
/// cycles' records only; no figures: the command line draws none).
fn cycles_in_control<'py>(
    py: Python<'py>,
    spec: &SceneSpec,
    shown: Option<&(String, String)>,
    request: &CyclesInControlRequest,
    mut observer: Signals,
    orbits_file: Option<String>,
) -> PyResult<Bound<'py, PyDict>> {
    let result = py.detach(|| {
        stickslip::jobs::cycles_in::Plan::new(spec, request).and_then(|plan| {
            let header = plan.header_record();
            plan.run(&mut observer).map(|r| (r, header))
        })
    });
    let (mut result, header) = result.map_err(|e| to_py(e, shown))?;
    observer.reraise(py)?;
    result.orbits_file = orbits_file;
    let d = PyDict::new(py);
    d.set_item("json", to_json(&result)?)?;
    d.set_item("orbits", PyList::empty(py))?;
    let columns = header_of(&header).map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    d.set_item("columns", columns.split(',').collect::<Vec<_>>())?;
    d.set_item(
        "interrupted",
        matches!(result.failure, Some(Error::Interrupted(_))),
    )?;
    d.set_item("failure", failure_of(result.failure.take()))?;
    d.set_item("figures", Figures::new(spec, |_: &Path| Ok(Vec::new())))?;
    Ok(d)
}

/// `stickslip branch`: a dict with the JSON the command prints, whether
/// Ctrl-C stopped it, and the failure that ended it (`(kind, message)`).
#[pyfunction]
#[pyo3(signature = (scene, param=None, from_=None, to=None, max_steps=2000, from_file=None, index=None))]
#[allow(clippy::too_many_arguments)]
fn branch<'py>(
    py: Python<'py>,
    scene: SceneArg,
    param: Option<String>,
    from_: Option<f64>,
    to: Option<f64>,
    max_steps: usize,
    from_file: Option<PathBuf>,
    index: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
    let (spec, shown) = scene.spec()?;
    let mut observer = Signals::new();
    let result = py.detach(|| {
        let param = param
            .as_deref()
            .map(|p| Control::parse(p, "--param"))
            .transpose()?;
        let plan =
            match (restart_of(from_file, index, "branch")?, param) {
                (Some(_), _) if from_.is_some() => return Err(InputError::Conflict(
                    "from_ starts a fresh branch; a restart starts at its point: leave out from_"
                        .into(),
                )
                .into()),
                (Some(from), param) => BranchPlan::restart(
                    &spec,
                    &BranchRestart {
                        from,
                        param,
                        to,
                        max_steps,
                    },
                )?,
                (None, param) => BranchPlan::new(
                    &spec,
                    &BranchRequest {
                        param: param.unwrap_or(Control::Dimensionless(Param::Kappa)),
                        from: from_,
                        to,
                        max_steps,
                    },
                )?,
            };
        Ok::<_, Error>(plan.run(&mut observer))
    });
    let mut result = result.map_err(|e| to_py(e, shown.as_ref()))?;
    observer.reraise(py)?;
    let d = PyDict::new(py);
    d.set_item("json", to_json(&result)?)?;
    d.set_item(
        "interrupted",
        matches!(result.failure, Some(Error::Interrupted(_))),
    )?;
    d.set_item("failure", failure_of(result.failure.take()))?;
    Ok(d)
}

/// `stickslip fit`: the JSON the command prints (`files` empty), the
/// fitted scene's TOML and the figures.
#[pyfunction]
#[pyo3(signature = (scene, data, free=None))]
fn fit<'py>(
    py: Python<'py>,
    scene: SceneArg,
    data: Vec<(String, PathBuf)>,
    free: Option<Vec<String>>,
) -> PyResult<Bound<'py, PyDict>> {
    let (spec, shown) = scene.spec()?;
    let err = |e: Error| to_py(e, shown.as_ref());
    let data = data
        .into_iter()
        .map(|(kind, file)| Ok((Kind::parse(&kind)?, file)))
        .collect::<Result<Vec<_>, InputError>>()
        .map_err(|e| err(e.into()))?;
    // An adhesive scene: its own law's fit (stickslip::adhesive::fit).
    let adhesive = stickslip::scene::law_of(&spec.scene).map_err(|e| err(e.into()))?
        == stickslip::scene::Law::Adhesive;
    if adhesive {
        let result = py
            .detach(|| {
                stickslip::adhesive::fit::run(&spec.scene, &spec.set, &data, free.as_deref())
            })
            .map_err(err)?;
        let toml = result.outcome.fitted_toml.clone();
        return fit_dict(py, &spec, result, toml, |r, stem| {
            stickslip::plot::fit::data_figures(r, stem)
        });
    }
    let request = FitRequest {
        data,
        free,
        stability: true,
    };
    let result = py
        .detach(|| stickslip::jobs::fit::run(&spec, &request))
        .map_err(err)?;
    let toml = result.outcome.fitted_toml.clone();
    fit_dict(py, &spec, result, toml, stickslip::plot::fit::figures)
}

/// What `fit` returns: the JSON of `result`, the fitted scene `toml` and
/// the figures `draw` makes.
fn fit_dict<'py, T: serde::Serialize + Send + Sync + 'static>(
    py: Python<'py>,
    spec: &SceneSpec,
    result: T,
    toml: String,
    draw: fn(&T, &Path) -> Result<Vec<PathBuf>, PlotError>,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("json", to_json(&result)?)?;
    d.set_item("fitted_toml", toml)?;
    let figures = Figures::new(spec, move |stem| draw(&result, stem));
    d.set_item("figures", Py::new(py, figures)?)?;
    Ok(d)
}

/// `stickslip diagram` (one scene; `--x P --y Q` for a pair of control
/// parameters): the JSON the command prints (`files` empty, `elapsed_s` the
/// job's time) and its figures.
#[pyfunction]
#[pyo3(signature = (scene, nu_range=None, max_steps=None, x=None, y=None, x_range=None, y_range=None))]
#[allow(clippy::too_many_arguments)]
fn diagram<'py>(
    py: Python<'py>,
    scene: SceneArg,
    nu_range: Option<(f64, f64)>,
    max_steps: Option<usize>,
    x: Option<String>,
    y: Option<String>,
    x_range: Option<(f64, f64)>,
    y_range: Option<(f64, f64)>,
) -> PyResult<Bound<'py, PyDict>> {
    let (spec, shown) = scene.spec()?;
    let err = |e: Error| to_py(e, shown.as_ref());
    let request = DiagramRequest {
        nu_range,
        max_steps: max_steps.unwrap_or(DEFAULT_CURVE_STEPS),
    };
    if let Some((lo, hi)) = nu_range {
        let (min, max) = stickslip::params::MAGNITUDE_RANGE;
        let ok = lo.is_finite()
            && hi.is_finite()
            && lo > 0.0
            && hi > lo
            && (min..=max).contains(&lo)
            && (min..=max).contains(&hi);
        if !ok {
            return Err(err(InputError::Malformed {
                field: "--nu-range".into(),
                value: format!("({lo}, {hi})"),
                expected: "(LO, HI) with 0 < LO < HI, velocities of magnitude 1e-100 to 1e100 \
                           (units of V0)"
                    .into(),
            }
            .into()));
        }
    }
    for (field, r) in [("--x-range", x_range), ("--y-range", y_range)] {
        if let Some((lo, hi)) = r {
            if !(lo.is_finite() && hi.is_finite() && lo > 0.0 && hi > lo) {
                return Err(err(InputError::Malformed {
                    field: field.into(),
                    value: format!("({lo}, {hi})"),
                    expected: "(LO, HI) with 0 < LO < HI, in the axis parameter's unit".into(),
                }
                .into()));
            }
        }
    }
    let axes = Axes::parse(x.as_deref(), y.as_deref()).map_err(|e| err(e.into()))?;
    let t0 = Instant::now();
    let d = PyDict::new(py);
    let (mut value, figures) = match axes {
        Some(axes) => {
            let pair = py
                .detach(|| run_pair(&spec, axes, x_range, y_range, &request))
                .map_err(err)?;
            let value = pair.to_json();
            let suffix = format!("-stability-{}-vs-{}", axes.y.name(), axes.x.name());
            let draw = move |stem: &Path| {
                render(
                    &axes_figure(&pair.diagram, &pair.setup.label),
                    &with_suffix(stem, &suffix),
                )
            };
            (value, Figures::new(&spec, draw))
        }
        None => {
            if x_range.is_some() || y_range.is_some() {
                return Err(err(InputError::Conflict(
                    "--x-range and --y-range are the ranges of --x and --y; give --x (and --y)"
                        .into(),
                )
                .into()));
            }
            let r = py
                .detach(|| stickslip::jobs::diagram::run_with(&AsIs, &spec, &request))
                .map_err(err)?;
            let value = r.to_json();
            let draw = move |stem: &Path| {
                write_figures(&r.setup, &r.diagram, r.range, r.operating.as_ref(), stem)
            };
            (value, Figures::new(&spec, draw))
        }
    };
    value["files"] = serde_json::json!([]);
    value["elapsed_s"] = serde_json::json!(t0.elapsed().as_secs_f64());
    d.set_item("json", to_json(&value)?)?;
    d.set_item("figures", figures)?;
    Ok(d)
}

/// The observer of a simulation run from Python: every step kept as a row
/// of the CSV's columns, Ctrl-C checked every 20 ms.
struct Samples {
    signals: Signals,
    units: Units,
    columns: [Vec<f64>; 11],
    inertial: Vec<bool>,
}

/// The numeric columns of `-simulation.csv`, in its order (`model` aside).
const SIMULATION_COLUMNS: [&str; 11] = [
    "t_s",
    "t",
    "s",
    "v",
    "theta",
    "slip",
    "log10_v",
    "spring_force_N",
    "v_um_per_s",
    "theta_s",
    "slip_um",
];

impl stickslip::jobs::simulate::Observer for Samples {
    fn stop(&mut self) -> bool {
        self.signals.raised_now()
    }

    fn sample(&mut self, p: &Sample) -> std::io::Result<()> {
        let r = SimulationRow::new(p, &self.units);
        let values = [
            r.t_s,
            r.t,
            r.s,
            r.v.v,
            r.theta,
            r.slip,
            r.log10_v,
            r.spring_force_n,
            r.v_um_per_s.v,
            r.theta_s,
            r.slip_um,
        ];
        for (c, v) in self.columns.iter_mut().zip(values) {
            c.push(v);
        }
        self.inertial.push(p.model == ModelKind::Inertial);
        Ok(())
    }
}

/// `stickslip simulate`: a dict with the run's record as JSON (the text's
/// facts: model, steps, times, switch, the regime reached, `complete`,
/// `stop`), every step's row of the CSV as numpy columns, and the figures.
#[pyfunction]
#[pyo3(signature = (scene, protocol=None, perturb=1e-2, rtol=1e-8, max_steps=200_000, plot_points=20_000))]
fn simulate<'py>(
    py: Python<'py>,
    scene: SceneArg,
    protocol: Option<Vec<(f64, f64)>>,
    perturb: f64,
    rtol: f64,
    max_steps: usize,
    plot_points: usize,
) -> PyResult<Bound<'py, PyDict>> {
    let (spec, shown) = scene.spec()?;
    let err = |e: Error| to_py(e, shown.as_ref());
    let request = SimulateRequest {
        protocol,
        perturb,
        rtol,
        max_steps,
        plot_points,
    };
    let plan = py
        .detach(|| stickslip::jobs::simulate::Plan::new(&spec, request))
        .map_err(err)?;
    let u = plan.setup.scene.units;
    let mut observer = Samples {
        signals: Signals::new(),
        units: u,
        columns: Default::default(),
        inertial: Vec::new(),
    };
    let sim = py.detach(|| plan.run(&mut observer));
    observer.signals.reraise(py)?;
    let switch = sim.end.as_ref().ok().and_then(|end| end.switch);
    let record = sim.to_json();
    let d = PyDict::new(py);
    d.set_item("json", to_json(&record)?)?;
    let columns = PyDict::new(py);
    let Samples {
        columns: values,
        inertial,
        ..
    } = observer;
    for (name, c) in SIMULATION_COLUMNS.iter().zip(values) {
        columns.set_item(*name, c.into_pyarray(py))?;
    }
    columns.set_item("inertial", inertial.into_pyarray(py))?;
    d.set_item("columns", columns)?;
    d.set_item("interrupted", sim.interrupted)?;
    let failure = match &sim.end {
        Err(Error::Numerical(n)) => Some(("numerical", n.to_string())),
        Err(e) => Some(("other", e.to_string())),
        Ok(_) => None,
    };
    d.set_item("failure", failure)?;
    let name = sim.figure_title();
    let (trajectory, protocol) = (sim.trajectory, sim.protocol);
    let draw = move |stem: &Path| {
        if trajectory.t.len() < 2 {
            return Ok(Vec::new());
        }
        sim_figures(
            &name,
            &trajectory,
            &protocol,
            &u,
            &with_suffix(stem, "-simulation"),
            switch.map(|s| s.t),
        )
    };
    d.set_item("figures", Figures::new(&spec, draw))?;
    Ok(d)
}

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(scenes, m)?)?;
    m.add_function(wrap_pyfunction!(builtin_toml, m)?)?;
    m.add_function(wrap_pyfunction!(setup, m)?)?;
    m.add_function(wrap_pyfunction!(scene_toml, m)?)?;
    m.add_function(wrap_pyfunction!(law, m)?)?;
    m.add_function(wrap_pyfunction!(adhesive, m)?)?;
    m.add_function(wrap_pyfunction!(hopf, m)?)?;
    m.add_function(wrap_pyfunction!(cycles, m)?)?;
    m.add_function(wrap_pyfunction!(branch, m)?)?;
    m.add_function(wrap_pyfunction!(diagram, m)?)?;
    m.add_function(wrap_pyfunction!(simulate, m)?)?;
    m.add_function(wrap_pyfunction!(fit, m)?)?;
    m.add_class::<Figures>()?;
    m.add("DEFAULT_CURVE_STEPS", DEFAULT_CURVE_STEPS)?;
    m.add(
        "DEFAULT_INERTIA_THRESHOLD",
        stickslip::analysis::model_choice::DEFAULT_INERTIA_THRESHOLD,
    )?;
    Ok(())
}
