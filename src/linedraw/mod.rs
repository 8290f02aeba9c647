//! The exact visible line drawing of a scene in a camera, by hidden-line removal on the block
//! polyhedra (not from pixels): the ground truth `lines_<view>.json` of docs/rendering.md "Rendering", in the
//! vocabulary of Chapter IV (lines, junctions, six-bit codes) and Kanade's labels (Chapter II).
//!
//! ## Why a stage of its own, and why this name
//! The thesis's input is a *line drawing* (Chapter IV builds it from a picture; Chapter II's
//! labels are labels of one), and this module *draws* it from geometry: hence `linedraw`, the
//! thing it makes rather than the use one caller puts it to. It is pure geometry (no wgpu, no
//! pixels), taking a [`Scene`] and a [`Camera`] and returning a [`LineDrawing`], and it has
//! three kinds of caller: the renderer's ground truth (`render`), the recognizer's check that an
//! answer redraws the input (`recognize::verify`), and the comparisons and benches of the
//! binary. Inside `render` it let the recognizer import the GPU code; beside it, the stages that
//! only need the drawing depend on geometry alone (`tests/layering.rs`).
//!
//! ## Algorithm
//! 1. **Scene geometry** (`geometry`): every block face as a plane and a picture polygon; a face
//!    is *front-facing* when the eye is on its outer side (faces seen exactly edge-on are
//!    neither front nor back and hide nothing).
//! 2. **Visibility** (`visibility`): each block edge with at least one front-facing face is
//!    clipped against every front-facing face of the other blocks: the 2D overlap of the edge
//!    with the face's picture polygon (a closed polygon, so an edge lying on a silhouette counts
//!    as behind it) is intersected with the part of the edge that lies behind the face's plane by
//!    more than [`TruthTolerances::contact_mm`]. What is left are exact parameter intervals of
//!    the 3D edge, so T junctions come out exact. A face whose plane contains the edge never
//!    hides it.
//! 3. **Kinds** (`classify`): each visible interval is cut where another block's edge or vertex
//!    touches it (within [`TruthTolerances::seam_mm`]), then every piece is classified by
//!    casting one ray on each side of its midpoint, [`TruthTolerances::sample_offset_mm`] away:
//!    background or a distant surface on one side makes it a boundary; the same plane of two
//!    blocks on both sides a crack; two planes meeting at the edge a convex or concave line
//!    (a contact when they belong to different blocks).
//! 4. **Assembly** (`assemble`): pieces that coincide in the picture are kept once: the nearer
//!    one where they lie at different depths (an edge hidden exactly behind a silhouette), else
//!    the one whose own faces are seen beside it, else the upper block's (a lower block's top
//!    edge under the flush bottom edge of the block above); a trimmed piece is classified
//!    again. Then collinear pieces of the same edge and kind are joined, line ends closer than
//!    the snap distance become one point, and a line is split where another line ends on its
//!    interior (the T junctions); codes and junctions come from [`LineDrawing::finalize`].
//!
//! ## The viewer's hidden-line removal
//! [`eye_space`] is the other hidden-line removal, the one the viewer (`view`, Chapter VI-VII)
//! draws with: in eye coordinates with hither clipping, for a camera that may stand inside the
//! scene, and without line kinds. It shares the interval complement
//! ([`unit_interval_complement`]), Newell's normal ([`crate::geom::newell_vector`]) and the
//! contact tolerance ([`CONTACT_TOL_MM`]) with the exact drawing above.
//!
//! ## Round parts
//! A round part's own lines come from `round` in closed form (rims as chords with every end on
//! the exact circle, flagged in [`LineDrawing::curved_lines`]; the silhouette generators at the
//! exact tangent angles); its faces, for hiding and for the classifying rays, are its catalog
//! prism's (within 0.009 mm of the cylinder, docs/formats.md "Block catalog").
//!
//! ## Contact policy
//! Settled poses are not flush (docs/formats.md "The exact line drawing"). Faces parallel within
//! [`TruthTolerances::parallel_deg`] and within [`TruthTolerances::seam_mm`] of each other
//! count as one surface, and a face hides nothing closer than [`TruthTolerances::contact_mm`]
//! ([`crate::geom::CONTACT_TOL_MM`]). `seam_mm` is twice the contact tolerance because two
//! neighbours may each be off flush by up to `CONTACT_TOL_MM`. Points and lines closer in the
//! picture than `seam_mm` projected (or [`TruthTolerances::merge_px`], whichever is larger)
//! are one: no line of a grid scene is that short.

mod assemble;
mod classify;
pub mod eye_space;
mod geometry;
mod round;
mod visibility;

use crate::camera::Camera;
use crate::drawing::LineDrawing;
use crate::geom::CONTACT_TOL_MM;
use crate::scene::Scene;

