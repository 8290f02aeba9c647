//! `blockworld settle` (not yet implemented).

/// Options of `blockworld settle`.
#[derive(Debug, clap::Args)]
pub struct Args {}

/// Runs `blockworld settle`.
pub fn run(_args: Args) -> anyhow::Result<()> {
    anyhow::bail!("`blockworld settle` is not implemented yet")
}
