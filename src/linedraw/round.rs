//! The exact lines of a round part (Chapter VII's "circles"): its two rims, circles that project
//! to ellipses, and the two silhouette generators of its side, which depend on the view. Both in
//! closed form, not from the tessellation: the rims as chains of chords whose every end lies
//! exactly on the circle (at the catalog prism's 64 ring angles and at the generators' exact
//! tangent angles; a chord strays from the arc by at most `r (1 - cos(pi / 64))`, 0.009 mm for
//! 7.5 mm), the generators at the angles where the side's normal is perpendicular to the line
//! of sight:
//!
//! - orthographic, towards-eye direction `d`: `n(theta) . d = 0`, so `theta = phi +- pi / 2`
//!   with `phi = atan2(d . e2, d . e1)`;
//! - perspective, eye `E`, axis through `C`: `n(theta) . (E - P(theta)) = 0`, i.e.
//!   `rho cos(theta - phi) = r` with `(rho, phi)` the polar form of `((E - C) . e1, (E - C) . e2)`,
//!   so `theta = phi +- acos(r / rho)` (the same at every height, as `n` is perpendicular to the
//!   axis).
//!
//! Here `P(theta) = C + r (cos theta e1 + sin theta e2) + s u` with the block's local x, z and y
//! axes `e1`, `e2`, `u`. Whether a piece of the bottom rim can be seen is decided by the exact
//! normal at its middle; hiding by other blocks and by the part itself uses the prism's faces
//! (within the same 0.009 mm).

use super::geometry::{Edge, Face};
use crate::camera::{Camera, Projector};
use crate::geom::DVec3;
use crate::scene::Block;
use std::f64::consts::TAU;

/// A tangent angle this close to a ring angle (in ring steps) replaces it, so no sliver chord is
/// made next to a generator.
const SNAP_STEPS: f64 = 0.25;

/// The world frame of a round part: centre, local x and z (the circle's plane) and y (axis).
struct Frame {
    centre: DVec3,
    e1: DVec3,
    e2: DVec3,
    axis: DVec3,
    radius_mm: f64,
}

impl Frame {
    fn normal(&self, theta: f64) -> DVec3 {
        self.e1 * theta.cos() + self.e2 * theta.sin()
    }

    fn point(&self, theta: f64, s_mm: f64) -> DVec3 {
        self.centre + self.normal(theta) * self.radius_mm + self.axis * s_mm
    }
}

/// The angles of the silhouette generators of the side in `camera` (none when the line of sight
/// runs along the axis or the eye is inside the cylinder), in `[0, 2 pi)`.
fn generator_angles(f: &Frame, camera: &Camera) -> Vec<f64> {
    let (d, half_width) = if camera.is_orthographic() {
        (camera.towards_eye(), std::f64::consts::FRAC_PI_2)
    } else {
        let d = camera.eye() - f.centre;
        let rho = d.dot(f.e1).hypot(d.dot(f.e2));
        if rho <= f.radius_mm {
            return Vec::new();
        }
        (d, (f.radius_mm / rho).acos())
    };
    let (a, b) = (d.dot(f.e1), d.dot(f.e2));
    if a.hypot(b) < 1e-12 {
        return Vec::new();
    }
    let phi = b.atan2(a);
    [phi - half_width, phi + half_width]
        .map(|t| t.rem_euclid(TAU))
        .to_vec()
}

/// The rim angles: the `n` ring angles with each generator angle inserted (or replacing a ring
/// angle within [`SNAP_STEPS`]), ascending in `[0, 2 pi)`.
fn rim_angles(n: usize, generators: &[f64]) -> Vec<f64> {
    let step = TAU / n as f64;
    let mut angles: Vec<f64> = (0..n).map(|k| k as f64 * step).collect();
    for &g in generators {
        let k = (g / step).round() as usize % n;
        let off = (g - k as f64 * step + TAU / 2.0).rem_euclid(TAU) - TAU / 2.0;
        if off.abs() <= SNAP_STEPS * step {
            angles[k] = g;
        } else {
            angles.push(g);
        }
    }
    angles.sort_by(f64::total_cmp);
    angles
}

/// Side facet (local face index) holding angle `theta` whose facing agrees with `front`, if one
/// of the facet holding it and its two neighbours does; else the facet holding it.
fn side_facet(theta: f64, n: usize, front: bool, faces: &[Face], first_face: usize) -> usize {
    let j = ((theta.rem_euclid(TAU) / (TAU / n as f64)).floor() as usize).min(n - 1);
    [j, (j + 1) % n, (j + n - 1) % n]
        .into_iter()
        .find(|&k| faces[first_face + k].front == front)
        .unwrap_or(j)
}

