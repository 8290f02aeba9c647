//! `blockworld export-dataset DATASET --format hawp|lcnn|letr -o OUT [--split 0.9]
//! [--split-seed S] [--rgb] [--jobs N]` (docs/wireframe.md "Wireframe datasets"): a generated
//! dataset's exact line drawings as training sets for learned wireframe parsers. The work is
//! `dataset::export_wireframes`; this command parses the flags, shows progress and prints the
//! summary. `--format coco|hf|bop` exports the views for vision tools (docs/exports.md) through
//! `dataset::export_vision`.

use crate::cli::progress::with_progress;
use anyhow::{bail, Context};
use blockworld::dataset::{
    export_vision, export_wireframes, VisionFormat, WireframeExportOptions, WireframeExportSummary,
};
use blockworld::export::wireframe::WireframeFormat;
use std::path::PathBuf;
use std::time::Instant;

/// The formats on the command line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum FormatArg {
    /// HAWP: images/, train.json, test.json.
    Hawp,
    /// L-CNN: images/, train.json, valid.json.
    Lcnn,
    /// LETR (COCO style): train2017/, val2017/, annotations/lines_{train2017,val2017}.json.
    Letr,
    /// COCO instances (block masks, boxes, categories): images/, annotations/instances.json.
    Coco,
    /// Hugging Face image folder: train/ with the pictures and metadata.jsonl.
    Hf,
    /// BOP (6D object pose benchmark): models/, train_pbr/<scene>/, camera.json; needs a
    /// dataset made with `generate --projection perspective`.
    Bop,
}

impl FormatArg {
    /// The library's wireframe format, or the vision-tool format (docs/exports.md).
    pub fn format(self) -> Result<WireframeFormat, VisionFormat> {
        match self {
            FormatArg::Hawp => Ok(WireframeFormat::Hawp),
            FormatArg::Lcnn => Ok(WireframeFormat::Lcnn),
            FormatArg::Letr => Ok(WireframeFormat::Letr),
            FormatArg::Coco => Err(VisionFormat::Coco),
            FormatArg::Hf => Err(VisionFormat::HuggingFace),
            FormatArg::Bop => Err(VisionFormat::Bop),
        }
    }
}

/// Options of `blockworld export-dataset`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// A dataset made by `blockworld generate` (with its manifest.jsonl).
    pub dataset: PathBuf,
    /// Output format.
    #[arg(long, value_enum)]
    pub format: FormatArg,
    /// Output directory (created; re-running the same command resumes).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Fraction of scenes in the training set (by a seeded hash of the scene id).
    #[arg(long, default_value_t = 0.9)]
    pub split: f64,
    /// Seed of the split hash.
    #[arg(long, default_value_t = 0)]
    pub split_seed: u64,
    /// Write three-channel (RGB) PNGs; 8-bit grayscale otherwise. The current HAWP, L-CNN and
    /// LETR loaders take gray; HAWP v1 (its `parsing/` tree) needs RGB.
    #[arg(long)]
    pub rgb: bool,
    /// Scenes exported at once. Pictures and part files are written to a temporary name and
    /// renamed without a sync each (a resumed run re-checks them by sha256); the annotation
    /// files assembled at the end are synced. The output's bytes do not depend on it.
    #[arg(long, default_value_t = DEFAULT_JOBS)]
    pub jobs: usize,
}

/// Default `--jobs`.
pub const DEFAULT_JOBS: usize = 4;

/// What an export did, and its wall time.
#[derive(Debug, Clone)]
pub struct ExportSummary {
    /// The library's summary.
    pub summary: WireframeExportSummary,
    /// Wall time of this run, s.
    pub wall_s: f64,
}

/// Runs `blockworld export-dataset`.
pub fn run(args: Args) -> anyhow::Result<()> {
    if let Err(format) = args.format.format() {
        return run_vision(&args, format);
    }
    let ExportSummary { summary: s, wall_s } = export(&args)?;
    for note in &s.left_out_notes {
        eprintln!("export-dataset: {note}");
    }
    println!(
        "{} scenes ({} kept from an earlier run): {} images, {} lines, {} pictures left out (the loader cannot take them); {} images exported in {:.2} s ({:.1} images/s) -> {}",
        s.scenes,
        s.resumed,
        s.images,
        s.lines,
        s.left_out,
        s.new_images,
        wall_s,
        s.new_images as f64 / wall_s.max(1e-9),
        args.output.display()
    );
    Ok(())
}

/// Exports the dataset in a vision-tool format (`dataset::export_vision`, docs/exports.md) with
/// progress on stderr, and says what it did.
fn run_vision(args: &Args, format: VisionFormat) -> anyhow::Result<()> {
    let started = Instant::now();
    let s = with_progress("export-dataset", "scenes", 0, |progress| {
        export_vision(&args.dataset, &args.output, format, args.jobs, progress)
    })
    .with_context(|| format!("exporting {}", args.dataset.display()))?;
    let a = s.agreement;
    println!(
        "{} scenes ({} kept from an earlier run): {} images, {} annotations; full masks against the id pictures: {} visible px outside, {} px on the background, of {} px; {:.2} s -> {}",
        s.scenes,
        s.resumed,
        s.images,
        s.annotations,
        a.visible_outside_px,
        a.silhouette_on_background_px,
        a.silhouette_px,
        started.elapsed().as_secs_f64(),
        args.output.display()
    );
    Ok(())
}

/// Exports the dataset (`dataset::export_wireframes`) with progress on stderr.
pub fn export(args: &Args) -> anyhow::Result<ExportSummary> {
    let format = match args.format.format() {
        Ok(f) => f,
        Err(v) => bail!(
            "--format {} is not a wireframe format; run `blockworld export-dataset` for it",
            v.name()
        ),
    };
    let opts = WireframeExportOptions {
        format,
        split: args.split,
        split_seed: args.split_seed,
        rgb: args.rgb,
        jobs: args.jobs,
    };
    let started = Instant::now();
    let summary = with_progress("export-dataset", "scenes", 0, |progress| {
        export_wireframes(&args.dataset, &args.output, &opts, progress)
    })
    .with_context(|| format!("exporting {}", args.dataset.display()))?;
    Ok(ExportSummary {
        summary,
        wall_s: started.elapsed().as_secs_f64(),
    })
}
