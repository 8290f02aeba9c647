//! The viewer's hidden-line removal, the first of Chapter VII's recommended additions ("the hidden surface
//! removal and the shading models (Foley & Dam 1982) can be attached to the display").
//!
//! Exact, object-space, in the manner of Appel and Roberts: a convex face hides the points of
//! a line that lie inside the pyramid from the eye through the face's edges and behind the
//! face's plane. In eye coordinates (eye at the origin) every one of those conditions is an
//! affine function of the line's parameter, so the hidden part of a line is one interval per
//! face, and the visible parts are what the union of those intervals leaves of [0, 1].

use super::unit_interval_complement;
use crate::geom::{newell_vector, DVec3, CONTACT_TOL_MM};

/// How far behind a face's plane a point must be to count as hidden, and how far outside its
/// pyramid it may be and still count as inside, in mm: the contact tolerance of docs/formats.md
/// "Conventions". An edge lying on a face (its own, or a touching block's) stays visible; an
/// edge seen exactly behind the boundary of two faces (the back edge of a cube seen along its
/// diagonal) is hidden, not left as a sliver between the two pyramids.
const HIDDEN_TOL_MM: f64 = CONTACT_TOL_MM;

/// A convex face as the half-spaces (unit normal n, offset c: n·p - c > 0 inside, the
/// tolerance folded into c) whose intersection is the region it hides.
#[derive(Debug, Clone)]
pub struct Occluder {
    half_spaces: Vec<(DVec3, f64)>,
}

/// The occluder of a convex face given in eye mm with every vertex in front of the eye
/// (z > 0); `None` when the face is seen edge-on or is degenerate (it hides nothing).
pub fn occluder(polygon_eye_mm: &[DVec3]) -> Option<Occluder> {
    if polygon_eye_mm.len() < 3 {
        return None;
    }
    let centroid = polygon_eye_mm.iter().sum::<DVec3>() / polygon_eye_mm.len() as f64;
    let normal = newell_normal(polygon_eye_mm)?;
    let d = normal.dot(polygon_eye_mm[0]);
    if d.abs() < HIDDEN_TOL_MM {
        return None;
    }
    // Behind the plane: on the side away from the eye, whose value is n·0 - d = -d.
    let mut half_spaces = vec![(normal * d.signum(), d.abs() + HIDDEN_TOL_MM)];
    for (i, a) in polygon_eye_mm.iter().enumerate() {
        let b = polygon_eye_mm[(i + 1) % polygon_eye_mm.len()];
        let n = a.cross(b);
        if n.length() <= f64::EPSILON * a.length() * b.length() {
            continue;
        }
        let n = n.normalize();
        half_spaces.push((if n.dot(centroid) < 0.0 { -n } else { n }, -HIDDEN_TOL_MM));
    }
    Some(Occluder { half_spaces })
}

/// The unit normal of a planar polygon by Newell's method; `None` for a degenerate one.
fn newell_normal(polygon: &[DVec3]) -> Option<DVec3> {
    let n = newell_vector(polygon);
    (n.length() > 0.0).then(|| n.normalize())
}

/// The parameter interval of the line p1 p2 (eye mm) that `occ` hides, if any.
fn hidden_interval(occ: &Occluder, p1: DVec3, p2: DVec3) -> Option<(f64, f64)> {
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    for &(n, c) in &occ.half_spaces {
        let (g1, g2) = (n.dot(p1) - c, n.dot(p2) - c);
        if g1 <= 0.0 && g2 <= 0.0 {
            return None;
        }
        if g1 > 0.0 && g2 > 0.0 {
            continue;
        }
        let t = g1 / (g1 - g2);
        if g1 <= 0.0 {
            lo = lo.max(t);
        } else {
            hi = hi.min(t);
        }
    }
    (lo < hi).then_some((lo, hi))
}

/// The visible parts of the line p1 p2 (eye mm) as parameter intervals in [0, 1], in order.
pub fn visible_parts(p1: DVec3, p2: DVec3, occluders: &[Occluder]) -> Vec<(f64, f64)> {
    let mut hidden: Vec<[f64; 2]> = occluders
        .iter()
        .filter_map(|o| hidden_interval(o, p1, p2))
        .map(|(lo, hi)| [lo, hi])
        .collect();
    unit_interval_complement(&mut hidden)
        .into_iter()
        .map(|[lo, hi]| (lo, hi))
        .collect()
}

