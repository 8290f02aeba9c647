//! One catalog block type as a flat-shaded triangle mesh in metres: each convex face is
//! fan-triangulated and gets its own copies of its vertices, so every vertex carries its face's
//! normal (sharp block edges, as in the thesis's line drawings). No glTF types here.

use super::ExportError;
use crate::geom::{newell_vector, DVec3};
use crate::scene::BlockType;

/// Metres per millimetre: glTF 2.0 lengths are metres, blockworld's are millimetres.
pub(super) const METRES_PER_MM: f64 = 0.001;

/// A block type's triangles, ready for a glTF buffer.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct FlatMesh {
    /// Vertex positions in block-local metres (one copy per face that uses the vertex).
    pub positions_m: Vec<[f32; 3]>,
    /// The outward unit normal of each vertex's face.
    pub normals: Vec<[f32; 3]>,
    /// Triangles as vertex-index triples, counter-clockwise seen from outside.
    pub indices: Vec<u32>,
}

impl FlatMesh {
    /// Per-axis (min, max) of the positions, as glTF wants on a POSITION accessor.
    pub fn bounds_m(&self) -> ([f32; 3], [f32; 3]) {
        let mut lo = [f32::INFINITY; 3];
        let mut hi = [f32::NEG_INFINITY; 3];
        for p in &self.positions_m {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        (lo, hi)
    }
}

/// Builds the flat-shaded mesh of `block_type` from its catalog vertices and faces. Faces are
/// convex loops (catalog contract), so a fan from the first vertex triangulates each one; a
/// face of n edges gives n - 2 triangles. Nothing assumes a cuboid.
pub(super) fn flat_mesh(block_type: &BlockType) -> Result<FlatMesh, ExportError> {
    let mut mesh = FlatMesh {
        positions_m: Vec::new(),
        normals: Vec::new(),
        indices: Vec::new(),
    };
    for (face_index, face) in block_type.faces().iter().enumerate() {
        let corners = face_corners_mm(block_type, face_index)?;
        let normal = face_normal(&corners).ok_or_else(|| ExportError::DegenerateFace {
            block_type: block_type.id.to_string(),
            face: face_index,
            reason: "its vertices enclose no area".to_string(),
        })?;
        let base = mesh.positions_m.len() as u32;
        for c in &corners {
            mesh.positions_m.push(to_f32(*c * METRES_PER_MM));
            mesh.normals.push(to_f32(normal));
        }
        for k in 1..face.len() as u32 - 1 {
            mesh.indices.extend([base, base + k, base + k + 1]);
        }
    }
    Ok(mesh)
}

/// The corners of face `face_index` in block-local mm, checked against the vertex table.
fn face_corners_mm(block_type: &BlockType, face_index: usize) -> Result<Vec<DVec3>, ExportError> {
    let face = block_type.faces()[face_index];
    let bad = |reason: String| ExportError::DegenerateFace {
        block_type: block_type.id.to_string(),
        face: face_index,
        reason,
    };
    if face.len() < 3 {
        return Err(bad(format!("it has {} vertices, fewer than 3", face.len())));
    }
    face.iter()
        .map(|&i| {
            block_type
                .vertices_mm()
                .get(i as usize)
                .map(|v| DVec3::from_array(*v))
                .ok_or_else(|| {
                    bad(format!(
                        "vertex index {i} is past the {} vertices",
                        block_type.vertices_mm().len()
                    ))
                })
        })
        .collect()
}

/// Outward unit normal of a counter-clockwise loop (Newell's method), `None` for zero area.
fn face_normal(corners: &[DVec3]) -> Option<DVec3> {
    newell_vector(corners).try_normalize()
}

fn to_f32(v: DVec3) -> [f32; 3] {
    [v.x as f32, v.y as f32, v.z as f32]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{block_type, ConvexPolyhedron, Shape, CATALOG};

    /// Signed volume enclosed by the triangles, in m^3 (divergence theorem).
    fn volume_m3(mesh: &FlatMesh) -> f64 {
        let p = |i: u32| DVec3::from_array(mesh.positions_m[i as usize].map(f64::from));
        mesh.indices
            .chunks(3)
            .map(|t| p(t[0]).dot(p(t[1]).cross(p(t[2]))) / 6.0)
            .sum()
    }

    #[test]
    fn cuboid_gives_twelve_triangles_with_axis_normals() {
        let mesh = flat_mesh(block_type("b30").unwrap()).unwrap();
        assert_eq!(mesh.positions_m.len(), 24, "4 copies per face, 6 faces");
        assert_eq!(mesh.indices.len(), 36, "2 triangles per quad");
        let (lo, hi) = mesh.bounds_m();
        assert_eq!(lo, [-0.015, -0.0075, -0.0075]);
        assert_eq!(hi, [0.015, 0.0075, 0.0075]);
        for n in &mesh.normals {
            let nonzero: Vec<_> = n.iter().filter(|c| **c != 0.0).collect();
            assert_eq!(nonzero.len(), 1, "{n:?}");
            assert_eq!(nonzero[0].abs(), 1.0);
        }
    }

    #[test]
    fn every_catalog_mesh_encloses_the_catalog_volume() {
        for t in CATALOG {
            let mesh = flat_mesh(t).unwrap();
            let want = t.volume_mm3() * 1e-9;
            let got = volume_m3(&mesh);
            // f32 positions: about 6e-8 relative per coordinate.
            assert!(
                ((got - want) / want).abs() < 1e-6,
                "{}: {got} vs {want}",
                t.id
            );
        }
    }

    #[test]
    fn triangles_face_outward_along_their_normals() {
        for t in CATALOG {
            let mesh = flat_mesh(t).unwrap();
            let p = |i: u32| DVec3::from_array(mesh.positions_m[i as usize].map(f64::from));
            for tri in mesh.indices.chunks(3) {
                let n = (p(tri[1]) - p(tri[0])).cross(p(tri[2]) - p(tri[0]));
                let stored = DVec3::from_array(mesh.normals[tri[0] as usize].map(f64::from));
                assert!(n.normalize().dot(stored) > 0.999_999, "{}", t.id);
            }
        }
    }

    /// A triangular prism (a wedge-like, non-cuboid block): 5 faces, 2 triangles + 3 quads.
    const PRISM_VERTICES: [[f64; 3]; 6] = [
        [-5.0, -5.0, -5.0],
        [5.0, -5.0, -5.0],
        [-5.0, 5.0, -5.0],
        [-5.0, -5.0, 5.0],
        [5.0, -5.0, 5.0],
        [-5.0, 5.0, 5.0],
    ];
    const PRISM_FACES: &[&[u8]] = &[
        &[0, 2, 1],
        &[3, 4, 5],
        &[0, 1, 4, 3],
        &[0, 3, 5, 2],
        &[1, 2, 5, 4],
    ];
    const PRISM: BlockType = BlockType {
        id: "prism",
        name: "test prism",
        shape: Shape::ConvexPolyhedron(ConvexPolyhedron {
            vertices_mm: &PRISM_VERTICES,
            faces: PRISM_FACES,
        }),
    };
    const fn with_faces(faces: &'static [&'static [u8]]) -> BlockType {
        BlockType {
            shape: Shape::ConvexPolyhedron(ConvexPolyhedron {
                vertices_mm: &PRISM_VERTICES,
                faces,
            }),
            ..PRISM
        }
    }

