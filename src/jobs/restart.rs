//! Restarts: a cycle written by an earlier `cycles` run read back
//! (`cycles --from FILE.json --index N`), exactly as it was computed, with
//! the scene it was computed for; a point of steady sliding written by
//! `branch --json` (`branch --from FILE.json --index N`,
//! [`Restart::load_branch_point`]); the parameters of either
//! (`hopf --from`, [`Restart::load_point`]); and the numbering of the
//! cycles a run writes ([`Labels`]), which is what `--index` names.

use super::cycles::Observer;
use super::{SceneSpec, Setup};
use crate::analysis::cycles::CycleRecord;
use crate::analysis::model_choice::DEFAULT_INERTIA_THRESHOLD;
use crate::error::{Error, InputError};
use crate::file_names::with_suffix;
use crate::log_model::LogBlock;
use crate::model::ModelKind;
use crate::params::{Param, Params};
use crate::records::cycle::Cycle;
use crate::records::orbit::{Source, StoredOrbit};
use serde::Serialize;
use serde_json::Value;
use std::io::BufRead;
use std::path::{Path, PathBuf};

/// The suffix of the orbits file after a run's stem (`<run>-cycles-orbits.jsonl`).
pub const ORBITS_SUFFIX: &str = "-orbits.jsonl";

/// The orbits file of the `cycles` outputs named `stem` (`<out>/<run>-cycles`).
pub fn orbits_path(cycles_stem: &Path) -> PathBuf {
    with_suffix(cycles_stem, ORBITS_SUFFIX)
}

/// Where to restart from: a `cycles --json` file and the label of one of
/// its cycles.
#[derive(Clone, Debug, PartialEq)]
pub struct Restart {
    /// The JSON `cycles --json` printed.
    pub file: PathBuf,
    /// The cycle's `label`.
    pub index: usize,
}

/// A cycle read back to restart from, with where it came from.
pub struct Restarted {
    /// The scene, overrides and model of the run that wrote it.
    pub source: Source,
    /// The orbit.
    pub orbit: StoredOrbit,
    /// Its variables and the cycle on its mesh.
    pub log: LogBlock,
    pub cycle: continuation::periodic::Cycle,
    /// The run's `kappa_c` (the Hopf point's stiffness), if it had one.
    pub kappa_c: Option<f64>,
    /// The stiffness the run measured its range against (`--kappa-fraction`):
    /// its `kappa_c`, else the simulated orbit's stiffness it started from
    /// (`start.kappa`), or the one a restart carried on (`start.reference_kappa`).
    pub reference_kappa: Option<f64>,
    /// The parameter the run continued, when the cycle is a fold of cycles
    /// (LPC) it located: there the orbit at fixed parameter is not
    /// isolated, and a branch in that parameter starts at fixed period.
    pub fold_in: Option<Param>,
    /// Why the run started in its model, where its file says so
    /// (`model_reason`, which `cycles --param` writes: the model judged over
    /// its range); a stiffness branch chose it at the scene's own values,
    /// as [`Restart::scene_setup`] chooses it again.
    pub run_model_reason: Option<String>,
    /// The file and the label, for the text and the JSON.
    pub from: Restart,
}

impl Restart {
    /// The error about `field` of this restart's file.
    fn error(&self, field: &str, reason: impl Into<String>) -> Error {
        InputError::Restart {
            path: self.file.display().to_string(),
            field: field.to_string(),
            reason: reason.into(),
        }
        .into()
    }

