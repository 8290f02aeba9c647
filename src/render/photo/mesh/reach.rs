//! Where a block's soft shadow can reach across the key light: the parts of a face or of the
//! floor that need the shadow test ([`super::photo_mesh`]).

use crate::geom::DVec3;

/// How far in front of a face's plane a point of another block must lie to count as an
/// occluder in [`shadow_reach`], mm. The shader's blockers lie in front of the plane through
/// the receiver moved out along its normal by 1.5 shadow-map texels, so at least a tenth of a
/// texel (the texel the tap reads may lie 1.4 texels from the tap) in front of the face: far
/// more than this. A block whose face is flush with the receiver's plane does not count.
pub(super) const OCCLUDER_FRONT_MM: f64 = 1e-4;

/// Coordinates across the key light: `u` and `v` span the plane normal to `along` (the unit
/// vector towards the light), `u x v = along`, so a polygon counter-clockwise seen from the
/// light stays counter-clockwise in `(u, v)`.
#[derive(Debug, Clone, Copy)]
pub(super) struct LightFrame {
    along: DVec3,
    u: DVec3,
    v: DVec3,
}

impl LightFrame {
    pub(super) fn new(towards_light: DVec3) -> LightFrame {
        let along = towards_light.normalize_or(DVec3::Y);
        let u = along.any_orthonormal_vector();
        LightFrame {
            along,
            u,
            v: along.cross(u),
        }
    }

    /// `p` across the light, mm.
    pub(super) fn across(&self, p: DVec3) -> glam::DVec2 {
        glam::DVec2::new(p.dot(self.u), p.dot(self.v))
    }

    /// The point of the plane through `on_plane` with normal `normal` (not across the light)
    /// that lies at `q` across the light.
    pub(super) fn onto_plane(&self, q: glam::DVec2, on_plane: DVec3, normal: DVec3) -> DVec3 {
        let p = self.u * q.x + self.v * q.y;
        p + self.along * (normal.dot(on_plane - p) / normal.dot(self.along))
    }
}

/// The convex region, across the light ([`LightFrame`]), where the soft shadow test on the
/// light-facing face `corners` (outward normal `outward`) can find a blocker: within
/// `reach_mm` of the part of some `occluders` solid (convex, given by its corners) that lies
/// in front of the face's plane (the solid clipped by the plane: its corners in front, and
/// where the segments between corners cross the plane). Empty when no solid reaches in front;
/// the hull of all of them otherwise (a 16-gon around each point, circumscribing the reach).
pub(super) fn shadow_reach(
    corners: &[DVec3],
    outward: DVec3,
    frame: &LightFrame,
    occluders: &[&[DVec3]],
    reach_mm: f64,
) -> Vec<glam::DVec2> {
    let outward = outward.normalize_or_zero();
    let mut front = Vec::new();
    for solid in occluders {
        let height: Vec<f64> = solid
            .iter()
            .map(|p| outward.dot(*p - corners[0]) - OCCLUDER_FRONT_MM)
            .collect();
        for (i, (p, hp)) in solid.iter().zip(&height).enumerate() {
            if *hp > 0.0 {
                front.push(frame.across(*p));
            }
            for (q, hq) in solid.iter().zip(&height).skip(i + 1) {
                if (*hp > 0.0) != (*hq > 0.0) {
                    front.push(frame.across(*p + (*q - *p) * (hp / (hp - hq))));
                }
            }
        }
    }
    if front.is_empty() {
        return Vec::new();
    }
    let radius = reach_mm / (std::f64::consts::PI / REACH_SIDES as f64).cos();
    let hull = crate::geom::convex_hull(&front);
    crate::geom::convex_hull(&grown_corners(&hull, radius))
}

/// The corners of the [`REACH_SIDES`]-gon of circumradius `radius` around each vertex of the
/// counter-clockwise convex polygon `hull` that can lie on the outline of their hull (the
/// polygon grown by the regular polygon: [`in_cone`]).
pub(super) fn grown_corners(hull: &[glam::DVec2], radius: f64) -> Vec<glam::DVec2> {
    hull.iter()
        .enumerate()
        .flat_map(|(i, c)| {
            let cone = vertex_cone(hull, i);
            REACH_DIRECTIONS
                .iter()
                .filter(move |d| cone.is_none_or(|(e_in, e_out)| in_cone(**d, e_in, e_out)))
                .map(move |d| *c + *d * radius)
        })
        .collect()
}