/// The tolerances of the hidden-line removal, all named.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TruthTolerances {
    /// A face hides an edge point only if the point lies more than this behind the face's plane,
    /// in mm; default [`CONTACT_TOL_MM`] (0.05 mm), so touching faces never hide each other.
    pub contact_mm: f64,
    /// Surfaces and edges of different blocks closer than this count as one seam, in mm;
    /// default `2 * CONTACT_TOL_MM` (each neighbour may be off flush by `CONTACT_TOL_MM`).
    pub seam_mm: f64,
    /// Faces whose normals differ by less than this are parallel, in degrees; default 0.5.
    pub parallel_deg: f64,
    /// Line ends closer than this in the picture are always one point, in px; default 0.01
    /// (docs/formats.md "The exact line drawing").
    pub merge_px: f64,
    /// How far beside a line the classifying rays look, in mm; default 0.3 (larger than any
    /// seam gap, far smaller than a block).
    pub sample_offset_mm: f64,
}

impl Default for TruthTolerances {
    fn default() -> Self {
        TruthTolerances {
            contact_mm: CONTACT_TOL_MM,
            seam_mm: 2.0 * CONTACT_TOL_MM,
            parallel_deg: 0.5,
            merge_px: 0.01,
            sample_offset_mm: 0.3,
        }
    }
}

/// The visible line drawing of `scene` seen by `camera`, in picture px (x right, y up, origin at
/// the bottom-left corner), with every line's kind and 3D edge, and every point's six-bit code
/// (Chapter IV) and junction class (Chapter V, Figure 5.1). Uses [`TruthTolerances::default`].
pub fn visible_line_drawing(scene: &Scene, camera: &Camera) -> LineDrawing {
    visible_line_drawing_with_tolerances(scene, camera, &TruthTolerances::default())
}

/// [`visible_line_drawing`] with explicit tolerances.
pub fn visible_line_drawing_with_tolerances(
    scene: &Scene,
    camera: &Camera,
    tol: &TruthTolerances,
) -> LineDrawing {
    visible_line_drawing_with_progress(scene, camera, tol, &|_, _| {})
}

/// [`visible_line_drawing_with_tolerances`] reporting `(done, total)` as it goes: the hidden-line
/// removal and the classification each count the scene's edges once (`total` is twice the
/// number of edges), so a large scene's drawing, which takes seconds, can show progress
/// (docs/cli.md "Exit codes and progress output").
pub fn visible_line_drawing_with_progress(
    scene: &Scene,
    camera: &Camera,
    tol: &TruthTolerances,
    progress: &(dyn Fn(u64, u64) + Sync),
) -> LineDrawing {
    let geo = geometry::SceneGeometry::new(scene, camera);
    let edges = geo.edges.len() as u64;
    let intervals = visibility::visible_intervals(&geo, tol, &|done| progress(done, 2 * edges));
    let classified = intervals.len().max(1) as u64;
    let pieces = classify::classify_pieces(&geo, &intervals, tol, &|done| {
        progress(edges + done * edges / classified, 2 * edges)
    });
    assemble::assemble_drawing(&geo, pieces, tol)
}

/// `[0, 1]` minus the union of the parameter intervals `hidden` (sorted in place by their
/// start), in order: what is left visible of an edge once each hiding face has taken its
/// interval. Shared by the exact drawing (`visibility`) and the viewer's [`eye_space`].
pub fn unit_interval_complement(hidden: &mut [[f64; 2]]) -> Vec<[f64; 2]> {
    hidden.sort_by(|a, b| a[0].total_cmp(&b[0]));
    let mut out = Vec::new();
    let mut start = 0.0f64;
    for h in hidden.iter() {
        if h[0] > start {
            out.push([start, h[0]]);
        }
        start = start.max(h[1]);
    }
    if start < 1.0 {
        out.push([start, 1.0]);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn complement_of_overlapping_intervals() {
        let mut h = [[0.5, 0.7], [0.1, 0.2], [0.6, 0.8]];
        assert_eq!(
            unit_interval_complement(&mut h),
            vec![[0.0, 0.1], [0.2, 0.5], [0.8, 1.0]]
        );
        assert!(unit_interval_complement(&mut [[0.0, 1.0]]).is_empty());
    }
    use crate::camera::{CameraOptions, CornerView};
    use crate::scene::Block;
    use glam::DVec3;

    #[test]
    fn an_empty_scene_draws_nothing_and_a_cube_draws_a_hexagon_with_a_fork() {
        let empty = Scene::new("empty", vec![]);
        let cam = Camera::frame(&[], CornerView::Ne, &CameraOptions::default());
        assert!(visible_line_drawing(&empty, &cam).lines.is_empty());
        let cube = Scene::new(
            "cube",
            vec![Block::new("b15", DVec3::new(0.0, 7.5, 0.0), 0.0)],
        );
        let cam = Camera::frame(
            &cube.blocks[0].world_vertices(),
            CornerView::Se,
            &CameraOptions::default(),
        );
        let d = visible_line_drawing(&cube, &cam);
        assert_eq!((d.points.len(), d.lines.len()), (7, 9));
        assert_eq!(d.codes.iter().filter(|c| c.0 == 22).count(), 1);
    }
}
