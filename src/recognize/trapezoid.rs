//! Telling a trapezoidal block from a solid one by the gradient of its sloped face (thesis
//! Chapter VII, Figure 7.1: "Because of the gradient constraints, solid blocks and trapezoidal
//! blocks can be distinguished").
//!
//! Every line of a scene of blocks in one direction depicts one of a few world directions: the
//! three axes of the solid blocks, and the 45-degree slope of a trapezoidal block (`w30`, docs/formats.md
//! "Block catalog") facing +-x or +-z, a fourth and fifth picture direction in each view. Two
//! lines meeting at an L, fork or arrow junction span a face plane; its gradient `(p, q)` in
//! the camera frame (`z = p x + q y`, x right, y up, z towards the eye, as in Chapter II's
//! gradient space) is that of an axis plane for every face of a solid block, and another one
//! exactly when a face is sloped.
//!
//! The sloped face also says which way the block faces and, with the parallelogram it is (a
//! horizontal edge and a sloped one meeting at a corner), where it stands: [`facing_yaw_deg`]
//! and [`trapezoid_proposals`], the trapezoidal block's entry into the recognizer's pool.

use super::catalog_match::{MatchTolerances, Proposal};
use super::constraints::picture_angles_deg;
use super::parallelogram::{horizontal_axis_on, ray_at_height};
use super::Camera;
use crate::camera::Projector;
use crate::drawing::{EdgeAxis, Junction, LineDrawing};
use crate::geom::{DQuat, DVec2, DVec3};
use crate::scene::{Block, BlockType, Orientation, Shape, CATALOG};

/// A face plane spanned by two lines meeting at a junction, with its gradient.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FaceGradient {
    /// The junction point.
    pub point: usize,
    /// The two lines.
    pub lines: [usize; 2],
    /// Unit world normal of the plane, turned towards the eye.
    pub normal: DVec3,
    /// Gradient `(p, q)` of the plane in the camera frame (Chapter II's gradient space).
    pub gradient: DVec2,
    /// Whether the plane is none of the axis planes: a sloped face (Figure 7.1).
    pub sloped: bool,
}

/// The world direction (unit) whose picture direction at line `line`'s middle is nearest the
/// line's, within `tol_deg`: the nearest axis if one is that close, else the nearest of
/// [`EdgeAxis::TRAPEZOID_SLOPES`]; in perspective views each direction is taken towards its
/// vanishing point ([`picture_angles_deg`]).
pub fn line_world_direction(
    drawing: &LineDrawing,
    camera: &Camera,
    line: usize,
    tol_deg: f64,
) -> Option<DVec3> {
    let [a, b] = drawing.lines[line];
    let ends = (drawing.points[a], drawing.points[b]);
    let best = |dirs: &[DVec3]| {
        dirs.iter()
            .zip(picture_angles_deg(camera, ends, dirs))
            .filter(|&(_, ang)| ang <= tol_deg)
            .min_by(|x, y| x.1.total_cmp(&y.1))
            .map(|(dir, _)| *dir)
    };
    // An axis first: where a slope projects parallel to an axis (in isometric corner views a
    // 45-degree slope in a vertical plane does, in two of the four views), the line is read as
    // the solid blocks' axis, so no sloped face is ever invented.
    let slopes = EdgeAxis::TRAPEZOID_SLOPES.map(EdgeAxis::world_direction);
    best(&[DVec3::X, DVec3::Y, DVec3::Z]).or_else(|| best(&slopes))
}

