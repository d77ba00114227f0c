//! The docs, the README, the sources (rustdoc and CLI help) and the examples
//! cite the project's model page as `docs/model.md`, the file users have,
//! never `MODEL` followed by `.md` (upper case), a file users do not have.

use std::path::{Path, PathBuf};

/// The text files under `path` (a file or a folder), skipping build
/// output, hidden folders and files that are not UTF-8 (figures).
fn text_files(path: &Path, out: &mut Vec<(PathBuf, String)>) {
    if path.is_dir() {
        let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("");
        if name == "target" || name.starts_with('.') {
            return;
        }
        for entry in std::fs::read_dir(path).unwrap() {
            text_files(&entry.unwrap().path(), out);
        }
    } else if let Ok(text) = std::fs::read_to_string(path) {
        out.push((path.to_path_buf(), text));
    }
}

#[test]
fn the_model_page_is_cited_as_docs_model_md() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    assert!(root.join("docs/model.md").is_file());
    // Spelled in two parts so that this file does not cite it.
    let wrong = concat!("MODEL", ".md");
    let mut files = Vec::new();
    for part in [
        "README.md",
        "docs",
        "src",
        "examples",
        "tests",
        "continuation",
        "bench",
    ] {
        text_files(&root.join(part), &mut files);
    }
    assert!(files.len() > 50, "{} files read", files.len());
    let cited: Vec<String> = files
        .iter()
        .flat_map(|(path, text)| {
            text.lines()
                .enumerate()
                .filter(|(_, line)| line.contains(wrong))
                .map(move |(i, line)| format!("{}:{}: {line}", path.display(), i + 1))
        })
        .collect();
    assert!(
        cited.is_empty(),
        "{wrong} cited (the page is docs/model.md):\n{}",
        cited.join("\n")
    );
}
