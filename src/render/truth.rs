//! The exact visible line drawing of a scene in a camera, by hidden-line removal on the block
//! polyhedra (not from pixels).

use super::Camera;
use crate::drawing::LineDrawing;
use crate::scene::Scene;

/// The visible line drawing of `scene` seen by `camera`, in picture px (not implemented yet).
pub fn visible_line_drawing(_scene: &Scene, _camera: &Camera) -> LineDrawing {
    LineDrawing::default()
}
