//! Outlines against a floor of the same gray (docs/recognizer-pictures.md "Outlines against a
//! floor of the same gray"): a side face in a lamp's shade, or a face whose albedo and light
//! give the floor's gray, shows no step where it meets the floor. Its outline is in the scene
//! and not in the picture, so the right answer's redraw has lines the drawing lacks that no
//! step or crack confirms. [`hidden_against_floor`] names those the picture lets pass: flat
//! across, against the floor, beside a face seen whole.

use super::edge_profile::{flat_across, uniform_along, ViewPicture};
use super::verify::ViewMismatch;
use crate::drawing::{LineDrawing, LineKind};
use crate::geom::{convex_hull, distance_to_segment_px, inside_convex, DVec2};

/// How far beside a redrawn line [`hidden_against_floor`] looks for the floor, px.
const BESIDE_PX: f64 = 3.0;

/// The redrawn lines the drawing lacks, not confirmed, that are outlines against a floor of
/// the same gray (docs/recognizer-pictures.md "Outlines against a floor of the same gray"):
/// a boundary line with the floor on one side (a bottom edge on the floor, or a line of the
/// redraw's convex hull), an end at a point the drawing has, and the picture flat across it
/// ([`flat_across`]). A side face in a lamp's shade can be as dark as the floor: its outline
/// is in the scene and not in the picture. At most half of the redraw's boundary lines are
/// excused so, and never a line between two faces (a flat line there is a wrong split).
pub(super) fn hidden_against_floor(
    drawn: &LineDrawing,
    picture: &ViewPicture,
    m: &ViewMismatch,
    confirmed: &[usize],
) -> Vec<usize> {
    let hull = convex_hull(&drawn.points);
    let boundary = |k: usize| drawn.kinds.get(k) == Some(&LineKind::Boundary);
    let on_floor = |k: usize| {
        drawn
            .edges
            .get(k)
            .is_some_and(|e| e.from_mm[1].abs() < 1e-6 && e.to_mm[1].abs() < 1e-6)
    };
    let on_hull = |k: usize| inward_of_hull(drawn, &hull, k).is_some();
    let seen_end = |k: usize| drawn.lines[k].iter().any(|p| !m.extra_points.contains(p));
    let hidden: Vec<usize> = m
        .extra_lines
        .iter()
        .copied()
        .filter(|k| !confirmed.contains(k))
        .filter(|&k| boundary(k) && (on_floor(k) || on_hull(k)) && seen_end(k))
        .filter(|&k| {
            let [i, j] = drawn.lines[k];
            flat_across(picture, drawn.points[i], drawn.points[j])
                && face_seen_whole(drawn, picture, k, &hull)
        })
        .collect();
    let outline = (0..drawn.lines.len()).filter(|&k| boundary(k)).count();
    if hidden.len() * 2 > outline {
        return Vec::new();
    }
    hidden
}

/// The unit normal of redrawn line `k` towards the inside of the convex hull `hull` when
/// the line lies on the hull (the point [`BESIDE_PX`] beside its middle is inside on one side
/// and outside on the other); `None` otherwise.
fn inward_of_hull(drawn: &LineDrawing, hull: &[DVec2], k: usize) -> Option<DVec2> {
    let [i, j] = drawn.lines[k];
    let (a, b) = (drawn.points[i], drawn.points[j]);
    let n = (b - a).normalize_or_zero().perp();
    let mid = a.lerp(b, 0.5);
    match (
        inside_convex(hull, mid + n * BESIDE_PX, 0.0),
        inside_convex(hull, mid - n * BESIDE_PX, 0.0),
    ) {
        (true, false) => Some(n),
        (false, true) => Some(-n),
        _ => None,
    }
}

/// Walks across a face start and stop this far from a redrawn line, px (clear of the
/// edges' blur and the strips' half width).
const FACE_EDGE_PX: f64 = 4.0;
/// Longest walk across a face, px.
const FACE_WALK_PX: f64 = 120.0;

/// `true` when the face of the redraw beside outline line `k` (inside the convex hull `hull`,
/// or above a bottom edge on the floor) shows no step from the line to the next redrawn line,
/// walked across at a quarter, half and three quarters of its length ([`uniform_along`]): a
/// face as gray as the floor is one gray to its other edges, where a block in front of it that
/// the redraw lacks, as faint as the floor, shows its own edges inside the face.
fn face_seen_whole(drawn: &LineDrawing, picture: &ViewPicture, k: usize, hull: &[DVec2]) -> bool {
    let [i, j] = drawn.lines[k];
    let (a, b) = (drawn.points[i], drawn.points[j]);
    let n = (b - a).normalize_or_zero().perp();
    let up = (n.y.abs() > 1e-9).then(|| n * n.y.signum());
    let Some(inward) = inward_of_hull(drawn, hull, k).or(up) else {
        return false;
    };
    let near_other = |q: DVec2| {
        (0..drawn.lines.len()).filter(|&l| l != k).any(|l| {
            let [c, d] = drawn.lines[l];
            distance_to_segment_px(q, drawn.points[c], drawn.points[d]) <= FACE_EDGE_PX
        })
    };
    [0.25, 0.5, 0.75].iter().all(|&f| {
        let start = a.lerp(b, f) + inward * FACE_EDGE_PX;
        let len = (0..FACE_WALK_PX as i32)
            .map(f64::from)
            .find(|&t| near_other(start + inward * t))
            .unwrap_or(FACE_WALK_PX);
        uniform_along(picture, start, inward, len)
    })
}

