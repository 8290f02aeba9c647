//! Curved edges of the edge map (thesis Chapter VII: "with other kinds of blocks like pyramids
//! or circles, the parallelogram surface searching fails"). A round part's rims project to
//! ellipses; the straight-line finder ([`super::fit_lines`]) sees only pieces of them, where the
//! ellipse runs along a block direction for a while, and drops the rest. This step reports them
//! as curves instead, the way the exact drawing does (docs/formats.md "The exact line drawing":
//! `curved_lines`, chords of the curve):
//!
//! 1. **Residue**: the edge pixels farther than [`NEAR_LINE_PX`] from every fitted straight line
//!    are grouped into 8-connected pieces (bridging gaps up to [`BRIDGE_PX`]).
//! 2. **Chords found as lines**: a fitted line with residue at both ends whose own pixels and
//!    the residue within [`END_REACH_PX`] of its ends lie on one circle (RMS at most
//!    [`MAX_CIRCLE_RMS_PX`]) is a piece of a curve, not an edge: it joins the pieces it touches.
//!    A straight silhouette generator fails this test, since the rim bends away at its ends.
//! 3. **Curves**: a group of at least [`MIN_CURVE_PX`] pixels that bulges at least
//!    [`MIN_SAGITTA_PX`] from its best straight line is ordered by angle about its centroid (an
//!    arc of an ellipse is convex, so the order follows the arc), averaged into points about
//!    [`CHORD_PX`] apart, and kept when its pixels lie within [`MAX_OFF_CURVE_PX`] (RMS) of that
//!    polyline and it turns one way only.
//!
//! Block scenes leave only small blobs at junctions in the residue, so their drawings are
//! unchanged.

use super::lines::{fit_line_least_squares, picture_from_raster, FittedLine};
use super::votes::EdgeList;
use crate::drawing::LineDrawing;
use crate::geom::{bounds2, DMat3, DVec2, DVec3, UnionFind};
use image::GrayImage;

/// An edge pixel within this distance of a fitted straight segment belongs to it, px.
pub const NEAR_LINE_PX: f64 = 2.5;
/// Residue pixels this close (Chebyshev distance, px) belong to one piece.
pub const BRIDGE_PX: i64 = 2;
/// Residue within this distance of a line's end is the curve continuing there, px: far
/// enough that a rim bending away from a silhouette generator (radius of curvature about 30 px
/// at 512 x 480) departs from the generator's line by several pixels.
pub const END_REACH_PX: f64 = 15.0;
/// At most this RMS distance from one circle for a line to be a piece of a curve, px.
pub const MAX_CIRCLE_RMS_PX: f64 = 2.0;
/// A curve has at least this many edge pixels.
pub const MIN_CURVE_PX: usize = 40;
/// A curve departs at least this far from its best straight line, px.
pub const MIN_SAGITTA_PX: f64 = 2.0;
/// Distance between consecutive points of a reported curve, px (arc length, about).
pub const CHORD_PX: f64 = 8.0;
/// RMS distance of a curve's pixels from its polyline, at most, px.
pub const MAX_OFF_CURVE_PX: f64 = 1.5;

/// A chord of a curve may turn against the curve's sense by at most this, degrees.
pub const MAX_REVERSE_DEG: f64 = 6.0;

/// A chord of a curve turns by at most this, degrees: a rim seen at 512 x 480 turns by up to
/// about 20 degrees per [`CHORD_PX`] at the ends of its ellipse, a corner of blocks by more.
pub const MAX_TURN_DEG: f64 = 30.0;
/// A curve turns by at least this in all, degrees: the shortest rim arcs of the round family
/// seen at 512 x 480 turn by more than 50, the wobble of a noisy straight edge by about 6.
pub const MIN_TOTAL_TURN_DEG: f64 = 30.0;
/// Chords in a run that must turn by [`MIN_RUN_TURN_DEG`] together.
pub const STRAIGHT_RUN_CHORDS: usize = 4;
/// Least total turn of [`STRAIGHT_RUN_CHORDS`] chords in a row of a curve, degrees: an ellipse
/// of radius of curvature up to 600 px turns by more over 32 px.
pub const MIN_RUN_TURN_DEG: f64 = 3.0;

