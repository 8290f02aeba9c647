//! Picture and block geometry that the checks of several test files share.

use blockworld::camera::{Camera, CameraOptions, CornerView};
use blockworld::geom::DVec2;
use blockworld::linedraw::visible_line_drawing;
use blockworld::recognize::ObservedView;
use blockworld::scene::{Block, Scene};

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
            ObservedView { drawing, camera }
        })
        .collect()
}

/// Distance (px) from `p` to the segment `a`–`b` in the picture: to the foot of the
/// perpendicular when it falls on the segment, else to the nearer end (to `a` when the segment
/// has no length).
pub fn distance_to_segment(p: DVec2, a: DVec2, b: DVec2) -> f64 {
    let ab = b - a;
    let len2 = ab.length_squared();
    let t = if len2 == 0.0 {
        0.0
    } else {
        ((p - a).dot(ab) / len2).clamp(0.0, 1.0)
    };
    p.distance(a + ab * t)
}

/// `true` when `got` holds the blocks of `truth`: as many blocks, and for each of `truth` one of
/// `got` of the same type with every corner within `tol_mm` of one of its corners (the same
/// solid whatever symmetry its turn has; a wedge has none, so its facing counts).
pub fn same_blocks(got: &[Block], truth: &[Block], tol_mm: f64) -> bool {
    got.len() == truth.len()
        && truth.iter().all(|t| {
            let corners = t.world_vertices();
            got.iter().any(|b| {
                let mine = b.world_vertices();
                b.block_type.id == t.block_type.id
                    && corners
                        .iter()
                        .all(|p| mine.iter().any(|q| q.distance(*p) < tol_mm))
            })
        })
}
