//! From classified pieces to a [`LineDrawing`]: coincident pieces are kept once, line ends
//! closer than the snap distance become one point, and a line is split wherever another line
//! ends on its interior, which makes the thesis's collinear "T" junctions (Chapter V,
//! Figure 5.1).

use super::classify::{join_pieces, reclassify, Piece};
use super::geometry::SceneGeometry;
use super::TruthTolerances;
use crate::camera::Projector;
use crate::drawing::{EdgeRef, LineDrawing};
use crate::geom::{DVec2, UnionFind};

/// Two coincident pieces whose depths differ by more than this many seam tolerances are an
/// occlusion (the nearer is drawn), otherwise a contact (the score and height decide).
const OCCLUSION_DEPTH_FACTOR: f64 = 5.0;
/// Coincident pieces may differ in picture direction by up to this (perturbed poses).
const COINCIDENT_ANGLE_DEG: f64 = 1.0;

/// A piece with its picture ends.
#[derive(Debug, Clone, Copy)]
struct Seg {
    piece: Piece,
    p: [DVec2; 2],
}

impl Seg {
    fn new(geo: &SceneGeometry, piece: Piece) -> Seg {
        let e = &geo.edges[piece.edge];
        Seg {
            piece,
            p: [
                geo.proj.picture(e.at(piece.t[0])),
                geo.proj.picture(e.at(piece.t[1])),
            ],
        }
    }

    fn length_px(&self) -> f64 {
        self.p[0].distance(self.p[1])
    }

    /// Edge parameter at local picture parameter `u` (0 at `p[0]`, 1 at `p[1]`).
    fn t_at(&self, geo: &SceneGeometry, u: f64) -> f64 {
        let e = &geo.edges[self.piece.edge];
        let s0 = Projector::s_from_t(self.piece.t[0], e.wa, e.wb);
        let s1 = Projector::s_from_t(self.piece.t[1], e.wa, e.wb);
        Projector::t_from_s(s0 + u * (s1 - s0), e.wa, e.wb)
    }

    /// Local picture parameter of the projection of `q` onto the segment's line.
    fn u_of(&self, q: DVec2) -> f64 {
        let d = self.p[1] - self.p[0];
        (q - self.p[0]).dot(d) / d.length_squared()
    }

    fn distance_to_line(&self, q: DVec2) -> f64 {
        let d = (self.p[1] - self.p[0]).normalize();
        d.perp_dot(q - self.p[0]).abs()
    }

    /// The part `[u0, u1]` of this segment as a new segment.
    fn sub(&self, geo: &SceneGeometry, u0: f64, u1: f64) -> Seg {
        let mut piece = self.piece;
        piece.t = [self.t_at(geo, u0), self.t_at(geo, u1)];
        Seg::new(geo, piece)
    }
}

/// Builds the final drawing.
pub(super) fn assemble_drawing(
    geo: &SceneGeometry,
    pieces: Vec<Piece>,
    tol: &TruthTolerances,
) -> LineDrawing {
    let snap_px = tol.merge_px.max(tol.seam_mm * geo.px_per_mm);
    let mut segs: Vec<Seg> = pieces.into_iter().map(|p| Seg::new(geo, p)).collect();
    remove_coincident(geo, &mut segs, snap_px, tol);
    // Slivers go first, so that the pieces on either side of one can join across it.
    segs.retain(|s| s.length_px() > snap_px);
    segs.sort_by(|a, b| {
        (a.piece.edge.cmp(&b.piece.edge)).then(a.piece.t[0].total_cmp(&b.piece.t[0]))
    });
    let gap_t = |edge: usize| {
        let e = &geo.edges[edge];
        snap_px / e.pa.distance(e.pb).max(1e-12)
    };
    let pieces: Vec<Piece> = segs.iter().map(|s| s.piece).collect();
    let segs: Vec<Seg> = join_pieces(pieces, gap_t)
        .into_iter()
        .map(|p| Seg::new(geo, p))
        .collect();
    let (points, ends) = merge_ends(&segs, snap_px);
    build_lines(geo, &segs, &points, &ends, snap_px)
}

