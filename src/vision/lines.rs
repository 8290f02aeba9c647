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
pub(super) use crate::geom::gray_at;
use crate::geom::{floor_i64, gray_at_px, DVec2, DVec3};
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

/// One direction's vote coordinates (see [`EdgeDirection::vote_coordinates`]).
struct VoteFrame {
    dir: EdgeDirection,
    axis: DVec2,
    radius: f64,
}

/// The edge pixels of a binary map in raster order, with where each row's pixels start, so the
/// pixels near a line are found among its rows' few edge pixels (no raster-sized table). Listed
/// once per picture and shared by the line finder and the curve step.
pub(super) struct EdgeList {
    /// `(column, row)` of each edge pixel, row by row.
    pub(super) px: Vec<(u32, u32)>,
    /// `px[row_start[r]..row_start[r + 1]]` are row `r`'s pixels.
    pub(super) row_start: Vec<u32>,
}

impl EdgeList {
    /// The edge pixels (non-zero) of `edges`.
    pub(super) fn new(edges: &GrayImage) -> EdgeList {
        let px = edge_pixels(edges.as_raw(), edges.width());
        let mut row_start = vec![0u32; edges.height() as usize + 1];
        for &(_, r) in &px {
            row_start[r as usize + 1] += 1;
        }
        for r in 0..edges.height() as usize {
            row_start[r + 1] += row_start[r];
        }
        EdgeList { px, row_start }
    }
}

/// The `(column, row)` of every edge pixel (non-zero), row by row: found once and shared by
/// the three directions' votes. Eight pixels are tested at a time, since most are not edges,
/// and the non-zero bytes of a group are visited by their bits.
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
            let v = u64::from_le_bytes(c.try_into().expect("eight bytes"));
            if v == 0 {
                base += 8;
                continue;
            }
            // The lowest bit of each byte set where the byte is non-zero.
            let mut set = v | (v >> 4);
            set |= set >> 2;
            set |= set >> 1;
            set &= 0x0101_0101_0101_0101;
            while set != 0 {
                let i = set.trailing_zeros() as usize / 8;
                out.push(((base + i) as u32, row as u32));
                set &= set - 1;
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
    let mut linear = None;
    if let EdgeDirection::Parallel(u) = frame.dir {
        n_steps = raster_steps(u, opts.reach_px, &mut steps);
        linear = Some(LinearSteps::new(&steps[..n_steps], w, h));
    }
    let mut votes = Vec::with_capacity(edge_px.len());
    let (wi, hi) = (i64::from(w), i64::from(h));
    for &(col, row) in edge_px {
        if let EdgeDirection::Vanishing(_) = frame.dir {
            let p = picture_from_raster(col, row, h);
            n_steps = raster_steps(frame.dir.at(p), opts.reach_px, &mut steps);
        }
        let supported = match &linear {
            Some(l) if l.inside(col, row) => l.supports(raw, col, row, opts.max_misses),
            _ => supports(
                raw,
                wi,
                hi,
                i64::from(col),
                i64::from(row),
                &steps[..n_steps],
                opts.max_misses,
            ),
        };
        if supported {
            let p = picture_from_raster(col, row, h);
            let (rho, t) = frame.dir.vote_coordinates(p, frame.axis, frame.radius);
            votes.push(Vote { rho, t, p });
        }
    }
    votes
}

/// [`supports`] for one parallel direction with its steps turned into offsets in the raster,
/// for the pixels whose every checked neighbour lies inside the picture (all but a thin
/// border): no per-neighbour bounds test, the same answer (the misses are counted the same).
struct LinearSteps {
    /// `+-(drow * w + dcol)` for each step, both signs.
    offsets: [i64; 2 * MAX_REACH_PX],
    len: usize,
    w: i64,
    /// Columns `margin_col..w - margin_col` and rows `margin_row..h - margin_row` qualify.
    margin_col: i64,
    margin_row: i64,
    h: i64,
}

