//! `stickslip-bench`: times the user-level jobs of `stickslip` and counts
//! their vector-field evaluations, or runs the work-precision study.

use clap::Parser;
use continuation::EVAL_KINDS;
use std::process::ExitCode;
use stickslip::error::Error;
use stickslip_bench::{run_all, table, to_json, Settings};

/// Time the user-level jobs of stickslip (Hopf point, Hopf curve, diagrams,
/// cycle branches) and count vector-field evaluations.
#[derive(Parser, Debug)]
#[command(name = "stickslip-bench", version)]
struct BenchArgs {
    /// Print a JSON array, one record per job (`job`, `median_s`, `points`,
    /// `per_point_s`, `repetitions`, `evals`), instead of a table.
    #[arg(long)]
    json: bool,
    /// A fast smoke run: about 10 ms of repetitions per job instead of 0.5 s
    /// (timings are rough; evaluation counts are exact either way).
    #[arg(long)]
    quick: bool,
    /// Instead of the job table: the work-precision study (error against
    /// time as the accuracy knobs turn), written as CSV and figures into `--out`.
    #[arg(long)]
    work_precision: bool,
    /// Only these jobs (repeatable; default: all of them).
    #[arg(long = "job", value_name = "NAME")]
    jobs: Vec<String>,
    /// Output directory of `--work-precision`.
    #[arg(long, default_value = "out")]
    out: std::path::PathBuf,
}

fn main() -> ExitCode {
    match run(&BenchArgs::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("stickslip-bench: {e}");
            ExitCode::from(e.exit_code() as u8)
        }
    }
}

/// Runs the command.
fn run(args: &BenchArgs) -> Result<(), Error> {
    if args.work_precision {
        let m = stickslip_bench::work_precision::study()?;
        println!(
            "{:<26} {:<36} {:>8} {:>12} {:>12}",
            "job", "method", "knob", "time [s]", "rel. error"
        );
        for r in &m {
            // Counts (NTST) as integers, tolerances and steps as powers of ten.
            let knob = if r.knob >= 1.0 && r.knob.fract() == 0.0 {
                format!("{}", r.knob)
            } else {
                format!("{:.0e}", r.knob)
            };
            println!(
                "{:<26} {:<36} {:>8} {:>12.3e} {:>12.3e}",
                r.job, r.method, knob, r.seconds, r.error
            );
        }
        for f in stickslip_bench::work_precision::write(&m, &args.out)? {
            println!("wrote {}", f.display());
        }
        return Ok(());
    }
    let settings = if args.quick {
        Settings::quick()
    } else {
        Settings::full()
    };
    let reports = run_all(&args.jobs, settings)?;
    if args.json {
        println!(
            "{}",
            serde_json::to_string_pretty(&to_json(&reports)).map_err(std::io::Error::other)?
        );
        return Ok(());
    }
    println!(
        "wall time of one run (median over reps), {} thread(s){}",
        rayon::current_num_threads(),
        if args.quick { ", --quick: rough" } else { "" }
    );
    println!(
        "evals: rhs calls of the driven-block model in one run, by derivative order of the scalar ({})",
        EVAL_KINDS.join(", ")
    );
    println!();
    print!("{}", table(&reports));
    println!();
    for r in &reports {
        println!("  {:<30} {}", r.job, r.description);
    }
    Ok(())
}
