//! Output files: names `<out>/<run>-<what>.<ext>` (the run named by its
//! scene and overrides, or `--name`), never replacing an earlier run's
//! without `--force`, and their creation with errors that name the path.

use super::SceneArgs;
use crate::error::InputError;
use crate::model::ModelKind;
use clap::Args;
use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

/// `e` with the path it concerns in front of its message.
pub fn at_path(path: &Path, e: std::io::Error) -> std::io::Error {
    std::io::Error::new(e.kind(), format!("{}: {e}", path.display()))
}

/// Creates the output folder `dir` (and its parents).
pub fn create_dir(dir: &Path) -> std::io::Result<()> {
    std::fs::create_dir_all(dir).map_err(|e| at_path(dir, e))
}

/// Creates (or truncates) the file `path` for buffered writing.
pub fn create_file(path: &Path) -> std::io::Result<BufWriter<File>> {
    File::create(path)
        .map(BufWriter::new)
        .map_err(|e| at_path(path, e))
}

/// Writes `contents` to the file `path`.
pub fn write(path: &Path, contents: impl AsRef<[u8]>) -> std::io::Result<()> {
    std::fs::write(path, contents).map_err(|e| at_path(path, e))
}

/// Where a command writes and under which name.
#[derive(Args, Debug, Clone)]
pub struct OutputArgs {
    /// Output directory for figures and data.
    #[arg(long, default_value = "out")]
    pub out: PathBuf,
    /// Name of the output files, instead of the scene's name followed by
    /// the --set overrides and a forced --model (e.g. pmma_kappa=0.009_m=0.01).
    #[arg(long)]
    pub name: Option<String>,
    /// Replace the files of an earlier run of the same name (without it the
    /// run stops before computing, naming the file that exists).
    #[arg(long)]
    pub force: bool,
}

impl OutputArgs {
    /// The output folder `out` (and its parents), created.
    pub fn create_dir(&self) -> std::io::Result<()> {
        create_dir(&self.out)
    }

    /// `<out>/<run>`, the stem of the files of a run on the scene named
    /// `scene` with the overrides and forced model of `args` (see
    /// [`run_name`]), or `<out>/<--name>` (`<--name>_<scene>` when the
    /// command runs `several` scenes). Refuses (naming the file) when any of
    /// the run's files `<stem><suffix>`, `suffix` in `outputs`, exists,
    /// unless `--force`; refuses an empty `--name`.
    pub fn stem(
        &self,
        scene: &str,
        args: &SceneArgs,
        several: bool,
        outputs: &[&str],
    ) -> Result<PathBuf, InputError> {
        let model = args.model.map(|m| ModelKind::from(m).name());
        let name = match self.name.as_deref().map(str::trim) {
            Some("") => {
                return Err(InputError::Malformed {
                    field: "--name".into(),
                    value: String::new(),
                    expected: "a name for the output files".into(),
                })
            }
            Some(name) if several => format!("{name}_{scene}"),
            Some(name) => name.to_string(),
            None => run_name(scene, &args.set, model),
        };
        let stem = stem(&self.out, &name);
        let existing = outputs
            .iter()
            .map(|suffix| with_suffix(&stem, suffix))
            .find(|path| path.exists());
        match existing {
            Some(path) if !self.force => Err(InputError::Conflict(format!(
                "{} exists (an earlier run of the same name): --force replaces its \
                 files, --name NAME writes under another name",
                path.display()
            ))),
            _ => Ok(stem),
        }
    }
}

/// The name of a run: the scene's, then its overrides `NAME=VALUE` (by
/// name, the last of a repeated one; numbers written one way, so that
/// `kappa=0.0090` and `kappa=9e-3` name the same run) and a forced model,
/// joined by `_` (`pmma_kappa=0.009_m=0.01_inertial`).
pub fn run_name(scene: &str, set: &[String], model: Option<&str>) -> String {
    let mut name = scene.to_string();
    for part in canonical_overrides(set)
        .iter()
        .map(|(k, v)| format!("{k}={v}"))
        .chain(model.map(str::to_string))
    {
        name.push('_');
        name.push_str(&part);
    }
    name
}

/// The overrides `NAME=VALUE` of `set` sorted by name, the last of a
/// repeated one kept, numbers in one spelling ([`canonical_number`]).
pub fn canonical_overrides(set: &[String]) -> Vec<(String, String)> {
    let mut overrides: Vec<(String, String)> = Vec::new();
    for part in set {
        let (key, value) = part.split_once('=').unwrap_or((part.as_str(), ""));
        let (key, value) = (key.trim().to_string(), value.trim());
        let value = value
            .parse::<f64>()
            .map_or_else(|_| value.to_string(), canonical_number);
        overrides.retain(|(k, _)| *k != key);
        overrides.push((key, value));
    }
    overrides.sort_by(|a, b| a.0.cmp(&b.0));
    overrides
}