    /// The JSON of this restart's file and what wrote it: `cycles --json`
    /// or `branch --json`, with its `source` (a file of neither kind, or
    /// written before sources were, is refused naming `what` the caller
    /// restarts from).
    fn read(&self) -> Result<(Value, Written, Source), Error> {
        let text =
            std::fs::read_to_string(&self.file).map_err(|e| self.error("--from", e.to_string()))?;
        let json: Value = serde_json::from_str(&text)
            .map_err(|e| self.error("--from", format!("not JSON ({e})")))?;
        let has_list = |k: &str| json.get(k).is_some_and(Value::is_array);
        let written = if has_list("cycles") && json.get("leg_stops").is_some() {
            Written::Cycles
        } else if has_list("points") && json.get("param").is_some_and(Value::is_string) {
            Written::Branch
        } else {
            return Err(self.error(
                "cycles/points",
                "not the JSON of `stickslip cycles --json` (a list `cycles` with `leg_stops`) \
                 nor of `stickslip branch --json` (a list `points` with `param`)",
            ));
        };
        let source: Source = match json.get("source") {
            Some(s) => serde_json::from_value(s.clone())
                .map_err(|e| self.error("source", format!("out of shape ({e})")))?,
            None => {
                return Err(self.error(
                    "source",
                    format!(
                        "this file does not say where its run came from: rerun `{}` with this \
                         version (its JSON names the scene, the overrides and the parameters in \
                         `source`)",
                        written.command()
                    ),
                ))
            }
        };
        Ok((json, written, source))
    }

    /// The error for a file of the other kind than `wanted`.
    fn other_kind(&self, written: Written, wanted: &str) -> Error {
        let why = match written {
            Written::Branch => {
                "this is the JSON of `branch --json`, whose points are steady sliding, not \
                 cycles: `cycles --from` takes the JSON of `cycles --json` (a branch point \
                 restarts with `branch --from`, and `hopf --from` takes either)"
            }
            Written::Cycles => {
                "this is the JSON of `cycles --json`, whose entries are cycles: `branch --from` \
                 continues steady sliding from a point of `branch --json` (a cycle restarts with \
                 `cycles --from`, and `hopf --from` takes either)"
            }
        };
        self.error(wanted, why)
    }

