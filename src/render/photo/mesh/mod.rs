//! The render mesh and light of the photographic look (docs/rendering.md "Photographic look"): every
//! block's catalog polyhedron with its faces pulled in by half a crack ([`CRACK_MM`]) and its
//! edges and corners cut by a small bevel ([`BEVEL_MM`]), so edges catch the light as the
//! thesis's wooden blocks do (Figure 6.3) and touching blocks leave a real narrow gap. The
//! catalog, physics, exact drawing and scoring keep the sharp solid; only the picture sees this.
//!
//! Plain data, no wgpu. The render polyhedron of one block and the contacts between blocks
//! are in `polyhedron`, the reach of a shadow across the light in `reach`.

mod polyhedron;
mod reach;
#[cfg(test)]
mod tests;

use super::super::mesh::light_in_world;
use crate::camera::{Camera, FRONT_FACING_COS};
use crate::geom::DVec3;
use crate::scene::Scene;
pub use polyhedron::{
    bevelled_block, find_contacts, profiled_block, Contacts, EdgeProfile, MeshPolygon,
};
use polyhedron::{clip_convex, polygon_area, push_polygon};
use rand::{Rng, SeedableRng};
use reach::{grow_box, may_be_shadowed, shadow_reach, swept_box_meets, LightFrame};

/// Width of the bevel cut along every block edge, measured in each face, mm.
pub const BEVEL_MM: f64 = 0.05;

/// Width of the crack between two touching blocks, mm: every face of a block moves inward by
/// half of it.
pub const CRACK_MM: f64 = 0.3;

/// Ambient light (radiance of a white face in full shadow).
pub const PHOTO_AMBIENT: f64 = 0.2;

/// Diffuse intensity of the key light (radiance of a white face lit head-on, over ambient).
pub const PHOTO_DIFFUSE: f64 = 0.65;

/// Angular radius of the key light, degrees (a large softbox, about 90 cm across at 1 m): shadows
/// are hard where they touch their occluder and soften with distance, so a block's shadow on a
/// neighbour fades out instead of drawing a line.
pub const KEY_LIGHT_RADIUS_DEG: f64 = 25.0;

/// Albedo of the floor (dark cloth): lit floor well below a block's darkest lit face.
pub const PHOTO_FLOOR_ALBEDO: f64 = 0.15;

/// The shape and floor of the render mesh: the photo look's chamfer and dark floor by default,
/// drawn per scene by the varied look (docs/varied-look.md "What is drawn").
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeshLook {
    /// The block edges' profile; default a [`BEVEL_MM`] chamfer.
    pub edge: EdgeProfile,
    /// The floor's albedo; default [`PHOTO_FLOOR_ALBEDO`].
    pub floor_albedo: f64,
}

impl Default for MeshLook {
    fn default() -> Self {
        MeshLook {
            edge: EdgeProfile::chamfer(BEVEL_MM),
            floor_albedo: PHOTO_FLOOR_ALBEDO,
        }
    }
}

/// One vertex as `shaders/photo.wgsl` reads it (`VertexIn`).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct PhotoVertex {
    /// World position, mm.
    pub position_mm: [f32; 3],
    /// Albedo of the surface, 0..=1.
    pub albedo: f32,
    /// Outward unit normal of the triangle, world.
    pub normal: [f32; 3],
    /// Padding to 32 bytes.
    pub pad: f32,
}

/// The key light of one view: unit direction towards the light (world) and its diffuse
/// intensity, plus the ambient share.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KeyLight {
    /// Unit vector from the scene towards the light, world.
    pub towards_light: DVec3,
    /// Diffuse intensity.
    pub diffuse: f64,
    /// Ambient radiance.
    pub ambient: f64,
    /// Angular radius of the light seen from the scene, degrees: an area light (a softbox)
    /// whose shadows soften with the distance from the occluder.
    pub angular_radius_deg: f64,
    /// Radiance the lit floor sends back up, per unit albedo of the face it reaches: a face
    /// turned by `n` gets `floor_bounce * (1 - n.y)` of it, and the ambient only its sky share
    /// `ambient * (1 + n.y) / 2` ([`ambient_radiance`]); 0 keeps the ambient the same on
    /// every face (the fixed photographic look).
    pub floor_bounce: f64,
}

