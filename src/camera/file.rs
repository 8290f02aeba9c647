//! `camera_<view>.json`: the camera's fields in their declared order, then the depth scale and
//! the picture convention in words (docs/rendering.md "Rendering"). Written by `render` and `generate`,
//! read back by every stage that maps pixels to the world; a file that is not exactly this is
//! refused with a reason, never half-read.

use super::{Camera, Projection, DEPTH_UNITS_PER_MM};
use serde::{Deserialize, Serialize};

/// The picture-coordinate convention written into every `camera_<v>.json`.
pub const PICTURE_CONVENTION: &str = "picture px: x right, y up, origin at the bottom-left \
corner of the picture, pixel centres at +0.5; PNG row r (0 at the top) has its centres at \
y = height - r - 0.5. Project a world point (mm) with clip = clip_from_view * view_from_world \
* [x, y, z, 1] (column-major), ndc = clip.xyz / clip.w, x_px = (ndc.x + 1) / 2 * width, \
y_px = (ndc.y + 1) / 2 * height; depth PNG value = round(depth along the optical axis in mm \
* depth_units_per_mm)";

/// Why a camera file was refused.
#[derive(Debug, thiserror::Error)]
pub enum CameraError {
    /// Not JSON of the camera layout (unknown or missing fields, wrong types).
    #[error("not a camera file: {0} (write one with `blockworld render`)")]
    Format(String),
    /// A field holds a value no camera can have.
    #[error("camera field `{field}` {problem} (write the camera with `blockworld render`)")]
    Degenerate {
        /// The field's name.
        field: &'static str,
        /// What is wrong with it.
        problem: String,
    },
}

#[derive(Serialize)]
struct CameraFileOut<'a> {
    #[serde(flatten)]
    camera: &'a Camera,
    depth_units_per_mm: f64,
    picture: &'static str,
}

/// `camera_<v>.json` as written: the camera plus the depth scale and the picture convention.
pub fn camera_json(camera: &Camera) -> String {
    let file = CameraFileOut {
        camera,
        depth_units_per_mm: DEPTH_UNITS_PER_MM,
        picture: PICTURE_CONVENTION,
    };
    crate::io::pretty_json(&file)
}

/// The on-disk layout, strict: every field of [`Camera`] plus the two informative ones.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CameraFileIn {
    view: super::CornerView,
    azimuth_deg: f64,
    elevation_deg: f64,
    projection: Projection,
    size_px: [u32; 2],
    pixel_aspect: f64,
    eye_mm: [f64; 3],
    target_mm: [f64; 3],
    view_from_world: [f64; 16],
    clip_from_view: [f64; 16],
    near_far_mm: [f64; 2],
    #[serde(default)]
    #[allow(dead_code)]
    depth_units_per_mm: Option<f64>,
    #[serde(default)]
    #[allow(dead_code)]
    picture: Option<String>,
}

/// Parses and checks the text of a `camera_<v>.json`: unknown fields, non-finite numbers, a
/// zero picture size, a pixel aspect or field of view outside its range, or matrices that
/// cannot be inverted are errors.
pub fn parse_camera_json(text: &str) -> Result<Camera, CameraError> {
    let f: CameraFileIn =
        serde_json::from_str(text).map_err(|e| CameraError::Format(e.to_string()))?;
    let camera = Camera {
        view: f.view,
        azimuth_deg: f.azimuth_deg,
        elevation_deg: f.elevation_deg,
        projection: f.projection,
        size_px: f.size_px,
        pixel_aspect: f.pixel_aspect,
        eye_mm: f.eye_mm,
        target_mm: f.target_mm,
        view_from_world: f.view_from_world,
        clip_from_view: f.clip_from_view,
        near_far_mm: f.near_far_mm,
    };
    check_camera(&camera)?;
    Ok(camera)
}

fn degenerate(field: &'static str, problem: impl Into<String>) -> CameraError {
    CameraError::Degenerate {
        field,
        problem: problem.into(),
    }
}