    #[test]
    fn non_cuboid_prism_triangulates_by_fan() {
        let mesh = flat_mesh(&PRISM).unwrap();
        assert_eq!(mesh.indices.len() / 3, 1 + 1 + 2 + 2 + 2);
        assert_eq!(mesh.positions_m.len(), 3 + 3 + 4 + 4 + 4);
        let want = PRISM.volume_mm3() * 1e-9;
        assert!((want - 0.5e-6).abs() < 1e-15, "half of a 10 mm cube");
        assert!(((volume_m3(&mesh) - want) / want).abs() < 1e-6);
    }

    #[test]
    fn degenerate_faces_are_named() {
        const FACES: &[&[u8]] = &[&[0, 1], &[0, 1, 9]];
        let two = with_faces(&FACES[..1]);
        let msg = flat_mesh(&two).unwrap_err().to_string();
        assert!(msg.contains("prism") && msg.contains("face 0"), "{msg}");
        let out_of_range = with_faces(&FACES[1..]);
        let msg = flat_mesh(&out_of_range).unwrap_err().to_string();
        assert!(msg.contains("vertex index 9"), "{msg}");
        const FLAT: &[&[u8]] = &[&[0, 1, 1]];
        let flat = with_faces(FLAT);
        assert!(flat_mesh(&flat)
            .unwrap_err()
            .to_string()
            .contains("no area"));
    }
}
