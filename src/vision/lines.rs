//! Step 2 of the vision front end: straight lines from the binary edge map (Chapter VI,
//! "Display the Final Sample": "20 to 30 pieces of data of a line are first selected. The Least
//! Square Fitness Test ... is then applied to the data to obtain the gradient of a line").
//!
//! In a 45-degree corner view the edges of blocks resting on the floor run in three picture
//! directions: vertical, and the projections of the two horizontal world axes (Chapter V: "the
//! gradients of the left and the right side of a block are constant"). They are computed from
//! the camera ([`picture_directions`]). Lines are found in three steps:
//!
//! 1. **Support**: an edge pixel supports direction `k` when the edge map is set at the pixels
//!    `1..=reach` steps away on both sides along `k` (a few misses allowed): it lies inside a
//!    band running that way. This works for a step between two faces and for the renderer's
//!    dark seams alike, since it only reads the binary map.
//! 2. **Vote**: a one-dimensional Hough vote per direction over the offset `rho = n . p`; its
//!    peaks seed infinite lines; the supporting pixels of a peak, ordered along the line, are
//!    split at gaps into segments.
//! 3. **Fit**: each segment is fitted by total least squares (orthogonal regression) on all its
//!    pixels (the thesis used 20-30 samples per line; every supporting pixel is used here),
//!    giving a sub-pixel line; its extent is that of the supporting pixels.
//!
//! Only the directions asked for are found: the front end asks for the three block axes and,
//! among the pixels they leave unexplained, a trapezoidal block's slopes (`super::picture_axes`,
//! Figure 7.1); a block turned about the vertical is not found, the thesis's method assumes
//! blocks aligned with the views (Ch. VII).

use super::votes::{collect_votes, lines_from_votes, EdgeList, VoteFrame};
use crate::camera::Camera;
use crate::drawing::EdgeAxis;
pub(super) use crate::geom::gray_at;
use crate::geom::{DVec2, DVec3};
use image::GrayImage;

/// Options of the line finder; every length is in picture pixels.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LineOptions {
    /// Pixels checked on each side of an edge pixel along a direction. Default 3.
    pub reach_px: u32,
    /// How many of the `2 * reach_px` checked pixels may be missing. Default 1.
    pub max_misses: u32,
    /// Pixels within this distance of a vote peak's offset belong to its line. Default 3.0.
    pub band_half_width_px: f64,
    /// Two vote peaks of one direction are at least this far apart. Default 3.
    pub peak_separation_px: u32,
    /// A segment is split where consecutive supporting pixels are further apart. Default 4.0.
    pub max_gap_px: f64,
    /// Shortest segment kept. Default 8.0.
    pub min_length_px: f64,
    /// A fitted segment may turn at most this far from its seed direction, degrees (blobs of
    /// edge pixels at junctions fit badly). Default 4.0.
    pub max_turn_deg: f64,
}

impl Default for LineOptions {
    fn default() -> Self {
        LineOptions {
            reach_px: 3,
            max_misses: 1,
            band_half_width_px: 3.0,
            peak_separation_px: 3,
            max_gap_px: 4.0,
            min_length_px: 8.0,
            max_turn_deg: 4.0,
        }
    }
}

/// A straight line fitted by least squares to the edge pixels of one segment (Ch. VI).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FittedLine {
    /// The world axis whose picture direction seeded it.
    pub axis: EdgeAxis,
    /// Centroid of the supporting pixels, picture px (x right, y up).
    pub centroid_px: DVec2,
    /// Unit direction of the fitted line, picture px.
    pub direction: DVec2,
    /// First end: the extreme supporting pixel projected onto the line.
    pub from_px: DVec2,
    /// Second end.
    pub to_px: DVec2,
    /// Number of supporting pixels.
    pub support: usize,
    /// Root mean square orthogonal distance of the pixels from the line, px.
    pub rms_px: f64,
}

impl FittedLine {
    /// Length between the two ends, px.
    pub fn length_px(&self) -> f64 {
        self.from_px.distance(self.to_px)
    }

    /// Signed distance of `p` from the infinite line (positive on the left of `direction`).
    pub fn signed_distance_px(&self, p: DVec2) -> f64 {
        self.direction.perp_dot(p - self.centroid_px)
    }

