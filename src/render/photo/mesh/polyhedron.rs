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

/// The cross-section of the render mesh along a block edge: how far the faces are cut back
/// from the edge and in how many flat strips the cut is drawn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EdgeProfile {
    /// How far each face is inset from the edge within its plane, mm: the chamfer's width, or
    /// the rounded edge's radius.
    pub radius_mm: f64,
    /// Strips across the edge: 1 is a flat chamfer; more follow a rounded profile (a quadratic
    /// Bezier arc from one face's inset to the other's, tangent to both faces, through the
    /// sharp edge as its control point).
    pub segments: usize,
}

impl EdgeProfile {
    /// Strips of a rounded edge: at 0.5 mm, the largest radius of the varied look, each is
    /// under 0.2 mm wide, well below a pixel at every picture size.
    pub const ROUND_SEGMENTS: usize = 4;

    /// A flat chamfer `width_mm` wide.
    pub fn chamfer(width_mm: f64) -> EdgeProfile {
        EdgeProfile {
            radius_mm: width_mm,
            segments: 1,
        }
    }

    /// A rounded edge of radius `radius_mm`.
    pub fn rounded(radius_mm: f64) -> EdgeProfile {
        EdgeProfile {
            radius_mm,
            segments: Self::ROUND_SEGMENTS,
        }
    }
}

/// The render polyhedron of `block` with chamfered edges ([`profiled_block`] with
/// [`EdgeProfile::chamfer`]`(bevel_mm)`).
pub fn bevelled_block(block: &Block, bevel_mm: f64, retract_mm: &[f64]) -> Vec<MeshPolygon> {
    profiled_block(block, &EdgeProfile::chamfer(bevel_mm), retract_mm)
}

/// The render polyhedron of `block`: each catalog face `f` moved inward by `retract_mm[f]` and
/// inset by the profile's radius within its plane, first, one polygon per catalog face; then
/// the strips of the edge profile along every edge, joining the two insets; then a corner
/// polygon at every vertex joining the insets of the faces and the strips' ends that meet
/// there.
pub fn profiled_block(
    block: &Block,
    profile: &EdgeProfile,
    retract_mm: &[f64],
) -> Vec<MeshPolygon> {
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
            inset_polygon(&corners, *n, profile.radius_mm)
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
    let solid = InsetSolid {
        faces,
        normals: &normals,
        shrunk: &shrunk,
        inset: &inset,
    };
    let mut ends: Vec<(u8, DVec3)> = Vec::new();
    solid.push_edge_strips(profile.segments.max(1), &mut out, &mut ends);
    for v in 0..block.block_type.vertices_mm().len() as u8 {
        let around: Vec<usize> = (0..faces.len())
            .filter(|&f| faces[f].contains(&v))
            .collect();
        let outward: DVec3 = around.iter().map(|&f| normals[f]).sum();
        let mut points: Vec<DVec3> = around
            .iter()
            .filter_map(|&f| solid.corner_of(f, v))
            .collect();
        points.extend(ends.iter().filter(|(w, _)| *w == v).map(|(_, p)| *p));
        if points.len() >= 3 {
            out.push(MeshPolygon {
                corners: sort_around(points, outward),
                outward,
            });
        }
    }
    out
}

/// A block's faces pulled in and inset, as [`profiled_block`] builds its edge strips from.
struct InsetSolid<'a> {
    faces: &'a [&'a [u8]],
    normals: &'a [DVec3],
    shrunk: &'a [DVec3],
    inset: &'a [Vec<DVec3>],
}

impl InsetSolid<'_> {
    /// Face `f`'s inset corner at vertex `v`, if `v` is on `f`.
    fn corner_of(&self, f: usize, v: u8) -> Option<DVec3> {
        let k = self.faces[f].iter().position(|&x| x == v)?;
        Some(self.inset[f][k])
    }

    /// The face where edge `a -> b` of face `f` runs `b -> a`.
    fn other_face(&self, f: usize, a: u8, b: u8) -> Option<usize> {
        let faces = self.faces;
        (0..faces.len()).find(|&g| {
            g != f
                && (0..faces[g].len())
                    .any(|j| faces[g][j] == b && faces[g][(j + 1) % faces[g].len()] == a)
        })
    }

    /// The profile's points across the edge at vertex `v` of `edge_dir`'s edge, from face
    /// `f`'s inset corner `p_f` to face `g`'s `p_g`: a quadratic Bezier whose control point is
    /// the sharp edge's point in that cross-section.
    fn profile_at(
        &self,
        v: u8,
        edge_dir: DVec3,
        p_f: DVec3,
        p_g: DVec3,
        segments: usize,
    ) -> Vec<DVec3> {
        let at = self.shrunk[v as usize];
        let along = ((p_f - at).dot(edge_dir) + (p_g - at).dot(edge_dir)) / 2.0;
        let sharp = at + edge_dir * along;
        (0..=segments)
            .map(|j| {
                let t = j as f64 / segments as f64;
                p_f * (1.0 - t) * (1.0 - t) + sharp * 2.0 * t * (1.0 - t) + p_g * t * t
            })
            .collect()
    }

    /// Pushes the strips along every edge (each edge once: from the face where it runs
    /// `a -> b` to the one where it runs `b -> a`) into `out`, and the strips' inner end
    /// points at each vertex into `ends`, for the corner polygons.
    fn push_edge_strips(
        &self,
        segments: usize,
        out: &mut Vec<MeshPolygon>,
        ends: &mut Vec<(u8, DVec3)>,
    ) {
        for (f, face) in self.faces.iter().enumerate() {
            for k in 0..face.len() {
                let (a, b) = (face[k], face[(k + 1) % face.len()]);
                let Some(g) = self.other_face(f, a, b).filter(|&g| g > f) else {
                    continue;
                };
                let (nf, ng) = (self.normals[f], self.normals[g]);
                let (Some(fa), Some(fb), Some(gb), Some(ga)) = (
                    self.corner_of(f, a),
                    self.corner_of(f, b),
                    self.corner_of(g, b),
                    self.corner_of(g, a),
                ) else {
                    continue;
                };
                if segments == 1 {
                    out.push(MeshPolygon {
                        corners: vec![fa, ga, gb, fb],
                        outward: nf + ng,
                    });
                    continue;
                }
                let dir = (self.shrunk[b as usize] - self.shrunk[a as usize]).normalize_or_zero();
                let at_a = self.profile_at(a, dir, fa, ga, segments);
                let at_b = self.profile_at(b, dir, fb, gb, segments);
                for j in 0..segments {
                    let t = (j as f64 + 0.5) / segments as f64;
                    out.push(MeshPolygon {
                        corners: vec![at_a[j], at_a[j + 1], at_b[j + 1], at_b[j]],
                        outward: nf * (1.0 - t) + ng * t,
                    });
                }
                ends.extend(at_a[1..segments].iter().map(|p| (a, *p)));
                ends.extend(at_b[1..segments].iter().map(|p| (b, *p)));
            }
        }
    }
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
/// exact drawing's seam tolerance (`linedraw::TruthTolerances::seam_mm`).
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
