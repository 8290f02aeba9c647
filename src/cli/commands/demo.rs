//! `blockworld demo` (not yet implemented).

/// Options of `blockworld demo`.
#[derive(Debug, clap::Args)]
pub struct Args {}

/// Runs `blockworld demo`.
pub fn run(_args: Args) -> anyhow::Result<()> {
    anyhow::bail!("`blockworld demo` is not implemented yet")
}
