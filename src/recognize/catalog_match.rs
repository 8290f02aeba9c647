//! Step 3 of the recognizer (Chapter V): turn each parallelogram's height and side lengths into
//! the catalog blocks they can belong to (with yaw 0 or 90), classify the blocks into layers
//! (the bottom layer at y = 0) and find which blocks touch.

use super::parallelogram::{drop_below_ray, horizontal_axis_on, ray_at_height};
use super::parallelogram::{Face, Parallelogram};
use super::Camera;
use crate::camera::Projector;
use crate::drawing::LineDrawing;
use crate::geom::DVec2;
use crate::geom::{DVec3, CONTACT_TOL_MM};
use crate::scene::{basic_blocks, Block, BlockType, Orientation};
use std::cell::RefCell;

/// Tolerances of the catalog match, mm and degrees.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MatchTolerances {
    /// A measured length may exceed a catalog length by this much, mm; default 1.0.
    pub length_mm: f64,
    /// A side may deviate from a world axis by this much in the picture, degrees; default 4.
    pub axis_deg: f64,
}

impl Default for MatchTolerances {
    fn default() -> Self {
        MatchTolerances {
            length_mm: 1.0,
            axis_deg: 4.0,
        }
    }
}

/// The heights (mm) a top face can have: every sum of catalog block heights up to
/// `max_height_mm` (a stack of layers on the floor, Chapter V), ascending.
pub fn level_heights_mm(max_height_mm: f64) -> Vec<f64> {
    let heights: Vec<f64> = basic_blocks().map(|t| t.size_mm().y).collect();
    let mut levels: Vec<f64> = vec![0.0];
    let mut i = 0;
    while i < levels.len() {
        for h in &heights {
            let y = levels[i] + h;
            if y <= max_height_mm + 1e-9 && !levels.iter().any(|l| (l - y).abs() < 1e-6) {
                levels.push(y);
            }
        }
        i += 1;
    }
    levels.retain(|&y| y > 0.0);
    levels.sort_by(f64::total_cmp);
    levels
}

/// The block's footprint along world x and z for yaw 0 or 90 degrees.
fn footprint_mm(t: &BlockType, yaw_deg: f64) -> (f64, f64) {
    let s = t.size_mm();
    if yaw_deg == 0.0 {
        (s.x, s.z)
    } else {
        (s.z, s.x)
    }
}

/// The yaws worth trying for a type: 0, and 90 when the footprint is not square.
pub fn distinct_yaws_deg(t: &BlockType) -> Vec<f64> {
    let s = t.size_mm();
    if (s.x - s.z).abs() < 1e-9 {
        vec![0.0]
    } else {
        vec![0.0, 90.0]
    }
}

/// The horizontal axis into a block from its visible side face whose top edge runs along
/// `along`: perpendicular to it, pointing away from the camera at `at_mm`.
fn into_block_axis(camera: &Camera, at_mm: DVec3, along: DVec3) -> DVec3 {
    let side = DVec3::new(along.z, 0.0, -along.x);
    let towards_eye = if camera.is_orthographic() {
        camera.towards_eye()
    } else {
        camera.eye() - at_mm
    };
    if side.dot(towards_eye) > 0.0 {
        -side
    } else {
        side
    }
}

/// The thesis's parallelogram record in world millimetres (Chapter IV: "vertex location
/// (x, y), height, length of left-up side ... right-up side"), for a face whose top lies at
/// a given height; converted through the camera's rays, so exact in any projection.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ParallelogramMm {
    /// The vertex in world mm.
    pub vertex_mm: DVec3,
    /// World unit axes (±x or ±z) of the two horizontal edges from the vertex; for a side
    /// face the second is the axis into the block, away from the camera.
    pub axes: [DVec3; 2],
    /// Length of each side up to its first point, mm (0 for a side face's unseen depth): a
    /// lower bound of the block's edges.
    pub visible_side_mm: [f64; 2],
    /// The closed parallelogram's sides, mm (for a side face: the top edge and the height).
    pub closed_side_mm: Option<[f64; 2]>,
    /// The visible vertical edge below the vertex, mm.
    pub height_mm: Option<f64>,
}