    /// Position of `p` along the line, measured from the centroid, px.
    pub fn along_px(&self, p: DVec2) -> f64 {
        self.direction.dot(p - self.centroid_px)
    }
}

/// A fitted segment from `a` to `b` along block axis `EdgeAxis::BLOCK_AXES[k]` (20 supporting
/// pixels, 0.3 px RMS): the unit tests' segment, one home for the steps' tests.
#[cfg(test)]
pub(super) fn test_segment(k: usize, a: DVec2, b: DVec2) -> FittedLine {
    FittedLine {
        axis: EdgeAxis::BLOCK_AXES[k],
        centroid_px: (a + b) / 2.0,
        direction: (b - a).normalize(),
        from_px: a,
        to_px: b,
        support: 20,
        rms_px: 0.3,
    }
}

/// The picture directions of block edges along `axes` in `camera` (unit vectors, picture px,
/// y up), each the projection of a short world step at the scene centre (`camera.target_mm`)
/// through `picture_from_world`; each is made to point up or right.
pub fn picture_directions(camera: &Camera, axes: &[EdgeAxis]) -> Vec<DVec2> {
    let c = DVec3::from_array(camera.target_mm);
    let base = camera.picture_from_world(c).truncate();
    let step_mm = 1.0;
    let project = |d: DVec3, fallback: DVec2| {
        let v = camera.picture_from_world(c + d * step_mm).truncate() - base;
        let v = if v.is_finite() && v.length() > 1e-9 {
            v.normalize()
        } else {
            fallback
        };
        if v.y < 0.0 || (v.y == 0.0 && v.x < 0.0) {
            -v
        } else {
            v
        }
    };
    axes.iter()
        .map(|a| {
            let fallback = match a {
                EdgeAxis::WorldX => DVec2::new(0.866, 0.5),
                EdgeAxis::WorldZ => DVec2::new(-0.866, 0.5),
                _ => DVec2::Y,
            };
            project(a.world_direction(), fallback)
        })
        .collect()
}

/// How the block edges along one world axis run in the picture: all parallel (orthographic
/// views) or converging on a vanishing point (perspective views; Chapter II's one-point and
/// three-point perspective, Figures 2.8-2.9).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum EdgeDirection {
    /// Every edge runs along this unit picture direction (pointing up or right).
    Parallel(DVec2),
    /// Every edge lies on a line through this vanishing point, picture px.
    Vanishing(DVec2),
}

impl EdgeDirection {
    /// The unit picture direction of an edge through `p`, pointing up or right.
    pub fn at(&self, p: DVec2) -> DVec2 {
        let v = match *self {
            EdgeDirection::Parallel(u) => u,
            EdgeDirection::Vanishing(vp) => (p - vp).normalize_or_zero(),
        };
        if v.y < 0.0 || (v.y == 0.0 && v.x < 0.0) {
            -v
        } else {
            v
        }
    }

    /// Coordinates for the vote: `rho` tells lines of this direction apart (px across, or the
    /// angle about the vanishing point times `radius_px`), `t` orders pixels along a line.
    pub(super) fn vote_coordinates(&self, p: DVec2, axis: DVec2, radius_px: f64) -> (f64, f64) {
        match *self {
            EdgeDirection::Parallel(u) => (u.perp().dot(p), u.dot(p)),
            EdgeDirection::Vanishing(vp) => {
                let q = p - vp;
                (axis.perp_dot(q).atan2(axis.dot(q)) * radius_px, q.length())
            }
        }
    }
}

