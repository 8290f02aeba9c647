//! Where a picture shows the outline of a block whose edges are rounded
//! (docs/recognizer-pictures.md "Known edge rounding"). A block with edges rounded by `r` is
//! its sharp solid shrunk by `r` and grown again by a ball of radius `r`; seen along a view,
//! an edge where a face turned to the camera meets one turned away (the block's own outline
//! there) shows as the shrunk edge's picture moved outwards by the ball's picture radius. For
//! a 90-degree edge seen from a corner view that puts the outline `r (sqrt 2 - 1)` inside the
//! sharp edge's, so a corner where two such outline lines meet lies about 0.5 r inside the
//! sharp corner: a third of a pixel at 3 px per mm and 0.2 mm. Placement (`placement`) fits
//! the blocks' shift to the corners the front end finds; with the rounding known, it expects
//! them there, not at the sharp corners, so the views' insets do not add up to a shift every
//! view shares. Edges between two faces turned to the camera are not moved: where their step
//! lies across the rounded band depends on how the two faces are lit.

use crate::camera::{Camera, Projector};
use crate::drawing::LineDrawing;
use crate::geom::{DMat2, DVec2, DVec3};
use crate::scene::Block;

/// The outward normal (picture px, unit) and outward move (px) of drawn line `k` of `drawn`
/// (`camera`'s redraw of `blocks`, `projector` its projection) when the blocks' edges are
/// rounded by `radius_mm`: `Some` only for an outline edge of its block (one of its two faces
/// turned to the camera).
fn outline_move_px(
    drawn: &LineDrawing,
    k: usize,
    blocks: &[Block],
    (camera, projector): (&Camera, &Projector),
    radius_mm: f64,
) -> Option<(DVec2, f64)> {
    let e = drawn.edges.get(k)?;
    let block = blocks.get(e.block)?;
    let [a, b] = e.vertices;
    let (fa, fb) = block
        .block_type
        .edges()
        .into_iter()
        .find(|&(i, j, _, _)| (i, j) == (a.min(b), a.max(b)))
        .map(|(_, _, f, g)| (f, g))?;
    let (na, nb) = (block.world_face_normal(fa), block.world_face_normal(fb));
    let on_edge = (DVec3::from(e.from_mm) + DVec3::from(e.to_mm)) / 2.0;
    if camera.faces_eye(na, on_edge) == camera.faces_eye(nb, on_edge) {
        return None;
    }
    let at = |w: DVec3| projector.picture(w);
    let [i, j] = drawn.lines[k];
    let along = (drawn.points[j] - drawn.points[i]).normalize_or_zero();
    let outward_mm = na + nb;
    let mut normal = along.perp();
    if normal.dot(at(on_edge + outward_mm) - at(on_edge)) < 0.0 {
        normal = -normal;
    }
    // The shrunk edge: `radius_mm` inside both faces' planes.
    let shrunk = on_edge - outward_mm * (radius_mm / (1.0 + na.dot(nb)));
    let ball_px = radius_mm * projector.px_per_mm(on_edge);
    let moved = normal.dot(at(shrunk) - at(on_edge)) + ball_px;
    (along != DVec2::ZERO && moved.is_finite()).then_some((normal, moved))
}

