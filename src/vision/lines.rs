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

use crate::camera::Camera;
use crate::drawing::EdgeAxis;
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
    fn vote_coordinates(&self, p: DVec2, axis: DVec2, radius_px: f64) -> (f64, f64) {
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
/// `height` rows (README "Picture coordinates": row `r` -> `y = H - r - 0.5`).
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

/// One supporting pixel: offset across and position along its direction, and its picture point.
#[derive(Clone, Copy)]
struct Vote {
    rho: f64,
    t: f64,
    p: DVec2,
}

/// Longest reach of the support test, px.
const MAX_REACH_PX: usize = 8;

/// Integer raster steps `(dcol, drow)` for `1..=reach` along picture direction `u` (no
/// allocation: it runs per pixel in perspective views).
fn raster_steps(u: DVec2, reach: u32, out: &mut [(i64, i64); MAX_REACH_PX]) -> usize {
    let n = (reach as usize).min(MAX_REACH_PX);
    for (i, o) in out.iter_mut().enumerate().take(n) {
        let f = (i + 1) as f64;
        *o = ((u.x * f).round() as i64, (-u.y * f).round() as i64);
    }
    n
}

/// Whether the edge pixel at `(col, row)` lies in a band running along `steps`.
fn supports(
    edges: &[u8],
    w: i64,
    h: i64,
    col: i64,
    row: i64,
    steps: &[(i64, i64)],
    max_misses: u32,
) -> bool {
    let set =
        |c: i64, r: i64| c >= 0 && r >= 0 && c < w && r < h && edges[(r * w + c) as usize] != 0;
    let mut misses = 0;
    for &(dc, dr) in steps {
        for s in [1, -1] {
            if !set(col + s * dc, row + s * dr) {
                misses += 1;
                if misses > max_misses {
                    return false;
                }
            }
        }
    }
    true
}

/// Finds the straight segments of the binary `edges` map (values 0/1 or 0/255) along the three
/// `directions` (usually [`edge_directions`] of the camera) and fits each by least squares
/// (Ch. VI). Segments are sorted by direction, then offset, then position; deterministic.
pub fn fit_lines(
    edges: &GrayImage,
    directions: &[(EdgeAxis, EdgeDirection)],
    opts: &LineOptions,
) -> Vec<FittedLine> {
    let (w, h) = edges.dimensions();
    let raw = edges.as_raw();
    let edge_px = edge_pixels(raw, w);
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
        let votes = collect_votes(raw, &edge_px, w, h, &frame, opts);
        lines.extend(lines_from_votes(votes, *k, &frame, opts));
    }
    lines
}

/// One direction's vote coordinates (see [`EdgeDirection::vote_coordinates`]).
struct VoteFrame {
    dir: EdgeDirection,
    axis: DVec2,
    radius: f64,
}

/// The `(column, row)` of every edge pixel (non-zero), row by row: found once and shared by
/// the three directions' votes. Eight pixels are tested at a time, since most are not edges.
fn edge_pixels(raw: &[u8], w: u32) -> Vec<(u32, u32)> {
    let mut out = Vec::new();
    let w = w as usize;
    if w == 0 {
        return out;
    }
    for (row, line) in raw.chunks_exact(w).enumerate() {
        let mut chunks = line.chunks_exact(8);
        let mut base = 0;
        for c in chunks.by_ref() {
            if u64::from_ne_bytes(c.try_into().expect("eight bytes")) != 0 {
                let hits = c.iter().enumerate().filter(|(_, &v)| v != 0);
                out.extend(hits.map(|(i, _)| ((base + i) as u32, row as u32)));
            }
            base += 8;
        }
        let rest = chunks
            .remainder()
            .iter()
            .enumerate()
            .filter(|(_, &v)| v != 0);
        out.extend(rest.map(|(i, _)| ((base + i) as u32, row as u32)));
    }
    out
}

