//! Speed against accuracy: each job is run with its accuracy knobs turned,
//! and its error is measured against an independent reference: a closed
//! form, or for cycles a different method (long-time integration).
//!
//! | job | methods (knob) | reference |
//! |---|---|---|
//! | `l1` at the PMMA onset | exact multilinear forms (dual numbers); finite differences (step `h`) | `l1 = -mu2 nu^2 / (2 sqrt(A (mu_phi - A)) D)` |
//! | `kappa_c` of the PMMA scene | Newton tolerance of the Hopf location | `kappa_c = mu_phi - mu_v` (eq. C12) |
//! | period and `Delta_s` of a stick-slip cycle (quasi-static PMMA at `0.95 kappa_c`; `m = 0.01` at `0.5 kappa_c`) | collocation of degree 2 to 5, adaptive or uniform mesh (`NTST`) | Radau IIA integration at `rtol = 1e-13` |

mod cycles;
mod onset;

pub use onset::l1_finite_differences;

use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;
use stickslip::error::Error;
use stickslip::plot::lines::{render, LineFigure};

/// One measurement: a method at one setting of its knob.
#[derive(Clone, Debug)]
pub struct Measurement {
    /// What is measured (`kappa_c`, `l1`, a cycle's period or `Delta_s`).
    pub job: &'static str,
    /// How it is computed.
    pub method: String,
    /// The accuracy knob's setting (a tolerance, a step, `NTST`; 0 where none).
    pub knob: f64,
    /// CPU seconds of one evaluation (median over batches, see `time_it`);
    /// NaN when the method failed at this setting.
    pub seconds: f64,
    /// Relative error against the reference; NaN when the method failed.
    pub error: f64,
}

/// Runs the whole study: the onset jobs, then the cycles.
pub fn study() -> Result<Vec<Measurement>, Error> {
    let mut out = onset::study()?;
    out.extend(cycles::study()?);
    Ok(out)
}

/// Writes `work-precision.csv` and the figures into `out`.
pub fn write(measurements: &[Measurement], out: &Path) -> Result<Vec<PathBuf>, Error> {
    std::fs::create_dir_all(out)?;
    let csv_path = out.join("work-precision.csv");
    let mut csv = std::io::BufWriter::new(std::fs::File::create(&csv_path)?);
    writeln!(csv, "job,method,knob,seconds,relative_error")?;
    for m in measurements {
        writeln!(
            csv,
            "{},{},{:e},{:.6e},{:.6e}",
            m.job, m.method, m.knob, m.seconds, m.error
        )?;
    }
    csv.flush()?;
    let mut files = vec![csv_path];
    files.extend(onset::figures(measurements, out)?);
    files.extend(cycles::figures(measurements, out)?);
    Ok(files)
}

/// Median CPU seconds per call of `f`: calls in batches of about 1 ms of
/// CPU time (a clock read costs a fraction of a microsecond), batches
/// repeated for about 50 ms of wall time (at least 5).
fn time_it<T>(mut f: impl FnMut() -> T) -> f64 {
    let t0 = cpu_seconds();
    std::hint::black_box(f());
    let batch = (1e-3 / (cpu_seconds() - t0).max(1e-7)).ceil() as usize;
    let start = Instant::now();
    let mut per_call = Vec::new();
    while per_call.len() < 5 || start.elapsed().as_secs_f64() < 0.05 {
        let t = cpu_seconds();
        for _ in 0..batch {
            std::hint::black_box(f());
        }
        per_call.push((cpu_seconds() - t) / batch as f64);
    }
    per_call.sort_by(f64::total_cmp);
    per_call[per_call.len() / 2]
}

/// CPU time of the calling thread, seconds: unlike wall time, it does not
/// grow while other processes have the core (the study runs on shared
/// machines).
#[cfg(unix)]
fn cpu_seconds() -> f64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: clock_gettime only writes the timespec it is handed.
    unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    ts.tv_sec as f64 + 1e-9 * ts.tv_nsec as f64
}

/// Wall time since the first call, where no thread CPU clock is at hand.
#[cfg(not(unix))]
fn cpu_seconds() -> f64 {
    static START: std::sync::OnceLock<Instant> = std::sync::OnceLock::new();
    START.get_or_init(Instant::now).elapsed().as_secs_f64()
}

/// The methods measured for `job`, in order of appearance.
fn methods<'a>(measurements: &'a [Measurement], job: &str) -> Vec<&'a str> {
    let mut methods: Vec<&str> = measurements
        .iter()
        .filter(|m| m.job == job)
        .map(|m| m.method.as_str())
        .collect();
    methods.dedup();
    methods
}

/// `(seconds, error)` of `method` on `job`, failures left out.
fn points(measurements: &[Measurement], job: &str, method: &str) -> Vec<(f64, f64)> {
    measurements
        .iter()
        .filter(|m| m.job == job && m.method == method && m.error.is_finite())
        .map(|m| (m.seconds, m.error))
        .collect()
}

/// Writes `out/work-precision-<name>.png` and `.svg`.
fn render_figure(fig: &LineFigure, out: &Path, name: &str) -> Result<Vec<PathBuf>, Error> {
    render(fig, &out.join(format!("work-precision-{name}")))
        .map_err(|e| Error::Output(std::io::Error::other(e.to_string())))
}