/// The face planes spanned at the L, fork and arrow junctions of `drawing` by pairs of lines
/// whose world directions [`line_world_direction`] knows, with their gradients in `camera`.
pub fn face_gradients(drawing: &LineDrawing, camera: &Camera, tol_deg: f64) -> Vec<FaceGradient> {
    let dirs: Vec<Option<DVec3>> = (0..drawing.lines.len())
        .map(|l| line_world_direction(drawing, camera, l, tol_deg))
        .collect();
    let mut incident: Vec<Vec<usize>> = vec![Vec::new(); drawing.points.len()];
    for (li, &[a, b]) in drawing.lines.iter().enumerate() {
        incident[a].push(li);
        incident[b].push(li);
    }
    let [right, up, towards] = camera.axes_in_world();
    let mut out = Vec::new();
    for (point, lines) in incident.iter().enumerate() {
        let corner = matches!(
            drawing.junctions.get(point),
            Some(Junction::L | Junction::Fork | Junction::Arrow)
        );
        if !corner {
            continue;
        }
        for (i, &l1) in lines.iter().enumerate() {
            for &l2 in &lines[i + 1..] {
                let (Some(d1), Some(d2)) = (dirs[l1], dirs[l2]) else {
                    continue;
                };
                let n = d1.cross(d2);
                if n.length() < 1e-6 {
                    continue;
                }
                let n = n.normalize() * n.dot(towards).signum();
                let c = DVec3::new(n.dot(right), n.dot(up), n.dot(towards));
                let sloped = off_every_axis(n, tol_deg);
                out.push(FaceGradient {
                    point,
                    lines: [l1, l2],
                    normal: n,
                    gradient: DVec2::new(-c.x / c.z, -c.y / c.z),
                    sloped,
                });
            }
        }
    }
    out
}

/// The sloped face planes of `drawing` ([`face_gradients`] that are no axis plane): a
/// trapezoidal block, told from a solid one by its gradient (Figure 7.1).
pub fn sloped_faces(drawing: &LineDrawing, camera: &Camera, tol_deg: f64) -> Vec<FaceGradient> {
    face_gradients(drawing, camera, tol_deg)
        .into_iter()
        .filter(|g| g.sloped)
        .collect()
}

/// `true` when `d` (unit) lies along none of the world axes within `tol_deg`.
fn off_every_axis(d: DVec3, tol_deg: f64) -> bool {
    let cos = tol_deg.to_radians().cos();
    [DVec3::X, DVec3::Y, DVec3::Z]
        .iter()
        .all(|axis| d.dot(*axis).abs() < cos)
}

/// Lines of `drawing` that [`line_world_direction`] reads as a trapezoidal block's sloped edge
/// (none of the axes): the fourth and fifth picture direction of Figure 7.1, which the
/// one-direction check of Chapter VII leaves to the trapezoidal block once a sloped face is
/// seen.
pub fn sloped_lines(drawing: &LineDrawing, camera: &Camera, tol_deg: f64) -> Vec<usize> {
    (0..drawing.lines.len())
        .filter(|&l| {
            line_world_direction(drawing, camera, l, tol_deg)
                .is_some_and(|d| off_every_axis(d, tol_deg))
        })
        .collect()
}

/// The trapezoidal blocks of the catalog (docs/formats.md "Block catalog": the wedge `w30`), each with
/// its one sloped face (a face whose normal is none of the local axes).
pub fn trapezoidal_blocks() -> impl Iterator<Item = (&'static BlockType, usize)> {
    CATALOG.iter().filter_map(|t| {
        if !matches!(t.shape, Shape::ConvexPolyhedron(_)) || t.cuboid_half_extents_mm().is_some() {
            return None;
        }
        let sloped: Vec<usize> = (0..t.faces().len())
            .filter(|&f| off_every_axis(t.face_normal(f), 1.0))
            .collect();
        match sloped[..] {
            [f] => Some((t, f)),
            _ => None,
        }
    })
}

/// The yaws a block in one direction can have, degrees (Chapter VII: blocks in one direction;
/// a trapezoidal block's four ways of facing).
const QUARTER_TURNS_DEG: [f64; 4] = [0.0, 90.0, 180.0, 270.0];