/// Keeps every stretch of picture covered by two collinear pieces once.
fn remove_coincident(
    geo: &SceneGeometry,
    segs: &mut Vec<Seg>,
    snap_px: f64,
    tol: &TruthTolerances,
) {
    let sin_max = COINCIDENT_ANGLE_DEG.to_radians().sin();
    let mut changed = true;
    while changed {
        changed = false;
        let mut i = 0;
        while i < segs.len() {
            let mut j = i + 1;
            while j < segs.len() {
                let (a, b) = (segs[i], segs[j]);
                let Some([u0, u1]) = overlap(&a, &b, snap_px, sin_max) else {
                    j += 1;
                    continue;
                };
                let i_wins = wins(geo, &a, &b, (u0 + u1) / 2.0, tol);
                let (winner, loser_index) = if i_wins { (a, j) } else { (b, i) };
                let loser = segs[loser_index];
                let (v0, v1) = {
                    let x = loser.u_of(winner.p[0].lerp(winner.p[1], 0.0));
                    let y = loser.u_of(winner.p[0].lerp(winner.p[1], 1.0));
                    (x.min(y), x.max(y))
                };
                let mut rest = Vec::new();
                if v0 > 0.0 {
                    rest.push(loser.sub(geo, 0.0, v0.min(1.0)));
                }
                if v1 < 1.0 {
                    rest.push(loser.sub(geo, v1.max(0.0), 1.0));
                }
                // A trimmed piece may have lost the stretch its kind was read on: read it again.
                let rest: Vec<Seg> = rest
                    .into_iter()
                    .filter(|s| s.length_px() > snap_px)
                    .filter_map(|s| reclassify(geo, &s.piece, tol).map(|p| Seg { piece: p, ..s }))
                    .collect();
                changed = true;
                segs.remove(loser_index);
                segs.extend(rest);
                if loser_index == i {
                    j = i + 1;
                    if i >= segs.len() {
                        break;
                    }
                    continue;
                }
            }
            i += 1;
        }
    }
}

/// The overlap of `b` on `a` as a range of `a`'s local parameter, if the two are collinear
/// within `snap_px` and overlap by more than `snap_px`.
fn overlap(a: &Seg, b: &Seg, snap_px: f64, sin_max: f64) -> Option<[f64; 2]> {
    let (alo, ahi) = (a.p[0].min(a.p[1]), a.p[0].max(a.p[1]));
    let (blo, bhi) = (b.p[0].min(b.p[1]), b.p[0].max(b.p[1]));
    if alo.x > bhi.x + snap_px
        || blo.x > ahi.x + snap_px
        || alo.y > bhi.y + snap_px
        || blo.y > ahi.y + snap_px
    {
        return None;
    }
    let (da, db) = (a.p[1] - a.p[0], b.p[1] - b.p[0]);
    if da.perp_dot(db).abs() > sin_max * da.length() * db.length() {
        return None;
    }
    let (long, short) = if da.length() >= db.length() {
        (a, b)
    } else {
        (b, a)
    };
    if short.p.iter().any(|q| long.distance_to_line(*q) > snap_px) {
        return None;
    }
    let (x, y) = (a.u_of(b.p[0]), a.u_of(b.p[1]));
    let (u0, u1) = (x.min(y).max(0.0), x.max(y).min(1.0));
    ((u1 - u0) * da.length() > snap_px).then_some([u0, u1])
}

/// Whether `a` is drawn rather than `b` where they coincide (around `a`'s parameter `u`).
fn wins(geo: &SceneGeometry, a: &Seg, b: &Seg, u: f64, tol: &TruthTolerances) -> bool {
    let m = a.p[0].lerp(a.p[1], u);
    let depth = |s: &Seg, q: DVec2| {
        let e = &geo.edges[s.piece.edge];
        geo.proj
            .depth_mm(e.at(s.t_at(geo, s.u_of(q).clamp(0.0, 1.0))))
    };
    let (da, db) = (depth(a, m), depth(b, m));
    if (da - db).abs() > OCCLUSION_DEPTH_FACTOR * tol.seam_mm {
        return da < db;
    }
    if a.piece.score != b.piece.score {
        return a.piece.score > b.piece.score;
    }
    let (ea, eb) = (&geo.edges[a.piece.edge], &geo.edges[b.piece.edge]);
    let (ya, yb) = (
        geo.blocks[ea.block].centre_y_mm,
        geo.blocks[eb.block].centre_y_mm,
    );
    if (ya - yb).abs() > 1.0 {
        return ya > yb;
    }
    a.piece.edge <= b.piece.edge
}

/// Merges line ends closer than `snap_px` (union-find over an x-sorted sweep). Returns the
/// points (cluster means, in order of first appearance) and each segment's two point indices.
fn merge_ends(segs: &[Seg], snap_px: f64) -> (Vec<DVec2>, Vec<[usize; 2]>) {
    let ends: Vec<DVec2> = segs.iter().flat_map(|s| s.p).collect();
    let mut sets = UnionFind::new(ends.len());
    let mut order: Vec<usize> = (0..ends.len()).collect();
    order.sort_by(|&a, &b| ends[a].x.total_cmp(&ends[b].x));
    for (k, &i) in order.iter().enumerate() {
        for &j in &order[k + 1..] {
            if ends[j].x - ends[i].x > snap_px {
                break;
            }
            if ends[i].distance(ends[j]) <= snap_px {
                sets.union(i, j);
            }
        }
    }
    let mut index_of_root = vec![usize::MAX; ends.len()];
    let mut sums: Vec<(DVec2, f64)> = Vec::new();
    let mut point_of_end = vec![0; ends.len()];
    for (i, end) in ends.iter().enumerate() {
        let r = sets.find(i);
        if index_of_root[r] == usize::MAX {
            index_of_root[r] = sums.len();
            sums.push((DVec2::ZERO, 0.0));
        }
        let k = index_of_root[r];
        sums[k].0 += *end;
        sums[k].1 += 1.0;
        point_of_end[i] = k;
    }
    let points = sums.iter().map(|(s, n)| *s / *n).collect();
    let seg_ends = (0..segs.len())
        .map(|s| [point_of_end[2 * s], point_of_end[2 * s + 1]])
        .collect();
    (points, seg_ends)
}

