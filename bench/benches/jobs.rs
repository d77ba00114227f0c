//! Criterion benchmarks of the user-level jobs of `stickslip-bench`
//! (`stickslip_bench::JOB_NAMES`): `cargo bench -p stickslip-bench` (all),
//! `cargo bench -p stickslip-bench -- hopf_point` (a filter). Short
//! measurement windows keep the whole run near a minute; the diagram jobs
//! write their files into a temporary directory and discard the command's
//! standard output. See docs/performance.md.

use criterion::{criterion_group, criterion_main, Criterion, SamplingMode};
use std::time::Duration;
use stickslip_bench::{Job, JOB_NAMES};

fn jobs(c: &mut Criterion) {
    let mut group = c.benchmark_group("jobs");
    group.warm_up_time(Duration::from_secs(1));
    for name in JOB_NAMES {
        // Millisecond jobs: a fixed iteration count per sample.
        group.sampling_mode(if name.starts_with("hopf_point") {
            SamplingMode::Auto
        } else {
            SamplingMode::Flat
        });
        // Cycle branches take a few tenths of a second, the jobs compared with
        // AUTO-07p up to seconds: criterion's fewest samples.
        let cycles = name.starts_with("cycle_branch") || name.starts_with("auto_job");
        group
            .sample_size(if cycles { 10 } else { 20 })
            .measurement_time(Duration::from_secs(if cycles { 5 } else { 3 }));
        // Prepared (and run once) only when the filter selects the job.
        let mut job: Option<Job> = None;
        group.bench_function(name, |b| {
            let job = job.get_or_insert_with(|| {
                let job = Job::new(name).unwrap_or_else(|e| panic!("preparing {name}: {e}"));
                job.run_untallied()
                    .unwrap_or_else(|e| panic!("first run of {name}: {e}"));
                job
            });
            b.iter(|| job.run_untallied().expect("benchmark job failed"))
        });
    }
    group.finish();
}

criterion_group!(benches, jobs);
criterion_main!(benches);
