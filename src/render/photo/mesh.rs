//! The render mesh and light of the photographic look (docs/rendering.md "Photographic look"): every
//! block's catalog polyhedron with its faces pulled in by half a crack ([`CRACK_MM`]) and its
//! edges and corners cut by a small bevel ([`BEVEL_MM`]), so edges catch the light as the
//! thesis's wooden blocks do (Figure 6.3) and touching blocks leave a real narrow gap. The
//! catalog, physics, exact drawing and scoring keep the sharp solid; only the picture sees this.
//!
//! Plain data, no wgpu.

use super::super::gpu::mesh::light_in_world;
use crate::camera::{Camera, FRONT_FACING_COS};
use crate::geom::DVec3;
use crate::scene::{Block, Scene};
use glam::DMat3;
use rand::{Rng, SeedableRng};

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
    let frame = LightFrame::new(towards_light);
    let solids: Vec<Vec<DVec3>> = scene.blocks.iter().map(|b| b.world_vertices()).collect();
    let boxes: Vec<(DVec3, DVec3)> = solids
        .iter()
        .map(|w| crate::geom::bounds3(w.iter().copied()).unwrap_or_default())
        .collect();
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
        let near_boxes: Vec<(DVec3, DVec3)> = near.iter().map(|&j| boxes[j]).collect();
        // The first polygons are the block's faces, one per catalog face (`bevelled_block`).
        for (k, polygon) in bevelled_block(block, BEVEL_MM, &retract_mm)
            .iter()
            .enumerate()
        {
            let (corners, outward) = (&polygon.corners, polygon.outward);
            let reachable = outward.dot(towards_light) > 0.0
                && may_be_shadowed(corners, towards_light, reach_mm, &near_boxes);
            if !reachable {
                parts.push(Part::Rest, corners, outward, *albedo);
                continue;
            }
            if k >= retract_mm.len() {
                // A bevel strip or corner, a twentieth of a millimetre wide: whole.
                parts.push(Part::Shadowed, corners, outward, *albedo);
                continue;
            }
            let occluders: Vec<&[DVec3]> = near
                .iter()
                .filter(|&&j| may_be_shadowed(corners, towards_light, reach_mm, &[boxes[j]]))
                .map(|&j| solids[j].as_slice())
                .collect();
            let reached = shadow_reach(corners, outward, &frame, &occluders, reach_mm);
            if reached.is_empty() {
                parts.push(Part::Rest, corners, outward, *albedo);
                continue;
            }
            let lifted: Vec<DVec3> = reached
                .iter()
                .map(|q| frame.onto_plane(*q, corners[0], outward))
                .collect();
            let part = clip_convex(corners, &lifted, outward);
            let (part_mm2, whole_mm2) = (polygon_area(&part), polygon_area(corners));
            if part_mm2 <= 1e-9 * whole_mm2 {
                parts.push(Part::Rest, corners, outward, *albedo);
            } else if part_mm2 >= (1.0 - 1e-9) * whole_mm2 {
                parts.push(Part::Shadowed, corners, outward, *albedo);
            } else {
                parts.push(Part::Shadowed, &part, outward, *albedo);
                parts.push(Part::Behind, corners, outward, *albedo);
            }
        }
    }
    for sheet in &contacts.sheets {
        parts.push(Part::Rest, &sheet.corners, sheet.outward, 0.0);
    }
    let floor = floor_corners(camera, 0.0);
    let every_solid: Vec<&[DVec3]> = solids.iter().map(Vec::as_slice).collect();
    let reached: Vec<DVec3> = shadow_reach(&floor, DVec3::Y, &frame, &every_solid, reach_mm)
        .iter()
        .map(|q| frame.onto_plane(*q, floor[0], DVec3::Y))
        .collect();
    let shadowed_floor = clip_convex(&floor, &reached, DVec3::Y);
    parts.push(
        Part::Shadowed,
        &shadowed_floor,
        DVec3::Y,
        PHOTO_FLOOR_ALBEDO,
    );
    let lowered = floor_corners(camera, -OUTER_FLOOR_DROP_MM);
    parts.push(Part::Rest, &lowered, DVec3::Y, PHOTO_FLOOR_ALBEDO);
    parts.finish()
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

/// How far in front of a face's plane a point of another block must lie to count as an
/// occluder in [`shadow_reach`], mm. The shader's blockers lie in front of the plane through
/// the receiver moved out along its normal by 1.5 shadow-map texels, so at least a tenth of a
/// texel (the texel the tap reads may lie 1.4 texels from the tap) in front of the face: far
/// more than this. A block whose face is flush with the receiver's plane does not count.
const OCCLUDER_FRONT_MM: f64 = 1e-4;

/// Coordinates across the key light: `u` and `v` span the plane normal to `along` (the unit
/// vector towards the light), `u x v = along`, so a polygon counter-clockwise seen from the
/// light stays counter-clockwise in `(u, v)`.
#[derive(Debug, Clone, Copy)]
struct LightFrame {
    along: DVec3,
    u: DVec3,
    v: DVec3,
}

impl LightFrame {
    fn new(towards_light: DVec3) -> LightFrame {
        let along = towards_light.normalize_or(DVec3::Y);
        let u = along.any_orthonormal_vector();
        LightFrame {
            along,
            u,
            v: along.cross(u),
        }
    }

