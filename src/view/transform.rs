//! The thesis's viewing matrices (Chapter II "Mathematics of Planar Geometric Projections",
//! eq. 2.2-2.6), after Foley & van Dam (1982).
//!
//! The thesis writes row vectors (`p' = p M`, translation in the bottom row); blockworld's glam
//! matrices act on column vectors (`p' = M p`, docs/formats.md "Conventions"), so every function here
//! returns the transpose of the printed matrix. The tests check each one against the printed
//! layout, row for row (`to_cols_array_2d` of a glam matrix lists the thesis's rows).

use super::ViewError;
use crate::geom::{DMat4, DVec3, DVec4};

/// Eq. 2.2: the translation T(dx, dy, dz).
pub fn translation(d: DVec3) -> DMat4 {
    thesis_rows([
        [1.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
        [d.x, d.y, d.z, 1.0],
    ])
}

/// Eq. 2.3a: the rotation R_z(θ) about the z axis, as printed (row vectors: x' = x cos θ -
/// y sin θ, y' = x sin θ + y cos θ).
pub fn rotation_z(theta_deg: f64) -> DMat4 {
    let (s, c) = theta_deg.to_radians().sin_cos();
    thesis_rows([
        [c, s, 0.0, 0.0],
        [-s, c, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ])
}

/// Eq. 2.3b: the rotation R_y(θ) about the y axis, as printed.
pub fn rotation_y(theta_deg: f64) -> DMat4 {
    let (s, c) = theta_deg.to_radians().sin_cos();
    thesis_rows([
        [c, 0.0, -s, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [s, 0.0, c, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ])
}

/// Eq. 2.3c: the rotation R_x(θ) about the x axis, as printed.
pub fn rotation_x(theta_deg: f64) -> DMat4 {
    let (s, c) = theta_deg.to_radians().sin_cos();
    thesis_rows([
        [1.0, 0.0, 0.0, 0.0],
        [0.0, c, s, 0.0],
        [0.0, -s, c, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ])
}

/// A matrix given as the thesis prints it (rows, for row vectors) as a glam column-vector
/// matrix: glam's columns are the thesis's rows read as columns, i.e. the transpose.
fn thesis_rows(rows: [[f64; 4]; 4]) -> DMat4 {
    DMat4::from_cols_array_2d(&rows)
}

/// The viewing axes A1, A2, A3 of eq. 2.4-2.5 (unit vectors in world coordinates): A3 looks
/// from F to A, A1 points right and A2 up in the picture. Together they form the thesis's
/// left-handed viewing system (x right, y up, z into the screen).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ViewingAxes {
    /// A1: the picture's x axis (right).
    pub a1: DVec3,
    /// A2: the picture's y axis (up).
    pub a2: DVec3,
    /// A3: the line of sight (into the screen).
    pub a3: DVec3,
}

/// Eq. 2.5a-c: the viewing axes from the From point F, the At point A and the Up direction.
///
/// The thesis sets `A' = A - F` and `U' = A - U`. With that sign A2 comes out as -Up: the
/// picture is upside down on a y-up picture (docs/thesis-readings.md "Thesis readings"). blockworld follows the
/// geometry and takes `U' = Up`, the up direction (the thesis's "up point" relative to the At
/// point), so that A2 is the component of Up across the line of sight:
/// A3 = A'/|A'|, A1 = (A' × U')/|A' × U'|, A2 = ((A' × U') × A')/|(A' × U') × A'|.
pub fn viewing_axes(from_mm: DVec3, at_mm: DVec3, up: DVec3) -> Result<ViewingAxes, ViewError> {
    let a_prime = at_mm - from_mm;
    if a_prime.length() <= 0.0 || !a_prime.is_finite() {
        return Err(ViewError::FromAtSamePoint {
            at_mm: at_mm.into(),
        });
    }
    // Up's length does not matter: scaled to a largest component of 1, a huge or tiny Up
    // neither overflows nor vanishes in the cross product.
    let u_prime = up / up.abs().max_element().max(f64::MIN_POSITIVE);
    let across = a_prime.cross(u_prime);
    if across.length() <= 1e-9 * a_prime.length() * u_prime.length() || !across.is_finite() {
        return Err(ViewError::UpAlongLineOfSight { up: up.into() });
    }
    Ok(ViewingAxes {
        a1: across.normalize(),
        a2: across.cross(a_prime).normalize(),
        a3: a_prime.normalize(),
    })
}

/// Eq. 2.4: the rotation whose rows (in the thesis's layout) hold A1, A2, A3 as columns, so a
/// row vector p maps to (p·A1, p·A2, p·A3): world directions into the viewing system.
pub fn orientation(axes: &ViewingAxes) -> DMat4 {
    let ViewingAxes { a1, a2, a3 } = *axes;
    thesis_rows([
        [a1.x, a2.x, a3.x, 0.0],
        [a1.y, a2.y, a3.y, 0.0],
        [a1.z, a2.z, a3.z, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ])
}

/// D = 1 / tan(view angle / 2), eq. 2.6.
pub fn view_angle_scale(view_angle_deg: f64) -> f64 {
    1.0 / (view_angle_deg.to_radians() / 2.0).tan()
}

/// Eq. 2.6: M = diag(D, D, 1, 1), which puts the edges of the view angle on the planes
/// y = ±z and x = ±z.
pub fn view_angle_matrix(view_angle_deg: f64) -> DMat4 {
    let d = view_angle_scale(view_angle_deg);
    thesis_rows([
        [d, 0.0, 0.0, 0.0],
        [0.0, d, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ])
}

/// The whole viewing transform of Figure 2.11: translate F to the origin (eq. 2.2 with
/// -F), turn into the viewing axes (eq. 2.4-2.5), scale by the view angle (eq. 2.6), then scale
/// uniformly by 1/yon so that the far plane is z = 1 (Foley & van Dam's canonical perspective
/// volume, which the thesis's clipping planes assume).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ViewingTransform {
    /// World mm → eye mm (left-handed, eye at the origin, z along the line of sight).
    pub eye_from_world: DMat4,
    /// Eye mm → the canonical volume |x| ≤ z, |y| ≤ z, z_min ≤ z ≤ 1.
    pub canonical_from_eye: DMat4,
    /// The front (hither) plane z = z_min of the canonical volume.
    pub z_min: f64,
}

impl ViewingTransform {
    /// The transform for F, A, Up, a view angle and the hither and yon distances (mm along
    /// the line of sight from F).
    pub fn new(
        from_mm: DVec3,
        at_mm: DVec3,
        up: DVec3,
        view_angle_deg: f64,
        hither_yon_mm: (f64, f64),
    ) -> Result<ViewingTransform, ViewError> {
        let axes = viewing_axes(from_mm, at_mm, up)?;
        let (hither, yon) = hither_yon_mm;
        let eye_from_world = orientation(&axes) * translation(-from_mm);
        let canonical_from_eye =
            DMat4::from_scale(DVec3::splat(1.0 / yon)) * view_angle_matrix(view_angle_deg);
        Ok(ViewingTransform {
            eye_from_world,
            canonical_from_eye,
            z_min: hither / yon,
        })
    }

    /// A world point in eye mm.
    pub fn eye(&self, world_mm: DVec3) -> DVec3 {
        self.eye_from_world.transform_point3(world_mm)
    }

    /// An eye point in the canonical volume's coordinates.
    pub fn canonical(&self, eye_mm: DVec3) -> DVec3 {
        (self.canonical_from_eye * DVec4::from((eye_mm, 1.0))).truncate()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rows(m: DMat4) -> [[f64; 4]; 4] {
        m.to_cols_array_2d()
    }

    /// A row vector times the thesis's matrix, done the thesis's way (eq. 2.2: p' = p M).
    fn row_times(p: [f64; 4], m: [[f64; 4]; 4]) -> [f64; 4] {
        let mut out = [0.0; 4];
        for (j, o) in out.iter_mut().enumerate() {
            *o = (0..4).map(|i| p[i] * m[i][j]).sum();
        }
        out
    }

    fn close(a: DVec3, b: DVec3) -> bool {
        (a - b).length() < 1e-12
    }

    #[test]
    fn translation_is_eq_2_2_row_for_row() {
        let m = translation(DVec3::new(2.0, -3.0, 5.0));
        assert_eq!(
            rows(m),
            [
                [1.0, 0.0, 0.0, 0.0],
                [0.0, 1.0, 0.0, 0.0],
                [0.0, 0.0, 1.0, 0.0],
                [2.0, -3.0, 5.0, 1.0]
            ]
        );
        let p = DVec3::new(1.0, 1.0, 1.0);
        assert_eq!(m.transform_point3(p), DVec3::new(3.0, -2.0, 6.0));
        assert_eq!(
            row_times([1.0, 1.0, 1.0, 1.0], rows(m)),
            [3.0, -2.0, 6.0, 1.0]
        );
    }

    #[test]
    fn rotations_are_eq_2_3_row_for_row_and_act_like_the_row_product() {
        let (s, c) = 30f64.to_radians().sin_cos();
        assert_eq!(rows(rotation_z(30.0))[0], [c, s, 0.0, 0.0]);
        assert_eq!(rows(rotation_z(30.0))[1], [-s, c, 0.0, 0.0]);
        assert_eq!(rows(rotation_y(30.0))[0], [c, 0.0, -s, 0.0]);
        assert_eq!(rows(rotation_y(30.0))[2], [s, 0.0, c, 0.0]);
        assert_eq!(rows(rotation_x(30.0))[1], [0.0, c, s, 0.0]);
        assert_eq!(rows(rotation_x(30.0))[2], [0.0, -s, c, 0.0]);
        let p = DVec3::new(0.3, -1.2, 2.5);
        for m in [rotation_x(30.0), rotation_y(30.0), rotation_z(30.0)] {
            let thesis = row_times([p.x, p.y, p.z, 1.0], rows(m));
            assert!(close(
                m.transform_point3(p),
                DVec3::new(thesis[0], thesis[1], thesis[2])
            ));
        }
        // A quarter turn as printed: R_z takes x to y, R_y takes z to x, R_x takes y to z.
        assert!(close(rotation_z(90.0).transform_point3(DVec3::X), DVec3::Y));
        assert!(close(rotation_y(90.0).transform_point3(DVec3::Z), DVec3::X));
        assert!(close(rotation_x(90.0).transform_point3(DVec3::Y), DVec3::Z));
    }

    #[test]
    fn viewing_axes_look_from_f_to_a_with_up_up_and_a_left_handed_frame() {
        // Looking along world +z from F = (0, 0, -10) with Up = +y: right is world -x.
        let axes = viewing_axes(DVec3::new(0.0, 0.0, -10.0), DVec3::ZERO, DVec3::Y).unwrap();
        assert!(close(axes.a3, DVec3::Z));
        assert!(
            close(axes.a2, DVec3::Y),
            "picture up must be Up: {:?}",
            axes.a2
        );
        assert!(close(axes.a1, -DVec3::X));
        // Left-handed in a right-handed world: A1 x A2 = -A3.
        assert!(close(axes.a1.cross(axes.a2), -axes.a3));
        // The printed U' = A - U would give A2 = -Up (upside down): our reading differs there.
        let printed = viewing_axes(DVec3::new(0.0, 0.0, -10.0), DVec3::ZERO, -DVec3::Y).unwrap();
        assert!(close(printed.a2, -DVec3::Y));
    }

    #[test]
    fn viewing_axes_take_the_part_of_up_across_the_line_of_sight() {
        let axes = viewing_axes(DVec3::new(10.0, 10.0, 0.0), DVec3::ZERO, DVec3::Y).unwrap();
        let s = 0.5f64.sqrt();
        assert!(close(axes.a3, DVec3::new(-s, -s, 0.0)));
        assert!(close(axes.a2, DVec3::new(-s, s, 0.0)));
        assert!(axes.a2.dot(DVec3::Y) > 0.0);
    }

    #[test]
    fn viewing_axes_reject_up_along_the_line_of_sight_and_f_on_a() {
        let e = viewing_axes(DVec3::new(0.0, 5.0, 0.0), DVec3::ZERO, DVec3::Y);
        assert!(matches!(e, Err(ViewError::UpAlongLineOfSight { .. })));
        let e = viewing_axes(DVec3::ONE, DVec3::ONE, DVec3::Y);
        assert!(matches!(e, Err(ViewError::FromAtSamePoint { .. })));
    }

    #[test]
    fn orientation_is_eq_2_4_with_the_axes_as_columns() {
        let axes = viewing_axes(DVec3::new(0.0, 0.0, -10.0), DVec3::ZERO, DVec3::Y).unwrap();
        let m = orientation(&axes);
        assert_eq!(
            rows(m),
            [
                [-1.0, 0.0, 0.0, 0.0],
                [0.0, 1.0, 0.0, 0.0],
                [0.0, 0.0, 1.0, 0.0],
                [0.0, 0.0, 0.0, 1.0]
            ]
        );
    }

    #[test]
    fn view_angle_matrix_is_eq_2_6_and_puts_the_angle_on_y_equals_z() {
        assert!((view_angle_scale(90.0) - 1.0).abs() < 1e-12);
        let d = view_angle_scale(60.0);
        assert!((d - 3f64.sqrt()).abs() < 1e-12);
        assert_eq!(rows(view_angle_matrix(60.0))[0], [d, 0.0, 0.0, 0.0]);
        assert_eq!(rows(view_angle_matrix(60.0))[2], [0.0, 0.0, 1.0, 0.0]);
        // A point on the edge of a 60-degree view angle (30 degrees off the axis) lands on y = z.
        let p = DVec3::new(0.0, 30f64.to_radians().tan() * 7.0, 7.0);
        let q = view_angle_matrix(60.0).transform_point3(p);
        assert!((q.y - q.z).abs() < 1e-12);
    }

    #[test]
    fn viewing_transform_puts_a_at_the_axis_and_yon_at_z_1() {
        let f = DVec3::new(100.0, 80.0, 110.0);
        let a = DVec3::new(22.5, 15.0, 15.0);
        let t = ViewingTransform::new(f, a, DVec3::Y, 60.0, (1.0, 200.0)).unwrap();
        let e = t.eye(a);
        assert!(e.x.abs() < 1e-9 && e.y.abs() < 1e-9);
        assert!((e.z - (a - f).length()).abs() < 1e-9);
        let far = t.canonical(DVec3::new(0.0, 0.0, 200.0));
        assert!((far.z - 1.0).abs() < 1e-12);
        assert!((t.z_min - 1.0 / 200.0).abs() < 1e-15);
        // A world point above A appears above it in the picture (y up).
        assert!(t.eye(a + DVec3::Y).y > 0.0);
    }
}
