//! `stickslip._native`: the library jobs of `stickslip` for Python. Each
//! function takes the scene as plain values (a built-in name or a TOML
//! text, the `--set` overrides, the model options) and the job's options
//! by the command line's names, runs the job with the GIL released, and
//! returns the record serialized exactly as the command's `--json` prints
//! it, with the column data the JSON leaves out (orbit samples) as numpy
//! arrays. The pure-Python layer (`python/stickslip/__init__.py`) wraps
//! these in `Scene` and result objects.

use numpy::ndarray::Array2;
use numpy::IntoPyArray;
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::Mutex;
use stickslip::analysis::control::Control;
use stickslip::cli::interrupt::{Interruption, StopSignal};
use stickslip::error::{Error, InputError};
use stickslip::jobs::cycles::{asked_stiffnesses, CyclesRequest, Observer, Plan};
use stickslip::jobs::hopf::HopfRequest;
use stickslip::jobs::SceneSpec;
use stickslip::model::ModelKind;
use stickslip::records::csv::header;
use stickslip::records::cycle::Cycle;
use stickslip::scene;

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
        InputError::File { path, .. } => Some(path.clone()),
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
    serde_json::to_string_pretty(value).map_err(|e| PyRuntimeError::new_err(e.to_string()))
}

/// The built-in scenes: `(name, description)`.
#[pyfunction]
fn scenes() -> Vec<(String, String)> {
    scene::builtin_names()
        .iter()
        .filter_map(|n| scene::builtin(n))
        .map(|s| (s.name, s.description))
        .collect()
}

/// The TOML text of a built-in scene.
#[pyfunction]
fn builtin_toml(name: &str) -> PyResult<String> {
    match BUILTIN_TEXTS.iter().find(|(n, _)| *n == name) {
        Some((_, text)) => Ok(text.to_string()),
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
    let overrides = stickslip::overrides::Overrides::parse(&scene.set).map_err(|e| e.into_py())?;
    let physical = overrides.physical();
    let dimensionless: Vec<String> = scene
        .set
        .iter()
        .filter(|s| {
            let name = s.split_once('=').map_or(s.as_str(), |(n, _)| n).trim();
            stickslip::overrides::PhysicalKey::find(name).is_none()
        })
        .cloned()
        .collect();
    if physical.is_empty() {
        return Ok((text, dimensionless));
    }
    let mut t: toml::Table = text
        .parse()
        .map_err(|e: toml::de::Error| PyRuntimeError::new_err(e.to_string()))?;
    if !t.contains_key("name") {
        t.insert("name".into(), toml::Value::String(scene.stem.clone()));
    }
    for o in &physical {
        if o.key == "tau" {
            t.remove("mu2");
        }
        t.insert(o.key.into(), o.value.clone());
    }
    let text = toml::to_string(&t).map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    Ok((text, dimensionless))
}

/// `stickslip hopf`: the JSON the command prints, and its note.
#[pyfunction]
#[pyo3(signature = (scene, param=None, from_=None, to=None))]
fn hopf(
    py: Python<'_>,
    scene: SceneArg,
    param: Option<String>,
    from_: Option<f64>,
    to: Option<f64>,
) -> PyResult<(String, Option<String>)> {
    let (spec, shown) = scene.spec()?;
    let result = py.detach(|| {
        let request = HopfRequest {
            param: Control::from_param(param.as_deref())?,
            from: from_,
            to,
        };
        stickslip::jobs::hopf::run(&spec, &request)
    });
    let hopf = result.map_err(|e| to_py(e, shown.as_ref()))?;
    let value =
        serde_json::to_value(&hopf.report).map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    Ok((to_json(&value)?, hopf.note))
}

/// The observer of a job run from Python: Ctrl-C (a Python signal handler
/// raising, checked between cycles) stops the branch and keeps it.
struct Signals {
    /// The exception a signal handler raised.
    raised: Option<PyErr>,
}

impl Observer for Signals {
    fn stop(&mut self, at: &dyn Fn() -> String) -> Option<Error> {
        let err = Python::attach(|py| py.check_signals().err())?;
        self.raised = Some(err);
        Some(Error::Interrupted(Interruption {
            signal: StopSignal::Interrupt,
            at: at(),
        }))
    }
}

/// `stickslip cycles` in the stiffness: a dict with the JSON the command
/// prints (`files` empty), the orbit samples of each cycle (an `n x 4`
/// array of `t/T, s, v, theta`), the CSV columns, whether the run was
/// interrupted, and the failure that ended a leg (`(kind, message)`).
#[pyfunction]
#[pyo3(signature = (scene, kappa_fraction, from_simulation, max_steps, ntst, ntst_max, collocation, lpc_curve, at_kappa, at, param, to))]
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
) -> PyResult<Bound<'py, PyDict>> {
    let (spec, shown) = scene.spec()?;
    let err = |e: Error| to_py(e, shown.as_ref());
    let control = Control::from_param(param.as_deref()).map_err(|e| err(e.into()))?;
    if let Some(c) = control.filter(|c| !c.is_stiffness()) {
        return Err(err(InputError::Conflict(format!(
            "--param {}: cycles in a control parameter other than the stiffness (K, kappa) are \
             not in the Python package yet; use `stickslip cycles --param {}`",
            c.name(),
            c.name()
        ))
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
    let collocation = match collocation.as_deref() {
        None => None,
        Some("gauss") => Some(continuation::periodic::mesh::CollocationPoints::Gauss),
        Some("radau") => Some(continuation::periodic::mesh::CollocationPoints::Radau),
        Some(other) => {
            return Err(err(InputError::UnknownName {
                what: "--collocation",
                name: other.into(),
                suggestion: None,
                allowed: "gauss, radau".into(),
            }
            .into()))
        }
    };
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
    };
    let mut observer = Signals { raised: None };
    let result = py.detach(|| Plan::new(&spec, request).map(|plan| plan.run(&mut observer)));
    let mut result = result.map_err(err)?;
    if let Some(raised) = observer.raised.take() {
        if !raised.is_instance_of::<pyo3::exceptions::PyKeyboardInterrupt>(py) {
            return Err(raised);
        }
    }
    let d = PyDict::new(py);
    d.set_item("json", to_json(&result)?)?;
    let orbits = PyList::empty(py);
    for r in &result.records {
        let flat: Vec<f64> = r.samples.iter().flatten().copied().collect();
        let a = Array2::from_shape_vec((r.samples.len(), 4), flat)
            .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
        orbits.append(a.into_pyarray(py))?;
    }
    d.set_item("orbits", orbits)?;
    let columns = header::<Cycle>().map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    d.set_item("columns", columns.split(',').collect::<Vec<_>>())?;
    d.set_item("interrupted", result.interrupted())?;
    let failure = match result.failure.take() {
        Some(Error::Interrupted(_)) | None => None,
        Some(e @ Error::Numerical(_)) => Some(("numerical", e.to_string())),
        Some(e) => Some(("other", e.to_string())),
    };
    d.set_item("failure", failure)?;
    Ok(d)
}

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(scenes, m)?)?;
    m.add_function(wrap_pyfunction!(builtin_toml, m)?)?;
    m.add_function(wrap_pyfunction!(setup, m)?)?;
    m.add_function(wrap_pyfunction!(scene_toml, m)?)?;
    m.add_function(wrap_pyfunction!(hopf, m)?)?;
    m.add_function(wrap_pyfunction!(cycles, m)?)?;
    m.add(
        "DEFAULT_INERTIA_THRESHOLD",
        stickslip::analysis::model_choice::DEFAULT_INERTIA_THRESHOLD,
    )?;
    Ok(())
}
