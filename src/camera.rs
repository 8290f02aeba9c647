//! The one camera every stage shares: the four 45-degree corner views of Chapter VI
//! (North-East, South-East, South-West, North-West) framed automatically on a scene, the
//! From/At/Up construction of Chapter II (eq. 2.5), orthographic and perspective projection,
//! picture-from-world, ray-from-picture, the front-facing test, and the reading and writing of
//! `camera_<view>.json`. Pure math, no wgpu: the renderer, its ground truth, the vision stage,
//! the recognizer and the viewer all map world points to picture pixels through this module.
//!
//! Conventions (docs/formats.md "Camera files"): azimuth is the compass bearing of the camera seen from the
//! scene, clockwise from north (-z) towards east (+x): NE 45, SE 135, SW 225, NW 315 degrees.
//! Elevation is the camera's angle above the floor, default the exact isometric angle.
//! Pixel aspect is the thesis's "vertical to horizontal pixel size ratio" (1.173913 for its
//! COHU CCD): a pixel covers `pixel_aspect` times more world height than width.

use crate::geom::{bounds3, DMat4, DVec2, DVec3, ISOMETRIC_ELEVATION_DEG};
use serde::{Deserialize, Serialize};

mod file;
mod projector;

pub use file::{camera_json, parse_camera_json, CameraError, PICTURE_CONVENTION};
pub use projector::Projector;

/// Depth PNG scale written into every `camera_<view>.json`: steps per millimetre (1/16 mm
/// resolution, up to 4095.9 mm).
pub const DEPTH_UNITS_PER_MM: f64 = 16.0;

/// One of the four corner views.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum CornerView {
    /// North-East: the camera stands at +x, -z.
    Ne,
    /// South-East: +x, +z.
    Se,
    /// South-West: -x, +z.
    Sw,
    /// North-West: -x, -z.
    Nw,
}

impl CornerView {
    /// All four, in the file order `ne, se, sw, nw`.
    pub const ALL: [CornerView; 4] = [
        CornerView::Ne,
        CornerView::Se,
        CornerView::Sw,
        CornerView::Nw,
    ];

    /// Position in [`CornerView::ALL`] (`ne` 0 to `nw` 3): what per-view seeds and
    /// per-view tables index by.
    pub fn index(self) -> usize {
        match self {
            CornerView::Ne => 0,
            CornerView::Se => 1,
            CornerView::Sw => 2,
            CornerView::Nw => 3,
        }
    }

    /// Compass bearing of the camera from the scene, degrees clockwise from north.
    pub fn azimuth_deg(self) -> f64 {
        match self {
            CornerView::Ne => 45.0,
            CornerView::Se => 135.0,
            CornerView::Sw => 225.0,
            CornerView::Nw => 315.0,
        }
    }

    /// Lower-case name used in file names (`view_ne.png`).
    pub fn name(self) -> &'static str {
        match self {
            CornerView::Ne => "ne",
            CornerView::Se => "se",
            CornerView::Sw => "sw",
            CornerView::Nw => "nw",
        }
    }

    /// Parses `ne`, `se`, `sw` or `nw` (any case).
    pub fn parse(s: &str) -> Option<CornerView> {
        CornerView::ALL
            .into_iter()
            .find(|v| v.name().eq_ignore_ascii_case(s.trim()))
    }
}

/// Orthographic (the default, as Kanade's gradient space assumes) or a real pinhole camera.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum Projection {
    /// Parallel projection.
    Orthographic,
    /// Perspective with the given vertical field of view.
    Perspective {
        /// Vertical field of view in degrees.
        fov_y_deg: f64,
    },
}

/// One projection of each kind, the perspective one with a 30-degree field of view: the
/// projections the unit tests run their checks in.
#[cfg(test)]
pub(crate) const BOTH_PROJECTIONS: [Projection; 2] = [
    Projection::Orthographic,
    Projection::Perspective { fov_y_deg: 30.0 },
];

