//! `blockworld recognize DIR -o RECON.json [--views ne,se,sw,nw] [--from-truth]`: the modified
//! Kanade recognizer (thesis Chapters IV-V) on a directory as `render` writes it, per view
//! `view_<v>.png` + `camera_<v>.json` (or the exact `lines_<v>.json` with `--from-truth`).
//! Writes a reconstruction file: the scene-file blocks plus `status`, `reason` and the CSG tree
//! (Figure 4.6).

use super::vertices::{read_camera, read_picture};
use crate::csg::build_csg;
use crate::drawing::LineDrawing;
use crate::recognize::{recognize, ObservedView, RecognizeOptions};
use crate::render::CornerView;
use crate::scene::scene_to_json;
use crate::vision::{detect_line_drawing, VisionOptions};
use anyhow::Context;
use std::path::{Path, PathBuf};

/// Options of `blockworld recognize`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Directory with `camera_<v>.json` and `view_<v>.png` (or `lines_<v>.json`) per view.
    pub dir: PathBuf,
    /// The reconstruction file to write.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Comma-separated corner views to use (any subset, e.g. `ne,sw`).
    #[arg(long, value_delimiter = ',', default_value = "ne,se,sw,nw")]
    pub views: Vec<String>,
    /// Read the exact line drawings `lines_<v>.json` instead of running the vision front end
    /// on `view_<v>.png`.
    #[arg(long)]
    pub from_truth: bool,
}

/// Reads one `lines_<view>.json`.
fn read_drawing(path: &Path) -> anyhow::Result<LineDrawing> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
    serde_json::from_str(&text).with_context(|| {
        format!(
            "{}: not a line drawing (write one with `blockworld render`)",
            path.display()
        )
    })
}

/// Reads one view of `dir`: its camera and its drawing (exact, or from the picture).
fn read_view(dir: &Path, view: CornerView, from_truth: bool) -> anyhow::Result<ObservedView> {
    let v = view.name();
    let camera_path = dir.join(format!("camera_{v}.json"));
    let camera = read_camera(&camera_path)?;
    if camera.view != view {
        anyhow::bail!(
            "{}: holds the {} view, not {v}; re-render the directory",
            camera_path.display(),
            camera.view.name()
        );
    }
    let drawing = if from_truth {
        read_drawing(&dir.join(format!("lines_{v}.json")))?
    } else {
        let picture = dir.join(format!("view_{v}.png"));
        let gray = read_picture(&picture)?;
        detect_line_drawing(&gray, &camera, &VisionOptions::default())
            .with_context(|| format!("{} (camera {})", picture.display(), camera_path.display()))?
            .drawing
    };
    Ok(ObservedView { drawing, camera })
}

/// Runs `blockworld recognize`.
pub fn run(args: Args) -> anyhow::Result<()> {
    let views = args
        .views
        .iter()
        .map(|v| {
            CornerView::parse(v)
                .with_context(|| format!("--views: unknown view {v:?}; use ne, se, sw, nw"))
        })
        .collect::<anyhow::Result<Vec<_>>>()?;
    let observed = views
        .iter()
        .map(|&v| read_view(&args.dir, v, args.from_truth))
        .collect::<anyhow::Result<Vec<_>>>()?;
    let recognition = recognize(&observed, &RecognizeOptions::default())
        .with_context(|| format!("recognizing {}", args.dir.display()))?;
    let name = args
        .dir
        .file_name()
        .map_or("recognized".into(), |n| n.to_string_lossy().into_owned());
    let mut scene = recognition.to_scene(&name);
    scene.csg = Some(build_csg(&recognition.blocks, 0.5).to_json());
    crate::io::write_atomic(&args.output, scene_to_json(&scene).as_bytes())
        .with_context(|| format!("writing {}", args.output.display()))?;
    eprintln!(
        "{}: {} blocks in {} layers -> {}{}",
        args.dir.display(),
        recognition.blocks.len(),
        recognition.layers.len(),
        args.output.display(),
        recognition
            .reason
            .as_deref()
            .map_or(String::new(), |r| format!(" (unsupported: {r})"))
    );
    Ok(())
}
