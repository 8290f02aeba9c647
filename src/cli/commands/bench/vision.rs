//! `blockworld bench vision` (not yet implemented).

/// Options of `blockworld bench vision`.
#[derive(Debug, clap::Args)]
pub struct Args {}

/// Runs `blockworld bench vision`.
pub fn run(_args: Args) -> anyhow::Result<()> {
    anyhow::bail!("`blockworld bench vision` is not implemented yet")
}
