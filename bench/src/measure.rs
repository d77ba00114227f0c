//! Timing: repetitions to fill a time budget, their median, and the
//! evaluation counts of one run.

use super::cycles::Accuracy;
use super::jobs::{jobs, Job};
use continuation::N_EVAL_KINDS;
use std::time::{Duration, Instant};
use stickslip::error::Error;

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
    /// The job's name, one of [`JOB_NAMES`](super::JOB_NAMES).
    pub job: &'static str,
    /// What the job does, in one line.
    pub description: &'static str,
    /// Median wall time of one run, seconds.
    pub median_s: f64,
    /// Fastest run, seconds.
    pub min_s: f64,
    /// Slowest run, seconds.
    pub max_s: f64,
    /// Points the job produced.
    pub points: usize,
    /// `median_s / points`.
    pub per_point_s: f64,
    /// Timed runs.
    pub repetitions: usize,
    /// Vector-field evaluations of one run, indexed like
    /// [`EVAL_KINDS`](continuation::EVAL_KINDS).
    pub evals: [u64; N_EVAL_KINDS],
    /// For a cycle branch: its last cycle against long-time integration.
    pub accuracy: Option<Accuracy>,
}

/// Times `job`: one run with evaluation counting (which also warms caches
/// and the thread pool; a cycle branch's last cycle is then checked against
/// integration, untimed), one run to estimate the time, then enough timed
/// runs (without counters) to fill `settings.budget`; reports their median.
pub fn measure(job: &Job, settings: Settings) -> Result<JobReport, Error> {
    let (tally, evals) = job.run_counted()?;
    let accuracy = tally.last_cycle.map(|c| c.accuracy()).transpose()?;
    let points = tally.points;
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
        accuracy,
    })
}

/// Prepares and measures the jobs named in `only`, or every job in the
/// order of [`JOB_NAMES`](super::JOB_NAMES) when `only` is empty.
pub fn run_all(only: &[String], settings: Settings) -> Result<Vec<JobReport>, Error> {
    if only.is_empty() {
        return jobs()?.iter().map(|j| measure(j, settings)).collect();
    }
    only.iter()
        .map(|name| measure(&Job::new(name)?, settings))
        .collect()
}
