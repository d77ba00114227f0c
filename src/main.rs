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
    // A file grown beyond the size limit (`ulimit -f`) makes the write fail
    // (EFBIG), named in the message with exit status 1 and the file left
    // complete or marked incomplete, instead of killing the process by
    // SIGXFSZ with a half-written file.
    #[cfg(unix)]
    // SAFETY: ignoring SIGXFSZ before any thread starts; no handler is installed.
    unsafe {
        libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
    }
    let cli = Cli::parse();
    // `println!` panics when standard output cannot be written (a full disk,
    // `> /dev/full`): that is an output error (status 1), not a crash.
    std::panic::set_hook(Box::new(|info| {
        let message = info
            .payload()
            .downcast_ref::<String>()
            .map(String::as_str)
            .or_else(|| info.payload().downcast_ref::<&str>().copied())
            .unwrap_or("");
        if message.starts_with("failed printing to stdout") {
            eprintln!("stickslip: cannot write output: standard output: {message}");
            std::process::exit(1);
        }
        eprintln!("stickslip: internal error (please report): {info}");
    }));
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("stickslip: {e}");
            ExitCode::from(e.exit_code() as u8)
        }
    }
}