    /// Reads the cycle labelled `index` from `file` and its orbits file.
    /// Errors (exit status 2) name the file and the field: a missing or
    /// unreadable file, not a `cycles` JSON, a file written before orbits
    /// were (no `orbits_file`), an index out of range (with the valid
    /// range), an orbits file missing, cut short or edited out of shape.
    pub fn load(&self) -> Result<Restarted, Error> {
        let (json, written, source) = match self.read() {
            // A file older than sources has no orbits either.
            Err(e) if matches!(&e, Error::Input(InputError::Restart { field, .. }) if field == "source") => {
                return Err(self.no_orbits("source"))
            }
            r => r?,
        };
        if written != Written::Cycles {
            return Err(self.other_kind(written, "cycles"));
        }
        let orbits = match json.get("orbits_file") {
            Some(Value::String(o)) => o.as_str(),
            // The Python package's results name no file.
            Some(Value::Null) => {
                return Err(self.error(
                    "orbits_file",
                    "null: the run wrote no orbits file (the Python package does not); \
                     restart from the JSON of `stickslip cycles --json`",
                ))
            }
            _ => return Err(self.no_orbits("orbits_file")),
        };
        let entry = self.entry(&json, written)?;
        if entry.get("method").and_then(Value::as_str) == Some("return_map") {
            let k = entry
                .get("kappa")
                .and_then(Value::as_f64)
                .unwrap_or(f64::NAN);
            return Err(self.error(
                "method",
                format!(
                    "return_map: the cycle labelled {} is a fixed point of the return map (its \
                     stick lies below the resolution of f64, docs/cycles.md), which keeps no \
                     collocation orbit to restart from; restart from a cycle with method \
                     collocation, or give its stiffness on the same scene (`hopf --set \
                     kappa={k:e}`, `cycles --at-kappa {k:e}`)",
                    self.index,
                ),
            ));
        }
        let orbit = self.find_orbit(orbits)?;
        // The orbits file belongs to this JSON: the same period, bit for bit.
        if entry.get("period").and_then(Value::as_f64) != Some(orbit.period) {
            return Err(self.error(
                "orbits_file",
                format!(
                    "{orbits}: the orbit labelled {} has period {:e}, the JSON's cycle {}: \
                     the orbits file is another run's",
                    self.index,
                    orbit.period,
                    entry
                        .get("period")
                        .and_then(Value::as_f64)
                        .map_or_else(|| "none".to_string(), |p| format!("{p:e}"))
                ),
            ));
        }
        // And the same parameters, each the JSON names (the stiffness, the
        // inertia, a continued parameter): an orbit edited since would
        // restart elsewhere than the cycle the JSON reports.
        for q in Param::ALL {
            let (stored, reported) = (orbit.param(q), entry.get(q.name()).and_then(Value::as_f64));
            if reported.is_some_and(|r| r.to_bits() != stored.to_bits()) {
                return Err(self.error(
                    "orbits_file",
                    format!(
                        "{orbits}: the orbit labelled {} has {} = {stored:e}, the JSON's cycle \
                         {:e}: the orbits file was edited or is another run's",
                        self.index,
                        q.name(),
                        reported.unwrap_or_default()
                    ),
                ));
            }
        }
        let (log, cycle) = orbit.cycle().map_err(|(field, why)| {
            self.error(&format!("{orbits}: label {}: {field}", self.index), why)
        })?;
        Ok(Restarted {
            source,
            log,
            cycle,
            orbit,
            kappa_c: json.get("kappa_c").and_then(Value::as_f64),
            reference_kappa: json.get("kappa_c").and_then(Value::as_f64).or_else(|| {
                let start = |k: &str| json.pointer(&format!("/start/{k}")).and_then(Value::as_f64);
                match json.pointer("/start/kind").and_then(Value::as_str) {
                    Some("simulation") => start("kappa"),
                    Some("restart") => start("reference_kappa"),
                    _ => None,
                }
            }),
            fold_in: (entry.get("kind").and_then(Value::as_str) == Some("lpc"))
                .then(|| continued_param(&json))
                .flatten(),
            run_model_reason: json
                .get("model_reason")
                .and_then(Value::as_str)
                .map(str::to_string),
            from: self.clone(),
        })
    }

    /// The error of a `cycles` file that has no orbits (`field` missing).
    fn no_orbits(&self, field: &str) -> Error {
        self.error(
            field,
            "this file has no orbits: rerun `cycles` with this version (it writes each \
             cycle's orbit to <run>-cycles-orbits.jsonl and names it in `orbits_file`)",
        )
    }

    /// Reads the point labelled `index` of the `branch --json` in `file`:
    /// the parameter continued there and its value, the run's model, range
    /// and control. Errors as [`Restart::load`]'s: not a branch JSON (a
    /// `cycles` one says so), no `source`, an index out of range, a point
    /// or a field out of shape.
    pub fn load_branch_point(&self) -> Result<BranchPoint, Error> {
        let (json, written, source) = self.read()?;
        if written != Written::Branch {
            return Err(self.other_kind(written, "points"));
        }
        let entry = self.entry(&json, written)?;
        let name = json
            .get("param")
            .and_then(Value::as_str)
            .unwrap_or_default();
        let param = Param::parse(name).map_err(|e| self.error("param", e.to_string()))?;
        let number = |v: Option<&Value>, field: &str| {
            v.and_then(Value::as_f64)
                .filter(|x| x.is_finite())
                .ok_or_else(|| self.error(field, "expected a finite number"))
        };
        let value = number(
            entry.get(name),
            &format!("points[label {}].{name}", self.index),
        )?;
        let model: ModelKind = json
            .get("model")
            .cloned()
            .map(serde_json::from_value)
            .transpose()
            .ok()
            .flatten()
            .ok_or_else(|| self.error("model", "expected \"quasi-static\" or \"inertial\""))?;
        let mut params = source
            .params()
            .map_err(|why| self.error("source.scene_params", why))?;
        params.set(param, value);
        let control = match json.pointer("/control/param") {
            Some(Value::String(c)) => c.clone(),
            _ => name.to_string(),
        };
        Ok(BranchPoint {
            to: number(json.get("to"), "to")?,
            event: entry
                .get("event")
                .and_then(Value::as_str)
                .map(str::to_string),
            param,
            value,
            control,
            model,
            params,
            source,
            from: self.clone(),
        })
    }

