//! Geometry conventions shared by every stage.
//!
//! * World units are **millimetres**; axes are right-handed with **+y up**, the floor is the
//!   plane y = 0, **+x is east** and **-z is north** (docs/formats.md "Conventions").
//! * Picture coordinates are **pixels, x right, y up**, with (0, 0) the bottom-left corner of the
//!   picture and pixel centres at +0.5 (the GPU viewport transform with y flipped). A raster row
//!   `r` (0 at the top) has its centres at `y_px = height_px - r - 0.5`.
//! * The thesis draws its Chapter II viewing pipeline with row vectors (`p' = p M`); this crate
//!   uses glam's column vectors (`p' = M p`), i.e. the transposed matrices.
//!
//! This module imports nothing from the crate; every other stage may import it.

pub use glam::{
    DMat2, DMat3, DMat4, DQuat, DVec2, DVec3, DVec4, Mat3, Mat4, Quat, Vec2, Vec3, Vec4,
};

/// Contact tolerance in millimetres: two faces closer than this (and parallel) count as
/// touching, and a penetration shallower than this is not an overlap. Settled rapier poses sit
/// 0.03 mm into their supports with the stiff contact parameters used in `physics`, so the
/// same tolerance serves validation, ground truth and settling (docs/formats.md "Conventions").
pub const CONTACT_TOL_MM: f64 = 0.05;

/// Newell's vector of a closed polygon: the sum of `p_i x p_(i+1)` around it, normal to a
/// planar polygon, pointing the way its loop turns counter-clockwise, twice its area long
/// (zero for a degenerate one). The one home of Newell's method: face normals of the catalog,
/// the exporters, the viewer and its hidden-line removal normalize it as each needs.
pub fn newell_vector(polygon: &[DVec3]) -> DVec3 {
    let mut n = DVec3::ZERO;
    for (i, a) in polygon.iter().enumerate() {
        n += a.cross(polygon[(i + 1) % polygon.len()]);
    }
    n
}

/// Half the side of the world's square floor, mm: every block vertex must have |x| and |z| at
/// most this, and y in `0..=WORLD_HEIGHT_MM` (docs/formats.md "Conventions", world extent). It is the
/// physics floor (a 20 m square, `physics`), and it keeps every coordinate far inside f32's
/// range, so cameras, pictures and glTF nodes stay finite (the renderer works in f32).
pub const WORLD_HALF_EXTENT_MM: f64 = 10_000.0;

/// The world's height, mm: no block vertex lies above this (docs/formats.md "Conventions").
pub const WORLD_HEIGHT_MM: f64 = 10_000.0;

/// `x.floor()` as an integer (saturating at the ends of `i64`, 0 for NaN, like `as i64`),
/// without the library call `f64::floor` compiles to on baseline x86-64: it runs for every
/// pixel sampled near a line (the vision front end's line finder, the recognizer's reading of
/// the picture).
#[inline(always)]
pub fn floor_i64(x: f64) -> i64 {
    let t = x as i64;
    t.saturating_sub(i64::from((t as f64) > x))
}

/// Gray level at picture point `p` (px, y up; the pixel whose square holds it), `None` outside
/// the picture. The one home of reading a picture at a point: the vision front end reads its
/// lines' profiles with it, the recognizer's picture-aware check its hypotheses' edges.
pub fn gray_at(gray: &image::GrayImage, p: DVec2) -> Option<f64> {
    gray_at_px(gray, floor_i64(p.x), floor_i64(p.y))
}

/// Gray level of the pixel in column `x` and picture row `y` (counted up from the bottom, as
/// picture y runs; docs/formats.md "Conventions"), `None` outside the picture: [`gray_at`] for a whole
/// pixel, for walks that step from pixel to pixel without a point.
#[inline]
pub fn gray_at_px(gray: &image::GrayImage, x: i64, y: i64) -> Option<f64> {
    let (w, h) = (i64::from(gray.width()), i64::from(gray.height()));
    if x < 0 || y < 0 || x >= w || y >= h {
        return None;
    }
    Some(f64::from(gray.as_raw()[((h - 1 - y) * w + x) as usize]))
}

