//! The scene as seen by one camera: block faces as planes and picture polygons, block edges as
//! 3D segments with their picture segments, and the projection both ways (Chapter II,
//! eqs. 2.2-2.8, in the camera's matrices).

use crate::camera::{Camera, Projector};
use crate::geom::{bounds2, bounds3, DVec2, DVec3};
use crate::scene::{Block, BlockType, Scene};

/// One block face: plane, picture polygon (counter-clockwise), facing.
pub(super) struct Face {
    /// Block index in scene order.
    pub block: usize,
    /// Outward unit normal, world.
    pub normal: DVec3,
    /// Plane offset: `normal . x = offset` on the face.
    pub offset: f64,
    /// Picture polygon, counter-clockwise (front faces only; empty otherwise).
    pub poly: Vec<DVec2>,
    /// Picture bounds of `poly`.
    pub lo: DVec2,
    /// Picture bounds of `poly`.
    pub hi: DVec2,
    /// Faces the eye (not edge-on, not turned away).
    pub front: bool,
}

impl Face {
    /// Signed distance of `p` from the plane, positive outside.
    pub fn plane_distance(&self, p: DVec3) -> f64 {
        self.normal.dot(p) - self.offset
    }

    /// Whether picture point `q` lies inside the polygon, boundary within `eps_px` included.
    pub fn contains_px(&self, q: DVec2, eps_px: f64) -> bool {
        if q.x < self.lo.x - eps_px
            || q.y < self.lo.y - eps_px
            || q.x > self.hi.x + eps_px
            || q.y > self.hi.y + eps_px
        {
            return false;
        }
        let n = self.poly.len();
        (0..n).all(|k| {
            let (a, b) = (self.poly[k], self.poly[(k + 1) % n]);
            let e = b - a;
            e.perp_dot(q - a) >= -eps_px * e.length()
        })
    }
}

/// One block edge.
pub(super) struct Edge {
    /// Block index in scene order.
    pub block: usize,
    /// Catalog vertex indices.
    pub vertices: [usize; 2],
    /// Global indices of its two faces in [`SceneGeometry::faces`].
    pub faces: [usize; 2],
    /// World ends.
    pub a: DVec3,
    /// World ends.
    pub b: DVec3,
    /// Picture ends.
    pub pa: DVec2,
    /// Picture ends.
    pub pb: DVec2,
    /// Clip w of the ends.
    pub wa: f64,
    /// Clip w of the ends.
    pub wb: f64,
    /// A chord of a curved edge (a round part's rim, see `round`).
    pub curved: bool,
}

impl Edge {
    /// World point at edge parameter `t`.
    pub fn at(&self, t: f64) -> DVec3 {
        self.a.lerp(self.b, t)
    }

    /// Whether at least one of its faces is front-facing (otherwise it cannot be seen).
    pub fn may_show(&self, faces: &[Face]) -> bool {
        faces[self.faces[0]].front || faces[self.faces[1]].front
    }
}

/// A catalog edge: vertex indices and the two faces' indices (`BlockType::edges`).
type CatalogEdge = (usize, usize, usize, usize);

/// Per-block summary.
pub(super) struct BlockGeometry {
    /// World bounds.
    pub lo: DVec3,
    /// World bounds.
    pub hi: DVec3,
    /// Centre height, mm (the "upper block" tie-break).
    pub centre_y_mm: f64,
    /// Range of its edges in [`SceneGeometry::edges`].
    pub edges: std::ops::Range<usize>,
}

/// Everything the hidden-line removal needs about the scene in one camera.
pub(super) struct SceneGeometry {
    /// The projection.
    pub proj: Projector,
    /// All faces of all blocks, block by block.
    pub faces: Vec<Face>,
    /// The front-facing faces (the only faces that hide or are hit) by picture cell, for
    /// queries near a point or a box.
    pub grid: FaceGrid,
    /// All edges of all blocks, block by block.
    pub edges: Vec<Edge>,
    /// Per block.
    pub blocks: Vec<BlockGeometry>,
    /// Picture px per mm at the scene's centre.
    pub px_per_mm: f64,
}

