//! Ctrl-C and progress for long computations: an interrupt stops the work at
//! the next point, keeps everything already written, and says where it
//! stopped; a progress bar shows on a terminal only.

use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Once;

static INTERRUPTED: AtomicBool = AtomicBool::new(false);
static INSTALL: Once = Once::new();

/// Installs the Ctrl-C handler (once); afterwards Ctrl-C sets a flag instead
/// of killing the process.
pub fn catch_interrupts() {
    INSTALL.call_once(|| {
        // If another handler is already installed, Ctrl-C keeps its default
        // effect; the files written so far are complete either way.
        let _ = ctrlc::set_handler(|| INTERRUPTED.store(true, Ordering::SeqCst));
    });
}

/// Whether Ctrl-C was pressed.
pub fn interrupted() -> bool {
    INTERRUPTED.load(Ordering::SeqCst)
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