/// How to take a view: picture size, camera angles, projection, framing.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CameraOptions {
    /// Picture width and height in pixels; default 512 x 480, the thesis's digitizer (Ch. VI).
    pub size_px: [u32; 2],
    /// Camera elevation above the floor in degrees; default the exact isometric angle.
    pub elevation_deg: f64,
    /// Projection; default orthographic.
    pub projection: Projection,
    /// Vertical/horizontal pixel size ratio; default 1 (square pixels), 1.173913 for the
    /// thesis's CCD.
    pub pixel_aspect: f64,
    /// Empty border on each side as a share of the picture; default 0.08.
    pub margin: f64,
}

impl Default for CameraOptions {
    fn default() -> Self {
        CameraOptions {
            size_px: [512, 480],
            elevation_deg: ISOMETRIC_ELEVATION_DEG,
            projection: Projection::Orthographic,
            pixel_aspect: 1.0,
            margin: 0.08,
        }
    }
}

/// A camera that maps world mm to picture px exactly: `camera.json` holds all of it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Camera {
    /// Which corner view.
    pub view: CornerView,
    /// Compass bearing, degrees clockwise from north.
    pub azimuth_deg: f64,
    /// Elevation above the floor, degrees.
    pub elevation_deg: f64,
    /// Projection kind.
    pub projection: Projection,
    /// Picture width and height in pixels.
    pub size_px: [u32; 2],
    /// Vertical/horizontal pixel size ratio.
    pub pixel_aspect: f64,
    /// Eye position, world mm.
    pub eye_mm: [f64; 3],
    /// Point looked at, world mm.
    pub target_mm: [f64; 3],
    /// World to camera (right-handed, camera looks down -z, y up), column-major 4x4.
    pub view_from_world: [f64; 16],
    /// Camera to clip space (wgpu: x, y in [-1, 1], y up, depth in [0, 1]), column-major 4x4.
    pub clip_from_view: [f64; 16],
    /// Near and far clip distances along the optical axis, mm.
    pub near_far_mm: [f64; 2],
}