/// Every this many rows of the picture are read by [`noise_levels`]: a quarter of a 512 x 480
/// picture's neighbour differences (61,000) pins their median as well as all of them do.
const NOISE_ROW_STEP: usize = 4;

/// The median of `values` as every stage takes it: the value at index `n / 2` of the sorted
/// values (for an even count the upper of the middle two), so the median of observed values is
/// one of them (a gray level stays a level, a time a measured time); `None` when empty. Sorts
/// `values` in place (`f64::total_cmp`: NaN last).
pub fn median(values: &mut [f64]) -> Option<f64> {
    values.sort_by(f64::total_cmp);
    values.get(values.len() / 2).copied()
}

/// The picture's noise sigma, gray levels: the [`median`] absolute difference of horizontally
/// neighbouring pixels (on every [`NOISE_ROW_STEP`]-th row) times 1.4826 / sqrt(2) (a face is
/// flat, so most differences are noise; a difference of two pixels has sigma sqrt(2) times
/// theirs).
pub fn noise_levels(gray: &image::GrayImage) -> f64 {
    let mut hist = [0usize; 256];
    let w = gray.width() as usize;
    if w < 2 {
        return 0.0;
    }
    for row in gray.as_raw().chunks(w).step_by(NOISE_ROW_STEP) {
        for pair in row.windows(2) {
            hist[usize::from(pair[0].abs_diff(pair[1]))] += 1;
        }
    }
    let total: usize = hist.iter().sum();
    let mut seen = 0;
    for (d, &c) in hist.iter().enumerate() {
        seen += c;
        if 2 * seen > total {
            return d as f64 * 1.4826 / std::f64::consts::SQRT_2;
        }
    }
    0.0
}

/// Which world bound a point breaks, as text such as `"x = 12000 mm is beyond +/-10000 mm"`;
/// `None` when the point lies in the world (see [`WORLD_HALF_EXTENT_MM`]).
pub fn outside_world(p_mm: DVec3) -> Option<String> {
    let h = WORLD_HALF_EXTENT_MM;
    if p_mm.x.abs() > h {
        return Some(format!("x = {} mm is beyond +/-{h} mm", p_mm.x));
    }
    if p_mm.z.abs() > h {
        return Some(format!("z = {} mm is beyond +/-{h} mm", p_mm.z));
    }
    if p_mm.y > WORLD_HEIGHT_MM {
        return Some(format!("y = {} mm is above {WORLD_HEIGHT_MM} mm", p_mm.y));
    }
    None
}

/// The exact isometric elevation, atan(1/sqrt(2)) = 35.26438968 degrees. "35.264" is a
/// rounding of this angle; using the rounded value makes coincident points drift 0.001 px
/// apart (docs/formats.md "Conventions").
pub const ISOMETRIC_ELEVATION_DEG: f64 = 35.264_389_682_754_654;

/// The heading of a rotation: the angle of the turned local +x axis about +y, degrees
/// (counter-clockwise seen from above, the sense of `yaw_deg` in scene files); tilt ignored.
pub fn heading_deg(q: DQuat) -> f64 {
    let x = q * DVec3::X;
    (-x.z).atan2(x.x).to_degrees()
}

/// Converts a unit quaternion to the yaw about +y in degrees, if the rotation is a pure yaw
/// (within `tol_deg` of the y axis); `None` for any tilt.
pub fn pure_yaw_deg(q: Quat, tol_deg: f64) -> Option<f64> {
    let q = q.as_dquat().normalize();
    let up = q * DVec3::Y;
    if up.angle_between(DVec3::Y).to_degrees() > tol_deg {
        return None;
    }
    Some(heading_deg(q))
}

/// Axis-aligned bounds (min, max) of `points`; `None` when there are none.
pub fn bounds3(points: impl IntoIterator<Item = DVec3>) -> Option<(DVec3, DVec3)> {
    points.into_iter().fold(None, |acc, v| match acc {
        None => Some((v, v)),
        Some((lo, hi)) => Some((lo.min(v), hi.max(v))),
    })
}

