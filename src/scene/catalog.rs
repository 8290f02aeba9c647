//! The block catalog: every block type as data, a convex polyhedron given by its vertices and
//! faces in one table (Chapter VI, Figure 6.1: the three basic Fischer-Technik blocks).
//!
//! Renderer, ground truth, physics and scoring read shapes only through [`BlockType`], so a new
//! block (the trapezoidal wedge of Chapter VII, Figure 7.1) is one more row in [`CATALOG`].

use crate::geom::{bounds3, newell_vector, DVec3};

/// Vertex indices of the six faces of a cuboid whose vertices follow [`cuboid_vertices`]'s order,
/// each face counter-clockwise seen from outside.
const CUBOID_FACES: &[&[u8]] = &[
    &[0, 1, 3, 2], // -x
    &[4, 6, 7, 5], // +x
    &[0, 4, 5, 1], // -y (bottom)
    &[2, 3, 7, 6], // +y (top)
    &[0, 2, 6, 4], // -z
    &[1, 5, 7, 3], // +z
];

/// The eight corners of a cuboid centred on the origin with the given full size in mm;
/// vertex `i` has x = +size.x/2 when bit 2 of `i` is set, y when bit 1 is, z when bit 0 is.
const fn cuboid_vertices(x: f64, y: f64, z: f64) -> [[f64; 3]; 8] {
    let (hx, hy, hz) = (x / 2.0, y / 2.0, z / 2.0);
    [
        [-hx, -hy, -hz],
        [-hx, -hy, hz],
        [-hx, hy, -hz],
        [-hx, hy, hz],
        [hx, -hy, -hz],
        [hx, -hy, hz],
        [hx, hy, -hz],
        [hx, hy, hz],
    ]
}

const B15_VERTICES: [[f64; 3]; 8] = cuboid_vertices(15.0, 15.0, 15.0);
const B30_VERTICES: [[f64; 3]; 8] = cuboid_vertices(30.0, 15.0, 15.0);
const B7_5_VERTICES: [[f64; 3]; 8] = cuboid_vertices(15.0, 7.5, 15.0);

/// The trapezoidal block of Chapter VII (Figure 7.1): a prism along local z whose two side faces
/// (at z = -7.5 and z = +7.5) are trapezoids with a 30 mm bottom, a 15 mm top over its -x half,
/// a vertical 15 mm end at -x and a face sloped at 45 degrees down to the +x bottom edge.
/// Vertex `i` is at z = +7.5 when bit 0 of `i` is set; bits 1-2 walk the trapezoid
/// (-x bottom, +x bottom, top middle, -x top).
const W30_VERTICES: [[f64; 3]; 8] = [
    [-15.0, -7.5, -7.5],
    [-15.0, -7.5, 7.5],
    [15.0, -7.5, -7.5],
    [15.0, -7.5, 7.5],
    [0.0, 7.5, -7.5],
    [0.0, 7.5, 7.5],
    [-15.0, 7.5, -7.5],
    [-15.0, 7.5, 7.5],
];

/// Faces of [`W30_VERTICES`], counter-clockwise seen from outside.
const W30_FACES: &[&[u8]] = &[
    &[0, 6, 4, 2], // -z trapezoid
    &[1, 3, 5, 7], // +z trapezoid
    &[0, 2, 3, 1], // -y (bottom)
    &[6, 7, 5, 4], // +y (top, the -x half)
    &[0, 1, 7, 6], // -x end
    &[2, 4, 5, 3], // the sloped face, normal (1, 1, 0) / sqrt 2
];

/// Sides of the polygonal prism that stands in for a round part (see [`RoundPart`]). 64 is a
/// multiple of 4, so vertices sit on the local x and z axes and the bounding box is exact.
pub const ROUND_PRISM_SIDES: usize = 64;

