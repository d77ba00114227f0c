use clap::Parser;
use std::process::ExitCode;
use stickslip::cli::{run, Cli};

fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("stickslip: {e}");
            ExitCode::from(e.exit_code() as u8)
        }
    }
}
