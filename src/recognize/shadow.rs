//! The edges of the shadows an answer casts under the lights known to have lit a view
//! (docs/recognizer-pictures.md "Known lights").
//!
//! Thesis Chapter II counts discontinuities of illumination among what a picture's lines come
//! from, beside orientation, range and reflectance; a blocks-world reading keeps only the
//! others. A cast shadow's edge is a step on one surface, from its lit part to its shaded
//! part, and where it lies follows from the blocks and the light: every block of an answer is
//! cast along each light onto the floor and onto every face of every other block turned
//! towards that light, and an observed line lying along the edge of such a shadow is one no
//! block draws. The prediction ignores a block standing between a shadow and the camera or the
//! light, so it finds more shadow edges than a picture shows; a predicted edge only ever lets
//! an observed line go unexplained, it never stands for a block's edge, so every other line of
//! every view must still be explained by the answer.

use super::answer::ObservedView;
use super::catalog_match::bounds_mm;
use super::edge_profile::ViewPicture;
use super::picture::pictures_mismatch;
use super::verify::ViewMismatch;
use crate::camera::Projector;
use crate::drawing::LineDrawing;
use crate::geom::{clip_segment_to_box, convex_hull, distance_to_segment_px, DVec2, DVec3};
use crate::scene::Block;

/// A light whose direction makes a smaller cosine than this with a face's outward normal
/// grazes it: no shadow edge on that face is predicted (nor on the floor, for a light this
/// low).
const GRAZING_COS: f64 = 0.05;
/// An observed line lies along a shadow's edge when at least this share of its samples, one
/// per px, lie near a predicted edge running its way.
const ON_EDGE_SHARE: f64 = 0.9;
/// A predicted edge runs an observed line's way within this angle, degrees.
const ALONG_WITHIN_DEG: f64 = 8.0;
/// A sample is near a predicted edge within this many times the point tolerance: the front
/// end reads a soft shadow's edge somewhere in its penumbra, off the sharp edge predicted
/// (the figures of docs/recognizer-pictures.md "Known lights" are measured with it).
const NEAR_TOL_FACTOR: f64 = 1.5;
/// A hull edge this close to a caster's own cross-section, mm, is the caster's foot on the
/// receiving plane, not a shadow's edge.
const FOOT_MARGIN_MM: f64 = 0.3;
/// Predicted edges shorter than this in the picture, px, are left out.
const SHORTEST_EDGE_PX: f64 = 1.0;

/// A plane that receives shadows: the floor, or one face of a block's box.
struct Receiver {
    /// The world axis of the plane's normal (0 x, 1 y, 2 z).
    axis: usize,
    /// The plane's coordinate along `axis`, mm.
    at_mm: f64,
    /// +1 when the face looks along +`axis`, -1 along -`axis`.
    outward: f64,
    /// The face's extent in the plane's own axes ([`in_plane_axes`]); `None`: the unbounded
    /// floor.
    extent_mm: Option<(DVec2, DVec2)>,
    /// The block the face belongs to (it casts no shadow on itself).
    owner: Option<usize>,
}

/// The two world axes spanning a plane normal to `axis`.
fn in_plane_axes(axis: usize) -> (usize, usize) {
    match axis {
        0 => (2, 1),
        1 => (0, 2),
        _ => (0, 1),
    }
}

/// The floor and every face of `boxes` except the bottoms (a bottom face rests on something
/// or looks at the floor, away from every light above the horizon).
fn receivers(boxes: &[(DVec3, DVec3)]) -> Vec<Receiver> {
    let floor = Receiver {
        axis: 1,
        at_mm: 0.0,
        outward: 1.0,
        extent_mm: None,
        owner: None,
    };
    let mut out = vec![floor];
    for (i, (lo, hi)) in boxes.iter().enumerate() {
        for axis in 0..3 {
            let (u, v) = in_plane_axes(axis);
            let extent = (DVec2::new(lo[u], lo[v]), DVec2::new(hi[u], hi[v]));
            for (at_mm, outward) in [(hi[axis], 1.0), (lo[axis], -1.0)] {
                if axis == 1 && outward < 0.0 {
                    continue;
                }
                out.push(Receiver {
                    axis,
                    at_mm,
                    outward,
                    extent_mm: Some(extent),
                    owner: Some(i),
                });
            }
        }
    }
    out
}

