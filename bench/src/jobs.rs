//! The benchmark jobs: what each one runs, prepared once and run repeatedly.

use super::cycles::{CycleWork, LastCycle};
use super::sandbox::{silence_stdout, TempDir};
use clap::Parser;
use continuation::N_EVAL_KINDS;
use continuation::{AsIs, ContinuationSettings, Counting, Wrap};
use serde_json::Value;
use std::path::Path;
use stickslip::analysis::diagram::{hopf_curve_with, DEFAULT_CURVE_STEPS};
use stickslip::analysis::hopf::{find_hopf_with, HopfOutcome};
use stickslip::analysis::model_choice::DEFAULT_INERTIA_THRESHOLD;
use stickslip::cli::diagram::DiagramArgs;
use stickslip::cli::files::OutputArgs;
use stickslip::cli::{Cli, SceneArgs, TextUnits};
use stickslip::error::{Error, NumericalError};
use stickslip::jobs::hopf::HopfRequest;
use stickslip::jobs::SceneSpec;
use stickslip::model::ModelKind;
use stickslip::params::Params;

/// Names of the jobs, in the order they run.
pub const JOB_NAMES: [&str; 13] = [
    "hopf_point_l1",
    "hopf_point_l1_inertial",
    "hopf_curve_4_decades",
    "diagram_default",
    "diagram_three_scenes_parallel",
    "cycle_branch_100",
    "cycle_branch_100_inertial",
    "auto_job2_diagram",
    "auto_job3_cycles",
    "auto_job4_stiff_branch",
    "auto_job5_fold_curve",
    "hopf_job",
    "fit_velocity_step",
];

/// The command lines of the jobs compared with AUTO-07p (docs/performance.md,
/// "Side by side"), after `stickslip`; each writes into a temporary `--out`.
const AUTO_JOBS: [(&str, &str, &[&str]); 4] = [
    (
        "auto_job2_diagram",
        "job 2: `diagram --set m=0.01 --model inertial --nu-range 0.01:100` end to end",
        &["diagram", "--json", "--set", "m=0.01", "--model", "inertial", "--nu-range", "0.01:100"],
    ),
    (
        "auto_job3_cycles",
        "job 3: `cycles --set m=0.01 --model inertial --ntst 50 --ntst-max 50 --kappa-fraction 0.44504` end to end",
        &[
            "cycles", "--json", "--set", "m=0.01", "--model", "inertial", "--ntst", "50",
            "--ntst-max", "50", "--kappa-fraction", "0.44504",
        ],
    ),
    (
        "auto_job4_stiff_branch",
        "job 4: `cycles --set m=0.01 --model inertial --kappa-fraction 0.023223` end to end",
        &[
            "cycles", "--json", "--set", "m=0.01", "--model", "inertial", "--kappa-fraction",
            "0.023223",
        ],
    ),
    (
        "auto_job5_fold_curve",
        "job 5: `cycles` on the cutoff law (theta_c = 10, m = 1, nu = 0.085) with `--lpc-curve`, end to end",
        &[
            "cycles", "--json", "--set", "A=0.012", "--set", "B=0.023", "--set", "mu0=0.5",
            "--set", "theta_c=10", "--set", "m=1", "--set", "nu=0.085", "--lpc-curve",
        ],
    ),
];

/// The inertial variant of the worked example (docs/index.md §5).
const INERTIAL_OVERRIDES: [&str; 5] = ["A=0.01", "B=0.02", "mu2=5e-4", "m=0.1", "nu=3"];

/// The scenes of `diagram_three_scenes_parallel`.
const THREE_SCENES: &str = "pmma,pmma-rr,brockley";

/// What one run of a job produced.
#[derive(Clone, Debug)]
pub struct Tally {
    /// 1 for a Hopf point, the curve points of a diagram, the cycles of a
    /// branch; 1 for a whole command line.
    pub points: usize,
    /// The last cycle of a cycle branch.
    pub last_cycle: Option<LastCycle>,
}

/// A prepared benchmark job.
pub struct Job {
    /// One of [`JOB_NAMES`].
    pub name: &'static str,
    /// What the job does, in one line.
    pub description: &'static str,
    work: Work,
}