/// A curved edge found in a picture: a polyline whose points lie on the curve.
#[derive(Debug, Clone, PartialEq)]
pub struct CurvedEdge {
    /// The polyline's points in order along the curve, picture px.
    pub points_px: Vec<DVec2>,
    /// Whether the curve closes (the last point joins the first): a whole ellipse.
    pub closed: bool,
}

/// Splits `lines` (fitted on `edges`) into the straight edges and the curves of the picture
/// (steps 1-3 of the module doc): returns the curves and the lines that are not pieces of them.
pub fn find_curved_edges(
    edges: &GrayImage,
    lines: &[FittedLine],
) -> (Vec<CurvedEdge>, Vec<FittedLine>) {
    find_curved_edges_on(edges, &EdgeList::new(edges), lines)
}

/// [`find_curved_edges`] with the edge pixels of `edges` already listed.
pub(super) fn find_curved_edges_on(
    edges: &GrayImage,
    list: &EdgeList,
    lines: &[FittedLine],
) -> (Vec<CurvedEdge>, Vec<FittedLine>) {
    let (per_line, residue) = assign_pixels(edges, list, lines);
    let mut groups = residue_pieces(&residue, edges.width(), edges.height());
    let boxes: Vec<(DVec2, DVec2)> = groups
        .iter()
        .map(|g| bounds2(g.iter().copied()).unwrap_or_default())
        .collect();
    let mut candidates: Vec<(f64, usize, Vec<usize>)> = lines
        .iter()
        .enumerate()
        .filter_map(|(li, l)| {
            chord_of_curve(l, &per_line[li], &groups, &boxes)
                .map(|(rms, touched)| (rms, li, touched))
        })
        .collect();
    candidates.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    let mut sets = UnionFind::new(groups.len());
    let mut chord_lines = Vec::new();
    for (_, li, touched) in candidates {
        let mut roots: Vec<usize> = touched.iter().map(|&p| sets.find(p)).collect();
        roots.sort_unstable();
        roots.dedup();
        let mut merged = per_line[li].clone();
        for &r in &roots {
            merged.extend_from_slice(&groups[r]);
        }
        if curve_through(&merged).is_none() {
            continue;
        }
        for &r in &roots {
            sets.union(roots[0], r);
            groups[r].clear();
        }
        groups[sets.find(roots[0])] = merged;
        chord_lines.push(li);
    }
    let curves = groups.iter().filter_map(|g| curve_through(g)).collect();
    let straight = (0..lines.len())
        .filter(|li| !chord_lines.contains(li))
        .map(|li| lines[li])
        .collect();
    (curves, straight)
}

/// Squared distance from `p` to the segment of `line`, px² (compared with
/// [`NEAR_LINE_PX`] squared: the same order as the distance, without a square root per pixel).
fn distance_sq_to_line_px(line: &FittedLine, p: DVec2) -> f64 {
    let (a, b) = (line.along_px(line.from_px), line.along_px(line.to_px));
    let t = line.along_px(p);
    let beyond = (a.min(b) - t).max(t - a.max(b)).max(0.0);
    let across = line.signed_distance_px(p);
    across * across + beyond * beyond
}

/// Distance from `p` to the segment of `line`, px.
#[cfg(test)]
fn distance_to_line_px(line: &FittedLine, p: DVec2) -> f64 {
    distance_sq_to_line_px(line, p).sqrt()
}

