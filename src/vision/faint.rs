//! Step 3b of the vision front end: faint edges between found vertices (docs/rendering.md "Photographic look").
//!
//! Two faces of nearly equal shading meet in an edge of a few gray levels (in a camera picture,
//! a bevel's highlight between a face and its neighbour lit almost alike): too weak for Chapter
//! VI's threshold, so no line is fitted along it, while the vertices at its two ends are found
//! from the strong edges that meet there. [`add_faint_edges`] looks where the drawing predicts
//! such an edge, between two of its vertices that lie along a picture direction of block
//! edges with no line between them, and reads the picture there as the thesis's line finder
//! read its edge pixels, across the line: the edge is added when the brightness changes by at
//! least [`FaintEdgeOptions::min_step_levels`] within 2 px along most of its length. A face
//! between the two vertices (no edge) changes by the noise only, a penumbra by far less than
//! that within 2 px.

use super::lines::{gray_at, EdgeDirection};
use crate::drawing::{EdgeAxis, LineDrawing};
use crate::geom::{noise_levels, DVec2};
use image::GrayImage;

/// Options of [`add_faint_edges`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FaintEdgeOptions {
    /// Smallest change of brightness within 2 px across the edge, gray levels. Default 4 (a
    /// photo-look face's noise is about 1 level; raised to [`NOISE_MULTIPLE`] times the
    /// picture's noise when that is higher).
    pub min_step_levels: f64,
    /// Share of the samples along the edge that must show the step. Default 0.7: where a soft
    /// shadow darkens one face to the other's brightness the step vanishes over part of the
    /// edge. Measured on the photo-look accuracy suite with `blockworld vertices
    /// --faint-min-share S --faint-min-step T` against the exact drawings: views matching
    /// 143 of 216 at (0.9, 5), 153 at (0.7, 4) and at (0.6, 4).
    pub min_share: f64,
    /// The two vertices' direction may differ from the block direction by this much, degrees.
    /// Default 1.5.
    pub max_angle_deg: f64,
    /// Shortest edge looked for, px. Default 10.
    pub min_length_px: f64,
}

impl Default for FaintEdgeOptions {
    fn default() -> Self {
        FaintEdgeOptions {
            min_step_levels: 4.0,
            min_share: 0.7,
            max_angle_deg: 1.5,
            min_length_px: 10.0,
        }
    }
}

/// The step looked for is at least this many times the picture's noise: a sample shows a
/// step when one of five 2 px differences reaches it, which noise of sigma 8 does at about 4%
/// of the samples at 3.5 sigma (and `min_share` asks for most of them). A photo-look picture
/// (noise about 1 level) keeps the 4 levels of the default.
pub const NOISE_MULTIPLE: f64 = 3.5;
/// Ends of the edge skipped by the samples, px (the strong edges meeting at the vertices).
const END_MARGIN_PX: f64 = 4.0;
/// A point this close to the segment between two vertices stands on it, px.
const ON_SEGMENT_PX: f64 = 2.0;

/// `true` when the picture shows an edge along `a`-`b`: at one offset across it (within 2 px of
/// the segment), at most samples (every px, away from the ends) the brightness changes by at
/// least `min_step` within 2 px, in the direction it changes at most samples there. An edge
/// steps one way all along; the noise of a face changes either way from sample to sample, so
/// a bright face's shot noise, well above the picture's noise (measured mostly on the darker
/// floor), shows no edge however often it reaches `min_step`.
fn picture_shows_edge(
    gray: &GrayImage,
    a: DVec2,
    b: DVec2,
    min_step: f64,
    opts: &FaintEdgeOptions,
) -> bool {
    let len = a.distance(b);
    let u = (b - a) / len;
    let n = u.perp();
    let offsets = -3..=1;
    let mut diffs: Vec<Vec<f64>> = offsets.clone().map(|_| Vec::new()).collect();
    let mut seen = 0usize;
    let mut t = END_MARGIN_PX;
    while t <= len - END_MARGIN_PX {
        let c = a + u * t;
        for (k, out) in offsets.clone().zip(diffs.iter_mut()) {
            let k = f64::from(k);
            if let (Some(far), Some(near)) =
                (gray_at(gray, c + n * (k + 2.0)), gray_at(gray, c + n * k))
            {
                out.push(far - near);
            }
        }
        seen += 1;
        t += 1.0;
    }
    seen > 0
        && diffs.iter().any(|d| {
            let ups = d.iter().filter(|&&x| x >= min_step).count();
            let downs = d.iter().filter(|&&x| x <= -min_step).count();
            ups.max(downs) as f64 >= opts.min_share * seen as f64
        })
}

