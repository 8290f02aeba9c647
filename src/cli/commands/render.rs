//! `blockworld render` (not yet implemented).

/// Options of `blockworld render`.
#[derive(Debug, clap::Args)]
pub struct Args {}

/// Runs `blockworld render`.
pub fn run(_args: Args) -> anyhow::Result<()> {
    anyhow::bail!("`blockworld render` is not implemented yet")
}