/// Measures `p` in millimetres with its top at `y_top_mm`: `None` when a side is off the world
/// axes by more than `tol.axis_deg` (Chapter VII: blocks in one direction).
pub fn measure_parallelogram_mm(
    p: &Parallelogram,
    drawing: &LineDrawing,
    camera: &Camera,
    y_top_mm: f64,
    tol: &MatchTolerances,
) -> Option<ParallelogramMm> {
    let proj = Projector::new(camera);
    let rays = RayCache::new(&proj, camera.is_orthographic());
    measure_on(p, drawing, camera, &rays, y_top_mm, tol)
}

/// The camera rays through a parallelogram's points, each made once for all the heights it is
/// measured at, and (orthographic views only, where an axis looks the same everywhere) the
/// world axis of each side.
struct RayCache<'a> {
    proj: &'a Projector,
    rays: RefCell<Vec<(DVec2, (DVec3, DVec3))>>,
    axes: RefCell<[Option<(DVec3, f64)>; 2]>,
    orthographic: bool,
}

impl<'a> RayCache<'a> {
    fn new(proj: &'a Projector, orthographic: bool) -> Self {
        RayCache {
            proj,
            rays: RefCell::new(Vec::new()),
            axes: RefCell::new([None; 2]),
            orthographic,
        }
    }

    fn ray(&self, p_px: DVec2) -> (DVec3, DVec3) {
        let mut rays = self.rays.borrow_mut();
        if let Some((_, r)) = rays.iter().find(|(q, _)| *q == p_px) {
            return *r;
        }
        let r = self.proj.ray(p_px);
        rays.push((p_px, r));
        r
    }

    fn axis(&self, k: usize, corner: DVec3, picture_dir: DVec2) -> (DVec3, f64) {
        if !self.orthographic {
            return horizontal_axis_on(self.proj, corner, picture_dir);
        }
        *self.axes.borrow_mut()[k]
            .get_or_insert_with(|| horizontal_axis_on(self.proj, corner, picture_dir))
    }
}

/// [`measure_parallelogram_mm`] through the rays of `rays` (made once per parallelogram).
fn measure_on(
    p: &Parallelogram,
    drawing: &LineDrawing,
    camera: &Camera,
    rays: &RayCache,
    y_top_mm: f64,
    tol: &MatchTolerances,
) -> Option<ParallelogramMm> {
    let v_px = p.vertex.at_px;
    let corner = ray_at_height(rays.ray(v_px), y_top_mm)?;
    let along_mm = |i: usize| {
        ray_at_height(rays.ray(drawing.points[i]), y_top_mm).map_or(0.0, |q| q.distance(corner))
    };
    let down_mm = |i: usize| drop_below_ray(rays.ray(drawing.points[i]), corner);
    let horizontal = match p.face {
        Face::Top(_) => 2,
        Face::Side(_) => 1,
    };
    let mut axes = [DVec3::ZERO; 2];
    let mut visible_side_mm = [0.0; 2];
    for k in 0..horizontal {
        let end = p.sides[k].first()?.point;
        let (axis, ang) = rays.axis(k, corner, drawing.points[end] - v_px);
        if ang > tol.axis_deg {
            return None;
        }
        axes[k] = axis;
        visible_side_mm[k] = along_mm(end);
    }
    if horizontal == 1 {
        axes[1] = into_block_axis(camera, corner, axes[0]);
    }
    if axes[0].dot(axes[1]).abs() >= 0.5 {
        return None;
    }
    let closed_side_mm = p.closed.map(|[a, b]| match p.face {
        Face::Top(_) => [along_mm(a.point), along_mm(b.point)],
        Face::Side(_) => [along_mm(a.point), down_mm(b.point)],
    });
    Some(ParallelogramMm {
        vertex_mm: corner,
        axes,
        visible_side_mm,
        closed_side_mm,
        height_mm: p.down_end.map(down_mm),
    })
}

/// One catalog block a parallelogram proposes, and whether it fits the parallelogram exactly.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Proposal {
    /// The catalog block, placed in world mm.
    pub block: Block,
    /// `true` when the block's sides equal the closed parallelogram's (and its height the
    /// visible "down" edge, when there is one) within the length tolerance: the thesis's
    /// direct reading of a block's type from its sizes (Chapter V, "this information is put
    /// together to obtain the type of the blocks"), not merely a block at least that long.
    pub closed_fit: bool,
    /// `true` when the exact fit is of a side face (a closed parallelogram under a top corner):
    /// the block's own side is seen, which a ghost of a lower block's top face never shows
    /// (`direct`).
    pub side_fit: bool,
}