/// The light a face with unit normal `normal` (world, y up) receives besides the direct light,
/// per unit albedo: with no floor bounce, `ambient` on every face; with it, the sky's share of
/// `ambient` (the half-space above the face's horizon: all of it on a top face, half on a
/// side) plus the bounce of a floor lit evenly all round ([`KeyLight::floor_bounce`]). The
/// shader (`ambient_in` in shaders/photo.wgsl) computes the same.
pub fn ambient_radiance(ambient: f64, floor_bounce: f64, normal: DVec3) -> f64 {
    if floor_bounce > 0.0 {
        ambient * (1.0 + normal.y) / 2.0 + floor_bounce * (1.0 - normal.y)
    } else {
        ambient
    }
}

/// The key light for `camera`: the line-art light's direction (upper left, behind the camera,
/// turning with the camera; [`light_in_world`]) turned by up to `jitter_deg` in azimuth and in
/// elevation, the same turn for every view of a scene (seeded by the scene's `seed`);
/// elevation stays within 10..=85 degrees.
pub fn key_light(camera: &Camera, jitter_deg: f64, seed: u64) -> KeyLight {
    let base = light_in_world(camera).normalize();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed ^ 0x11_6A7);
    let (d_az, d_el) = if jitter_deg > 0.0 {
        (
            rng.random_range(-jitter_deg..=jitter_deg),
            rng.random_range(-jitter_deg..=jitter_deg),
        )
    } else {
        (0.0, 0.0)
    };
    let el = (base.y.asin().to_degrees() + d_el)
        .clamp(10.0, 85.0)
        .to_radians();
    let az = base.x.atan2(base.z) + d_az.to_radians();
    KeyLight {
        towards_light: DVec3::new(el.cos() * az.sin(), el.sin(), el.cos() * az.cos()),
        diffuse: PHOTO_DIFFUSE,
        ambient: PHOTO_AMBIENT,
        angular_radius_deg: KEY_LIGHT_RADIUS_DEG,
        floor_bounce: 0.0,
    }
}

/// One albedo per block, uniform in `[lo, hi]`, seeded by the scene's `seed`.
pub fn block_albedos(scene: &Scene, [lo, hi]: [f64; 2], seed: u64) -> Vec<f64> {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed ^ 0xA1_BED0);
    scene
        .blocks
        .iter()
        .map(|_| {
            if hi > lo {
                rng.random_range(lo..=hi)
            } else {
                lo
            }
        })
        .collect()
}

/// Triangles of every block (cracked and bevelled, [`bevelled_block`]) and then of the floor
/// (a square at y = 0 under the camera target, as wide as the far clip distance). The faces of
/// touching blocks draw back by half a crack each, and a black sheet fills the crack's middle
/// plane where they touch: no light reaches the bottom of a narrow crack ([`find_contacts`]).
pub fn photo_vertices(scene: &Scene, camera: &Camera, albedos: &[f64]) -> Vec<PhotoVertex> {
    let mut out = block_vertices(scene, albedos);
    push_polygon(
        &mut out,
        &floor_corners(camera, 0.0),
        DVec3::Y,
        PHOTO_FLOOR_ALBEDO,
    );
    out
}

/// The render mesh of [`photo_vertices`] ordered by the work its pixels need: first the
/// triangles the key light's soft shadow can reach (nearer blocks first, the floor last), then
/// the rest, which the renderer shades without the shadow test (the same radiance: their light
/// share is 1, or it does not matter).
/// The rest are the faces turned away from the light (ambient only), the black crack sheets,
/// the parts of block faces no other block comes near on the light's side, and the floor away
/// from every block's shadow ([`photo_mesh`]). A face only part of which a shadow can reach
/// is drawn twice: that part with the shadow test, and the whole face without it, last and
/// a hair behind (the renderer's depth bias), so it shows only where the part does not.
///
/// Each pass gets only the triangles it does not cull: the radiance pass those turned towards
/// the eye, the shadow pass (which culls the faces turned towards the light) those turned away
/// from the light. A triangle neither pass draws is left out, so the GPU never transforms it;
/// the pictures are the same (docs/rendering.md "Photographic look").
#[derive(Debug, Clone, PartialEq)]
pub struct PhotoMesh {
    /// Triangles, in the order of their ranges: `shadowed`, `behind`, then `unshadowed`, whose
    /// end overlaps `casters` (faces turned to the eye and away from the light), then the rest
    /// of `casters`.
    pub vertices: Vec<PhotoVertex>,
    /// The triangles that need the shadow test, drawn last in the radiance pass.
    pub shadowed: std::ops::Range<usize>,
    /// Whole faces drawn behind their shadowed part, after `unshadowed`.
    pub behind: std::ops::Range<usize>,
    /// The triangles the radiance pass shades without the shadow test, drawn first.
    pub unshadowed: std::ops::Range<usize>,
    /// The triangles of the shadow map: every face turned away from the light.
    pub casters: std::ops::Range<usize>,
}

