//! `blockworld score` (not yet implemented).

/// Options of `blockworld score`.
#[derive(Debug, clap::Args)]
pub struct Args {}

/// Runs `blockworld score`.
pub fn run(_args: Args) -> anyhow::Result<()> {
    anyhow::bail!("`blockworld score` is not implemented yet")
}
