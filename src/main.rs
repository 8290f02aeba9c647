//! The `blockworld` binary: the command line (`cli`: clap arguments, anyhow context, progress
//! bars) over the library's stages. It parses, runs one subcommand, prints the error chain once
//! and exits 2 on error (docs/cli.md "Exit codes and progress output").

mod cli;

fn main() -> std::process::ExitCode {
    cli::main()
}
