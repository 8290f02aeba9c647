//! `blockworld report DATASET [--recognitions DIR] -o SITE`: a static web site of a dataset and
//! of the recognizer's answers on it (docs/report.md). The pages are made by
//! `blockworld::report` from plain data; this command reads the dataset and the recognitions
//! folder (`recognize-dataset` writes it), copies each scene's pictures, makes the depth and id
//! pictures visible, and writes the site whole or not at all.

use super::recognize_dataset::{read_dataset_manifest, RECOGNITIONS_FILE};
use crate::cli::files::{read_drawing, StagedFolder};
use anyhow::{bail, Context};
use blockworld::dataset::{views_of, ManifestEntry};
use blockworld::report::{
    depth_picture, ids_picture, index_files, scene_page, Outcome, ReportScene, ReportView, RunInfo,
    SceneSummary, SeenView,
};
use blockworld::scene::{read_reconstruction, Reconstruction};
use blockworld::score::SceneResult;
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Options of `blockworld report`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The dataset folder (`generate` or `merge` wrote its manifest.jsonl).
    pub dataset: PathBuf,
    /// The recognizer's answers on the dataset: the folder `blockworld recognize-dataset`
    /// wrote. Without it the site shows the dataset and its ground truth only.
    #[arg(long, value_name = "DIR")]
    pub recognitions: Option<PathBuf>,
    /// The site's folder (new, empty, or an earlier report); open SITE/index.html.
    #[arg(short, long, value_name = "SITE")]
    pub output: PathBuf,
}

/// The file that marks a report's folder.
const SITE_MARKER: &str = "scenes.js";

/// The recognitions folder read: its run and the results by scene id.
struct Recognitions {
    dir: PathBuf,
    views: Vec<String>,
    results: BTreeMap<String, SceneResult>,
}

fn read_recognitions(dir: &Path) -> anyhow::Result<Recognitions> {
    let path = dir.join(RECOGNITIONS_FILE);
    let fix = "give the folder `blockworld recognize-dataset DATASET -o DIR` wrote";
    let text = std::fs::read_to_string(&path)
        .with_context(|| format!("{}: cannot read it; {fix}", path.display()))?;
    #[derive(serde::Deserialize)]
    struct Run {
        views: Vec<String>,
        scenes: Vec<SceneResult>,
    }
    let run: Run = serde_json::from_str(&text)
        .with_context(|| format!("{}: not a recognitions file; {fix}", path.display()))?;
    Ok(Recognitions {
        dir: dir.to_path_buf(),
        views: run.views,
        results: run.scenes.into_iter().map(|r| (r.id.clone(), r)).collect(),
    })
}

/// The answer and per-view drawings of scene `id`, when the recognitions hold it.
fn read_answer(
    rec: &Recognitions,
    id: &str,
) -> anyhow::Result<Option<(SceneResult, Reconstruction, Vec<SeenView>)>> {
    let Some(result) = rec.results.get(id) else {
        return Ok(None);
    };
    let recon_path = rec.dir.join(format!("{id}.json"));
    let recon = read_reconstruction(&recon_path)
        .with_context(|| format!("reading {}; re-run recognize-dataset", recon_path.display()))?;
    let views_path = rec.dir.join(format!("{id}.views.json"));
    let text = std::fs::read_to_string(&views_path)
        .with_context(|| format!("reading {}; re-run recognize-dataset", views_path.display()))?;
    let seen: Vec<SeenView> = serde_json::from_str(&text).with_context(|| {
        format!(
            "{}: not a views file; re-run recognize-dataset",
            views_path.display()
        )
    })?;
    Ok(Some((result.clone(), recon, seen)))
}

/// Copies the view's picture and writes its depth and id pictures made visible; returns the
/// picture's size.
fn write_view_pictures(
    out: &StagedFolder,
    dir: &Path,
    id: &str,
    v: &str,
) -> anyhow::Result<[u32; 2]> {
    let picture = dir.join(format!("view_{v}.png"));
    let bytes =
        std::fs::read(&picture).with_context(|| format!("reading {}", picture.display()))?;
    out.write(&format!("{id}/view_{v}.png"), &bytes)?;
    let depth_path = dir.join(format!("depth_{v}.png"));
    let (w, h, depth) = crate::cli::files::read_gray16(&depth_path)?;
    let depth = depth_picture(w, h, &depth).context("depth picture")?;
    out.write(
        &format!("{id}/depth_{v}.png"),
        &blockworld::output::encode_png_flat(&depth.into())?,
    )?;
    let ids_path = dir.join(format!("ids_{v}.png"));
    let (iw, ih, ids) = crate::cli::files::read_gray16(&ids_path)?;
    let ids = ids_picture(iw, ih, &ids)
        .filter(|_| [iw, ih] == [w, h])
        .with_context(|| {
            format!(
                "{}: not the size of {}; re-generate the scene",
                ids_path.display(),
                depth_path.display()
            )
        })?;
    out.write(
        &format!("{id}/ids_{v}.png"),
        &blockworld::output::encode_png_flat(&ids.into())?,
    )?;
    Ok([w, h])
}

