//! `blockworld recognize-dataset DATASET -o DIR [--views ne,se,sw,nw] [--from-truth]`: the
//! recognizer on every scene of a dataset, as `recognize` runs it on one folder (vision front
//! end on `view_<v>.png`, or the exact drawings with `--from-truth`), each answer scored
//! against the scene's truth. DIR is what `blockworld report --recognitions DIR` reads
//! (docs/report.md "Recognitions"):
//!
//! * `<id>.json`: the reconstruction file, as `recognize` writes it (and `bench accuracy
//!   --recognizer DIR` scores);
//! * `<id>.views.json`: per view the observed drawing, the answer's drawing in the view's
//!   camera and which lines of each the other does not explain (`report::SeenView`);
//! * `recognitions.json`: the run (dataset, views, source), the per-family table and every
//!   scene's result, as `bench accuracy` writes them.
//!
//! Scenes run in parallel; the bytes do not depend on the number of threads. The folder is
//! written whole or not at all.

use super::recognize::{recognize_folder, SourceArgs, WorldArgs};
use crate::cli::files::StagedFolder;
use anyhow::Context;
use blockworld::camera::CornerView;
use blockworld::csg::reconstruction;
use blockworld::dataset::{parse_manifest, ManifestEntry, MANIFEST_NAME};
use blockworld::recognize::steps::mismatched_features;
use blockworld::recognize::{draw_hypothesis, RecognizeOptions};
use blockworld::report::SeenView;
use blockworld::scene::{read_scene, reconstruction_to_json};
use blockworld::score::{score_suite_scene, summarize_by_family, SceneResult, ScoreOptions};
use rayon::prelude::*;
use std::path::{Path, PathBuf};

/// The file that marks a recognitions folder.
pub const RECOGNITIONS_FILE: &str = "recognitions.json";

/// Options of `blockworld recognize-dataset`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The dataset folder (`generate` or `merge` wrote its manifest.jsonl).
    pub dataset: PathBuf,
    /// The recognitions folder to write (new, empty, or an earlier output of this command).
    #[arg(short, long)]
    pub output: PathBuf,
    /// The views and where their drawings come from.
    #[command(flatten)]
    pub source: SourceArgs,
    /// What the recognizer is told of the world.
    #[command(flatten)]
    pub world: WorldArgs,
}

/// One scene's files and result.
struct Recognized {
    result: SceneResult,
    recon_json: String,
    views_json: String,
}

/// Reads `DATASET/manifest.jsonl`, naming the file and the fix when it is missing or damaged.
pub(super) fn read_dataset_manifest(dataset: &Path) -> anyhow::Result<Vec<ManifestEntry>> {
    let path = dataset.join(MANIFEST_NAME);
    let text = blockworld::dataset::read_manifest_text(&path).with_context(|| {
        format!(
            "{}: cannot read it; give a dataset folder that `blockworld generate` (or `merge`) finished",
            path.display()
        )
    })?;
    let entries = parse_manifest(&text, &path)?;
    if entries.is_empty() {
        anyhow::bail!("{}: no scenes; generate the dataset first", path.display());
    }
    Ok(entries)
}

/// Recognizes and scores one scene of the dataset.
fn recognize_scene(
    dataset: &Path,
    entry: &ManifestEntry,
    views: &[CornerView],
    from_truth: bool,
    opts: &RecognizeOptions,
) -> anyhow::Result<Recognized> {
    let dir = dataset.join(&entry.id);
    let truth_path = dir.join("scene.json");
    let truth =
        read_scene(&truth_path).with_context(|| format!("reading {}", truth_path.display()))?;
    let (observed, recognition) = recognize_folder(&dir, views, from_truth, false, opts)?;
    let recon = reconstruction(&entry.id, &recognition, 0.5);
    let result = score_suite_scene(&entry.id, &truth, Ok(&recon), &ScoreOptions::default());
    let seen: Vec<SeenView> = observed
        .iter()
        .map(|v| {
            let answer = draw_hypothesis(&recognition.evidence.hypothesis, &v.camera);
            let m = mismatched_features(&answer, &v.drawing, opts.tol_px);
            SeenView {
                view: v.camera.view.name().to_string(),
                observed: v.drawing.clone(),
                answer,
                unexplained_lines: m.unexplained_lines,
                extra_lines: m.extra_lines,
            }
        })
        .collect();
    Ok(Recognized {
        result,
        recon_json: reconstruction_to_json(&recon),
        views_json: serde_json::to_string(&seen)? + "\n",
    })
}

/// Runs `blockworld recognize-dataset`.
pub fn run(args: Args) -> anyhow::Result<()> {
    let views = crate::cli::view_args::parse_corner_views(&args.source.views)?;
    let opts = RecognizeOptions {
        grid_mm: args.world.grid_mm()?,
        ..RecognizeOptions::default()
    };
    let entries = read_dataset_manifest(&args.dataset)?;
    let out = StagedFolder::new(&args.output, RECOGNITIONS_FILE, "recognitions folder")?;
    let started = std::time::Instant::now();
    let done = std::sync::atomic::AtomicU64::new(0);
    let total = entries.len() as u64;
    let results = crate::cli::progress::with_progress("recognize-dataset", "scenes", total, |p| {
        entries
            .par_iter()
            .map(|e| {
                let r = recognize_scene(&args.dataset, e, &views, args.source.from_truth, &opts)?;
                out.write(&format!("{}.json", e.id), r.recon_json.as_bytes())?;
                out.write(&format!("{}.views.json", e.id), r.views_json.as_bytes())?;
                p(
                    done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1,
                    total,
                );
                Ok(r.result)
            })
            .collect::<anyhow::Result<Vec<SceneResult>>>()
    })?;
    let families = summarize_by_family(&results);
    let run = serde_json::json!({
        "dataset": args.dataset.display().to_string(),
        "views": views.iter().map(|v| v.name()).collect::<Vec<_>>(),
        "from_truth": args.source.from_truth,
        "grid_mm": opts.grid_mm,
        "families": families,
        "scenes": results,
    });
    out.write(
        RECOGNITIONS_FILE,
        blockworld::io::pretty_json(&run).as_bytes(),
    )?;
    out.publish()?;
    let exact = results
        .iter()
        .filter(|r| r.verdict.as_str() == "exact")
        .count();
    let declined = results
        .iter()
        .filter(|r| r.verdict.as_str() == "unsupported")
        .count();
    let wrong = results.iter().filter(|r| r.confidently_wrong).count();
    outln!(
        "{} scenes: {exact} exact, {declined} declined, {wrong} confidently wrong; {:.1} s -> {}",
        results.len(),
        started.elapsed().as_secs_f64(),
        args.output.display()
    )?;
    Ok(())
}