/// `v` in one spelling: plain digits within `[1e-3, 1e5)`, else the
/// shortest mantissa and exponent (`1e-12`).
fn canonical_number(v: f64) -> String {
    if v == 0.0 || (1e-3..1e5).contains(&v.abs()) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// `<out>/<name>`, with every character of the name that is not a letter, a
/// digit or one of `- _ = . +` replaced by `_`, and a leading dot or dash
/// too (a name never leaves `out` nor reads as an option).
pub fn stem(out: &Path, name: &str) -> PathBuf {
    let safe: String = name
        .chars()
        .enumerate()
        .map(|(i, c)| {
            let allowed = c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '=' | '+');
            if (allowed && !(c == '-' && i == 0)) || (c == '.' && i > 0) {
                c
            } else {
                '_'
            }
        })
        .collect();
    out.join(if safe.is_empty() {
        "scene".to_string()
    } else {
        safe
    })
}

/// `stem` followed by `suffix` (no extension logic: names may contain dots).
pub fn with_suffix(stem: &Path, suffix: &str) -> PathBuf {
    let mut s = stem.as_os_str().to_owned();
    s.push(suffix);
    PathBuf::from(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn write_errors_name_the_path() {
        let path = Path::new("/nonexistent-folder/x/y.csv");
        let e = create_file(path).unwrap_err().to_string();
        assert!(e.starts_with("/nonexistent-folder/x/y.csv: "), "{e}");
        let e = write(path, "a").unwrap_err().to_string();
        assert!(e.contains("/nonexistent-folder/x/y.csv"), "{e}");
    }

    #[test]
    fn scene_names_stay_inside_the_output_folder() {
        assert_eq!(stem(Path::new("out"), "../x"), PathBuf::from("out/_._x"));
        assert_eq!(stem(Path::new("out"), ".."), PathBuf::from("out/_."));
        assert_eq!(
            with_suffix(&stem(Path::new("o"), "my.v2"), ".png"),
            PathBuf::from("o/my.v2.png")
        );
    }

    #[test]
    fn runs_are_named_by_their_overrides_and_never_overwritten() {
        let set = vec!["m=1e-2".to_string(), "kappa=0.0090".to_string()];
        assert_eq!(
            run_name("pmma", &set, Some("inertial")),
            "pmma_kappa=0.009_m=0.01_inertial"
        );
        // The same run however its overrides are written, ordered or repeated.
        let same = ["kappa=0.5", "m=1e-12", "kappa=9e-3"].map(String::from);
        assert_eq!(run_name("pmma", &same, None), "pmma_kappa=0.009_m=1e-12");
        assert_eq!(run_name("pmma", &[], None), "pmma");
        let dir = std::env::temp_dir().join(format!("stickslip-names-{}", std::process::id()));
        let mut args = OutputArgs {
            out: dir.clone(),
            name: None,
            force: false,
        };
        args.create_dir().unwrap();
        let scene = SceneArgs {
            scene: "pmma".into(),
            set: set.clone(),
            model: None,
            inertia_threshold: 1e-3,
        };
        let plain = SceneArgs {
            set: Vec::new(),
            ..scene.clone()
        };
        let outputs = ["-cycles.csv", "-cycles-orbits.png"];
        let stem = args.stem("pmma", &scene, false, &outputs).unwrap();
        assert_eq!(stem, dir.join("pmma_kappa=0.009_m=0.01"));
        // Any of the run's files, not only the first.
        write(&with_suffix(&stem, "-cycles-orbits.png"), "x").unwrap();
        let e = args.stem("pmma", &scene, false, &outputs).unwrap_err();
        assert!(
            e.to_string()
                .contains("pmma_kappa=0.009_m=0.01-cycles-orbits.png exists"),
            "{e}"
        );
        assert!(args.stem("pmma", &plain, false, &outputs).is_ok());
        args.force = true;
        assert!(args.stem("pmma", &scene, false, &outputs).is_ok());
        args.name = Some("mine".into());
        let named = args.stem("pmma", &scene, false, &outputs).unwrap();
        assert_eq!(named, dir.join("mine"));
        // Several scenes under one name get one name each.
        let one_of_several = args.stem("pmma", &scene, true, &outputs).unwrap();
        assert_eq!(one_of_several, dir.join("mine_pmma"));
        args.name = Some(" ".into());
        assert!(args.stem("pmma", &scene, false, &outputs).is_err());
        assert_eq!(super::stem(&dir, "-x"), dir.join("_x"));
        std::fs::remove_dir_all(&dir).ok();
    }
}
