//! Picture and block geometry that the checks of several test files share.

use blockworld::camera::{Camera, CameraOptions, CornerView};
use blockworld::linedraw::visible_line_drawing;
use blockworld::recognize::ObservedView;
use blockworld::scene::Scene;

/// The camera of `view` framed on every block of `scene`, as `render` frames it.
pub fn frame(scene: &Scene, view: CornerView, opts: &CameraOptions) -> Camera {
    Camera::frame(&scene.world_vertices(), view, opts)
}

/// The exact line drawings of `scene` in `views`, each with its camera ([`frame`]): the
/// recognizer's input when the pictures are read without error.
pub fn exact_views(scene: &Scene, views: &[CornerView], opts: &CameraOptions) -> Vec<ObservedView> {
    views
        .iter()
        .map(|&v| {
            let camera = frame(scene, v, opts);
            let drawing = visible_line_drawing(scene, &camera);
            ObservedView::new(drawing, camera)
        })
        .collect()
}

pub use blockworld::geom::distance_to_segment_px as distance_to_segment;

pub use blockworld::scene::same_blocks;
