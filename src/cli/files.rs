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

/// The one output-path check of every command that writes a file, run before any work
/// (docs/limits.md "Outputs"): a directory where a file is meant is refused, a device node or
/// FIFO is written through (`blockworld::io::check_output_path`), and an output that is one of
/// the command's `inputs` (the same file, by device and inode) is refused, since writing it
/// would replace the input the command reads.
pub fn check_output(output: &Path, inputs: &[&Path]) -> anyhow::Result<()> {
    use std::os::unix::fs::MetadataExt;
    let target = blockworld::io::check_output_path(output)
        .with_context(|| format!("output {}", output.display()))?;
    if target == blockworld::io::OutputTarget::Stream {
        return Ok(());
    }
    let Ok(out) = std::fs::metadata(output) else {
        return Ok(());
    };
    for input in inputs {
        let same =
            std::fs::metadata(input).is_ok_and(|m| (m.dev(), m.ino()) == (out.dev(), out.ino()));
        if same {
            anyhow::bail!(
                "output {} is the input {}: writing it would replace what is read; give another \
                 output name",
                output.display(),
                input.display()
            );
        }
    }
    Ok(())
}
