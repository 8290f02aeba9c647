//! `blockworld bench generate` (not yet implemented).

/// Options of `blockworld bench generate`.
#[derive(Debug, clap::Args)]
pub struct Args {}

/// Runs `blockworld bench generate`.
pub fn run(_args: Args) -> anyhow::Result<()> {
    anyhow::bail!("`blockworld bench generate` is not implemented yet")
}