fn check_camera(c: &Camera) -> Result<(), CameraError> {
    let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
    let numbers: [(&'static str, &[f64]); 7] = [
        ("azimuth_deg", &[c.azimuth_deg]),
        ("elevation_deg", &[c.elevation_deg]),
        ("eye_mm", &c.eye_mm),
        ("target_mm", &c.target_mm),
        ("view_from_world", &c.view_from_world),
        ("clip_from_view", &c.clip_from_view),
        ("near_far_mm", &c.near_far_mm),
    ];
    for (field, v) in numbers {
        if !finite(v) {
            return Err(degenerate(field, "holds a number that is not finite"));
        }
    }
    if c.size_px[0] == 0 || c.size_px[1] == 0 {
        return Err(degenerate("size_px", "has a zero side"));
    }
    if !(c.pixel_aspect.is_finite() && c.pixel_aspect > 0.0) {
        return Err(degenerate("pixel_aspect", "must be a positive number"));
    }
    if let Projection::Perspective { fov_y_deg } = c.projection {
        if !(fov_y_deg > 0.0 && fov_y_deg < 180.0) {
            return Err(degenerate(
                "projection",
                format!("has fov_y_deg {fov_y_deg}, outside (0, 180)"),
            ));
        }
    }
    for (field, m) in [
        ("view_from_world", c.view_matrix()),
        ("clip_from_view", c.projection_matrix()),
    ] {
        let det = m.determinant();
        if !(det.is_finite() && det.abs() > 1e-300) {
            return Err(degenerate(field, "is not invertible"));
        }
    }
    check_rigid(c)?;
    check_projection(c)
}

/// Largest entry of |RᵀR - I| (and |det R - 1|) accepted in `view_from_world`'s rotation R.
/// A camera file written by blockworld holds R to the last bit of an f64 (about 1e-16); a
/// rotation typed by hand with seven significant digits is off by about 1e-7. A deviation of
/// 1e-6 shears or scales a 10,000 px picture by at most 0.01 px, below what any stage resolves,
/// while a larger one is a camera that no rigid eye can have.
pub const RIGID_TOLERANCE: f64 = 1e-6;

/// `view_from_world` must be rigid: an orthonormal rotation with determinant +1 (no scale,
/// shear or mirror), a finite translation and a last row of (0, 0, 0, 1) (thesis Ch. II
/// eq. 2.2-2.5: the viewing transform turns and moves the world, nothing else).
fn check_rigid(c: &Camera) -> Result<(), CameraError> {
    let m = c.view_matrix();
    if (m.row(3) - crate::geom::DVec4::W).abs().max_element() > RIGID_TOLERANCE {
        return Err(degenerate(
            "view_from_world",
            "has a last row other than (0, 0, 0, 1); write a rigid transform",
        ));
    }
    let r = crate::geom::DMat3::from_mat4(m);
    let gram = r.transpose() * r - crate::geom::DMat3::IDENTITY;
    let off = gram
        .to_cols_array()
        .iter()
        .fold((r.determinant() - 1.0).abs(), |a, x| a.max(x.abs()));
    if off.is_nan() || off > RIGID_TOLERANCE {
        return Err(degenerate(
            "view_from_world",
            format!(
                "is not a rigid rotation (off by {:.1e}, tolerance {RIGID_TOLERANCE:.0e}): its \
                 3x3 part scales, shears or mirrors; re-render the camera",
                off
            ),
        ));
    }
    Ok(())
}

/// `clip_from_view` must be the projection its `projection` names (thesis Ch. II eq. 2.6):
/// perspective divides by the depth (last row (0, 0, -1, 0)), orthographic does not (last row
/// (0, 0, 0, 1)); both scale x and y by a positive factor; `near_far_mm` is ordered and, for a
/// perspective, in front of the eye.
fn check_projection(c: &Camera) -> Result<(), CameraError> {
    use crate::geom::DVec4;
    let m = c.projection_matrix();
    let (w_row, name) = match c.projection {
        Projection::Perspective { .. } => (DVec4::new(0.0, 0.0, -1.0, 0.0), "perspective"),
        _ => (DVec4::W, "orthographic"),
    };
    if (m.row(3) - w_row).abs().max_element() > RIGID_TOLERANCE {
        return Err(degenerate(
            "clip_from_view",
            format!(
                "does not match its {name} projection (the last row must be {w_row}); re-render the camera"
            ),
        ));
    }
    if !(m.x_axis.x > 0.0 && m.y_axis.y > 0.0) {
        return Err(degenerate(
            "clip_from_view",
            "does not scale x and y by positive factors; re-render the camera",
        ));
    }
    let [near, far] = c.near_far_mm;
    let in_front = near > 0.0 || name == "orthographic";
    if !(near < far && in_front) {
        return Err(degenerate(
            "near_far_mm",
            format!("[{near}, {far}] is not an ordered range in front of the eye"),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::{CameraOptions, CornerView};
    use crate::geom::DVec3;

    fn camera() -> Camera {
        let pts = [DVec3::ZERO, DVec3::new(15.0, 15.0, 15.0)];
        Camera::frame(&pts, CornerView::Se, &CameraOptions::default())
    }

    #[test]
    fn camera_file_round_trips_exactly() {
        let c = camera();
        let back = parse_camera_json(&camera_json(&c)).unwrap();
        assert_eq!(back, c);
        assert_eq!(camera_json(&back), camera_json(&c));
    }

    #[test]
    fn camera_file_refuses_unknown_fields_and_degenerate_values() {
        let good: serde_json::Value = serde_json::from_str(&camera_json(&camera())).unwrap();
        let mutate = |f: &dyn Fn(&mut serde_json::Value)| {
            let mut v = good.clone();
            f(&mut v);
            parse_camera_json(&v.to_string())
        };
        assert!(mutate(&|v| v["extra"] = 1.into()).is_err());
        assert!(mutate(&|v| v["pixel_aspect"] = 0.0.into()).is_err());
        assert!(mutate(&|v| v["size_px"] = serde_json::json!([0, 480])).is_err());
        assert!(mutate(&|v| v["view_from_world"] = serde_json::json!(vec![0.0; 16])).is_err());
        assert!(mutate(
            &|v| v["projection"] = serde_json::json!({"kind": "perspective", "fov_y_deg": 180.0})
        )
        .is_err());
        assert!(mutate(&|_| {}).is_ok());
    }

    #[test]
    fn camera_file_refuses_a_view_that_is_not_rigid_or_a_wrong_projection() {
        // An entry of 1e20 keeps the matrix invertible but not rigid (it panicked the
        // recognizer's check); a scale of 1.001 or a mirror is not rigid either.
        let good: serde_json::Value = serde_json::from_str(&camera_json(&camera())).unwrap();
        let mutate = |f: &dyn Fn(&mut serde_json::Value)| {
            let mut v = good.clone();
            f(&mut v);
            parse_camera_json(&v.to_string())
        };
        let scaled = |k: usize, by: f64| {
            move |v: &mut serde_json::Value| {
                let x = v["view_from_world"][k].as_f64().unwrap();
                v["view_from_world"][k] = (x * by + if x == 0.0 { by } else { 0.0 }).into();
            }
        };
        for (k, by) in [(9, 1e20), (0, 1.001), (5, -1.0)] {
            let err = mutate(&scaled(k, by)).unwrap_err().to_string();
            assert!(err.contains("not a rigid rotation"), "{k} {by}: {err}");
        }
        assert!(mutate(&scaled(0, 1.0 + 1e-9)).is_ok());
        let err = mutate(&|v| v["clip_from_view"][11] = (-1.0).into())
            .unwrap_err()
            .to_string();
        assert!(err.contains("orthographic projection"), "{err}");
        let err = mutate(&|v| v["near_far_mm"] = serde_json::json!([10.0, 1.0])).unwrap_err();
        assert!(err.to_string().contains("near_far_mm"), "{err}");
    }
}