/// Whether a block with horizontal extents `dims` along `m.axes` and height `h` has exactly the
/// sides of `m`'s closed parallelogram (and of its visible vertical edge).
fn fits_closed(m: &ParallelogramMm, face: Face, dims: [f64; 2], h: f64, tol_mm: f64) -> bool {
    let Some([a, b]) = m.closed_side_mm else {
        return false;
    };
    let near = |x: f64, y: f64| (x - y).abs() <= tol_mm;
    let sides = match face {
        Face::Top(_) => near(dims[0], a) && near(dims[1], b),
        Face::Side(_) => near(dims[0], a) && near(h, b),
    };
    sides && m.height_mm.is_none_or(|d| near(h, d))
}

/// Every catalog block (type, yaw 0/90) that has `p`'s vertex as the corner `p.face` of its
/// top face (or the top corner of a side face) at one of `levels_mm`, with edges at least as
/// long as the visible ones and a height at least the visible "down" edge (rule (1) of
/// Chapter V: an edge may be occluded, never longer than the block), each marked when it fits
/// the closed parallelogram exactly. Empty when a side is not along a world axis.
pub fn catalog_proposals(
    p: &Parallelogram,
    drawing: &LineDrawing,
    camera: &Camera,
    levels_mm: &[f64],
    tol: &MatchTolerances,
) -> Vec<Proposal> {
    catalog_proposals_where(p, drawing, camera, levels_mm, tol, &|_| true)
}