fn collect_votes(
    raw: &[u8],
    edge_px: &[(u32, u32)],
    w: u32,
    h: u32,
    frame: &VoteFrame,
    opts: &LineOptions,
) -> Vec<Vote> {
    let mut steps = [(0i64, 0i64); MAX_REACH_PX];
    let mut n_steps = 0;
    if let EdgeDirection::Parallel(u) = frame.dir {
        n_steps = raster_steps(u, opts.reach_px, &mut steps);
    }
    let mut votes = Vec::new();
    let (wi, hi) = (i64::from(w), i64::from(h));
    for &(col, row) in edge_px {
        let p = picture_from_raster(col, row, h);
        if let EdgeDirection::Vanishing(_) = frame.dir {
            n_steps = raster_steps(frame.dir.at(p), opts.reach_px, &mut steps);
        }
        if supports(
            raw,
            wi,
            hi,
            i64::from(col),
            i64::from(row),
            &steps[..n_steps],
            opts.max_misses,
        ) {
            let (rho, t) = frame.dir.vote_coordinates(p, frame.axis, frame.radius);
            votes.push(Vote { rho, t, p });
        }
    }
    votes
}

/// Peaks of the offset histogram (1 px bins, summed over 3 neighbouring bins), with
/// non-maximum suppression over `peak_separation_px`.
fn vote_peaks(votes: &[Vote], rho_min: f64, bins: usize, opts: &LineOptions) -> Vec<f64> {
    let mut hist = vec![0u32; bins];
    for v in votes {
        let b = ((v.rho - rho_min).floor() as usize).min(bins - 1);
        hist[b] += 1;
    }
    let boxed: Vec<u32> = (0..bins)
        .map(|b| hist[b.saturating_sub(1)..(b + 2).min(bins)].iter().sum())
        .collect();
    let min_votes = opts.min_length_px.max(1.0) as u32;
    let sep = opts.peak_separation_px as usize;
    let mut peaks = Vec::new();
    for b in 0..bins {
        let v = boxed[b];
        if v < min_votes {
            continue;
        }
        let lo = b.saturating_sub(sep);
        let hi = (b + sep + 1).min(bins);
        // Strictly greater than earlier neighbours, at least as great as later ones: one peak
        // per plateau.
        let is_peak = (lo..b).all(|i| boxed[i] < v) && (b + 1..hi).all(|i| boxed[i] <= v);
        if is_peak {
            // Centre of mass of the three bins: the peak offset to a fraction of a pixel.
            let (mut s, mut m) = (0.0, 0.0);
            let lo = b.saturating_sub(1);
            for (i, &n) in hist.iter().enumerate().take((b + 2).min(bins)).skip(lo) {
                s += f64::from(n) * (i as f64 + 0.5);
                m += f64::from(n);
            }
            peaks.push(rho_min + s / m.max(1.0));
        }
    }
    peaks
}

fn lines_from_votes(
    votes: Vec<Vote>,
    k: EdgeAxis,
    frame: &VoteFrame,
    opts: &LineOptions,
) -> Vec<FittedLine> {
    if votes.is_empty() {
        return Vec::new();
    }
    let (lo, hi) = votes
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v.rho), hi.max(v.rho))
        });
    if !(lo.is_finite() && hi.is_finite()) || hi - lo > 1e6 {
        return Vec::new();
    }
    let rho_min = lo.floor() - 2.0;
    let bins = (hi - rho_min + 4.0).ceil() as usize + 1;
    let peaks = vote_peaks(&votes, rho_min, bins, opts);
    if peaks.is_empty() {
        return Vec::new();
    }
    // Each pixel joins its nearest peak within the band.
    let mut groups: Vec<Vec<Vote>> = vec![Vec::new(); peaks.len()];
    for v in votes {
        let i = peaks.partition_point(|&r| r < v.rho);
        let best = [i.wrapping_sub(1), i]
            .into_iter()
            .filter(|&j| j < peaks.len())
            .min_by(|&a, &b| {
                (peaks[a] - v.rho)
                    .abs()
                    .total_cmp(&(peaks[b] - v.rho).abs())
            });
        if let Some(j) = best {
            if (peaks[j] - v.rho).abs() <= opts.band_half_width_px {
                groups[j].push(v);
            }
        }
    }
    let mut out = Vec::new();
    let mut points = Vec::new();
    for mut g in groups {
        g.sort_by(|a, b| a.t.total_cmp(&b.t));
        let mut start = 0;
        for i in 1..=g.len() {
            if i == g.len() || g[i].t - g[i - 1].t > opts.max_gap_px {
                let run = &g[start..i];
                start = i;
                if run.is_empty() || run[run.len() - 1].t - run[0].t < opts.min_length_px {
                    continue;
                }
                points.clear();
                points.extend(run.iter().map(|v| v.p));
                let centroid = points.iter().fold(DVec2::ZERO, |a, p| a + *p) / points.len() as f64;
                let u = frame.dir.at(centroid);
                if let Some(line) = fit_segment(&points, k, u, opts.max_turn_deg) {
                    out.push(line);
                }
            }
        }
    }
    out
}

