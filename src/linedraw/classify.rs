//! What each visible piece of an edge depicts: a boundary (Kanade's occluding line: background,
//! floor or a farther surface on one side), a convex or concave line (two planes meeting at the
//! edge), or a crack (one plane of two touching blocks on both sides). Decided by one ray on
//! each side of the piece's midpoint, after cutting the visible intervals wherever another
//! block's edge or vertex touches the edge (where the surroundings, and so the kind, can change).

use super::geometry::SceneGeometry;
use super::visibility::EdgeIntervals;
use super::TruthTolerances;
use crate::drawing::LineKind;
use crate::geom::{touching_box_pairs, DVec3};

/// A hit on a side ray counts as "at the edge" when it is at most this many sample offsets away
/// (a face seen at a grazing angle of about 3 degrees still qualifies).
const NEAR_HIT_FACTOR: f64 = 20.0;

/// A visible, classified piece of one block edge.
#[derive(Debug, Clone, Copy)]
pub(super) struct Piece {
    /// Index into [`SceneGeometry::edges`].
    pub edge: usize,
    /// Edge parameter of the piece's ends.
    pub t: [f64; 2],
    /// What it depicts.
    pub kind: LineKind,
    /// The touching block for cracks and contact lines.
    pub other_block: Option<usize>,
    /// On a contact between two blocks.
    pub contact: bool,
    /// How many of the two surfaces seen beside it are the edge's own faces (0..=2): when two
    /// blocks' edges coincide, the one with the higher score is drawn.
    pub score: u8,
}

/// The classification of one piece (or `None`: nothing changes across it, no line).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Class {
    kind: LineKind,
    other_block: Option<usize>,
    contact: bool,
    score: u8,
}

/// Cuts and classifies the visible intervals of every edge (pieces stay cut, so that a piece
/// trimmed later can be classified again on what is left of it; see [`join_pieces`]);
/// `progress(n)` after the n-th edge.
pub(super) fn classify_pieces(
    geo: &SceneGeometry,
    intervals: &[EdgeIntervals],
    tol: &TruthTolerances,
    progress: &dyn Fn(u64),
) -> Vec<Piece> {
    let mut out = Vec::new();
    let mut cuts = Vec::new();
    let near = near_blocks(geo, tol.seam_mm);
    for (n, ei) in intervals.iter().enumerate() {
        progress(n as u64 + 1);
        cuts.clear();
        let e = &geo.edges[ei.edge];
        collect_cuts(geo, ei.edge, &near[e.block], tol, &mut cuts);
        cuts.sort_by(f64::total_cmp);
        cuts.dedup_by(|b, a| *b - *a < 1e-9);
        for &[t0, t1] in &ei.intervals {
            let mut start = t0;
            let inner = cuts
                .iter()
                .copied()
                .filter(|&c| c > t0 + 1e-9 && c < t1 - 1e-9);
            for end in inner.chain(std::iter::once(t1)) {
                if let Some(c) = classify(geo, ei.edge, [start, end], tol) {
                    out.push(Piece {
                        edge: ei.edge,
                        t: [start, end],
                        kind: c.kind,
                        other_block: c.other_block,
                        contact: c.contact,
                        score: c.score,
                    });
                }
                start = end;
            }
        }
    }
    out
}

/// Joins consecutive pieces of the same edge with the same classification whose parameters
/// are at most `gap_t(edge)` apart (`pieces` sorted by edge and parameter).
pub(super) fn join_pieces(pieces: Vec<Piece>, gap_t: impl Fn(usize) -> f64) -> Vec<Piece> {
    let mut out: Vec<Piece> = Vec::with_capacity(pieces.len());
    for p in pieces {
        if let Some(last) = out.last_mut() {
            let same = last.edge == p.edge
                && (p.t[0] - last.t[1]).abs() <= gap_t(p.edge).max(1e-9)
                && last.kind == p.kind
                && last.other_block == p.other_block
                && last.contact == p.contact;
            if same {
                last.t[1] = p.t[1];
                last.score = last.score.max(p.score);
                continue;
            }
        }
        out.push(p);
    }
    out
}

/// Per block, the other blocks within `gap_mm` of it ([`SceneGeometry::blocks_near`]),
/// ascending: found by a sweep over the boxes grown by a little more than half the gap (a
/// superset), then the exact test, so the lists are those of comparing every pair.
fn near_blocks(geo: &SceneGeometry, gap_mm: f64) -> Vec<Vec<usize>> {
    let grow = DVec3::splat(gap_mm / 2.0 + 1e-6);
    let boxes: Vec<(DVec3, DVec3)> = geo
        .blocks
        .iter()
        .map(|b| (b.lo - grow, b.hi + grow))
        .collect();
    let mut near = vec![Vec::new(); geo.blocks.len()];
    for [a, b] in touching_box_pairs(&boxes) {
        if geo.blocks_near(a, b, gap_mm) {
            near[a].push(b);
            near[b].push(a);
        }
    }
    for n in &mut near {
        n.sort_unstable();
    }
    near
}