impl LinearSteps {
    fn new(steps: &[(i64, i64)], w: u32, h: u32) -> LinearSteps {
        let (w, h) = (i64::from(w), i64::from(h));
        let mut offsets = [0i64; 2 * MAX_REACH_PX];
        for (i, &(dc, dr)) in steps.iter().enumerate() {
            offsets[2 * i] = dr * w + dc;
            offsets[2 * i + 1] = -(dr * w + dc);
        }
        LinearSteps {
            offsets,
            len: 2 * steps.len(),
            w,
            margin_col: steps.iter().map(|s| s.0.abs()).max().unwrap_or(0),
            margin_row: steps.iter().map(|s| s.1.abs()).max().unwrap_or(0),
            h,
        }
    }

    fn inside(&self, col: u32, row: u32) -> bool {
        let (c, r) = (i64::from(col), i64::from(row));
        c >= self.margin_col
            && c + self.margin_col < self.w
            && r >= self.margin_row
            && r + self.margin_row < self.h
    }

    /// Counts every miss without stopping early (no branch on the map's data to mispredict).
    /// The default reach (3 px each way) has six offsets, counted unrolled.
    fn supports(&self, edges: &[u8], col: u32, row: u32, max_misses: u32) -> bool {
        let at = i64::from(row) * self.w + i64::from(col);
        let miss = |o: &i64| u32::from(edges[(at + o) as usize] == 0);
        let misses: u32 = match <&[i64; 6]>::try_from(&self.offsets[..self.len]) {
            Ok(six) => six.iter().map(miss).sum(),
            Err(_) => self.offsets[..self.len].iter().map(miss).sum(),
        };
        misses <= max_misses
    }
}

