//! `blockworld bench vision --scaling`: the vision front end's cost as the picture grows
//! (docs/vision.md "Vision front end", bounded cost on hostile input). A picture as dense in edges as the
//! front end accepts (just under [`MAX_EDGE_PX_PER_SIDE_PX`] x (w + h) edge pixels) is made at
//! each size, and the time per megapixel is printed: near linear in pixels means that figure
//! stays flat as the side doubles. A noise picture of the same size is refused by the edge cap,
//! and the time to refuse it is printed beside.

use super::fastest_ms;
use super::machine::banner;
use blockworld::camera::{Camera, CameraOptions, CornerView};
use blockworld::vision::{
    detect_line_drawing, VisionError, VisionOptions, MAX_EDGE_PX_PER_SIDE_PX,
};
use image::GrayImage;

/// The gray levels of the three kinds of cell (the shades of a cube's three visible faces).
const SHADES: [u8; 3] = [60, 130, 200];

/// A triangular tiling by the three picture directions of the block edges in an isometric
/// corner view (vertical and +-30 degrees, Chapter IV), `cells` cells across, each cell shaded
/// by the sum of its three indices modulo 3 so that every cell boundary is a gray-level step.
fn tiling(side_px: u32, cells: u32) -> GrayImage {
    let s = f64::from(side_px) / f64::from(cells);
    let t = 30f64.to_radians().tan();
    GrayImage::from_fn(side_px, side_px, |x, y| {
        let (x, y) = (f64::from(x) + 0.5, f64::from(y) + 0.5);
        let i = (x / s).floor() as i64;
        let j = ((y - t * x) / s).floor() as i64;
        let k = ((y + t * x) / s).floor() as i64;
        image::Luma([SHADES[(i + j + k).rem_euclid(3) as usize]])
    })
}

/// Uniform noise from a fixed seed (a splitmix64 sequence), half its pixels edges.
fn noise(side_px: u32) -> GrayImage {
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    GrayImage::from_fn(side_px, side_px, |_, _| {
        state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        image::Luma([(z >> 56) as u8])
    })
}

/// The default corner camera with a square picture of `side_px`.
fn square_camera(side_px: u32) -> Camera {
    let opts = CameraOptions {
        size_px: [side_px, side_px],
        ..CameraOptions::default()
    };
    Camera::frame(&[], CornerView::Ne, &opts)
}

/// Cells across the tiling at every size: the densest tiling the edge cap accepts at 512 px
/// (its edge pixels grow with the side, as the cap does, so it stays under the cap at every
/// size).
const CELLS: u32 = 28;

/// Runs the scaling table for sides 512, 1024, ... up to `max_side_px`.
pub fn run(max_side_px: u32, repeat: u32) -> anyhow::Result<()> {
    outln!("{}", banner(None).trim_end())?;
    outln!(
        "vision front end vs picture size: a {CELLS}-cell tiling in the block directions (edges just under the cap of {MAX_EDGE_PX_PER_SIDE_PX} x (w + h) pixels), fastest of {repeat}, one core"
    )?;
    outln!("| side px | Mpx | edge px | cap px | lines | vertices | ms | ms per Mpx | noise: refused in ms |")?;
    outln!("|---|---|---|---|---|---|---|---|---|")?;
    let opts = VisionOptions::default();
    let mut side = 512;
    while side <= max_side_px {
        let camera = square_camera(side);
        let picture = tiling(side, CELLS);
        let (ms, det) = fastest_ms(repeat as usize, || {
            detect_line_drawing(&picture, &camera, &opts)
        });
        let det = det?;
        let edge_px = det.edges.as_raw().iter().filter(|v| **v != 0).count();
        let cap_px = MAX_EDGE_PX_PER_SIDE_PX * 2 * u64::from(side);
        let hostile = noise(side);
        let (noise_ms, refused) = fastest_ms(repeat as usize, || {
            detect_line_drawing(&hostile, &camera, &opts)
        });
        let refused = matches!(refused, Err(VisionError::TooManyEdges { .. }));
        let mpx = f64::from(side) * f64::from(side) / 1e6;
        outln!(
            "| {side} | {mpx:.2} | {edge_px} | {cap_px} | {} | {} | {ms:.1} | {:.1} | {} |",
            det.lines.len(),
            det.drawing.points.len(),
            ms / mpx,
            if refused {
                format!("{noise_ms:.1}")
            } else {
                "NOT refused".to_string()
            }
        )?;
        side *= 2;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_tiling_stays_under_the_edge_cap_at_two_sizes_and_noise_does_not() {
        let opts = VisionOptions::default();
        for side in [512, 1024] {
            let camera = square_camera(side);
            let det = detect_line_drawing(&tiling(side, CELLS), &camera, &opts).unwrap();
            let edge_px = det.edges.as_raw().iter().filter(|v| **v != 0).count() as u64;
            let cap_px = MAX_EDGE_PX_PER_SIDE_PX * 2 * u64::from(side);
            assert!(
                edge_px * 2 > cap_px && edge_px < cap_px,
                "{edge_px} of {cap_px}"
            );
            assert!(
                det.lines.len() > 3 * CELLS as usize,
                "{} lines",
                det.lines.len()
            );
        }
        let camera = square_camera(512);
        assert!(matches!(
            detect_line_drawing(&noise(512), &camera, &opts),
            Err(VisionError::TooManyEdges { .. })
        ));
    }
}
