use clap::Parser;
use std::process::ExitCode;
use stickslip::cli::{run, Cli};

fn main() -> ExitCode {
    // Die quietly like other Unix tools when the reader of our output goes
    // away (`stickslip ... | head`), instead of panicking on a broken pipe.
    #[cfg(unix)]
    // SAFETY: restoring the default disposition of SIGPIPE before any thread
    // starts; no handler is installed.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    let cli = Cli::parse();
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("stickslip: {e}");
            ExitCode::from(e.exit_code() as u8)
        }
    }
}