    /// The parameters of the cycle or branch point labelled `index` in
    /// `file` (a `cycles --json` or a `branch --json`), for `hopf --from`:
    /// the scene's parameters with the point's values (a quasi-static
    /// cycle, computed without inertia, keeps the scene's `m`).
    pub fn load_point(&self) -> Result<WrittenPoint, Error> {
        let (_, written, _) = self.read()?;
        match written {
            Written::Cycles => {
                let r = self.load()?;
                let scene = r
                    .source
                    .params()
                    .map_err(|why| self.error("source.scene_params", why))?;
                Ok(WrittenPoint {
                    kind: "cycle",
                    params: r.params(&scene),
                    source: r.source,
                    model: r.orbit.model,
                    from: self.clone(),
                })
            }
            Written::Branch => {
                let b = self.load_branch_point()?;
                Ok(WrittenPoint {
                    kind: "branch point",
                    source: b.source,
                    params: b.params,
                    model: b.model,
                    from: self.clone(),
                })
            }
        }
    }

    /// The scene of `source` set up again, checked to give the same
    /// parameters; `given` is what the command line or the caller asked
    /// besides `--from`: an override, a model or an inertia threshold is
    /// refused (they come from the file). A scene named in `given` (an
    /// empty name is none) other than the file's stands in for it (a scene
    /// file moved since the run) only where it gives the run's parameters
    /// bit for bit and, while the file's scene can still be read, its
    /// units. The model is chosen as the run chose it.
    pub fn scene_setup(&self, source: &Source, given: &SceneSpec) -> Result<Setup, Error> {
        self.scene_spec(source, given).map(|(_, setup)| setup)
    }

    /// [`Self::scene_setup`] with the scene options it set up (the file's,
    /// or the scene standing in for it).
    pub fn scene_spec(
        &self,
        source: &Source,
        given: &SceneSpec,
    ) -> Result<(SceneSpec, Setup), Error> {
        let mut spec = source.spec();
        let threshold_given = given.inertia_threshold != DEFAULT_INERTIA_THRESHOLD
            && given.inertia_threshold != source.inertia_threshold;
        if !given.set.is_empty() || given.model.is_some() || threshold_given {
            return Err(self.error(
                "--set/--model/--inertia-threshold",
                format!(
                    "the scene, its overrides, the model and the inertia threshold ({:e}) come \
                     from the file; leave them out (or run afresh with them)",
                    source.inertia_threshold
                ),
            ));
        }
        let same_file = |scene: &str| {
            std::fs::canonicalize(scene).is_ok_and(|p| p.display().to_string() == spec.scene)
        };
        // Set up once: the stand-in, or the file's scene.
        let setup =
            if !given.scene.is_empty() && given.scene != spec.scene && !same_file(&given.scene) {
                let standing_in = SceneSpec {
                    scene: given.scene.clone(),
                    ..spec.clone()
                };
                let stand_in = standing_in.setup(|p| *p).map_err(|e| {
                    self.error(
                        "source.scene",
                        format!(
                            "the file's run is of the scene {}; --scene {} cannot stand in for \
                             it: {e}",
                            spec.scene, given.scene
                        ),
                    )
                })?;
                if let Ok(run) = spec.setup(|p| *p) {
                    if run.scene.units != stand_in.scene.units {
                        return Err(self.error(
                            "source.scene",
                            format!(
                                "the file's run is of the scene {}, not --scene {} (their units \
                             differ): leave out --scene",
                                spec.scene, given.scene
                            ),
                        ));
                    }
                }
                spec = standing_in;
                stand_in
            } else {
                spec.setup(|p| *p)?
            };
        let now = setup.scene_params.to_vec();
        if let Some(q) = Param::ALL.iter().find(|q| {
            source.scene_params.get(**q as usize).map(|v| v.to_bits())
                != Some(now[**q as usize].to_bits())
        }) {
            let filed = source
                .scene_params
                .get(*q as usize)
                .map_or_else(|| "no value".to_string(), |v| format!("{v:e}"));
            let (name, now) = (q.name(), now[*q as usize]);
            return Err(if spec.scene == source.scene {
                self.error(
                    "source.scene_params",
                    format!(
                        "the scene {} now gives {name} = {now:e}, the file {filed}: the scene \
                         changed since the run",
                        spec.scene
                    ),
                )
            } else {
                self.error(
                    "source.scene",
                    format!(
                        "the file's run is of the scene {}, not --scene {} (which gives {name} = \
                         {now:e}, the file {filed}): leave out --scene, or name the run's scene",
                        source.scene, spec.scene
                    ),
                )
            });
        }
        if setup.scene_params.state_law != source.state_law {
            return Err(self.error(
                "source.state_law",
                format!(
                    "the scene {} now has the {} state law, the file the {}: the scene changed \
                     since the run",
                    spec.scene,
                    setup.scene_params.state_law.name(),
                    source.state_law.name()
                ),
            ));
        }
        Ok((spec, setup))
    }