    /// `p` across the light, mm.
    fn across(&self, p: DVec3) -> glam::DVec2 {
        glam::DVec2::new(p.dot(self.u), p.dot(self.v))
    }

    /// The point of the plane through `on_plane` with normal `normal` (not across the light)
    /// that lies at `q` across the light.
    fn onto_plane(&self, q: glam::DVec2, on_plane: DVec3, normal: DVec3) -> DVec3 {
        let p = self.u * q.x + self.v * q.y;
        p + self.along * (normal.dot(on_plane - p) / normal.dot(self.along))
    }
}

/// The convex region, across the light ([`LightFrame`]), where the soft shadow test on the
/// light-facing face `corners` (outward normal `outward`) can find a blocker: within
/// `reach_mm` of the part of some `occluders` solid (convex, given by its corners) that lies
/// in front of the face's plane (the solid clipped by the plane: its corners in front, and
/// where the segments between corners cross the plane). Empty when no solid reaches in front;
/// the hull of all of them otherwise (a 16-gon around each point, circumscribing the reach).
fn shadow_reach(
    corners: &[DVec3],
    outward: DVec3,
    frame: &LightFrame,
    occluders: &[&[DVec3]],
    reach_mm: f64,
) -> Vec<glam::DVec2> {
    let outward = outward.normalize_or_zero();
    let mut front = Vec::new();
    for solid in occluders {
        let height: Vec<f64> = solid
            .iter()
            .map(|p| outward.dot(*p - corners[0]) - OCCLUDER_FRONT_MM)
            .collect();
        for (i, (p, hp)) in solid.iter().zip(&height).enumerate() {
            if *hp > 0.0 {
                front.push(frame.across(*p));
            }
            for (q, hq) in solid.iter().zip(&height).skip(i + 1) {
                if (*hp > 0.0) != (*hq > 0.0) {
                    front.push(frame.across(*p + (*q - *p) * (hp / (hp - hq))));
                }
            }
        }
    }
    if front.is_empty() {
        return Vec::new();
    }
    let radius = reach_mm / (std::f64::consts::PI / REACH_SIDES as f64).cos();
    let hull = crate::geom::convex_hull(&front);
    crate::geom::convex_hull(&grown_corners(&hull, radius))
}

/// The corners of the [`REACH_SIDES`]-gon of circumradius `radius` around each vertex of the
/// counter-clockwise convex polygon `hull` that can lie on the outline of their hull (the
/// polygon grown by the regular polygon: [`in_cone`]).
fn grown_corners(hull: &[glam::DVec2], radius: f64) -> Vec<glam::DVec2> {
    hull.iter()
        .enumerate()
        .flat_map(|(i, c)| {
            let cone = vertex_cone(hull, i);
            REACH_DIRECTIONS
                .iter()
                .filter(move |d| cone.is_none_or(|(e_in, e_out)| in_cone(**d, e_in, e_out)))
                .map(move |d| *c + *d * radius)
        })
        .collect()
}

/// Sides of the polygon circumscribing the reach around each point in [`shadow_reach`].
const REACH_SIDES: usize = 16;

/// The unit directions to the corners of [`REACH_SIDES`]-gon, counter-clockwise from +u.
static REACH_DIRECTIONS: std::sync::LazyLock<[glam::DVec2; REACH_SIDES]> =
    std::sync::LazyLock::new(|| {
        std::array::from_fn(|k| {
            let a = std::f64::consts::TAU * k as f64 / REACH_SIDES as f64;
            glam::DVec2::new(a.cos(), a.sin())
        })
    });

/// The edges into and out of vertex `i` of the counter-clockwise convex polygon `hull`, which
/// bound the directions in which that vertex is the farthest ([`in_cone`]); `None` for fewer
/// than three vertices (every direction counts).
fn vertex_cone(hull: &[glam::DVec2], i: usize) -> Option<(glam::DVec2, glam::DVec2)> {
    let n = hull.len();
    (n >= 3).then(|| (hull[i] - hull[(i + n - 1) % n], hull[(i + 1) % n] - hull[i]))
}

/// Whether moving the vertex between edges `e_in` and `e_out` (of a counter-clockwise convex
/// polygon) along `d`, a corner direction of the [`REACH_SIDES`]-gon, can give a corner of the
/// grown polygon (their Minkowski sum): only when the directions in which the vertex is the
/// polygon's farthest point meet those in which that corner is the regular polygon's, which
/// lie within half a side's angle of `d`. So each edge's half-plane of directions is widened
/// by that angle (and a millionth), and [`shadow_reach`] hulls only the points that pass: the
/// same hull as of every point, with far fewer to sort.
fn in_cone(d: glam::DVec2, e_in: glam::DVec2, e_out: glam::DVec2) -> bool {
    // sin(pi / 16): half the angle between neighbouring corner directions.
    const HALF_SIDE_SIN: f64 = 0.195_090_322_016_128_25;
    const MARGIN: f64 = HALF_SIDE_SIN + 1e-6;
    const _: () = assert!(REACH_SIDES == 16, "HALF_SIDE_SIN is sin(pi / REACH_SIDES)");
    d.dot(e_in) >= -MARGIN * e_in.length() && d.dot(e_out) <= MARGIN * e_out.length()
}

/// The box `(lo, hi)` grown by `mm` on every side.
fn grow_box((lo, hi): (DVec3, DVec3), mm: f64) -> (DVec3, DVec3) {
    (lo - DVec3::splat(mm), hi + DVec3::splat(mm))
}

