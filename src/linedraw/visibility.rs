//! Hidden-line removal by exact intervals: the part of a 3D edge hidden by a face is where the
//! edge's picture segment overlaps the face's picture polygon AND the edge lies behind the
//! face's plane by more than the contact tolerance (Chapter II's viewing model; Kanade's
//! occlusion). A face whose plane contains the edge never hides it.

use super::geometry::{Edge, Face, SceneGeometry};
use super::{unit_interval_complement, TruthTolerances};
use crate::camera::Projector;
use crate::geom::DVec2;

/// Picture tolerance of the closed-polygon overlap test: an edge lying exactly on a face's
/// silhouette counts as covered by it (then the depth test decides).
const OVERLAP_EPS_PX: f64 = 1e-6;

/// The visible parameter intervals `[t0, t1]` of one edge (parameter along the 3D edge, 0 at
/// `a`, 1 at `b`), sorted and disjoint.
pub(super) struct EdgeIntervals {
    /// Index into [`SceneGeometry::edges`].
    pub edge: usize,
    /// Visible intervals.
    pub intervals: Vec<[f64; 2]>,
}

/// Visible intervals of every edge that can be seen at all; `progress(n)` after the n-th edge.
pub(super) fn visible_intervals(
    geo: &SceneGeometry,
    tol: &TruthTolerances,
    progress: &dyn Fn(u64),
) -> Vec<EdgeIntervals> {
    let mut out = Vec::new();
    let mut hidden: Vec<[f64; 2]> = Vec::new();
    let mut near = Vec::new();
    let mut seen = vec![false; geo.faces.len()];
    for (ei, edge) in geo.edges.iter().enumerate() {
        progress(ei as u64 + 1);
        if !edge.may_show(&geo.faces) {
            continue;
        }
        hidden.clear();
        let (lo, hi) = (edge.pa.min(edge.pb), edge.pa.max(edge.pb));
        geo.grid.candidates_unordered(lo, hi, &mut seen, &mut near);
        for face in near.iter().map(|&f| &geo.faces[f]) {
            if face.block == edge.block
                || face.lo.x > hi.x + OVERLAP_EPS_PX
                || face.lo.y > hi.y + OVERLAP_EPS_PX
                || face.hi.x < lo.x - OVERLAP_EPS_PX
                || face.hi.y < lo.y - OVERLAP_EPS_PX
            {
                continue;
            }
            if let Some(h) = hidden_by_face(edge, face, tol.contact_mm) {
                hidden.push(h);
            }
        }
        let intervals = unit_interval_complement(&mut hidden);
        if !intervals.is_empty() {
            out.push(EdgeIntervals {
                edge: ei,
                intervals,
            });
        }
    }
    out
}

/// The edge-parameter interval hidden by `face`, if any: the part of the picture overlap that
/// lies behind the face's plane, provided the overlap reaches more than `contact_mm` behind it
/// (so a face touching the edge hides nothing, while a face clearly in front hides exactly up
/// to where the edge crosses its plane).
fn hidden_by_face(edge: &Edge, face: &Face, contact_mm: f64) -> Option<[f64; 2]> {
    // Cheap test first: an edge nowhere behind the plane cannot be hidden by the face.
    if face.plane_distance(edge.a).min(face.plane_distance(edge.b)) >= -contact_mm {
        return None;
    }
    let [s0, s1] = clip_segment_to_polygon(edge.pa, edge.pb, &face.poly, OVERLAP_EPS_PX)?;
    let ta = Projector::t_from_s(s0, edge.wa, edge.wb);
    let tb = Projector::t_from_s(s1, edge.wa, edge.wb);
    let (da, db) = (
        face.plane_distance(edge.at(ta)),
        face.plane_distance(edge.at(tb)),
    );
    if da.min(db) >= -contact_mm {
        return None;
    }
    let cross = ta + (tb - ta) * da / (da - db);
    let (t0, t1) = match (da < 0.0, db < 0.0) {
        (true, true) => (ta, tb),
        (true, false) => (ta, cross),
        (false, true) => (cross, tb),
        (false, false) => return None,
    };
    (t1 > t0).then_some([t0, t1])
}

/// The parameter range `[s0, s1]` of segment `p0 -> p1` inside the closed convex
/// counter-clockwise polygon grown by `eps_px` (Cyrus-Beck clipping).
pub(super) fn clip_segment_to_polygon(
    p0: DVec2,
    p1: DVec2,
    poly: &[DVec2],
    eps_px: f64,
) -> Option<[f64; 2]> {
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    let n = poly.len();
    for k in 0..n {
        let (a, b) = (poly[k], poly[(k + 1) % n]);
        let e = b - a;
        let len = e.length();
        if len < 1e-12 {
            continue;
        }
        let f0 = e.perp_dot(p0 - a) / len + eps_px;
        let f1 = e.perp_dot(p1 - a) / len + eps_px;
        match (f0 < 0.0, f1 < 0.0) {
            (true, true) => return None,
            (false, false) => {}
            (true, false) => lo = lo.max(f0 / (f0 - f1)),
            (false, true) => hi = hi.min(f0 / (f0 - f1)),
        }
        if lo > hi {
            return None;
        }
    }
    Some([lo, hi])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clipping_a_segment_through_a_unit_square() {
        let sq = [
            DVec2::new(0.0, 0.0),
            DVec2::new(1.0, 0.0),
            DVec2::new(1.0, 1.0),
            DVec2::new(0.0, 1.0),
        ];
        let r = clip_segment_to_polygon(DVec2::new(-1.0, 0.5), DVec2::new(3.0, 0.5), &sq, 0.0);
        let [a, b] = r.unwrap();
        assert!((a - 0.25).abs() < 1e-12 && (b - 0.5).abs() < 1e-12);
        // Along the boundary: inside only with the closed test.
        let on = clip_segment_to_polygon(DVec2::new(0.2, 0.0), DVec2::new(0.8, 0.0), &sq, 1e-9);
        assert_eq!(on, Some([0.0, 1.0]));
        assert!(
            clip_segment_to_polygon(DVec2::new(2.0, 2.0), DVec2::new(3.0, 2.0), &sq, 0.0).is_none()
        );
    }
}