/// The yaw, degrees (0, 90, 180 or 270), that turns the sloped face `face` of block type `t`
/// to the plane of `g`, within `tol_deg`: which way the trapezoidal block faces, read from the
/// sloped face's gradient (Figure 7.1). The face's outward normal points up (the slope falls
/// away from the block's top), which fixes the sign of the plane's normal.
pub fn facing_yaw_deg(t: &BlockType, face: usize, g: &FaceGradient, tol_deg: f64) -> Option<f64> {
    let outward = g.normal * g.normal.y.signum();
    let local = t.face_normal(face);
    QUARTER_TURNS_DEG.into_iter().find(|&yaw| {
        let n = DQuat::from_rotation_y(yaw.to_radians()) * local;
        n.dot(outward) >= tol_deg.to_radians().cos()
    })
}

/// The corner of a trapezoidal block's sloped face seen at a junction: `ridge` when the sloped
/// edge runs down from it (the top end), else the foot; `along` the world axis of the face's
/// horizontal edge from it.
#[derive(Debug, Clone, Copy, PartialEq)]
struct SlopeCorner {
    ridge: bool,
    along: DVec3,
}

/// The local vertex of sloped face `face` of `t`, turned by `turn`, at the corner `c`: the
/// top (ridge) or bottom (foot) vertex whose partner on the same height lies along `c.along`;
/// with the face's edge lengths, mm (horizontal, sloped).
fn corner_vertex(t: &BlockType, face: usize, turn: DQuat, c: SlopeCorner) -> (DVec3, [f64; 2]) {
    let verts: Vec<DVec3> = t.faces()[face]
        .iter()
        .map(|&i| turn * DVec3::from_array(t.vertices_mm()[i as usize]))
        .collect();
    let top = verts.iter().map(|v| v.y).fold(f64::NEG_INFINITY, f64::max);
    let bottom = verts.iter().map(|v| v.y).fold(f64::INFINITY, f64::min);
    let level = if c.ridge { top } else { bottom };
    let same: Vec<DVec3> = verts
        .iter()
        .copied()
        .filter(|v| (v.y - level).abs() < 1e-9)
        .collect();
    let mut at = same[0];
    if let [a, b] = same[..] {
        at = if (b - a).dot(c.along) > 0.0 { a } else { b };
    }
    let horizontal = same.iter().map(|v| v.distance(at)).fold(0.0, f64::max);
    let other = verts
        .iter()
        .copied()
        .filter(|v| (v.y - level).abs() >= 1e-9)
        .map(|v| v.distance(at))
        .fold(f64::INFINITY, f64::min);
    (at, [horizontal, other])
}

/// A sloped face plane seen at a junction: the junction `p`, the far ends of its horizontal
/// and sloped edges, picture px, and the sloped edge's world direction pointing up.
#[derive(Debug, Clone, Copy, PartialEq)]
struct SlopeJunction {
    p: DVec2,
    flat_end: DVec2,
    slope_end: DVec2,
    slope_up: DVec3,
}

impl SlopeJunction {
    /// The junction of `g` when one of its lines is horizontal and the other sloped.
    fn of(g: &FaceGradient, drawing: &LineDrawing, camera: &Camera, tol_deg: f64) -> Option<Self> {
        let dirs = g
            .lines
            .map(|l| line_world_direction(drawing, camera, l, tol_deg));
        let (d0, d1) = (dirs[0]?, dirs[1]?);
        let (flat, slope, slope_dir) = if d0.y.abs() < 1e-9 {
            (g.lines[0], g.lines[1], d1)
        } else if d1.y.abs() < 1e-9 {
            (g.lines[1], g.lines[0], d0)
        } else {
            return None;
        };
        let far_end = |l: usize| {
            let [a, b] = drawing.lines[l];
            drawing.points[if a == g.point { b } else { a }]
        };
        Some(SlopeJunction {
            p: drawing.points[g.point],
            flat_end: far_end(flat),
            slope_end: far_end(slope),
            slope_up: slope_dir * slope_dir.y.signum(),
        })
    }
}

/// A trapezoidal block read from one sloped face corner, with whether both of the face's
/// edges seen at the corner have the block's lengths.
struct CornerReading {
    block: Block,
    corner_mm: DVec3,
    exact: bool,
}

