//! Step 3 of the vision front end: vertices where fitted lines meet, and the line drawing with
//! each vertex's six-bit code and junction class (Chapter IV "Six-Bit Coding Method", Chapter V;
//! Chapter VI: "A vertex is found by solving the equations of two lines").
//!
//! A segment's end is joined to another line when the two lines' intersection lies within
//! `join_radius_px` of that end (the edge map's band makes a segment stop a few pixels short of
//! the true corner) and within the other segment's extent (plus the same slack). Intersections
//! that share a segment end, or lie within `merge_radius_px` of each other, are one vertex,
//! placed at the point nearest (in least squares) to all its lines. A vertex on the interior of
//! another line splits it there: that is how the thesis's collinear "T" appears (Ch. V,
//! Figure 5.1). An end joined to nothing is a vertex of its own (junction "end").

use super::lines::FittedLine;
use crate::drawing::{EdgeAxis, LineDrawing};
use crate::geom::{DVec2, UnionFind};

/// Options of the vertex finder, in picture pixels.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VertexOptions {
    /// A segment end joins a line whose intersection lies this close to it. Default 7.0: twice
    /// the 3.5 px by which the edge map's band ends a segment short of a 60° corner
    /// (docs/vision.md "Tolerances").
    pub join_radius_px: f64,
    /// Junction points closer than this are merged. Default 3.0: five times the 0.6 px by which
    /// three fitted lines through one corner miss each other, a seventh of the shortest edge
    /// (docs/vision.md "Tolerances").
    pub merge_radius_px: f64,
    /// A vertex this close to another line's interior splits that line. Default 2.0.
    pub on_line_px: f64,
}

impl Default for VertexOptions {
    fn default() -> Self {
        VertexOptions {
            join_radius_px: 7.0,
            merge_radius_px: 3.0,
            on_line_px: 2.0,
        }
    }
}

/// Intersection of the infinite lines of `a` and `b`; `None` when (nearly) parallel.
pub(super) fn intersect(a: &FittedLine, b: &FittedLine) -> Option<DVec2> {
    let den = a.direction.perp_dot(b.direction);
    if den.abs() < 0.05 {
        return None;
    }
    let t = (b.centroid_px - a.centroid_px).perp_dot(b.direction) / den;
    Some(a.centroid_px + a.direction * t)
}

/// The point nearest in least squares to all `lines` (by index into `all`); the mean of
/// `fallback` when the lines are (nearly) parallel.
fn nearest_point(all: &[FittedLine], lines: &[usize], fallback: &[DVec2]) -> DVec2 {
    let (mut a11, mut a12, mut a22, mut b1, mut b2) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for &i in lines {
        let n = all[i].direction.perp();
        let c = n.dot(all[i].centroid_px);
        a11 += n.x * n.x;
        a12 += n.x * n.y;
        a22 += n.y * n.y;
        b1 += n.x * c;
        b2 += n.y * c;
    }
    let det = a11 * a22 - a12 * a12;
    if det.abs() > 1e-6 {
        DVec2::new((b1 * a22 - b2 * a12) / det, (a11 * b2 - a12 * b1) / det)
    } else {
        fallback.iter().fold(DVec2::ZERO, |s, p| s + *p) / fallback.len().max(1) as f64
    }
}

/// One junction candidate: an intersection near the end `end` (0 or 1) of line `line`.
#[derive(Clone, Copy)]
struct Candidate {
    line: usize,
    end: usize,
    other: usize,
    p: DVec2,
}

/// Builds the line drawing of `lines` (picture px): vertices at joined ends and intersections,
/// lines split at vertices on their interior, then [`LineDrawing::finalize`] computes each
/// vertex's six-bit code (Chapter IV bit order) and junction class. Deterministic.
pub fn find_vertices(lines: &[FittedLine], opts: &VertexOptions) -> LineDrawing {
    let joined = join_sloped_ends(lines, opts);
    let kept = drop_junction_blobs(&joined, opts);
    build_drawing(&kept, opts)
}

/// Longest reach of [`join_sloped_ends`], in join radii.
const MAX_SLOPED_REACH_JOIN_RADII: f64 = 4.0;

