//! Clipping lines against the canonical perspective view volume (Chapter II "Clipping Image
//! against a Canonical View Volume", eq. 2.7-2.8, after Foley & van Dam 1982).
//!
//! The volume is bounded by y = z, y = -z, x = z, x = -z, z = z_min and z = 1. Each endpoint
//! gets an outcode; a line is accepted when both codes are zero and rejected when their
//! bitwise "and" is not zero, otherwise it is cut at the planes it crosses. The thesis lists
//! four bits and prints `y_v > -z_v` for "below" and `x_v > -z_v` for "left"; the geometry says
//! `y_v < -z_v` and `x_v < -z_v` (docs/thesis-readings.md "Thesis readings"), and the planes z = z_min and z = 1
//! need two more bits, so [`OutCode`] has six.

use crate::geom::DVec3;

/// The outcode of a point against the canonical volume (Chapter II): one bit per plane the
/// point lies outside of.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct OutCode(pub u8);

impl OutCode {
    /// Bit 1: above the volume, y > z.
    pub const ABOVE: u8 = 1;
    /// Bit 2: below, y < -z (the thesis prints `>`).
    pub const BELOW: u8 = 2;
    /// Bit 3: right, x > z.
    pub const RIGHT: u8 = 4;
    /// Bit 4: left, x < -z (the thesis prints `>`).
    pub const LEFT: u8 = 8;
    /// Bit 5: in front of the hither plane, z < z_min.
    pub const FRONT: u8 = 16;
    /// Bit 6: beyond the yon plane, z > 1.
    pub const BEHIND: u8 = 32;

    /// The outcode of canonical point `p` for a hither plane at `z_min`.
    pub fn of(p: DVec3, z_min: f64) -> OutCode {
        let mut code = 0;
        for (bit, _) in PLANES.iter().filter(|(_, f)| f(p, z_min) < 0.0) {
            code |= bit;
        }
        OutCode(code)
    }

    /// `true` when the point is inside the volume (all bits clear).
    pub fn is_inside(self) -> bool {
        self.0 == 0
    }
}

/// Each plane as its outcode bit and a function that is >= 0 on the inside (the volume's
/// side). Where a line crosses the plane, eq. 2.7 gives t = f(P1) / (f(P1) - f(P2)); for the
/// plane y = z, f = z - y, which is eq. 2.8a: t = (z1 - y1) / ((y2 - y1) - (z2 - z1)).
type PlaneSide = fn(DVec3, f64) -> f64;

const PLANES: [(u8, PlaneSide); 6] = [
    (OutCode::ABOVE, |p, _| p.z - p.y),
    (OutCode::BELOW, |p, _| p.z + p.y),
    (OutCode::RIGHT, |p, _| p.z - p.x),
    (OutCode::LEFT, |p, _| p.z + p.x),
    (OutCode::FRONT, |p, z_min| p.z - z_min),
    (OutCode::BEHIND, |p, _| 1.0 - p.z),
];

/// What clipping did to a line from P1 to P2.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Clipped {
    /// Both endpoints inside: the whole line is kept.
    Inside,
    /// The part from parameter `t0` to `t1` (eq. 2.7, 0 at P1 and 1 at P2) is kept.
    Cut {
        /// Where the kept part starts (0 when P1 is inside).
        t0: f64,
        /// Where it ends (1 when P2 is inside).
        t1: f64,
    },
    /// No part of the line is in the volume.
    Outside,
}

impl Clipped {
    /// The kept parameter range, if any.
    pub fn range(self) -> Option<(f64, f64)> {
        match self {
            Clipped::Inside => Some((0.0, 1.0)),
            Clipped::Cut { t0, t1 } => Some((t0, t1)),
            Clipped::Outside => None,
        }
    }
}

/// The point of eq. 2.7 at parameter `t` on the line from `p1` to `p2`.
pub fn point_at(p1: DVec3, p2: DVec3, t: f64) -> DVec3 {
    (p2 - p1) * t + p1
}

