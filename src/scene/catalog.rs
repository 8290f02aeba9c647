//! The block catalog: every block type as data, a convex polyhedron given by its vertices and
//! faces in one table (Chapter VI, Figure 6.1: the three basic Fischer-Technik blocks).
//!
//! Renderer, ground truth, physics and scoring read shapes only through [`BlockType`], so a new
//! block (the trapezoidal wedge of Chapter VII, Figure 7.1) is one more row in [`CATALOG`].

use crate::geom::{bounds3, DVec3};

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

/// A convex polyhedron in block-local millimetres, centred on the centre of its bounding box,
/// resting orientation with local +y up.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConvexPolyhedron {
    /// Vertices in block-local mm, relative to the bounding-box centre.
    pub vertices_mm: &'static [[f64; 3]],
    /// Faces as vertex-index loops, counter-clockwise seen from outside.
    pub faces: &'static [&'static [u8]],
}

/// The solid of a catalog entry. Every stage reads it through [`BlockType::polyhedron`] (the
/// exact solid for polyhedra); a curved part (Chapter VII's "circles") joins as a new variant
/// whose polyhedron is its stated approximation, without touching the stages' code.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Shape {
    /// A convex polyhedron (the three basic blocks of Figure 6.1).
    ConvexPolyhedron(ConvexPolyhedron),
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

/// The catalog (README "Rendering"): ids and sizes as x length, y height, z width in mm.
///
/// | id | name | x | y | z |
/// |---|---|---|---|---|
/// | `b15` | Baustein 15 | 15 | 15 | 15 |
/// | `b30` | Baustein 30 | 30 | 15 | 15 |
/// | `b7_5` | Baustein 7,5 | 15 | 7.5 | 15 |
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
];

/// Looks a block type up by its scene-file id.
pub fn block_type(id: &str) -> Option<&'static BlockType> {
    CATALOG.iter().find(|t| t.id == id)
}

impl BlockType {
    /// The solid as a convex polyhedron: exact for the polyhedral blocks.
    pub fn polyhedron(&self) -> &ConvexPolyhedron {
        match &self.shape {
            Shape::ConvexPolyhedron(p) => p,
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
        let v = |k: usize| DVec3::from_array(self.vertices_mm()[face[k] as usize]);
        let mut n = DVec3::ZERO;
        for k in 0..face.len() {
            n += v(k).cross(v((k + 1) % face.len()));
        }
        n.normalize()
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
    fn catalog_sizes_match_issue_2() {
        let size = |id| block_type(id).unwrap().size_mm().to_array();
        assert_eq!(size("b15"), [15.0, 15.0, 15.0]);
        assert_eq!(size("b30"), [30.0, 15.0, 15.0]);
        assert_eq!(size("b7_5"), [15.0, 7.5, 15.0]);
        assert!(block_type("b45").is_none());
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
            assert!((t.volume_mm3() - s.x * s.y * s.z).abs() < 1e-9);
            assert!(t.cuboid_half_extents_mm().is_some());
        }
    }
}