/// The block of type `t` whose sloped face `face`, turned by `yaw_deg`, has its corner at the
/// junction `j` with its bottom at `base_mm`: the sloped edge runs up from a foot and down
/// from a ridge, the horizontal edge gives the axis along the face. `None` when the corner is
/// on no ray at that height, the horizontal edge is along no world axis, or an edge is longer
/// than the block's (rule (1) of Chapter V: an edge may be occluded, never longer).
fn read_corner(
    proj: &Projector,
    j: &SlopeJunction,
    t: &'static BlockType,
    face: usize,
    yaw_deg: f64,
    base_mm: f64,
    tol: &MatchTolerances,
) -> Option<CornerReading> {
    let turn = DQuat::from_rotation_y(yaw_deg.to_radians());
    let probe = ray_at_height(proj.ray(j.p), base_mm)?;
    let up_px = proj.picture(probe + j.slope_up) - proj.picture(probe);
    let ridge = up_px.dot(j.slope_end - j.p) < 0.0;
    let (along, ang) = horizontal_axis_on(proj, probe, j.flat_end - j.p);
    if ang > tol.axis_deg {
        return None;
    }
    let (at, [flat_mm, slope_mm]) = corner_vertex(t, face, turn, SlopeCorner { ridge, along });
    let q = ray_at_height(proj.ray(j.p), base_mm + at.y - t.local_bounds_mm().0.y)?;
    let flat_seen = ray_at_height(proj.ray(j.flat_end), q.y)?.distance(q);
    // The sloped edge lies in the vertical plane across `along` through the corner.
    let (o, d) = proj.ray(j.slope_end);
    let denom = d.dot(along);
    let slope_seen = if denom.abs() < 1e-12 {
        0.0
    } else {
        (o + d * ((q - o).dot(along) / denom)).distance(q)
    };
    if flat_seen > flat_mm + tol.length_mm || slope_seen > slope_mm + tol.length_mm {
        return None;
    }
    let exact = (flat_mm - flat_seen).abs() <= tol.length_mm
        && (slope_mm - slope_seen).abs() <= tol.length_mm;
    let block = Block {
        block_type: t,
        center_mm: q - at,
        orientation: Orientation::YawDeg(yaw_deg),
    };
    Some(CornerReading {
        block,
        corner_mm: q,
        exact,
    })
}

