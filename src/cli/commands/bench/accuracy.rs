//! `blockworld bench accuracy` (not yet implemented).

/// Options of `blockworld bench accuracy`.
#[derive(Debug, clap::Args)]
pub struct Args {}

/// Runs `blockworld bench accuracy`.
pub fn run(_args: Args) -> anyhow::Result<()> {
    anyhow::bail!("`blockworld bench accuracy` is not implemented yet")
}
