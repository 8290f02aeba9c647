//! The vision front end (docs/vision.md "Vision front end"): the thesis's image stage, from a grayscale corner view to a
//! line drawing with six-bit codes.
//!
//! 1. [`sobel_magnitude`], [`smooth_3x3`], [`threshold`]: the Sobel operator of Chapter II
//!    (eq. 2.1, Figure 2.7) with the 3x3 smoothing and the threshold of Chapter VI, giving a
//!    binary edge map ([`EdgeOptions`], default threshold 80 as in the thesis); [`edge_map`]
//!    computes the three in one pass over the picture. With [`VisionOptions::oriented`] set,
//!    [`oriented_edge_map`] adds the pixels of faint steps read along the block directions
//!    (the recognizer's last reading of a declined picture).
//! 2. [`fit_lines`]: straight segments along the three picture directions of block edges
//!    ([`edge_directions`], from the camera: parallel, or through vanishing points), each fitted by least squares (Ch. VI).
//!    [`drop_soft_edges`] drops lines along soft shading (a shadow's penumbra, read across
//!    the line in the picture), and [`bridge_free_ends`] then carries a line that stops in the open (an edge a soft shadow
//!    hides over part of its length) on to the line ahead of it.
//! 3. [`find_vertices`]: vertices at the intersections and ends of the fitted lines, as a
//!    [`LineDrawing`] whose `finalize` gives each vertex its six-bit code (Chapter IV bit order:
//!    0 up, 1 down, 2 left-up, 3 left-down, 4 right-up, 5 right-down; Appendix A's table uses
//!    another order and is not followed) and junction class (Ch. V "Y" and collinear "T").
//!
//!    [`add_faint_edges`] then adds the edges too faint for the threshold between vertices the
//!    drawing already has, where the picture shows them.
//!
//! 4. [`find_curved_edges`]: the edges that are not straight (a round part's rims, Chapter
//!    VII's "circles") reported as curves, chains of chords flagged in `curved_lines` as in the
//!    exact drawing, instead of being chopped into straight pieces or dropped.
//!
//! [`detect_line_drawing`] runs all three after checking the picture against its camera;
//! [`match_vertices`] measures a drawing against ground truth (`lines_<view>.json`).
//! Picture coordinates are those of `geom`: px, x right, y up, origin at the bottom-left corner,
//! raster row `r` at `y = H - r - 0.5`. No file I/O happens here.

mod curves;
mod edges;
mod error;
mod eval;
mod faint;
mod gaps;
mod lines;
mod oriented;
mod seams;
mod soft;
mod vertices;
mod votes;

pub use crate::geom::noise_levels;
pub use curves::{add_curved_edges, find_curved_edges, fit_circle, residue_map, CurvedEdge};
pub use edges::{
    detect_edges, edge_map, smooth_3x3, sobel_magnitude, threshold, threshold_hysteresis,
    EdgeOptions, MagnitudeImage, SmoothWindow,
};
pub use error::VisionError;
pub use eval::{
    line_angle_errors_deg, match_vertices, match_vertices_with_tolerances, MatchTolerances,
    VertexMatch,
};
pub use faint::{add_faint_edges, FaintEdgeOptions};
pub use gaps::{bridge_free_ends, GapOptions};
pub use lines::{
    edge_directions, fit_line_least_squares, fit_lines, isometric_edge_directions,
    picture_directions, picture_from_raster, EdgeDirection, FittedLine, LineOptions,
};
pub use oriented::{oriented_edge_map, OrientedOptions};
pub use seams::refine_lines_on_seams;
pub use soft::{drop_soft_edges, step_sharpness, STEP_SHARPNESS_MIN};
pub use vertices::{find_vertices, VertexOptions};

use crate::camera::Camera;
use crate::drawing::{EdgeAxis, LineDrawing};
use image::GrayImage;
use oriented::union_of_edge_maps;

/// Largest picture side accepted, px (the renderer's `--size` limit). Larger pictures get
/// [`VisionError::TooLarge`] instead of gigabytes of intermediate images.
pub const MAX_PICTURE_SIDE_PX: u32 = 8192;

