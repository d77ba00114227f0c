//! Benchmark jobs: the analyses a user runs, timed end to end, with the
//! number of vector-field evaluations each one makes.
//!
//! `stickslip bench` and the criterion benchmarks (`benches/jobs.rs`) share
//! these jobs. A job is prepared once (scene loaded, overrides applied, model
//! chosen, output directory created) and then run repeatedly; only the run is
//! timed. Evaluation counts come from [`crate::model::eval_counts`] around one
//! run, so they are exact for that run (the counters are process-wide: other
//! analyses running at the same time in the same process would add to them).
//! See `docs/performance.md`.

use crate::analysis::diagram::stability_diagram;
use crate::analysis::hopf::{find_hopf, HopfOutcome};
use crate::analysis::model_choice::DEFAULT_INERTIA_THRESHOLD;
use crate::cli::diagram::DiagramArgs;
use crate::cli::SceneArgs;
use crate::error::{Error, NumericalError};
use crate::model::{eval_counts, reset_eval_counts, ModelKind, EVAL_KINDS, N_EVAL_KINDS};
use crate::params::Params;
use serde_json::{json, Value};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

/// Names of the jobs, in the order they run.
pub const JOB_NAMES: [&str; 5] = [
    "hopf_point_l1",
    "hopf_point_l1_inertial",
    "hopf_curve_4_decades",
    "diagram_default",
    "diagram_three_scenes_parallel",
];

/// The inertial variant of the worked example (docs/index.md §5).
const INERTIAL_OVERRIDES: [&str; 5] = ["A=0.01", "B=0.02", "mu2=5e-4", "m=0.1", "nu=3"];

/// The scenes of `diagram_three_scenes_parallel`.
const THREE_SCENES: &str = "pmma,pmma-rr,brockley";

/// A prepared benchmark job.
pub struct Job {
    /// One of [`JOB_NAMES`].
    pub name: &'static str,
    /// What the job does, in one line.
    pub description: &'static str,
    work: Work,
}

enum Work {
    /// `find_hopf` (continuation in kappa, Hopf location, normal form with l1).
    Hopf { kind: ModelKind, params: Params },
    /// `stability_diagram` (Hopf curve in (ln kappa, ln nu) with l1 at every point).
    Curve {
        kind: ModelKind,
        params: Params,
        range: (f64, f64),
    },
    /// The `diagram` command end to end (figures, CSV, JSON written), its
    /// standard output discarded.
    Diagram {
        args: DiagramArgs,
        /// File-name stems of the scenes (their `name`), to count points.
        stems: Vec<String>,
        _dir: TempDir,
    },
}

/// A scene with `--set` overrides, as the CLI would set it up.
fn scene_args(scene: &str, set: &[&str]) -> SceneArgs {
    SceneArgs {
        scene: scene.to_string(),
        set: set.iter().map(|s| s.to_string()).collect(),
        model: None,
        inertia_threshold: DEFAULT_INERTIA_THRESHOLD,
    }
}

impl Job {
    /// Prepares the job called `name` (one of [`JOB_NAMES`]).
    pub fn new(name: &str) -> Result<Job, Error> {
        let (name, description, work) = match name {
            "hopf_point_l1" => {
                let setup = scene_args(crate::scene::DEFAULT_SCENE, &[]).setup(|p| *p)?;
                (
                    JOB_NAMES[0],
                    "find_hopf on the default scene (pmma, quasi-static), with l1",
                    Work::Hopf {
                        kind: setup.choice.kind,
                        params: setup.params,
                    },
                )
            }
            "hopf_point_l1_inertial" => {
                let setup =
                    scene_args(crate::scene::DEFAULT_SCENE, &INERTIAL_OVERRIDES).setup(|p| *p)?;
                (
                    JOB_NAMES[1],
                    "find_hopf, --set A=0.01 B=0.02 mu2=5e-4 m=0.1 nu=3 (inertial), with l1",
                    Work::Hopf {
                        kind: setup.choice.kind,
                        params: setup.params,
                    },
                )
            }
            "hopf_curve_4_decades" => {
                let scene = crate::scene::load("pmma")?;
                (
                    JOB_NAMES[2],
                    "stability_diagram, pmma, inertial, nu in [0.01, 100], l1 at every point",
                    Work::Curve {
                        kind: ModelKind::Inertial,
                        params: scene.params,
                        range: (0.01, 100.0),
                    },
                )
            }
            "diagram_default" => (
                JOB_NAMES[3],
                "`stickslip diagram` end to end (pmma; PNG, SVG, CSV, JSON written)",
                diagram_work(crate::scene::DEFAULT_SCENE)?,
            ),
            "diagram_three_scenes_parallel" => (
                JOB_NAMES[4],
                "`stickslip diagram --scene pmma,pmma-rr,brockley` end to end (rayon)",
                diagram_work(THREE_SCENES)?,
            ),
            other => {
                return Err(NumericalError::Analysis(format!(
                    "no benchmark job '{other}'; jobs: {}",
                    JOB_NAMES.join(", ")
                ))
                .into())
            }
        };
        Ok(Job {
            name,
            description,
            work,
        })
    }

