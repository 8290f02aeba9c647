//! `blockworld bench render` (not yet implemented).

/// Options of `blockworld bench render`.
#[derive(Debug, clap::Args)]
pub struct Args {}

/// Runs `blockworld bench render`.
pub fn run(_args: Args) -> anyhow::Result<()> {
    anyhow::bail!("`blockworld bench render` is not implemented yet")
}
