//! Restarts: a cycle written by an earlier `cycles` run read back
//! (`cycles --from FILE.json --index N`), exactly as it was computed, with
//! the scene it was computed for; and the numbering of the cycles a run
//! writes ([`Labels`]), which is what `--index` names.

use super::cycles::Observer;
use super::{SceneSpec, Setup};
use crate::analysis::cycles::CycleRecord;
use crate::error::{Error, InputError};
use crate::file_names::with_suffix;
use crate::log_model::LogBlock;
use crate::params::Param;
use crate::records::cycle::Cycle;
use crate::records::orbit::{Source, StoredOrbit};
use crate::scene::DEFAULT_SCENE;
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
    pub cycle: continuation::periodic::cycle::Cycle,
    /// The run's `kappa_c` (the Hopf point's stiffness), if it had one.
    pub kappa_c: Option<f64>,
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

    /// Reads the cycle labelled `index` from `file` and its orbits file.
    /// Errors (exit status 2) name the file and the field: a missing or
    /// unreadable file, not a `cycles` JSON, a file written before orbits
    /// were (no `orbits_file`), an index out of range (with the valid
    /// range), an orbits file missing, cut short or edited out of shape.
    pub fn load(&self) -> Result<Restarted, Error> {
        let text =
            std::fs::read_to_string(&self.file).map_err(|e| self.error("--from", e.to_string()))?;
        let json: Value = serde_json::from_str(&text)
            .map_err(|e| self.error("--from", format!("not JSON ({e})")))?;
        if !(json.get("cycles").is_some_and(Value::is_array) && json.get("leg_stops").is_some()) {
            return Err(self.error(
                "cycles",
                "not the JSON of `stickslip cycles --json` (no list `cycles` with `leg_stops`)",
            ));
        }
        let no_orbits = |field: &str| {
            self.error(
                field,
                "this file has no orbits: rerun `cycles` with this version (it writes each \
                 cycle's orbit to <run>-cycles-orbits.jsonl and names it in `orbits_file`)",
            )
        };
        let source: Source = match json.get("source") {
            Some(s) => serde_json::from_value(s.clone())
                .map_err(|e| self.error("source", format!("out of shape ({e})")))?,
            None => return Err(no_orbits("source")),
        };
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
            _ => return Err(no_orbits("orbits_file")),
        };
        let entry = self.entry(&json)?;
        let orbit = self.find_orbit(orbits)?;
        // The orbits file belongs to this JSON: the same period, bit for bit.
        if entry.get("period").and_then(Value::as_f64) != Some(orbit.period) {
            return Err(self.error(
                "orbits_file",
                format!(
                    "{orbits}: the orbit labelled {} has period {:e}, the JSON's cycle {:?}: \
                     the orbits file is another run's",
                    self.index,
                    orbit.period,
                    entry.get("period")
                ),
            ));
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
            from: self.clone(),
        })
    }

    /// The JSON entry of the cycle labelled `index` (in `cycles`,
    /// `special_points` or `operating_point.cycle`), or the range of the
    /// labels.
    fn entry<'a>(&self, json: &'a Value) -> Result<&'a Value, Error> {
        let list = |k: &str| json.get(k).and_then(Value::as_array).into_iter().flatten();
        let entries: Vec<&Value> = list("cycles")
            .chain(list("special_points"))
            .chain(json.pointer("/operating_point/cycle"))
            .collect();
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
                        "no cycle labelled {}: the file's cycles are labelled {lo} to {hi} (the \
                         `label` of each cycle in the JSON and the CSV, #N in the text)",
                        self.index
                    ),
                    _ => "the file holds no cycle".to_string(),
                },
            )),
        }
    }

    /// The orbit labelled `index` in the orbits file `written` (as the run
    /// named it; else beside this JSON, under its own name).
    fn find_orbit(&self, written: &str) -> Result<StoredOrbit, Error> {
        let beside = self
            .file
            .parent()
            .unwrap_or(Path::new(""))
            .join(Path::new(written).file_name().unwrap_or_default());
        let file = std::fs::File::open(written)
            .or_else(|e| std::fs::File::open(&beside).map_err(|_| e))
            .map_err(|e| {
                self.error(
                    "orbits_file",
                    format!("cannot read {written} (nor {}): {e}", beside.display()),
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
    /// The scene set up as the run that wrote the cycle had it, checked to
    /// give the same parameters, with the cycle's model; `given` is what
    /// the command line or the caller asked besides `--from`: an override
    /// or a model, or a scene other than the file's, is refused (the scene
    /// comes from the file; the default scene counts as not given).
    pub fn setup(&self, given: &SceneSpec) -> Result<Setup, Error> {
        let from = &self.from;
        let spec = self.source.spec();
        if !given.set.is_empty() || given.model.is_some() {
            return Err(from.error(
                "--set/--model",
                "the scene, its overrides and the model come from the file; leave out --set \
                 and --model (or run `cycles` afresh with them)",
            ));
        }
        if given.scene != DEFAULT_SCENE && given.scene != spec.scene {
            let same_file = std::fs::canonicalize(&given.scene)
                .is_ok_and(|p| p.display().to_string() == spec.scene);
            if !same_file {
                return Err(from.error(
                    "source.scene",
                    format!(
                        "the file's cycles are of the scene {}, not --scene {}: leave out --scene",
                        spec.scene, given.scene
                    ),
                ));
            }
        }
        let mut setup = spec.setup(|p| *p)?;
        let now = setup.scene_params.to_vec();
        if let Some(q) = Param::ALL.iter().find(|q| {
            now[**q as usize].to_bits() != self.source.scene_params[**q as usize].to_bits()
        }) {
            return Err(from.error(
                "source.scene_params",
                format!(
                    "the scene {} now gives {} = {:e}, the file {:e}: the scene changed since \
                     the run",
                    spec.scene,
                    q.name(),
                    now[*q as usize],
                    self.source.scene_params[*q as usize]
                ),
            ));
        }
        if setup.scene_params.state_law != self.orbit.state_law {
            return Err(from.error(
                "state_law",
                format!(
                    "the scene {} now has the {} state law, the stored cycle the {}: the scene \
                     changed since the run",
                    spec.scene,
                    setup.scene_params.state_law.name(),
                    self.orbit.state_law.name()
                ),
            ));
        }
        let kind = self.orbit.model;
        if setup.choice.kind != kind {
            setup.choice.reason = format!(
                "{}: the model of the cycle restarted from (the run started {})",
                kind.name(),
                setup.choice.reason
            );
        }
        setup.choice.kind = kind;
        setup.params = crate::analysis::model_choice::params_for(kind, &setup.scene_params);
        Ok(setup)
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