impl SceneGeometry {
    /// Builds the geometry of `scene` in `camera`.
    pub fn new(scene: &Scene, camera: &Camera) -> SceneGeometry {
        let proj = Projector::new(camera);
        let mut faces = Vec::new();
        let mut edges = Vec::new();
        let mut blocks = Vec::new();
        let mut edge_cache: Vec<(*const BlockType, Vec<CatalogEdge>)> = Vec::new();
        for (bi, block) in scene.blocks.iter().enumerate() {
            let verts = block.world_vertices();
            let first_face = faces.len();
            push_block_faces(block, bi, &verts, camera, &proj, &mut faces);
            let first_edge = edges.len();
            if block.block_type.round().is_some() {
                super::round::round_part_edges(
                    block, bi, &faces, first_face, camera, &proj, &mut edges,
                );
            } else {
                let catalog = catalog_edges(&mut edge_cache, block.block_type);
                push_block_edges(bi, &verts, catalog, first_face, &proj, &mut edges);
            }
            let (lo, hi) = bounds3(verts.iter().copied()).unwrap_or_default();
            blocks.push(BlockGeometry {
                lo,
                hi,
                centre_y_mm: block.center_mm.y,
                edges: first_edge..edges.len(),
            });
        }
        let centre = DVec3::from_array(camera.target_mm);
        let px_per_mm = proj.px_per_mm(centre);
        let front_faces: Vec<usize> = (0..faces.len()).filter(|&f| faces[f].front).collect();
        let grid = FaceGrid::new(&faces, &front_faces);
        SceneGeometry {
            proj,
            faces,
            grid,
            edges,
            blocks,
            px_per_mm,
        }
    }

    /// The nearest front face hit by the ray through picture point `q`, with the hit point.
    pub fn first_hit(&self, q: DVec2) -> Option<(usize, DVec3)> {
        let (o, d) = self.proj.ray(q);
        let mut best: Option<(usize, DVec3, f64)> = None;
        for &fi in self.grid.at(q) {
            let f = &self.faces[fi];
            if !f.contains_px(q, 0.0) {
                continue;
            }
            let den = f.normal.dot(d);
            if den.abs() < 1e-12 {
                continue;
            }
            let t = (f.offset - f.normal.dot(o)) / den;
            if best.is_none_or(|(_, _, bt)| t < bt) {
                best = Some((fi, o + d * t, t));
            }
        }
        best.map(|(fi, p, _)| (fi, p))
    }

    /// Whether blocks `a` and `b` are within `gap_mm` of each other (bounding boxes).
    pub fn blocks_near(&self, a: usize, b: usize, gap_mm: f64) -> bool {
        let (x, y) = (&self.blocks[a], &self.blocks[b]);
        (0..3).all(|k| x.lo[k] <= y.hi[k] + gap_mm && y.lo[k] <= x.hi[k] + gap_mm)
    }
}

/// A uniform grid over the picture boxes of the front faces: a query visits only the faces
/// whose boxes share a cell with it, instead of every face, so the hidden-line removal grows
/// near linearly with the blocks of a spread-out scene (docs/benchmarks.md "Benchmarks", scale). Queries
/// return a superset of the faces whose boxes meet the query box, in ascending face order, so
/// results do not depend on the grid.
pub(super) struct FaceGrid {
    origin: DVec2,
    cell_px: f64,
    cols: usize,
    rows: usize,
    /// Face indices per cell, row by row, ascending.
    cells: Vec<Vec<usize>>,
}

/// Slack added around boxes and queries, px (far below a pixel, above rounding).
const GRID_SLACK_PX: f64 = 1e-3;

/// Most cells along one side of the grid.
const MAX_GRID_SIDE: usize = 256;

