//! World to picture and back for one camera, with the matrices multiplied once: the form the
//! ground truth's hidden-line removal uses for its many points (Chapter II, eqs. 2.2-2.8, in
//! the camera's matrices).

use crate::camera::Camera;
use crate::geom::{DMat4, DVec2, DVec3, DVec4};

/// A camera's projection, ready for many points.
#[derive(Debug, Clone, Copy)]
pub struct Projector {
    clip_from_world: DMat4,
    world_from_clip: DMat4,
    view_from_world: DMat4,
    size_px: DVec2,
    right: DVec3,
}

impl Projector {
    /// The projector of `camera`.
    pub fn new(camera: &Camera) -> Projector {
        let clip_from_world = camera.clip_from_world();
        let towards_eye = camera.towards_eye();
        Projector {
            clip_from_world,
            world_from_clip: clip_from_world.inverse(),
            view_from_world: camera.view_matrix(),
            size_px: DVec2::new(camera.size_px[0] as f64, camera.size_px[1] as f64),
            right: DVec3::Y.cross(towards_eye).normalize_or(DVec3::X),
        }
    }

    /// Picture px of a world point and its clip w (1 for orthographic cameras).
    pub fn picture_and_w(&self, p_mm: DVec3) -> (DVec2, f64) {
        let c = self.clip_from_world * p_mm.extend(1.0);
        let ndc = DVec2::new(c.x / c.w, c.y / c.w);
        ((ndc + DVec2::ONE) * 0.5 * self.size_px, c.w)
    }

    /// Picture px of a world point.
    pub fn picture(&self, p_mm: DVec3) -> DVec2 {
        self.picture_and_w(p_mm).0
    }

    /// Depth along the optical axis in mm.
    pub fn depth_mm(&self, p_mm: DVec3) -> f64 {
        -(self.view_from_world * p_mm.extend(1.0)).z
    }

    /// The ray through picture point `q_px`: origin (on the near plane for orthographic views,
    /// the eye for perspective) and unit direction away from the eye.
    pub fn ray(&self, q_px: DVec2) -> (DVec3, DVec3) {
        let ndc = q_px / self.size_px * 2.0 - DVec2::ONE;
        let unproject = |z: f64| {
            let p = self.world_from_clip * DVec4::new(ndc.x, ndc.y, z, 1.0);
            p.truncate() / p.w
        };
        let (a, b) = (unproject(0.0), unproject(1.0));
        (a, (b - a).normalize())
    }

    /// Picture px per world mm at `p_mm`, measured across the view (horizontally).
    pub fn px_per_mm(&self, p_mm: DVec3) -> f64 {
        self.picture(p_mm + self.right).distance(self.picture(p_mm))
    }

    /// The 3D edge parameter `t` of the point at picture parameter `s` along the projected
    /// segment whose ends have clip w `wa`, `wb` (perspective division is not linear).
    pub fn t_from_s(s: f64, wa: f64, wb: f64) -> f64 {
        let den = (1.0 - s) * wb + s * wa;
        if den.abs() < 1e-300 {
            s
        } else {
            s * wa / den
        }
    }

    /// Inverse of [`Projector::t_from_s`].
    pub fn s_from_t(t: f64, wa: f64, wb: f64) -> f64 {
        let den = wa + t * (wb - wa);
        if den.abs() < 1e-300 {
            t
        } else {
            t * wb / den
        }
    }
}