/// The pairs `[a, b]` (a < b, sorted) of axis-aligned boxes `(min, max)` that touch or
/// overlap, found by a sweep along x (sort by min x, keep the boxes still open): the same pairs
/// as comparing every pair, in time near linear for stacks spread over the floor.
pub fn touching_box_pairs(boxes: &[(DVec3, DVec3)]) -> Vec<[usize; 2]> {
    let disjoint = |(lo_a, hi_a): (DVec3, DVec3), (lo_b, hi_b): (DVec3, DVec3)| {
        hi_a.cmplt(lo_b).any() || hi_b.cmplt(lo_a).any()
    };
    let mut order: Vec<usize> = (0..boxes.len()).collect();
    order.sort_by(|&i, &j| boxes[i].0.x.total_cmp(&boxes[j].0.x).then(i.cmp(&j)));
    let mut open: Vec<usize> = Vec::new();
    let mut pairs = Vec::new();
    for &i in &order {
        open.retain(|&j| boxes[j].1.x >= boxes[i].0.x);
        pairs.extend(
            open.iter()
                .filter(|&&j| !disjoint(boxes[i], boxes[j]))
                .map(|&j| [i.min(j), i.max(j)]),
        );
        open.push(i);
    }
    pairs.sort_unstable();
    pairs
}

/// Distance (px) from the picture point `p` to the segment `a`-`b`: to the foot of the
/// perpendicular when it falls on the segment, else to the nearer end (to `a` when the segment
/// has no length). The one home of this distance in src and tests.
pub fn distance_to_segment_px(p: DVec2, a: DVec2, b: DVec2) -> f64 {
    let ab = b - a;
    let len2 = ab.length_squared();
    if len2 == 0.0 {
        return p.distance(a);
    }
    let t = ((p - a).dot(ab) / len2).clamp(0.0, 1.0);
    p.distance(a + ab * t)
}

/// Liang–Barsky clipping of segment `p`–`q` to the axis-aligned box `[lo, hi]`: the parameter
/// interval `[t0, t1]` of the segment inside it, or `None` when the segment misses the box.
pub fn clip_segment_to_box(p: DVec2, q: DVec2, lo: DVec2, hi: DVec2) -> Option<(f64, f64)> {
    let d = q - p;
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    let bounds = [
        (-d.x, p.x - lo.x),
        (d.x, hi.x - p.x),
        (-d.y, p.y - lo.y),
        (d.y, hi.y - p.y),
    ];
    for (den, num) in bounds {
        if den == 0.0 {
            if num < 0.0 {
                return None;
            }
            continue;
        }
        let t = num / den;
        if den < 0.0 {
            t0 = t0.max(t);
        } else {
            t1 = t1.min(t);
        }
    }
    (t1 > t0).then_some((t0, t1))
}

/// Axis-aligned bounds (min, max) of picture points; `None` when there are none.
pub fn bounds2(points: impl IntoIterator<Item = DVec2>) -> Option<(DVec2, DVec2)> {
    points.into_iter().fold(None, |acc, v| match acc {
        None => Some((v, v)),
        Some((lo, hi)) => Some((lo.min(v), hi.max(v))),
    })
}

