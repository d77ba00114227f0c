//! The names of a run's output files: the run's name from its scene,
//! overrides and model, the stem `<out>/<name>` made safe, and the files
//! `<stem><suffix>` (shared by the command line and the Python package).

use crate::overrides::canonical_overrides;
use std::path::{Path, PathBuf};

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
    fn scene_names_stay_inside_the_output_folder() {
        assert_eq!(stem(Path::new("out"), "../x"), PathBuf::from("out/_._x"));
        assert_eq!(stem(Path::new("out"), ".."), PathBuf::from("out/_."));
        assert_eq!(
            with_suffix(&stem(Path::new("o"), "my.v2"), ".png"),
            PathBuf::from("o/my.v2.png")
        );
    }

    #[test]
    fn runs_are_named_by_their_overrides() {
        let set = vec!["m=1e-2".to_string(), "kappa=0.0090".to_string()];
        assert_eq!(
            run_name("pmma", &set, Some("inertial")),
            "pmma_kappa=0.009_m=0.01_inertial"
        );
        // The same run however its overrides are written, ordered or repeated.
        let same = ["kappa=0.5", "m=1e-12", "kappa=9e-3"].map(String::from);
        assert_eq!(run_name("pmma", &same, None), "pmma_kappa=0.009_m=1e-12");
        assert_eq!(run_name("pmma", &[], None), "pmma");
        // Physical overrides carry their unit (never a dimensionless name,
        // also where file names ignore case: M_kg beside m).
        let physical = ["m=2", "M=2", "K=200000.0", "V_range=0.10:1e2"].map(String::from);
        assert_eq!(
            run_name("pmma", &physical, None),
            "pmma_K_N_per_m=2e5_M_kg=2_V_range_um_per_s=0.1:100_m=2"
        );
    }
}