/// Edge parameters where an edge or vertex of a block in `near` (the blocks near this edge's
/// block) touches edge `ei` (within `seam_mm`).
fn collect_cuts(
    geo: &SceneGeometry,
    ei: usize,
    near: &[usize],
    tol: &TruthTolerances,
    cuts: &mut Vec<f64>,
) {
    let e = &geo.edges[ei];
    let sin_par = tol.parallel_deg.to_radians().sin();
    // An edge whose box is farther than the seam from this edge's box comes nowhere near it.
    let (lo, hi) = (e.a.min(e.b) - tol.seam_mm, e.a.max(e.b) + tol.seam_mm);
    for block in near.iter().map(|&bi| &geo.blocks[bi]) {
        for other in &geo.edges[block.edges.clone()] {
            let (olo, ohi) = (other.a.min(other.b), other.a.max(other.b));
            if olo.cmpgt(hi).any() || ohi.cmplt(lo).any() {
                continue;
            }
            let (d1, d2) = (e.b - e.a, other.b - other.a);
            if d1.cross(d2).length() <= sin_par * d1.length() * d2.length() {
                for x in [other.a, other.b] {
                    let t = (x - e.a).dot(d1) / d1.length_squared();
                    if (0.0..=1.0).contains(&t) && e.at(t).distance(x) <= tol.seam_mm {
                        cuts.push(t);
                    }
                }
            } else {
                let (t, u) = closest_params(e.a, d1, other.a, d2);
                if e.at(t).distance(other.a + d2 * u) <= tol.seam_mm {
                    cuts.push(t);
                }
            }
        }
    }
}

/// Parameters of the closest points of segments `p1 + t d1` and `p2 + u d2`, t, u in [0, 1]
/// (Ericson, Real-Time Collision Detection, 5.1.9), for non-parallel segments.
fn closest_params(p1: DVec3, d1: DVec3, p2: DVec3, d2: DVec3) -> (f64, f64) {
    let r = p1 - p2;
    let (a, e, f) = (d1.length_squared(), d2.length_squared(), d2.dot(r));
    let (b, c) = (d1.dot(d2), d1.dot(r));
    let denom = a * e - b * b;
    let mut t = if denom > 0.0 {
        ((b * f - c * e) / denom).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let mut u = (b * t + f) / e;
    if u < 0.0 {
        u = 0.0;
        t = (-c / a).clamp(0.0, 1.0);
    } else if u > 1.0 {
        u = 1.0;
        t = ((b - c) / a).clamp(0.0, 1.0);
    }
    (t, u)
}

/// Classifies the piece `t` of edge `ei` by looking beside its midpoint; `None` when nothing
/// changes across it (no line).
pub(super) fn reclassify(
    geo: &SceneGeometry,
    piece: &Piece,
    tol: &TruthTolerances,
) -> Option<Piece> {
    classify(geo, piece.edge, piece.t, tol).map(|c| Piece {
        edge: piece.edge,
        t: piece.t,
        kind: c.kind,
        other_block: c.other_block,
        contact: c.contact,
        score: c.score,
    })
}

/// Classifies the piece `t` of edge `ei` by looking beside its midpoint.
fn classify(geo: &SceneGeometry, ei: usize, t: [f64; 2], tol: &TruthTolerances) -> Option<Class> {
    let e = &geo.edges[ei];
    let dir = e.pb - e.pa;
    if dir.length() < 1e-9 {
        return None;
    }
    let p = e.at((t[0] + t[1]) / 2.0);
    let q = geo.proj.picture(p);
    let offset_px = tol.sample_offset_mm * geo.proj.px_per_mm(p);
    let side = dir.normalize().perp() * offset_px;
    let near = |hit: Option<(usize, DVec3)>| {
        hit.filter(|&(f, x)| {
            x.distance(p) <= NEAR_HIT_FACTOR * tol.sample_offset_mm
                && geo.faces[f].plane_distance(p).abs() <= tol.seam_mm
        })
    };
    let (h1, h2) = (geo.first_hit(q + side), geo.first_hit(q - side));
    let own = |h: Option<(usize, DVec3)>| {
        h.is_some_and(|(f, _)| geo.faces[f].block == e.block && e.faces.contains(&f)) as u8
    };
    let score = own(h1) + own(h2);
    let boundary = Class {
        kind: LineKind::Boundary,
        other_block: None,
        contact: false,
        score,
    };
    let (Some((f1, x1)), Some((f2, x2))) = (near(h1), near(h2)) else {
        return Some(boundary);
    };
    if f1 == f2 {
        return None;
    }
    let (a, b) = (&geo.faces[f1], &geo.faces[f2]);
    let other = [a.block, b.block].into_iter().find(|&k| k != e.block);
    let contact = a.block != b.block;
    // Unit normals: within the angle exactly when the cosine is at least its cosine (no acos).
    let parallel = a.normal.dot(b.normal) >= tol.parallel_deg.to_radians().cos();
    if parallel && a.plane_distance(x2).abs() <= tol.seam_mm {
        if !contact {
            return None;
        }
        return Some(Class {
            kind: LineKind::Crack,
            other_block: other,
            contact,
            score,
        });
    }
    let bend = a.plane_distance(x2) + b.plane_distance(x1);
    Some(Class {
        kind: if bend > 0.0 {
            LineKind::Concave
        } else {
            LineKind::Convex
        },
        other_block: if contact { other } else { None },
        contact,
        score,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn closest_params_of_crossing_segments() {
        let (t, u) = closest_params(
            DVec3::new(-1.0, 0.0, 0.0),
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(0.0, -1.0, 1.0),
            DVec3::new(0.0, 4.0, 0.0),
        );
        assert!((t - 0.5).abs() < 1e-12 && (u - 0.25).abs() < 1e-12);
    }
}