/// `(cos, sin)` of `2 pi k / ROUND_PRISM_SIDES`, evaluated at compile time: a Taylor series on
/// the first quadrant (angle below pi / 2, 24 terms: error below 1e-16), turned into the others
/// exactly, so the four axis points are exact.
const fn round_cos_sin(k: usize) -> (f64, f64) {
    let quarter = ROUND_PRISM_SIDES / 4;
    let phi = 2.0 * std::f64::consts::PI * (k % quarter) as f64 / ROUND_PRISM_SIDES as f64;
    let (mut c, mut s, mut term_c, mut term_s) = (1.0, phi, 1.0, phi);
    let mut n = 1;
    while n < 24 {
        term_c = -term_c * phi * phi / ((2 * n - 1) * (2 * n)) as f64;
        term_s = -term_s * phi * phi / ((2 * n) * (2 * n + 1)) as f64;
        c += term_c;
        s += term_s;
        n += 1;
    }
    match k / quarter {
        0 => (c, s),
        1 => (-s, c),
        2 => (-c, -s),
        _ => (s, -c),
    }
}

/// The vertices of the prism inscribed in a cylinder of `radius` and `height` (mm) standing on
/// its base: bottom ring `0..N` at y = -height/2, top ring `N..2N` above it, vertex `k` of a ring
/// at angle `2 pi k / N` from local +x towards local +z.
const fn round_prism_vertices(radius: f64, height: f64) -> [[f64; 3]; 2 * ROUND_PRISM_SIDES] {
    let mut out = [[0.0; 3]; 2 * ROUND_PRISM_SIDES];
    let mut k = 0;
    while k < ROUND_PRISM_SIDES {
        let (c, s) = round_cos_sin(k);
        out[k] = [radius * c, -height / 2.0, radius * s];
        out[k + ROUND_PRISM_SIDES] = [radius * c, height / 2.0, radius * s];
        k += 1;
    }
    out
}

/// Side quads of the round prism, each counter-clockwise seen from outside.
const fn round_prism_sides() -> [[u8; 4]; ROUND_PRISM_SIDES] {
    let n = ROUND_PRISM_SIDES;
    let mut out = [[0u8; 4]; ROUND_PRISM_SIDES];
    let mut k = 0;
    while k < n {
        let next = (k + 1) % n;
        out[k] = [k as u8, (n + k) as u8, (n + next) as u8, next as u8];
        k += 1;
    }
    out
}

/// One ring of the round prism (`first` = 0 bottom, N top), counter-clockwise seen from outside:
/// ascending for the bottom (seen from below), descending for the top.
const fn round_prism_ring(first: usize, descending: bool) -> [u8; ROUND_PRISM_SIDES] {
    let mut out = [0u8; ROUND_PRISM_SIDES];
    let mut k = 0;
    while k < ROUND_PRISM_SIDES {
        let j = if descending {
            ROUND_PRISM_SIDES - 1 - k
        } else {
            k
        };
        out[k] = (first + j) as u8;
        k += 1;
    }
    out
}

static ROUND_SIDES: [[u8; 4]; ROUND_PRISM_SIDES] = round_prism_sides();
static ROUND_BOTTOM: [u8; ROUND_PRISM_SIDES] = round_prism_ring(0, false);
static ROUND_TOP: [u8; ROUND_PRISM_SIDES] = round_prism_ring(ROUND_PRISM_SIDES, true);

/// The round prism's faces: the side quads, then bottom and top.
const fn round_prism_faces() -> [&'static [u8]; ROUND_PRISM_SIDES + 2] {
    let mut out: [&'static [u8]; ROUND_PRISM_SIDES + 2] = [&[]; ROUND_PRISM_SIDES + 2];
    let mut k = 0;
    while k < ROUND_PRISM_SIDES {
        out[k] = &ROUND_SIDES[k];
        k += 1;
    }
    out[ROUND_PRISM_SIDES] = &ROUND_BOTTOM;
    out[ROUND_PRISM_SIDES + 1] = &ROUND_TOP;
    out
}

static ROUND_FACES: [&[u8]; ROUND_PRISM_SIDES + 2] = round_prism_faces();
static C15_VERTICES: [[f64; 3]; 2 * ROUND_PRISM_SIDES] = round_prism_vertices(7.5, 15.0);

/// A convex polyhedron in block-local millimetres, centred on the centre of its bounding box,
/// resting orientation with local +y up.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConvexPolyhedron {
    /// Vertices in block-local mm, relative to the bounding-box centre.
    pub vertices_mm: &'static [[f64; 3]],
    /// Faces as vertex-index loops, counter-clockwise seen from outside.
    pub faces: &'static [&'static [u8]],
}