    /// The JSON entry labelled `index` (a cycle in `cycles`,
    /// `special_points` or `operating_point.cycle`; a branch point in
    /// `points`), or the range of the labels.
    fn entry<'a>(&self, json: &'a Value, written: Written) -> Result<&'a Value, Error> {
        let list = |k: &str| json.get(k).and_then(Value::as_array).into_iter().flatten();
        let entries: Vec<&Value> = match written {
            Written::Cycles => list("cycles")
                .chain(list("special_points"))
                .chain(json.pointer("/operating_point/cycle"))
                .collect(),
            Written::Branch => list("points").collect(),
        };
        let what = written.entry();
        let labels: Vec<u64> = entries
            .iter()
            .filter_map(|c| c.get("label").and_then(Value::as_u64))
            .collect();
        match entries
            .iter()
            .find(|c| c.get("label").and_then(Value::as_u64) == Some(self.index as u64))
        {
            Some(e) => Ok(e),
            None => Err(self.error(
                "--index",
                match (labels.iter().min(), labels.iter().max()) {
                    (Some(lo), Some(hi)) => format!(
                        "no {what} labelled {}: the file's {what}s are labelled {lo} to {hi} \
                         (the `label` of each {what} in the JSON and the CSV, #N in the text)",
                        self.index
                    ),
                    _ => format!("the file holds no {what} with a label"),
                },
            )),
        }
    }

    /// The orbit labelled `index` in the orbits file `written` (as the run
    /// named it, from the directory it ran in; else from this JSON's
    /// directory; else beside this JSON under its own name).
    fn find_orbit(&self, written: &str) -> Result<StoredOrbit, Error> {
        let dir = self.file.parent().unwrap_or(Path::new(""));
        let mut tried: Vec<PathBuf> = vec![PathBuf::from(written), dir.join(written)];
        tried.push(dir.join(Path::new(written).file_name().unwrap_or_default()));
        tried.dedup();
        let file = tried
            .iter()
            .find_map(|p| std::fs::File::open(p).ok())
            .ok_or_else(|| {
                let shown: Vec<String> = tried.iter().map(|p| p.display().to_string()).collect();
                self.error(
                    "orbits_file",
                    format!(
                        "cannot read the orbits file {written}: tried {}",
                        shown.join(", ")
                    ),
                )
            })?;
        /// A line's label, read before the rest of it.
        #[derive(serde::Deserialize)]
        struct Label {
            label: usize,
        }
        for (n, line) in std::io::BufReader::new(file).lines().enumerate() {
            let line = line.map_err(|e| self.error("orbits_file", format!("{written}: {e}")))?;
            // A run stopped by a signal ends the file with a `# incomplete` line.
            if line.is_empty() || line.starts_with('#') {
                continue;
            }
            let bad = |e: serde_json::Error| {
                self.error("orbits_file", format!("{written}: line {}: {e}", n + 1))
            };
            if serde_json::from_str::<Label>(&line).map_err(bad)?.label == self.index {
                return serde_json::from_str(&line).map_err(bad);
            }
        }
        Err(self.error(
            "orbits_file",
            format!(
                "{written} has no orbit labelled {} (cut short? a run stopped by a signal keeps \
                 the orbits written before it)",
                self.index
            ),
        ))
    }
}