/// Options of all three steps.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct VisionOptions {
    /// Step 1: Sobel, smoothing, threshold.
    pub edges: EdgeOptions,
    /// Step 1b: when set, the edge pixels of faint steps along the block directions are added
    /// to step 1's ([`oriented_edge_map`]); off by default, as in the thesis.
    pub oriented: Option<OrientedOptions>,
    /// Step 2: line finding and fitting.
    pub lines: LineOptions,
    /// Step 2b: free line ends carried on to the line they stop short of.
    pub gaps: GapOptions,
    /// Step 3: vertices.
    pub vertices: VertexOptions,
    /// Step 3b: faint edges between found vertices.
    pub faint: FaintEdgeOptions,
}

/// Everything the front end found in one picture.
#[derive(Debug, Clone)]
pub struct Detection {
    /// The binary edge map (0/1).
    pub edges: GrayImage,
    /// The fitted lines.
    pub lines: Vec<FittedLine>,
    /// Vertices, the lines between them, six-bit codes and junction classes.
    pub drawing: LineDrawing,
    /// Milliseconds spent in each step, measured where the step runs.
    pub timings: VisionTimings,
}

/// The front end's stage counters: milliseconds per step of one picture, measured inside
/// [`detect_with_directions`] so benchmarks report the stage's own figures.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct VisionTimings {
    /// Step 1 in one pass ([`edge_map`]): Sobel magnitude (eq. 2.1), 3x3 smoothing and the
    /// threshold (Chapter VI: 80).
    pub edges_ms: f64,
    /// Line finding, least-squares fits and their refinement.
    pub lines_ms: f64,
    /// Vertices, six-bit codes and junction classes.
    pub vertices_ms: f64,
}

impl VisionTimings {
    /// The three steps, in order: edges, lines, vertices.
    pub fn steps_ms(&self) -> [f64; 3] {
        [self.edges_ms, self.lines_ms, self.vertices_ms]
    }
}

/// Checks a picture against its camera: same size, not larger than [`MAX_PICTURE_SIDE_PX`].
pub fn check_picture(image: &GrayImage, camera: &Camera) -> Result<(), VisionError> {
    let (w, h) = image.dimensions();
    check_side(w, h)?;
    let [cw, ch] = camera.size_px;
    if (w, h) != (cw, ch) {
        return Err(VisionError::SizeMismatch {
            got_w: w,
            got_h: h,
            want_w: cw,
            want_h: ch,
        });
    }
    Ok(())
}

fn check_side(w: u32, h: u32) -> Result<(), VisionError> {
    if w > MAX_PICTURE_SIDE_PX || h > MAX_PICTURE_SIDE_PX {
        return Err(VisionError::TooLarge {
            w,
            h,
            max: MAX_PICTURE_SIDE_PX,
        });
    }
    Ok(())
}

/// Runs steps 1-3 on `image` taken by `camera`. An empty or constant picture gives an empty
/// drawing; a picture of another size than the camera's is an error, and so is one with more
/// edge pixels than any block scene gives ([`MAX_EDGE_PX_PER_SIDE_PX`]).
pub fn detect_line_drawing(
    image: &GrayImage,
    camera: &Camera,
    opts: &VisionOptions,
) -> Result<Detection, VisionError> {
    detect_line_drawing_with_progress(image, camera, opts, &|_, _| {})
}

/// The steps [`detect_line_drawing_with_progress`] reports: edges (Sobel, smoothing and
/// threshold in one pass), lines, vertices.
pub const VISION_STEPS: u64 = 3;

/// [`detect_line_drawing`] reporting `(done, VISION_STEPS)` after each step, so vision on a
/// large picture, which takes seconds, can show progress (docs/cli.md "Exit codes and progress output").
pub fn detect_line_drawing_with_progress(
    image: &GrayImage,
    camera: &Camera,
    opts: &VisionOptions,
    progress: &(dyn Fn(u64, u64) + Sync),
) -> Result<Detection, VisionError> {
    check_picture(image, camera)?;
    let (edges, timings) = timed_edges(image, opts, progress);
    check_edge_count(&edges)?;
    let directions = edge_directions(camera, &picture_axes(camera));
    Ok(detect_from_edges(
        image,
        edges,
        &directions,
        opts,
        timings,
        progress,
    ))
}