/// For every edge pixel of `list` (in its order), the line within [`NEAR_LINE_PX`] nearest to
/// it (the lower index on a tie), or `u32::MAX` when none is. Each line looks only at the edge
/// pixels of its own band: row by row, those of the row's edge pixels inside
/// [`band_columns`], found by a binary search among the row's few, so the cost grows with the
/// lines' rows and the edge pixels near them, not with the pixels of the bands.
fn nearest_lines(edges: &GrayImage, list: &EdgeList, lines: &[FittedLine]) -> Vec<u32> {
    let h = edges.height();
    let near_sq = NEAR_LINE_PX * NEAR_LINE_PX;
    let mut best = vec![(f64::INFINITY, u32::MAX); list.px.len()];
    for (li, line) in lines.iter().enumerate() {
        let li = li as u32;
        let (y0, y1) = (
            line.from_px.y.min(line.to_px.y) - NEAR_LINE_PX,
            line.from_px.y.max(line.to_px.y) + NEAR_LINE_PX,
        );
        // Rows whose centre `h - row - 0.5` lies in [y0, y1], widened by one.
        let row_lo = (f64::from(h) - 0.5 - y1).floor().max(0.0) as u32;
        let row_hi = ((f64::from(h) - 0.5 - y0).ceil() + 1.0).clamp(0.0, f64::from(h)) as u32;
        for row in row_lo..row_hi {
            let y = f64::from(h) - f64::from(row) - 0.5;
            let Some((c0, c1)) = band_columns(line, y) else {
                continue;
            };
            let (lo, hi) = (
                list.row_start[row as usize] as usize,
                list.row_start[row as usize + 1] as usize,
            );
            let in_row = &list.px[lo..hi];
            let first = in_row.partition_point(|&(c, _)| i64::from(c) < c0);
            for (k, &(c, r)) in in_row.iter().enumerate().skip(first) {
                if i64::from(c) > c1 {
                    break;
                }
                let d = distance_sq_to_line_px(line, picture_from_raster(c, r, h));
                let b = &mut best[lo + k];
                if d <= near_sq && (d < b.0 || (d == b.0 && li < b.1)) {
                    *b = (d, li);
                }
            }
        }
    }
    best.into_iter().map(|(_, li)| li).collect()
}

/// The columns (inclusive, widened by one) whose pixel centres on the picture row at height
/// `y` may lie within [`NEAR_LINE_PX`] of `line`'s segment: inside the segment's extent grown by
/// the distance, and inside the strip of that half-width about the infinite line. A superset:
/// each pixel's distance is then measured.
fn band_columns(line: &FittedLine, y: f64) -> Option<(i64, i64)> {
    let (a, b, c, d) = (line.from_px, line.to_px, line.centroid_px, line.direction);
    let (mut x0, mut x1) = (a.x.min(b.x) - NEAR_LINE_PX, a.x.max(b.x) + NEAR_LINE_PX);
    if d.y.abs() > 1e-9 {
        // |d.x (y - c.y) - d.y (x - c.x)| <= NEAR_LINE_PX, solved for x.
        let mid = c.x + d.x * (y - c.y) / d.y;
        let half = NEAR_LINE_PX / d.y.abs();
        (x0, x1) = (x0.max(mid - half), x1.min(mid + half));
    } else if (d.x * (y - c.y)).abs() > NEAR_LINE_PX + 1.0 {
        return None;
    }
    (x0 <= x1).then(|| ((x0 - 0.5).floor() as i64 - 1, (x1 - 0.5).ceil() as i64 + 1))
}

/// The edge map `edges` without the pixels within [`NEAR_LINE_PX`] of any of `lines`: what
/// the straight lines found so far leave unexplained (a wedge's sloped edges, curves, blobs at
/// junctions).
pub fn residue_map(edges: &GrayImage, lines: &[FittedLine]) -> GrayImage {
    residue_map_on(edges, &EdgeList::new(edges), lines)
}

/// [`residue_map`] with the edge pixels of `edges` already listed.
pub(super) fn residue_map_on(
    edges: &GrayImage,
    list: &EdgeList,
    lines: &[FittedLine],
) -> GrayImage {
    let mut out = edges.clone();
    let w = edges.width() as usize;
    for (&(c, r), li) in list.px.iter().zip(nearest_lines(edges, list, lines)) {
        if li != u32::MAX {
            out.as_mut()[r as usize * w + c as usize] = 0;
        }
    }
    out
}

/// The edge pixels (picture px) of each line (those within [`NEAR_LINE_PX`] of it, each to its
/// nearest line) and the residue, the pixels near no line.
fn assign_pixels(
    edges: &GrayImage,
    list: &EdgeList,
    lines: &[FittedLine],
) -> (Vec<Vec<DVec2>>, Vec<DVec2>) {
    let h = edges.height();
    let mut per_line = vec![Vec::new(); lines.len()];
    let mut residue = Vec::new();
    for (&(c, r), li) in list.px.iter().zip(nearest_lines(edges, list, lines)) {
        let p = picture_from_raster(c, r, h);
        match per_line.get_mut(li as usize) {
            Some(own) => own.push(p),
            None => residue.push(p),
        }
    }
    (per_line, residue)
}

