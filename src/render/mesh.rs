//! The triangle mesh the GPU draws: every block's catalog polyhedron (convex faces; a round
//! part's inscribed prism with its smooth side unseamed,
//! fan-triangulated) plus a floor quad, with the per-vertex data the shader needs: flat
//! Lambert gray level, block id and, for the seam between touching blocks, the lines of the
//! face's projected edges in framebuffer pixels (computed in f64 with the same
//! `Camera::picture_from_world` the ground truth uses, so seams sit on the exact lines).
//!
//! Plain data, no wgpu: the shading rule lives here so tests can compute the expected levels.

use crate::camera::Camera;
use crate::geom::{DVec2, DVec3};
use crate::scene::Scene;

/// Most edges a face polygon may have: the shader carries one line per edge in six `vec4`s
/// (catalog faces have 4; the Chapter VII wedge has at most 4 too).
pub const MAX_FACE_EDGES: usize = 8;

/// Line written for unused edge slots and for the floor: `x + 1e9 = 0`, far beyond any seam
/// (a unit normal, so the shader never divides by zero).
const NO_EDGE_LINE: [f32; 3] = [1.0, 0.0, 1.0e9];

/// Ambient share of the light (faces turned away from the light get only this).
pub const AMBIENT: f64 = 0.25;

/// The directional light, scaled by its diffuse intensity, in the light frame that turns with
/// the camera about the vertical: (camera right, world up, horizontal towards the camera).
/// It comes from the upper left, behind the camera. Chosen so that, for any elevation, block
/// faces (albedo 1) in a corner view get top 210, left 150, right 100 (see [`face_gray_level`]).
pub const LIGHT_IN_CAMERA_FRAME: [f64; 3] = [-0.1387, 0.5735, 0.3397];

/// Albedo of the blocks (light wood in the thesis's photographs, Figure 6.3).
pub const BLOCK_ALBEDO: f64 = 1.0;

/// Albedo of the floor: 2/7 of a block's, so the floor's gray level is 60.
pub const FLOOR_ALBEDO: f64 = 2.0 / 7.0;

/// One vertex as the shader reads it (`shaders/scene.wgsl`, `VertexIn`).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Vertex {
    /// World position, mm.
    pub position_mm: [f32; 3],
    /// The face's projected edge lines `(a, b, c)` in framebuffer px (x right, y down, pixel
    /// centres at +0.5), normalised so `|a x + b y + c|` is the distance in px, then doubled for
    /// silhouette edges (see `seam_scales`); the same for
    /// every vertex of the face. [`NO_EDGE_LINE`] for unused slots, the floor, and faces that
    /// reach behind the near plane.
    pub edge_lines_px: [[f32; 3]; MAX_FACE_EDGES],
    /// Flat gray level 0..=255 of the face.
    pub gray_level: u32,
    /// Block index + 1; 0 for the floor.
    pub block_id: u32,
}

/// A face polygon with more edges than the shader carries.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TooManyEdges {
    /// Block index in the scene.
    pub block: usize,
    /// Face index in the block's catalog polyhedron.
    pub face: usize,
    /// Its number of edges.
    pub edges: usize,
}

/// The light vector (direction times diffuse intensity) in world coordinates for `camera`:
/// [`LIGHT_IN_CAMERA_FRAME`] in the camera's horizontal frame (its right, world up, and the
/// horizontal direction towards the eye), so every view and elevation sees the same levels.
pub fn light_in_world(camera: &Camera) -> DVec3 {
    let [right, _, towards_eye] = camera.axes_in_world();
    let towards = DVec3::new(towards_eye.x, 0.0, towards_eye.z).normalize_or(DVec3::Z);
    let right = DVec3::new(right.x, 0.0, right.z).normalize_or(DVec3::X);
    let [x, y, z] = LIGHT_IN_CAMERA_FRAME;
    right * x + DVec3::Y * y + towards * z
}

/// Lambert shading of a flat face with outward unit normal `normal` and `albedo`, as a gray
/// level: `255 * albedo * (AMBIENT + max(0, normal . light))`, rounded. Top faces of blocks get
/// 210, the left and right faces of an unturned block 150 and 100, the floor 60.
pub fn face_gray_level(normal: DVec3, albedo: f64, camera: &Camera) -> u8 {
    let lambert = normal.dot(light_in_world(camera)).max(0.0);
    (255.0 * albedo * (AMBIENT + lambert))
        .round()
        .clamp(0.0, 255.0) as u8
}

