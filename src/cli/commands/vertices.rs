//! `blockworld vertices` (not yet implemented).

/// Options of `blockworld vertices`.
#[derive(Debug, clap::Args)]
pub struct Args {}

/// Runs `blockworld vertices`.
pub fn run(_args: Args) -> anyhow::Result<()> {
    anyhow::bail!("`blockworld vertices` is not implemented yet")
}