impl PhotoMesh {
    /// The same radiance triangles, all drawn without the shadow test, and no shadow casters:
    /// the photo view with its shadows taken out, for measuring what they cost
    /// (`Renderer::render_photo_parts`, docs/rendering.md "Photographic look"). The whole faces stay
    /// behind the parts of them that had the shadow test, so every pixel shows the surface it
    /// showed, lit as if nothing cast a shadow.
    pub fn without_shadows(&self) -> PhotoMesh {
        let mut vertices = self.vertices[self.behind.clone()].to_vec();
        vertices.extend_from_slice(&self.vertices[self.shadowed.clone()]);
        vertices.extend_from_slice(&self.vertices[self.unshadowed.clone()]);
        let (b, n) = (self.behind.len(), vertices.len());
        PhotoMesh {
            vertices,
            shadowed: 0..0,
            behind: 0..b,
            unshadowed: b..n,
            casters: n..n,
        }
    }
}

/// Where [`photo_mesh`] puts a polygon of the render mesh.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Part {
    /// Drawn with the shadow test.
    Shadowed,
    /// A whole face drawn behind its shadowed part.
    Behind,
    /// Drawn without the shadow test.
    Rest,
}

/// The polygons of [`photo_mesh`] sorted by the passes that draw them ([`PhotoMesh`]).
struct MeshParts<'a> {
    camera: &'a Camera,
    towards_light: DVec3,
    shadowed: Vec<PhotoVertex>,
    behind: Vec<PhotoVertex>,
    lit: Vec<PhotoVertex>,
    unlit: Vec<PhotoVertex>,
    casters: Vec<PhotoVertex>,
}