enum Work {
    /// The `hopf` job of the library as the command line and Python run it
    /// (scene loaded, model chosen, onset, l1 with its bound, operating
    /// point): the reference of Python's per-call overhead.
    HopfJob(SceneSpec),
    /// `jobs::fit::run` on a time series (integration with forward
    /// sensitivities inside Levenberg–Marquardt); its models are built by
    /// the job itself, so its evaluations are not counted.
    Fit(Box<(SceneSpec, stickslip::jobs::fit::FitRequest)>),
    /// `find_hopf` (continuation in kappa, Hopf location, normal form with l1).
    Hopf { kind: ModelKind, params: Params },
    /// `hopf_curve` (the Hopf curve in (ln kappa, ln nu) with l1 at every
    /// point and l2 at Bautin points; the curves of folds of cycles that
    /// `stability_diagram` adds are timed with the diagram jobs).
    Curve {
        kind: ModelKind,
        params: Params,
        range: (f64, f64),
    },
    /// The `diagram` command end to end (figures, CSV, JSON written), its
    /// standard output discarded.
    Diagram {
        args: Box<DiagramArgs>,
        /// File-name stems of the scenes (their `name`), to count points.
        stems: Vec<String>,
        _dir: TempDir,
    },
    /// A branch of cycles from the Hopf point on a fixed mesh, with Floquet multipliers.
    Cycles(Box<CycleWork>),
    /// A whole command line (`stickslip` and `args`) run as `main` runs it,
    /// its standard output discarded; its models are built by the command
    /// itself, so its evaluations are not counted.
    Command { args: Vec<String>, _dir: TempDir },
}

/// The velocity-step fit of the speed target (issue 26: four
/// parameters from 2000 points in at most 2 s): the example data on the
/// stiff-machine PMMA scene, started from values 5-20 % off, without the
/// fitted scene's stability band.
fn fit_work() -> Work {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/..");
    let spec = scene_spec(
        &format!("{root}/examples/scenes/pmma-machine.toml"),
        &["A=0.0135", "B=0.021", "D0=0.47", "mu0=0.502"],
    );
    let request = stickslip::jobs::fit::FitRequest {
        data: vec![(
            stickslip::fit::data::Kind::VelocityStep,
            format!("{root}/examples/data/pmma-velocity-step.csv").into(),
        )],
        free: Some(["A", "B", "D0", "mu0"].map(String::from).to_vec()),
        stability: false,
    };
    Work::Fit(Box::new((spec, request)))
}

/// A scene with `--set` overrides, the model chosen.
fn scene_spec(scene: &str, set: &[&str]) -> SceneSpec {
    SceneSpec {
        set: set.iter().map(|s| s.to_string()).collect(),
        ..SceneSpec::named(scene)
    }
}

/// The diagram command's scene options: `scenes` as they are.
fn scene_args(scenes: &str) -> SceneArgs {
    SceneArgs {
        scene: Some(scenes.to_string()),
        set: Vec::new(),
        model: None,
        inertia_threshold: DEFAULT_INERTIA_THRESHOLD,
    }
}