    /// Runs the job once; returns the number of points it produced (1 for a
    /// Hopf point, the curve points of a diagram).
    pub fn run(&self) -> Result<usize, Error> {
        self.execute(true)
    }

    /// Runs the job once without counting points afterwards (what is timed:
    /// for the diagram jobs, counting means reading the JSON files back).
    pub fn run_untallied(&self) -> Result<(), Error> {
        self.execute(false).map(|_| ())
    }

    fn execute(&self, tally: bool) -> Result<usize, Error> {
        match &self.work {
            Work::Hopf { kind, params } => match find_hopf(*kind, params)? {
                HopfOutcome::Found(h) => {
                    std::hint::black_box(&h);
                    Ok(1)
                }
                HopfOutcome::StableForAllStiffness { .. } => Err(NumericalError::Analysis(
                    format!("benchmark job {}: no Hopf point found", self.name),
                )
                .into()),
            },
            Work::Curve {
                kind,
                params,
                range,
            } => {
                let d = stability_diagram(*kind, params, *range)?;
                Ok(std::hint::black_box(d).points.len())
            }
            Work::Diagram { args, stems, .. } => {
                silence_stdout(|| crate::cli::diagram::run(args))?;
                if tally {
                    stems.iter().map(|s| curve_points(&args.out, s)).sum()
                } else {
                    Ok(0)
                }
            }
        }
    }
}

/// All jobs of [`JOB_NAMES`], prepared.
pub fn jobs() -> Result<Vec<Job>, Error> {
    JOB_NAMES.iter().map(|n| Job::new(n)).collect()
}

fn diagram_work(scenes: &str) -> Result<Work, Error> {
    let dir = TempDir::new()?;
    let stems = scenes
        .split(',')
        .map(|s| crate::scene::load(s).map(|sc| sc.name))
        .collect::<Result<_, _>>()?;
    Ok(Work::Diagram {
        args: DiagramArgs {
            scene: scene_args(scenes, &[]),
            nu_range: None,
            out: dir.0.clone(),
            json: false,
        },
        stems,
        _dir: dir,
    })
}

/// Number of Hopf-curve points in `DIR/<stem>-diagram.json`.
fn curve_points(dir: &Path, stem: &str) -> Result<usize, Error> {
    let path = dir.join(format!("{stem}-diagram.json"));
    let text = std::fs::read_to_string(&path)?;
    let v: Value = serde_json::from_str(&text).map_err(std::io::Error::other)?;
    v["hopf_curve"].as_array().map(Vec::len).ok_or_else(|| {
        std::io::Error::other(format!("{} has no hopf_curve array", path.display())).into()
    })
}

/// A directory under the system's temporary directory, removed on drop.
struct TempDir(PathBuf);