/// Triangles of every block of `scene` and then of the floor, as seen by `camera` (the light follows
/// the camera). The floor is a square at y = 0 centred under the camera target, as wide as the
/// far clip distance, so it fills every picture down to the far plane or the horizon.
pub fn scene_vertices(scene: &Scene, camera: &Camera) -> Result<Vec<Vertex>, TooManyEdges> {
    let mut out = Vec::with_capacity(6 + scene.blocks.len() * 36);
    for (index, block) in scene.blocks.iter().enumerate() {
        let world = block.world_vertices();
        if block.block_type.round().is_some() {
            push_round_part(&mut out, block, index as u32 + 1, &world, camera);
            continue;
        }
        for (f, face) in block.block_type.faces().iter().enumerate() {
            if face.len() > MAX_FACE_EDGES {
                return Err(TooManyEdges {
                    block: index,
                    face: f,
                    edges: face.len(),
                });
            }
            let corners: Vec<DVec3> = face.iter().map(|&k| world[k as usize]).collect();
            let level = face_gray_level(block.world_face_normal(f), BLOCK_ALBEDO, camera);
            let scales = seam_scales(block, f, &world, camera);
            push_face(&mut out, &corners, &scales, camera, level, index as u32 + 1);
        }
    }
    // The floor last: the depth test then rejects its fragments behind blocks before shading.
    push_floor(&mut out, camera);
    Ok(out)
}

/// Half the side of the floor square under `camera`'s target, mm: the far clip distance, at
/// least a metre.
fn floor_half_side_mm(camera: &Camera) -> f64 {
    camera.near_far_mm[1].max(1000.0)
}

fn push_floor(out: &mut Vec<Vertex>, camera: &Camera) {
    let half = floor_half_side_mm(camera);
    let [cx, _, cz] = camera.target_mm;
    let corner = |dx: f64, dz: f64| DVec3::new(cx + dx * half, 0.0, cz + dz * half);
    // Counter-clockwise seen from above.
    let quad = [
        corner(-1.0, -1.0),
        corner(-1.0, 1.0),
        corner(1.0, 1.0),
        corner(1.0, -1.0),
    ];
    let level = face_gray_level(DVec3::Y, FLOOR_ALBEDO, camera) as u32;
    for k in [0, 1, 2, 0, 2, 3] {
        out.push(Vertex {
            position_mm: quad[k].as_vec3().to_array(),
            edge_lines_px: [NO_EDGE_LINE; MAX_FACE_EDGES],
            gray_level: level,
            block_id: 0,
        });
    }
}

/// The floor of a picture it fills, computed instead of rasterized (docs/rendering.md "How a
/// view is drawn"):
/// when the floor square of [`scene_vertices`] covers the whole picture between the near and
/// far planes (the usual corner view), the floor's pixels are exactly those no block covers,
/// all of one gray level, and their depth along the optical axis is a plane's, affine across
/// the picture (its reciprocal for a perspective camera). The GPU then draws only the blocks
/// and the readback writes the floor's depth, evaluated in f64 at each pixel centre and
/// rounded as the shader rounds a drawn fragment's (`depth_of` in `shaders/scene.wgsl`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FloorFill {
    /// Gray level of the floor ([`face_gray_level`] of the floor's normal).
    pub gray_level: u8,
    /// Depth (perspective: its reciprocal, 1/mm) at the centre of raster pixel (0, 0), top
    /// left, and its steps per column and per row.
    at_first_px: f64,
    per_column: f64,
    per_row: f64,
    /// `true` when the affine quantity is 1 / depth (a perspective camera).
    reciprocal: bool,
}

impl FloorFill {
    /// The floor's depth at raster pixel (`column`, `row`) (row 0 at the top) in depth-picture
    /// steps of 1/16 mm, rounded half to even and clamped to 1..=65535 as the shader does.
    pub fn depth_units(&self, column: usize, row: usize) -> u16 {
        self.depth_units_in_row(self.row_start(row), column as f64)
    }

