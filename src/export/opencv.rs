//! A blockworld camera in the OpenCV convention the vision tools use (docs/exports.md "Cameras"):
//! camera axes x right, y down, z forward (out of the eye), pixel coordinates x right, y down
//! from the top-left corner with the centre of the top-left pixel at (0, 0).
//!
//! blockworld's view space (`view_from_world`) has x right, y up and looks down -z; its picture
//! has y up from the bottom edge and pixel centres at +0.5 (docs/formats.md "Conventions"). So
//! the OpenCV camera is the view space turned half a turn about x (`diag(1, -1, -1)`), and an
//! OpenCV pixel `(u, v)` is the picture point `(u + 0.5, height - v - 0.5)`.

use crate::camera::Camera;
use crate::geom::{DMat4, DVec3, DVec4};

/// A camera in OpenCV's convention.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OpenCvCamera {
    /// World to camera rotation, row-major (`x_cam = R x_world + t`).
    pub r_w2c: [[f64; 3]; 3],
    /// World to camera translation, mm.
    pub t_w2c_mm: [f64; 3],
    /// Camera (homogeneous, mm) to homogeneous OpenCV pixels, row-major 3 x 4: `[u w, v w, w] =
    /// M [x, y, z, 1]`. For a perspective camera `w` is the depth `z` and `M = [K | 0]`; for an
    /// orthographic one the last row is `(0, 0, 0, 1)` and `u`, `v` are affine in `x`, `y`.
    pub pixels_from_camera: [[f64; 4]; 3],
    /// The pinhole intrinsics `K` (row-major, pixels) of a perspective camera; `None` for an
    /// orthographic one, which has none.
    pub k: Option<[[f64; 3]; 3]>,
}

impl OpenCvCamera {
    /// The OpenCV form of `camera`.
    pub fn from_camera(camera: &Camera) -> OpenCvCamera {
        let flip = DMat4::from_diagonal(DVec4::new(1.0, -1.0, -1.0, 1.0));
        let cam_from_world = flip * camera.view_matrix();
        let [w, h] = camera.size_px.map(f64::from);
        // clip -> homogeneous OpenCV pixels: u = (ndc.x + 1) w / 2 - 0.5,
        // v = (1 - ndc.y) h / 2 - 0.5, with ndc = clip / clip.w.
        let pixels_from_clip = [
            DVec4::new(w / 2.0, 0.0, 0.0, w / 2.0 - 0.5),
            DVec4::new(0.0, -h / 2.0, 0.0, h / 2.0 - 0.5),
            DVec4::new(0.0, 0.0, 0.0, 1.0),
        ];
        // The view space from the OpenCV camera is the same flip.
        let clip_from_cam = camera.projection_matrix() * flip;
        let pixels_from_camera = pixels_from_clip.map(|row| {
            let r = clip_from_cam.transpose() * row;
            r.to_array()
        });
        let k = (!camera.is_orthographic())
            .then(|| pixels_from_camera.map(|row| [row[0], row[1], row[2]]));
        let r = |i: usize| {
            let row = cam_from_world.row(i);
            [row.x, row.y, row.z]
        };
        OpenCvCamera {
            r_w2c: [r(0), r(1), r(2)],
            t_w2c_mm: cam_from_world.w_axis.truncate().to_array(),
            pixels_from_camera,
            k,
        }
    }

    /// A world point (mm) in OpenCV camera coordinates (mm).
    pub fn camera_from_world(&self, p_mm: DVec3) -> DVec3 {
        let r = self.r_w2c;
        let t = self.t_w2c_mm;
        DVec3::new(
            r[0][0] * p_mm.x + r[0][1] * p_mm.y + r[0][2] * p_mm.z + t[0],
            r[1][0] * p_mm.x + r[1][1] * p_mm.y + r[1][2] * p_mm.z + t[1],
            r[2][0] * p_mm.x + r[2][1] * p_mm.y + r[2][2] * p_mm.z + t[2],
        )
    }

    /// The OpenCV pixel `(u, v)` of a world point.
    pub fn pixel_from_world(&self, p_mm: DVec3) -> [f64; 2] {
        let c = self.camera_from_world(p_mm).extend(1.0);
        let m = self
            .pixels_from_camera
            .map(|row| DVec4::from_array(row).dot(c));
        [m[0] / m[2], m[1] / m[2]]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::{CameraOptions, CornerView, Projection};

    fn cube() -> Vec<DVec3> {
        (0..8)
            .map(|i| {
                DVec3::new(
                    if i & 4 != 0 { 15.0 } else { 0.0 },
                    if i & 2 != 0 { 15.0 } else { 0.0 },
                    if i & 1 != 0 { 15.0 } else { 0.0 },
                )
            })
            .collect()
    }

    #[test]
    fn opencv_pixels_are_picture_points_flipped_and_shifted_by_half_a_pixel() {
        for projection in [
            Projection::Orthographic,
            Projection::Perspective { fov_y_deg: 40.0 },
        ] {
            let opts = CameraOptions {
                projection,
                ..Default::default()
            };
            for view in CornerView::ALL {
                let camera = Camera::frame(&cube(), view, &opts);
                let cv = OpenCvCamera::from_camera(&camera);
                assert_eq!(cv.k.is_some(), !camera.is_orthographic());
                for p in cube() {
                    let q = camera.picture_from_world(p);
                    let [u, v] = cv.pixel_from_world(p);
                    assert!((u - (q.x - 0.5)).abs() < 1e-9, "{view:?} {u} {q}");
                    assert!((v - (480.0 - q.y - 0.5)).abs() < 1e-9, "{view:?} {v} {q}");
                    // z forward: the depth along the optical axis, as depth_<v>.png holds it.
                    let z = cv.camera_from_world(p).z;
                    assert!((z - q.z).abs() < 1e-9, "{z} {}", q.z);
                }
                let r = glam::DMat3::from_cols_array_2d(&cv.r_w2c).transpose();
                assert!((r.determinant() - 1.0).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn a_pinhole_k_has_the_textbook_shape() {
        let opts = CameraOptions {
            projection: Projection::Perspective { fov_y_deg: 40.0 },
            ..Default::default()
        };
        let camera = Camera::frame(&cube(), CornerView::Ne, &opts);
        let k = OpenCvCamera::from_camera(&camera).k.unwrap();
        let f = 240.0 / (20f64).to_radians().tan();
        assert!(
            (k[0][0] - f).abs() < 1e-9 && (k[1][1] - f).abs() < 1e-9,
            "{k:?}"
        );
        assert_eq!(
            [k[0][1], k[1][0], k[2][0], k[2][1], k[2][2]],
            [0.0, 0.0, 0.0, 0.0, 1.0]
        );
        assert!(
            (k[0][2] - 255.5).abs() < 1e-9 && (k[1][2] - 239.5).abs() < 1e-9,
            "{k:?}"
        );
    }
}