impl Restarted {
    /// What the text says of the cycle restarted from and how it is
    /// corrected: `", a fold of cycles (LPC) in kappa"` and `"at its
    /// period"` for a fold, else nothing and `"at its parameters"`.
    pub fn correction_words(&self) -> (String, &'static str) {
        match self.fold_in {
            Some(p) => (
                format!(", a fold of cycles (LPC) in {}", p.name()),
                "at its period",
            ),
            None => (String::new(), "at its parameters"),
        }
    }

    /// The scene set up as the run that wrote the cycle had it, checked to
    /// give the same parameters ([`Restart::scene_setup`]), with the
    /// cycle's model, and the reason saying so: the model of the cycle,
    /// with why the run started in its own ([`Restarted::run_model_reason`],
    /// else the scene's choice).
    pub fn setup(&self, given: &SceneSpec) -> Result<Setup, Error> {
        let mut setup = self.from.scene_setup(&self.source, given)?;
        let kind = self.orbit.model;
        let run = self
            .run_model_reason
            .as_deref()
            .unwrap_or(&setup.choice.reason);
        setup.choice.reason = format!(
            "{}: the model of the cycle restarted from (the run started {run})",
            kind.name()
        );
        setup.choice.kind = kind;
        setup.params = crate::analysis::model_choice::params_for(kind, &setup.scene_params);
        Ok(setup)
    }

    /// The cycle's parameters: the scene's `scene` with the orbit's values
    /// (the ageing form the scene's; a quasi-static cycle, computed without
    /// inertia, keeps the scene's `m`).
    pub fn params(&self, scene: &Params) -> Params {
        let mut params = scene.with_vec(&self.orbit.params);
        if self.orbit.model == ModelKind::QuasiStatic {
            params.m = scene.m;
        }
        params
    }

    /// Where a run restarted from this cycle, with the scene's parameters
    /// `scene` (JSON `restarted_from`).
    pub fn record(&self, scene: &Params) -> CycleRestartRecord {
        CycleRestartRecord {
            point: RestartRecord::new(&self.from, "cycle", self.orbit.model, &self.params(scene)),
            kappa: self.orbit.param(Param::Kappa),
            period: self.orbit.period,
            lpc: self.fold_in.is_some(),
        }
    }
}

/// What wrote a file restarted from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Written {
    Cycles,
    Branch,
}

impl Written {
    /// The command.
    fn command(self) -> &'static str {
        match self {
            Written::Cycles => "cycles",
            Written::Branch => "branch",
        }
    }

    /// What its labelled entries are.
    fn entry(self) -> &'static str {
        match self {
            Written::Cycles => "cycle",
            Written::Branch => "point",
        }
    }
}

/// The dimensionless parameter a `cycles --json` run continued: its
/// `control.continued` (`cycles --param`), else the stiffness.
fn continued_param(json: &Value) -> Option<Param> {
    match json.pointer("/control/continued") {
        Some(Value::String(name)) => Param::parse(name).ok(),
        Some(_) => None,
        None => Some(Param::Kappa),
    }
}