/// The part of a convex polygon (eye mm) on or beyond the hither plane z = `hither_mm`
/// (Sutherland-Hodgman against one plane), so that only faces in front of the eye occlude
/// or are shaded.
pub fn clip_polygon_to_hither(polygon_eye_mm: &[DVec3], hither_mm: f64) -> Vec<DVec3> {
    let mut out = Vec::with_capacity(polygon_eye_mm.len() + 1);
    for (i, &a) in polygon_eye_mm.iter().enumerate() {
        let b = polygon_eye_mm[(i + 1) % polygon_eye_mm.len()];
        let (fa, fb) = (a.z - hither_mm, b.z - hither_mm);
        if fa >= 0.0 {
            out.push(a);
        }
        if (fa >= 0.0) != (fb >= 0.0) {
            out.push(a + (b - a) * (fa / (fa - fb)));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 10 mm square facing the eye at depth `z`, centred on the line of sight.
    fn square(z: f64) -> Vec<DVec3> {
        vec![
            DVec3::new(-5.0, -5.0, z),
            DVec3::new(5.0, -5.0, z),
            DVec3::new(5.0, 5.0, z),
            DVec3::new(-5.0, 5.0, z),
        ]
    }

    #[test]
    fn a_square_hides_the_middle_of_a_line_behind_it() {
        let occ = occluder(&square(50.0)).unwrap();
        // A line at depth 100 from x = -20 to 20: the square covers |x| <= 10 there.
        let (p1, p2) = (DVec3::new(-20.0, 0.0, 100.0), DVec3::new(20.0, 0.0, 100.0));
        let parts = visible_parts(p1, p2, &[occ]);
        assert_eq!(parts.len(), 2);
        assert!((parts[0].1 - 0.25).abs() < 0.01 && (parts[1].0 - 0.75).abs() < 0.01);
    }

    #[test]
    fn a_line_in_front_of_the_face_or_on_it_stays_visible() {
        let occ = occluder(&square(50.0)).unwrap();
        let front = visible_parts(
            DVec3::new(-2.0, 0.0, 20.0),
            DVec3::new(2.0, 0.0, 20.0),
            std::slice::from_ref(&occ),
        );
        assert_eq!(front, vec![(0.0, 1.0)]);
        // The face's own edge.
        let own = visible_parts(
            DVec3::new(-5.0, 5.0, 50.0),
            DVec3::new(5.0, 5.0, 50.0),
            &[occ],
        );
        assert_eq!(own, vec![(0.0, 1.0)]);
    }

    #[test]
    fn a_line_wholly_behind_is_hidden_and_overlapping_faces_merge() {
        let a = occluder(&square(50.0)).unwrap();
        let shifted: Vec<DVec3> = square(50.0).iter().map(|p| *p + DVec3::X * 6.0).collect();
        let b = occluder(&shifted).unwrap();
        let (p1, p2) = (DVec3::new(-4.0, 0.0, 60.0), DVec3::new(4.0, 0.0, 60.0));
        assert!(visible_parts(p1, p2, std::slice::from_ref(&a)).is_empty());
        // Two overlapping squares hide x in [-6, 13.2] at depth 60 of a line from -20 to 20.
        let (p1, p2) = (DVec3::new(-20.0, 0.0, 60.0), DVec3::new(20.0, 0.0, 60.0));
        let parts = visible_parts(p1, p2, &[b, a]);
        assert_eq!(parts.len(), 2);
        assert!(parts[0].1 < parts[1].0);
    }

    #[test]
    fn a_face_seen_edge_on_hides_nothing() {
        let edge_on = vec![
            DVec3::new(0.0, -5.0, 40.0),
            DVec3::new(0.0, 5.0, 40.0),
            DVec3::new(0.0, 5.0, 60.0),
            DVec3::new(0.0, -5.0, 60.0),
        ];
        assert!(occluder(&edge_on).is_none());
    }

    #[test]
    fn hither_clipping_keeps_the_part_beyond_the_plane() {
        let tilted = vec![
            DVec3::new(-5.0, 0.0, 0.0),
            DVec3::new(5.0, 0.0, 0.0),
            DVec3::new(5.0, 0.0, 10.0),
            DVec3::new(-5.0, 0.0, 10.0),
        ];
        let kept = clip_polygon_to_hither(&tilted, 4.0);
        assert_eq!(kept.len(), 4);
        assert!(kept.iter().all(|p| p.z >= 4.0));
        assert!(clip_polygon_to_hither(&square(1.0), 4.0).is_empty());
    }
}