impl Job {
    /// Prepares the job called `name` (one of [`JOB_NAMES`]).
    pub fn new(name: &str) -> Result<Job, Error> {
        let (name, description, work) = match name {
            "hopf_job" => (
                JOB_NAMES[11],
                "jobs::hopf::run on the default scene (what `stickslip.hopf()` runs)",
                Work::HopfJob(SceneSpec::named(stickslip::scene::DEFAULT_SCENE)),
            ),
            "fit_velocity_step" => (
                JOB_NAMES[12],
                "jobs::fit::run: A, B, D0, mu0 from examples/data/pmma-velocity-step.csv (2000 rows), started 5-20 % off",
                fit_work(),
            ),
            "hopf_point_l1" => {
                let setup = scene_spec(stickslip::scene::DEFAULT_SCENE, &[]).setup(|p| *p)?;
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
                    scene_spec(stickslip::scene::DEFAULT_SCENE, &INERTIAL_OVERRIDES).setup(|p| *p)?;
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
                let scene = stickslip::scene::load("pmma")?;
                (
                    JOB_NAMES[2],
                    "hopf_curve, pmma, inertial, nu in [0.01, 100], l1 at every point",
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
                diagram_work(stickslip::scene::DEFAULT_SCENE)?,
            ),
            "diagram_three_scenes_parallel" => (
                JOB_NAMES[4],
                "`stickslip diagram --scene pmma,pmma-rr,brockley` end to end (rayon)",
                diagram_work(THREE_SCENES)?,
            ),
            // Quasi-static cycles stiffen fast: at NTST = 50 the Floquet
            // multipliers are lost below ~0.92 kappa_c, so short steps.
            "cycle_branch_100" => (
                JOB_NAMES[5],
                "100 cycles from the Hopf point, pmma (quasi-static), NTST 50, degree 4, multipliers",
                cycle_work(&[], 0.94, 0.02)?,
            ),
            "cycle_branch_100_inertial" => (
                JOB_NAMES[6],
                "100 cycles from the Hopf point, pmma --set m=0.01 (inertial), NTST 50, degree 4, Radau points, multipliers",
                cycle_work(&["m=0.01"], 0.3, 0.05)?,
            ),
            other => match AUTO_JOBS.into_iter().find(|j| j.0 == other) {
                Some((name, description, args)) => (name, description, command_work(args)?),
                None => {
                    return Err(NumericalError::Analysis(format!(
                        "no benchmark job '{other}'; jobs: {}",
                        JOB_NAMES.join(", ")
                    ))
                    .into())
                }
            },
        };
        Ok(Job {
            name,
            description,
            work,
        })
    }

    /// Runs the job once with every model it builds [`Counted`](continuation::Counted)
    /// into one tally; returns what it produced and the evaluations, indexed
    /// like [`EVAL_KINDS`](continuation::EVAL_KINDS).
    pub fn run_counted(&self) -> Result<(Tally, [u64; N_EVAL_KINDS]), Error> {
        let counting = Counting::new();
        let tally = self.execute(&counting, true)?;
        Ok((tally, counting.counts()))
    }

    /// Runs the job once, as it is timed: no counters, and no counting of
    /// points afterwards (for the diagram jobs, that means reading the JSON
    /// files back).
    pub fn run_untallied(&self) -> Result<(), Error> {
        self.execute(&AsIs, false).map(|_| ())
    }

    fn execute<F: Wrap>(&self, fields: &F, tally: bool) -> Result<Tally, Error> {
        let points = |points| Tally {
            points,
            last_cycle: None,
        };
        match &self.work {
            Work::Fit(work) => {
                let f = stickslip::jobs::fit::run(&work.0, &work.1)?;
                Ok(points(std::hint::black_box(f).summary.datasets[0].rows))
            }
            Work::HopfJob(spec) => {
                let h = stickslip::jobs::hopf::run(spec, &HopfRequest::default())?;
                std::hint::black_box(&h);
                Ok(points(1))
            }
            Work::Hopf { kind, params } => match find_hopf_with(
                fields,
                *kind,
                params,
                &ContinuationSettings::default().locator,
            )? {
                HopfOutcome::Found(h) => {
                    std::hint::black_box(&h);
                    Ok(points(1))
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
                let d = hopf_curve_with(
                    fields,
                    *kind,
                    params,
                    stickslip::params::Param::Nu,
                    *range,
                    DEFAULT_CURVE_STEPS,
                )?;
                Ok(points(std::hint::black_box(d).points.len()))
            }
            Work::Diagram { args, stems, .. } => {
                kept(silence_stdout(|| {
                    stickslip::cli::diagram::run_with(args, fields)
                }))?;
                if tally {
                    stems
                        .iter()
                        .map(|s| curve_points(&args.output.out, s))
                        .sum::<Result<usize, Error>>()
                        .map(points)
                } else {
                    Ok(points(0))
                }
            }
            Work::Cycles(work) => {
                let (count, last) = work.run(fields)?;
                Ok(Tally {
                    points: count,
                    last_cycle: Some(last),
                })
            }
            Work::Command { args, .. } => {
                let cli = Cli::try_parse_from(args)
                    .map_err(|e| NumericalError::Analysis(format!("{}: {e}", self.name)))?;
                kept(silence_stdout(|| stickslip::cli::run(cli)))?;
                Ok(points(1))
            }
        }
    }
}

/// A command's outcome as work done: partial results (status 4: kept, the
/// request incomplete, e.g. a fold-of-cycles curve that stops short where
/// its cycles become too stiff) are the work measured.
fn kept(outcome: Result<(), Error>) -> Result<(), Error> {
    match outcome {
        Err(Error::Partial(_)) => Ok(()),
        other => other,
    }
}

/// All jobs of [`JOB_NAMES`], prepared.
pub fn jobs() -> Result<Vec<Job>, Error> {
    JOB_NAMES.iter().map(|n| Job::new(n)).collect()
}

/// The cycle branch of the default scene with `set` overrides, down to at
/// most `fraction kappa_c`, arclength steps up to `ds_max`.
fn cycle_work(set: &[&str], fraction: f64, ds_max: f64) -> Result<Work, Error> {
    let setup = scene_spec(stickslip::scene::DEFAULT_SCENE, set).setup(|p| *p)?;
    Ok(Work::Cycles(Box::new(CycleWork::new(
        setup.choice.kind,
        &setup.params,
        fraction,
        ds_max,
    )?)))
}

/// The command line `stickslip args --out <temporary> --force`.
fn command_work(args: &[&str]) -> Result<Work, Error> {
    let dir = TempDir::new()?;
    let out = dir.0.display().to_string();
    let args = ["stickslip"]
        .iter()
        .chain(args)
        .map(|a| a.to_string())
        .chain(["--out".to_string(), out, "--force".to_string()])
        .collect();
    Ok(Work::Command { args, _dir: dir })
}

fn diagram_work(scenes: &str) -> Result<Work, Error> {
    let dir = TempDir::new()?;
    let stems = scenes
        .split(',')
        .map(|s| stickslip::scene::load(s).map(|sc| sc.name))
        .collect::<Result<_, _>>()?;
    Ok(Work::Diagram {
        args: Box::new(DiagramArgs {
            scene: scene_args(scenes),
            nu_range: None,
            output: OutputArgs {
                out: dir.0.clone(),
                name: None,
                // Each repetition of the job writes the same files again.
                force: true,
            },
            units: TextUnits::Physical,
            json: false,
            max_steps: stickslip::analysis::diagram::DEFAULT_CURVE_STEPS,
            axes: Default::default(),
        }),
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