/// The [`EdgeDirection`]s of block edges along `axes` in `camera`, with their axes. Each world
/// axis `d` maps to the clip-space vector `C (d, 0)`: when its `w` is zero (always for
/// orthographic cameras) the edges are parallel, otherwise they meet at the vanishing point
/// `C (d, 0)` in normalized device coordinates.
pub fn edge_directions(camera: &Camera, axes: &[EdgeAxis]) -> Vec<(EdgeAxis, EdgeDirection)> {
    let c = camera.clip_from_world();
    let [w, h] = [f64::from(camera.size_px[0]), f64::from(camera.size_px[1])];
    let fallback = picture_directions(camera, axes);
    let one = |d: DVec3, k: usize| {
        let v = c * d.extend(0.0);
        let screen = DVec2::new(v.x * w / 2.0, v.y * h / 2.0);
        let far_px = 1e7;
        if v.w.abs() * far_px <= screen.length() || v.w.abs() < 1e-12 {
            return EdgeDirection::Parallel(fallback[k]);
        }
        let vp = DVec2::new((v.x / v.w + 1.0) / 2.0 * w, (v.y / v.w + 1.0) / 2.0 * h);
        if vp.is_finite() {
            EdgeDirection::Vanishing(vp)
        } else {
            EdgeDirection::Parallel(fallback[k])
        }
    };
    axes.iter()
        .enumerate()
        .map(|(k, a)| (*a, one(a.world_direction(), k)))
        .collect()
}

/// The block edge directions of an ideal isometric corner view without a camera at hand: vertical
/// and 30 degrees either side of horizontal (Chapter V's 45-degree views), all parallel.
pub fn isometric_edge_directions() -> Vec<(EdgeAxis, EdgeDirection)> {
    let s = 3f64.sqrt() / 2.0;
    let dirs = [DVec2::Y, DVec2::new(s, 0.5), DVec2::new(-s, 0.5)];
    EdgeAxis::BLOCK_AXES
        .into_iter()
        .zip(dirs.map(EdgeDirection::Parallel))
        .collect()
}

/// Picture coordinates (px, y up) of the centre of raster pixel `(col, row)` in an image of
/// `height` rows (docs/formats.md "Conventions": row `r` -> `y = H - r - 0.5`).
pub fn picture_from_raster(col: u32, row: u32, height: u32) -> DVec2 {
    DVec2::new(col as f64 + 0.5, height as f64 - row as f64 - 0.5)
}

/// Total least squares (orthogonal regression) line through `points`: the centroid, the unit
/// direction of largest spread, and the RMS orthogonal distance. `None` for fewer than two
/// distinct points. The closed form of the 2x2 covariance's principal axis is used.
pub fn fit_line_least_squares(points: &[DVec2]) -> Option<(DVec2, DVec2, f64)> {
    if points.len() < 2 {
        return None;
    }
    let n = points.len() as f64;
    let c = points.iter().fold(DVec2::ZERO, |a, p| a + *p) / n;
    let (mut sxx, mut sxy, mut syy) = (0.0, 0.0, 0.0);
    for p in points {
        let d = *p - c;
        sxx += d.x * d.x;
        sxy += d.x * d.y;
        syy += d.y * d.y;
    }
    if sxx + syy <= 0.0 {
        return None;
    }
    let angle = 0.5 * (2.0 * sxy).atan2(sxx - syy);
    let dir = DVec2::new(angle.cos(), angle.sin());
    let normal = dir.perp();
    let ss: f64 = points.iter().map(|p| normal.dot(*p - c).powi(2)).sum();
    Some((c, dir, (ss / n).sqrt()))
}

/// Finds the straight segments of the binary `edges` map (values 0/1 or 0/255) along the three
/// `directions` (usually [`edge_directions`] of the camera) and fits each by least squares
/// (Ch. VI). Segments are sorted by direction, then offset, then position; deterministic.
pub fn fit_lines(
    edges: &GrayImage,
    directions: &[(EdgeAxis, EdgeDirection)],
    opts: &LineOptions,
) -> Vec<FittedLine> {
    fit_lines_on(edges, &EdgeList::new(edges), directions, opts)
}

/// [`fit_lines`] with the edge pixels of `edges` already listed (the front end lists them once
/// for the lines and the curves).
pub(super) fn fit_lines_on(
    edges: &GrayImage,
    list: &EdgeList,
    directions: &[(EdgeAxis, EdgeDirection)],
    opts: &LineOptions,
) -> Vec<FittedLine> {
    let (w, h) = edges.dimensions();
    let raw = edges.as_raw();
    let edge_px = &list.px;
    let mut lines = Vec::new();
    for (k, dir) in directions.iter() {
        let ok = match *dir {
            EdgeDirection::Parallel(u) => u.is_finite() && u.length_squared() > 0.5,
            EdgeDirection::Vanishing(vp) => vp.is_finite(),
        };
        if !ok {
            continue;
        }
        let centre = DVec2::new(f64::from(w), f64::from(h)) / 2.0;
        let (axis, radius) = match *dir {
            EdgeDirection::Vanishing(vp) => (
                (centre - vp).normalize_or(DVec2::X),
                centre.distance(vp).max(1.0),
            ),
            EdgeDirection::Parallel(_) => (DVec2::X, 1.0),
        };
        let frame = VoteFrame {
            dir: *dir,
            axis,
            radius,
        };
        let votes = collect_votes(raw, edge_px, w, h, &frame, opts);
        lines.extend(lines_from_votes(votes, *k, &frame, opts));
    }
    lines
}