/// Whether some box of `occluders` meets the box of `face` grown by `reach_mm` and swept
/// towards the light.
fn may_be_shadowed(
    face: &[DVec3],
    towards_light: DVec3,
    reach_mm: f64,
    occluders: &[(DVec3, DVec3)],
) -> bool {
    let Some(bounds) = crate::geom::bounds3(face.iter().copied()) else {
        return false;
    };
    let grown = grow_box(bounds, reach_mm);
    occluders
        .iter()
        .any(|b| swept_box_meets(grown, towards_light, *b))
}

/// Whether box `(lo, hi)` moved by `t * dir` for some `t >= 0` overlaps box `other` (touching
/// counts): the slab test, one interval of `t` per axis.
fn swept_box_meets((lo, hi): (DVec3, DVec3), dir: DVec3, (olo, ohi): (DVec3, DVec3)) -> bool {
    let (mut t0, mut t1) = (0.0f64, f64::INFINITY);
    for k in 0..3 {
        let d = dir[k];
        if d.abs() < 1e-12 {
            if lo[k] > ohi[k] || hi[k] < olo[k] {
                return false;
            }
            continue;
        }
        let (a, b) = ((olo[k] - hi[k]) / d, (ohi[k] - lo[k]) / d);
        t0 = t0.max(a.min(b));
        t1 = t1.min(a.max(b));
        if t0 > t1 {
            return false;
        }
    }
    true
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

/// A flat convex polygon of the render mesh with its outward direction.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshPolygon {
    /// Corners, world mm.
    pub corners: Vec<DVec3>,
    /// Outward direction (not necessarily unit; the winding is fixed against it).
    pub outward: DVec3,
}

/// The render polyhedron of `block`: each catalog face `f` moved inward by `retract_mm[f]` and
/// inset by `bevel_mm` within its plane; a bevel strip along every edge joins the two insets;
/// a corner polygon at every vertex joins the insets of the faces that meet there.
pub fn bevelled_block(block: &Block, bevel_mm: f64, retract_mm: &[f64]) -> Vec<MeshPolygon> {
    let faces = block.block_type.faces();
    let normals: Vec<DVec3> = (0..faces.len())
        .map(|f| block.world_face_normal(f))
        .collect();
    let shrunk = pull_faces_in(&block.world_vertices(), faces, &normals, retract_mm);
    // inset[f][k]: face f's corner k after the in-plane inset.
    let inset: Vec<Vec<DVec3>> = faces
        .iter()
        .zip(&normals)
        .map(|(face, n)| {
            let corners: Vec<DVec3> = face.iter().map(|&k| shrunk[k as usize]).collect();
            inset_polygon(&corners, *n, bevel_mm)
        })
        .collect();
    let mut out: Vec<MeshPolygon> = inset
        .iter()
        .zip(&normals)
        .map(|(c, n)| MeshPolygon {
            corners: c.clone(),
            outward: *n,
        })
        .collect();
    let corner_of = |f: usize, v: u8| {
        let k = faces[f].iter().position(|&x| x == v)?;
        Some(inset[f][k])
    };
    for (f, face) in faces.iter().enumerate() {
        for k in 0..face.len() {
            let (a, b) = (face[k], face[(k + 1) % face.len()]);
            // Each edge once: from the face where it runs a -> b to the one where it runs b -> a.
            let Some(g) = (0..faces.len()).find(|&g| {
                g != f
                    && (0..faces[g].len())
                        .any(|j| faces[g][j] == b && faces[g][(j + 1) % faces[g].len()] == a)
            }) else {
                continue;
            };
            if g < f {
                continue;
            }
            if let (Some(fa), Some(fb), Some(gb), Some(ga)) = (
                corner_of(f, a),
                corner_of(f, b),
                corner_of(g, b),
                corner_of(g, a),
            ) {
                out.push(MeshPolygon {
                    corners: vec![fa, ga, gb, fb],
                    outward: normals[f] + normals[g],
                });
            }
        }
    }
    for v in 0..block.block_type.vertices_mm().len() as u8 {
        let around: Vec<usize> = (0..faces.len())
            .filter(|&f| faces[f].contains(&v))
            .collect();
        let outward: DVec3 = around.iter().map(|&f| normals[f]).sum();
        let points: Vec<DVec3> = around.iter().filter_map(|&f| corner_of(f, v)).collect();
        if points.len() >= 3 {
            out.push(MeshPolygon {
                corners: sort_around(points, outward),
                outward,
            });
        }
    }
    out
}

/// Moves every vertex so that each face `f` through it moves inward by `offset_mm[f]` along its
/// normal (exact where three faces meet; least squares where more do).
fn pull_faces_in(
    vertices: &[DVec3],
    faces: &[&[u8]],
    normals: &[DVec3],
    offset_mm: &[f64],
) -> Vec<DVec3> {
    vertices
        .iter()
        .enumerate()
        .map(|(v, p)| {
            let mut m = DMat3::ZERO;
            let mut rhs = DVec3::ZERO;
            for (f, face) in faces.iter().enumerate() {
                if face.contains(&(v as u8)) {
                    let n = normals[f];
                    m += DMat3::from_cols(n * n.x, n * n.y, n * n.z);
                    rhs -= n * offset_mm[f];
                }
            }
            if m.determinant().abs() < 1e-9 {
                return *p;
            }
            *p + m.inverse() * rhs
        })
        .collect()
}