/// Joins the ends of lines in a direction other than the block axes (a trapezoidal block's
/// sloped edges, Figure 7.1) to the block-axis line they meet. Such a line is fitted to the
/// edge pixels no block-axis line explains, so near a junction it loses the pixels inside the
/// other line's band, a stretch that grows as `1 / sin` of the angle between the two (a slope
/// 30 degrees off the vertical loses about 10 px), and the block-axis line may run on over
/// them. Each end is moved to the nearest intersection with a block-axis line within
/// `join_radius_px / sin(angle)` (at most [`MAX_SLOPED_REACH_JOIN_RADII`] join radii) beyond
/// it, and every block-axis line through that corner that runs on past it, by less than the
/// same reach, on the sloped line's side, is cut there. Block-axis lines alone pass
/// unchanged.
fn join_sloped_ends(lines: &[FittedLine], opts: &VertexOptions) -> Vec<FittedLine> {
    let mut out = lines.to_vec();
    let is_axis = |l: &FittedLine| EdgeAxis::BLOCK_AXES.contains(&l.axis);
    for i in 0..out.len() {
        if is_axis(&out[i]) {
            continue;
        }
        for e in 0..2 {
            let s = out[i];
            let (end, other_end) = if e == 0 {
                (s.from_px, s.to_px)
            } else {
                (s.to_px, s.from_px)
            };
            let outward = (end - other_end).normalize_or_zero();
            let best = out
                .iter()
                .filter(|l| is_axis(l))
                .filter_map(|l| {
                    let x = intersect(&s, l)?;
                    let reach = sloped_reach_px(l, &s, opts);
                    let beyond = (x - end).dot(outward);
                    let (t, t0, t1) = (l.along_px(x), l.along_px(l.from_px), l.along_px(l.to_px));
                    let on_l = t >= t0 - opts.join_radius_px && t <= t1 + opts.join_radius_px;
                    let near = beyond >= -opts.join_radius_px && beyond <= reach && on_l;
                    near.then_some((x.distance(end), x))
                })
                .min_by(|a, b| a.0.total_cmp(&b.0));
            let Some((_, x)) = best else {
                continue;
            };
            if e == 0 {
                out[i].from_px = x;
            } else {
                out[i].to_px = x;
            }
            cut_axis_lines_at(&mut out, &s, x, other_end, opts);
        }
    }
    out
}

/// How far beyond a sloped line's end `s` its corner with the block-axis line `l` is looked
/// for, px: `join_radius_px / sin(angle)`, at most [`MAX_SLOPED_REACH_JOIN_RADII`] join radii.
fn sloped_reach_px(l: &FittedLine, s: &FittedLine, opts: &VertexOptions) -> f64 {
    let sin = l.direction.perp_dot(s.direction).abs().max(1e-9);
    (opts.join_radius_px / sin).min(MAX_SLOPED_REACH_JOIN_RADII * opts.join_radius_px)
}

/// Cuts at the corner `x` the block-axis lines meeting the sloped line `s` there that run on
/// over the sloped line's lost pixels (towards `other_end`, its other end); see
/// [`join_sloped_ends`].
fn cut_axis_lines_at(
    out: &mut [FittedLine],
    s: &FittedLine,
    x: DVec2,
    other_end: DVec2,
    opts: &VertexOptions,
) {
    let is_axis = |l: &FittedLine| EdgeAxis::BLOCK_AXES.contains(&l.axis);
    // Cut the block-axis lines meeting there that run on over the sloped line's lost
    // pixels.
    for l in out.iter_mut().filter(|l| is_axis(l)) {
        let Some(xj) = intersect(s, l).filter(|p| p.distance(x) <= opts.merge_radius_px) else {
            continue;
        };
        let reach = sloped_reach_px(l, s, opts);
        let (from, to) = (l.from_px, l.to_px);
        for (run_end, other) in [(from, to), (to, from)] {
            let past = run_end.distance(xj);
            let towards_slope = (run_end - xj).dot(other_end - xj) > 0.0;
            // The line runs on through the corner: the rest of it, beyond the corner,
            // is longer than the run to cut (and than a join radius).
            let rest = (xj - other).dot((run_end - other).normalize_or_zero());
            let through = rest > past.max(opts.join_radius_px);
            if past > 0.0 && past < reach && towards_slope && through {
                if run_end == from {
                    l.from_px = xj;
                } else {
                    l.to_px = xj;
                }
            }
        }
    }
}

