//! `blockworld merge` (not yet implemented).

/// Options of `blockworld merge`.
#[derive(Debug, clap::Args)]
pub struct Args {}

/// Runs `blockworld merge`.
pub fn run(_args: Args) -> anyhow::Result<()> {
    anyhow::bail!("`blockworld merge` is not implemented yet")
}