/// Peaks of the offset histogram (1 px bins, summed over 3 neighbouring bins), with
/// non-maximum suppression over `peak_separation_px`.
fn vote_peaks(votes: &[Vote], rho_min: f64, bins: usize, opts: &LineOptions) -> Vec<f64> {
    let mut hist = vec![0u32; bins];
    for v in votes {
        // `rho - rho_min` is at least 2, so truncating is flooring.
        let b = ((v.rho - rho_min) as usize).min(bins - 1);
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
    let band = opts.band_half_width_px;
    let (grouped, starts) = group_by_peak(&votes, &peaks, band, rho_min, bins);
    let mut out = Vec::new();
    let mut points = Vec::new();
    let mut along = SortAlong::default();
    for range in starts.windows(2) {
        let g = &grouped[range[0]..range[1]];
        let order = along.sort(g);
        let mut start = 0;
        for i in 1..=order.len() {
            if i == order.len() || order[i].0 - order[i - 1].0 > opts.max_gap_px {
                let run = &order[start..i];
                start = i;
                if run.is_empty() || run[run.len() - 1].0 - run[0].0 < opts.min_length_px {
                    continue;
                }
                points.clear();
                points.extend(run.iter().map(|&(_, j)| g[j as usize].p));
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

/// Each vote joins its nearest peak when within `band` of it: the votes of peak `j`, in their
/// original order, are `grouped[starts[j]..starts[j + 1]]` (one array filled by counting, not
/// one growing vector per peak).
fn group_by_peak(
    votes: &[Vote],
    peaks: &[f64],
    band: f64,
    rho_min: f64,
    bins: usize,
) -> (Vec<Vote>, Vec<usize>) {
    let below = PeaksBelow::new(peaks, rho_min, bins);
    let owner: Vec<usize> = votes
        .iter()
        .map(|v| {
            let i = below.count(peaks, v.rho);
            let best = [i.wrapping_sub(1), i]
                .into_iter()
                .filter(|&j| j < peaks.len())
                .min_by(|&a, &b| {
                    (peaks[a] - v.rho)
                        .abs()
                        .total_cmp(&(peaks[b] - v.rho).abs())
                });
            match best {
                Some(j) if (peaks[j] - v.rho).abs() <= band => j,
                _ => usize::MAX,
            }
        })
        .collect();
    let mut starts = vec![0usize; peaks.len() + 1];
    for &j in owner.iter().filter(|&&j| j != usize::MAX) {
        starts[j + 1] += 1;
    }
    for j in 0..peaks.len() {
        starts[j + 1] += starts[j];
    }
    let mut next = starts.clone();
    let mut grouped = vec![
        Vote {
            rho: 0.0,
            t: 0.0,
            p: DVec2::ZERO
        };
        starts[peaks.len()]
    ];
    for (v, &j) in votes.iter().zip(&owner) {
        if j != usize::MAX {
            grouped[next[j]] = *v;
            next[j] += 1;
        }
    }
    (grouped, starts)
}

/// Orders a peak's votes along the line: `(t, index)` pairs sorted by `t`, equal positions in
/// their original order (what a stable sort by `t` gives). Votes lie on a raster, a few per
/// pixel of length, so they are spread into 1 px buckets by counting (`t - t_min` truncated,
/// which keeps the order of `t`) and each bucket is put in order by insertion; a comparison sort
/// orders what does not fit that (non-finite or sparse positions).
#[derive(Default)]
struct SortAlong {
    keys: Vec<(f64, u32)>,
    spread: Vec<(f64, u32)>,
    starts: Vec<u32>,
}

impl SortAlong {
    fn sort(&mut self, g: &[Vote]) -> &[(f64, u32)] {
        self.keys.clear();
        self.keys
            .extend(g.iter().enumerate().map(|(i, v)| (v.t, i as u32)));
        let (lo, hi) = self
            .keys
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), k| {
                (lo.min(k.0), hi.max(k.0))
            });
        let n = self.keys.len();
        if n < 2 || !(lo.is_finite() && hi.is_finite()) || hi - lo > (4 * n + 64) as f64 {
            self.keys
                .sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            return &self.keys;
        }
        let buckets = (hi - lo) as usize + 1;
        self.starts.clear();
        self.starts.resize(buckets + 1, 0);
        for k in &self.keys {
            self.starts[(k.0 - lo) as usize + 1] += 1;
        }
        for b in 0..buckets {
            self.starts[b + 1] += self.starts[b];
        }
        self.spread.clear();
        self.spread.resize(n, (0.0, 0));
        for k in &self.keys {
            let slot = &mut self.starts[(k.0 - lo) as usize];
            self.spread[*slot as usize] = *k;
            *slot += 1;
        }
        insertion_sort_by_t(&mut self.spread);
        &self.spread
    }
}

/// Stable insertion sort by `t` (`total_cmp`): cheap on the bucketed votes, where every vote is
/// at most a bucket away from its place.
fn insertion_sort_by_t(keys: &mut [(f64, u32)]) {
    for i in 1..keys.len() {
        let mut j = i;
        while j > 0 && keys[j - 1].0.total_cmp(&keys[j].0).is_gt() {
            keys.swap(j - 1, j);
            j -= 1;
        }
    }
}

/// How many peaks lie below an offset (`partition_point(|r| r < rho)`), found from a table of
/// the count below each 1 px bin's start and a step or two from there instead of a binary
/// search per vote; the same count, since the peaks are sorted (checked; unsorted peaks, which
/// odd options could give, are searched).
struct PeaksBelow {
    /// Peaks below `rho_min + b` for each bin `b`; empty when the peaks are not sorted.
    at_bin: Vec<usize>,
    rho_min: f64,
}

impl PeaksBelow {
    fn new(peaks: &[f64], rho_min: f64, bins: usize) -> PeaksBelow {
        let mut at_bin = Vec::new();
        if peaks.windows(2).all(|p| p[0] <= p[1]) {
            let mut i = 0;
            at_bin.extend((0..bins).map(|b| {
                while i < peaks.len() && peaks[i] < rho_min + b as f64 {
                    i += 1;
                }
                i
            }));
        }
        PeaksBelow { at_bin, rho_min }
    }

    fn count(&self, peaks: &[f64], rho: f64) -> usize {
        if self.at_bin.is_empty() {
            return peaks.partition_point(|&r| r < rho);
        }
        let b = ((rho - self.rho_min) as usize).min(self.at_bin.len() - 1);
        let mut i = self.at_bin[b];
        while i > 0 && peaks[i - 1] >= rho {
            i -= 1;
        }
        while i < peaks.len() && peaks[i] < rho {
            i += 1;
        }
        i
    }
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
    let mut pts: Vec<DVec2> = Vec::new();
    let mut weights: Vec<f64> = Vec::new();
    lines
        .iter()
        .map(|l| {
            seam_pixels(gray, l, &mut pts, &mut weights);
            refine_one(l, &pts, &weights).unwrap_or(*l)
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

/// The seam pixels of `l` (see [`refine_lines_on_seams`]): the pixels within
/// `SEAM_SEARCH_PX` of the line, between its ends less a margin, darker by at least
/// [`MIN_SEAM_CONTRAST`] than both pixels `SEAM_SIDE_PX` away across it, into `pts`, each with
/// its weight (its darkness beyond three quarters of the contrast) in `weights`. A pixel centre
/// `(x + 0.5, y + 0.5)` moved by a fixed offset lands in the pixel `x + floor(0.5 + offset)`,
/// so the two side pixels are fixed raster steps from it, found once per line.
fn seam_pixels(gray: &GrayImage, l: &FittedLine, pts: &mut Vec<DVec2>, weights: &mut Vec<f64>) {
    pts.clear();
    weights.clear();
    let level = |x: i64, y: i64| gray_at_px(gray, x, y);
    let n = l.direction.perp();
    let side = |s: f64| (floor_i64(0.5 + n.x * s), floor_i64(0.5 + n.y * s));
    let (ahead, behind) = (side(SEAM_SIDE_PX), side(-SEAM_SIDE_PX));
    // Keep clear of the ends, where other lines' seams cross the band.
    let margin = (0.25 * l.length_px()).min(SEAM_END_MARGIN_PX);
    let (t0, t1) = (l.along_px(l.from_px) + margin, l.along_px(l.to_px) - margin);
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
    // Pixel centres `q + 0.5` within SEAM_SEARCH_PX of the line lie within this many px of its
    // crossing along the row/column; one more on each side for rounding.
    let reach_q = SEAM_SEARCH_PX / slope_room.max(0.3);
    let mut s = floor_i64(lo);
    while (s as f64) <= hi.ceil() {
        let s_c = s as f64 + 0.5;
        // Where the line crosses this row/column.
        let other = if steep {
            l.centroid_px.x + (s_c - l.centroid_px.y) * l.direction.x / l.direction.y
        } else {
            l.centroid_px.y + (s_c - l.centroid_px.x) * l.direction.y / l.direction.x
        };
        for q in floor_i64(other - reach_q - 0.5)..=floor_i64(other + reach_q - 0.5) + 1 {
            let (x, y) = if steep { (q, s) } else { (s, q) };
            let p = DVec2::new(x as f64 + 0.5, y as f64 + 0.5);
            let t = l.along_px(p);
            let d = n.dot(p - l.centroid_px);
            if d.abs() > SEAM_SEARCH_PX || t < t0 || t > t1 {
                continue;
            }
            let Some(g) = level(x, y) else { continue };
            let sides = (
                level(x + ahead.0, y + ahead.1),
                level(x + behind.0, y + behind.1),
            );
            let (Some(a), Some(b)) = sides else { continue };
            let darkness = a.min(b) - g;
            if darkness >= MIN_SEAM_CONTRAST {
                pts.push(p);
                // Only the darkness beyond most of the threshold counts: noise that barely
                // passes the test weighs little next to a real seam.
                weights.push(darkness - 0.75 * MIN_SEAM_CONTRAST);
            }
        }
        s += 1;
    }
}

fn refine_one(l: &FittedLine, pts: &[DVec2], weights: &[f64]) -> Option<FittedLine> {
    // Seam pixels must cover at least half the line (counted along it, one per px).
    let sampled = l.length_px() - 2.0 * (0.25 * l.length_px()).min(SEAM_END_MARGIN_PX);
    if (distinct_along_px(l, pts) as f64) < 0.5 * sampled {
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

/// How many distinct whole pixels along `l` (`along_px` rounded) the points `pts` fall on:
/// marked in a table over their range (they span the line's length), or sorted when the range
/// is out of proportion to their number.
fn distinct_along_px(l: &FittedLine, pts: &[DVec2]) -> usize {
    let mut along: Vec<i64> = pts.iter().map(|p| l.along_px(*p).round() as i64).collect();
    let (lo, hi) = along
        .iter()
        .fold((i64::MAX, i64::MIN), |(lo, hi), &a| (lo.min(a), hi.max(a)));
    let span = hi.saturating_sub(lo);
    if along.is_empty() || span < 0 || span as u64 > 4 * along.len() as u64 + 64 {
        along.sort_unstable();
        along.dedup();
        return along.len();
    }
    let mut seen = vec![false; span as usize + 1];
    along
        .iter()
        .filter(|&&a| !std::mem::replace(&mut seen[(a - lo) as usize], true))
        .count()
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
        // Any non-zero byte is an edge, whichever of its bits are set.
        let raw: Vec<u8> = (0..w * h)
            .map(|i| {
                u8::from(i % 7 == 0 || i % 11 == 3) * [1, 255, 0x80, 0x10, 0x02][i as usize % 5]
            })
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
    fn floor_i64_is_floor_everywhere_it_is_used() {
        let xs = [
            -2.5,
            -1.0,
            -0.999,
            -0.0,
            0.0,
            0.3,
            1.0,
            1.5,
            479.999,
            1e15 + 0.5,
            -1e15 - 0.5,
        ];
        for x in xs {
            assert_eq!(floor_i64(x), x.floor() as i64, "{x}");
        }
        for x in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY, 1e300, -1e300] {
            assert_eq!(floor_i64(x), x.floor() as i64, "{x}");
        }
        // It can fail: truncation alone is wrong below zero.
        assert_ne!(-0.5f64 as i64, floor_i64(-0.5));
    }

    /// A seeded pseudo-random 0/1 map of `w` x `h`, about one pixel in `one_in` set.
    fn speckle(w: u32, h: u32, one_in: u64) -> Vec<u8> {
        let mut x = 0x9E37_79B9_7F4A_7C15u64;
        (0..w * h)
            .map(|_| {
                x ^= x << 13;
                x ^= x >> 7;
                x ^= x << 17;
                u8::from(x % one_in != 0)
            })
            .collect()
    }

    #[test]
    fn the_offset_support_test_agrees_with_the_bounded_one_on_every_pixel() {
        let (w, h) = (37u32, 23u32);
        let raw = speckle(w, h, 4);
        let (mut agree, mut inside) = (0, 0);
        for u in [DVec2::Y, DVec2::new(0.866, 0.5), DVec2::new(-0.866, 0.5)] {
            let mut steps = [(0i64, 0i64); MAX_REACH_PX];
            let n = raster_steps(u, 3, &mut steps);
            let linear = LinearSteps::new(&steps[..n], w, h);
            for (row, col) in (0..h).flat_map(|r| (0..w).map(move |c| (r, c))) {
                if !linear.inside(col, row) {
                    continue;
                }
                inside += 1;
                let want = supports(
                    &raw,
                    w.into(),
                    h.into(),
                    col.into(),
                    row.into(),
                    &steps[..n],
                    1,
                );
                assert_eq!(linear.supports(&raw, col, row, 1), want, "{u} {col} {row}");
                agree += usize::from(want);
            }
            // The border, where a neighbour lies outside, is left to the bounded test.
            assert!(!linear.inside(0, 0) && linear.inside(w / 2, h / 2));
        }
        assert!(agree > 20 && agree < inside, "{agree} of {inside}");
    }

    #[test]
    fn votes_are_ordered_along_the_line_like_a_stable_sort() {
        let raw = speckle(64, 1, 3);
        let vote = |t: f64| Vote {
            rho: 0.0,
            t,
            p: DVec2::ZERO,
        };
        // Raster-like positions with many ties, a sparse set (comparison sort) and a NaN.
        let dense: Vec<Vote> = (0..300)
            .map(|i| vote(f64::from((i * 37) % 101) * 0.5 - 7.25 + f64::from(raw[i as usize % 64])))
            .collect();
        let sparse: Vec<Vote> = [5e6, -3.0, 1e7, -3.0, 0.5].map(vote).to_vec();
        let odd: Vec<Vote> = [2.0, f64::NAN, 1.0, 2.0].map(vote).to_vec();
        let mut along = SortAlong::default();
        for g in [&dense, &sparse, &odd, &Vec::new()] {
            let mut want: Vec<(f64, u32)> =
                g.iter().enumerate().map(|(i, v)| (v.t, i as u32)).collect();
            want.sort_by(|a, b| a.0.total_cmp(&b.0));
            let got = along.sort(g);
            assert_eq!(got.len(), want.len());
            for (a, b) in got.iter().zip(&want) {
                assert!(a.0.to_bits() == b.0.to_bits() && a.1 == b.1, "{got:?}");
            }
        }
        // It can fail: the insertion pass is what orders a bucket.
        let mut keys = vec![(1.5, 0), (1.25, 1), (1.5, 2)];
        insertion_sort_by_t(&mut keys);
        assert_eq!(keys, vec![(1.25, 1), (1.5, 0), (1.5, 2)]);
    }

    #[test]
    fn distinct_pixels_along_a_line_are_counted_once() {
        let l = FittedLine {
            axis: EdgeAxis::Vertical,
            centroid_px: DVec2::new(10.0, 0.0),
            direction: DVec2::Y,
            from_px: DVec2::new(10.0, -50.0),
            to_px: DVec2::new(10.0, 50.0),
            support: 0,
            rms_px: 0.0,
        };
        // Several points per pixel along the line, on both sides of it.
        let pts: Vec<DVec2> = (0..90)
            .map(|i| DVec2::new(9.0 + f64::from(i % 3), f64::from(i / 3) * 0.75 - 20.0))
            .collect();
        let mut plain: Vec<i64> = pts.iter().map(|p| l.along_px(*p).round() as i64).collect();
        plain.sort_unstable();
        plain.dedup();
        assert_eq!(distinct_along_px(&l, &pts), plain.len());
        assert!(plain.len() < pts.len());
        // Far apart (the sorted path) and none.
        let far = [
            DVec2::new(10.0, -1e6),
            DVec2::new(10.0, 1e6),
            DVec2::new(10.0, 1e6),
        ];
        assert_eq!(distinct_along_px(&l, &far), 2);
        assert_eq!(distinct_along_px(&l, &[]), 0);
    }

    #[test]
    fn peaks_below_counts_like_a_binary_search() {
        let peaks = [2.25, 3.0, 3.5, 9.75, 14.0];
        let below = PeaksBelow::new(&peaks, 0.0, 20);
        for i in 0..=200 {
            let rho = f64::from(i) * 0.0625 + 0.01 * f64::from(i % 3);
            let want = peaks.partition_point(|&r| r < rho);
            assert_eq!(below.count(&peaks, rho), want, "{rho}");
        }
        // Exactly on a peak and just below one.
        assert_eq!(below.count(&peaks, 3.0), 1);
        assert_eq!(below.count(&peaks, 2.999_999), 1);
        // Unsorted peaks fall back to the search itself.
        let odd = [5.0, 2.0, 8.0];
        let below = PeaksBelow::new(&odd, 0.0, 10);
        assert!(below.at_bin.is_empty());
        assert_eq!(below.count(&odd, 6.0), odd.partition_point(|&r| r < 6.0));
    }

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
