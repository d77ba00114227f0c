//! Output files: names `<out>/<run>-<what>.<ext>` (the run named by its
//! scene and overrides, or `--name`), never replacing an earlier finished
//! run's without `--force`, and their writing with errors that name the
//! path. A file is either complete or marked incomplete: a CSV written as
//! the run computes it holds whole lines only and ends with a `# incomplete`
//! line when the run did not finish it; a file written at once (a figure, a
//! JSON) appears under its name only when written in full.

use super::SceneArgs;
use crate::error::InputError;
use crate::file_names::{run_name, stem, with_suffix};
use crate::model::ModelKind;
use clap::Args;
use std::collections::VecDeque;
use std::fs::File;
use std::io::{ErrorKind, Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

/// How the comment line that ends a file the run did not finish starts.
pub const INCOMPLETE: &str = "# incomplete:";

/// `e` with the path it concerns in front of its message.
pub fn at_path(path: &Path, e: std::io::Error) -> std::io::Error {
    std::io::Error::new(e.kind(), format!("{}: {e}", path.display()))
}

/// Creates the output folder `dir` (and its parents).
pub fn create_dir(dir: &Path) -> std::io::Result<()> {
    std::fs::create_dir_all(dir).map_err(|e| at_path(dir, e))
}

/// Creates (or truncates) the file `path` for writing line by line as the
/// run computes (see [`LineFile`]).
pub fn create_file(path: &Path) -> std::io::Result<LineFile> {
    File::create(path)
        .map(|file| LineFile::new(path, file))
        .map_err(|e| at_path(path, e))
}

/// Writes `contents` to the file `path` in full or not at all
/// ([`write_whole`]); the error names the path.
pub fn write(path: &Path, contents: impl AsRef<[u8]>) -> std::io::Result<()> {
    write_whole(path, contents).map_err(|e| at_path(path, e))
}

/// Writes `contents` to the file `path` in full or not at all: to a
/// temporary file next to it, renamed to `path` once written (the
/// temporary removed on failure), so that a failed write (a full disk)
/// never leaves a truncated file under the name.
pub fn write_whole(path: &Path, contents: impl AsRef<[u8]>) -> std::io::Result<()> {
    let temporary = temporary_path(path);
    let written =
        std::fs::write(&temporary, contents).and_then(|()| std::fs::rename(&temporary, path));
    if written.is_err() {
        let _ = std::fs::remove_file(&temporary);
    }
    written
}

/// `<dir>/.<name>.<pid>.tmp` next to `path`: hidden, and never one of a run's names.
fn temporary_path(path: &Path) -> PathBuf {
    let mut name = std::ffi::OsString::from(".");
    name.push(path.file_name().unwrap_or_default());
    name.push(format!(".{}.tmp", std::process::id()));
    path.with_file_name(name)
}

/// Bytes gathered before complete lines are written without a flush.
const CHUNK: usize = 1 << 16;

/// Line ends remembered, to cut a file back to a complete line and make
/// room for the `# incomplete` line after a write error.
const LINE_ENDS: usize = 64;

/// A text file (a CSV) written as the run computes it, whole lines only.
///
/// What is written is gathered and goes to the file, up to its last
/// complete line, on [`flush`](Write::flush) (or every 64 KiB), in one
/// write. When a write fails (a full disk, a size limit), the file is cut
/// back to its last complete line and ends with a `# incomplete: write
/// error` line (earlier lines are given up to make room for it if need
/// be); every later write returns the same error, which names the path.
/// When the value is dropped before [`LineFile::finish`] (the run stopped
/// on an error) and the file does not already end with a `# incomplete`
/// line, one is added.
#[derive(Debug)]
pub struct LineFile {
    path: PathBuf,
    file: File,
    /// Bytes not yet written: complete lines, then the start of the next.
    pending: Vec<u8>,
    /// The file's length after each of the last lines written (the last
    /// is its length), `0` first while there is room.
    ends: VecDeque<u64>,
    /// Whether the last line written starts with [`INCOMPLETE`].
    marked: bool,
    /// The write error that closed the file (kind and message).
    failed: Option<(ErrorKind, String)>,
    /// Whether the run finished the file ([`LineFile::finish`]).
    finished: bool,
}

impl LineFile {
    fn new(path: &Path, file: File) -> LineFile {
        LineFile {
            path: path.to_path_buf(),
            file,
            pending: Vec::new(),
            ends: VecDeque::from([0]),
            marked: false,
            failed: None,
            finished: false,
        }
    }

    /// Writes the complete lines gathered and declares the file finished
    /// as the run meant it (no `# incomplete` line is added on drop).
    pub fn finish(mut self) -> std::io::Result<()> {
        self.commit()?;
        self.finished = true;
        Ok(())
    }

    /// `Ok` while no write has failed; else that write's error again.
    fn open(&self) -> std::io::Result<()> {
        match &self.failed {
            Some((kind, message)) => Err(std::io::Error::new(*kind, message.clone())),
            None => Ok(()),
        }
    }

    /// The file's length: the end of its last complete line.
    fn len(&self) -> u64 {
        self.ends.back().copied().unwrap_or(0)
    }

    fn push_end(&mut self, end: u64) {
        if self.ends.len() == LINE_ENDS {
            self.ends.pop_front();
        }
        self.ends.push_back(end);
    }

    /// The line ends within the first `n` pending bytes, as file offsets
    /// from `start`.
    fn pending_ends(&self, start: u64, n: usize) -> Vec<u64> {
        memchr::memchr_iter(b'\n', &self.pending[..n])
            .map(|i| start + i as u64 + 1)
            .collect()
    }

    /// Writes the complete lines gathered, in one write.
    fn commit(&mut self) -> std::io::Result<()> {
        self.open()?;
        let Some(last) = memchr::memrchr(b'\n', &self.pending) else {
            return Ok(());
        };
        let start = self.len();
        let n = last + 1;
        if let Err(e) = self.file.write_all(&self.pending[..n]) {
            let e = at_path(&self.path, e);
            self.fail(start, n, &e);
            return Err(e);
        }
        for end in self.pending_ends(start, n) {
            self.push_end(end);
        }
        let line_start = memchr::memrchr(b'\n', &self.pending[..last]).map_or(0, |i| i + 1);
        self.marked = self.pending[line_start..last].starts_with(INCOMPLETE.as_bytes());
        self.pending.drain(..n);
        Ok(())
    }

    /// After the write of the first `n` pending bytes at `start` failed
    /// with `e`: keeps the lines that reached the file whole, then ends it
    /// with a `# incomplete` line, giving up lines until it fits (or, if
    /// none fits, ends the file at its last complete line); closes the file.
    fn fail(&mut self, start: u64, n: usize, e: &std::io::Error) {
        let on_disk = self.file.metadata().map_or(start, |m| m.len());
        for end in self.pending_ends(start, n) {
            if end <= on_disk {
                self.push_end(end);
            }
        }
        self.pending.clear();
        let marker = format!("{INCOMPLETE} write error, the rest of the run is missing: {e}\n");
        let mut cuts = self.ends.iter().rev();
        let placed = cuts.any(|&len| place(&mut self.file, len, marker.as_bytes()).is_ok());
        if !placed {
            let _ = self.file.set_len(self.len());
        }
        self.failed = Some((e.kind(), e.to_string()));
    }
}

/// Cuts `file` to `len` bytes and writes `bytes` after them.
fn place(file: &mut File, len: u64, bytes: &[u8]) -> std::io::Result<()> {
    file.set_len(len)?;
    file.seek(SeekFrom::Start(len))?;
    file.write_all(bytes)
}

impl Write for LineFile {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.open()?;
        self.pending.extend_from_slice(buf);
        if self.pending.len() >= CHUNK {
            self.commit()?;
        }
        Ok(buf.len())
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.commit()
    }
}