/// Where blocks touch: per block and face whether it touches another block's face, and the
/// black sheets (both sides) on the touching patches' middle planes.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Contacts {
    /// `touching[block][face]`.
    pub touching: Vec<Vec<bool>>,
    /// The touching patches (each twice, facing both ways).
    pub sheets: Vec<MeshPolygon>,
}

/// Faces of different blocks closer than this along their (opposite) normals touch, mm: the
/// exact drawing's seam tolerance (`truth::TruthTolerances::seam_mm`).
const CONTACT_MM: f64 = 2.0 * crate::geom::CONTACT_TOL_MM;

/// Finds the touching face pairs of `scene` (opposite normals, planes within [`CONTACT_MM`],
/// polygons overlapping) among the block pairs whose boxes touch (`geom::touching_box_pairs`).
pub fn find_contacts(scene: &Scene) -> Contacts {
    let worlds: Vec<Vec<DVec3>> = scene.blocks.iter().map(|b| b.world_vertices()).collect();
    let boxes: Vec<(DVec3, DVec3)> = worlds
        .iter()
        .map(|w| {
            grow_box(
                crate::geom::bounds3(w.iter().copied()).unwrap_or_default(),
                CONTACT_MM,
            )
        })
        .collect();
    let mut out = Contacts {
        touching: scene
            .blocks
            .iter()
            .map(|b| vec![false; b.block_type.faces().len()])
            .collect(),
        sheets: Vec::new(),
    };
    // Each block's faces in world coordinates, with their outward normals: once per block.
    let faces: Vec<Vec<(DVec3, Vec<DVec3>)>> = scene
        .blocks
        .iter()
        .zip(&worlds)
        .map(|(block, world)| {
            let loops = block.block_type.faces();
            let corners = |face: &[_]| face.iter().map(|&k: &u8| world[k as usize]).collect();
            (0..loops.len())
                .map(|f| (block.world_face_normal(f), corners(loops[f])))
                .collect()
        })
        .collect();
    for [a, b] in crate::geom::touching_box_pairs(&boxes) {
        for (fa, (na, poly_a)) in faces[a].iter().enumerate() {
            let na = *na;
            for (fb, (nb, poly_b)) in faces[b].iter().enumerate() {
                let nb = *nb;
                if na.dot(nb) > -0.9999 || na.dot(poly_b[0] - poly_a[0]).abs() > CONTACT_MM {
                    continue;
                }
                let patch = clip_convex(poly_a, poly_b, nb);
                if polygon_area(&patch) < 1e-3 {
                    continue;
                }
                out.touching[a][fa] = true;
                out.touching[b][fb] = true;
                out.sheets.push(MeshPolygon {
                    corners: patch.clone(),
                    outward: na,
                });
                out.sheets.push(MeshPolygon {
                    corners: patch,
                    outward: nb,
                });
            }
        }
    }
    out
}

/// The part of convex polygon `subject` inside convex polygon `clip` (counter-clockwise seen
/// along `-clip_normal`, its outward normal), both in (nearly) one plane: Sutherland-Hodgman.
fn clip_convex(subject: &[DVec3], clip: &[DVec3], clip_normal: DVec3) -> Vec<DVec3> {
    let mut out = subject.to_vec();
    for k in 0..clip.len() {
        let (c0, c1) = (clip[k], clip[(k + 1) % clip.len()]);
        let inward = clip_normal.cross(c1 - c0);
        let side = |p: DVec3| inward.dot(p - c0);
        let input = std::mem::take(&mut out);
        for i in 0..input.len() {
            let (p, q) = (input[i], input[(i + 1) % input.len()]);
            let (sp, sq) = (side(p), side(q));
            if sp >= 0.0 {
                out.push(p);
            }
            if (sp >= 0.0) != (sq >= 0.0) {
                out.push(p + (q - p) * (sp / (sp - sq)));
            }
        }
        if out.is_empty() {
            break;
        }
    }
    out
}

/// Area of a planar polygon, mm^2.
fn polygon_area(corners: &[DVec3]) -> f64 {
    let n = corners.len();
    if n < 3 {
        return 0.0;
    }
    let twice: DVec3 = (1..n - 1)
        .map(|k| (corners[k] - corners[0]).cross(corners[k + 1] - corners[0]))
        .sum();
    twice.length() / 2.0
}

/// The convex polygon `corners` (counter-clockwise seen from outside, along `-normal`)
/// with every edge moved `inset_mm` inward within its plane.
fn inset_polygon(corners: &[DVec3], normal: DVec3, inset_mm: f64) -> Vec<DVec3> {
    let n = corners.len();
    let inward: Vec<DVec3> = (0..n)
        .map(|k| {
            normal
                .cross(corners[(k + 1) % n] - corners[k])
                .normalize_or_zero()
        })
        .collect();
    (0..n)
        .map(|k| {
            let (e0, e1) = (inward[(k + n - 1) % n], inward[k]);
            let denom = 1.0 + e0.dot(e1);
            if denom < 1e-6 {
                return corners[k];
            }
            corners[k] + (e0 + e1) * (inset_mm / denom)
        })
        .collect()
}

