//! The render polyhedron of one block (faces pulled in by half a crack, edges and corners
//! cut by the bevel) and the touching faces between blocks, with the flat-polygon helpers
//! the render mesh is built from.

use super::reach::grow_box;
use super::PhotoVertex;
use crate::geom::DVec3;
use crate::scene::{Block, Scene};
use glam::DMat3;

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
pub(super) fn pull_faces_in(
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
pub(super) const CONTACT_MM: f64 = 2.0 * crate::geom::CONTACT_TOL_MM;

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
pub(super) fn clip_convex(subject: &[DVec3], clip: &[DVec3], clip_normal: DVec3) -> Vec<DVec3> {
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
pub(super) fn polygon_area(corners: &[DVec3]) -> f64 {
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
pub(super) fn inset_polygon(corners: &[DVec3], normal: DVec3, inset_mm: f64) -> Vec<DVec3> {
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
pub(super) fn sort_around(mut points: Vec<DVec3>, outward: DVec3) -> Vec<DVec3> {
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
pub(super) fn push_polygon(
    out: &mut Vec<PhotoVertex>,
    corners: &[DVec3],
    outward: DVec3,
    albedo: f64,
) {
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
