//! `blockworld vertices VIEW.png --camera camera.json [-o OUT.json]`: lines, vertices, six-bit
//! codes and junction classes of a view (thesis Ch. IV-VI), as JSON in the picture coordinates
//! of `lines_<view>.json` (px, x right, y up, origin at the bottom-left corner).

use crate::camera::Camera;
use crate::vision::{decode_gray, detect_line_drawing, Detection, EdgeOptions, VisionOptions};
use anyhow::Context;
use image::GrayImage;
use std::path::{Path, PathBuf};

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
}

/// Runs `blockworld vertices`.
pub fn run(args: Args) -> anyhow::Result<()> {
    let gray = read_picture(&args.view)?;
    let camera = read_camera(&args.camera)?;
    let mut opts = VisionOptions::default();
    opts.edges.threshold = args.threshold;
    let det = detect_line_drawing(&gray, &camera, &opts)
        .with_context(|| format!("{} (camera {})", args.view.display(), args.camera.display()))?;
    let text = detection_json(&det);
    match &args.output {
        Some(p) => {
            crate::io::write_atomic(p, text.as_bytes())
                .with_context(|| format!("writing {}", p.display()))?;
            eprintln!(
                "{} vertices, {} lines -> {}",
                det.drawing.points.len(),
                det.drawing.lines.len(),
                p.display()
            );
        }
        None => print!("{text}"),
    }
    Ok(())
}

/// One vertex of the `vertices` JSON.
#[derive(serde::Serialize)]
struct VertexJson {
    x: f64,
    y: f64,
    code: u8,
    /// The thesis's class: "Y", "T", "L" or "other".
    junction: &'static str,
    /// The finer class (fork, arrow, T, L, end, ...).
    kind: crate::drawing::Junction,
}

/// One fitted line of the `vertices` JSON.
#[derive(serde::Serialize)]
struct FittedJson {
    from: [f64; 2],
    to: [f64; 2],
    orientation: usize,
    support: usize,
    rms_px: f64,
}

/// The whole `vertices` JSON, fields in this order.
#[derive(serde::Serialize)]
struct DetectionJson {
    vertices: Vec<VertexJson>,
    lines: Vec<[usize; 2]>,
    fitted: Vec<FittedJson>,
}

/// The `vertices` JSON: `{"vertices": [{"x", "y", "code", "junction", "kind"}], "lines":
/// [[a, b]], "fitted": [...]}` in picture px; `junction` is the thesis's class ("Y", "T", "L",
/// "other"), `lines` index `vertices`, `fitted` are the least-squares lines before splitting.
pub fn detection_json(det: &Detection) -> String {
    let d = &det.drawing;
    let round = |v: f64| (v * 1e4).round() / 1e4;
    let out = DetectionJson {
        vertices: d
            .points
            .iter()
            .enumerate()
            .map(|(i, p)| VertexJson {
                x: round(p.x),
                y: round(p.y),
                code: d.codes[i].0,
                junction: d.junctions[i].thesis_class(),
                kind: d.junctions[i],
            })
            .collect(),
        lines: d.lines.clone(),
        fitted: det
            .lines
            .iter()
            .map(|l| FittedJson {
                from: [round(l.from_px.x), round(l.from_px.y)],
                to: [round(l.to_px.x), round(l.to_px.y)],
                orientation: l.orientation,
                support: l.support,
                rms_px: round(l.rms_px),
            })
            .collect(),
    };
    let mut s = serde_json::to_string_pretty(&out).unwrap_or_default();
    s.push('\n');
    s
}

/// Reads a PNG as 8-bit gray; warns when it had to convert it.
pub fn read_picture(path: &Path) -> anyhow::Result<GrayImage> {
    let bytes = std::fs::read(path).with_context(|| format!("reading {}", path.display()))?;
    let dec = decode_gray(&bytes).with_context(|| format!("{}", path.display()))?;
    if let Some(from) = &dec.converted_from {
        eprintln!(
            "warning: {}: {from} image converted to 8-bit gray",
            path.display()
        );
    }
    Ok(dec.gray)
}

/// Reads `camera_<view>.json`.
pub fn read_camera(path: &Path) -> anyhow::Result<Camera> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
    serde_json::from_str(&text).with_context(|| {
        format!(
            "{}: not a camera file (write one with `blockworld render`)",
            path.display()
        )
    })
}
