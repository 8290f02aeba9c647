//! `blockworld merge DATASET`: joins `manifest.shard-I-of-N.jsonl` into `manifest.jsonl`,
//! checking that no shard or scene is missing or doubled and that every file has its hash.

use anyhow::Context;
use blockworld::dataset::merge_shards;
use std::path::PathBuf;

/// Options of `blockworld merge`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The dataset directory the shards wrote into.
    pub dataset: PathBuf,
}

/// Runs `blockworld merge`.
pub fn run(args: Args) -> anyhow::Result<()> {
    let s = merge_shards(&args.dataset)
        .with_context(|| format!("merging {}", args.dataset.display()))?;
    outln!(
        "merged {} shards, {} scenes, every file's sha256 checked: {}",
        s.shards,
        s.scenes,
        s.manifest.display()
    )?;
    Ok(())
}