/// Drops short segments that sit inside a junction of other lines: shorter than twice the join
/// radius, with two other (non-parallel) lines meeting within the join radius of its midpoint.
/// Under sensor noise the edge pixels at an arrow or fork junction can line up into such a
/// stub, which would pull the vertex off the corner.
fn drop_junction_blobs(lines: &[FittedLine], opts: &VertexOptions) -> Vec<FittedLine> {
    let inside_junction = |i: usize| {
        let s = &lines[i];
        if s.length_px() >= 2.0 * opts.join_radius_px {
            return false;
        }
        let mid = (s.from_px + s.to_px) / 2.0;
        let near = |l: &FittedLine| {
            l.signed_distance_px(mid).abs() <= opts.join_radius_px && l.length_px() > s.length_px()
        };
        let others: Vec<&FittedLine> = lines
            .iter()
            .enumerate()
            .filter(|&(j, l)| j != i && l.axis != s.axis && near(l))
            .map(|(_, l)| l)
            .collect();
        others.iter().enumerate().any(|(a, la)| {
            others[a + 1..].iter().any(|lb| {
                la.axis != lb.axis
                    && intersect(la, lb).is_some_and(|p| p.distance(mid) <= opts.join_radius_px)
            })
        })
    };
    (0..lines.len())
        .filter(|&i| !inside_junction(i))
        .map(|i| lines[i])
        .collect()
}

/// Builds the drawing from the kept lines (see [`find_vertices`]).
fn build_drawing(lines: &[FittedLine], opts: &VertexOptions) -> LineDrawing {
    let cands = end_candidates(lines, opts);
    let (vertex_of, members) = group_candidates(lines.len(), &cands, opts);
    let mut points: Vec<DVec2> = members
        .iter()
        .map(|(ls, ps)| nearest_point(lines, ls, ps))
        .collect();
    add_crossings(lines, &mut points, opts);
    let on_line = attach_vertices(lines, &cands, &vertex_of, &mut points, opts);
    compact(points, lines_between_vertices(on_line))
}

/// Step 1 of [`build_drawing`]: candidates, the intersections near a segment end and on (or
/// near) the other segment.
fn end_candidates(lines: &[FittedLine], opts: &VertexOptions) -> Vec<Candidate> {
    let mut cands: Vec<Candidate> = Vec::new();
    for (i, a) in lines.iter().enumerate() {
        for (j, b) in lines.iter().enumerate() {
            if i == j {
                continue;
            }
            let Some(p) = intersect(a, b) else { continue };
            let tb = b.along_px(p);
            let (b0, b1) = (b.along_px(b.from_px), b.along_px(b.to_px));
            if tb < b0 - opts.join_radius_px || tb > b1 + opts.join_radius_px {
                continue;
            }
            for (e, q) in [a.from_px, a.to_px].into_iter().enumerate() {
                if q.distance(p) <= opts.join_radius_px {
                    cands.push(Candidate {
                        line: i,
                        end: e,
                        other: j,
                        p,
                    });
                }
            }
        }
    }
    cands
}

/// The lines and candidate points of one vertex.
type VertexMembers = (Vec<usize>, Vec<DVec2>);

/// Steps 2 and 3 of [`build_drawing`]: candidates sharing a segment end, or close together, are
/// one vertex. Returns each candidate's vertex and each vertex's lines and candidate points.
fn group_candidates(
    line_count: usize,
    cands: &[Candidate],
    opts: &VertexOptions,
) -> (Vec<usize>, Vec<VertexMembers>) {
    let mut sets = UnionFind::new(cands.len());
    let mut by_end: Vec<Option<usize>> = vec![None; line_count * 2];
    for (ci, c) in cands.iter().enumerate() {
        let key = c.line * 2 + c.end;
        match by_end[key] {
            Some(first) => sets.union(first, ci),
            None => by_end[key] = Some(ci),
        }
    }
    for a in 0..cands.len() {
        for b in a + 1..cands.len() {
            if cands[a].p.distance(cands[b].p) <= opts.merge_radius_px {
                sets.union(a, b);
            }
        }
    }
    let mut root_to_vertex: Vec<Option<usize>> = vec![None; cands.len()];
    let mut members: Vec<VertexMembers> = Vec::new();
    let mut vertex_of = Vec::with_capacity(cands.len());
    for (ci, cand) in cands.iter().enumerate() {
        let r = sets.find(ci);
        let v = *root_to_vertex[r].get_or_insert_with(|| {
            members.push((Vec::new(), Vec::new()));
            members.len() - 1
        });
        vertex_of.push(v);
        let (ls, ps) = &mut members[v];
        for l in [cand.line, cand.other] {
            if !ls.contains(&l) {
                ls.push(l);
            }
        }
        ps.push(cand.p);
    }
    (vertex_of, members)
}