/// `points` (a convex polygon's corners in any order) sorted counter-clockwise seen from the
/// side `outward` points to.
fn sort_around(mut points: Vec<DVec3>, outward: DVec3) -> Vec<DVec3> {
    let centre = points.iter().copied().sum::<DVec3>() / points.len() as f64;
    let axis = outward.normalize_or(DVec3::Y);
    let u = (points[0] - centre)
        .reject_from(axis)
        .normalize_or(axis.any_orthonormal_vector());
    let w = axis.cross(u);
    let angle = |p: &DVec3| {
        let d = *p - centre;
        d.dot(w).atan2(d.dot(u))
    };
    points.sort_by(|a, b| angle(a).total_cmp(&angle(b)));
    points
}

/// Fan-triangulates the convex polygon `corners`, each triangle wound counter-clockwise seen
/// from `outward` and carrying its own unit normal; degenerate triangles are skipped.
fn push_polygon(out: &mut Vec<PhotoVertex>, corners: &[DVec3], outward: DVec3, albedo: f64) {
    for k in 1..corners.len().saturating_sub(1) {
        let (a, mut b, mut c) = (corners[0], corners[k], corners[k + 1]);
        let mut n = (b - a).cross(c - a);
        if n.length() < 1e-12 {
            continue;
        }
        if n.dot(outward) < 0.0 {
            std::mem::swap(&mut b, &mut c);
            n = -n;
        }
        let normal = n.normalize().as_vec3().to_array();
        for p in [a, b, c] {
            out.push(PhotoVertex {
                position_mm: p.as_vec3().to_array(),
                albedo: albedo as f32,
                normal,
                pad: 0.0,
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::{CameraOptions, CornerView};

    fn cube() -> Block {
        Block::new("b15", DVec3::new(0.0, 7.5, 0.0), 0.0)
    }

    /// The corner view `view` framing [`cube`], as `render` frames a scene of it alone.
    fn cube_camera(view: CornerView) -> Camera {
        Camera::frame(&cube().world_vertices(), view, &CameraOptions::default())
    }

    #[test]
    fn a_bevelled_cube_has_6_faces_12_strips_8_corners_and_stays_inside() {
        let polygons = bevelled_block(&cube(), BEVEL_MM, &[CRACK_MM / 2.0; 6]);
        assert_eq!(polygons.len(), 6 + 12 + 8);
        assert_eq!(polygons.iter().filter(|p| p.corners.len() == 3).count(), 8);
        let half = 7.5 - CRACK_MM / 2.0;
        for p in &polygons {
            for c in &p.corners {
                let local = *c - DVec3::new(0.0, 7.5, 0.0);
                assert!(local.abs().max_element() <= half + 1e-9, "{c}");
            }
        }
        // A face's inset square: 15 - crack - 2 bevel on a side.
        let top = polygons
            .iter()
            .find(|p| p.outward == DVec3::Y)
            .expect("top face");
        let side = (top.corners[1] - top.corners[0]).length();
        assert!(
            (side - (15.0 - CRACK_MM - 2.0 * BEVEL_MM)).abs() < 1e-9,
            "{side}"
        );
        assert!(top
            .corners
            .iter()
            .all(|c| (c.y - (15.0 - CRACK_MM / 2.0)).abs() < 1e-9));
    }

    #[test]
    fn every_triangle_faces_outward_and_the_bevel_strips_lean_between_faces() {
        let scene = Scene::new("c", vec![cube()]);
        let cam = cube_camera(CornerView::Ne);
        let v = photo_vertices(&scene, &cam, &[1.0]);
        assert_eq!(v.len(), (6 * 2 + 12 * 2 + 8) * 3 + 6);
        let centre = DVec3::new(0.0, 7.5, 0.0);
        for t in v[..v.len() - 6].chunks(3) {
            let p: Vec<DVec3> = t
                .iter()
                .map(|q| DVec3::from(q.position_mm.map(f64::from)))
                .collect();
            let n = (p[1] - p[0]).cross(p[2] - p[0]).normalize();
            assert!(n.dot((p[0] + p[1] + p[2]) / 3.0 - centre) > 0.0);
            assert!((n - DVec3::from(t[0].normal.map(f64::from))).length() < 1e-5);
        }
        let strip_normals = v[..v.len() - 6]
            .chunks(3)
            .filter(|t| {
                let n = DVec3::from(t[0].normal.map(f64::from));
                (n.abs().max_element() - std::f64::consts::FRAC_1_SQRT_2).abs() < 1e-5
            })
            .count();
        assert_eq!(strip_normals, 12 * 2, "twelve 45-degree bevel strips");
    }

    #[test]
    fn the_light_is_seeded_per_scene_and_albedos_stay_in_range() {
        let cam = cube_camera(CornerView::Se);
        let still = key_light(&cam, 0.0, 1);
        let base = light_in_world(&cam).normalize();
        assert!((still.towards_light - base).length() < 1e-9);
        let a = key_light(&cam, 20.0, 1);
        assert_eq!(a, key_light(&cam, 20.0, 1));
        assert_ne!(a, key_light(&cam, 20.0, 2));
        let turn = a.towards_light.dot(base).acos().to_degrees();
        assert!(
            turn > 0.0 && turn <= 20.0 * std::f64::consts::SQRT_2 + 1e-9,
            "{turn}"
        );
        let scene = Scene::new("c", vec![cube(); 20]);
        let albedos = block_albedos(&scene, [0.8, 1.0], 3);
        assert!(albedos.iter().all(|a| (0.8..=1.0).contains(a)));
        assert_ne!(albedos[0], albedos[1]);
        assert_eq!(albedos, block_albedos(&scene, [0.8, 1.0], 3));
        assert_eq!(block_albedos(&scene, [0.9, 0.9], 3), vec![0.9; 20]);
    }

    #[test]
    fn touching_blocks_get_a_crack_with_a_black_sheet_and_apart_blocks_none() {
        let pair = |dx: f64| {
            Scene::new(
                "p",
                vec![cube(), Block::new("b15", DVec3::new(dx, 7.5, 0.0), 0.0)],
            )
        };
        let c = find_contacts(&pair(15.0));
        assert_eq!(c.touching[0].iter().filter(|t| **t).count(), 1);
        assert_eq!(c.touching[1].iter().filter(|t| **t).count(), 1);
        assert_eq!(c.sheets.len(), 2);
        assert!((polygon_area(&c.sheets[0].corners) - 225.0).abs() < 1e-9);
        assert!(c.sheets[0].corners.iter().all(|p| (p.x - 7.5).abs() < 1e-9));
        // Half overlapping (shifted 7.5 mm along z): half the patch.
        let mut shifted = pair(15.0);
        shifted.blocks[1].center_mm.z = 7.5;
        let c = find_contacts(&shifted);
        assert!((polygon_area(&c.sheets[0].corners) - 112.5).abs() < 1e-9);
        let apart = find_contacts(&pair(15.5));
        assert!(apart.sheets.is_empty());
        assert!(apart.touching.iter().flatten().all(|t| !t));
    }

    #[test]
    fn a_swept_box_meets_what_lies_towards_the_light_only() {
        let unit = (DVec3::ZERO, DVec3::ONE);
        let up = DVec3::new(0.0, 1.0, 0.0);
        let above = (DVec3::new(0.0, 5.0, 0.0), DVec3::new(1.0, 6.0, 1.0));
        let below = (DVec3::new(0.0, -6.0, 0.0), DVec3::new(1.0, -5.0, 1.0));
        let aside = (DVec3::new(3.0, 5.0, 0.0), DVec3::new(4.0, 6.0, 1.0));
        assert!(swept_box_meets(unit, up, above));
        assert!(!swept_box_meets(unit, up, below), "behind the light's path");
        assert!(!swept_box_meets(unit, up, aside), "beside the light's path");
        assert!(
            swept_box_meets(grow_box(unit, 2.0), up, aside),
            "within the reach"
        );
        let slanted = DVec3::new(1.0, 1.0, 0.0).normalize();
        assert!(swept_box_meets(unit, slanted, aside));
    }

    /// Whether triangle `t` (its vertices' normal) turns away from direction `dir`, by more
    /// than an f32 normal's rounding (a face seen edge-on does not).
    /// A cube with another on top, shifted 7.5 mm across `cam`'s key light (`sign` 1: towards
    /// it, -1: away), and the direction towards that light.
    fn stacked_across_the_light(cam: &Camera, sign: f64) -> (Scene, DVec3) {
        let light = key_light(cam, 0.0, 1).towards_light;
        let shift = sign * DVec3::new(light.x, 0.0, light.z).normalize() * 7.5;
        let upper = Block::new("b15", DVec3::new(0.0, 22.5, 0.0) + shift, 0.0);
        (Scene::new("s", vec![cube(), upper]), light)
    }

    fn turned_away(t: &[PhotoVertex], dir: DVec3) -> bool {
        DVec3::from(t[0].normal.map(f64::from)).dot(dir.normalize()) < -1e-6
    }

    /// Whether triangle `t` runs clockwise in `camera`'s picture (x right, y up) by more than
    /// rounding: the back face the radiance pass culls. A face seen edge-on (a sliver whose
    /// area is a rounding of its vertices, under 1e-4 of its longest side squared) does not.
    fn clockwise_on_screen(t: &[PhotoVertex], camera: &Camera) -> bool {
        let p: Vec<glam::DVec2> = t
            .iter()
            .map(|v| {
                let q = camera.picture_from_world(DVec3::from(v.position_mm.map(f64::from)));
                glam::DVec2::new(q.x, q.y)
            })
            .collect();
        let longest_sq = [p[1] - p[0], p[2] - p[1], p[0] - p[2]]
            .iter()
            .map(|e| e.length_squared())
            .fold(0.0, f64::max);
        (p[1] - p[0]).perp_dot(p[2] - p[0]) < -1e-4 * longest_sq
    }

    #[test]
    fn each_pass_gets_the_triangles_it_does_not_cull() {
        // A stack, a touching neighbour (cracks and their sheets) and a jittered light.
        let upper = Block::new("b15", DVec3::new(3.0, 22.5, 2.0), 0.0);
        let beside = Block::new("b15", DVec3::new(15.0, 7.5, 0.0), 0.0);
        let scene = Scene::new("s", vec![cube(), upper, beside]);
        let albedos = [0.9, 0.8, 0.85];
        for view in CornerView::ALL {
            let cam = cube_camera(view);
            let light = key_light(&cam, 20.0, 3).towards_light;
            let m = photo_mesh(&scene, &cam, &albedos, light, 9.0);
            let tris = |r: std::ops::Range<usize>| m.vertices[r].to_vec();
            let drawn = [
                tris(m.shadowed.clone()),
                tris(m.behind.clone()),
                tris(m.unshadowed.clone()),
            ]
            .concat();
            assert!(!drawn.is_empty());
            for t in drawn.chunks_exact(3) {
                assert!(
                    !clockwise_on_screen(t, &cam),
                    "{view:?}: a triangle turned away from the eye"
                );
            }
            let casters = tris(m.casters.clone());
            assert!(casters.chunks_exact(3).all(|t| !turned_away(t, -light)));
            // Every face turned away from the light casts, as in the plain mesh.
            let plain = photo_vertices(&scene, &cam, &albedos);
            let away = plain
                .chunks_exact(3)
                .filter(|t| !turned_away(t, -light))
                .count();
            assert_eq!(casters.len() / 3, away, "{view:?}");
            // The ranges cover every vertex, so nothing is uploaded that no pass draws.
            assert_eq!(m.shadowed.start, 0);
            assert_eq!(
                (m.shadowed.end, m.behind.end),
                (m.behind.start, m.unshadowed.start)
            );
            assert!(m.casters.start >= m.unshadowed.start && m.casters.start <= m.unshadowed.end);
            assert_eq!(m.casters.end, m.vertices.len());
        }
    }

    #[test]
    fn only_faces_and_floor_near_another_block_get_the_shadow_test() {
        let cam = cube_camera(CornerView::Ne);
        let light = key_light(&cam, 0.0, 1).towards_light;
        let lone = Scene::new("c", vec![cube()]);
        let m = photo_mesh(&lone, &cam, &[0.9], light, 9.0);
        // A lone convex block shades no face of its own: only the floor near it is shadowed.
        let shadowed = &m.vertices[m.shadowed.clone()];
        assert!(!shadowed.is_empty() && shadowed.iter().all(|v| v.albedo == 0.15));
        assert!(shadowed.iter().all(|v| v.position_mm[1] == 0.0));
        // Every block triangle turned to the eye is drawn once, whichever pipeline draws it.
        let all = photo_vertices(&lone, &cam, &[0.9]);
        let seen: Vec<PhotoVertex> = all
            .chunks_exact(3)
            .filter(|t| !clockwise_on_screen(t, &cam))
            .flatten()
            .copied()
            .collect();
        let blocks = |v: &[PhotoVertex]| v.iter().filter(|v| v.albedo != 0.15).count();
        let radiance = [
            &m.vertices[m.shadowed.clone()],
            &m.vertices[m.unshadowed.clone()],
        ];
        assert_eq!(blocks(&radiance.concat()), blocks(&seen));
        assert!(m.behind.is_empty());
        // A cube on top of another, shifted towards the light: the lower one's top faces it.
        let (stack, _) = stacked_across_the_light(&cam, 1.0);
        let m = photo_mesh(&stack, &cam, &[0.9, 0.8], light, 9.0);
        let shadowed = &m.vertices[m.shadowed.clone()];
        assert!(shadowed
            .iter()
            .any(|v| v.albedo == 0.9 && v.normal[1] > 0.99));
        assert!(!shadowed
            .iter()
            .any(|v| v.albedo == 0.8 && v.normal[1] > 0.99));
        let rest = &m.vertices[m.unshadowed.clone()];
        assert!(rest
            .iter()
            .any(|v| v.position_mm[1] == -OUTER_FLOOR_DROP_MM as f32));
    }

    #[test]
    fn a_face_partly_within_reach_is_split_and_drawn_whole_behind() {
        let cam = cube_camera(CornerView::Ne);
        // A cube on top of another, shifted away from the light: the lower top's half on the
        // light's side is lit beyond 3 mm from the upper block.
        let (stack, light) = stacked_across_the_light(&cam, -1.0);
        let m = photo_mesh(&stack, &cam, &[0.9, 0.8], light, 3.0);
        let lower_top = |t: &&[PhotoVertex]| t[0].albedo == 0.9 && t[0].normal[1] > 0.99;
        let top_area = |v: &[PhotoVertex]| -> f64 {
            v.chunks_exact(3)
                .filter(lower_top)
                .map(|t| {
                    let p = t.iter().map(|v| DVec3::from(v.position_mm.map(f64::from)));
                    polygon_area(&p.collect::<Vec<_>>())
                })
                .sum()
        };
        let behind = &m.vertices[m.behind.clone()];
        let shadowed = &m.vertices[m.shadowed.clone()];
        let (part, whole) = (top_area(shadowed), top_area(behind));
        // The lower top: its sides touch nothing, so only the bevel insets them.
        let side = 15.0 - 2.0 * BEVEL_MM;
        assert!((whole - side * side).abs() < 1e-3, "{whole}");
        assert!(
            part > 0.3 * whole && part < 0.9 * whole,
            "{part} of {whole}"
        );
        // The whole top is drawn once behind, not also in front.
        let front = &m.vertices[m.unshadowed.clone()];
        assert_eq!(top_area(front), 0.0);
        // With the reach of the shader, the whole top is within reach: shadowed, drawn once.
        let m = photo_mesh(&stack, &cam, &[0.9, 0.8], light, 9.0);
        assert!((top_area(&m.vertices[m.shadowed.clone()]) - side * side).abs() < 1e-3);
        assert_eq!(top_area(&m.vertices[m.shadowed.end..]), 0.0);
    }

    #[test]
    fn without_shadows_every_seen_triangle_is_drawn_without_the_test_and_nothing_casts() {
        let cam = cube_camera(CornerView::Ne);
        let (stack, light) = stacked_across_the_light(&cam, -1.0);
        let m = photo_mesh(&stack, &cam, &[0.9, 0.8], light, 3.0);
        assert!(!m.shadowed.is_empty() && !m.behind.is_empty() && !m.casters.is_empty());
        let bare = m.without_shadows();
        assert!(bare.shadowed.is_empty() && bare.casters.is_empty());
        assert_eq!(bare.behind, 0..m.behind.len());
        assert_eq!(bare.unshadowed, m.behind.len()..bare.vertices.len());
        // The whole faces first (drawn behind), then the parts that had the shadow test and
        // the rest, all drawn without it; no caster, as no shadow map is needed.
        let expected = [
            &m.vertices[m.behind.clone()],
            &m.vertices[m.shadowed.clone()],
            &m.vertices[m.unshadowed.clone()],
        ]
        .concat();
        assert_eq!(bare.vertices, expected);
    }

    #[test]
    fn the_reach_hulls_only_the_grown_points_that_can_bound_it() {
        // Every point of the 16-gons around every vertex, hulled, against the points within
        // each vertex's cone: the same polygon, on random convex hulls and on a segment.
        let mut rng = rand::rngs::StdRng::seed_from_u64(7);
        let radius = 9.0;
        for case in 0..200 {
            let n = if case % 10 == 0 {
                2
            } else {
                rng.random_range(3..12)
            };
            let points: Vec<glam::DVec2> = (0..n)
                .map(|_| {
                    glam::DVec2::new(rng.random_range(-20.0..20.0), rng.random_range(-20.0..20.0))
                })
                .collect();
            let hull = crate::geom::convex_hull(&points);
            let every: Vec<glam::DVec2> = hull
                .iter()
                .flat_map(|c| REACH_DIRECTIONS.iter().map(move |d| *c + *d * radius))
                .collect();
            let want = crate::geom::convex_hull(&every);
            let kept = grown_corners(&hull, radius);
            assert!(kept.len() < every.len() || hull.len() < 3);
            let got = crate::geom::convex_hull(&kept);
            assert_eq!(got.len(), want.len(), "case {case}");
            for (g, w) in got.iter().zip(&want) {
                assert!(g.distance(*w) < 1e-9, "case {case}: {g} against {w}");
            }
        }
        // The cone test can fail: a vertex is not the farthest against its edges' directions.
        let (e_in, e_out) = (glam::DVec2::X, glam::DVec2::Y);
        assert!(in_cone(
            glam::DVec2::new(1.0, -1.0).normalize(),
            e_in,
            e_out
        ));
        assert!(!in_cone(
            glam::DVec2::new(-1.0, -1.0).normalize(),
            e_in,
            e_out
        ));
        assert!(!in_cone(
            glam::DVec2::new(1.0, 1.0).normalize(),
            e_in,
            e_out
        ));
        // Widened by half a 16-gon side's angle, 11.25 degrees, and no more.
        let at = |deg: f64| glam::DVec2::from_angle(deg.to_radians());
        assert!(in_cone(at(11.0), e_in, e_out) && in_cone(at(-101.0), e_in, e_out));
        assert!(!in_cone(at(11.5), e_in, e_out) && !in_cone(at(-101.5), e_in, e_out));
    }

    #[test]
    fn a_neighbour_flush_with_a_face_casts_no_shadow_on_it() {
        // Two cubes side by side, touching: each top is flush with the other's, so neither top
        // needs the shadow test, though each block's box, grown by the reach, meets the
        // other's.
        let cam = cube_camera(CornerView::Ne);
        let light = key_light(&cam, 0.0, 1).towards_light;
        let beside = Block::new("b15", DVec3::new(15.0, 7.5, 0.0), 0.0);
        let row = Scene::new("r", vec![cube(), beside]);
        let m = photo_mesh(&row, &cam, &[0.9, 0.8], light, 9.0);
        let shadowed = &m.vertices[m.shadowed.clone()];
        assert!(
            !shadowed
                .iter()
                .any(|v| v.albedo != PHOTO_FLOOR_ALBEDO as f32 && v.normal[1] > 0.99),
            "a top face got the shadow test"
        );
        // The reach test itself: a solid flush with the face reaches nothing; lifted a
        // millimetre above it, it reaches the face.
        let frame = LightFrame::new(light);
        let top = [
            DVec3::new(-7.5, 15.0, -7.5),
            DVec3::new(-7.5, 15.0, 7.5),
            DVec3::new(7.5, 15.0, 7.5),
            DVec3::new(7.5, 15.0, -7.5),
        ];
        let flush = beside.world_vertices();
        assert!(shadow_reach(&top, DVec3::Y, &frame, &[&flush], 9.0).is_empty());
        let lifted: Vec<DVec3> = flush.iter().map(|p| *p + DVec3::Y).collect();
        let reached = shadow_reach(&top, DVec3::Y, &frame, &[&lifted], 9.0);
        let near = frame.across(DVec3::new(7.0, 15.0, 0.0));
        assert!(crate::geom::inside_convex(&reached, near, 0.0));
        // Lifted back onto the top's plane, a point of the region stays where it was across
        // the light.
        let on_top = frame.onto_plane(near, top[0], DVec3::Y);
        assert!((on_top - DVec3::new(7.0, 15.0, 0.0)).length() < 1e-9);
    }
}