/// The world point of `r`'s plane at in-plane coordinates `q`.
fn on_plane(r: &Receiver, q: DVec2) -> DVec3 {
    let (u, v) = in_plane_axes(r.axis);
    let mut p = DVec3::ZERO;
    p[r.axis] = r.at_mm;
    p[u] = q.x;
    p[v] = q.y;
    p
}

/// The shadow the box `caster` casts along `towards_light` on `r`'s plane: the convex hull
/// (in-plane coordinates) of the part of the box on the lit side of the plane, each corner
/// moved away from the light onto the plane; with whether that part touches the plane.
/// `None` when no part of the box is on the lit side.
fn cast_on(
    caster: (DVec3, DVec3),
    r: &Receiver,
    towards_light: DVec3,
) -> Option<(Vec<DVec2>, bool)> {
    let (lo, hi) = caster;
    let (u, v) = in_plane_axes(r.axis);
    let (mut near, mut far) = (lo[r.axis], hi[r.axis]);
    if r.outward > 0.0 {
        near = near.max(r.at_mm);
    } else {
        far = far.min(r.at_mm);
    }
    if far - near <= 1e-6 {
        return None;
    }
    let touches = (near - r.at_mm).abs() < 1e-6 || (far - r.at_mm).abs() < 1e-6;
    let mut corners = Vec::with_capacity(8);
    for t in [near, far] {
        for x in [lo[u], hi[u]] {
            for y in [lo[v], hi[v]] {
                let along = (t - r.at_mm) / towards_light[r.axis];
                corners.push(DVec2::new(
                    x - towards_light[u] * along,
                    y - towards_light[v] * along,
                ));
            }
        }
    }
    Some((convex_hull(&corners), touches))
}

/// The edges, world mm, of the shadows `blocks` cast along `towards_light` (a unit vector
/// from the scene towards the light) on the floor and on each other's faces turned towards
/// it (module doc). A hull edge lying on a caster's own foot is left out; each edge is cut to
/// the receiving face.
pub(super) fn shadow_edges_mm(blocks: &[Block], towards_light: DVec3) -> Vec<[DVec3; 2]> {
    let boxes: Vec<(DVec3, DVec3)> = blocks.iter().map(bounds_mm).collect();
    let mut out = Vec::new();
    for r in receivers(&boxes) {
        if towards_light[r.axis] * r.outward <= GRAZING_COS {
            continue;
        }
        let (u, v) = in_plane_axes(r.axis);
        for (i, &(lo, hi)) in boxes.iter().enumerate() {
            if Some(i) == r.owner {
                continue;
            }
            let Some((hull, touches)) = cast_on((lo, hi), &r, towards_light) else {
                continue;
            };
            let foot = (DVec2::new(lo[u], lo[v]), DVec2::new(hi[u], hi[v]));
            let on_foot = |q: DVec2| within_box(q, foot, FOOT_MARGIN_MM);
            for k in 0..hull.len() {
                let (a, b) = (hull[k], hull[(k + 1) % hull.len()]);
                if touches && on_foot(a) && on_foot(b) {
                    continue;
                }
                let cut = match r.extent_mm {
                    Some((flo, fhi)) => clip_segment_to_box(a, b, flo, fhi)
                        .map(|(t0, t1)| (a.lerp(b, t0), a.lerp(b, t1))),
                    None => Some((a, b)),
                };
                out.extend(cut.map(|(a, b)| [on_plane(&r, a), on_plane(&r, b)]));
            }
        }
    }
    out
}