/// `true` when some line of `d` already runs along `a`-`b` or crosses it.
fn blocked(d: &LineDrawing, a: DVec2, b: DVec2) -> bool {
    let len = a.distance(b);
    let u = (b - a) / len;
    let on = |p: DVec2| {
        let t = u.dot(p - a);
        t > ON_SEGMENT_PX && t < len - ON_SEGMENT_PX && u.perp_dot(p - a).abs() <= ON_SEGMENT_PX
    };
    // A vertex on the way: the edge would be two edges, looked for pair by pair.
    if d.points.iter().any(|&p| on(p)) {
        return true;
    }
    d.lines.iter().any(|&[i, j]| {
        let (c, e) = (d.points[i], d.points[j]);
        let along = (e - c).normalize_or_zero();
        let parallel = along.perp_dot(u).abs() < 0.05;
        if parallel {
            // Along it: the midpoint of a-b lies on the line.
            let m = (a + b) / 2.0;
            let s = along.dot(m - c);
            return s >= 0.0 && s <= c.distance(e) && along.perp_dot(m - c).abs() <= ON_SEGMENT_PX;
        }
        // Crossing it in both interiors.
        let den = u.perp_dot(e - c);
        let t = (c - a).perp_dot(e - c) / den;
        let s = (c - a).perp_dot(u) / den;
        t > ON_SEGMENT_PX && t < len - ON_SEGMENT_PX && s > 0.05 && s < 0.95
    })
}

