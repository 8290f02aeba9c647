//! `blockworld bench export-dataset DATASET`: images/s of the wireframe export in each format
//! (docs/wireframe.md "Wireframe datasets"), each into a fresh temporary folder that is removed afterwards.

use super::machine::banner;
use crate::cli::commands::export_dataset::{export, Args as ExportArgs, FormatArg, DEFAULT_JOBS};
use std::path::PathBuf;

/// Options of `blockworld bench export-dataset`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// A dataset made by `blockworld generate`.
    pub dataset: PathBuf,
}

/// Runs every format (grayscale, and HAWP also with `--rgb`) and prints a table.
pub fn run(args: Args) -> anyhow::Result<()> {
    print!("{}", banner(None));
    println!(
        "build: {}",
        if cfg!(debug_assertions) {
            "debug (dependencies at opt-level 3)"
        } else {
            "release"
        }
    );
    println!("| format | pictures | images | lines | s | images/s |");
    println!("|---|---|---|---|---|---|");
    let runs = [
        (FormatArg::Hawp, true),
        (FormatArg::Hawp, false),
        (FormatArg::Lcnn, false),
        (FormatArg::Letr, false),
    ];
    for (format, rgb) in runs {
        let dir = std::env::temp_dir().join(format!(
            "blockworld-bench-export-{}-{format:?}-{rgb}",
            std::process::id()
        ));
        let result = export(&ExportArgs {
            dataset: args.dataset.clone(),
            format,
            output: dir.clone(),
            split: 0.9,
            split_seed: 0,
            rgb,
            jobs: DEFAULT_JOBS,
        });
        let _ = std::fs::remove_dir_all(&dir);
        let s = result?;
        println!(
            "| {} | {} | {} | {} | {:.2} | {:.1} |",
            format.format().map_or_else(|v| v.name(), |w| w.name()),
            if rgb { "rgb" } else { "gray" },
            s.summary.new_images,
            s.summary.lines,
            s.wall_s,
            s.summary.new_images as f64 / s.wall_s.max(1e-9)
        );
    }
    Ok(())
}