    /// The affine quantity (depth, or its reciprocal) at column 0 of raster row `row`.
    #[inline(always)]
    pub fn row_start(&self, row: usize) -> f64 {
        self.at_first_px + self.per_row * row as f64
    }

    /// [`FloorFill::depth_units`] at `column` (as f64) of the row whose
    /// [`FloorFill::row_start`] is `row_start`: the per-pixel step of the readback's loop,
    /// written so that loop vectorizes (no rounding call, no float-to-integer conversion).
    #[inline(always)]
    pub fn depth_units_in_row(&self, row_start: f64, column: f64) -> u16 {
        let v = row_start + self.per_column * column;
        let depth_mm = if self.reciprocal { 1.0 / v } else { v };
        // Adding 2^52 to a number in 0..2^51 rounds it to an integer, half to even (IEEE round
        // to nearest: the shader's `round`), and leaves that integer in the low bits of the
        // sum's mantissa. `max` then `min` (not `clamp`) compile to packed max and min.
        const ROUND: f64 = 4_503_599_627_370_496.0;
        #[allow(clippy::manual_clamp)]
        let x = (depth_mm * crate::camera::DEPTH_UNITS_PER_MM)
            .max(1.0)
            .min(65535.0);
        (x + ROUND).to_bits() as u16
    }
}

/// Margin inside the floor square and the clip depths within which a picture corner must see
/// the floor for [`floor_fill`], mm: far beyond any rounding of the rasterizer.
const FLOOR_FILL_MARGIN_MM: f64 = 1.0;

/// The [`FloorFill`] of `scene` seen by `camera` when the floor fills the whole picture: the
/// rays through the four picture corners meet the floor inside its square, in front of the eye
/// and between the near and far planes (the region where that holds is convex in the picture,
/// so the corners decide for every pixel), the eye is above the floor, and no block reaches
/// below it (scene validation allows a block to sink by the contact tolerance; the floor must
/// then hide that part, so it is drawn). `None` otherwise: the floor is then drawn.
pub fn floor_fill(scene: &Scene, camera: &Camera) -> Option<FloorFill> {
    let sinks = scene
        .blocks
        .iter()
        .any(|b| b.world_vertices().iter().any(|p| p.y < 0.0));
    if sinks {
        return None;
    }
    let projector = crate::camera::Projector::new(camera);
    let [w, h] = camera.size_px.map(f64::from);
    let [near, far] = camera.near_far_mm;
    let half = floor_half_side_mm(camera) - FLOOR_FILL_MARGIN_MM;
    let [cx, _, cz] = camera.target_mm;
    if camera.towards_eye().y <= 0.0 || (!camera.is_orthographic() && camera.eye().y <= 0.0) {
        return None;
    }
    let floor_depth_mm = |x_px: f64, y_px: f64| -> Option<f64> {
        let (origin, direction) = projector.ray(DVec2::new(x_px, y_px));
        if direction.y >= -1e-12 {
            return None;
        }
        let hit = origin + direction * (-origin.y / direction.y);
        let inside = (hit.x - cx).abs() <= half && (hit.z - cz).abs() <= half;
        let depth_mm = projector.depth_mm(hit);
        let in_range =
            depth_mm >= near + FLOOR_FILL_MARGIN_MM && depth_mm <= far - FLOOR_FILL_MARGIN_MM;
        (inside && in_range).then_some(depth_mm)
    };
    for [x, y] in [[0.0, 0.0], [w, 0.0], [0.0, h], [w, h]] {
        floor_depth_mm(x, y)?;
    }
    // Raster pixel (column, row) has its centre at picture (column + 0.5, h - row - 0.5).
    let reciprocal = !camera.is_orthographic();
    let affine = |column: f64, row: f64| -> Option<f64> {
        let d = floor_depth_mm(column + 0.5, h - row - 0.5)?;
        Some(if reciprocal { 1.0 / d } else { d })
    };
    let at_first_px = affine(0.0, 0.0)?;
    Some(FloorFill {
        gray_level: face_gray_level(DVec3::Y, FLOOR_ALBEDO, camera),
        at_first_px,
        per_column: affine(1.0, 0.0)? - at_first_px,
        per_row: affine(0.0, 1.0)? - at_first_px,
        reciprocal,
    })
}