/// The trapezoidal blocks the sloped faces of one view propose (Figure 7.1): each sloped face
/// plane found at a junction ([`sloped_faces`]) read as a corner of a catalog trapezoidal
/// block's sloped face, facing the way its gradient says ([`facing_yaw_deg`]), with the
/// block's bottom on the floor or at each of `levels_mm`, where `corner_ok` accepts the
/// corner (world mm). Both edges at the corner of
/// the block's lengths make the proposal an exact fit; the sloped face, its own, is a side no
/// ghost of a lower block shows.
pub fn trapezoid_proposals(
    drawing: &LineDrawing,
    camera: &Camera,
    levels_mm: &[f64],
    tol: &MatchTolerances,
    tol_deg: f64,
    corner_ok: &dyn Fn(DVec3) -> bool,
) -> Vec<Proposal> {
    let proj = Projector::new(camera);
    let mut out = Vec::new();
    for g in sloped_faces(drawing, camera, tol_deg) {
        let Some(j) = SlopeJunction::of(&g, drawing, camera, tol_deg) else {
            continue;
        };
        for (t, face) in trapezoidal_blocks() {
            let Some(yaw) = facing_yaw_deg(t, face, &g, tol_deg) else {
                continue;
            };
            let bases = std::iter::once(0.0).chain(levels_mm.iter().copied());
            for base in bases {
                let Some(r) = read_corner(&proj, &j, t, face, yaw, base, tol) else {
                    continue;
                };
                if !corner_ok(r.corner_mm) {
                    continue;
                }
                out.push(Proposal {
                    block: r.block,
                    closed_fit: r.exact,
                    side_fit: r.exact,
                });
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::recognize::{views_of, CornerView};
    use crate::scene::block_type;

    fn wedge(yaw_deg: f64) -> Block {
        Block::new("w30", DVec3::new(7.5, 7.5, -7.5), yaw_deg)
    }

    /// The wedge's sloped face, local outward normal (1, 1, 0) / sqrt 2, turned by each of the
    /// four quarter turns: in every corner view that shows it as a sloped plane, its gradient
    /// reads back that turn, and at least two of the four views show it.
    #[test]
    fn the_sloped_face_reads_which_of_the_four_ways_the_wedge_faces() {
        let (w30, face) = trapezoidal_blocks().next().unwrap();
        assert_eq!(w30.id, "w30");
        assert!(trapezoidal_blocks().all(|(t, _)| t.id == "w30"));
        for yaw in QUARTER_TURNS_DEG {
            let views = views_of(&[wedge(yaw)], &CornerView::ALL);
            let mut seen = 0;
            for v in &views {
                let sloped = sloped_faces(&v.drawing, &v.camera, 3.0);
                seen += usize::from(!sloped.is_empty());
                for g in &sloped {
                    assert_eq!(facing_yaw_deg(w30, face, g, 3.0), Some(yaw), "{v:?}");
                }
            }
            assert!(seen >= 2, "yaw {yaw}: {seen} views show the slope");
        }
        // An axis plane faces no way.
        let g = FaceGradient {
            point: 0,
            lines: [0, 1],
            normal: DVec3::Y,
            gradient: DVec2::ZERO,
            sloped: false,
        };
        assert_eq!(facing_yaw_deg(w30, face, &g, 3.0), None);
    }

    /// From each view showing the slope, the sloped face's corners propose the wedge at its
    /// place and turn, as an exact fit, among the proposals at other heights.
    #[test]
    fn the_sloped_face_places_the_wedge_at_its_height_and_turn() {
        let tol = MatchTolerances::default();
        let levels = [7.5, 15.0, 22.5, 30.0];
        for yaw in QUARTER_TURNS_DEG {
            for base in [0.0, 15.0] {
                let mut truth = wedge(yaw);
                truth.center_mm.y += base;
                for v in views_of(&[truth], &CornerView::ALL) {
                    let p =
                        trapezoid_proposals(&v.drawing, &v.camera, &levels, &tol, 3.0, &|_| true);
                    if sloped_faces(&v.drawing, &v.camera, 3.0).is_empty() {
                        assert!(p.is_empty());
                        continue;
                    }
                    let at_truth: Vec<&Proposal> = p
                        .iter()
                        .filter(|c| c.block.center_mm.distance(truth.center_mm) < 1e-6)
                        .collect();
                    assert!(!at_truth.is_empty(), "yaw {yaw} base {base}: {p:?}");
                    for c in at_truth {
                        assert_eq!(c.block.orientation, Orientation::YawDeg(yaw));
                        assert!(c.closed_fit && c.side_fit);
                    }
                    assert!(p.iter().all(|c| c.block.bottom_mm() > -1e-9));
                }
            }
        }
    }

    /// The solid blocks have no sloped face and are no trapezoidal block; a cube's drawing
    /// proposes no wedge.
    #[test]
    fn solid_blocks_propose_no_trapezoidal_block() {
        let b30 = block_type("b30").unwrap();
        assert!(trapezoidal_blocks().all(|(t, _)| t.id != b30.id));
        let cube = [Block::new("b30", DVec3::new(0.0, 7.5, 0.0), 90.0)];
        for v in views_of(&cube, &CornerView::ALL) {
            let tol = MatchTolerances::default();
            let p = trapezoid_proposals(&v.drawing, &v.camera, &[15.0], &tol, 3.0, &|_| true);
            assert!(p.is_empty());
            assert!(sloped_lines(&v.drawing, &v.camera, 3.0).is_empty());
        }
    }
}