/// The convex hull of picture points, counter-clockwise, without collinear points (Andrew's
/// monotone chain, A. M. Andrew, "Another efficient algorithm for convex hulls in two
/// dimensions", 1979). Fewer than three distinct points give what there is.
pub fn convex_hull(points: &[DVec2]) -> Vec<DVec2> {
    let mut pts = points.to_vec();
    // Points equal in this total order have the same bits, so the unstable sort (cheaper: the
    // photo look's shadow reach hulls thousands of points per view) gives the stable one's order.
    pts.sort_unstable_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    pts.dedup();
    if pts.len() < 3 {
        return pts;
    }
    let turn = |o: DVec2, a: DVec2, b: DVec2| (a - o).perp_dot(b - o);
    let mut hull: Vec<DVec2> = Vec::with_capacity(2 * pts.len());
    for pass in [pts.clone(), pts.into_iter().rev().collect()] {
        let start = hull.len();
        for p in pass {
            while hull.len() >= start + 2
                && turn(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0.0
            {
                hull.pop();
            }
            hull.push(p);
        }
        hull.pop();
    }
    hull
}

/// Whether picture point `p` lies inside the counter-clockwise convex polygon `hull` grown by
/// `tol_px` (a polygon of fewer than three points contains nothing).
pub fn inside_convex(hull: &[DVec2], p: DVec2, tol_px: f64) -> bool {
    ConvexRegion::new(hull).contains(p, tol_px)
}

/// A counter-clockwise convex polygon ready for many [`inside_convex`] questions: each edge's
/// start, direction and length computed once (the recognizer asks every candidate corner of
/// every layer height).
#[derive(Debug, Clone)]
pub struct ConvexRegion {
    edges: Vec<(DVec2, DVec2, f64)>,
}

impl ConvexRegion {
    /// The region of `hull`; empty when it has fewer than three points.
    pub fn new(hull: &[DVec2]) -> ConvexRegion {
        let n = hull.len();
        let edges = if n < 3 {
            Vec::new()
        } else {
            (0..n)
                .map(|k| {
                    let (a, b) = (hull[k], hull[(k + 1) % n]);
                    (a, b - a, (b - a).length())
                })
                .collect()
        };
        ConvexRegion { edges }
    }

    /// Whether `p` lies inside the polygon grown by `tol_px`.
    pub fn contains(&self, p: DVec2, tol_px: f64) -> bool {
        !self.edges.is_empty()
            && self
                .edges
                .iter()
                .all(|&(a, e, len)| e.perp_dot(p - a) >= -tol_px * len)
    }
}

/// Disjoint sets over `0..n` with path halving; a union keeps the smaller index as the root,
/// so the sets' representatives do not depend on the order of unions (deterministic output).
#[derive(Debug, Clone)]
pub struct UnionFind(Vec<usize>);

impl UnionFind {
    /// `n` singletons.
    pub fn new(n: usize) -> UnionFind {
        UnionFind((0..n).collect())
    }

    /// The representative of `i`'s set.
    pub fn find(&mut self, mut i: usize) -> usize {
        while self.0[i] != i {
            self.0[i] = self.0[self.0[i]];
            i = self.0[i];
        }
        i
    }

    /// Joins the sets of `a` and `b`.
    pub fn union(&mut self, a: usize, b: usize) {
        let (a, b) = (self.find(a), self.find(b));
        if a != b {
            self.0[a.max(b)] = a.min(b);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn segment_distance_is_perpendicular_inside_and_to_the_end_outside() {
        let (a, b) = (DVec2::ZERO, DVec2::new(10.0, 0.0));
        assert_eq!(distance_to_segment_px(DVec2::new(5.0, 3.0), a, b), 3.0);
        assert_eq!(distance_to_segment_px(DVec2::new(13.0, 4.0), a, b), 5.0);
        assert_eq!(distance_to_segment_px(DVec2::new(-3.0, -4.0), a, b), 5.0);
        assert_eq!(distance_to_segment_px(DVec2::new(3.0, 4.0), a, a), 5.0);
    }

    #[test]
    fn the_median_is_an_observed_value_the_upper_middle_of_an_even_count() {
        assert_eq!(median(&mut [5.0, 1.0, 3.0]), Some(3.0));
        assert_eq!(median(&mut [4.0, 1.0, 3.0, 2.0]), Some(3.0));
        assert_eq!(median(&mut [7.0]), Some(7.0));
        assert_eq!(median(&mut []), None);
        // Sorted by total order: a NaN goes last instead of scrambling the order.
        assert_eq!(median(&mut [f64::NAN, 2.0, 1.0]), Some(2.0));
    }

    #[test]
    fn newell_vector_is_twice_the_area_along_the_counter_clockwise_normal() {
        let square = [DVec3::ZERO, DVec3::X, DVec3::X + DVec3::Y, DVec3::Y];
        assert_eq!(newell_vector(&square), DVec3::Z * 2.0);
        let mut clockwise = square;
        clockwise.reverse();
        assert_eq!(newell_vector(&clockwise), DVec3::Z * -2.0);
        assert_eq!(newell_vector(&[DVec3::X, DVec3::X * 2.0]), DVec3::ZERO);
    }

    #[test]
    fn the_sweep_finds_the_same_box_pairs_as_comparing_every_pair() {
        let mut seed = 7u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 33) as f64 / (1u64 << 31) as f64
        };
        let boxes: Vec<(DVec3, DVec3)> = (0..300)
            .map(|_| {
                let lo = DVec3::new(next() * 100.0, next() * 20.0, next() * 100.0);
                let size = DVec3::new(next() * 15.0, next() * 15.0, next() * 15.0);
                (lo, lo + size)
            })
            .collect();
        let mut every = Vec::new();
        for a in 0..boxes.len() {
            for b in a + 1..boxes.len() {
                let (ba, bb) = (boxes[a], boxes[b]);
                if !(ba.1.cmplt(bb.0).any() || bb.1.cmplt(ba.0).any()) {
                    every.push([a, b]);
                }
            }
        }
        assert!(every.len() > 100, "the random boxes must touch often");
        assert_eq!(touching_box_pairs(&boxes), every);
        // Boxes that only share a face count as touching.
        let face = [
            (DVec3::ZERO, DVec3::splat(15.0)),
            (DVec3::new(15.0, 0.0, 0.0), DVec3::new(30.0, 15.0, 15.0)),
        ];
        assert_eq!(touching_box_pairs(&face), vec![[0, 1]]);
    }

    #[test]
    fn the_hull_of_a_square_with_an_inner_point_is_the_square_and_contains_its_centre() {
        let pts = [
            DVec2::new(0.0, 0.0),
            DVec2::new(2.0, 0.0),
            DVec2::new(1.0, 1.0),
            DVec2::new(2.0, 2.0),
            DVec2::new(0.0, 2.0),
            DVec2::new(1.0, 0.0),
        ];
        let hull = convex_hull(&pts);
        assert_eq!(hull.len(), 4, "{hull:?}");
        assert!(inside_convex(&hull, DVec2::new(1.0, 1.0), 0.0));
        assert!(inside_convex(&hull, DVec2::new(2.05, 1.0), 0.1));
        assert!(!inside_convex(&hull, DVec2::new(2.5, 1.0), 0.1));
    }

    #[test]
    fn isometric_angle_is_atan_of_inverse_sqrt2() {
        let exact = (1.0f64 / 2f64.sqrt()).atan().to_degrees();
        assert!((exact - ISOMETRIC_ELEVATION_DEG).abs() < 1e-12);
    }

    #[test]
    fn bounds_and_sets() {
        let b = bounds3([DVec3::new(1.0, -2.0, 3.0), DVec3::new(-1.0, 5.0, 0.0)]).unwrap();
        assert_eq!(b, (DVec3::new(-1.0, -2.0, 0.0), DVec3::new(1.0, 5.0, 3.0)));
        assert!(bounds2(std::iter::empty()).is_none());
        let mut u = UnionFind::new(4);
        u.union(3, 1);
        u.union(2, 3);
        assert_eq!((u.find(2), u.find(3), u.find(0)), (1, 1, 0));
    }

    #[test]
    fn pure_yaw_round_trips() {
        for yaw in [-170.0f64, -90.0, 0.0, 30.0, 90.0, 179.0] {
            let q = Quat::from_rotation_y(yaw.to_radians() as f32);
            let got = pure_yaw_deg(q, 0.1).unwrap();
            assert!((got - yaw).abs() < 1e-3, "{yaw} -> {got}");
        }
        assert!(pure_yaw_deg(Quat::from_rotation_x(0.3), 1.0).is_none());
    }
}