impl Drop for LineFile {
    /// A file the run did not finish ends with a `# incomplete` line
    /// (best effort: a write error here has nowhere to go, and the file
    /// still ends with a complete line).
    fn drop(&mut self) {
        if self.finished || self.failed.is_some() || self.commit().is_err() {
            return;
        }
        if !self.marked {
            self.pending.clear();
            self.pending.extend_from_slice(
                format!(
                    "{INCOMPLETE} the run stopped on an error before this file was finished \
                     (see its message)\n"
                )
                .as_bytes(),
            );
            let _ = self.commit();
        }
    }
}

/// Whether the file `path` ends with a `# incomplete` line: a CSV of a run
/// that did not finish. Reads its last 64 KiB only.
fn ends_incomplete(path: &Path) -> bool {
    let tail = || -> std::io::Result<String> {
        let mut file = File::open(path)?;
        let len = file.metadata()?.len();
        file.seek(SeekFrom::Start(len.saturating_sub(CHUNK as u64)))?;
        let mut bytes = Vec::new();
        file.read_to_end(&mut bytes)?;
        Ok(String::from_utf8_lossy(&bytes).into_owned())
    };
    tail().is_ok_and(|text| {
        text.lines()
            .last()
            .is_some_and(|line| line.starts_with(INCOMPLETE))
    })
}

