//! `blockworld generate` (not yet implemented).

/// Options of `blockworld generate`.
#[derive(Debug, clap::Args)]
pub struct Args {}

/// Runs `blockworld generate`.
pub fn run(_args: Args) -> anyhow::Result<()> {
    anyhow::bail!("`blockworld generate` is not implemented yet")
}