/// Scale of a silhouette edge's line `(a, b, c)`: the shader reads `a^2 + b^2 = 4` as the
/// silhouette flag (`shaders/scene.wgsl`, `is_seam`).
const SILHOUETTE_LINE_SCALE: f64 = 2.0;

/// Per edge of face `f` of `block`, the factor its line is scaled by: 1 for an edge whose other
/// face also turns towards the camera (that face draws the other half of the seam),
/// [`SILHOUETTE_LINE_SCALE`] for a silhouette edge of the block, whose far side belongs to
/// whatever lies behind, possibly a face of the same gray level: the shader then also darkens
/// the nearest pixel on the block's side (see `render::SEAM_HALF_WIDTH_PX`).
fn seam_scales(
    block: &crate::scene::Block,
    f: usize,
    world: &[DVec3],
    camera: &Camera,
) -> [f64; MAX_FACE_EDGES] {
    let face = block.block_type.faces()[f];
    let mut scales = [1.0; MAX_FACE_EDGES];
    for k in 0..face.len().min(MAX_FACE_EDGES) {
        let (a, b) = (face[k], face[(k + 1) % face.len()]);
        if is_silhouette_edge(block, f, [a, b], world, camera) {
            scales[k] = SILHOUETTE_LINE_SCALE;
        }
    }
    scales
}

/// Whether the edge `a`-`b` of face `f` of `block` is a silhouette: the other face that shares
/// it turns away from the camera (or there is none).
fn is_silhouette_edge(
    block: &crate::scene::Block,
    f: usize,
    [a, b]: [u8; 2],
    world: &[DVec3],
    camera: &Camera,
) -> bool {
    let faces = block.block_type.faces();
    let neighbour =
        (0..faces.len()).find(|&g| g != f && faces[g].contains(&a) && faces[g].contains(&b));
    neighbour
        .is_none_or(|g| !camera.faces_eye(block.world_face_normal(g), world[faces[g][0] as usize]))
}

/// Triangles of a round part (docs/formats.md "Block catalog"): its inscribed prism, each side quad
/// flat-shaded, the two rings fanned from their centres. The side is smooth, so no seam is
/// drawn between side facets except on the silhouette generators (where the next facet turns
/// away); the rim chords carry seams like any block edge. 64 sides keep the silhouette within
/// 0.009 mm of the circle, under a tenth of a pixel at 512 x 480, and adjacent facets differ by
/// at most about 17 gray levels, a step the Sobel threshold (Ch. VI, 80) does not report.
fn push_round_part(
    out: &mut Vec<Vertex>,
    block: &crate::scene::Block,
    id: u32,
    world: &[DVec3],
    camera: &Camera,
) {
    let faces = block.block_type.faces();
    let n = faces.len() - 2;
    for (f, face) in faces.iter().enumerate() {
        let level = face_gray_level(block.world_face_normal(f), BLOCK_ALBEDO, camera);
        let scale = |a: u8, b: u8| match is_silhouette_edge(block, f, [a, b], world, camera) {
            true => SILHOUETTE_LINE_SCALE,
            false => 1.0,
        };
        if f < n {
            // Side quad [k, top k, top k+1, k+1]: edges 0 and 2 are generators, 1 and 3 rims;
            // a generator is a seam only where this facet faces the eye and the next one not.
            let faces_eye = camera.faces_eye(block.world_face_normal(f), world[face[0] as usize]);
            let mut scales = [0.0; MAX_FACE_EDGES];
            for e in 0..4 {
                let (a, b) = (face[e], face[(e + 1) % 4]);
                let rim = e % 2 == 1;
                scales[e] = match (rim, scale(a, b)) {
                    (true, s) => s,
                    (false, s) if faces_eye && s == SILHOUETTE_LINE_SCALE => s,
                    _ => 0.0,
                };
            }
            let corners: Vec<DVec3> = face.iter().map(|&k| world[k as usize]).collect();
            push_face(out, &corners, &scales, camera, level, id);
            continue;
        }
        let centre = face.iter().map(|&k| world[k as usize]).sum::<DVec3>() / face.len() as f64;
        for k in 0..face.len() {
            let (a, b) = (face[k], face[(k + 1) % face.len()]);
            let mut scales = [0.0; MAX_FACE_EDGES];
            scales[1] = scale(a, b);
            let corners = [centre, world[a as usize], world[b as usize]];
            push_face(out, &corners, &scales, camera, level, id);
        }
    }
}