/// A point of steady sliding read back from a `branch --json`
/// ([`Restart::load_branch_point`]).
#[derive(Clone, Debug)]
pub struct BranchPoint {
    /// The scene, overrides and model of the run that wrote it.
    pub source: Source,
    /// The dimensionless parameter the run continued, and its value here.
    pub param: Param,
    pub value: f64,
    /// The end of the run's range (`to`, in `param`).
    pub to: f64,
    /// The run's `--param` (a control such as `K`, or `param` itself).
    pub control: String,
    /// The run's model.
    pub model: ModelKind,
    /// The scene's parameters with `param` at `value`.
    pub params: Params,
    /// The bifurcation located at the point (`hopf`, `fold`), if any.
    pub event: Option<String>,
    /// The file and the label.
    pub from: Restart,
}

/// The parameters of a written cycle or branch point
/// ([`Restart::load_point`]).
#[derive(Clone, Debug)]
pub struct WrittenPoint {
    /// `cycle` or `branch point`.
    pub kind: &'static str,
    /// The run's scene, overrides and model.
    pub source: Source,
    /// The scene's parameters with the point's values.
    pub params: Params,
    /// The model the point was computed with.
    pub model: ModelKind,
    /// The file and the label.
    pub from: Restart,
}

/// Where a run's parameters came from, in its JSON (`restarted_from`):
/// the file, the label, what the point was and its parameters.
#[derive(Clone, Debug, Serialize)]
pub struct RestartRecord {
    pub file: String,
    pub label: usize,
    /// `cycle` or `branch point`.
    pub kind: &'static str,
    /// The model the point was computed with.
    pub model: ModelKind,
    /// The point's parameters, by name.
    pub params: Value,
}

/// Where a `cycles --param` run restarted from (JSON `restarted_from`):
/// the record of a restart's point, with what the stiffness branch's
/// `start` says of a restart (the cycle's `kappa`, its period in `D0/V0`,
/// whether it is a fold of cycles).
#[derive(Clone, Debug, Serialize)]
pub struct CycleRestartRecord {
    #[serde(flatten)]
    pub point: RestartRecord,
    pub kappa: f64,
    pub period: f64,
    pub lpc: bool,
}

impl RestartRecord {
    /// The record of the `kind` point labelled in `from`, computed with
    /// `model` at `params`.
    pub fn new(from: &Restart, kind: &'static str, model: ModelKind, params: &Params) -> Self {
        RestartRecord {
            file: from.file.display().to_string(),
            label: from.index,
            kind,
            model,
            params: crate::records::params_json(params),
        }
    }
}

impl WrittenPoint {
    /// The record of where the parameters came from.
    pub fn record(&self) -> RestartRecord {
        RestartRecord::new(&self.from, self.kind, self.model, &self.params)
    }

    /// `cycle #40 of pmma.json`, for the text.
    pub fn describe(&self) -> String {
        format!(
            "{} #{} of {}",
            self.kind,
            self.from.index,
            self.from.file.display()
        )
    }
}

/// Numbers the cycles a run writes (`label`, from 0 in the order written)
/// and hands each one's orbit to the observer.
#[derive(Debug, Default)]
pub struct Labels {
    next: usize,
}

impl Labels {
    /// The label the next cycle gets.
    pub fn next(&self) -> usize {
        self.next
    }

    /// Labels `cycle` (made from `rec`) and hands its orbit to `observer`
    /// (whose error, a file that cannot be written, stops the run).
    pub fn label(
        &mut self,
        cycle: &mut Cycle,
        rec: &CycleRecord,
        observer: &mut dyn Observer,
    ) -> Result<(), Error> {
        cycle.label = self.next;
        self.next += 1;
        match StoredOrbit::of(cycle.label, rec) {
            Some(orbit) => observer.orbit(&orbit),
            None => Ok(()),
        }
    }
}