/// Why the files of the run `stem` with `outputs` are those of a run that
/// did not finish, if they are: judged by the first of `outputs`, the run's
/// record; a CSV (written as the run computes) ends with a `# incomplete`
/// line, any other record (a JSON, written last) is missing.
fn unfinished(stem: &Path, outputs: &[&str]) -> Option<String> {
    let record = with_suffix(stem, outputs.first()?);
    if record.extension().is_some_and(|e| e == "csv") {
        ends_incomplete(&record)
            .then(|| format!("{} ends with a '{INCOMPLETE}' line", record.display()))
    } else {
        (!record.exists()).then(|| format!("{} was never written", record.display()))
    }
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
    /// unless `--force` or the earlier run did not finish (judged by the
    /// first of `outputs`, its record: a CSV ending with a `# incomplete`
    /// line, or a missing JSON), which is then replaced with a note on
    /// standard error; refuses an empty `--name`.
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
        let Some(path) = existing.filter(|_| !self.force) else {
            return Ok(stem);
        };
        match unfinished(&stem, outputs) {
            Some(why) => {
                eprintln!(
                    "note: replacing the files of an earlier run of the same name that did \
                     not finish ({why})"
                );
                Ok(stem)
            }
            None => Err(InputError::Conflict(format!(
                "{} exists (an earlier run of the same name): --force replaces its \
                 files, --name NAME writes under another name",
                path.display()
            ))),
        }
    }
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
    fn a_line_file_not_finished_ends_with_an_incomplete_line() {
        let dir = std::env::temp_dir().join(format!("stickslip-lines-{}", std::process::id()));
        create_dir(&dir).unwrap();
        let read = |name: &str| std::fs::read_to_string(dir.join(name)).unwrap();
        // Finished: as written, a half line never reaches the file.
        let mut f = create_file(&dir.join("done.csv")).unwrap();
        write!(f, "a,b\n1,2\n3,").unwrap();
        f.flush().unwrap();
        assert_eq!(read("done.csv"), "a,b\n1,2\n");
        writeln!(f, "4").unwrap();
        f.finish().unwrap();
        assert_eq!(read("done.csv"), "a,b\n1,2\n3,4\n");
        // Dropped before finishing (the run stopped on an error): marked.
        let mut f = create_file(&dir.join("cut.csv")).unwrap();
        write!(f, "a,b\n1,2\n3,").unwrap();
        drop(f);
        let cut = read("cut.csv");
        assert!(
            cut.starts_with("a,b\n1,2\n# incomplete: the run stopped"),
            "{cut}"
        );
        // Marked by the run already: not twice.
        let mut f = create_file(&dir.join("marked.csv")).unwrap();
        writeln!(f, "a,b\n1,2\n# incomplete: interrupted").unwrap();
        drop(f);
        assert_eq!(read("marked.csv"), "a,b\n1,2\n# incomplete: interrupted\n");
        // A write in full or not at all, no temporary left.
        write(&dir.join("x.json"), "{}").unwrap();
        assert_eq!(read("x.json"), "{}");
        assert!(write(&dir.join("no-such-folder/x.json"), "{}").is_err());
        let names: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names.len(), 4, "{names:?}");
        std::fs::remove_dir_all(&dir).ok();
    }

    /// Output into a new folder `name` of the temporary directory, without
    /// `--force`, and the pmma scene with the overrides `set`.
    fn output_and_scene(name: &str, set: Vec<String>) -> (PathBuf, OutputArgs, SceneArgs) {
        let dir = std::env::temp_dir().join(format!("stickslip-{name}-{}", std::process::id()));
        let args = OutputArgs {
            out: dir.clone(),
            name: None,
            force: false,
        };
        args.create_dir().unwrap();
        let scene = SceneArgs {
            scene: Some("pmma".into()),
            set,
            model: None,
            inertia_threshold: 1e-3,
        };
        (dir, args, scene)
    }

    #[test]
    fn an_unfinished_run_is_replaced_a_finished_one_kept() {
        let (dir, args, scene) = output_and_scene("rerun", Vec::new());
        let csv_run = ["-cycles.csv", "-cycles-orbits.png"];
        write(&dir.join("pmma-cycles-orbits.png"), "x").unwrap();
        write(
            &dir.join("pmma-cycles.csv"),
            "a\n1\n# incomplete: write error\n",
        )
        .unwrap();
        assert!(args.stem("pmma", &scene, false, &csv_run).is_ok());
        write(&dir.join("pmma-cycles.csv"), "a\n1\n").unwrap();
        assert!(args.stem("pmma", &scene, false, &csv_run).is_err());
        // A run whose record is written last: unfinished while it is missing.
        let json_run = ["-diagram.json", "-hopf-curve.csv"];
        write(&dir.join("pmma-hopf-curve.csv"), "a\n1\n").unwrap();
        assert!(args.stem("pmma", &scene, false, &json_run).is_ok());
        write(&dir.join("pmma-diagram.json"), "{}").unwrap();
        assert!(args.stem("pmma", &scene, false, &json_run).is_err());
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn runs_are_never_overwritten() {
        let set = vec!["m=1e-2".to_string(), "kappa=0.0090".to_string()];
        let (dir, mut args, scene) = output_and_scene("names", set.clone());
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