/// Two picture directions closer than this, degrees, are one: a trapezoidal block's slope that
/// projects (nearly) parallel to a block axis is found as that axis.
pub const MIN_DIRECTION_SEPARATION_DEG: f64 = 6.0;

/// The world directions whose edges the line finder looks for in `camera`'s picture: the three
/// block axes and the trapezoidal block's slopes (Chapter VII, Figure 7.1: a fourth and fifth
/// picture direction), each slope only where its picture direction differs from every earlier
/// one by at least [`MIN_DIRECTION_SEPARATION_DEG`] (in isometric corner views a 45-degree slope
/// projects parallel to a horizontal axis in two of the four views).
pub fn picture_axes(camera: &Camera) -> Vec<EdgeAxis> {
    let mut axes = EdgeAxis::BLOCK_AXES.to_vec();
    for slope in EdgeAxis::TRAPEZOID_SLOPES {
        let dirs = picture_directions(camera, &axes);
        let d = picture_directions(camera, &[slope])[0];
        let apart = dirs.iter().all(|u| {
            let ang = u.angle_to(d).abs().to_degrees();
            ang.min(180.0 - ang) >= MIN_DIRECTION_SEPARATION_DEG
        });
        if apart {
            axes.push(slope);
        }
    }
    axes
}

/// Shortest line kept in a direction other than the block axes, px: the sloped edges are
/// looked for only among the edge pixels no block-axis line explains ([`residue_map`]), where
/// the blobs left at junctions of block edges give pieces shorter than this.
pub const MIN_SLOPED_LINE_PX: f64 = 12.0;

/// Edge pixels allowed per pixel of picture side (width + height). A line drawing's edge
/// pixels grow with the picture's side, since its lines are a few pixels wide: over the
/// accuracy suite's views at 512x480 and 2048x2048 at most 20 (w + h) pixels were edges.
/// Noise grows with the area (half the pixels of a random picture are edges) and made line
/// finding superlinear (an 8192x8192 noise picture took 263 s and 2.7 GB), so a picture with
/// more than 200 (w + h) edge pixels, ten times any block scene, is refused.
pub const MAX_EDGE_PX_PER_SIDE_PX: u64 = 200;

/// Refuses an edge map with more than [`MAX_EDGE_PX_PER_SIDE_PX`] x (w + h) edge pixels.
pub fn check_edge_count(edges: &GrayImage) -> Result<(), VisionError> {
    let (w, h) = edges.dimensions();
    let cap_px = MAX_EDGE_PX_PER_SIDE_PX * (w as u64 + h as u64);
    let edge_px = edges.as_raw().iter().filter(|v| **v != 0).count() as u64;
    if edge_px > cap_px {
        return Err(VisionError::TooManyEdges { edge_px, cap_px });
    }
    Ok(())
}

/// Steps 1-3 with the three picture directions given (no camera check).
pub fn detect_with_directions(
    image: &GrayImage,
    directions: &[(EdgeAxis, EdgeDirection)],
    opts: &VisionOptions,
) -> Detection {
    let (edges, timings) = timed_edges(image, opts, &|_, _| {});
    detect_from_edges(image, edges, directions, opts, timings, &|_, _| {})
}

fn ms_since(t: std::time::Instant) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}

/// Step 1, counted.
fn timed_edges(
    image: &GrayImage,
    opts: &VisionOptions,
    progress: &(dyn Fn(u64, u64) + Sync),
) -> (GrayImage, VisionTimings) {
    let t = std::time::Instant::now();
    let edges = edge_map(image, &opts.edges);
    let timings = VisionTimings {
        edges_ms: ms_since(t),
        ..Default::default()
    };
    progress(1, VISION_STEPS);
    (edges, timings)
}

