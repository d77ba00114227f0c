//! Ctrl-C, SIGTERM and progress for long computations: either signal stops
//! the work at the next point, keeps everything already written, and says
//! where it stopped; the exit status tells which signal came (130 after
//! SIGINT, 143 after SIGTERM, as a shell reports a process killed by it).
//! A progress bar shows on a terminal only.

pub use crate::error::{Interruption, StopSignal};
use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::sync::atomic::{AtomicU8, Ordering};
use std::sync::Once;

/// The signal received first: 0 none, else a [`StopSignal`] code.
static RECEIVED: AtomicU8 = AtomicU8::new(NONE);
static INSTALL: Once = Once::new();

const NONE: u8 = 0;
const INTERRUPT: u8 = 1;
const TERMINATE: u8 = 2;

/// Records the first stop signal (async-signal-safe: one atomic operation).
fn record(code: u8) {
    let _ = RECEIVED.compare_exchange(NONE, code, Ordering::SeqCst, Ordering::SeqCst);
}

/// Installs the handlers of SIGINT and SIGTERM (once); afterwards either
/// signal sets a flag instead of killing the process. A signal that was
/// ignored when the program started (`nohup`, a background job) stays
/// ignored, and one with a handler already installed keeps it.
pub fn catch_interrupts() {
    INSTALL.call_once(install);
}

#[cfg(unix)]
fn install() {
    extern "C" fn handler(signal: libc::c_int) {
        record(if signal == libc::SIGTERM {
            TERMINATE
        } else {
            INTERRUPT
        });
    }
    for signal in [libc::SIGINT, libc::SIGTERM] {
        // SAFETY: `sigaction` on zero-initialised (valid) structs; the
        // handler only performs an atomic compare-and-swap, which is
        // async-signal-safe. A failure leaves the default disposition.
        unsafe {
            let mut old: libc::sigaction = std::mem::zeroed();
            if libc::sigaction(signal, std::ptr::null(), &mut old) != 0
                || old.sa_sigaction != libc::SIG_DFL
            {
                continue;
            }
            let mut action: libc::sigaction = std::mem::zeroed();
            action.sa_sigaction = handler as extern "C" fn(libc::c_int) as libc::sighandler_t;
            action.sa_flags = libc::SA_RESTART;
            libc::sigemptyset(&mut action.sa_mask);
            libc::sigaction(signal, &action, std::ptr::null_mut());
        }
    }
}

#[cfg(not(unix))]
fn install() {
    // If another handler is already installed, Ctrl-C keeps its default
    // effect; the files written so far are complete either way.
    let _ = ctrlc::set_handler(|| record(INTERRUPT));
}

/// Whether a stop signal (SIGINT or SIGTERM) came.
pub fn interrupted() -> bool {
    stop_signal().is_some()
}

/// The first stop signal that came, if any.
pub fn stop_signal() -> Option<StopSignal> {
    match RECEIVED.load(Ordering::SeqCst) {
        INTERRUPT => Some(StopSignal::Interrupt),
        TERMINATE => Some(StopSignal::Terminate),
        _ => None,
    }
}

/// The error of a run stopped by a signal, `at` saying where it stopped
/// (SIGINT when no signal was recorded).
pub fn stopped(at: String) -> crate::error::Error {
    crate::error::Error::Interrupted(Interruption {
        signal: stop_signal().unwrap_or(StopSignal::Interrupt),
        at,
    })
}

/// A spinner with a message on standard error when it is a terminal; hidden otherwise.
pub fn progress(what: &str) -> ProgressBar {
    on_terminal(
        ProgressBar::new_spinner(),
        "{spinner} {elapsed} {msg}",
        what,
    )
}

/// A bar filling up to `len` with a message and the time left on standard
/// error when it is a terminal; hidden otherwise.
pub fn progress_bar(len: u64, what: &str) -> ProgressBar {
    let template = "{spinner} {bar:30} {percent:>3}% {msg}  {elapsed} (eta {eta})";
    on_terminal(ProgressBar::new(len), template, what)
}

fn on_terminal(bar: ProgressBar, template: &str, what: &str) -> ProgressBar {
    if !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    if let Ok(style) = ProgressStyle::with_template(template) {
        bar.set_style(style);
    }
    bar.set_message(what.to_string());
    bar.enable_steady_tick(std::time::Duration::from_millis(120));
    bar
}