pub(super) fn fit_segment(
    points: &[DVec2],
    k: EdgeAxis,
    u: DVec2,
    max_turn_deg: f64,
) -> Option<FittedLine> {
    let (c, mut dir, rms) = fit_line_least_squares(points)?;
    if dir.dot(u) < 0.0 {
        dir = -dir;
    }
    if dir.dot(u) < max_turn_deg.to_radians().cos() {
        return None;
    }
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for p in points {
        let t = dir.dot(*p - c);
        lo = lo.min(t);
        hi = hi.max(t);
    }
    Some(FittedLine {
        axis: k,
        centroid_px: c,
        direction: dir,
        from_px: c + dir * lo,
        to_px: c + dir * hi,
        support: points.len(),
        rms_px: rms,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use image::Luma;

    #[test]
    fn least_squares_recovers_a_line_to_sub_pixel() {
        let pts: Vec<DVec2> = (0..25)
            .map(|i| {
                DVec2::new(
                    i as f64,
                    0.5 * i as f64 + 3.0 + if i % 2 == 0 { 0.1 } else { -0.1 },
                )
            })
            .collect();
        let (c, d, rms) = fit_line_least_squares(&pts).unwrap();
        assert!((d.y / d.x - 0.5).abs() < 0.01, "slope {}", d.y / d.x);
        assert!((c.y - (0.5 * c.x + 3.0)).abs() < 0.05);
        assert!(rms < 0.11);
        assert!(fit_line_least_squares(&pts[..1]).is_none());
        assert!(fit_line_least_squares(&[DVec2::ONE, DVec2::ONE]).is_none());
    }

    #[test]
    fn isometric_views_have_vertical_and_thirty_degree_directions() {
        use crate::camera::{CameraOptions, CornerView};
        let pts = [DVec3::new(-7.5, 0.0, -7.5), DVec3::new(7.5, 15.0, 7.5)];
        for view in CornerView::ALL {
            let cam = Camera::frame(&pts, view, &CameraOptions::default());
            let [v, a, b] = picture_directions(&cam, &EdgeAxis::BLOCK_AXES)[..] else {
                unreachable!()
            };
            assert!(v.distance(DVec2::Y) < 1e-9, "{view:?} {v}");
            for d in [a, b] {
                let deg = d.y.atan2(d.x.abs()).to_degrees();
                assert!((deg - 30.0).abs() < 1e-6, "{view:?} {d} at {deg} degrees");
            }
            assert!(a.x * b.x < 0.0, "one leans left, one right");
        }
    }

    #[test]
    fn a_vertical_band_gives_one_vertical_line() {
        // Columns 9..=12 set over rows 5..=40 of a 30 x 50 map.
        let edges = GrayImage::from_fn(30, 50, |x, y| {
            Luma([u8::from((9..=12).contains(&x) && (5..=40).contains(&y))])
        });
        let dirs = [DVec2::Y, DVec2::new(0.866, 0.5), DVec2::new(-0.866, 0.5)]
            .map(EdgeDirection::Parallel);
        let dirs: Vec<_> = EdgeAxis::BLOCK_AXES.into_iter().zip(dirs).collect();
        let lines = fit_lines(&edges, &dirs, &LineOptions::default());
        assert_eq!(lines.len(), 1, "{lines:?}");
        let l = lines[0];
        assert_eq!(l.axis, EdgeAxis::Vertical);
        assert!((l.centroid_px.x - 11.0).abs() < 1e-9, "{l:?}");
        assert!(l.direction.x.abs() < 1e-9);
        assert!(l.length_px() > 25.0);
    }
}