#[cfg(test)]
mod tests {
    use super::super::edge_profile::edge_profile;
    use super::super::picture::{picture_mismatch, without_lines};
    use super::super::verify::{compare_drawings, draw_hypothesis};
    use super::*;
    use crate::geom::DVec3;
    use crate::recognize::painted_picture as picture;
    use crate::recognize::{views_of, Camera, CornerView, RecognizeOptions};
    use crate::scene::Block;
    use image::GrayImage;

    /// The 15 mm cube at the origin as `camera` sees it, each pixel shaded by what its ray
    /// meets first: the top at `grays[0]`, the faces across x at `grays[1]`, across z at
    /// `grays[2]` (at `band.2` from `band.0` to `band.1` mm high), the floor (and what lies
    /// beyond it) at `grays[3]`.
    fn shaded_cube(camera: &Camera, grays: [u8; 4], band: (f64, f64, u8)) -> GrayImage {
        let projector = crate::camera::Projector::new(camera);
        let (lo, hi) = (DVec3::new(-7.5, 0.0, -7.5), DVec3::new(7.5, 15.0, 7.5));
        picture(camera, grays[3], |q| {
            let (o, d) = projector.ray(q);
            let (mut near, mut far, mut axis) = (f64::NEG_INFINITY, f64::INFINITY, 0);
            for a in 0..3 {
                let (t0, t1) = ((lo[a] - o[a]) / d[a], (hi[a] - o[a]) / d[a]);
                if t0.min(t1) > near {
                    (near, axis) = (t0.min(t1), a);
                }
                far = far.min(t0.max(t1));
            }
            let y = (o + d * near).y;
            let in_band = y > band.0 && y < band.1;
            (near <= far).then_some(match axis {
                2 if in_band => band.2,
                _ => grays[[1, 0, 2][axis]],
            })
        })
    }

    #[test]
    fn an_outline_against_a_floor_of_its_face_gray_is_excused_and_an_edge_between_faces_not() {
        let blocks = vec![Block::new("b15", DVec3::new(0.0, 7.5, 0.0), 0.0)];
        let view = views_of(&blocks, &[CornerView::Ne]).remove(0);
        let drawn = draw_hypothesis(&blocks, &view.camera);
        let tol_px = RecognizeOptions::default().tol_px;
        let read = |grays: [u8; 4], band: (f64, f64, u8)| {
            let gray = shaded_cube(&view.camera, grays, band);
            let picture = ViewPicture::new(&gray, &view.camera);
            // What a front end draws: the redraw's lines the picture steps across.
            let unseen: Vec<usize> = (0..drawn.lines.len())
                .filter(|&k| {
                    let [i, j] = drawn.lines[k];
                    !edge_profile(&picture, drawn.points[i], drawn.points[j]).confirms()
                })
                .collect();
            let seen = without_lines(&drawn, &unseen);
            let plain = compare_drawings(&drawn, &seen, tol_px);
            (
                plain,
                picture_mismatch(&drawn, &seen, &picture, tol_px).counts(),
            )
        };
        // Every face apart from the floor: the drawing is the redraw.
        let whole = (0.0, 0.0, 0);
        let (plain, _) = read([200, 60, 140, 100], whole);
        assert!(plain.is_explained(), "{plain:?}");
        // One side face as gray as the floor: its outline is not in the picture, and flat
        // across it, the redraw's lines there are excused.
        let (plain, read_through) = read([200, 60, 100, 100], whole);
        assert!(plain.extra_lines >= 2, "{plain:?}");
        assert!(read_through.is_explained(), "{read_through:?}");
        // It can fail: both side faces as gray as the floor hide the edge between them, a line
        // between two faces, which is never excused so.
        let (_, read_through) = read([200, 100, 100, 100], whole);
        assert!(!read_through.is_explained(), "{read_through:?}");
        // Nor an outline where the face beside it is not one gray to its other edges (a block
        // as faint as the floor in front of the face the redraw has): a band across the face
        // from 5 to 10 mm high leaves the outline flat over most of its length.
        let (_, read_through) = read([200, 60, 100, 100], (5.0, 10.0, 125));
        assert!(!read_through.is_explained(), "{read_through:?}");
        // Nor is an outline where the picture steps, only fainter than the front end reads.
        let gray = shaded_cube(&view.camera, [200, 60, 108, 100], whole);
        let picture = ViewPicture::new(&gray, &view.camera);
        let hidden = (0..drawn.lines.len())
            .filter(|&k| {
                let [i, j] = drawn.lines[k];
                flat_across(&picture, drawn.points[i], drawn.points[j])
            })
            .count();
        assert_eq!(hidden, 0);
    }
}