/// Adds to `drawing` the faint edges the picture shows between its vertices (see the module
/// doc): pairs of vertices along one of `directions` (within `max_angle_deg`), nothing between
/// them, the step seen along the whole way. Recomputes codes and junctions when it adds any.
pub fn add_faint_edges(
    gray: &GrayImage,
    drawing: &mut LineDrawing,
    directions: &[(EdgeAxis, EdgeDirection)],
    opts: &FaintEdgeOptions,
) {
    // The noise is read only once a pair is worth looking at: most drawings have none.
    let mut min_step = None;
    let sin_max = opts.max_angle_deg.to_radians().sin();
    let mut added: Vec<[usize; 2]> = Vec::new();
    let n = drawing.points.len();
    for i in 0..n {
        for j in i + 1..n {
            let (a, b) = (drawing.points[i], drawing.points[j]);
            let len = a.distance(b);
            if len < opts.min_length_px || !len.is_finite() {
                continue;
            }
            let u = (b - a) / len;
            let mid = (a + b) / 2.0;
            let along_axis = directions
                .iter()
                .any(|(_, dir)| dir.at(mid).perp_dot(u).abs() <= sin_max);
            if !along_axis || blocked(drawing, a, b) {
                continue;
            }
            let min_step = *min_step.get_or_insert_with(|| {
                opts.min_step_levels
                    .max(NOISE_MULTIPLE * noise_levels(gray))
            });
            if picture_shows_edge(gray, a, b, min_step, opts) {
                added.push([i, j]);
            }
        }
    }
    if !added.is_empty() {
        drawing.lines.extend(added);
        drawing.finalize();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use image::Luma;

    /// Two vertices 40 px apart on a vertical, joined by nothing, and a line elsewhere.
    fn drawing() -> LineDrawing {
        LineDrawing {
            points: vec![
                DVec2::new(30.0, 10.0),
                DVec2::new(30.0, 50.0),
                DVec2::new(5.0, 5.0),
                DVec2::new(5.0, 55.0),
            ],
            lines: vec![[2, 3]],
            ..Default::default()
        }
    }

    fn vertical() -> Vec<(EdgeAxis, EdgeDirection)> {
        vec![(EdgeAxis::BLOCK_AXES[0], EdgeDirection::Parallel(DVec2::Y))]
    }

    #[test]
    fn a_faint_step_between_two_vertices_becomes_a_line_and_a_flat_face_does_not() {
        // Faces of 84 and 77 with a 1 px bevel of 95 between them (a photo-look edge).
        let faint = GrayImage::from_fn(60, 60, |x, _| {
            Luma([match x {
                0..=28 => 84,
                29 => 95,
                _ => 77,
            }])
        });
        let mut d = drawing();
        add_faint_edges(&faint, &mut d, &vertical(), &FaintEdgeOptions::default());
        assert!(d.lines.contains(&[0, 1]), "{:?}", d.lines);
        // A flat face: nothing to add.
        let flat = GrayImage::from_pixel(60, 60, Luma([80]));
        let mut d = drawing();
        add_faint_edges(&flat, &mut d, &vertical(), &FaintEdgeOptions::default());
        assert_eq!(d.lines, vec![[2, 3]]);
        // A step of 3 levels, under the 4 asked for: not an edge.
        let weak = GrayImage::from_fn(60, 60, |x, _| Luma([if x < 30 { 80 } else { 83 }]));
        let mut d = drawing();
        add_faint_edges(&weak, &mut d, &vertical(), &FaintEdgeOptions::default());
        assert_eq!(d.lines, vec![[2, 3]]);
    }

    /// A bright face whose shot noise (sigma about 3 levels) is far above the picture's noise,
    /// which the dark floor around it sets: its 2 px differences reach the 4 levels asked for
    /// at most samples, but of either sign, so no edge runs across it (the diagonal of a lit
    /// block face); the same face with a 6-level step down its middle shows the step.
    #[test]
    fn a_bright_noisy_face_shows_no_edge_and_a_step_on_it_does() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        let noise: Vec<f64> = (0..60 * 60).map(|_| rng.random_range(-5.5..5.5)).collect();
        // The face is columns 20 to 39; the floor, two thirds of the picture, is flat.
        let face = |step: f64| {
            GrayImage::from_fn(60, 60, |x, y| {
                let level = match x {
                    20..30 => 150.0,
                    30..40 => 150.0 - step,
                    _ => return Luma([18]),
                };
                Luma([(level + noise[(y * 60 + x) as usize]).round() as u8])
            })
        };
        let flat = face(0.0);
        assert!(
            noise_levels(&flat) < 4.0 / NOISE_MULTIPLE,
            "{}",
            noise_levels(&flat)
        );
        let mut d = drawing();
        add_faint_edges(&flat, &mut d, &vertical(), &FaintEdgeOptions::default());
        assert_eq!(d.lines, vec![[2, 3]], "noise read as an edge");
        let mut d = drawing();
        add_faint_edges(
            &face(12.0),
            &mut d,
            &vertical(),
            &FaintEdgeOptions::default(),
        );
        assert!(d.lines.contains(&[0, 1]), "{:?}", d.lines);
    }

    #[test]
    fn noise_raises_the_step_asked_for() {
        // Alternating 60/100 columns: every neighbour differs by 40, noise about 42 levels.
        let noisy = GrayImage::from_fn(60, 60, |x, _| Luma([if x % 2 == 0 { 60 } else { 100 }]));
        assert!((noise_levels(&noisy) - 41.9).abs() < 0.1);
        let mut d = drawing();
        add_faint_edges(&noisy, &mut d, &vertical(), &FaintEdgeOptions::default());
        assert_eq!(d.lines, vec![[2, 3]]);
    }
}