/// The residue grouped into pieces: pixels within [`BRIDGE_PX`] (Chebyshev) of each other
/// join one piece. Pieces in raster order of their first pixel.
fn residue_pieces(residue: &[DVec2], w: u32, h: u32) -> Vec<Vec<DVec2>> {
    let (w, h) = (w as i64, h as i64);
    let cell = |p: DVec2| ((p.x - 0.5) as i64, (h as f64 - 0.5 - p.y) as i64);
    let cells: Vec<(i64, i64)> = residue.iter().map(|p| cell(*p)).collect();
    // The residue comes in raster order; each row's cells are found by where the row starts.
    let mut row_start = vec![0usize; h as usize + 1];
    for &(_, r) in &cells {
        row_start[r as usize + 1] += 1;
    }
    for r in 0..h as usize {
        row_start[r + 1] += row_start[r];
    }
    let mut sets = UnionFind::new(residue.len());
    for (i, &(c, r)) in cells.iter().enumerate() {
        for rr in (r - BRIDGE_PX).max(0)..=(r + BRIDGE_PX).min(h - 1) {
            let row = &cells[row_start[rr as usize]..row_start[rr as usize + 1]];
            let from = row.partition_point(|&(cc, _)| cc < c - BRIDGE_PX);
            for (k, &(cc, _)) in row.iter().enumerate().skip(from) {
                if cc > c + BRIDGE_PX || cc >= w {
                    break;
                }
                sets.union(i, row_start[rr as usize] + k);
            }
        }
    }
    let mut by_root: Vec<Vec<DVec2>> = vec![Vec::new(); residue.len()];
    for (i, p) in residue.iter().enumerate() {
        by_root[sets.find(i)].push(*p);
    }
    by_root.into_iter().filter(|g| !g.is_empty()).collect()
}

/// Whether `line` (with its edge pixels `own`) is a chord of a curve (step 2): residue of
/// `pieces` at both ends, all on one circle with the line's pixels. The pieces it touches.
fn chord_of_curve(
    line: &FittedLine,
    own: &[DVec2],
    pieces: &[Vec<DVec2>],
    boxes: &[(DVec2, DVec2)],
) -> Option<(f64, Vec<usize>)> {
    let mut touched = Vec::new();
    let mut near_ends = Vec::new();
    for end in [line.from_px, line.to_px] {
        let mut found = false;
        for (i, piece) in pieces.iter().enumerate() {
            let (lo, hi) = boxes[i];
            if end.cmplt(lo - END_REACH_PX).any() || end.cmpgt(hi + END_REACH_PX).any() {
                continue;
            }
            let near: Vec<DVec2> = piece
                .iter()
                .copied()
                .filter(|p| p.distance(end) <= END_REACH_PX)
                .collect();
            if near.len() >= 3 {
                found = true;
                touched.push(i);
                near_ends.extend(near);
            }
        }
        if !found {
            return None;
        }
    }
    // The line's own pixels first, then the residue at its ends (copied only for the lines
    // that reach residue at both ends, a few per picture).
    let mut sample = own.to_vec();
    sample.extend(near_ends);
    let (_, _, rms) = fit_circle(&sample)?;
    (rms <= MAX_CIRCLE_RMS_PX).then_some((rms, touched))
}

/// Least-squares circle through `points` (the algebraic fit of Kasa: `x^2 + y^2 + D x + E y +
/// F = 0` solved linearly): centre, radius and the RMS distance of the points from the circle,
/// px. `None` for fewer than three points or collinear ones.
pub fn fit_circle(points: &[DVec2]) -> Option<(DVec2, f64, f64)> {
    if points.len() < 3 {
        return None;
    }
    let c0 = points.iter().fold(DVec2::ZERO, |a, p| a + *p) / points.len() as f64;
    let (mut ata, mut atb) = (DMat3::ZERO, DVec3::ZERO);
    for p in points {
        let q = *p - c0;
        let row = DVec3::new(q.x, q.y, 1.0);
        ata += DMat3::from_cols(row * row.x, row * row.y, row * row.z);
        atb += row * -(q.length_squared());
    }
    if ata.determinant().abs() < 1e-9 {
        return None;
    }
    let s = ata.inverse() * atb;
    let centre = DVec2::new(-s.x / 2.0, -s.y / 2.0);
    let r2 = centre.length_squared() - s.z;
    if r2.is_nan() || r2 <= 0.0 {
        return None;
    }
    let r = r2.sqrt();
    let ss: f64 = points
        .iter()
        .map(|p| ((*p - c0).distance(centre) - r).powi(2))
        .sum();
    Some((centre + c0, r, (ss / points.len() as f64).sqrt()))
}