impl<'a> MeshParts<'a> {
    fn new(camera: &'a Camera, towards_light: DVec3) -> MeshParts<'a> {
        MeshParts {
            camera,
            towards_light,
            shadowed: Vec::new(),
            behind: Vec::new(),
            lit: Vec::new(),
            unlit: Vec::new(),
            casters: Vec::new(),
        }
    }

    /// Adds the polygon `corners` (outward normal `outward`) to `part`, in every range whose
    /// pass does not cull it. Only a face turned clearly away (past edge-on by the renderer's
    /// [`FRONT_FACING_COS`]) from the eye or towards the light is left out of a pass; one
    /// closer to edge-on goes to the GPU, whose own test decides.
    fn push(&mut self, part: Part, corners: &[DVec3], outward: DVec3, albedo: f64) {
        let Some(&first) = corners.first() else {
            return;
        };
        let n = outward.normalize_or_zero();
        let seen = !self.camera.faces_eye(-n, first);
        let casts = n.dot(self.towards_light) <= FRONT_FACING_COS;
        let out = match (part, seen, casts) {
            (Part::Shadowed, true, _) => &mut self.shadowed,
            (Part::Behind, true, _) => &mut self.behind,
            (Part::Rest, true, false) => &mut self.lit,
            (Part::Rest, true, true) => &mut self.unlit,
            (_, false, true) => &mut self.casters,
            (_, false, false) => return,
        };
        push_polygon(out, corners, outward, albedo);
    }

    /// The vertices in [`PhotoMesh`]'s order, with its ranges (shadowed and behind faces all
    /// face the light, so the shadow pass culls them anyway).
    fn finish(self) -> PhotoMesh {
        let shadowed = 0..self.shadowed.len();
        let behind = shadowed.end..shadowed.end + self.behind.len();
        let lit_end = behind.end + self.lit.len();
        let unlit_end = lit_end + self.unlit.len();
        let mut vertices = self.shadowed;
        vertices.extend(self.behind);
        vertices.extend(self.lit);
        vertices.extend(self.unlit);
        vertices.extend(self.casters);
        PhotoMesh {
            shadowed,
            unshadowed: behind.end..unlit_end,
            behind,
            casters: lit_end..vertices.len(),
            vertices,
        }
    }
}

/// Drop of the floor drawn without the shadow test below the floor drawn with it, mm: the two
/// never fight over a pixel's depth (the shadowed part wins where both are drawn), and that
/// far from every block a 0.1 mm lower floor looks the same.
pub const OUTER_FLOOR_DROP_MM: f64 = 0.1;

/// The photo look's render mesh ([`PhotoMesh`]) lit from `towards_light` (elevation at least
/// 10 degrees): a point can be in shadow only when some other block comes within `reach_mm`
/// of the light's path from it, across the light (the shader's blocker search radius plus a
/// margin), on the light's side of the point's face plane (the shader compares each tap with
/// the receiver's plane). So a light-facing block face needs the shadow test only where it
/// lies within the reach, across the light, of another block's part in front of its plane
/// ([`shadow_reach`]; blocks whose box misses the face's box grown by the reach and swept
/// towards the light are skipped at once; a bevel strip or corner is shadowed whole when
/// another block's box meets its own so grown and swept), and the floor only within the reach,
/// across the light, of the blocks ([`shadow_reach`] of the floor square); the whole floor
/// square lies [`OUTER_FLOOR_DROP_MM`] lower with the rest.
pub fn photo_mesh(
    scene: &Scene,
    camera: &Camera,
    albedos: &[f64],
    towards_light: DVec3,
    reach_mm: f64,
) -> PhotoMesh {
    photo_mesh_with(
        scene,
        camera,
        albedos,
        towards_light,
        reach_mm,
        &MeshLook::default(),
    )
}

/// [`photo_mesh`] with the given edge profile and floor albedo.
pub fn photo_mesh_with(
    scene: &Scene,
    camera: &Camera,
    albedos: &[f64],
    towards_light: DVec3,
    reach_mm: f64,
    look: &MeshLook,
) -> PhotoMesh {
    let solids: Vec<Vec<DVec3>> = scene.blocks.iter().map(|b| b.world_vertices()).collect();
    let boxes: Vec<(DVec3, DVec3)> = solids
        .iter()
        .map(|w| crate::geom::bounds3(w.iter().copied()).unwrap_or_default())
        .collect();
    let reach = Reach {
        frame: LightFrame::new(towards_light),
        towards_light,
        reach_mm,
        solids: &solids,
        boxes: &boxes,
        floor_albedo: look.floor_albedo,
    };
    let mut parts = MeshParts::new(camera, towards_light);
    let contacts = find_contacts(scene);
    for i in nearer_first(camera, &boxes) {
        let (block, albedo, touching) = (&scene.blocks[i], &albedos[i], &contacts.touching[i]);
        let grown = grow_box(boxes[i], reach_mm);
        let near: Vec<usize> = (0..boxes.len())
            .filter(|&j| j != i && swept_box_meets(grown, towards_light, boxes[j]))
            .collect();
        let retract_mm: Vec<f64> = touching
            .iter()
            .map(|t| if *t { CRACK_MM / 2.0 } else { 0.0 })
            .collect();
        // The first polygons are the block's faces, one per catalog face (`bevelled_block`).
        for (k, polygon) in profiled_block(block, &look.edge, &retract_mm)
            .iter()
            .enumerate()
        {
            let is_face = k < retract_mm.len();
            reach.push_polygon(&mut parts, polygon, is_face, &near, *albedo);
        }
    }
    for sheet in &contacts.sheets {
        parts.push(Part::Rest, &sheet.corners, sheet.outward, 0.0);
    }
    reach.push_floor(&mut parts, camera);
    parts.finish()
}

/// What [`photo_mesh`] knows of the key light's reach: the light, the reach across it, and
/// every block's solid and box.
struct Reach<'a> {
    frame: LightFrame,
    towards_light: DVec3,
    reach_mm: f64,
    solids: &'a [Vec<DVec3>],
    boxes: &'a [(DVec3, DVec3)],
    floor_albedo: f64,
}

