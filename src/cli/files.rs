//! Output files: names `<out>/<scene>-<what>.<ext>`, and their creation
//! with errors that name the path.

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
    fn write_errors_name_the_path() {
        let path = Path::new("/nonexistent-folder/x/y.csv");
        let e = create_file(path).unwrap_err().to_string();
        assert!(e.starts_with("/nonexistent-folder/x/y.csv: "), "{e}");
        let e = write(path, "a").unwrap_err().to_string();
        assert!(e.contains("/nonexistent-folder/x/y.csv"), "{e}");
    }

    #[test]
    fn scene_names_stay_inside_the_output_folder() {
        assert_eq!(stem(Path::new("out"), "../x"), PathBuf::from("out/___x"));
        assert_eq!(
            with_suffix(&stem(Path::new("o"), "my.v2"), ".png"),
            PathBuf::from("o/my_v2.png")
        );
    }
}