impl Camera {
    /// Frames `points_mm` (usually all block vertices) in `view`: the picture is filled with a
    /// margin of `opts.margin` on the tighter axis, centred.
    pub fn frame(points_mm: &[DVec3], view: CornerView, opts: &CameraOptions) -> Camera {
        let (lo, hi) = match bounds3(points_mm.iter().copied()) {
            Some((lo, hi)) if lo.is_finite() => (lo, hi),
            _ => (DVec3::splat(-10.0), DVec3::splat(10.0)),
        };
        let target = (lo + hi) / 2.0;
        let radius = ((hi - lo).length() / 2.0).max(1.0);
        let az = view.azimuth_deg().to_radians();
        let el = opts.elevation_deg.to_radians();
        let towards_eye = DVec3::new(el.cos() * az.sin(), el.sin(), -el.cos() * az.cos());
        let [w, h] = [opts.size_px[0] as f64, opts.size_px[1] as f64];
        let fill = (1.0 - 2.0 * opts.margin).max(0.05);
        match opts.projection {
            Projection::Orthographic => {
                let dist = 4.0 * radius + 100.0;
                let eye = target + towards_eye * dist;
                let v = view_matrix(eye, target);
                let (clo, chi) = bounds_in(&v, points_mm);
                let centre = (clo + chi) / 2.0;
                // mm per horizontal pixel so both extents fit.
                let s = ((chi.x - clo.x) / (w * fill))
                    .max((chi.y - clo.y) / (opts.pixel_aspect * h * fill))
                    .max(1e-3);
                let half = DVec2::new(s * w / 2.0, s * opts.pixel_aspect * h / 2.0);
                let (near, far) = (1.0, 2.0 * dist + 20.0 * radius + 2000.0);
                let proj = orthographic(
                    centre.x - half.x,
                    centre.x + half.x,
                    centre.y - half.y,
                    centre.y + half.y,
                    near,
                    far,
                );
                Camera::build(view, opts, eye, target, v, proj, near, far)
            }
            Projection::Perspective { fov_y_deg } => {
                let half_v = (fov_y_deg.to_radians() / 2.0).clamp(1e-3, 1.5);
                let aspect = w / (h * opts.pixel_aspect);
                let half_h = (half_v.tan() * aspect).atan();
                let dist = radius / (half_v.min(half_h).sin() * fill);
                let eye = target + towards_eye * dist;
                let v = view_matrix(eye, target);
                let (near, far) = (
                    (dist - 2.0 * radius).max(1.0),
                    dist + 20.0 * radius + 2000.0,
                );
                let proj = perspective(half_v, aspect, near, far);
                Camera::build(view, opts, eye, target, v, proj, near, far)
            }
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn build(
        view: CornerView,
        opts: &CameraOptions,
        eye: DVec3,
        target: DVec3,
        v: DMat4,
        p: DMat4,
        near: f64,
        far: f64,
    ) -> Camera {
        Camera {
            view,
            azimuth_deg: view.azimuth_deg(),
            elevation_deg: opts.elevation_deg,
            projection: opts.projection,
            size_px: opts.size_px,
            pixel_aspect: opts.pixel_aspect,
            eye_mm: eye.to_array(),
            target_mm: target.to_array(),
            view_from_world: v.to_cols_array(),
            clip_from_view: p.to_cols_array(),
            near_far_mm: [near, far],
        }
    }

    /// The same camera describing its picture averaged `factor` x `factor` down (docs/rendering.md
    /// "Photographic look"; the thesis's 2 x 2 averaging, Ch. VI): `size_px` divided by
    /// `factor`, the projection unchanged, so a world point lands on the written picture's px,
    /// scaled by `1 / factor` from the full picture. Sides not divisible by `factor` drop their
    /// remainder (as the averaging drops an odd last row or column).
    pub fn downsampled(&self, factor: u32) -> Camera {
        let f = factor.max(1);
        let mut out = *self;
        out.size_px = [self.size_px[0] / f, self.size_px[1] / f];
        if out.size_px[0] * f != self.size_px[0] || out.size_px[1] * f != self.size_px[1] {
            // The kept pixels span less than the full picture: shrink clip space to them.
            let sx = (out.size_px[0] * f) as f64 / self.size_px[0] as f64;
            let sy = (out.size_px[1] * f) as f64 / self.size_px[1] as f64;
            let to_kept = DMat4::from_cols_array(&[
                1.0 / sx,
                0.0,
                0.0,
                0.0, //
                0.0,
                1.0 / sy,
                0.0,
                0.0, //
                0.0,
                0.0,
                1.0,
                0.0, //
                1.0 / sx - 1.0,
                1.0 - 1.0 / sy,
                0.0,
                1.0,
            ]);
            out.clip_from_view = (to_kept * self.projection_matrix()).to_cols_array();
        }
        out
    }

    /// World to camera matrix.
    pub fn view_matrix(&self) -> DMat4 {
        DMat4::from_cols_array(&self.view_from_world)
    }

    /// Camera to clip matrix.
    pub fn projection_matrix(&self) -> DMat4 {
        DMat4::from_cols_array(&self.clip_from_view)
    }

    /// World to clip matrix.
    pub fn clip_from_world(&self) -> DMat4 {
        self.projection_matrix() * self.view_matrix()
    }

    /// Eye position in world mm.
    pub fn eye(&self) -> DVec3 {
        DVec3::from_array(self.eye_mm)
    }

    /// Projects a world point to picture px (x right, y up, origin bottom-left); `z` of the
    /// result is the depth along the optical axis in mm (positive in front of the eye).
    pub fn picture_from_world(&self, p_mm: DVec3) -> DVec3 {
        let c = self.view_matrix() * p_mm.extend(1.0);
        let clip = self.projection_matrix() * c;
        let ndc = clip.truncate() / clip.w;
        DVec3::new(
            (ndc.x + 1.0) / 2.0 * self.size_px[0] as f64,
            (ndc.y + 1.0) / 2.0 * self.size_px[1] as f64,
            -c.z,
        )
    }

    /// The world ray through picture point `(x_px, y_px)`: origin (on the near plane for
    /// orthographic views, the eye for perspective) and unit direction.
    pub fn ray_through_picture(&self, x_px: f64, y_px: f64) -> (DVec3, DVec3) {
        Projector::new(self).ray(DVec2::new(x_px, y_px))
    }

    /// Whether a face with outward unit normal `normal` through `point_mm` turns towards the
    /// eye: the one front-facing test of the renderer and its ground truth (a face seen exactly
    /// edge-on, within [`FRONT_FACING_COS`], is neither front nor back).
    pub fn faces_eye(&self, normal: DVec3, point_mm: DVec3) -> bool {
        let to_eye = if self.is_orthographic() {
            self.towards_eye()
        } else {
            (self.eye() - point_mm).normalize()
        };
        normal.dot(to_eye) > FRONT_FACING_COS
    }

    /// The camera's right, up and towards-eye axes in world coordinates (the rows of the
    /// rotation in `view_from_world`; eq. 2.4's A1, A2 and -A3).
    pub fn axes_in_world(&self) -> [DVec3; 3] {
        let v = self.view_matrix();
        let row = |i: usize| DVec3::new(v.col(0)[i], v.col(1)[i], v.col(2)[i]);
        [row(0), row(1), row(2)]
    }

    /// Unit vector from the scene towards the eye (for orthographic views, the reverse of the
    /// viewing direction everywhere).
    pub fn towards_eye(&self) -> DVec3 {
        (self.eye() - DVec3::from_array(self.target_mm)).normalize()
    }

    /// `true` for orthographic cameras.
    pub fn is_orthographic(&self) -> bool {
        matches!(self.projection, Projection::Orthographic)
    }
}

/// Cosine below which a face counts as seen edge-on, not front-facing: far below any real
/// face's tilt (a face turned by 1e-7 degrees), far above rounding noise.
pub const FRONT_FACING_COS: f64 = 1e-9;

/// The view matrix of Chapter II's From/At/Up construction (eq. 2.5a-c): world to camera,
/// right-handed, the camera looking down its -z, picture up along the projection of `up_dir`.
/// The thesis writes `U' = A - U` and a left-handed viewing system, which turns the picture
/// upside down on a y-up picture; this follows the geometry instead (docs/thesis-readings.md "Thesis readings").
pub fn look_at(from_mm: DVec3, at_mm: DVec3, up_dir: DVec3) -> DMat4 {
    glam::dcamera::rh::view::look_at_mat4(from_mm, at_mm, up_dir)
}

/// The corner views' look-at: world +y is picture up.
fn view_matrix(eye: DVec3, target: DVec3) -> DMat4 {
    look_at(eye, target, DVec3::Y)
}

/// wgpu's clip space: depth 0 at near, 1 at far, y up.
fn orthographic(l: f64, r: f64, b: f64, t: f64, near: f64, far: f64) -> DMat4 {
    glam::dcamera::rh::proj::directx::orthographic(l, r, b, t, near, far)
}

fn perspective(half_fov_y: f64, aspect: f64, near: f64, far: f64) -> DMat4 {
    glam::dcamera::rh::proj::directx::perspective(2.0 * half_fov_y, aspect, near, far)
}

fn bounds_in(v: &DMat4, points: &[DVec3]) -> (DVec3, DVec3) {
    bounds3(points.iter().map(|p| v.transform_point3(*p)))
        .unwrap_or((DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube_points() -> Vec<DVec3> {
        let mut v = Vec::new();
        for i in 0..8 {
            v.push(DVec3::new(
                if i & 4 != 0 { 7.5 } else { -7.5 },
                if i & 2 != 0 { 15.0 } else { 0.0 },
                if i & 1 != 0 { 7.5 } else { -7.5 },
            ));
        }
        v
    }

    #[test]
    fn each_view_indexes_its_place_in_all_and_parses_back_from_its_name() {
        for (k, view) in CornerView::ALL.into_iter().enumerate() {
            assert_eq!(view.index(), k, "{view:?}");
            assert_eq!(CornerView::parse(view.name()), Some(view));
        }
    }

    #[test]
    fn ne_camera_stands_at_plus_x_minus_z_and_up_is_up() {
        let c = Camera::frame(&cube_points(), CornerView::Ne, &CameraOptions::default());
        let eye = c.eye();
        assert!(eye.x > 0.0 && eye.z < 0.0 && eye.y > 0.0);
        let top = c.picture_from_world(DVec3::new(0.0, 15.0, 0.0));
        let bottom = c.picture_from_world(DVec3::new(0.0, 0.0, 0.0));
        assert!(top.y > bottom.y, "picture y is up");
        // East (+x) is on the left in the NE view: the camera looks towards -x, +z.
        let east = c.picture_from_world(DVec3::new(7.5, 0.0, 7.5));
        let north = c.picture_from_world(DVec3::new(-7.5, 0.0, -7.5));
        assert!(east.x < north.x);
    }

    #[test]
    fn framing_fills_with_margin_and_rays_round_trip() {
        for projection in BOTH_PROJECTIONS {
            let opts = CameraOptions {
                projection,
                pixel_aspect: 1.173913,
                ..Default::default()
            };
            for view in CornerView::ALL {
                let c = Camera::frame(&cube_points(), view, &opts);
                let px: Vec<DVec3> = cube_points()
                    .iter()
                    .map(|p| c.picture_from_world(*p))
                    .collect();
                for p in &px {
                    assert!(p.x > 0.0 && p.x < 512.0 && p.y > 0.0 && p.y < 480.0, "{p}");
                }
                let p = DVec3::new(7.5, 15.0, -7.5);
                let q = c.picture_from_world(p);
                let (o, d) = c.ray_through_picture(q.x, q.y);
                let dist = (p - o).cross(d).length();
                assert!(dist < 1e-6, "ray misses by {dist} mm");
            }
        }
        // Orthographic: the tighter axis spans exactly the filled share of the picture.
        let c = Camera::frame(&cube_points(), CornerView::Ne, &CameraOptions::default());
        let xs: Vec<f64> = cube_points()
            .iter()
            .map(|p| c.picture_from_world(*p).x)
            .collect();
        let ys: Vec<f64> = cube_points()
            .iter()
            .map(|p| c.picture_from_world(*p).y)
            .collect();
        let span = |v: &[f64]| {
            v.iter().cloned().fold(f64::MIN, f64::max) - v.iter().cloned().fold(f64::MAX, f64::min)
        };
        let fill = 1.0 - 2.0 * 0.08;
        assert!((span(&xs) - 512.0 * fill).abs() < 1e-6 || (span(&ys) - 480.0 * fill).abs() < 1e-6);
    }

    #[test]
    fn a_downsampled_camera_maps_points_to_the_averaged_picture() {
        let full = Camera::frame(&cube_points(), CornerView::Se, &CameraOptions::default());
        for factor in [2, 4] {
            let small = full.downsampled(factor);
            assert_eq!(small.size_px, [512 / factor, 480 / factor]);
            for p in cube_points() {
                let (a, b) = (full.picture_from_world(p), small.picture_from_world(p));
                assert!((a.x / factor as f64 - b.x).abs() < 1e-9, "{a} {b}");
                assert!((a.y / factor as f64 - b.y).abs() < 1e-9, "{a} {b}");
            }
        }
        // An odd side: 5 px averaged 2 x 2 keeps 2 output px covering the first 4 input px;
        // picture y is up, so the dropped bottom row shifts y by one input px.
        let odd = CameraOptions {
            size_px: [5, 5],
            ..CameraOptions::default()
        };
        let full = Camera::frame(&cube_points(), CornerView::Ne, &odd);
        let small = full.downsampled(2);
        assert_eq!(small.size_px, [2, 2]);
        for p in cube_points() {
            let (a, b) = (full.picture_from_world(p), small.picture_from_world(p));
            assert!((a.x / 2.0 - b.x).abs() < 1e-9, "{a} {b}");
            assert!(((a.y - 1.0) / 2.0 - b.y).abs() < 1e-9, "{a} {b}");
        }
    }
}
