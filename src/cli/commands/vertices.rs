//! `blockworld vertices VIEW.png --camera camera.json [-o OUT.json]`: lines, vertices, six-bit
//! codes and junction classes of a view (thesis Ch. IV-VI), written as a line drawing in the
//! `lines_<view>.json` format (px, x right, y up, origin at the bottom-left corner): the one
//! `vertices_<view>.json` format, which `demo` writes too and `recognize` and `label` read.

use crate::cli::files::{read_camera, read_picture};
use crate::cli::progress::with_progress;
use anyhow::Context;
use blockworld::vision::{
    detect_line_drawing_with_progress, EdgeOptions, FaintEdgeOptions, GapOptions, OrientedOptions,
    VisionOptions, VISION_STEPS,
};
use std::path::PathBuf;

/// Options of `blockworld vertices`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The grayscale view (PNG), e.g. `view_ne.png`.
    pub view: PathBuf,
    /// Its camera (`camera_<view>.json`, written with the view).
    #[arg(long)]
    pub camera: PathBuf,
    /// Write the JSON here instead of printing it.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Smoothed Sobel magnitude above this is an edge (the thesis used 80, Ch. VI).
    #[arg(long, default_value_t = EdgeOptions::default().threshold)]
    pub threshold: u16,
    /// Hysteresis: a smoothed magnitude above this, connected to one above `--threshold`, is
    /// an edge too (docs/rendering.md "Photographic look"); `--weak-threshold 80` turns it off.
    #[arg(long, default_value_t = EdgeOptions::default().weak_threshold)]
    pub weak_threshold: u16,
    /// Faint edges between found vertices: the smallest step across them, gray levels.
    #[arg(long, default_value_t = FaintEdgeOptions::default().min_step_levels)]
    pub faint_min_step: f64,
    /// Faint edges: the share of their length that must show the step.
    #[arg(long, default_value_t = FaintEdgeOptions::default().min_share)]
    pub faint_min_share: f64,
    /// Longest stretch a line's free end is carried on to the line ahead, px.
    #[arg(long, default_value_t = GapOptions::default().max_gap_px)]
    pub max_gap: f64,
    /// Also mark the faint steps along the block directions, each read over 11 px along its
    /// direction (docs/recognizer-pictures.md "Steps read along the block directions"), as
    /// the last reading of `recognize` does.
    #[arg(long)]
    pub oriented: bool,
}

/// Runs `blockworld vertices`.
pub fn run(args: Args) -> anyhow::Result<()> {
    use crate::cli::check_number;
    let (step, share, gap) = (args.faint_min_step, args.faint_min_share, args.max_gap);
    check_number(
        "--faint-min-step",
        step,
        step >= 0.0,
        "use 0 gray levels or more",
    )?;
    let takes = "use a share from 0 to 1";
    check_number(
        "--faint-min-share",
        share,
        (0.0..=1.0).contains(&share),
        takes,
    )?;
    check_number("--max-gap", gap, gap >= 0.0, "use 0 px or more")?;
    if let Some(out) = &args.output {
        crate::cli::files::check_output(out, &[&args.view, &args.camera])?;
    }
    let gray = read_picture(&args.view)?;
    let camera = read_camera(&args.camera)?;
    let mut opts = VisionOptions::default();
    opts.edges.threshold = args.threshold;
    opts.edges.weak_threshold = args.weak_threshold;
    opts.faint.min_step_levels = args.faint_min_step;
    opts.faint.min_share = args.faint_min_share;
    opts.gaps.max_gap_px = args.max_gap;
    opts.oriented = args.oriented.then(OrientedOptions::default);
    let det = with_progress("vertices", "steps", VISION_STEPS, |p| {
        detect_line_drawing_with_progress(&gray, &camera, &opts, p)
    })
    .with_context(|| format!("{} (camera {})", args.view.display(), args.camera.display()))?;
    let text = det.drawing.to_json();
    match &args.output {
        Some(p) => {
            blockworld::io::write_atomic(p, text.as_bytes())
                .with_context(|| format!("writing {}", p.display()))?;
            outln!(
                "{} vertices, {} lines -> {}",
                det.drawing.points.len(),
                det.drawing.lines.len(),
                p.display()
            )?;
        }
        None => out!("{text}")?,
    }
    Ok(())
}