impl FaceGrid {
    /// The grid of `front` (indices into `faces`), cells sized so that there are about as
    /// many cells as faces.
    pub fn new(faces: &[Face], front: &[usize]) -> FaceGrid {
        let boxed: Vec<usize> = front
            .iter()
            .copied()
            .filter(|&f| faces[f].lo.is_finite() && faces[f].hi.is_finite())
            .collect();
        let bounds = bounds2(boxed.iter().flat_map(|&f| [faces[f].lo, faces[f].hi]));
        let (lo, hi) = bounds.unwrap_or((DVec2::ZERO, DVec2::ZERO));
        let size = (hi - lo).max(DVec2::splat(1.0));
        let cell_px = (size.x * size.y / boxed.len().max(1) as f64)
            .sqrt()
            .max(size.x.max(size.y) / MAX_GRID_SIDE as f64)
            .max(1.0);
        let cols = ((size.x / cell_px).ceil() as usize).clamp(1, MAX_GRID_SIDE);
        let rows = ((size.y / cell_px).ceil() as usize).clamp(1, MAX_GRID_SIDE);
        let mut grid = FaceGrid {
            origin: lo,
            cell_px,
            cols,
            rows,
            cells: vec![Vec::new(); cols * rows],
        };
        for f in boxed {
            let (c0, r0, c1, r1) = grid.cell_range(faces[f].lo, faces[f].hi);
            for r in r0..=r1 {
                for c in c0..=c1 {
                    grid.cells[r * cols + c].push(f);
                }
            }
        }
        grid
    }

    /// The cells (first column, first row, last column, last row) a box touches, clamped.
    fn cell_range(&self, lo: DVec2, hi: DVec2) -> (usize, usize, usize, usize) {
        let cell = |v: f64, o: f64, n: usize| {
            let k = ((v - o) / self.cell_px).floor();
            if k.is_nan() || k < 0.0 {
                0
            } else {
                (k as usize).min(n - 1)
            }
        };
        let (lo, hi) = (lo - GRID_SLACK_PX, hi + GRID_SLACK_PX);
        (
            cell(lo.x, self.origin.x, self.cols),
            cell(lo.y, self.origin.y, self.rows),
            cell(hi.x, self.origin.x, self.cols),
            cell(hi.y, self.origin.y, self.rows),
        )
    }

    /// The faces whose boxes may hold the point `q`, ascending: the one cell holding `q` (a
    /// face is listed in every cell its box, grown by the slack, touches), without a copy.
    pub fn at(&self, q: DVec2) -> &[usize] {
        // `cell_range` grows its box by the slack; offset so its first cell is the one of `q`.
        let (c, r, _, _) = self.cell_range(q + GRID_SLACK_PX, q + GRID_SLACK_PX);
        &self.cells[r * self.cols + c]
    }

    /// The faces that may meet the box `lo`..`hi`, without repeats and in no set order, into
    /// `out` (unsorted: the hidden intervals of an edge are a union, whatever the order of the
    /// faces that hide it). `seen` holds one mark per face, grown as needed, left all false.
    pub fn candidates_unordered(
        &self,
        lo: DVec2,
        hi: DVec2,
        seen: &mut Vec<bool>,
        out: &mut Vec<usize>,
    ) {
        out.clear();
        let (c0, r0, c1, r1) = self.cell_range(lo, hi);
        for r in r0..=r1 {
            for c in c0..=c1 {
                for &f in &self.cells[r * self.cols + c] {
                    if f >= seen.len() {
                        seen.resize(f + 1, false);
                    }
                    if !seen[f] {
                        seen[f] = true;
                        out.push(f);
                    }
                }
            }
        }
        for &f in out.iter() {
            seen[f] = false;
        }
    }
}

fn signed_area(poly: &[DVec2]) -> f64 {
    let n = poly.len();
    (0..n)
        .map(|k| poly[k].perp_dot(poly[(k + 1) % n]))
        .sum::<f64>()
        / 2.0
}

fn poly_bounds(poly: &[DVec2]) -> (DVec2, DVec2) {
    bounds2(poly.iter().copied())
        .unwrap_or((DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)))
}

/// Appends block `bi`'s faces: plane, and for the faces towards the eye the picture polygon
/// (counter-clockwise) with its bounds.
fn push_block_faces(
    block: &Block,
    bi: usize,
    verts: &[DVec3],
    camera: &Camera,
    proj: &Projector,
    faces: &mut Vec<Face>,
) {
    for (fi, face) in block.block_type.faces().iter().enumerate() {
        let normal = block.world_face_normal(fi);
        let p0 = verts[face[0] as usize];
        let front = camera.faces_eye(normal, p0);
        let mut poly: Vec<DVec2> = if front {
            face.iter()
                .map(|&v| proj.picture(verts[v as usize]))
                .collect()
        } else {
            Vec::new()
        };
        if signed_area(&poly) < 0.0 {
            poly.reverse();
        }
        let (lo, hi) = poly_bounds(&poly);
        faces.push(Face {
            block: bi,
            normal,
            offset: normal.dot(p0),
            poly,
            lo,
            hi,
            front,
        });
    }
}