fn fit_segment(points: &[DVec2], k: EdgeAxis, u: DVec2, max_turn_deg: f64) -> Option<FittedLine> {
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

/// Refines lines that sit on a dark seam (the renderer draws ~1 px dark lines along block
/// edges between faces): the edge map's band is lopsided when the faces on the two sides differ
/// in brightness, so its centre can miss the seam by most of a pixel. A pixel within
/// `SEAM_SEARCH_PX` of the line is a seam pixel when it is darker, by at least
/// [`MIN_SEAM_CONTRAST`] gray levels, than both pixels `SEAM_SIDE_PX` away across the line (a
/// local test, so faces that change along the line do not matter). When seam pixels cover at
/// least half the line's length, the line is re-fitted by least squares on them, weighted by
/// their darkness. Other lines (a plain step, e.g. a silhouette against the background, whose
/// band is symmetric) are kept as they are.
pub fn refine_lines_on_seams(
    gray: &GrayImage,
    lines: &[FittedLine],
    _opts: &LineOptions,
) -> Vec<FittedLine> {
    let mut samples: Vec<(f64, f64, DVec2)> = Vec::new();
    let mut pts: Vec<DVec2> = Vec::new();
    let mut weights: Vec<f64> = Vec::new();
    lines
        .iter()
        .map(|l| {
            band_samples(gray, l, SEAM_SEARCH_PX, &mut samples);
            refine_one(gray, l, &samples, &mut pts, &mut weights).unwrap_or(*l)
        })
        .collect()
}

/// Minimum local darkness of a seam pixel, gray levels. The renderer's seams are 35 against a
/// background of 60 and faces of 100 and more; sensor noise (sigma 8) passes now and then, so
/// each pixel weighs only its darkness beyond three quarters of this value. Measured with
/// `blockworld bench vision`: 15 brings the mean vertex distance from 0.65 px (at 30) to 0.44 px.
pub const MIN_SEAM_CONTRAST: f64 = 15.0;
/// Seam pixels are looked for this close to the band's line, px.
const SEAM_SEARCH_PX: f64 = 2.5;
/// Seam pixels are not taken this close to a line's ends, px.
const SEAM_END_MARGIN_PX: f64 = 5.0;
/// A seam pixel is compared with the pixels this far away on either side, px.
const SEAM_SIDE_PX: f64 = 2.0;

/// Gray level at picture point `p` (nearest pixel), `None` outside the picture.
fn gray_at(gray: &GrayImage, p: DVec2) -> Option<f64> {
    let (w, h) = gray.dimensions();
    let (x, y) = (p.x.floor(), p.y.floor());
    if x < 0.0 || y < 0.0 || x >= f64::from(w) || y >= f64::from(h) {
        return None;
    }
    let row = h as usize - 1 - y as usize;
    Some(f64::from(gray.as_raw()[row * w as usize + x as usize]))
}

/// Pixels within `reach` px of the line, between its ends: `(offset, gray, point)`.
fn band_samples(gray: &GrayImage, l: &FittedLine, reach: f64, out: &mut Vec<(f64, f64, DVec2)>) {
    out.clear();
    let (w, h) = gray.dimensions();
    let raw = gray.as_raw();
    // Keep clear of the ends, where other lines' seams cross the band.
    let margin = (0.25 * l.length_px()).min(SEAM_END_MARGIN_PX);
    let (t0, t1) = (l.along_px(l.from_px) + margin, l.along_px(l.to_px) - margin);
    let n = l.direction.perp();
    let steep = l.direction.y.abs() >= l.direction.x.abs();
    // Walk rows (steep lines) or columns (flat lines) between the ends.
    let (a, b) = (l.from_px, l.to_px);
    let (lo, hi) = if steep {
        (a.y.min(b.y), a.y.max(b.y))
    } else {
        (a.x.min(b.x), a.x.max(b.x))
    };
    let slope_room = if steep {
        l.direction.y.abs()
    } else {
        l.direction.x.abs()
    };
    let half = (reach / slope_room.max(0.3)).ceil() as i64 + 1;
    let mut s = lo.floor() as i64;
    while (s as f64) <= hi.ceil() {
        let s_c = s as f64 + 0.5;
        // Where the line crosses this row/column.
        let other = if steep {
            l.centroid_px.x + (s_c - l.centroid_px.y) * l.direction.x / l.direction.y
        } else {
            l.centroid_px.y + (s_c - l.centroid_px.x) * l.direction.y / l.direction.x
        };
        let o = other.floor() as i64;
        for q in o - half..=o + half {
            let (x, y) = if steep { (q, s) } else { (s, q) };
            if x < 0 || y < 0 || x >= i64::from(w) || y >= i64::from(h) {
                continue;
            }
            let p = DVec2::new(x as f64 + 0.5, y as f64 + 0.5);
            let t = l.along_px(p);
            let d = n.dot(p - l.centroid_px);
            if d.abs() <= reach && t >= t0 && t <= t1 {
                let row = h as i64 - 1 - y;
                out.push((d, f64::from(raw[(row * i64::from(w) + x) as usize]), p));
            }
        }
        s += 1;
    }
}

fn refine_one(
    gray: &GrayImage,
    l: &FittedLine,
    samples: &[(f64, f64, DVec2)],
    pts: &mut Vec<DVec2>,
    weights: &mut Vec<f64>,
) -> Option<FittedLine> {
    let n = l.direction.perp();
    pts.clear();
    weights.clear();
    for &(_, g, p) in samples {
        let a = gray_at(gray, p + n * SEAM_SIDE_PX);
        let b = gray_at(gray, p - n * SEAM_SIDE_PX);
        let (Some(a), Some(b)) = (a, b) else { continue };
        let darkness = a.min(b) - g;
        if darkness >= MIN_SEAM_CONTRAST {
            pts.push(p);
            // Only the darkness beyond most of the threshold counts: noise that barely passes
            // the test weighs little next to a real seam.
            weights.push(darkness - 0.75 * MIN_SEAM_CONTRAST);
        }
    }
    // Seam pixels must cover at least half the line (counted along it, one per px).
    let mut along: Vec<i64> = pts.iter().map(|p| l.along_px(*p).round() as i64).collect();
    along.sort_unstable();
    along.dedup();
    let sampled = l.length_px() - 2.0 * (0.25 * l.length_px()).min(SEAM_END_MARGIN_PX);
    if (along.len() as f64) < 0.5 * sampled {
        return None;
    }
    let (c, mut dir) = fit_line_weighted(pts, weights)?;
    if dir.dot(l.direction) < 0.0 {
        dir = -dir;
    }
    if dir.dot(l.direction) < 0.99 {
        return None;
    }
    let project = |p: DVec2| c + dir * dir.dot(p - c);
    Some(FittedLine {
        centroid_px: c,
        direction: dir,
        from_px: project(l.from_px),
        to_px: project(l.to_px),
        ..*l
    })
}

/// Weighted total least squares: centroid and unit direction.
fn fit_line_weighted(points: &[DVec2], weights: &[f64]) -> Option<(DVec2, DVec2)> {
    let wsum: f64 = weights.iter().sum();
    if points.len() < 2 || wsum <= 0.0 {
        return None;
    }
    let c = points
        .iter()
        .zip(weights)
        .fold(DVec2::ZERO, |a, (p, w)| a + *p * *w)
        / wsum;
    let (mut sxx, mut sxy, mut syy) = (0.0, 0.0, 0.0);
    for (p, w) in points.iter().zip(weights) {
        let d = *p - c;
        sxx += w * d.x * d.x;
        sxy += w * d.x * d.y;
        syy += w * d.y * d.y;
    }
    if sxx + syy <= 0.0 {
        return None;
    }
    let angle = 0.5 * (2.0 * sxy).atan2(sxx - syy);
    Some((c, DVec2::new(angle.cos(), angle.sin())))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn edge_pixels_lists_every_nonzero_pixel_row_by_row_like_a_plain_scan() {
        let (w, h) = (21u32, 5u32);
        let raw: Vec<u8> = (0..w * h)
            .map(|i| u8::from(i % 7 == 0 || i % 11 == 3))
            .collect();
        let plain: Vec<(u32, u32)> = (0..h)
            .flat_map(|r| (0..w).map(move |c| (c, r)))
            .filter(|&(c, r)| raw[(r * w + c) as usize] != 0)
            .collect();
        assert!(plain.len() > 10);
        assert_eq!(edge_pixels(&raw, w), plain);
        assert!(edge_pixels(&[0; 64], 8).is_empty());
    }
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