/// Copies the scene's own files the page links (`scene.json`, `scene.glb`) and writes the
/// reconstruction; returns their names.
fn write_scene_files(
    out: &StagedFolder,
    dir: &Path,
    id: &str,
    recon: Option<&Reconstruction>,
) -> anyhow::Result<Vec<String>> {
    let mut files = Vec::new();
    for name in ["scene.json", "scene.glb"] {
        let path = dir.join(name);
        if path.is_file() {
            let bytes =
                std::fs::read(&path).with_context(|| format!("reading {}", path.display()))?;
            out.write(&format!("{id}/{name}"), &bytes)?;
            files.push(name.to_string());
        }
    }
    if let Some(r) = recon {
        let text = blockworld::scene::reconstruction_to_json(r);
        out.write(&format!("{id}/recon.json"), text.as_bytes())?;
        files.push("recon.json".into());
    }
    Ok(files)
}

/// Builds scene `k`'s folder in the site and returns its line of the index.
fn build_scene(
    out: &StagedFolder,
    dataset: &Path,
    entries: &[ManifestEntry],
    k: usize,
    rec: Option<&Recognitions>,
) -> anyhow::Result<SceneSummary> {
    let entry = &entries[k];
    let dir = dataset.join(&entry.id);
    let answer = match rec {
        Some(r) => read_answer(r, &entry.id)?,
        None => None,
    };
    let view_names = views_of(entry);
    let mut views = Vec::new();
    for v in &view_names {
        let size_px = write_view_pictures(out, &dir, &entry.id, v)?;
        let truth = read_drawing(&dir.join(format!("lines_{v}.json")))?;
        let seen = answer
            .as_ref()
            .and_then(|(_, _, seen)| seen.iter().find(|s| &s.view == v).cloned());
        views.push(ReportView {
            name: v.clone(),
            size_px,
            truth,
            seen,
        });
    }
    let files = write_scene_files(out, &dir, &entry.id, answer.as_ref().map(|a| &a.1))?;
    let outcome = answer
        .as_ref()
        .map_or(Outcome::NotRecognized, |(r, recon, _)| {
            Outcome::of(r, Some(recon))
        });
    let summary = SceneSummary {
        id: entry.id.clone(),
        family: entry.family.clone(),
        blocks: entry.blocks,
        supported: entry.supported,
        thumbnail_view: view_names.first().cloned().unwrap_or_else(|| "ne".into()),
        thumbnail_px: views.first().map_or([0, 0], |v| v.size_px),
        outcome,
        result: answer.as_ref().map(|a| a.0.clone()),
    };
    let neighbour = |i: Option<usize>| i.and_then(|i| entries.get(i)).map(|e| e.id.clone());
    let scene = ReportScene {
        summary,
        expected_reason: entry.reason.clone(),
        views,
        recon: answer.map(|a| a.1),
        files,
        neighbours: [neighbour(k.checked_sub(1)), neighbour(Some(k + 1))],
    };
    out.write(
        &format!("{}/index.html", entry.id),
        scene_page(&scene).as_bytes(),
    )?;
    Ok(scene.summary)
}

/// Runs `blockworld report`.
pub fn run(args: Args) -> anyhow::Result<()> {
    let started = std::time::Instant::now();
    let entries = read_dataset_manifest(&args.dataset)?;
    let rec = args
        .recognitions
        .as_deref()
        .map(read_recognitions)
        .transpose()?;
    if let Some(r) = &rec {
        if !entries.iter().any(|e| r.results.contains_key(&e.id)) {
            bail!(
                "{}: recognizes none of the scenes of {}; give the folder `blockworld recognize-dataset {} -o DIR` wrote",
                r.dir.join(RECOGNITIONS_FILE).display(),
                args.dataset.display(),
                args.dataset.display()
            );
        }
    }
    let out = StagedFolder::new(&args.output, SITE_MARKER, "report")?;
    let total = entries.len() as u64;
    let done = std::sync::atomic::AtomicU64::new(0);
    let summaries = crate::cli::progress::with_progress("report", "scenes", total, |p| {
        (0..entries.len())
            .into_par_iter()
            .map(|k| {
                let s = build_scene(&out, &args.dataset, &entries, k, rec.as_ref())?;
                p(
                    done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1,
                    total,
                );
                Ok(s)
            })
            .collect::<anyhow::Result<Vec<SceneSummary>>>()
    })?;
    let run = RunInfo {
        dataset: args.dataset.display().to_string(),
        recognitions: rec.as_ref().map(|r| r.dir.display().to_string()),
        views: rec.as_ref().map_or(Vec::new(), |r| r.views.clone()),
    };
    for f in index_files(&run, &summaries) {
        out.write(&f.path, &f.bytes)?;
    }
    out.publish()?;
    outln!(
        "{} scenes ({} recognized) in {:.2} s -> {}",
        summaries.len(),
        summaries.iter().filter(|s| s.result.is_some()).count(),
        started.elapsed().as_secs_f64(),
        args.output.join("index.html").display()
    )?;
    Ok(())
}