/// Step 3b of [`build_drawing`]: two lines passing through each other away from their ends (an
/// X junction, e.g. where the cracks between four flush blocks meet) are a vertex too.
fn add_crossings(lines: &[FittedLine], points: &mut Vec<DVec2>, opts: &VertexOptions) {
    for (i, a) in lines.iter().enumerate() {
        for b in &lines[i + 1..] {
            let Some(p) = intersect(a, b) else { continue };
            let inside = |l: &FittedLine| {
                let t = l.along_px(p);
                t > l.along_px(l.from_px) + opts.join_radius_px
                    && t < l.along_px(l.to_px) - opts.join_radius_px
            };
            if inside(a) && inside(b) && points.iter().all(|q| q.distance(p) > opts.merge_radius_px)
            {
                points.push(p);
            }
        }
    }
}

/// Step 4 of [`build_drawing`]: each line's vertices with their positions along it, at its
/// ends (the candidate of that end, or a new free end) and on its interior.
fn attach_vertices(
    lines: &[FittedLine],
    cands: &[Candidate],
    vertex_of: &[usize],
    points: &mut Vec<DVec2>,
    opts: &VertexOptions,
) -> Vec<Vec<(f64, usize)>> {
    let mut on_line: Vec<Vec<(f64, usize)>> = vec![Vec::new(); lines.len()];
    let mut end_vertex: Vec<Option<usize>> = vec![None; lines.len() * 2];
    for (c, &v) in cands.iter().zip(vertex_of) {
        end_vertex[c.line * 2 + c.end] = Some(v);
    }
    for (li, l) in lines.iter().enumerate() {
        for (e, end) in [l.from_px, l.to_px].into_iter().enumerate() {
            let v = match end_vertex[li * 2 + e] {
                Some(v) => v,
                None => {
                    points.push(end);
                    points.len() - 1
                }
            };
            end_vertex[li * 2 + e] = Some(v);
            on_line[li].push((l.along_px(points[v]), v));
        }
    }
    for (li, l) in lines.iter().enumerate() {
        let (t0, t1) = (l.along_px(l.from_px), l.along_px(l.to_px));
        for (v, p) in points.iter().enumerate() {
            if on_line[li].iter().any(|&(_, w)| w == v) {
                continue;
            }
            let t = l.along_px(*p);
            if l.signed_distance_px(*p).abs() <= opts.on_line_px && t > t0 && t < t1 {
                on_line[li].push((t, v));
            }
        }
    }
    on_line
}

/// Step 5 of [`build_drawing`]: the drawing's lines, between consecutive vertices along each
/// fitted line.
fn lines_between_vertices(mut on_line: Vec<Vec<(f64, usize)>>) -> Vec<[usize; 2]> {
    let mut drawing_lines: Vec<[usize; 2]> = Vec::new();
    for vs in &mut on_line {
        vs.sort_by(|a, b| a.0.total_cmp(&b.0));
        for pair in vs.windows(2) {
            let (a, b) = (pair[0].1, pair[1].1);
            let key = [a.min(b), a.max(b)];
            if a != b && !drawing_lines.contains(&key) {
                drawing_lines.push(key);
            }
        }
    }
    drawing_lines
}