/// `true` when `q` lies in the box `(lo, hi)` grown by `margin`.
fn within_box(q: DVec2, (lo, hi): (DVec2, DVec2), margin: f64) -> bool {
    q.cmpge(lo - margin).all() && q.cmple(hi + margin).all()
}

/// The lines of `view`'s drawing that lie along the edge of a shadow `blocks` cast under the
/// view's known lights ([`shadow_edges_mm`] drawn through its camera): at least
/// [`ON_EDGE_SHARE`] of a line's samples within [`NEAR_TOL_FACTOR`] `tol_px` of a predicted
/// edge running its way. None when the view's lights are unknown.
pub(super) fn shadow_lines(view: &ObservedView, blocks: &[Block], tol_px: f64) -> Vec<usize> {
    if view.towards_lights.is_empty() || blocks.is_empty() {
        return Vec::new();
    }
    let projector = Projector::new(&view.camera);
    let edges: Vec<(DVec2, DVec2)> = view
        .towards_lights
        .iter()
        .flat_map(|&l| shadow_edges_mm(blocks, l))
        .map(|[a, b]| (projector.picture(a), projector.picture(b)))
        .filter(|(a, b)| a.distance(*b) > SHORTEST_EDGE_PX)
        .collect();
    let d = &view.drawing;
    (0..d.lines.len())
        .filter(|&l| {
            let [i, j] = d.lines[l];
            along_a_shadow_edge(d.points[i], d.points[j], &edges, NEAR_TOL_FACTOR * tol_px)
        })
        .collect()
}

/// `true` when at least [`ON_EDGE_SHARE`] of the samples of the picture segment `a`-`b`, one
/// per px, lie within `near_px` of one of `edges` running its way within
/// [`ALONG_WITHIN_DEG`].
fn along_a_shadow_edge(a: DVec2, b: DVec2, edges: &[(DVec2, DVec2)], near_px: f64) -> bool {
    let way = (b - a).normalize_or_zero();
    let turn = ALONG_WITHIN_DEG.to_radians().sin();
    let running: Vec<&(DVec2, DVec2)> = edges
        .iter()
        .filter(|(p, q)| way.perp_dot((*q - *p).normalize_or_zero()).abs() <= turn)
        .collect();
    if running.is_empty() {
        return false;
    }
    let n = (a.distance(b).ceil() as usize).max(1);
    let near = (0..=n)
        .map(|k| a.lerp(b, k as f64 / n as f64))
        .filter(|&s| {
            running
                .iter()
                .any(|(p, q)| distance_to_segment_px(s, *p, *q) <= near_px)
        })
        .count();
    near as f64 >= ON_EDGE_SHARE * (n + 1) as f64
}

/// `m`, the step-6 comparison of `view` with the drawing of `blocks`, without the observed
/// lines along the edges of the shadows `blocks` cast ([`shadow_lines`]), and without the
/// observed points that only such lines meet.
pub(super) fn without_shadow_lines(
    m: &mut ViewMismatch,
    view: &ObservedView,
    blocks: &[Block],
    tol_px: f64,
) {
    let shadow = shadow_lines(view, blocks, tol_px);
    if shadow.is_empty() {
        return;
    }
    m.unexplained_lines.retain(|l| !shadow.contains(l));
    let d = &view.drawing;
    let left = &m.unexplained_lines;
    m.unexplained_points.retain(|&p| {
        let meeting: Vec<usize> = (0..d.lines.len())
            .filter(|&l| d.lines[l].contains(&p))
            .collect();
        !meeting.iter().any(|l| shadow.contains(l)) || meeting.iter().any(|l| left.contains(l))
    });
}

