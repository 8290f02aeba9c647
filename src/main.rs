//! The `blockworld` binary: everything happens in `blockworld::cli` (parse, run, print the error
//! chain once, exit non-zero on error).

fn main() -> std::process::ExitCode {
    blockworld::cli::main()
}
