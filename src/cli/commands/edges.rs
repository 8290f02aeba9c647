//! `blockworld edges` (not yet implemented).

/// Options of `blockworld edges`.
#[derive(Debug, clap::Args)]
pub struct Args {}

/// Runs `blockworld edges`.
pub fn run(_args: Args) -> anyhow::Result<()> {
    anyhow::bail!("`blockworld edges` is not implemented yet")
}