impl TempDir {
    fn new() -> std::io::Result<TempDir> {
        static NEXT: AtomicUsize = AtomicUsize::new(0);
        let path = std::env::temp_dir().join(format!(
            "stickslip-bench-{}-{}",
            std::process::id(),
            NEXT.fetch_add(1, Ordering::Relaxed)
        ));
        std::fs::create_dir_all(&path)?;
        Ok(TempDir(path))
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Runs `f` with the process's standard output (file descriptor 1) sent to
/// `/dev/null`, so that a command's report does not mix with the benchmark's.
/// Printing still happens (and is timed); only its destination changes.
/// (Not in unit tests: there the test harness captures `println!` itself,
/// and redirecting descriptor 1 would swallow its reports of other tests.)
#[cfg(all(unix, not(test)))]
fn silence_stdout<T>(f: impl FnOnce() -> T) -> T {
    use std::io::Write;
    struct Restore(libc::c_int);
    impl Drop for Restore {
        fn drop(&mut self) {
            let _ = std::io::stdout().flush();
            // SAFETY: `self.0` is a descriptor duplicated from 1 below and
            // owned here; dup2 and close on valid descriptors.
            unsafe {
                libc::dup2(self.0, 1);
                libc::close(self.0);
            }
        }
    }
    let _ = std::io::stdout().flush();
    // SAFETY: plain descriptor calls; every descriptor opened here is closed
    // (the saved one by `Restore`), and 1 is restored even if `f` panics.
    let _restore = unsafe {
        let null = libc::open(c"/dev/null".as_ptr(), libc::O_WRONLY);
        if null < 0 {
            return f();
        }
        let saved = libc::dup(1);
        if saved < 0 {
            libc::close(null);
            return f();
        }
        libc::dup2(null, 1);
        libc::close(null);
        Restore(saved)
    };
    f()
}

#[cfg(not(all(unix, not(test))))]
fn silence_stdout<T>(f: impl FnOnce() -> T) -> T {
    f()
}

/// How long to time each job.
#[derive(Clone, Copy, Debug)]
pub struct Settings {
    /// Total time of the timed repetitions of one job (aimed at, not exact).
    pub budget: Duration,
    /// Repetitions at least, however long a run takes.
    pub min_repetitions: usize,
}

impl Settings {
    /// About half a second of repetitions per job, at least 5.
    pub fn full() -> Settings {
        Settings {
            budget: Duration::from_millis(500),
            min_repetitions: 5,
        }
    }

    /// A smoke run (`--quick`): about 10 ms per job, at least one repetition.
    pub fn quick() -> Settings {
        Settings {
            budget: Duration::from_millis(10),
            min_repetitions: 1,
        }
    }
}

/// The measurement of one job.
#[derive(Clone, Debug)]
pub struct JobReport {
    pub job: &'static str,
    pub description: &'static str,
    /// Median wall time of one run, seconds.
    pub median_s: f64,
    /// Fastest and slowest run, seconds.
    pub min_s: f64,
    pub max_s: f64,
    /// Points the job produced.
    pub points: usize,
    /// `median_s / points`.
    pub per_point_s: f64,
    /// Timed runs.
    pub repetitions: usize,
    /// Vector-field evaluations of one run, indexed like [`EVAL_KINDS`].
    pub evals: [u64; N_EVAL_KINDS],
}

impl JobReport {
    /// The JSON record: `job`, `median_s`, `points`, `per_point_s`,
    /// `repetitions`, `evals` (by kind), plus `min_s`, `max_s`, `description`.
    pub fn to_json(&self) -> Value {
        let evals: serde_json::Map<String, Value> = EVAL_KINDS
            .iter()
            .zip(self.evals)
            .map(|(k, n)| (k.to_string(), json!(n)))
            .collect();
        json!({
            "job": self.job,
            "description": self.description,
            "median_s": self.median_s,
            "min_s": self.min_s,
            "max_s": self.max_s,
            "points": self.points,
            "per_point_s": self.per_point_s,
            "repetitions": self.repetitions,
            "evals": evals,
        })
    }
}

/// Times `job`: one run with evaluation counting (which also warms caches
/// and the thread pool), one run to estimate the time, then enough timed
/// runs to fill `settings.budget`; reports their median.
pub fn measure(job: &Job, settings: Settings) -> Result<JobReport, Error> {
    reset_eval_counts();
    let points = job.run()?;
    let evals = eval_counts();
    let t = Instant::now();
    job.run_untallied()?;
    let estimate = t.elapsed().as_secs_f64().max(1e-9);
    let repetitions = ((settings.budget.as_secs_f64() / estimate).round() as usize)
        .clamp(settings.min_repetitions.max(1), 10_000_000);
    let mut times = Vec::with_capacity(repetitions);
    for _ in 0..repetitions {
        let t = Instant::now();
        job.run_untallied()?;
        times.push(t.elapsed().as_secs_f64());
    }
    times.sort_by(f64::total_cmp);
    let n = times.len();
    let median_s = if n % 2 == 1 {
        times[n / 2]
    } else {
        0.5 * (times[n / 2 - 1] + times[n / 2])
    };
    Ok(JobReport {
        job: job.name,
        description: job.description,
        median_s,
        min_s: times[0],
        max_s: times[n - 1],
        points,
        per_point_s: median_s / points.max(1) as f64,
        repetitions,
        evals,
    })
}

/// Prepares and measures every job, in the order of [`JOB_NAMES`].
pub fn run_all(settings: Settings) -> Result<Vec<JobReport>, Error> {
    jobs()?.iter().map(|j| measure(j, settings)).collect()
}

/// The reports as a JSON array, one record per job.
pub fn to_json(reports: &[JobReport]) -> Value {
    Value::Array(reports.iter().map(JobReport::to_json).collect())
}

/// A duration in seconds with a unit that keeps 3–4 significant digits.
pub fn format_seconds(s: f64) -> String {
    match s {
        _ if s >= 1.0 => format!("{s:.3} s"),
        _ if s >= 1e-3 => format!("{:.3} ms", s * 1e3),
        _ if s >= 1e-6 => format!("{:.2} us", s * 1e6),
        _ => format!("{:.0} ns", s * 1e9),
    }
}

/// The reports as an aligned text table.
pub fn table(reports: &[JobReport]) -> String {
    let mut header = vec![
        "job".to_string(),
        "median".into(),
        "min".into(),
        "reps".into(),
        "points".into(),
        "per point".into(),
    ];
    header.extend(EVAL_KINDS.iter().map(|k| format!("evals {k}")));
    let rows: Vec<Vec<String>> = reports
        .iter()
        .map(|r| {
            let mut row = vec![
                r.job.to_string(),
                format_seconds(r.median_s),
                format_seconds(r.min_s),
                r.repetitions.to_string(),
                r.points.to_string(),
                format_seconds(r.per_point_s),
            ];
            row.extend(r.evals.iter().map(u64::to_string));
            row
        })
        .collect();
    let widths: Vec<usize> = (0..header.len())
        .map(|c| {
            std::iter::once(&header)
                .chain(&rows)
                .map(|r| r[c].chars().count())
                .max()
                .unwrap_or(0)
        })
        .collect();
    let line = |cells: &[String]| {
        cells
            .iter()
            .zip(&widths)
            .enumerate()
            .map(|(c, (cell, &w))| {
                if c == 0 {
                    format!("{cell:<w$}")
                } else {
                    format!("{cell:>w$}")
                }
            })
            .collect::<Vec<_>>()
            .join("  ")
    };
    let mut out = line(&header);
    out.push('\n');
    for r in &rows {
        out.push_str(&line(r));
        out.push('\n');
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quick_run_gives_one_record_per_job_with_the_public_keys() {
        let reports = run_all(Settings::quick()).unwrap();
        let v = to_json(&reports);
        let records = v.as_array().unwrap();
        assert_eq!(records.len(), JOB_NAMES.len());
        for (r, name) in records.iter().zip(JOB_NAMES) {
            assert_eq!(r["job"], name);
            for key in ["median_s", "per_point_s"] {
                assert!(r[key].as_f64().is_some_and(|t| t > 0.0), "{name}: {key}");
            }
            assert!(r["points"].as_u64().is_some_and(|n| n >= 1), "{name}");
            assert!(r["repetitions"].as_u64().is_some_and(|n| n >= 1), "{name}");
            let evals = r["evals"].as_object().unwrap();
            for k in EVAL_KINDS {
                assert!(evals[k].as_u64().is_some(), "{name}: evals.{k}");
            }
            assert!(evals["order1"].as_u64().unwrap() > 0, "{name}");
        }
        // The three-scene job runs the default scene's diagram and two more.
        assert!(reports[4].points > reports[3].points);
        assert!(table(&reports).lines().count() == JOB_NAMES.len() + 1);
    }
}