/// Each view's picture-aware comparison of `blocks`, drawn as `drawn`, with the observed
/// drawing ([`pictures_mismatch`]), the lines along the edges of the shadows `blocks` cast
/// under the view's known lights left out ([`without_shadow_lines`]): step 6's check of an
/// answer and of its alternatives, one home so that both are held to the same check.
pub(super) fn mismatches_under_known_lights(
    blocks: &[Block],
    drawn: &[LineDrawing],
    views: &[ObservedView],
    pictures: &[ViewPicture],
    tol_px: f64,
) -> Vec<ViewMismatch> {
    let observed: Vec<&LineDrawing> = views.iter().map(|v| &v.drawing).collect();
    let mut mismatches = pictures_mismatch(drawn, &observed, pictures, tol_px);
    for (m, v) in mismatches.iter_mut().zip(views) {
        without_shadow_lines(m, v, blocks, tol_px);
    }
    mismatches
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::recognize::{grid_cubes, views_of, CornerView};
    use crate::scene::{same_blocks, ReconStatus};

    fn has_edge(edges: &[[DVec3; 2]], a: DVec3, b: DVec3) -> bool {
        let close = |p: DVec3, q: DVec3| p.distance(q) < 1e-9;
        edges
            .iter()
            .any(|&[p, q]| close(p, a) && close(q, b) || close(p, b) && close(q, a))
    }

    /// A 15 mm cube on the floor under a light 45 degrees up towards +x: its shadow on the
    /// floor is the rectangle from its foot to 15 mm beyond it towards -x; the far edge and the
    /// two long sides are shadow edges, the foot's edge under the cube is not.
    #[test]
    fn a_cube_on_the_floor_casts_the_rectangle_its_height_draws() {
        let cube = [Block::new("b15", DVec3::new(0.0, 7.5, 0.0), 0.0)];
        let light = DVec3::new(1.0, 1.0, 0.0).normalize();
        let edges = shadow_edges_mm(&cube, light);
        assert_eq!(edges.len(), 3, "{edges:?}");
        let at = |x: f64, z: f64| DVec3::new(x, 0.0, z);
        assert!(has_edge(&edges, at(-22.5, -7.5), at(-22.5, 7.5)));
        assert!(has_edge(&edges, at(-22.5, -7.5), at(7.5, -7.5)));
        assert!(has_edge(&edges, at(-22.5, 7.5), at(7.5, 7.5)));
        // A light grazing the floor casts no edge worth predicting.
        let low = DVec3::new(1.0, 0.01, 0.0).normalize();
        assert!(shadow_edges_mm(&cube, low).is_empty());
    }

    /// Two cubes side by side, a third on the right one, the light up and towards +x: the
    /// upper cube's shadow ends across the left cube's top face, half way along it.
    #[test]
    fn an_upper_block_casts_an_edge_across_a_lower_top_face() {
        let mut blocks = grid_cubes(0, &[0, 1]);
        blocks.extend(grid_cubes(1, &[1]));
        let light = DVec3::new(1.0, 2.0, 0.0).normalize();
        let edges = shadow_edges_mm(&blocks, light);
        let at = |z: f64| DVec3::new(0.0, 15.0, z);
        assert!(has_edge(&edges, at(-7.5), at(7.5)), "{edges:?}");
        // Nothing is cast on the faces turned from the light (the -x sides).
        assert!(edges
            .iter()
            .all(|[p, q]| !(p.x == -7.5 && q.x == -7.5 && p.y > 0.0)));
    }

    /// A drawn line along the predicted edge is a shadow line; the same line 6 px off it (twice
    /// the 3 px a sample may lie off at a 2 px tolerance), or with the lights unknown, is not.
    #[test]
    fn a_line_on_the_predicted_edge_is_a_shadow_line_and_one_beside_it_is_not() {
        let mut blocks = grid_cubes(0, &[0, 1]);
        blocks.extend(grid_cubes(1, &[1]));
        let light = DVec3::new(1.0, 2.0, 0.0).normalize();
        let view = &views_of(&blocks, &[CornerView::Sw])[0];
        let projector = Projector::new(&view.camera);
        let a = projector.picture(DVec3::new(0.0, 15.0, -7.5));
        let b = projector.picture(DVec3::new(0.0, 15.0, 7.5));
        let off = DVec2::new(0.0, 6.0);
        let lit = |v: ObservedView| ObservedView {
            towards_lights: vec![light],
            ..v
        };
        // The index of the added line, found by its ends.
        let added = |v: &ObservedView, from: DVec2, to: DVec2| {
            let d = &v.drawing;
            let close = |i: usize, q: DVec2| d.points[i].distance(q) < 0.5;
            (0..d.lines.len())
                .find(|&l| {
                    let [i, j] = d.lines[l];
                    close(i, from) && close(j, to) || close(i, to) && close(j, from)
                })
                .unwrap()
        };
        let on = lit(crate::recognize::with_line(view, a, b));
        let beside = lit(crate::recognize::with_line(view, a + off, b + off));
        assert!(shadow_lines(&on, &blocks, 2.0).contains(&added(&on, a, b)));
        let l = added(&beside, a + off, b + off);
        assert!(!shadow_lines(&beside, &blocks, 2.0).contains(&l));
        let unknown = crate::recognize::with_line(view, a, b);
        assert!(shadow_lines(&unknown, &blocks, 2.0).is_empty());
    }

    /// Pictures of the three cubes from the west under the light up and towards +x, with the
    /// upper cube's shadow painted on the left cube's top face (gray 100 on 150) and its edge
    /// in the drawings: with the light known the answer is the three cubes; with it unknown the
    /// edge across the top face is a line no answer explains, and the recognizer declines.
    #[test]
    fn a_shadow_edge_across_a_top_face_is_set_aside_only_under_the_known_light() {
        let mut truth = grid_cubes(0, &[0, 1]);
        truth.extend(grid_cubes(1, &[1]));
        let light = DVec3::new(1.0, 2.0, 0.0).normalize();
        let views = views_of(&truth, &[CornerView::Sw, CornerView::Nw]);
        let strip = [(0.0, -7.5), (7.5, -7.5), (7.5, 7.5), (0.0, 7.5)];
        let shadowed: Vec<(ObservedView, image::GrayImage)> = views
            .iter()
            .map(|v| {
                let projector = Projector::new(&v.camera);
                let at = |x: f64, z: f64| projector.picture(DVec3::new(x, 15.0, z));
                let hull = convex_hull(&strip.map(|(x, z)| at(x, z)));
                let d = &v.drawing;
                let picture = crate::recognize::painted_picture(&v.camera, 150, |p| {
                    let inked = d
                        .lines
                        .iter()
                        .any(|&[i, j]| distance_to_segment_px(p, d.points[i], d.points[j]) <= 0.8);
                    let shade = crate::geom::inside_convex(&hull, p, 0.0);
                    inked.then_some(40).or(shade.then_some(100))
                });
                let seen = crate::recognize::with_line(v, at(0.0, -7.5), at(0.0, 7.5));
                (seen, picture)
            })
            .collect();
        let answer = |lights: Vec<DVec3>| {
            let seen: Vec<ObservedView> = shadowed
                .iter()
                .map(|(v, _)| ObservedView {
                    towards_lights: lights.clone(),
                    ..v.clone()
                })
                .collect();
            let pictures: Vec<&image::GrayImage> = shadowed.iter().map(|(_, p)| p).collect();
            let opts = crate::recognize::RecognizeOptions::default();
            crate::recognize::recognize_in_pictures(&seen, &pictures, &opts).unwrap()
        };
        let known = answer(vec![light]);
        assert_eq!(known.status, ReconStatus::Ok, "{:?}", known.reason);
        assert!(
            same_blocks(&known.blocks, &truth, 0.1),
            "{:?}",
            known.blocks
        );
        let unknown = answer(Vec::new());
        assert_eq!(
            unknown.status,
            ReconStatus::Unsupported,
            "{:?}",
            unknown.blocks
        );
        let reason = unknown.reason.unwrap_or_default();
        assert!(reason.contains("1 lines unexplained"), "{reason}");
    }
}
