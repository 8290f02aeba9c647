//! The vision front end (README "Vision front end"): the thesis's image stage, from a grayscale corner view to a
//! line drawing with six-bit codes.
//!
//! 1. [`sobel_magnitude`], [`smooth_3x3`], [`threshold`]: the Sobel operator of Chapter II
//!    (eq. 2.1, Figure 2.7) with the 3x3 smoothing and the threshold of Chapter VI, giving a
//!    binary edge map ([`EdgeOptions`], default threshold 80 as in the thesis).
//! 2. [`fit_lines`]: straight segments along the three picture directions of block edges
//!    ([`edge_directions`], from the camera: parallel, or through vanishing points), each fitted by least squares (Ch. VI).
//! 3. [`find_vertices`]: vertices at the intersections and ends of the fitted lines, as a
//!    [`LineDrawing`] whose `finalize` gives each vertex its six-bit code (Chapter IV bit order:
//!    0 up, 1 down, 2 left-up, 3 left-down, 4 right-up, 5 right-down; Appendix A's table uses
//!    another order and is not followed) and junction class (Ch. V "Y" and collinear "T").
//!
//! [`detect_line_drawing`] runs all three after checking the picture against its camera;
//! [`match_vertices`] measures a drawing against ground truth (`lines_<view>.json`).
//! Picture coordinates are those of `geom`: px, x right, y up, origin at the bottom-left corner,
//! raster row `r` at `y = H - r - 0.5`. No file I/O happens here.

mod edges;
mod error;
mod eval;
mod lines;
mod vertices;

pub use edges::{
    detect_edges, smooth_3x3, sobel_magnitude, threshold, EdgeOptions, MagnitudeImage, SmoothWindow,
};
pub use error::VisionError;
pub use eval::{
    line_angle_errors_deg, match_vertices, match_vertices_with_tolerances, MatchTolerances,
    VertexMatch,
};
pub use lines::{
    edge_directions, fit_line_least_squares, fit_lines, isometric_edge_directions,
    picture_directions, picture_from_raster, refine_lines_on_seams, EdgeDirection, FittedLine,
    LineOptions,
};
pub use vertices::{find_vertices, VertexOptions};

use crate::camera::Camera;
use crate::drawing::{EdgeAxis, LineDrawing};
use image::GrayImage;

/// Largest picture side accepted, px (the renderer's `--size` limit). Larger pictures get
/// [`VisionError::TooLarge`] instead of gigabytes of intermediate images.
pub const MAX_PICTURE_SIDE_PX: u32 = 8192;

/// Options of all three steps.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct VisionOptions {
    /// Step 1: Sobel, smoothing, threshold.
    pub edges: EdgeOptions,
    /// Step 2: line finding and fitting.
    pub lines: LineOptions,
    /// Step 3: vertices.
    pub vertices: VertexOptions,
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
    /// Sobel magnitude (eq. 2.1).
    pub sobel_ms: f64,
    /// 3x3 smoothing (Chapter VI).
    pub smooth_ms: f64,
    /// Threshold (Chapter VI: 80).
    pub threshold_ms: f64,
    /// Line finding, least-squares fits and their refinement.
    pub lines_ms: f64,
    /// Vertices, six-bit codes and junction classes.
    pub vertices_ms: f64,
}

impl VisionTimings {
    /// The five steps, in order.
    pub fn steps_ms(&self) -> [f64; 5] {
        [
            self.sobel_ms,
            self.smooth_ms,
            self.threshold_ms,
            self.lines_ms,
            self.vertices_ms,
        ]
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
/// drawing; a picture of another size than the camera's is an error.
pub fn detect_line_drawing(
    image: &GrayImage,
    camera: &Camera,
    opts: &VisionOptions,
) -> Result<Detection, VisionError> {
    check_picture(image, camera)?;
    Ok(detect_with_directions(
        image,
        &edge_directions(camera, &EdgeAxis::BLOCK_AXES),
        opts,
    ))
}

/// Steps 1-3 with the three picture directions given (no camera check).
pub fn detect_with_directions(
    image: &GrayImage,
    directions: &[(EdgeAxis, EdgeDirection)],
    opts: &VisionOptions,
) -> Detection {
    let mut clock = std::time::Instant::now();
    let mut lap = || {
        let ms = clock.elapsed().as_secs_f64() * 1e3;
        clock = std::time::Instant::now();
        ms
    };
    let mut timings = VisionTimings::default();
    let magnitude = sobel_magnitude(image);
    timings.sobel_ms = lap();
    let smoothed = smooth_3x3(&magnitude, opts.edges.window);
    timings.smooth_ms = lap();
    let edges = threshold(&smoothed, opts.edges.threshold);
    timings.threshold_ms = lap();
    let lines = fit_lines(&edges, directions, &opts.lines);
    let lines = refine_lines_on_seams(image, &lines, &opts.lines);
    timings.lines_ms = lap();
    let drawing = find_vertices(&lines, &opts.vertices);
    timings.vertices_ms = lap();
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