/// How far from its sharp picture the front end finds point `p` of `drawn` (`camera`'s redraw
/// of `blocks`, `projector` its projection, built once per view) when the blocks' edges are
/// rounded by `radius_mm`, px: the point where the outline lines at `p`, each moved as
/// [`outline_move_px`] says, meet (least squares); zero where no outline line ends, or for
/// sharp edges.
pub fn rounded_corner_offset_px(
    drawn: &LineDrawing,
    p: usize,
    blocks: &[Block],
    seen_by: (&Camera, &Projector),
    radius_mm: f64,
) -> DVec2 {
    if radius_mm <= 0.0 {
        return DVec2::ZERO;
    }
    let moves: Vec<(DVec2, f64)> = super::picture::lines_at(drawn, p)
        .filter_map(|k| outline_move_px(drawn, k, blocks, seen_by, radius_mm))
        .collect();
    // Normal equations of n_k . d = m_k; one line moves the point along its normal.
    let (normals, rhs) = moves
        .iter()
        .fold((DMat2::ZERO, DVec2::ZERO), |(a, b), &(n, m)| {
            (a + DMat2::from_cols(n * n.x, n * n.y), b + n * m)
        });
    match moves.as_slice() {
        [] => DVec2::ZERO,
        [(n, m)] => *n * *m,
        _ if normals.determinant().abs() < 1e-6 => {
            moves.iter().map(|&(n, m)| n * m).sum::<DVec2>() / moves.len() as f64
        }
        _ => normals.inverse() * rhs,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::CornerView;
    use crate::drawing::LineKind;
    use crate::recognize::{draw_hypothesis, views_of};

    /// How far a convex solid reaches along picture direction `m` (px), from its corners: the
    /// support function of its picture in an orthographic view.
    fn reach_px(corners: &[DVec3], camera: &Camera, m: DVec2) -> f64 {
        corners
            .iter()
            .map(|&c| m.dot(camera.picture_from_world(c).truncate()))
            .fold(f64::NEG_INFINITY, f64::max)
    }

    /// Each outline line of a cube moves as the rounded solid's outline does, computed apart
    /// from the faces: the shrunk cube's reach along the line's outward normal, plus the
    /// ball's picture radius, minus the sharp cube's reach; 0.2 mm at the corner views'
    /// scale moves every outline line 0.414 r inwards (the isometric views see every edge at
    /// the same slant).
    #[test]
    fn outline_lines_move_where_the_rounded_solid_reaches() {
        let r = 0.2;
        let cube = [Block::new("b15", DVec3::new(0.0, 7.5, 0.0), 0.0)];
        let shrunk: Vec<DVec3> = cube[0]
            .world_vertices()
            .iter()
            .map(|v| DVec3::new(0.0, 7.5, 0.0) + (*v - DVec3::new(0.0, 7.5, 0.0)) * (7.5 - r) / 7.5)
            .collect();
        for v in views_of(&cube, &CornerView::ALL) {
            let d = draw_hypothesis(&cube, &v.camera);
            let projector = Projector::new(&v.camera);
            let scale = projector.px_per_mm(DVec3::ZERO);
            let mut outline = 0;
            for k in 0..d.lines.len() {
                let moved = outline_move_px(&d, k, &cube, (&v.camera, &projector), r);
                if d.kinds[k] != LineKind::Boundary {
                    assert_eq!(moved, None, "an inner edge of {:?} moved", v.camera.view);
                    continue;
                }
                let (m, px) = moved.expect("an outline line moves");
                let expected = reach_px(&shrunk, &v.camera, m) + r * scale
                    - reach_px(&cube[0].world_vertices(), &v.camera, m);
                assert!((px - expected).abs() < 1e-6, "{px} vs {expected}");
                assert!((px + (2f64.sqrt() - 1.0) * r * scale).abs() < 1e-6, "{px}");
                outline += 1;
            }
            assert_eq!(outline, 6, "a cube's outline is a hexagon");
        }
    }

    /// A cube's outline corners move towards its picture's centre by r (sqrt 2 - 1) / sin 60
    /// degrees in picture mm (two outline lines meeting at 120 degrees); its near corner, where
    /// only inner edges meet, stays; sharp edges move nothing.
    #[test]
    fn outline_corners_move_in_and_the_near_corner_stays() {
        let r = 0.3;
        let cube = [Block::new("b15", DVec3::new(0.0, 7.5, 0.0), 0.0)];
        let v = &views_of(&cube, &[CornerView::Se])[0];
        let d = draw_hypothesis(&cube, &v.camera);
        let projector = Projector::new(&v.camera);
        let scale = projector.px_per_mm(DVec3::ZERO);
        let centre = d.points.iter().sum::<DVec2>() / d.points.len() as f64;
        let corner_px = (2f64.sqrt() - 1.0) * r * scale / 60f64.to_radians().sin();
        let mut still = 0;
        for p in 0..d.points.len() {
            assert_eq!(
                rounded_corner_offset_px(&d, p, &cube, (&v.camera, &projector), 0.0),
                DVec2::ZERO
            );
            let off = rounded_corner_offset_px(&d, p, &cube, (&v.camera, &projector), r);
            if off == DVec2::ZERO {
                still += 1;
                continue;
            }
            assert!(
                (off.length() - corner_px).abs() < 1e-6,
                "{off:?} vs {corner_px}"
            );
            let inwards = (centre - d.points[p]).normalize();
            assert!(
                off.normalize().dot(inwards) > 0.999,
                "{off:?} not towards the centre"
            );
        }
        assert_eq!(still, 1, "only the near corner stays");
    }
}
