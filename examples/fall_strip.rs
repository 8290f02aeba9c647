//! A fall in four pictures (docs/stability.md "A fall in pictures"): scene 27 of the stability
//! dataset `generate --keep-unstable --seed 11` (a tower whose upper blocks are shifted off their
//! support), simulated with its trajectory, and its NE view at four of the trajectory's frames,
//! drawn from one camera framed on every frame's blocks, side by side.
//!
//! ```sh
//! cargo run --example fall_strip -- docs/stability_fall.png
//! ```

use blockworld::camera::{CameraOptions, CornerView};
use blockworld::dataset::{draw_scene, Family, SceneSpec, StabilityOptions};
use blockworld::geom::DVec3;
use blockworld::physics::SettleParams;
use blockworld::render::{RenderOptions, Renderer};
use blockworld::scene::{Orientation, Scene};
use image::GrayImage;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "docs/stability_fall.png".into());
    let spec = SceneSpec::new(11, 27, &Family::ALL);
    let stability = StabilityOptions {
        trajectory: true,
        ..Default::default()
    };
    let drawn = draw_scene(&spec, &SettleParams::default(), Some(&stability))?;
    let fall = drawn.trajectory.ok_or("the draw has no trajectory")?;
    // The scene with its blocks at the poses of frame k.
    let at = |k: usize| -> Scene {
        let mut s = drawn.scene.clone();
        for (b, (c, q)) in s.blocks.iter_mut().zip(&fall.frames[k]) {
            b.center_mm = *c;
            b.orientation = Orientation::Quaternion(*q);
        }
        s
    };
    let last = fall.frames.len() - 1;
    let picks = [0, last / 4, last / 2, last];
    let every_frame: Vec<DVec3> = (0..=last).flat_map(|k| at(k).world_vertices()).collect();
    let renderer = Renderer::new(Default::default())?;
    let opts = RenderOptions {
        camera: CameraOptions {
            size_px: [256, 240],
            ..Default::default()
        },
        ..Default::default()
    };
    let ne = [CornerView::ALL[0]];
    let mut strip = GrayImage::new(256 * 4, 240);
    for (slot, &k) in picks.iter().enumerate() {
        let view = renderer.render_views_pixels_framed(&at(k), &ne, &opts, &every_frame)?;
        image::imageops::replace(&mut strip, &view[0].gray, 256 * slot as i64, 0);
    }
    strip.save(&out)?;
    let times: Vec<String> = picks
        .iter()
        .map(|&k| format!("{:.3}", fall.times_s[k]))
        .collect();
    println!(
        "{} ({}, {}): frames {picks:?} of {} at {} s -> {out}",
        spec.id(),
        spec.family.name(),
        drawn
            .scene
            .meta
            .as_ref()
            .map_or(String::new(), |m| m["stability"]["cause"].to_string()),
        last + 1,
        times.join(", ")
    );
    Ok(())
}