/// A round part (Chapter VII: "blocks like pyramids or circles"): a right circular cylinder
/// standing on its base, axis along local +y through the origin.
///
/// Stages that need a polyhedron (separating-axis overlap, the render mesh, scoring, export) read
/// `prism`, the prism inscribed in the cylinder with [`ROUND_PRISM_SIDES`] sides. Its stated
/// bounds: every point of the cylinder lies within `radius (1 - cos(pi / N))` (0.009 mm for
/// 7.5 mm) of the prism, and the prism's volume falls short of the cylinder's by the fraction
/// `1 - N sin(2 pi / N) / (2 pi)` (0.16 %); see [`RoundPart::prism_volume_shortfall`].
/// Physics uses an exact cylinder collider and the exact line drawing the circle in closed form.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RoundPart {
    /// Radius of the base circle in mm.
    pub radius_mm: f64,
    /// Height along local y in mm.
    pub height_mm: f64,
    /// The inscribed polygonal prism (bottom ring first, then the top ring).
    pub prism: ConvexPolyhedron,
}

impl RoundPart {
    /// Exact volume of the cylinder in mm^3.
    pub fn cylinder_volume_mm3(&self) -> f64 {
        std::f64::consts::PI * self.radius_mm * self.radius_mm * self.height_mm
    }

    /// The fraction of the cylinder's volume that the inscribed prism misses:
    /// `1 - N sin(2 pi / N) / (2 pi)` (0.16 % for N = 64), the bound on the volume error of
    /// every stage that reads the prism.
    pub fn prism_volume_shortfall() -> f64 {
        let n = ROUND_PRISM_SIDES as f64;
        let t = std::f64::consts::TAU;
        1.0 - n * (t / n).sin() / t
    }

    /// The largest distance from the cylinder's surface to the prism, mm: `r (1 - cos(pi / N))`.
    pub fn prism_gap_mm(&self) -> f64 {
        self.radius_mm * (1.0 - (std::f64::consts::PI / ROUND_PRISM_SIDES as f64).cos())
    }
}

/// The solid of a catalog entry. Every stage reads it through [`BlockType::polyhedron`] (the
/// exact solid for polyhedra, the inscribed prism for round parts); stages that can do better
/// for a round part (physics, the exact line drawing) ask [`BlockType::round`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Shape {
    /// A convex polyhedron (the three basic blocks of Figure 6.1, the wedge of Figure 7.1).
    ConvexPolyhedron(ConvexPolyhedron),
    /// A round part (Chapter VII's "circles").
    Round(RoundPart),
}

/// One block type: an id used in scene files, a human name, and its shape.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BlockType {
    /// The id scene files use (`"b15"`).
    pub id: &'static str,
    /// The Fischer-Technik name (`"Baustein 15"`).
    pub name: &'static str,
    /// The solid.
    pub shape: Shape,
}

