//! Benchmark jobs of `stickslip`: the analyses a user runs, timed end to
//! end, with the number of vector-field evaluations each one makes; and the
//! work-precision study ([`work_precision`]).
//!
//! The `stickslip-bench` binary and the criterion benchmarks
//! (`benches/jobs.rs`) share these jobs. A job is prepared once (scene
//! loaded, overrides applied, model chosen, output directory created) and
//! then run repeatedly; only the run is timed. Evaluation counts come from one
//! further run with every model the analyses build wrapped in a
//! [`Counted`](continuation::Counted) ([`Job::run_counted`]), so they are
//! exact for that run and the timed runs carry no counters.
//! See `docs/performance.md`.

#![warn(missing_docs)]

mod cycles;
mod jobs;
mod measure;
mod reference;
mod report;
mod sandbox;
pub mod work_precision;

pub use cycles::{Accuracy, LastCycle};
pub use jobs::{jobs, Job, Tally, JOB_NAMES};
pub use measure::{measure, run_all, JobReport, Settings};
pub use reference::{reference_cycle, ReferenceCycle, REFERENCE};
pub use report::{format_seconds, table, to_json};

#[cfg(test)]
mod tests {
    use super::*;
    use continuation::EVAL_KINDS;

    #[test]
    fn quick_run_gives_one_record_per_job_with_the_public_keys() {
        let reports = run_all(&[], Settings::quick()).unwrap();
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
            // A whole command line, or a library job, builds its models
            // itself: not counted.
            let counted =
                !name.starts_with("auto_job") && !["hopf_job", "fit_velocity_step"].contains(&name);
            assert_eq!(evals["order1"].as_u64().unwrap() > 0, counted, "{name}");
        }
        // The three-scene job runs the default scene's diagram and two more.
        assert!(reports[4].points > reports[3].points);
        // Cycle branches: their last cycle agrees with long-time integration
        // (a different method), whose own spread is far smaller.
        for (r, record) in reports[5..7].iter().zip(&records[5..7]) {
            assert_eq!(r.points, 100, "{}", r.job);
            let a = r
                .accuracy
                .as_ref()
                .expect("a cycle job checks its last cycle");
            assert!(
                a.period_error < 1e-6 && a.delta_s_error < 1e-6,
                "{}: {a:?}",
                r.job
            );
            assert!(a.reference_spread < 1e-10, "{}: {a:?}", r.job);
            assert!(record["accuracy"]["period_rel_error"].is_f64());
        }
        assert!(reports[..5]
            .iter()
            .chain(&reports[7..])
            .all(|r| r.accuracy.is_none()));
        assert!(table(&reports).lines().count() == JOB_NAMES.len() + 1);
    }
}