/// The curve through `pixels` (step 3), if they form one.
fn curve_through(pixels: &[DVec2]) -> Option<CurvedEdge> {
    if pixels.len() < MIN_CURVE_PX {
        return None;
    }
    let (c, dir, _) = fit_line_least_squares(pixels)?;
    let sagitta = pixels
        .iter()
        .map(|p| dir.perp_dot(*p - c).abs())
        .fold(0.0, f64::max);
    if sagitta < MIN_SAGITTA_PX {
        return None;
    }
    let (centre, _, _) = fit_circle(pixels)?;
    let curve = order_by_angle(pixels, centre)?;
    (bends_smoothly(&curve) && rms_off_polyline(pixels, &curve) <= MAX_OFF_CURVE_PX)
        .then_some(curve)
}

/// `pixels` ordered by angle about `centre` and averaged in bins of about [`CHORD_PX`] of arc;
/// an arc starts after the largest angular gap, a curve with no gap wider than two bins closes.
fn order_by_angle(pixels: &[DVec2], centre: DVec2) -> Option<CurvedEdge> {
    let mean_r = pixels.iter().map(|p| p.distance(centre)).sum::<f64>() / pixels.len() as f64;
    if mean_r < CHORD_PX {
        return None;
    }
    let bin = CHORD_PX / mean_r;
    let tau = std::f64::consts::TAU;
    let mut polar: Vec<(f64, DVec2)> = pixels
        .iter()
        .map(|p| ((*p - centre).to_angle().rem_euclid(tau), *p))
        .collect();
    polar.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.x.total_cmp(&b.1.x)));
    let n = polar.len();
    let (gap, after) = (0..n)
        .map(|i| {
            (
                (polar[(i + 1) % n].0 - polar[i].0).rem_euclid(tau),
                (i + 1) % n,
            )
        })
        .fold((-1.0, 0), |best, g| if g.0 > best.0 { g } else { best });
    let start = polar[after].0;
    let mut sums: Vec<(DVec2, usize)> = Vec::new();
    for k in 0..n {
        let (a, p) = polar[(after + k) % n];
        let b = ((a - start).rem_euclid(tau) / bin) as usize;
        if sums.len() <= b {
            sums.resize(b + 1, (DVec2::ZERO, 0));
        }
        sums[b].0 += p;
        sums[b].1 += 1;
    }
    let points_px: Vec<DVec2> = sums
        .iter()
        .filter(|s| s.1 > 0)
        .map(|s| s.0 / s.1 as f64)
        .collect();
    (points_px.len() >= 5).then_some(CurvedEdge {
        points_px,
        closed: gap <= 2.0 * bin,
    })
}

/// Chords of `curve` as point pairs (closing chord included for a closed curve).
fn chords(curve: &CurvedEdge) -> Vec<(DVec2, DVec2)> {
    let p = &curve.points_px;
    let mut out: Vec<(DVec2, DVec2)> = p.windows(2).map(|w| (w[0], w[1])).collect();
    if curve.closed {
        out.push((p[p.len() - 1], p[0]));
    }
    out
}

/// RMS distance of `pixels` from the polyline of `curve`, px.
fn rms_off_polyline(pixels: &[DVec2], curve: &CurvedEdge) -> f64 {
    let segments = chords(curve);
    let ss: f64 = pixels
        .iter()
        .map(|p| {
            segments
                .iter()
                .map(|&(a, b)| {
                    let ab = b - a;
                    let t = ((*p - a).dot(ab) / ab.length_squared().max(1e-12)).clamp(0.0, 1.0);
                    p.distance_squared(a + ab * t)
                })
                .fold(f64::INFINITY, f64::min)
        })
        .sum();
    (ss / pixels.len() as f64).sqrt()
}