/// The catalog edges of block type `bt`, computed once per type of a scene.
fn catalog_edges<'c>(
    cache: &'c mut Vec<(*const BlockType, Vec<CatalogEdge>)>,
    bt: &'static BlockType,
) -> &'c [CatalogEdge] {
    let key = bt as *const BlockType;
    let cached = match cache.iter().position(|(k, _)| *k == key) {
        Some(i) => i,
        None => {
            cache.push((key, bt.edges()));
            cache.len() - 1
        }
    };
    &cache[cached].1
}

/// Appends block `bi`'s straight edges with their projected ends.
fn push_block_edges(
    bi: usize,
    verts: &[DVec3],
    catalog: &[CatalogEdge],
    first_face: usize,
    proj: &Projector,
    edges: &mut Vec<Edge>,
) {
    for &(i, j, fl, fr) in catalog {
        let (a, b) = (verts[i], verts[j]);
        let ((pa, wa), (pb, wb)) = (proj.picture_and_w(a), proj.picture_and_w(b));
        edges.push(Edge {
            block: bi,
            vertices: [i, j],
            faces: [first_face + fl, first_face + fr],
            a,
            b,
            pa,
            pb,
            wa,
            wb,
            curved: false,
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::{CameraOptions, CornerView};
    use crate::scene::Block;

    /// Every front face whose picture box meets a query box is among the grid's candidates,
    /// each once, for many boxes over a 64-block stack.
    #[test]
    fn the_face_grid_returns_every_face_a_box_meets_once() {
        let blocks: Vec<Block> = (0..64)
            .map(|i| {
                let c = DVec3::new(
                    (i % 4) as f64 * 15.0,
                    (i / 16) as f64 * 15.0 + 7.5,
                    ((i / 4) % 4) as f64 * 15.0,
                );
                Block::new("b15", c, 0.0)
            })
            .collect();
        let scene = Scene::new("grid", blocks);
        let pts: Vec<DVec3> = scene.world_vertices();
        let camera = Camera::frame(&pts, CornerView::Ne, &CameraOptions::default());
        let geo = SceneGeometry::new(&scene, &camera);
        assert!(geo.grid.cols * geo.grid.rows > 4, "a grid of several cells");
        let mut near = Vec::new();
        let mut seen = Vec::new();
        let mut checked = 0;
        for i in 0..40 {
            for j in 0..40 {
                let lo = DVec2::new(i as f64 * 13.0, j as f64 * 12.0);
                let hi = lo + DVec2::new((i % 5) as f64 * 9.0, (j % 3) as f64 * 20.0);
                geo.grid.candidates_unordered(lo, hi, &mut seen, &mut near);
                near.sort_unstable();
                assert!(near.windows(2).all(|w| w[0] < w[1]), "each face once");
                assert!(seen.iter().all(|s| !s), "the marks are left clear");
                for (f, face) in geo.faces.iter().enumerate() {
                    let meets = face.front
                        && face.lo.x <= hi.x
                        && face.lo.y <= hi.y
                        && face.hi.x >= lo.x
                        && face.hi.y >= lo.y;
                    if meets {
                        checked += 1;
                        assert!(near.contains(&f), "face {f} meets {lo}..{hi}");
                    }
                }
            }
        }
        assert!(checked > 1000, "the boxes meet many faces: {checked}");
        for i in 0..200 {
            let q = DVec2::new(i as f64 * 2.6, (i * 7 % 200) as f64 * 2.4);
            let at = geo.grid.at(q);
            assert!(at.windows(2).all(|w| w[0] < w[1]));
            for (f, face) in geo.faces.iter().enumerate() {
                if face.front && face.contains_px(q, 0.0) {
                    assert!(at.contains(&f), "face {f} holds {q}");
                }
            }
        }
    }
}
