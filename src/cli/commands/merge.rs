//! `blockworld merge DATASET`: joins `manifest.shard-I-of-N.jsonl` into `manifest.jsonl`,
//! checking that no shard or scene is missing or doubled and that every file has its hash.

use crate::cli::progress::with_progress;
use anyhow::Context;
use blockworld::dataset::merge_shards_with_progress;
use std::path::PathBuf;

/// Options of `blockworld merge`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The dataset directory the shards wrote into.
    pub dataset: PathBuf,
}

/// Runs `blockworld merge`.
pub fn run(args: Args) -> anyhow::Result<()> {
    let count = scene_count(&args.dataset);
    let s = with_progress("merge", "scenes checked", count, |p| {
        merge_shards_with_progress(&args.dataset, p)
    })
    .with_context(|| format!("merging {}", args.dataset.display()))?;
    outln!(
        "merged {} shards, {} scenes, every file's sha256 checked: {}",
        s.shards,
        s.scenes,
        s.manifest.display()
    )?;
    Ok(())
}

/// The count `dataset.json` claims, for the progress bar only (0 when unreadable: the merge
/// itself reports why).
fn scene_count(dataset: &std::path::Path) -> u64 {
    std::fs::read_to_string(dataset.join(blockworld::dataset::DATASET_FILE))
        .ok()
        .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
        .and_then(|v| v["count"].as_u64())
        .unwrap_or(0)
}