/// Whether `curve` bends like a smooth convex arc: no chord turns against the overall sense by
/// more than [`MAX_REVERSE_DEG`] (the averaged points wander by a fraction of a pixel where the
/// ellipse is flattest), none turns by more than [`MAX_TURN_DEG`] (a corner of two straight
/// edges), and no [`STRAIGHT_RUN_CHORDS`] chords in a row turn by less than
/// [`MIN_RUN_TURN_DEG`] together (a straight edge in another direction), and the whole turns
/// by at least [`MIN_TOTAL_TURN_DEG`] (not a noisy straight edge).
fn bends_smoothly(curve: &CurvedEdge) -> bool {
    let turns: Vec<f64> = chords(curve)
        .windows(2)
        .map(|w| (w[0].1 - w[0].0).angle_to(w[1].1 - w[1].0).to_degrees())
        .collect();
    let total = turns.iter().sum::<f64>();
    let sense = total.signum();
    let one_way = turns.iter().all(|t| t * sense >= -MAX_REVERSE_DEG);
    let no_corner = turns.iter().all(|t| t.abs() <= MAX_TURN_DEG);
    let no_straight_run = turns
        .windows(STRAIGHT_RUN_CHORDS - 1)
        .all(|w| w.iter().sum::<f64>().abs() >= MIN_RUN_TURN_DEG);
    total.abs() >= MIN_TOTAL_TURN_DEG && one_way && no_corner && no_straight_run
}

/// Appends `curves` to `drawing` as chains of lines flagged in `curved_lines` (the format of
/// the exact drawing, docs/formats.md "The exact line drawing") and recomputes codes and junctions.
pub fn add_curved_edges(drawing: &mut LineDrawing, curves: &[CurvedEdge]) {
    for curve in curves {
        let first = drawing.points.len();
        drawing.points.extend_from_slice(&curve.points_px);
        let n = curve.points_px.len();
        let ends = if curve.closed { n } else { n - 1 };
        for k in 0..ends {
            drawing.curved_lines.push(drawing.lines.len());
            drawing.lines.push([first + k, first + (k + 1) % n]);
        }
    }
    drawing.finalize();
}

#[cfg(test)]
mod tests {
    use super::*;
    use image::Luma;

    /// An edge map with the pixels within `half_width_px` of the curve `f(t)`, t in 0..1,
    /// sampled finely.
    fn band(w: u32, h: u32, half_width_px: f64, f: impl Fn(f64) -> DVec2) -> GrayImage {
        let samples: Vec<DVec2> = (0..=4000).map(|k| f(k as f64 / 4000.0)).collect();
        GrayImage::from_fn(w, h, |c, r| {
            let p = picture_from_raster(c, r, h);
            let near = samples.iter().any(|s| s.distance(p) <= half_width_px);
            Luma([u8::from(near)])
        })
    }

    fn ellipse(t: f64) -> DVec2 {
        let a = t * std::f64::consts::TAU;
        DVec2::new(100.0 + 60.0 * a.cos(), 80.0 + 35.0 * a.sin())
    }

    /// Distance from `p` to the ellipse of [`ellipse`], px (sampled).
    fn off_ellipse(p: DVec2) -> f64 {
        (0..4000)
            .map(|k| ellipse(k as f64 / 4000.0).distance(p))
            .fold(f64::INFINITY, f64::min)
    }

    /// Every edge pixel goes to the nearest segment within [`NEAR_LINE_PX`] (the lower index
    /// on a tie) and the others to none, as measuring every pixel against every segment says:
    /// segments at any slope (horizontal, vertical, steep, shallow, crossing, clipped by the
    /// border), on a map where every pixel is an edge.
    #[test]
    fn nearest_lines_matches_every_pixel_against_every_segment() {
        let (w, h) = (60u32, 50u32);
        let lines: Vec<FittedLine> = [
            (DVec2::new(3.2, 4.7), DVec2::new(55.1, 20.3)),
            (DVec2::new(10.0, 1.0), DVec2::new(14.0, 48.5)),
            (DVec2::new(-2.0, 30.0), DVec2::new(40.0, 30.0)),
            (DVec2::new(30.5, 49.8), DVec2::new(5.0, 0.2)),
            (DVec2::new(20.5, 10.0), DVec2::new(20.5, 40.0)),
            (
                DVec2::new(12.0, 22.0),
                DVec2::new(12.0, 22.0) + DVec2::new(1.0, 0.001) * 30.0,
            ),
        ]
        .into_iter()
        .map(|(a, b)| crate::vision::lines::test_segment(1, a, b))
        .collect();
        let edges = GrayImage::from_pixel(w, h, image::Luma([1]));
        let list = EdgeList::new(&edges);
        let got = nearest_lines(&edges, &list, &lines);
        let mut assigned = 0;
        for (&(c, r), &li) in list.px.iter().zip(&got) {
            let p = picture_from_raster(c, r, h);
            let mut want = (NEAR_LINE_PX, u32::MAX);
            for (k, l) in lines.iter().enumerate() {
                let d = distance_to_line_px(l, p);
                if d < want.0 || (d == want.0 && want.1 == u32::MAX) {
                    want = (d, k as u32);
                }
            }
            assert_eq!(li, want.1, "({c}, {r})");
            assigned += usize::from(li != u32::MAX);
        }
        assert!(assigned > 500 && assigned < list.px.len(), "{assigned}");
    }

