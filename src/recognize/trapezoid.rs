//! Telling a trapezoidal block from a solid one by the gradient of its sloped face (thesis
//! Chapter VII, Figure 7.1: "Because of the gradient constraints, solid blocks and trapezoidal
//! blocks can be distinguished").
//!
//! Every line of a scene of blocks in one direction depicts one of a few world directions: the
//! three axes of the solid blocks, and the 45-degree slope of a trapezoidal block (`w30`, README
//! "Block catalog") facing +-x or +-z, a fourth and fifth picture direction in each view. Two
//! lines meeting at an L, fork or arrow junction span a face plane; its gradient `(p, q)` in
//! the camera frame (`z = p x + q y`, x right, y up, z towards the eye, as in Chapter II's
//! gradient space) is that of an axis plane for every face of a solid block, and another one
//! exactly when a face is sloped.

use super::Camera;
use crate::drawing::{EdgeAxis, Junction, LineDrawing};
use crate::geom::{DVec2, DVec3};

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
/// [`EdgeAxis::TRAPEZOID_SLOPES`]; in perspective views each direction is taken towards its vanishing point, as in
/// `lines_off_the_axes`.
pub fn line_world_direction(
    drawing: &LineDrawing,
    camera: &Camera,
    line: usize,
    tol_deg: f64,
) -> Option<DVec3> {
    let [a, b] = drawing.lines[line];
    let (pa, pb) = (drawing.points[a], drawing.points[b]);
    let target = DVec3::from_array(camera.target_mm);
    let mid = (pa + pb) / 2.0;
    let (o, d) = camera.ray_through_picture(mid.x, mid.y);
    let at = o + d * (target - o).dot(d);
    let p0 = camera.picture_from_world(at).truncate();
    let best = |dirs: &mut dyn Iterator<Item = DVec3>| {
        dirs.map(|dir| {
            let q: DVec2 = camera.picture_from_world(at + dir).truncate() - p0;
            let ang = q.angle_to(pb - pa).abs().to_degrees();
            (dir, ang.min(180.0 - ang))
        })
        .filter(|&(_, ang)| ang <= tol_deg)
        .min_by(|x, y| x.1.total_cmp(&y.1))
        .map(|(dir, _)| dir)
    };
    // An axis first: where a slope projects parallel to an axis (in isometric corner views a
    // 45-degree slope in a vertical plane does, in two of the four views), the line is read as
    // the solid blocks' axis, so no sloped face is ever invented.
    let slopes = EdgeAxis::TRAPEZOID_SLOPES.map(EdgeAxis::world_direction);
    best(&mut [DVec3::X, DVec3::Y, DVec3::Z].into_iter()).or_else(|| best(&mut slopes.into_iter()))
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
                let sloped = [DVec3::X, DVec3::Y, DVec3::Z]
                    .iter()
                    .all(|axis| n.dot(*axis).abs() < (tol_deg.to_radians()).cos());
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
