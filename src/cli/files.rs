//! Output file names: `<out>/<scene>-<what>.<ext>`.

use std::path::{Path, PathBuf};

/// `<out>/<scene>`, with every character of the scene name that is not a
/// letter, digit, `-` or `_` replaced by `_` (a scene name never leaves `out`).
pub fn stem(out: &Path, scene: &str) -> PathBuf {
    let safe: String = scene
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
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
        assert_eq!(stem(Path::new("out"), "../x"), PathBuf::from("out/___x"));
        assert_eq!(
            with_suffix(&stem(Path::new("o"), "my.v2"), ".png"),
            PathBuf::from("o/my_v2.png")
        );
    }
}
