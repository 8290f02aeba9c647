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
}