/// [`catalog_proposals`] at the levels where `corner_ok` accepts the measured top corner
/// (world mm): the direct path asks only where the corner is seen inside every view's
/// silhouette, as every corner of the blocks it takes must be.
pub fn catalog_proposals_where(
    p: &Parallelogram,
    drawing: &LineDrawing,
    camera: &Camera,
    levels_mm: &[f64],
    tol: &MatchTolerances,
    corner_ok: &dyn Fn(DVec3) -> bool,
) -> Vec<Proposal> {
    let mut out = Vec::new();
    let proj = Projector::new(camera);
    let rays = RayCache::new(&proj, camera.is_orthographic());
    // Every (type, yaw) with its footprint and height, read from the catalog once.
    let shapes: Vec<(&'static BlockType, f64, (f64, f64), f64)> = basic_blocks()
        .flat_map(|t| {
            let h = t.size_mm().y;
            distinct_yaws_deg(t)
                .into_iter()
                .map(move |yaw| (t, yaw, footprint_mm(t, yaw), h))
        })
        .collect();
    for &y_top in levels_mm {
        // The top corner first (as `measure_on` finds it): most levels end here.
        let corner = ray_at_height(rays.ray(p.vertex.at_px), y_top);
        if !corner.is_some_and(corner_ok) {
            continue;
        }
        let Some(m) = measure_on(p, drawing, camera, &rays, y_top, tol) else {
            continue;
        };
        let (corner, axes, min_len) = (m.vertex_mm, m.axes, m.visible_side_mm);
        let min_height = m.height_mm.unwrap_or(0.0);
        for &(t, yaw, (fx, fz), h) in &shapes {
            let dim = |a: DVec3| if a.x.abs() > 0.5 { fx } else { fz };
            let fits = (0..2).all(|k| dim(axes[k]) + tol.length_mm >= min_len[k])
                && h + tol.length_mm >= min_height
                && h <= y_top + 1e-6;
            if fits {
                let centre = corner + axes[0] * dim(axes[0]) / 2.0 + axes[1] * dim(axes[1]) / 2.0
                    - DVec3::Y * h / 2.0;
                let dims = [dim(axes[0]), dim(axes[1])];
                let closed_fit = fits_closed(&m, p.face, dims, h, tol.length_mm);
                out.push(Proposal {
                    block: Block {
                        block_type: t,
                        center_mm: centre,
                        orientation: Orientation::YawDeg(yaw),
                    },
                    closed_fit,
                    side_fit: closed_fit && matches!(p.face, Face::Side(_)),
                });
            }
        }
    }
    out
}

/// The blocks of [`catalog_proposals`] without their fit marks.
pub fn catalog_candidates(
    p: &Parallelogram,
    drawing: &LineDrawing,
    camera: &Camera,
    levels_mm: &[f64],
    tol: &MatchTolerances,
) -> Vec<Block> {
    catalog_proposals(p, drawing, camera, levels_mm, tol)
        .into_iter()
        .map(|c| c.block)
        .collect()
}

/// Axis-aligned world bounds (min, max) of a block in mm.
pub fn bounds_mm(b: &Block) -> (DVec3, DVec3) {
    crate::geom::bounds3(b.world_vertices()).unwrap_or((DVec3::INFINITY, DVec3::NEG_INFINITY))
}

/// `true` when two blocks' boxes overlap by more than the contact tolerance on every axis.
pub fn blocks_overlap(a: &Block, b: &Block) -> bool {
    let (la, ha) = bounds_mm(a);
    let (lb, hb) = bounds_mm(b);
    let pen = ha.min(hb) - la.max(lb);
    pen.min_element() > 2.0 * CONTACT_TOL_MM
}

/// Makes faces that nearly coincide flush (Chapter V: blocks touch "within a layer and from
/// one layer to another"): per world axis, the block faces' coordinates closer than
/// `tol_mm` to a neighbour's (and to the floor, y = 0) are replaced by their mean, and each
/// block is re-centred between its two faces. Measurement error in the pictures (vision
/// vertices lie within about 0.5 px) otherwise leaves touching blocks a few hundredths of a
/// millimetre apart or overlapping, which the exact redraw (step 6) would show as gaps.
pub fn make_touching_flush(blocks: &[Block], tol_mm: f64) -> Vec<Block> {
    let bounds: Vec<(DVec3, DVec3)> = blocks.iter().map(bounds_mm).collect();
    let mut out = blocks.to_vec();
    for k in 0..3 {
        let mut coords: Vec<f64> = bounds.iter().flat_map(|(lo, hi)| [lo[k], hi[k]]).collect();
        if k == 1 {
            coords.push(0.0);
        }
        coords.sort_by(f64::total_cmp);
        let mut clusters: Vec<Vec<f64>> = Vec::new();
        for c in coords {
            match clusters.last_mut() {
                Some(cl) if c - cl[cl.len() - 1] <= tol_mm => cl.push(c),
                _ => clusters.push(vec![c]),
            }
        }
        // The agreed coordinate of a face, when another face (or the floor) is near it.
        let snap = |x: f64| -> Option<f64> {
            let cl = clusters
                .iter()
                .find(|cl| cl.iter().any(|c| (c - x).abs() < 1e-12))?;
            if k == 1 && cl.contains(&0.0) {
                Some(0.0)
            } else {
                (cl.len() > 1).then(|| cl.iter().sum::<f64>() / cl.len() as f64)
            }
        };
        for (b, (lo, hi)) in out.iter_mut().zip(&bounds) {
            let half = (hi[k] - lo[k]) / 2.0;
            let centres: Vec<f64> = [snap(lo[k]).map(|l| l + half), snap(hi[k]).map(|h| h - half)]
                .into_iter()
                .flatten()
                .collect();
            let on_floor = k == 1 && snap(lo[k]) == Some(0.0);
            if on_floor {
                b.center_mm[k] = half;
            } else if !centres.is_empty() {
                b.center_mm[k] = centres.iter().sum::<f64>() / centres.len() as f64;
            }
        }
    }
    out
}

/// One layer of the reconstruction (Chapter V: "classify the number of levels and the blocks
/// which belong to these levels"): blocks whose bottoms lie at one height.
#[derive(Debug, Clone, PartialEq)]
pub struct Layer {
    /// Height of the layer's bottom, mm (the bottom layer is at y = 0).
    pub bottom_mm: f64,
    /// Indices of its blocks.
    pub blocks: Vec<usize>,
}

/// Groups blocks into layers by bottom height (within `tol_mm`), lowest first, blocks of a
/// layer in input order: the layers of `scene::layer_bottoms_mm` (the one home of layer
/// counting) with their members.
pub fn classify_layers(blocks: &[Block], tol_mm: f64) -> Vec<Layer> {
    let bottoms = crate::scene::layer_bottoms_mm(blocks, tol_mm);
    let mut layers: Vec<Layer> = bottoms
        .iter()
        .map(|&bottom_mm| Layer {
            bottom_mm,
            blocks: Vec::new(),
        })
        .collect();
    for (i, b) in blocks.iter().enumerate() {
        let k = crate::scene::layer_index(&bottoms, b.bottom_mm(), tol_mm);
        if let Some(l) = layers.get_mut(k) {
            l.blocks.push(i);
        }
    }
    layers
}

/// Pairs of blocks that touch face to face (gap under `tol_mm` on one axis, overlapping on the
/// other two): the connections the thesis reads from "T" vertices within and between layers.
pub fn touching_pairs(blocks: &[Block], tol_mm: f64) -> Vec<[usize; 2]> {
    let mut out = Vec::new();
    for i in 0..blocks.len() {
        for j in i + 1..blocks.len() {
            let (la, ha) = bounds_mm(&blocks[i]);
            let (lb, hb) = bounds_mm(&blocks[j]);
            let overlap = ha.min(hb) - la.max(lb);
            let touching_axes = (0..3).filter(|&k| overlap[k].abs() <= tol_mm).count();
            let overlapping_axes = (0..3).filter(|&k| overlap[k] > tol_mm).count();
            if touching_axes == 1 && overlapping_axes == 2 {
                out.push([i, j]);
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::super::parallelogram::Face as F;
    use super::super::parallelogram::{ParallelogramSearch, TopCorner};
    use super::super::select::select_vertices;
    use super::*;
    use crate::linedraw::visible_line_drawing;
    use crate::recognize::{CameraOptions, CornerView};
    use crate::scene::Scene;

    /// The exact drawing of `b` alone in `view`, with its camera.
    fn alone(b: Block, view: CornerView, opts: &CameraOptions) -> (Camera, LineDrawing) {
        let cam = Camera::frame(&b.world_vertices(), view, opts);
        (cam, visible_line_drawing(&Scene::new("one", vec![b]), &cam))
    }

    /// The near top face found from the drawing's fork (code 22).
    fn fork_top_face(d: &LineDrawing) -> Parallelogram {
        let fork = select_vertices(d)
            .into_iter()
            .find(|v| v.code.0 == 22)
            .unwrap();
        let search = ParallelogramSearch::new(d, 0.5);
        search.search(&fork, F::Top(TopCorner::Near)).unwrap()
    }

    #[test]
    fn a_b30_top_face_measures_30_by_15_by_15_mm_in_both_projections() {
        let b = Block::new("b30", DVec3::new(15.0, 7.5, 7.5), 0.0);
        for projection in crate::camera::BOTH_PROJECTIONS {
            let opts = CameraOptions {
                projection,
                ..CameraOptions::default()
            };
            let (cam, d) = alone(b, CornerView::Sw, &opts);
            let p = fork_top_face(&d);
            let m =
                measure_parallelogram_mm(&p, &d, &cam, 15.0, &MatchTolerances::default()).unwrap();
            let mut sides = m.closed_side_mm.unwrap();
            sides.sort_by(f64::total_cmp);
            assert!(
                (sides[0] - 15.0).abs() < 1e-6 && (sides[1] - 30.0).abs() < 1e-6,
                "{sides:?}"
            );
            assert!((m.height_mm.unwrap() - 15.0).abs() < 1e-6);
            // SW camera sees the near top corner at the least x and the greatest z.
            assert!(
                m.vertex_mm.distance(DVec3::new(0.0, 15.0, 15.0)) < 1e-6,
                "{}",
                m.vertex_mm
            );
        }
    }

    #[test]
    fn levels_are_the_sums_of_catalog_heights() {
        assert_eq!(level_heights_mm(30.0), vec![7.5, 15.0, 22.5, 30.0]);
    }

    #[test]
    fn a_b30_fork_yields_the_b30_at_its_true_level_among_the_candidates() {
        let truth = Block::new("b30", DVec3::new(15.0, 22.5, 7.5), 0.0);
        let (cam, d) = alone(truth, CornerView::Ne, &CameraOptions::default());
        let search = ParallelogramSearch::new(&d, 0.5);
        let levels = level_heights_mm(45.0);
        let mut all = Vec::new();
        for v in select_vertices(&d) {
            if let Some(p) = search.search(&v, F::Top(TopCorner::Near)) {
                all.extend(catalog_candidates(
                    &p,
                    &d,
                    &cam,
                    &levels,
                    &MatchTolerances::default(),
                ));
            }
        }
        assert!(all
            .iter()
            .any(|b| b.block_type.id == "b30" && b.center_mm.distance(truth.center_mm) < 1e-6));
        // The b15 cannot be it: the visible 30 mm side is longer than 15 mm.
        assert!(all.iter().all(|b| b.block_type.id != "b15"));
        // The b7_5 cannot be it either: the visible vertical edge is 15 mm.
        assert!(all.iter().all(|b| b.block_type.id != "b7_5"));
    }

    #[test]
    fn only_the_block_with_the_closed_parallelograms_sides_fits_it_exactly() {
        let truth = Block::new("b30", DVec3::new(15.0, 22.5, 7.5), 0.0);
        let (cam, d) = alone(truth, CornerView::Ne, &CameraOptions::default());
        let p = fork_top_face(&d);
        assert!(p.closed.is_some());
        let all = catalog_proposals(&p, &d, &cam, &level_heights_mm(45.0), &Default::default());
        let fits: Vec<&Proposal> = all.iter().filter(|c| c.closed_fit).collect();
        assert!(!fits.is_empty(), "{all:?}");
        assert!(fits.iter().all(|c| c.block.block_type.id == "b30"));
        // Left open (a side occluded), the same sides are only lower bounds: no exact fit.
        let mut open = p.clone();
        open.closed = None;
        let levels = level_heights_mm(45.0);
        let open = catalog_proposals(&open, &d, &cam, &levels, &Default::default());
        assert_eq!(open.len(), all.len());
        assert!(open.iter().all(|c| !c.closed_fit));
        assert!(fits
            .iter()
            .any(|c| c.block.center_mm.distance(truth.center_mm) < 1e-6));
    }

    #[test]
    fn nearly_touching_faces_are_made_flush_and_the_floor_is_y_zero() {
        let blocks = vec![
            Block::new("b15", DVec3::new(7.54, 7.53, 7.5), 0.0),
            Block::new("b15", DVec3::new(22.5, 7.5, 7.5), 0.0),
            Block::new("b15", DVec3::new(60.0, 7.5, 7.5), 0.0),
        ];
        let flush = make_touching_flush(&blocks, 0.3);
        let (_, hi0) = bounds_mm(&flush[0]);
        let (lo1, _) = bounds_mm(&flush[1]);
        assert!((hi0.x - lo1.x).abs() < 1e-9, "{} {}", hi0.x, lo1.x);
        assert!(
            bounds_mm(&flush[0]).0.y.abs() < 0.02,
            "{:?}",
            flush[0].center_mm
        );
        assert_eq!(
            flush[2].center_mm, blocks[2].center_mm,
            "a block apart stays"
        );
    }

    #[test]
    fn layers_and_touching_pairs_of_a_two_layer_stack() {
        let blocks = vec![
            Block::new("b30", DVec3::new(15.0, 7.5, 7.5), 0.0),
            Block::new("b15", DVec3::new(7.5, 22.5, 7.5), 0.0),
            Block::new("b15", DVec3::new(37.5, 7.5, 7.5), 0.0),
            Block::new("b15", DVec3::new(90.0, 7.5, 7.5), 0.0),
        ];
        let layers = classify_layers(&blocks, 1.0);
        assert_eq!(layers.len(), 2);
        assert_eq!(layers[0].blocks, vec![0, 2, 3]);
        assert_eq!(layers[1].bottom_mm, 15.0);
        assert_eq!(touching_pairs(&blocks, 0.1), vec![[0, 1], [0, 2]]);
        assert!(!blocks_overlap(&blocks[0], &blocks[1]));
        let shifted = Block::new("b15", DVec3::new(10.0, 7.5, 7.5), 0.0);
        assert!(blocks_overlap(&blocks[0], &shifted));
    }
}
