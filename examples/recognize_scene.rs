//! The library's whole job in one program: read a scene, render its four corner views,
//! recognize the blocks from the pictures (the modified Kanade model) and score the answer
//! against the exact truth.
//!
//! ```sh
//! cargo run --example recognize_scene -- scenes/two_layer.json
//! cargo run --example recognize_scene -- scenes/thesis_sample.json --picture docs/overview.png
//! ```
//!
//! `--picture OUT.png` also writes the NE view side by side: the line-art picture, the photo
//! look, the ground truth's block ids, and the recognizer's answer drawn in line art (the
//! picture at the top of README.md).

use blockworld::camera::CornerView;
use blockworld::pipeline::{run_scene, PipelineOptions};
use blockworld::render::{Look, RenderOptions, Renderer};
use blockworld::scene::{read_scene, Scene};
use image::{GrayImage, Luma};
use std::path::{Path, PathBuf};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let mut scene_path = PathBuf::from("scenes/two_layer.json");
    let mut picture: Option<PathBuf> = None;
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--picture" => picture = args.next().map(PathBuf::from),
            _ => scene_path = PathBuf::from(arg),
        }
    }
    let scene = read_scene(&scene_path)?;
    let renderer = Renderer::new(Default::default())?;

    // Render, see, recognize and score: one call.
    let run = run_scene(&renderer, &scene.name, &scene, &PipelineOptions::default());
    let answer = run.reconstruction.as_ref();
    println!(
        "{}: {} blocks; recognized {} blocks; verdict {}, volume IoU {:.3}",
        scene.name,
        scene.blocks.len(),
        answer.map_or(0, |r| r.blocks.len()),
        run.result.verdict.as_str(),
        run.result.iou,
    );

    if let (Some(out), Some(answer)) = (picture, answer) {
        let answered = Scene::new(
            format!("{} (recognized)", scene.name),
            answer.blocks.clone(),
        );
        write_overview(&renderer, &scene, &answered, &out)?;
        println!("wrote {}", out.display());
    }
    Ok(())
}

/// The NE view of `truth` in line art and in the photo look, its block ids, and the NE view of
/// `answered` in line art, side by side.
fn write_overview(
    renderer: &Renderer,
    truth: &Scene,
    answered: &Scene,
    out: &Path,
) -> Result<(), Box<dyn std::error::Error>> {
    let ne = CornerView::ALL[0];
    let line_art = RenderOptions::default();
    let photo = RenderOptions {
        look: Look::Photo,
        ..RenderOptions::default()
    };
    let truth_view = renderer.render(truth, ne, &line_art)?;
    let photo_view = renderer.render(truth, ne, &photo)?;
    let answer_view = renderer.render(answered, ne, &line_art)?;
    // Block ids as gray levels: each block its own shade, the floor black.
    let blocks = truth.blocks.len().max(1) as f64;
    let ids = GrayImage::from_fn(truth_view.ids.width(), truth_view.ids.height(), |x, y| {
        let id = truth_view.ids.get_pixel(x, y)[0] as f64;
        Luma([if id == 0.0 {
            0
        } else {
            (80.0 + 175.0 * id / blocks) as u8
        }])
    });
    let panels = [&truth_view.gray, &photo_view.gray, &ids, &answer_view.gray];
    let (w, h) = (truth_view.gray.width(), truth_view.gray.height());
    let gap = 8;
    let mut sheet = GrayImage::from_pixel(4 * w + 3 * gap, h, Luma([255]));
    for (i, panel) in panels.iter().enumerate() {
        image::imageops::replace(&mut sheet, *panel, (i as u32 * (w + gap)) as i64, 0);
    }
    sheet.save(out)?;
    Ok(())
}