/// The catalog (docs/formats.md "Block catalog"): ids and sizes as x length, y height, z width in mm.
///
/// | id | name | x | y | z |
/// |---|---|---|---|---|
/// | `b15` | Baustein 15 | 15 | 15 | 15 |
/// | `b30` | Baustein 30 | 30 | 15 | 15 |
/// | `b7_5` | Baustein 7,5 | 15 | 7.5 | 15 |
/// | `w30` | Keil 30 (trapezoidal block) | 30 | 15 | 15 |
/// | `c15` | Rundstein 15 (round part) | 15 | 15 | 15 |
///
/// The two Chapter VII parts keep Fischer-Technik's grid: every length is a multiple of the
/// 7.5 mm half-pitch of the 15 mm building blocks, so they stack on and under the basic blocks
/// without gaps. The wedge `w30` has the Baustein 30 footprint with its +x half cut at 45 degrees
/// (a 15 mm top, a 15 mm run down the slope's 15 mm fall), so its sloped face is a new picture
/// direction and a new gradient (Figure 7.1); the round part `c15` is 15 mm across and 15 mm
/// tall, the Baustein 15's size.
pub const CATALOG: &[BlockType] = &[
    BlockType {
        id: "b15",
        name: "Baustein 15",
        shape: Shape::ConvexPolyhedron(ConvexPolyhedron {
            vertices_mm: &B15_VERTICES,
            faces: CUBOID_FACES,
        }),
    },
    BlockType {
        id: "b30",
        name: "Baustein 30",
        shape: Shape::ConvexPolyhedron(ConvexPolyhedron {
            vertices_mm: &B30_VERTICES,
            faces: CUBOID_FACES,
        }),
    },
    BlockType {
        id: "b7_5",
        name: "Baustein 7,5",
        shape: Shape::ConvexPolyhedron(ConvexPolyhedron {
            vertices_mm: &B7_5_VERTICES,
            faces: CUBOID_FACES,
        }),
    },
    BlockType {
        id: "w30",
        name: "Keil 30",
        shape: Shape::ConvexPolyhedron(ConvexPolyhedron {
            vertices_mm: &W30_VERTICES,
            faces: W30_FACES,
        }),
    },
    BlockType {
        id: "c15",
        name: "Rundstein 15",
        shape: Shape::Round(RoundPart {
            radius_mm: 7.5,
            height_mm: 15.0,
            prism: ConvexPolyhedron {
                vertices_mm: &C15_VERTICES,
                faces: &ROUND_FACES,
            },
        }),
    },
];

/// The basic blocks of Figure 6.1, the cuboids the thesis's method recognizes by parallelogram
/// search (Chapters IV-V): catalog entries whose polyhedron fills its bounding box.
pub fn basic_blocks() -> impl Iterator<Item = &'static BlockType> {
    CATALOG
        .iter()
        .filter(|t| t.cuboid_half_extents_mm().is_some())
}

/// Looks a block type up by its scene-file id.
pub fn block_type(id: &str) -> Option<&'static BlockType> {
    CATALOG.iter().find(|t| t.id == id)
}

/// Rotations that map a block type's polyhedron onto itself, among the 24 rotations of the
/// cube group (every catalog block is modelled in its bounding box's axes, so no other rotation
/// can be a symmetry of it except for shapes with rotational symmetry about a diagonal, which
/// the catalog does not have). A `b15` cube has all 24, a `b30` (30 x 15 x 15) and a `b7_5`
/// (15 x 7.5 x 15) have 8 each: 180° turns about every axis and 90° turns about the long
/// (short) axis; a wedge will have fewer.
pub fn symmetry_rotations(block_type: &BlockType) -> Vec<glam::DQuat> {
    let vertices: Vec<DVec3> = block_type.vertices().collect();
    cube_group()
        .into_iter()
        .filter(|q| {
            vertices.iter().all(|v| {
                let w = *q * *v;
                vertices.iter().any(|u| (*u - w).abs().max_element() < 1e-9)
            })
        })
        .collect()
}

/// The 24 proper rotations that permute the coordinate axes (with signs).
fn cube_group() -> Vec<glam::DQuat> {
    let axes = [DVec3::X, DVec3::Y, DVec3::Z];
    let mut out = Vec::with_capacity(24);
    for (i, &a) in axes.iter().enumerate() {
        for (j, &b) in axes.iter().enumerate() {
            if i == j {
                continue;
            }
            for sa in [1.0, -1.0] {
                for sb in [1.0, -1.0] {
                    let (x, y) = (a * sa, b * sb);
                    let m = glam::DMat3::from_cols(x, y, x.cross(y));
                    out.push(glam::DQuat::from_mat3(&m));
                }
            }
        }
    }
    out
}

impl BlockType {
    /// The solid as a convex polyhedron: exact for the polyhedral blocks, the inscribed prism
    /// (with [`RoundPart`]'s stated bounds) for a round part.
    pub fn polyhedron(&self) -> &ConvexPolyhedron {
        match &self.shape {
            Shape::ConvexPolyhedron(p) => p,
            Shape::Round(r) => &r.prism,
        }
    }

