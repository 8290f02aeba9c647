//! The `blockworld` binary: parse, run, print the error chain once, exit non-zero on error.

use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    let cli = blockworld::cli::Cli::parse();
    match blockworld::cli::run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            eprintln!("error: {err}");
            for cause in err.chain().skip(1) {
                eprintln!("  caused by: {cause}");
            }
            ExitCode::from(2)
        }
    }
}
