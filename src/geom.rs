//! Geometry conventions shared by every stage.
//!
//! * World units are **millimetres**; axes are right-handed with **+y up**, the floor is the
//!   plane y = 0, **+x is east** and **-z is north** (issue #2, scene-file contract).
//! * Picture coordinates are **pixels, x right, y up**, with (0, 0) the bottom-left corner of the
//!   picture and pixel centres at +0.5 (the GPU viewport transform with y flipped). A raster row
//!   `r` (0 at the top) has its centres at `y_px = height_px - r - 0.5`.
//! * The thesis draws its Chapter II viewing pipeline with row vectors (`p' = p M`); this crate
//!   uses glam's column vectors (`p' = M p`), i.e. the transposed matrices.
//!
//! This module imports nothing from the crate; every other stage may import it.

pub use glam::{DMat4, DQuat, DVec2, DVec3, DVec4, Mat3, Mat4, Quat, Vec2, Vec3, Vec4};

/// Contact tolerance in millimetres: two faces closer than this (and parallel) count as
/// touching, and a penetration shallower than this is not an overlap. Settled rapier poses sit
/// 0.03 mm into their supports with the stiff contact parameters used in `physics`, so the
/// same tolerance serves validation, ground truth and settling (see `shared/notes/ground-truth.md`).
pub const CONTACT_TOL_MM: f64 = 0.05;

/// The exact isometric elevation, atan(1/sqrt(2)) = 35.26438968 degrees. The issue's
/// "35.264" is a rounding of this angle; using the rounded value makes coincident points drift
/// 0.001 px apart (`shared/notes/ground-truth.md`).
pub const ISOMETRIC_ELEVATION_DEG: f64 = 35.264_389_682_754_654;

/// Converts a unit quaternion to the yaw about +y in degrees, if the rotation is a pure yaw
/// (within `tol_deg` of the y axis); `None` for any tilt.
pub fn pure_yaw_deg(q: Quat, tol_deg: f64) -> Option<f64> {
    let q = q.as_dquat().normalize();
    let up = q * DVec3::Y;
    if up.angle_between(DVec3::Y).to_degrees() > tol_deg {
        return None;
    }
    let x = q * DVec3::X;
    Some((-x.z).atan2(x.x).to_degrees())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn isometric_angle_is_atan_of_inverse_sqrt2() {
        let exact = (1.0f64 / 2f64.sqrt()).atan().to_degrees();
        assert!((exact - ISOMETRIC_ELEVATION_DEG).abs() < 1e-12);
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
