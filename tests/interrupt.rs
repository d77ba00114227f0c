//! Ctrl-C on long runs: `cycles`, `simulate` and a many-scene `diagram` are
//! sent SIGINT part-way and must exit with status 130, keep what was computed
//! (complete rows, no NaN, figures), and say where they stopped; SIGTERM
//! does the same with exit status 143.

mod common;

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// What an interrupted run left behind.
struct Interrupted {
    code: Option<i32>,
    stdout: String,
    stderr: String,
}

/// Runs stickslip with `args`, sends it SIGINT as soon as `ready(stdout so
/// far)` holds (polled every 20 ms, for at most 120 s), and waits for it to
/// exit (killing it after another 120 s).
fn interrupt_when(args: &[&str], ready: impl Fn(&str) -> bool) -> Interrupted {
    signal_when(args, libc::SIGINT, ready)
}

/// [`interrupt_when`] with the signal `signal`.
fn signal_when(args: &[&str], signal: libc::c_int, ready: impl Fn(&str) -> bool) -> Interrupted {
    let mut child = Command::new(env!("CARGO_BIN_EXE_stickslip"))
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start stickslip");
    let drain = |pipe: Option<Box<dyn Read + Send>>| {
        let text = Arc::new(Mutex::new(String::new()));
        let sink = Arc::clone(&text);
        let thread = std::thread::spawn(move || {
            let mut pipe = pipe.expect("piped");
            let mut buf = [0u8; 4096];
            while let Ok(n @ 1..) = pipe.read(&mut buf) {
                sink.lock()
                    .unwrap()
                    .push_str(&String::from_utf8_lossy(&buf[..n]));
            }
        });
        (text, thread)
    };
    let (stdout, out_thread) = drain(child.stdout.take().map(|p| Box::new(p) as _));
    let (stderr, err_thread) = drain(child.stderr.take().map(|p| Box::new(p) as _));
    let start = Instant::now();
    while !ready(&stdout.lock().unwrap())
        && child.try_wait().unwrap().is_none()
        && start.elapsed() < Duration::from_secs(120)
    {
        std::thread::sleep(Duration::from_millis(20));
    }
    // SAFETY: sending a signal to our own child process.
    unsafe {
        libc::kill(child.id() as libc::pid_t, signal);
    }
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if start.elapsed() > Duration::from_secs(120) {
            let _ = child.kill();
            panic!("stickslip {args:?} did not stop within 120 s of signal {signal}");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    out_thread.join().unwrap();
    err_thread.join().unwrap();
    let text = |t: Arc<Mutex<String>>| t.lock().unwrap().clone();
    Interrupted {
        code: status.code(),
        stdout: text(stdout),
        stderr: text(stderr),
    }
}

/// A fresh output directory for one test.
fn out_dir(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("stickslip-{test}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn lines(path: &Path) -> usize {
    std::fs::read_to_string(path)
        .map(|s| s.lines().count())
        .unwrap_or(0)
}

#[test]
fn ctrl_c_keeps_the_cycles_computed_so_far() {
    cycles_stopped_by(libc::SIGINT, 130, "Ctrl-C", "interrupt-cycles");
}

/// `cycles` sent `signal` once a few cycles are on disk (rows are written
/// as computed): exit `code`, the message names the signal (`word`), the
/// rows computed are kept whole and marked incomplete, with their figures.
fn cycles_stopped_by(signal: libc::c_int, code: i32, word: &str, dir_name: &str) {
    let dir = out_dir(dir_name);
    let out = dir.to_str().unwrap();
    let csv_path = dir.join("pmma_m=0.01-cycles.csv");
    let args = [
        "cycles",
        "--set",
        "m=0.01",
        "--kappa-fraction",
        "0.01",
        "--max-steps",
        "100000",
        "--out",
        out,
    ];
    let run = signal_when(&args, signal, |_| lines(&csv_path) >= 6);
    let err = &run.stderr;
    assert_eq!(run.code, Some(code), "{err}");
    assert!(
        err.contains(&format!("interrupted ({word})")) && err.contains("kept"),
        "{err}"
    );
    assert!(
        lines(&csv_path) >= 6,
        "cycles written before the signal are kept"
    );
    // The comment lines (the model first, the incomplete branch last) aside,
    // every row matches the header.
    assert!(whole_rows_marked_incomplete(&csv_path) >= 4, "rows kept");
    assert!(
        dir.join("pmma_m=0.01-cycles-amplitude.png").exists(),
        "figures of the computed cycles"
    );
    // Every figure of the branch says it was interrupted (the orbits and
    // the time series did not, session 25).
    for figure in ["amplitude", "period", "orbits", "time-series"] {
        let svg = std::fs::read_to_string(dir.join(format!("pmma_m=0.01-cycles-{figure}.svg")))
            .unwrap_or_default();
        assert!(svg.contains("interrupted"), "{figure}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn ctrl_c_keeps_the_simulated_time_series() {
    let dir = out_dir("interrupt-simulate");
    let out = dir.to_str().unwrap();
    // Stick-slip for 200 x 1500 s, several seconds of computing; interrupted
    // once rows are on disk.
    let protocol = vec!["1:1500"; 200].join(",");
    let csv_path = dir.join("pmma_kappa=0.009-simulation.csv");
    let args = [
        "simulate",
        "--set",
        "kappa=0.009",
        "--protocol",
        &protocol,
        "--out",
        out,
    ];
    let run = interrupt_when(&args, |_| lines(&csv_path) >= 50);
    let err = &run.stderr;
    assert_eq!(run.code, Some(130), "{err}");
    assert!(err.contains("interrupted") && err.contains("kept"), "{err}");
    // "... at simulated time t = T s of 3.000000e5 s (N integrator steps) ..."
    let reached: f64 = err
        .split("at simulated time t = ")
        .nth(1)
        .and_then(|rest| rest.split(' ').next())
        .and_then(|t| t.parse().ok())
        .unwrap_or_else(|| panic!("no stopping time in: {err}"));
    assert!(err.contains(" s of 3.000000e5 s"), "{err}");
    assert!(reached > 0.0 && reached < 3e5, "{err}");
    let csv = std::fs::read_to_string(&csv_path).unwrap();
    // The CSV alone says it stops short.
    let last = csv.lines().last().unwrap();
    assert!(
        last.starts_with("# incomplete: interrupted at t = "),
        "{last}"
    );
    let mut rows = csv.lines().filter(|l| !l.starts_with('#'));
    // The columns simulate has always written, then the physical ones.
    assert_eq!(
        rows.next(),
        Some("t_s,t,s,v,theta,slip,log10_v,model,spring_force_N,v_um_per_s,theta_s,slip_um")
    );
    // The numeric columns; the eighth names the model of the row.
    let values: Vec<Vec<f64>> = rows
        .map(|l| {
            let cells: Vec<&str> = l.split(',').collect();
            let model = cells.get(7).copied().unwrap_or_default();
            assert!(model == "quasi-static" || model == "inertial", "{l}");
            cells
                .iter()
                .enumerate()
                .filter(|(i, _)| *i != 7)
                .map(|(_, x)| x.parse::<f64>().unwrap())
                .collect()
        })
        .collect();
    assert!(values.len() >= 50, "{} rows", values.len());
    assert!(
        values
            .iter()
            .all(|r| r.len() == 11 && r.iter().all(|x| x.is_finite())),
        "complete rows, no NaN or infinity"
    );
    assert!(
        values.windows(2).all(|w| w[1][0] > w[0][0]),
        "time increases"
    );
    // The message names the last row written.
    let last = values.last().unwrap()[0];
    assert!((last / reached - 1.0).abs() < 1e-6, "{last} vs {err}");
    for f in [
        "pmma_kappa=0.009-simulation-velocity.png",
        "pmma_kappa=0.009-simulation-spring-force.svg",
    ] {
        assert!(dir.join(f).exists(), "figure {f} of the computed part");
    }
    assert!(run.stdout.contains("wrote"), "{}", run.stdout);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn ctrl_c_skips_the_scenes_not_started() {
    let dir = out_dir("interrupt-diagram");
    std::fs::create_dir_all(&dir).unwrap();
    // Many copies of the pmma scene, each under its own name.
    let pmma = include_str!("../examples/scenes/pmma.toml").replace("name = \"pmma\"", "");
    let scenes: Vec<String> = (0..200)
        .map(|i| {
            let path = dir.join(format!("s{i:03}.toml"));
            std::fs::write(&path, &pmma).unwrap();
            path.to_str().unwrap().to_string()
        })
        .collect();
    let list = scenes.join(",");
    let args = ["diagram", "--scene", &list, "--out", dir.to_str().unwrap()];
    // A finished scene's summary is printed at once: interrupt on the first.
    let run = interrupt_when(&args, |stdout| stdout.contains("scene: "));
    let err = &run.stderr;
    assert_eq!(run.code, Some(130), "{err}");
    // "... after N of 200 scenes (completed: a, b; skipped: c, d); ..."
    let names = |key: &str| -> Vec<String> {
        let rest = err
            .split(key)
            .nth(1)
            .unwrap_or_else(|| panic!("no '{key}' in: {err}"));
        rest.split([';', ')'])
            .next()
            .unwrap()
            .split(", ")
            .filter(|s| *s != "none")
            .map(str::to_string)
            .collect()
    };
    let (completed, skipped) = (names("completed: "), names("skipped: "));
    assert!(!completed.is_empty() && !skipped.is_empty(), "{err}");
    assert_eq!(completed.len() + skipped.len(), scenes.len(), "{err}");
    let stem = |path: &str| {
        Path::new(path)
            .file_stem()
            .unwrap()
            .to_str()
            .unwrap()
            .to_string()
    };
    for s in &completed {
        let name = stem(s);
        assert!(
            run.stdout.contains(&format!("scene: {name} ")),
            "summary of {name}"
        );
        assert!(dir.join(format!("{name}-diagram.json")).exists(), "{name}");
    }
    for s in &skipped {
        let name = stem(s);
        assert!(
            !dir.join(format!("{name}-hopf-curve.csv")).exists(),
            "{name} was skipped"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The CSV at `path` holds whole rows only (as many cells as its header)
/// and ends with a `# incomplete` line; its rows.
fn whole_rows_marked_incomplete(path: &Path) -> usize {
    let csv = std::fs::read_to_string(path).unwrap();
    let mut rows = csv.lines().filter(|l| !l.starts_with('#'));
    let header = rows.next().unwrap().split(',').count();
    let rows: Vec<&str> = rows.collect();
    for row in &rows {
        assert_eq!(row.split(',').count(), header, "half row: {row}");
    }
    let last = csv.lines().last().unwrap();
    assert!(last.starts_with("# incomplete: "), "{last}");
    rows.len()
}

#[test]
fn sigterm_keeps_the_cycles_computed_so_far() {
    cycles_stopped_by(libc::SIGTERM, 143, "SIGTERM", "sigterm-cycles");
}

#[test]
fn sigterm_keeps_the_simulated_time_series() {
    let dir = out_dir("sigterm-simulate");
    let out = dir.to_str().unwrap();
    let protocol = vec!["1:1500"; 200].join(",");
    let csv_path = dir.join("pmma_kappa=0.009-simulation.csv");
    let args = [
        "simulate",
        "--set",
        "kappa=0.009",
        "--protocol",
        &protocol,
        "--out",
        out,
    ];
    let run = signal_when(&args, libc::SIGTERM, |_| lines(&csv_path) >= 50);
    let err = &run.stderr;
    assert_eq!(run.code, Some(143), "{err}");
    assert!(
        err.contains("interrupted (SIGTERM)") && err.contains("kept"),
        "{err}"
    );
    assert!(whole_rows_marked_incomplete(&csv_path) >= 50, "rows kept");
    assert!(
        dir.join("pmma_kappa=0.009-simulation-velocity.png")
            .exists(),
        "figures of the computed part"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A branch of two legs (from a simulated orbit) interrupted in its second
/// leg keeps how the first one ended beside the interruption (a stranger's
/// interrupted restart showed only `interrupted`, the other leg's stop lost),
/// and still exits 130.
#[test]
fn an_interruption_in_the_second_leg_keeps_the_first_legs_end() {
    let dir = out_dir("interrupt-second-leg");
    let out = dir.to_str().unwrap();
    let csv_path = dir.join("pmma_m=0.01-cycles.csv");
    let args = [
        "cycles",
        "--set",
        "m=0.01",
        "--from-simulation",
        "--kappa-fraction",
        "0.01",
        "--max-steps",
        "100000",
        "--json",
        "--out",
        out,
    ];
    // The leg toward larger stiffness ends at the Hopf point after 16 to 20
    // cycles; 40 rows are well into the other leg.
    let run = interrupt_when(&args, |_| lines(&csv_path) >= 40);
    assert_eq!(run.code, Some(130), "{}", run.stderr);
    let v: serde_json::Value = serde_json::from_str(&run.stdout).unwrap();
    assert_eq!(
        common::leg_reasons(&v),
        ["hopf_point", "interrupted"],
        "{}",
        run.stdout
    );
}

/// An adhesive scene's `cycles` (the gel) sent SIGTERM once a few cycles
/// are on disk: exit 143, the rows kept whole and marked incomplete, the
/// JSON partial; a rerun of the same name replaces that unfinished run's
/// files with a note instead of refusing.
#[test]
fn sigterm_keeps_the_adhesive_cycles_and_a_rerun_replaces_them() {
    let dir = out_dir("sigterm-adhesive-cycles");
    let out = dir.to_str().unwrap();
    let csv_path = dir.join("gel-cycles.csv");
    let args = ["cycles", "--scene", "gel", "--out", out];
    let run = signal_when(&args, libc::SIGTERM, |_| lines(&csv_path) >= 4);
    let err = &run.stderr;
    assert_eq!(run.code, Some(143), "{err}");
    assert!(
        err.contains("interrupted (SIGTERM)") && err.contains("kept"),
        "{err}"
    );
    assert!(whole_rows_marked_incomplete(&csv_path) >= 3, "rows kept");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("gel-cycles.json")).unwrap())
            .unwrap();
    assert_eq!(json["complete"], false, "{json}");
    assert!(json["stop"].as_str().unwrap().contains("signal"), "{json}");
    let again = Command::new(env!("CARGO_BIN_EXE_stickslip"))
        .args(["cycles", "--scene", "gel", "--out", out, "--max-steps", "3"])
        .output()
        .unwrap();
    let note = String::from_utf8_lossy(&again.stderr);
    assert!(
        note.contains("replacing the files of an earlier run"),
        "{note}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// An adhesive scene's `simulate` sent SIGINT part-way: exit 130, the time
/// series up to the signal kept whole and marked incomplete, with figures.
#[test]
fn ctrl_c_keeps_the_adhesive_time_series() {
    let dir = out_dir("interrupt-adhesive-simulate");
    let out = dir.to_str().unwrap();
    // Stick-slip of the gel for 20 000 s: many seconds of computing.
    let args = [
        "simulate",
        "--scene",
        "gel",
        "--protocol",
        "20:20000",
        "--out",
        out,
    ];
    let started = Instant::now();
    let run = interrupt_when(&args, |_| started.elapsed() > Duration::from_millis(500));
    let err = &run.stderr;
    assert_eq!(run.code, Some(130), "{err}");
    assert!(err.contains("interrupted (Ctrl-C)"), "{err}");
    let csv_path = dir.join("gel-simulation.csv");
    assert!(whole_rows_marked_incomplete(&csv_path) >= 10, "rows kept");
    assert!(dir.join("gel-simulation-spring-force.png").exists());
    let _ = std::fs::remove_dir_all(&dir);
}