/// Drops points no line uses and finalizes the drawing.
fn compact(points: Vec<DVec2>, lines: Vec<[usize; 2]>) -> LineDrawing {
    let mut used = vec![usize::MAX; points.len()];
    let mut kept = Vec::new();
    for &[a, b] in &lines {
        for v in [a, b] {
            if used[v] == usize::MAX {
                used[v] = kept.len();
                kept.push(points[v]);
            }
        }
    }
    let mut d = LineDrawing {
        points: kept,
        lines: lines.iter().map(|&[a, b]| [used[a], used[b]]).collect(),
        ..Default::default()
    };
    d.finalize();
    d
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::drawing::{EdgeAxis, Junction};

    use crate::vision::lines::test_segment as seg;

    #[test]
    fn three_short_segments_meet_in_a_fork_with_code_22() {
        let o = DVec2::new(100.0, 100.0);
        let r = DVec2::new(0.866, 0.5);
        let l = DVec2::new(-0.866, 0.5);
        // Each stops 3 px short of the corner, as edge-map bands do.
        let lines = [
            seg(0, o - DVec2::Y * 40.0, o - DVec2::Y * 3.0),
            seg(1, o + r * 3.0, o + r * 40.0),
            seg(2, o + l * 3.0, o + l * 40.0),
        ];
        let d = find_vertices(&lines, &VertexOptions::default());
        assert_eq!(d.points.len(), 4);
        assert_eq!(d.lines.len(), 3);
        let centre = d
            .points
            .iter()
            .position(|p| p.distance(o) < 1e-6)
            .expect("fork found");
        // down + left-up + right-up = 2 + 4 + 16.
        assert_eq!(d.codes[centre].0, 22);
        assert_eq!(d.junctions[centre], Junction::Fork);
    }

    #[test]
    fn a_stem_ending_on_a_bar_makes_a_t() {
        let bar = seg(1, DVec2::new(0.0, 0.0), DVec2::new(86.6, 50.0));
        let foot = DVec2::new(43.3, 25.0);
        let stem = seg(0, foot + DVec2::Y * 4.0, foot + DVec2::Y * 40.0);
        let d = find_vertices(&[bar, stem], &VertexOptions::default());
        assert_eq!(d.lines.len(), 3, "{d:?}");
        let t = d
            .points
            .iter()
            .position(|p| p.distance(foot) < 1e-6)
            .expect("T found");
        assert_eq!(d.junctions[t], Junction::T);
        assert_eq!(
            d.junctions[t].thesis_class(),
            crate::drawing::ThesisClass::T
        );
    }

    /// A wedge's ridge corner as vision fits it: the sloped edge, 30 degrees off the vertical,
    /// stops 11 px short of the corner (its pixels there lie in the vertical line's band) and
    /// the vertical line runs 11 px on over them. The sloped end is joined to the corner and
    /// the run cut, so the corner is one vertex of three lines and no stub is left; without
    /// the join the drawing keeps both faults.
    #[test]
    fn a_sloped_edge_short_of_its_corner_is_joined_and_the_overrun_cut() {
        let c = DVec2::new(100.0, 100.0);
        let down = DVec2::new(0.5, -0.866);
        let mut slope = seg(0, c + down * 11.0, c + down * 150.0);
        slope.axis = EdgeAxis::TRAPEZOID_SLOPES[1];
        let lines = [
            seg(0, c + DVec2::Y * 110.0, c - DVec2::Y * 11.0),
            seg(1, c, c + DVec2::new(-0.866, 0.5) * 100.0),
            slope,
        ];
        let opts = VertexOptions::default();
        let far = c + down * 150.0;
        // The corner's lines, and whether one of them is the sloped edge.
        let corner_of = |d: &LineDrawing| {
            let k = d.points.iter().position(|p| p.distance(c) < 0.5)?;
            let at: Vec<&[usize; 2]> = d.lines.iter().filter(|l| l.contains(&k)).collect();
            let sloped = at
                .iter()
                .any(|l| l.iter().any(|&m| d.points[m].distance(far) < 1e-6));
            Some((at.len(), sloped))
        };
        let d = find_vertices(&lines, &opts);
        assert_eq!(corner_of(&d), Some((3, true)), "{d:?}");
        assert!(d
            .points
            .iter()
            .all(|p| p.y > c.y - 1.0 || p.distance(far) < 1e-6));
        let unjoined = build_drawing(&drop_junction_blobs(&lines, &opts), &opts);
        assert_eq!(corner_of(&unjoined), Some((3, false)), "{unjoined:?}");
        // Block-axis lines alone pass unchanged.
        assert_eq!(join_sloped_ends(&lines[..2], &opts), lines[..2].to_vec());
    }
}
