//! Reading the files the stages exchange, with errors that name the file and say how to make a
//! good one: pictures (`view_<v>.png`), cameras (`camera_<v>.json`) and line drawings
//! (`lines_<v>.json`, `vertices_<v>.json`, hand-made drawings).

use anyhow::Context;
use blockworld::camera::{parse_camera_json, Camera};
use blockworld::drawing::LineDrawing;
use blockworld::scene::{read_scene_with_progress, Scene, SceneError};
use blockworld::vision::decode_gray;
use image::GrayImage;
use std::path::Path;

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

/// Reads and checks a `camera_<view>.json`.
pub fn read_camera(path: &Path) -> anyhow::Result<Camera> {
    let text =
        blockworld::io::read_text(path).with_context(|| format!("reading {}", path.display()))?;
    parse_camera_json(&text).with_context(|| format!("{}", path.display()))
}

/// Reads and checks a line drawing.
pub fn read_drawing(path: &Path) -> anyhow::Result<LineDrawing> {
    let text =
        blockworld::io::read_text(path).with_context(|| format!("reading {}", path.display()))?;
    LineDrawing::from_json(&text).with_context(|| format!("{}", path.display()))
}

/// Reads and validates a scene file, showing the validation's progress (block pairs tested;
/// docs/cli.md "Exit codes and progress output"). The error is the library's, naming the file.
pub fn read_scene_shown(path: &Path) -> Result<Scene, SceneError> {
    crate::cli::progress::with_progress("validate", "block pairs", 0, |p| {
        read_scene_with_progress(path, p)
    })
}