/// Sides of the polygon circumscribing the reach around each point in [`shadow_reach`].
pub(super) const REACH_SIDES: usize = 16;

/// The unit directions to the corners of [`REACH_SIDES`]-gon, counter-clockwise from +u.
pub(super) static REACH_DIRECTIONS: std::sync::LazyLock<[glam::DVec2; REACH_SIDES]> =
    std::sync::LazyLock::new(|| {
        std::array::from_fn(|k| {
            let a = std::f64::consts::TAU * k as f64 / REACH_SIDES as f64;
            glam::DVec2::new(a.cos(), a.sin())
        })
    });

/// The edges into and out of vertex `i` of the counter-clockwise convex polygon `hull`, which
/// bound the directions in which that vertex is the farthest ([`in_cone`]); `None` for fewer
/// than three vertices (every direction counts).
pub(super) fn vertex_cone(hull: &[glam::DVec2], i: usize) -> Option<(glam::DVec2, glam::DVec2)> {
    let n = hull.len();
    (n >= 3).then(|| (hull[i] - hull[(i + n - 1) % n], hull[(i + 1) % n] - hull[i]))
}

/// Whether moving the vertex between edges `e_in` and `e_out` (of a counter-clockwise convex
/// polygon) along `d`, a corner direction of the [`REACH_SIDES`]-gon, can give a corner of the
/// grown polygon (their Minkowski sum): only when the directions in which the vertex is the
/// polygon's farthest point meet those in which that corner is the regular polygon's, which
/// lie within half a side's angle of `d`. So each edge's half-plane of directions is widened
/// by that angle (and a millionth), and [`shadow_reach`] hulls only the points that pass: the
/// same hull as of every point, with far fewer to sort.
pub(super) fn in_cone(d: glam::DVec2, e_in: glam::DVec2, e_out: glam::DVec2) -> bool {
    // sin(pi / 16): half the angle between neighbouring corner directions.
    const HALF_SIDE_SIN: f64 = 0.195_090_322_016_128_25;
    const MARGIN: f64 = HALF_SIDE_SIN + 1e-6;
    const _: () = assert!(REACH_SIDES == 16, "HALF_SIDE_SIN is sin(pi / REACH_SIDES)");
    d.dot(e_in) >= -MARGIN * e_in.length() && d.dot(e_out) <= MARGIN * e_out.length()
}

/// The box `(lo, hi)` grown by `mm` on every side.
pub(super) fn grow_box((lo, hi): (DVec3, DVec3), mm: f64) -> (DVec3, DVec3) {
    (lo - DVec3::splat(mm), hi + DVec3::splat(mm))
}

/// Whether some box of `occluders` meets the box of `face` grown by `reach_mm` and swept
/// towards the light.
pub(super) fn may_be_shadowed(
    face: &[DVec3],
    towards_light: DVec3,
    reach_mm: f64,
    occluders: &[(DVec3, DVec3)],
) -> bool {
    let Some(bounds) = crate::geom::bounds3(face.iter().copied()) else {
        return false;
    };
    let grown = grow_box(bounds, reach_mm);
    occluders
        .iter()
        .any(|b| swept_box_meets(grown, towards_light, *b))
}

/// Whether box `(lo, hi)` moved by `t * dir` for some `t >= 0` overlaps box `other` (touching
/// counts): the slab test, one interval of `t` per axis.
pub(super) fn swept_box_meets(
    (lo, hi): (DVec3, DVec3),
    dir: DVec3,
    (olo, ohi): (DVec3, DVec3),
) -> bool {
    let (mut t0, mut t1) = (0.0f64, f64::INFINITY);
    for k in 0..3 {
        let d = dir[k];
        if d.abs() < 1e-12 {
            if lo[k] > ohi[k] || hi[k] < olo[k] {
                return false;
            }
            continue;
        }
        let (a, b) = ((olo[k] - hi[k]) / d, (ohi[k] - lo[k]) / d);
        t0 = t0.max(a.min(b));
        t1 = t1.min(a.max(b));
        if t0 > t1 {
            return false;
        }
    }
    true
}