/// The nearest ring vertex (catalog index, bottom ring) to angle `theta`.
fn ring_vertex(theta: f64, n: usize) -> usize {
    (theta.rem_euclid(TAU) / (TAU / n as f64)).round() as usize % n
}

/// One edge of block `bi` between world points `a` and `b`.
fn edge(
    bi: usize,
    vertices: [usize; 2],
    faces: [usize; 2],
    [a, b]: [DVec3; 2],
    proj: &Projector,
    curved: bool,
) -> Edge {
    let ((pa, wa), (pb, wb)) = (proj.picture_and_w(a), proj.picture_and_w(b));
    Edge {
        block: bi,
        vertices,
        faces,
        a,
        b,
        pa,
        pb,
        wa,
        wb,
        curved,
    }
}

/// The edges of round part `block` (scene index `bi`, its prism's faces at
/// `faces[first_face..]`: the `n` side quads, then the bottom and the top) in `camera`: the
/// chords of both rims (curved) and the two generators (straight), appended to `out`.
pub(super) fn round_part_edges(
    block: &Block,
    bi: usize,
    faces: &[Face],
    first_face: usize,
    camera: &Camera,
    proj: &Projector,
    out: &mut Vec<Edge>,
) {
    let Some(round) = block.block_type.round() else {
        return;
    };
    let q = block.rotation();
    let f = Frame {
        centre: block.center_mm,
        e1: q * DVec3::X,
        e2: q * DVec3::Z,
        axis: q * DVec3::Y,
        radius_mm: round.radius_mm,
    };
    let n = block.block_type.faces().len() - 2;
    let half = round.height_mm / 2.0;
    let generators = generator_angles(&f, camera);
    let angles = rim_angles(n, &generators);
    for (cap, s, ring) in [(n, -half, 0), (n + 1, half, n)] {
        for k in 0..angles.len() {
            let (t0, t1) = (angles[k], angles[(k + 1) % angles.len()]);
            let t1 = if t1 <= t0 { t1 + TAU } else { t1 };
            let mid = (t0 + t1) / 2.0;
            let front = camera.faces_eye(f.normal(mid), f.point(mid, s));
            let side = side_facet(mid, n, front, faces, first_face);
            out.push(edge(
                bi,
                [ring + ring_vertex(t0, n), ring + ring_vertex(t1, n)],
                [first_face + cap, first_face + side],
                [f.point(t0, s), f.point(t1, s)],
                proj,
                true,
            ));
        }
    }
    for g in generators {
        let (faces, vertices) = generator_faces(&f, g, n, faces, first_face, camera);
        let ends = [f.point(g, -half), f.point(g, half)];
        out.push(edge(bi, vertices, faces, ends, proj, false));
    }
}

/// The two side facets (global face indices, the one facing the eye first) on either side of
/// the generator at angle `g`, and its nearest catalog ring vertices (bottom, top).
fn generator_faces(
    f: &Frame,
    g: f64,
    n: usize,
    faces: &[Face],
    first_face: usize,
    camera: &Camera,
) -> ([usize; 2], [usize; 2]) {
    let step = TAU / n as f64;
    let toward = |sign: f64| camera.faces_eye(f.normal(g + sign * step / 2.0), f.point(g, 0.0));
    let (lit, dark) = if toward(1.0) {
        (1.0, -1.0)
    } else {
        (-1.0, 1.0)
    };
    let at = |sign: f64, front: bool| {
        first_face + side_facet(g + sign * step / 2.0, n, front, faces, first_face)
    };
    let k = ring_vertex(g, n);
    ([at(lit, true), at(dark, false)], [k, n + k])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Ring angles with the tangent angles put in: one far from a ring angle is inserted, one
    /// within a quarter step replaces it; the result stays sorted.
    #[test]
    fn rim_angles_insert_or_snap_the_generator_angles() {
        let step = TAU / 8.0;
        let a = rim_angles(8, &[0.5 * step, 3.1 * step]);
        assert_eq!(a.len(), 9);
        assert!(a.windows(2).all(|w| w[0] < w[1]));
        assert!(a.contains(&(0.5 * step)) && a.contains(&(3.1 * step)));
        assert!(!a.contains(&(3.0 * step)));
    }
}
