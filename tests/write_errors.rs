//! Write errors (a full disk, simulated by a file size limit `ulimit -f`):
//! the run exits with status 1 naming the file, leaves every file either
//! complete or marked incomplete (whole CSV rows, a `# incomplete` line, no
//! truncated figure under its name), and a rerun is not refused because of
//! the failed run's files.

use std::path::{Path, PathBuf};
use std::process::Command;

/// Runs stickslip with `args` under `ulimit -f blocks` (no limit with
/// `None`): exit status and standard error.
fn run_limited(blocks: Option<u32>, args: &[&str]) -> (Option<i32>, String) {
    let bin = env!("CARGO_BIN_EXE_stickslip");
    let output = match blocks {
        Some(n) => Command::new("sh")
            .arg("-c")
            .arg(format!("ulimit -f {n}; exec \"$0\" \"$@\""))
            .arg(bin)
            .args(args)
            .output(),
        None => Command::new(bin).args(args).output(),
    }
    .expect("start stickslip");
    (
        output.status.code(),
        String::from_utf8_lossy(&output.stderr).into_owned(),
    )
}

/// A fresh output directory for one test.
fn out_dir(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("stickslip-{test}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

/// The CSV at `path` holds whole rows only (as many cells as its header)
/// and, when `marked`, ends with a `# incomplete` line; its last line.
fn whole_rows(path: &Path, marked: bool) -> String {
    let csv = std::fs::read_to_string(path).unwrap();
    assert!(csv.ends_with('\n'), "a half line at the end of {path:?}");
    let mut rows = csv.lines().filter(|l| !l.starts_with('#'));
    let header = rows.next().unwrap().split(',').count();
    for row in rows {
        assert_eq!(row.split(',').count(), header, "half row: {row}");
    }
    let last = csv.lines().last().unwrap().to_string();
    assert_eq!(last.starts_with("# incomplete: "), marked, "{last}");
    last
}

/// Every figure in `dir` is complete (a PNG ends with its IEND chunk, an
/// SVG with its closing tag) and no temporary file is left.
fn figures_whole(dir: &Path) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        assert!(!name.starts_with('.'), "temporary file left: {name}");
        let bytes = std::fs::read(&path).unwrap();
        if name.ends_with(".png") {
            assert!(bytes.ends_with(b"IEND\xaeB`\x82"), "truncated {name}");
        }
        if name.ends_with(".svg") {
            let text = String::from_utf8_lossy(&bytes);
            assert!(text.trim_end().ends_with("</svg>"), "truncated {name}");
        }
    }
}

/// A failed run under a size limit, then the same run without it: the
/// rerun replaces the failed run's files (saying so) and succeeds; a third
/// run is refused, the files now being a finished run's.
fn rerun_replaces(dir: &Path, args: &[&str], csv: &Path) {
    let (code, err) = run_limited(None, args);
    assert_eq!(code, Some(0), "{err}");
    assert!(
        err.contains("replacing the files of an earlier run"),
        "{err}"
    );
    whole_rows(csv, false);
    figures_whole(dir);
    let (code, err) = run_limited(None, args);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("exists (an earlier run"), "{err}");
}

#[test]
fn a_csv_cut_by_a_full_disk_keeps_whole_rows_and_says_so() {
    let dir = out_dir("write-error-cycles-csv");
    let out = dir.to_str().unwrap();
    let args = ["cycles", "--out", out];
    // 20 blocks (10 or 20 KiB) end the CSV of some 70 rows part-way.
    let (code, err) = run_limited(Some(20), &args);
    assert_eq!(code, Some(1), "{err}");
    assert!(
        err.contains("cannot write output: ") && err.contains(out),
        "{err}"
    );
    // The limit is per file: the orbits file (a line per cycle, some
    // 100 kB each, beside a CSV row of some 400 B) meets it first. The CSV
    // keeps its whole rows and says which file could not be written.
    let csv = dir.join("pmma-cycles.csv");
    let last = whole_rows(&csv, true);
    assert!(
        last.contains("cannot write output") && last.contains("pmma-cycles-orbits.jsonl"),
        "{last}"
    );
    figures_whole(&dir);
    rerun_replaces(&dir, &args, &csv);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_figure_that_cannot_be_written_leaves_no_truncated_file() {
    let dir = out_dir("write-error-cycles-figure");
    let out = dir.to_str().unwrap();
    let args = ["cycles", "--out", out];
    // 60 blocks (30 or 60 KiB): the CSV (23 KiB) fits, a PNG (near 80 KiB) does not.
    let (code, err) = run_limited(Some(60), &args);
    assert_eq!(code, Some(1), "{err}");
    assert!(err.contains("pmma-cycles-amplitude.png"), "{err}");
    assert!(!dir.join("pmma-cycles-amplitude.png").exists());
    figures_whole(&dir);
    // The rows are all there; the run did not finish the file.
    let csv = dir.join("pmma-cycles.csv");
    whole_rows(&csv, true);
    rerun_replaces(&dir, &args, &csv);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_simulation_cut_by_a_full_disk_keeps_whole_rows_and_says_so() {
    let dir = out_dir("write-error-simulate");
    let out = dir.to_str().unwrap();
    let args = [
        "simulate",
        "--set",
        "kappa=0.009",
        "--protocol",
        "1:1000",
        "--out",
        out,
    ];
    let (code, err) = run_limited(Some(20), &args);
    assert_eq!(code, Some(1), "{err}");
    let csv = dir.join("pmma_kappa=0.009-simulation.csv");
    assert!(err.contains(csv.to_str().unwrap()), "{err}");
    let last = whole_rows(&csv, true);
    assert!(last.contains("write error"), "{last}");
    figures_whole(&dir);
    rerun_replaces(&dir, &args, &csv);
    let _ = std::fs::remove_dir_all(&dir);
}