impl Reach<'_> {
    /// Puts one polygon of a block's render polyhedron (a catalog face when `is_face`, else a
    /// bevel strip or corner) into `parts`, split where another block in `near` can shadow it.
    fn push_polygon(
        &self,
        parts: &mut MeshParts,
        polygon: &MeshPolygon,
        is_face: bool,
        near: &[usize],
        albedo: f64,
    ) {
        let (corners, outward) = (&polygon.corners, polygon.outward);
        let (towards_light, reach_mm) = (self.towards_light, self.reach_mm);
        let near_boxes: Vec<(DVec3, DVec3)> = near.iter().map(|&j| self.boxes[j]).collect();
        let reachable = outward.dot(towards_light) > 0.0
            && may_be_shadowed(corners, towards_light, reach_mm, &near_boxes);
        if !reachable {
            parts.push(Part::Rest, corners, outward, albedo);
            return;
        }
        if !is_face {
            // A bevel strip or corner, at most half a millimetre wide: whole.
            parts.push(Part::Shadowed, corners, outward, albedo);
            return;
        }
        let occluders: Vec<&[DVec3]> = near
            .iter()
            .filter(|&&j| may_be_shadowed(corners, towards_light, reach_mm, &[self.boxes[j]]))
            .map(|&j| self.solids[j].as_slice())
            .collect();
        let reached = shadow_reach(corners, outward, &self.frame, &occluders, reach_mm);
        if reached.is_empty() {
            parts.push(Part::Rest, corners, outward, albedo);
            return;
        }
        let lifted: Vec<DVec3> = reached
            .iter()
            .map(|q| self.frame.onto_plane(*q, corners[0], outward))
            .collect();
        let part = clip_convex(corners, &lifted, outward);
        let (part_mm2, whole_mm2) = (polygon_area(&part), polygon_area(corners));
        if part_mm2 <= 1e-9 * whole_mm2 {
            parts.push(Part::Rest, corners, outward, albedo);
        } else if part_mm2 >= (1.0 - 1e-9) * whole_mm2 {
            parts.push(Part::Shadowed, corners, outward, albedo);
        } else {
            parts.push(Part::Shadowed, &part, outward, albedo);
            parts.push(Part::Behind, corners, outward, albedo);
        }
    }

    /// Puts the floor into `parts`: the part within the reach of every block's shadow with the
    /// shadow test, the whole square [`OUTER_FLOOR_DROP_MM`] lower without it.
    fn push_floor(&self, parts: &mut MeshParts, camera: &Camera) {
        let floor = floor_corners(camera, 0.0);
        let every_solid: Vec<&[DVec3]> = self.solids.iter().map(Vec::as_slice).collect();
        let reached: Vec<DVec3> =
            shadow_reach(&floor, DVec3::Y, &self.frame, &every_solid, self.reach_mm)
                .iter()
                .map(|q| self.frame.onto_plane(*q, floor[0], DVec3::Y))
                .collect();
        let shadowed_floor = clip_convex(&floor, &reached, DVec3::Y);
        parts.push(Part::Shadowed, &shadowed_floor, DVec3::Y, self.floor_albedo);
        let lowered = floor_corners(camera, -OUTER_FLOOR_DROP_MM);
        parts.push(Part::Rest, &lowered, DVec3::Y, self.floor_albedo);
    }
}

/// The blocks' indices, nearer to `camera` first (by the depth of their boxes' centres; ties
/// in index order): the order in which [`photo_mesh`] lists their triangles, so that the
/// renderer, drawing with a depth test, shades few hidden fragments.
fn nearer_first(camera: &Camera, boxes: &[(DVec3, DVec3)]) -> Vec<usize> {
    let view = camera.view_matrix();
    let depth_mm: Vec<f64> = boxes
        .iter()
        .map(|(lo, hi)| -view.transform_point3((*lo + *hi) / 2.0).z)
        .collect();
    let mut order: Vec<usize> = (0..boxes.len()).collect();
    order.sort_by(|&a, &b| depth_mm[a].total_cmp(&depth_mm[b]));
    order
}

/// Triangles of every block (cracked and bevelled) and of the black crack sheets.
fn block_vertices(scene: &Scene, albedos: &[f64]) -> Vec<PhotoVertex> {
    let mut out = Vec::with_capacity(6 + scene.blocks.len() * 44 * 3);
    let contacts = find_contacts(scene);
    for ((block, albedo), touching) in scene.blocks.iter().zip(albedos).zip(&contacts.touching) {
        let retract_mm: Vec<f64> = touching
            .iter()
            .map(|t| if *t { CRACK_MM / 2.0 } else { 0.0 })
            .collect();
        for polygon in bevelled_block(block, BEVEL_MM, &retract_mm) {
            push_polygon(&mut out, &polygon.corners, polygon.outward, *albedo);
        }
    }
    for sheet in &contacts.sheets {
        push_polygon(&mut out, &sheet.corners, sheet.outward, 0.0);
    }
    out
}

/// The floor square at height `y_mm` under the camera target, as wide as the far clip
/// distance (at least 1 m each way), counter-clockwise seen from above.
fn floor_corners(camera: &Camera, y_mm: f64) -> [DVec3; 4] {
    let half = camera.near_far_mm[1].max(1000.0);
    let [cx, _, cz] = camera.target_mm;
    let corner = |dx: f64, dz: f64| DVec3::new(cx + dx * half, y_mm, cz + dz * half);
    [
        corner(-1.0, -1.0),
        corner(-1.0, 1.0),
        corner(1.0, 1.0),
        corner(1.0, -1.0),
    ]
}