/// Splits every segment at the points lying on its interior and emits the lines.
fn build_lines(
    geo: &SceneGeometry,
    segs: &[Seg],
    points: &[DVec2],
    ends: &[[usize; 2]],
    snap_px: f64,
) -> LineDrawing {
    let mut d = LineDrawing {
        points: points.to_vec(),
        ..Default::default()
    };
    let mut seen = std::collections::HashSet::new();
    for (s, seg) in segs.iter().enumerate() {
        let [c0, c1] = ends[s];
        if c0 == c1 {
            continue;
        }
        let (q0, q1) = (points[c0], points[c1]);
        let (lo, hi) = (q0.min(q1) - snap_px, q0.max(q1) + snap_px);
        let len = q0.distance(q1);
        let dir = (q1 - q0) / len;
        let mut cuts: Vec<(f64, usize)> = vec![(0.0, c0), (len, c1)];
        for (k, q) in points.iter().enumerate() {
            if k == c0 || k == c1 || q.x < lo.x || q.y < lo.y || q.x > hi.x || q.y > hi.y {
                continue;
            }
            let along = (*q - q0).dot(dir);
            if along > snap_px && along < len - snap_px && dir.perp_dot(*q - q0).abs() <= snap_px {
                cuts.push((along, k));
            }
        }
        cuts.sort_by(|a, b| a.0.total_cmp(&b.0));
        for w in cuts.windows(2) {
            let ((a0, ka), (a1, kb)) = (w[0], w[1]);
            if ka == kb || !seen.insert((ka.min(kb), ka.max(kb))) {
                continue;
            }
            let e = &geo.edges[seg.piece.edge];
            let t_at = |along: f64, k: usize| {
                if k == c0 {
                    seg.piece.t[0]
                } else if k == c1 {
                    seg.piece.t[1]
                } else {
                    seg.t_at(geo, seg.u_of(q0 + dir * along).clamp(0.0, 1.0))
                }
            };
            if e.curved {
                d.curved_lines.push(d.lines.len());
            }
            d.lines.push([ka, kb]);
            d.kinds.push(seg.piece.kind);
            d.edges.push(EdgeRef {
                block: e.block,
                vertices: e.vertices,
                other_block: seg.piece.other_block,
                from_mm: e.at(t_at(a0, ka)).to_array(),
                to_mm: e.at(t_at(a1, kb)).to_array(),
                contact: seg.piece.contact,
            });
        }
    }
    drop_unused_points(&mut d);
    d.finalize();
    d
}

/// Removes points no line uses (ends of segments that merged into one point) and renumbers.
fn drop_unused_points(d: &mut LineDrawing) {
    let mut used = vec![false; d.points.len()];
    for l in &d.lines {
        used[l[0]] = true;
        used[l[1]] = true;
    }
    let mut new_index = vec![usize::MAX; d.points.len()];
    let mut points = Vec::new();
    for (i, p) in d.points.iter().enumerate() {
        if used[i] {
            new_index[i] = points.len();
            points.push(*p);
        }
    }
    d.points = points;
    for l in &mut d.lines {
        *l = [new_index[l[0]], new_index[l[1]]];
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::drawing::LineKind;

    fn seg(p0: (f64, f64), p1: (f64, f64)) -> Seg {
        Seg {
            piece: Piece {
                edge: 0,
                t: [0.0, 1.0],
                kind: LineKind::Boundary,
                other_block: None,
                contact: false,
                score: 0,
            },
            p: [DVec2::new(p0.0, p0.1), DVec2::new(p1.0, p1.1)],
        }
    }

    #[test]
    fn ends_closer_than_the_snap_distance_become_one_point() {
        let segs = [
            seg((0.0, 0.0), (10.0, 0.0)),
            seg((10.005, 0.0), (10.0, 10.0)),
            seg((20.0, 0.0), (10.3, 0.0)),
        ];
        let (points, ends) = merge_ends(&segs, 0.01);
        assert_eq!(points.len(), 5, "{points:?}");
        assert_eq!(ends[0][1], ends[1][0]);
        assert_ne!(ends[2][1], ends[0][1]);
        assert!((points[ends[0][1]].x - 10.0025).abs() < 1e-12);
    }

    #[test]
    fn collinear_overlap_is_measured_on_the_first_segment() {
        let sin = COINCIDENT_ANGLE_DEG.to_radians().sin();
        let a = seg((0.0, 0.0), (10.0, 0.0));
        let b = seg((15.0, 0.001), (5.0, 0.0));
        assert_eq!(overlap(&a, &b, 0.01, sin), Some([0.5, 1.0]));
        let far = seg((0.0, 1.0), (10.0, 1.0));
        assert_eq!(overlap(&a, &far, 0.01, sin), None);
        let touching = seg((10.0, 0.0), (20.0, 0.0));
        assert_eq!(overlap(&a, &touching, 0.01, sin), None);
    }
}