/// Fan-triangulates the convex polygon `corners` (counter-clockwise seen from outside); an edge
/// whose seam scale is 0 gets no seam line.
fn push_face(
    out: &mut Vec<Vertex>,
    corners: &[DVec3],
    seam_scales: &[f64; MAX_FACE_EDGES],
    camera: &Camera,
    level: u8,
    id: u32,
) {
    let mut lines = edge_lines_px(corners, camera);
    for (line, scale) in lines.iter_mut().zip(seam_scales) {
        if *scale == 0.0 {
            // Not an edge of the drawing (inside a round part's smooth side or ring).
            *line = NO_EDGE_LINE;
        } else if *line != NO_EDGE_LINE {
            *line = line.map(|v| (v as f64 * scale) as f32);
        }
    }
    let vertex = |p: DVec3| Vertex {
        position_mm: p.as_vec3().to_array(),
        edge_lines_px: lines,
        gray_level: level as u32,
        block_id: id,
    };
    for k in 1..corners.len() - 1 {
        out.push(vertex(corners[0]));
        out.push(vertex(corners[k]));
        out.push(vertex(corners[k + 1]));
    }
}

/// How many edge-line slots the fragment shader tests for a triangle (`shaders/scene.wgsl`):
/// the seam (docs/rendering.md "Rendering") is the costliest part of shading a pixel, so each triangle is
/// drawn with the shader variant that tests only the slots its face uses. A slot left out holds
/// [`NO_EDGE_LINE`], which is never seam, so the pictures are those of testing all slots.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SeamLines {
    /// No edge line (the floor).
    None,
    /// Lines in slots 0..4 only (every catalog face and a round part's facets).
    Four,
    /// Lines up to slot 8 ([`MAX_FACE_EDGES`]).
    Eight,
}

impl SeamLines {
    /// The variant that tests every used slot of `edge_lines_px`.
    pub fn of(edge_lines_px: &[[f32; 3]; MAX_FACE_EDGES]) -> SeamLines {
        let used = edge_lines_px
            .iter()
            .rposition(|l| *l != NO_EDGE_LINE)
            .map_or(0, |last| last + 1);
        match used {
            0 => SeamLines::None,
            1..=4 => SeamLines::Four,
            _ => SeamLines::Eight,
        }
    }
}

/// The triangle list `vertices` cut into runs of consecutive triangles that share a
/// [`SeamLines`] variant, in drawing order (so depth ties resolve as in one draw: the first
/// drawn wins): vertex ranges with their variant. A block stack gives two runs, its faces and
/// the floor.
pub fn seam_line_runs(vertices: &[Vertex]) -> Vec<(std::ops::Range<u32>, SeamLines)> {
    let mut runs: Vec<(std::ops::Range<u32>, SeamLines)> = Vec::new();
    for (t, triangle) in vertices.chunks(3).enumerate() {
        let lines = SeamLines::of(&triangle[0].edge_lines_px);
        let range = (3 * t) as u32..(3 * t + triangle.len()) as u32;
        match runs.last_mut() {
            Some((run, kind)) if *kind == lines => run.end = range.end,
            _ => runs.push((range, lines)),
        }
    }
    runs
}

/// The order in which a mesh's block triangles are drawn. lavapipe tests depth before it shades
/// a fragment, so a face drawn after the blocks in front of it costs a depth test instead of the
/// seam test; which block wins where two are equally near (where they touch) must not depend on
/// the order, though: in block index order the lower index wins, since each fragment is kept
/// only where it is nearer than what is drawn (`Less`). Drawn in the reverse order with
/// fragments kept where nearer or as near (`LessEqual`), the last drawn of equally near
/// fragments wins, which is again the lower index: every pixel is the same. The floor is drawn
/// last either way, keeping only nearer fragments, so blocks win where they stand on it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DrawOrder {
    /// Block index order (as [`scene_vertices`] gives them), fragments kept where nearer.
    Ascending,
    /// The reverse, fragments kept where nearer or as near.
    Descending,
}