/// Clips the line P1 P2 (canonical coordinates) against the view volume with hither plane
/// `z_min` (Chapter II, eq. 2.7-2.8): trivial accept and reject by outcodes, otherwise the
/// intersection parameter with each plane an endpoint lies outside of. Every t is taken on
/// the original line, so no rounding accumulates from one cut to the next.
pub fn clip_line(p1: DVec3, p2: DVec3, z_min: f64) -> Clipped {
    let (c1, c2) = (OutCode::of(p1, z_min), OutCode::of(p2, z_min));
    if c1.is_inside() && c2.is_inside() {
        return Clipped::Inside;
    }
    if c1.0 & c2.0 != 0 {
        return Clipped::Outside;
    }
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (bit, side) in PLANES {
        if (c1.0 | c2.0) & bit == 0 {
            continue;
        }
        let (f1, f2) = (side(p1, z_min), side(p2, z_min));
        let t = f1 / (f1 - f2);
        if f1 < 0.0 {
            t0 = t0.max(t); // entering the volume through this plane
        } else {
            t1 = t1.min(t); // leaving it
        }
    }
    if t0 < t1 {
        Clipped::Cut { t0, t1 }
    } else {
        Clipped::Outside
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const Z_MIN: f64 = 0.1;

    fn v(x: f64, y: f64, z: f64) -> DVec3 {
        DVec3::new(x, y, z)
    }

    fn cut(p1: DVec3, p2: DVec3) -> (f64, f64) {
        match clip_line(p1, p2, Z_MIN) {
            Clipped::Cut { t0, t1 } => (t0, t1),
            other => panic!("expected a cut, got {other:?}"),
        }
    }

    fn near(a: f64, b: f64) -> bool {
        (a - b).abs() < 1e-12
    }

    #[test]
    fn outcodes_use_the_geometric_inequalities_not_the_printed_ones() {
        assert_eq!(OutCode::of(v(0.0, 0.0, 0.5), Z_MIN), OutCode(0));
        assert_eq!(OutCode::of(v(0.0, 0.6, 0.5), Z_MIN).0, OutCode::ABOVE);
        // "below": y < -z. The printed y > -z would flag the centre of the volume too.
        assert_eq!(OutCode::of(v(0.0, -0.6, 0.5), Z_MIN).0, OutCode::BELOW);
        assert_eq!(OutCode::of(v(0.6, 0.0, 0.5), Z_MIN).0, OutCode::RIGHT);
        assert_eq!(OutCode::of(v(-0.6, 0.0, 0.5), Z_MIN).0, OutCode::LEFT);
        assert_eq!(OutCode::of(v(0.0, 0.0, 0.05), Z_MIN).0, OutCode::FRONT);
        assert_eq!(OutCode::of(v(0.0, 0.0, 1.5), Z_MIN).0, OutCode::BEHIND);
        assert_eq!(
            OutCode::of(v(2.0, 2.0, 1.5), Z_MIN).0,
            OutCode::ABOVE | OutCode::RIGHT | OutCode::BEHIND
        );
    }

    #[test]
    fn a_line_inside_is_kept_whole_and_one_beside_the_volume_is_rejected() {
        assert_eq!(
            clip_line(v(0.0, 0.0, 0.5), v(0.1, 0.2, 0.9), Z_MIN),
            Clipped::Inside
        );
        // Both endpoints above: the "and" of the codes is not zero.
        assert_eq!(
            clip_line(v(0.0, 1.0, 0.5), v(0.3, 2.0, 0.9), Z_MIN),
            Clipped::Outside
        );
    }

    #[test]
    fn leaving_through_y_equals_z_matches_eq_2_8() {
        let (p1, p2) = (v(0.1, 0.0, 0.5), v(0.3, 1.0, 0.5));
        let (t0, t1) = cut(p1, p2);
        // Eq. 2.8a-c, written out.
        let t = (p1.z - p1.y) / ((p2.y - p1.y) - (p2.z - p1.z));
        let x = (p2.x - p1.x) * (p1.z - p1.y) / ((p2.y - p1.y) - (p2.z - p1.z)) + p1.x;
        let y = (p2.y - p1.y) * (p1.z - p1.y) / ((p2.y - p1.y) - (p2.z - p1.z)) + p1.y;
        assert!(near(t0, 0.0) && near(t1, t) && near(t, 0.5));
        let q = point_at(p1, p2, t1);
        assert!(near(q.x, x) && near(q.y, y) && near(q.y, q.z));
    }

    #[test]
    fn entering_and_leaving_through_each_sloping_plane() {
        // Entering through y = -z (below) and leaving through y = z (above).
        let (t0, t1) = cut(v(0.0, -1.0, 0.5), v(0.0, 1.0, 0.5));
        assert!(near(t0, 0.25) && near(t1, 0.75));
        let (p1, p2) = (v(0.0, -1.0, 0.5), v(0.0, 1.0, 0.5));
        assert!(near(point_at(p1, p2, t0).y, -0.5));
        // Entering through x = -z (left) and leaving through x = z (right).
        let (t0, t1) = cut(v(-1.0, 0.0, 0.5), v(1.0, 0.0, 0.5));
        assert!(near(t0, 0.25) && near(t1, 0.75));
        // The other way round: entering through the right, leaving through the left.
        let (t0, t1) = cut(v(1.0, 0.2, 0.5), v(-1.0, 0.2, 0.5));
        assert!(near(t0, 0.25) && near(t1, 0.75));
    }

    #[test]
    fn entering_and_leaving_through_hither_and_yon() {
        // From in front of the hither plane to beyond the yon plane, along the axis.
        let (p1, p2) = (v(0.0, 0.0, 0.0), v(0.0, 0.0, 2.0));
        let (t0, t1) = cut(p1, p2);
        assert!(near(point_at(p1, p2, t0).z, Z_MIN));
        assert!(near(point_at(p1, p2, t1).z, 1.0));
        // Only leaving through the yon plane.
        let (t0, t1) = cut(v(0.0, 0.0, 0.5), v(0.0, 0.0, 1.5));
        assert!(near(t0, 0.0) && near(t1, 0.5));
    }

    #[test]
    fn a_line_passing_outside_a_corner_is_rejected_though_no_bit_is_shared() {
        // P1 is only above, P2 only right; the line between them passes above-right of the
        // edge where y = z meets x = z, so the cuts cross (t0 > t1).
        let (p1, p2) = (v(0.0, 1.2, 0.5), v(1.2, 0.0, 0.5));
        let (c1, c2) = (OutCode::of(p1, Z_MIN), OutCode::of(p2, Z_MIN));
        assert_eq!(c1.0 & c2.0, 0);
        assert_eq!(clip_line(p1, p2, Z_MIN), Clipped::Outside);
        // Moved inward it crosses the corner and is cut on both sides.
        let (t0, t1) = cut(v(0.0, 0.6, 0.5), v(0.6, 0.0, 0.5));
        assert!(t0 > 0.0 && t1 < 1.0 && t0 < t1);
    }

    #[test]
    fn every_plane_cuts_a_line_leaving_through_it_and_one_entering_through_it() {
        let inside = v(0.0, 0.0, 0.5);
        let outside: [DVec3; 6] = [
            v(0.0, 2.0, 0.5),  // above
            v(0.0, -2.0, 0.5), // below
            v(2.0, 0.0, 0.5),  // right
            v(-2.0, 0.0, 0.5), // left
            v(0.0, 0.0, 0.0),  // in front of the hither plane
            v(0.0, 0.0, 2.0),  // beyond the yon plane
        ];
        for (out, (bit, side)) in outside.into_iter().zip(PLANES) {
            // Each plane's side function is zero on the plane.
            let on_plane = |p: DVec3| side(p, Z_MIN);
            assert_eq!(OutCode::of(out, Z_MIN).0, bit);
            let (t0, t1) = cut(inside, out);
            assert!(near(t0, 0.0) && t1 < 1.0, "leaving {bit}");
            assert!(
                on_plane(point_at(inside, out, t1)).abs() < 1e-12,
                "leaving {bit}"
            );
            let (t0, t1) = cut(out, inside);
            assert!(t0 > 0.0 && near(t1, 1.0), "entering {bit}");
            assert!(
                on_plane(point_at(out, inside, t0)).abs() < 1e-12,
                "entering {bit}"
            );
        }
    }
}