    /// The round part's exact cylinder, `None` for a polyhedral block.
    pub fn round(&self) -> Option<&RoundPart> {
        match &self.shape {
            Shape::ConvexPolyhedron(_) => None,
            Shape::Round(r) => Some(r),
        }
    }

    /// The polyhedron's vertices as arrays, block-local mm.
    pub fn vertices_mm(&self) -> &'static [[f64; 3]] {
        self.polyhedron().vertices_mm
    }

    /// The polyhedron's faces as vertex-index loops, counter-clockwise seen from outside.
    pub fn faces(&self) -> &'static [&'static [u8]] {
        self.polyhedron().faces
    }

    /// The polyhedron's vertices, block-local mm.
    pub fn vertices(&self) -> impl ExactSizeIterator<Item = DVec3> + '_ {
        self.vertices_mm().iter().map(|v| DVec3::from_array(*v))
    }

    /// Full bounding-box size in mm (x length, y height, z width).
    pub fn size_mm(&self) -> DVec3 {
        let (lo, hi) = self.local_bounds_mm();
        hi - lo
    }

    /// Local axis-aligned bounds (min, max) in mm.
    pub fn local_bounds_mm(&self) -> (DVec3, DVec3) {
        bounds3(self.vertices()).unwrap_or((DVec3::ZERO, DVec3::ZERO))
    }

    /// Half extents in mm when the shape is an axis-aligned cuboid filling its bounding box
    /// (physics uses rapier's cuboid collider then); `None` for any other polyhedron.
    pub fn cuboid_half_extents_mm(&self) -> Option<DVec3> {
        let (lo, hi) = self.local_bounds_mm();
        let is_box = self.vertices_mm().len() == 8
            && self.faces().len() == 6
            && self.vertices().all(|v| {
                (0..3).all(|k| (v[k] - lo[k]).abs() < 1e-9 || (v[k] - hi[k]).abs() < 1e-9)
            });
        is_box.then(|| (hi - lo) / 2.0)
    }

    /// Volume in mm^3 (divergence theorem over the triangulated faces).
    pub fn volume_mm3(&self) -> f64 {
        let v: Vec<DVec3> = self.vertices().collect();
        self.faces()
            .iter()
            .flat_map(|f| {
                let v = &v;
                (1..f.len() - 1).map(move |k| {
                    let (a, b, c) = (v[f[0] as usize], v[f[k] as usize], v[f[k + 1] as usize]);
                    a.dot(b.cross(c)) / 6.0
                })
            })
            .sum()
    }

    /// Outward unit normal of face `f` in block-local coordinates.
    pub fn face_normal(&self, f: usize) -> DVec3 {
        let face = self.faces()[f];
        let corners: Vec<DVec3> = face
            .iter()
            .map(|&k| DVec3::from_array(self.vertices_mm()[k as usize]))
            .collect();
        newell_vector(&corners).normalize()
    }

    /// The polyhedron's edges as sorted vertex-index pairs, each once, with the two faces that
    /// share it: `(a, b, face_left, face_right)`.
    pub fn edges(&self) -> Vec<(usize, usize, usize, usize)> {
        let mut out: Vec<(usize, usize, usize, usize)> = Vec::new();
        for (fi, face) in self.faces().iter().enumerate() {
            for k in 0..face.len() {
                let (a, b) = (face[k] as usize, face[(k + 1) % face.len()] as usize);
                let key = (a.min(b), a.max(b));
                if let Some(e) = out.iter_mut().find(|e| (e.0, e.1) == key) {
                    e.3 = fi;
                } else {
                    out.push((key.0, key.1, fi, usize::MAX));
                }
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn catalog_sizes_are_the_fischer_technik_blocks() {
        let size = |id| block_type(id).unwrap().size_mm().to_array();
        assert_eq!(size("b15"), [15.0, 15.0, 15.0]);
        assert_eq!(size("b30"), [30.0, 15.0, 15.0]);
        assert_eq!(size("b7_5"), [15.0, 7.5, 15.0]);
        assert_eq!(size("w30"), [30.0, 15.0, 15.0]);
        assert_eq!(size("c15"), [15.0, 15.0, 15.0]);
        assert!(block_type("b45").is_none());
    }

    /// The basic blocks are the three cuboids of Figure 6.1; the wedge and the round part are
    /// not (the recognizer's parallelogram search reads only these).
    #[test]
    fn basic_blocks_are_the_three_cuboids_of_figure_6_1() {
        let ids: Vec<&str> = basic_blocks().map(|t| t.id).collect();
        assert_eq!(ids, ["b15", "b30", "b7_5"]);
        assert!(block_type("w30")
            .unwrap()
            .cuboid_half_extents_mm()
            .is_none());
        assert!(block_type("c15").unwrap().round().is_some());
        assert!(block_type("b15").unwrap().round().is_none());
    }

    /// The wedge: a trapezoid (30 mm bottom, 15 mm top, 15 mm tall) drawn out 15 mm, its sloped
    /// face at 45 degrees facing +x and up, every vertex on the 7.5 mm grid.
    #[test]
    fn wedge_is_a_trapezoidal_prism_with_one_45_degree_face() {
        let w = block_type("w30").unwrap();
        assert_eq!(w.volume_mm3(), (30.0 + 15.0) / 2.0 * 15.0 * 15.0);
        let sloped: Vec<DVec3> = (0..w.faces().len())
            .map(|f| w.face_normal(f))
            .filter(|n| n.x.abs() > 1e-9 && n.y.abs() > 1e-9)
            .collect();
        assert_eq!(sloped.len(), 1);
        assert!(sloped[0].distance(DVec3::new(1.0, 1.0, 0.0).normalize()) < 1e-12);
        for v in w.vertices() {
            assert!((0..3).all(|k| (v[k] / 7.5).fract() == 0.0), "{v}");
        }
    }

    /// The round part's prism keeps its stated bounds: vertices on the circle (the four axis
    /// points exactly), the volume shortfall `1 - N sin(2 pi / N) / (2 pi)` and the gap.
    #[test]
    fn round_part_prism_is_inscribed_within_the_stated_bounds() {
        let t = block_type("c15").unwrap();
        let r = t.round().unwrap();
        for v in t.vertices() {
            let radial = (v.x * v.x + v.z * v.z).sqrt();
            assert!((radial - 7.5).abs() < 1e-14, "{v}");
        }
        let axis: Vec<[f64; 3]> = [0, 16, 32, 48].map(|k| t.vertices_mm()[k]).to_vec();
        assert_eq!(
            axis,
            [
                [7.5, -7.5, 0.0],
                [0.0, -7.5, 7.5],
                [-7.5, -7.5, 0.0],
                [0.0, -7.5, -7.5]
            ]
        );
        let short = RoundPart::prism_volume_shortfall();
        assert!((0.0015..0.0017).contains(&short), "{short}");
        let want = r.cylinder_volume_mm3() * (1.0 - short);
        assert!((t.volume_mm3() - want).abs() < 1e-9 * want);
        assert!((r.prism_gap_mm() - 0.00903).abs() < 1e-5);
    }

    #[test]
    fn every_entry_is_a_closed_convex_polyhedron() {
        for t in CATALOG {
            let edges = t.edges();
            assert!(
                edges.iter().all(|e| e.3 != usize::MAX),
                "{} not closed",
                t.id
            );
            // Euler: V - E + F = 2.
            assert_eq!(
                t.vertices_mm().len() + t.faces().len(),
                edges.len() + 2,
                "{}",
                t.id
            );
            // Convex with outward normals: every vertex lies behind every face plane.
            for f in 0..t.faces().len() {
                let n = t.face_normal(f);
                let p0 = DVec3::from_array(t.vertices_mm()[t.faces()[f][0] as usize]);
                assert!(
                    t.vertices().all(|v| n.dot(v - p0) <= 1e-9),
                    "{} face {f}",
                    t.id
                );
            }
            let s = t.size_mm();
            let cuboid = (t.volume_mm3() - s.x * s.y * s.z).abs() < 1e-9;
            assert_eq!(cuboid, t.cuboid_half_extents_mm().is_some(), "{}", t.id);
        }
    }
}