/// How many vertices at the start of `vertices` belong to blocks: the mesh up to its floor
/// (the trailing vertices of block id 0).
pub fn block_vertex_count(vertices: &[Vertex]) -> usize {
    vertices
        .iter()
        .rposition(|v| v.block_id != 0)
        .map_or(0, |last| last + 1)
}

/// The [`DrawOrder`] that draws nearer blocks first more often for the camera whose depth is
/// `-dot(view_z_row, (p, 1))` (`FrameUniforms::view_z_row`): descending when the blocks' nearest
/// corners come nearer as the block id grows (a negative covariance of id and depth).
pub fn nearer_first_order(vertices: &[Vertex], view_z_row: [f32; 4]) -> DrawOrder {
    let blocks = &vertices[..block_vertex_count(vertices)];
    let max_id = blocks.iter().map(|v| v.block_id).max().unwrap_or(0) as usize;
    let mut nearest_mm = vec![f64::INFINITY; max_id + 1];
    for v in blocks {
        let [x, y, z] = v.position_mm.map(f64::from);
        let [a, b, c, d] = view_z_row.map(f64::from);
        let depth_mm = -(a * x + b * y + c * z + d);
        let slot = &mut nearest_mm[v.block_id as usize];
        *slot = slot.min(depth_mm);
    }
    let seen: Vec<(f64, f64)> = (0..=max_id)
        .filter(|&id| nearest_mm[id].is_finite())
        .map(|id| (id as f64, nearest_mm[id]))
        .collect();
    let n = seen.len().max(1) as f64;
    let mean_id = seen.iter().map(|p| p.0).sum::<f64>() / n;
    let mean_mm = seen.iter().map(|p| p.1).sum::<f64>() / n;
    let covariance: f64 = seen
        .iter()
        .map(|(id, mm)| (id - mean_id) * (mm - mean_mm))
        .sum();
    if covariance < 0.0 {
        DrawOrder::Descending
    } else {
        DrawOrder::Ascending
    }
}

/// `vertices` (block triangles in index order, then the floor) with the block triangles in
/// `order`, each triangle's corners (and so its winding and first vertex) unchanged; borrowed
/// as they are in [`DrawOrder::Ascending`], copied only to be reordered.
pub fn in_draw_order(vertices: &[Vertex], order: DrawOrder) -> std::borrow::Cow<'_, [Vertex]> {
    if order == DrawOrder::Ascending {
        return std::borrow::Cow::Borrowed(vertices);
    }
    let mut out = vertices.to_vec();
    let blocks = &mut out[..block_vertex_count(vertices)];
    blocks.reverse();
    for triangle in blocks.chunks_exact_mut(3) {
        triangle.reverse();
    }
    std::borrow::Cow::Owned(out)
}

/// The lines through the projected edges of a face, in framebuffer px: `(a, b, c)` with
/// `a^2 + b^2 = 1`, so `|a x + b y + c|` is the distance of pixel point `(x, y)` from the line.
pub fn edge_lines_px(corners: &[DVec3], camera: &Camera) -> [[f32; 3]; MAX_FACE_EDGES] {
    let mut lines = [NO_EDGE_LINE; MAX_FACE_EDGES];
    let height = camera.size_px[1] as f64;
    let projected: Vec<DVec3> = corners
        .iter()
        .map(|p| camera.picture_from_world(*p))
        .collect();
    if projected
        .iter()
        .any(|p| !p.is_finite() || p.z <= camera.near_far_mm[0])
    {
        return lines;
    }
    // Framebuffer coordinates: picture x, y flipped.
    let fb: Vec<DVec2> = projected
        .iter()
        .map(|p| DVec2::new(p.x, height - p.y))
        .collect();
    let n = fb.len();
    for k in 0..n.min(MAX_FACE_EDGES) {
        let (p, q) = (fb[k], fb[(k + 1) % n]);
        let along = q - p;
        if along.length() < 1e-12 {
            continue;
        }
        let normal = along.perp().normalize();
        lines[k] = [normal.x as f32, normal.y as f32, (-normal.dot(p)) as f32];
    }
    lines
}

#[cfg(test)]
mod tests;