/// Steps 2-3 on an edge map of `image`, counted into `timings`.
fn detect_from_edges(
    image: &GrayImage,
    edges: GrayImage,
    directions: &[(EdgeAxis, EdgeDirection)],
    opts: &VisionOptions,
    mut timings: VisionTimings,
    progress: &(dyn Fn(u64, u64) + Sync),
) -> Detection {
    let t = std::time::Instant::now();
    let (axes, others): (Vec<_>, Vec<_>) = directions
        .iter()
        .partition(|(k, _)| EdgeAxis::BLOCK_AXES.contains(k));
    let list = votes::EdgeList::new(&edges);
    // Step 1b's pixels feed the block-axis lines only: the sloped lines and the curves are
    // read from Chapter VI's edges, as without it (a penumbra's faint arc is no rim).
    let with_faint = opts.oriented.map(|o| {
        let dirs: Vec<EdgeDirection> = axes.iter().map(|(_, d)| *d).collect();
        let mut union = edges.clone();
        union_of_edge_maps(&mut union, &oriented_edge_map(image, &dirs, &o));
        union
    });
    let mut lines = match &with_faint {
        Some(union) => {
            let union_list = votes::EdgeList::new(union);
            lines::fit_lines_on(union, &union_list, &axes, &opts.lines)
        }
        None => lines::fit_lines_on(&edges, &list, &axes, &opts.lines),
    };
    if !others.is_empty() {
        let residue = curves::residue_map_on(&edges, &list, &lines);
        let sloped = fit_lines(&residue, &others, &opts.lines);
        lines.extend(
            sloped
                .into_iter()
                .filter(|l| l.length_px() >= MIN_SLOPED_LINE_PX),
        );
    }
    let lines = refine_lines_on_seams(image, &lines, &opts.lines);
    let lines = drop_soft_edges(image, &lines);
    let (curves, lines) = curves::find_curved_edges_on(&edges, &list, &lines);
    let lines = bridge_free_ends(&lines, &opts.gaps);
    timings.lines_ms = ms_since(t);
    progress(2, VISION_STEPS);
    let t = std::time::Instant::now();
    let mut drawing = find_vertices(&lines, &opts.vertices);
    add_faint_edges(image, &mut drawing, directions, &opts.faint);
    if !curves.is_empty() {
        add_curved_edges(&mut drawing, &curves);
    }
    timings.vertices_ms = ms_since(t);
    progress(3, VISION_STEPS);
    Detection {
        edges,
        lines,
        drawing,
        timings,
    }
}

/// A picture decoded from bytes, converted to 8-bit gray when it was not.
#[derive(Debug, Clone)]
pub struct DecodedPicture {
    /// The 8-bit grayscale picture.
    pub gray: GrayImage,
    /// The colour type it had when it was not 8-bit grayscale (it was converted), e.g. "Rgb8".
    pub converted_from: Option<String>,
}

/// Decodes image bytes (PNG) to 8-bit gray, refusing pictures larger than
/// [`MAX_PICTURE_SIDE_PX`] before allocating them; other colour types are converted (luma) and
/// reported in [`DecodedPicture::converted_from`] so the caller can warn.
pub fn decode_gray(bytes: &[u8]) -> Result<DecodedPicture, VisionError> {
    let reader = image::ImageReader::new(std::io::Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| VisionError::Decode(e.to_string()))?;
    let (w, h) = reader
        .into_dimensions()
        .map_err(|e| VisionError::Decode(e.to_string()))?;
    check_side(w, h)?;
    let mut reader = image::ImageReader::new(std::io::Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| VisionError::Decode(e.to_string()))?;
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(MAX_PICTURE_SIDE_PX);
    limits.max_image_height = Some(MAX_PICTURE_SIDE_PX);
    reader.limits(limits);
    let img = reader
        .decode()
        .map_err(|e| VisionError::Decode(e.to_string()))?;
    let converted_from = match img.color() {
        image::ColorType::L8 => None,
        other => Some(format!("{other:?}")),
    };
    Ok(DecodedPicture {
        gray: img.into_luma8(),
        converted_from,
    })
}