    #[test]
    fn circle_fit_is_exact_on_a_circle_and_refuses_a_line() {
        let pts: Vec<DVec2> = (0..7)
            .map(|k| DVec2::new(3.0, -2.0) + DVec2::from_angle(k as f64 * 0.4) * 12.5)
            .collect();
        let (c, r, rms) = fit_circle(&pts).unwrap();
        assert!(c.distance(DVec2::new(3.0, -2.0)) < 1e-9 && (r - 12.5).abs() < 1e-9);
        assert!(rms < 1e-9);
        let line: Vec<DVec2> = (0..5)
            .map(|k| DVec2::new(k as f64, 2.0 * k as f64))
            .collect();
        assert!(fit_circle(&line).is_none());
    }

    /// A whole ellipse seen with no straight line fitted on it is one closed curve whose points
    /// lie on the ellipse within a pixel, added to a drawing as a chain flagged curved.
    #[test]
    fn an_ellipse_band_is_one_closed_curve_on_the_ellipse() {
        let edges = band(200, 160, 1.5, ellipse);
        let (curves, straight) = find_curved_edges(&edges, &[]);
        assert!(straight.is_empty());
        assert_eq!(curves.len(), 1, "{curves:?}");
        let c = &curves[0];
        assert!(c.closed && c.points_px.len() >= 30, "{}", c.points_px.len());
        for p in &c.points_px {
            assert!(off_ellipse(*p) < 1.0, "{p} off the ellipse");
        }
        let mut d = LineDrawing::default();
        add_curved_edges(&mut d, &curves);
        assert_eq!(d.lines.len(), c.points_px.len());
        assert_eq!(d.curved_lines, (0..d.lines.len()).collect::<Vec<_>>());
    }

    /// Straight edges in directions the line finder does not know (a turned block, a wedge's
    /// slope) and a corner of two of them are not curves: the checks that a curve bends
    /// smoothly are what tells them apart from a rim.
    #[test]
    fn a_straight_edge_and_a_corner_off_the_directions_are_not_curves() {
        let slope = |t: f64| DVec2::new(20.0 + 150.0 * t, 30.0 + 60.0 * t);
        let (curves, _) = find_curved_edges(&band(200, 160, 1.5, slope), &[]);
        assert!(curves.is_empty(), "{curves:?}");
        let corner = |t: f64| {
            if t < 0.5 {
                DVec2::new(30.0 + 160.0 * t, 40.0 + 100.0 * t)
            } else {
                DVec2::new(110.0 + 160.0 * (t - 0.5), 90.0 - 40.0 * (t - 0.5))
            }
        };
        let (curves, _) = find_curved_edges(&band(200, 160, 1.5, corner), &[]);
        assert!(curves.is_empty(), "{curves:?}");
    }

    /// A straight line fitted on a flat stretch of an ellipse is a chord of the curve and is
    /// absorbed; a line fitted elsewhere stays.
    #[test]
    fn a_line_fitted_on_an_ellipse_is_absorbed_into_the_curve() {
        let edges = band(200, 160, 1.5, ellipse);
        let on_rim = FittedLine {
            axis: crate::drawing::EdgeAxis::WorldX,
            centroid_px: DVec2::new(100.0, 115.0),
            direction: DVec2::X,
            from_px: DVec2::new(88.0, 115.0),
            to_px: DVec2::new(112.0, 115.0),
            support: 60,
            rms_px: 0.5,
        };
        let elsewhere = FittedLine {
            centroid_px: DVec2::new(100.0, 10.0),
            from_px: DVec2::new(80.0, 10.0),
            to_px: DVec2::new(120.0, 10.0),
            ..on_rim
        };
        let (curves, straight) = find_curved_edges(&edges, &[on_rim, elsewhere]);
        assert_eq!(curves.len(), 1);
        assert_eq!(straight, vec![elsewhere]);
    }
}
