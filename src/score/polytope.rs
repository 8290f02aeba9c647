//! Convex polytopes in world millimetres and the exact volume of their intersection through
//! parry3d's convex hull (the route measured in `shared/notes/dependencies.md`, "parry3d 0.31.1:
//! exact overlap volume": within 5e-7 relative of an f64 clipper; `intersect_meshes` is wrong
//! whenever faces are coplanar, which is the normal case for blocks, so it is not used).
//!
//! The intersection of two convex polytopes A and B is convex, and each of its vertices lies on
//! an edge of A inside B or on an edge of B inside A (a vertex lies on three face planes; two of
//! them belong to the same polytope and meet on one of its edges). So clipping every edge of
//! each polytope to the other and taking the convex hull of the clipped end points gives the
//! intersection exactly; `trimesh_signed_volume_and_center_of_mass` gives its volume. The hull
//! is again a [`ConvexPolytope`] (triangles as faces), so k-fold intersections chain.

use super::{ScoreError, VolumeTolerances};
use crate::geom::DVec3;
use crate::scene::Block;
use parry3d::math::Vector as PVec;

/// A convex polytope: vertices, edges and outward face planes in world mm.
#[derive(Debug, Clone)]
pub(crate) struct ConvexPolytope {
    vertices: Vec<DVec3>,
    edges: Vec<[usize; 2]>,
    /// `(n, d)`: outward unit normal and offset; inside when `n . p <= d`.
    planes: Vec<(DVec3, f64)>,
    lo: DVec3,
    hi: DVec3,
}

impl ConvexPolytope {
    /// The block's catalog polyhedron placed in the world.
    pub(crate) fn from_block(block: &Block) -> ConvexPolytope {
        let vertices = block.world_vertices();
        let edges = block
            .block_type
            .edges()
            .iter()
            .map(|&(a, b, _, _)| [a, b])
            .collect();
        let planes = (0..block.block_type.faces.len())
            .map(|f| {
                let n = block.world_face_normal(f);
                let p0 = vertices[block.block_type.faces[f][0] as usize];
                (n, n.dot(p0))
            })
            .collect();
        ConvexPolytope::new(vertices, edges, planes)
    }

    fn new(vertices: Vec<DVec3>, edges: Vec<[usize; 2]>, planes: Vec<(DVec3, f64)>) -> Self {
        let (lo, hi) = vertices.iter().fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), v| (lo.min(*v), hi.max(*v)),
        );
        ConvexPolytope {
            vertices,
            edges,
            planes,
            lo,
            hi,
        }
    }

    /// The segment `a..b` clipped to this polytope (Cyrus–Beck), or `None` when it misses.
    /// A point within `plane_mm` outside a face counts as on it.
    fn clip_segment(&self, a: DVec3, b: DVec3, plane_mm: f64) -> Option<(DVec3, DVec3)> {
        let (mut t0, mut t1) = (0.0f64, 1.0f64);
        for &(n, d) in &self.planes {
            let (da, db) = (n.dot(a) - d, n.dot(b) - d);
            match (da > plane_mm, db > plane_mm) {
                (true, true) => return None,
                (false, false) => {}
                (true, false) => t0 = t0.max(da / (da - db)),
                (false, true) => t1 = t1.min(da / (da - db)),
            }
            if t0 > t1 {
                return None;
            }
        }
        Some((a + (b - a) * t0, a + (b - a) * t1))
    }

    /// End points of this polytope's edges clipped to `other`, appended to `out`.
    fn clipped_edge_points(&self, other: &ConvexPolytope, plane_mm: f64, out: &mut Vec<DVec3>) {
        for &[i, j] in &self.edges {
            if let Some((p, q)) = other.clip_segment(self.vertices[i], self.vertices[j], plane_mm) {
                out.push(p);
                out.push(q);
            }
        }
    }

    fn bounds_overlap(&self, other: &ConvexPolytope, plane_mm: f64) -> bool {
        (0..3).all(|k| self.lo[k] <= other.hi[k] + plane_mm && other.lo[k] <= self.hi[k] + plane_mm)
    }

    /// `self ∩ other` and its volume in mm³, or `None` when the volume is at most
    /// `tol.min_volume_mm3` (disjoint or only touching).
    pub(crate) fn intersect(
        &self,
        other: &ConvexPolytope,
        tol: &VolumeTolerances,
    ) -> Result<Option<(ConvexPolytope, f64)>, ScoreError> {
        if !self.bounds_overlap(other, tol.plane_mm) {
            return Ok(None);
        }
        let mut points = Vec::new();
        self.clipped_edge_points(other, tol.plane_mm, &mut points);
        other.clipped_edge_points(self, tol.plane_mm, &mut points);
        dedup_points(&mut points, tol.plane_mm);
        if points.len() < 4 {
            return Ok(None);
        }
        hull_with_volume(&points, tol)
    }
}

/// Removes points closer than `tol_mm` (max norm) to an earlier one.
fn dedup_points(points: &mut Vec<DVec3>, tol_mm: f64) {
    let mut kept: Vec<DVec3> = Vec::with_capacity(points.len());
    for &p in points.iter() {
        if !kept.iter().any(|q| (*q - p).abs().max_element() <= tol_mm) {
            kept.push(p);
        }
    }
    *points = kept;
}

/// The convex hull of `points` (parry3d, in f32 around the points' mean so that rounding is
/// relative to the overlap's size, not its distance from the origin) as a polytope, and its
/// volume from parry's signed trimesh volume, clamped at zero.
fn hull_with_volume(
    points: &[DVec3],
    tol: &VolumeTolerances,
) -> Result<Option<(ConvexPolytope, f64)>, ScoreError> {
    use parry3d::transformation::{try_convex_hull, ConvexHullError};
    let origin = points.iter().copied().sum::<DVec3>() / points.len() as f64;
    let local: Vec<PVec> = points
        .iter()
        .map(|p| {
            let q = *p - origin;
            PVec::new(q.x as f32, q.y as f32, q.z as f32)
        })
        .collect();
    let (hull_vertices, triangles) = match try_convex_hull(&local) {
        Ok(hull) => hull,
        // Too few or (almost) coplanar points: a flat contact, no volume.
        Err(ConvexHullError::IncompleteInput | ConvexHullError::MissingSupportPoint) => {
            return Ok(None)
        }
        Err(e) => return Err(ScoreError::Hull(e.to_string())),
    };
    if triangles.is_empty() {
        return Ok(None);
    }
    let (signed, _) = parry3d::mass_properties::details::trimesh_signed_volume_and_center_of_mass(
        &hull_vertices,
        &triangles,
    );
    let volume_mm3 = f64::from(signed.abs());
    if volume_mm3 <= tol.min_volume_mm3 {
        return Ok(None);
    }
    let vertices: Vec<DVec3> = hull_vertices
        .iter()
        .map(|v| origin + DVec3::new(v.x.into(), v.y.into(), v.z.into()))
        .collect();
    let outward = if signed >= 0.0 { 1.0 } else { -1.0 };
    Ok(Some((
        polytope_from_triangles(vertices, &triangles, outward),
        volume_mm3,
    )))
}

/// A polytope whose faces are the hull's triangles; `outward` is -1 when the triangles wind
/// inward. Coplanar neighbour triangles give repeated planes and edges inside faces; both are
/// harmless to clipping (an edge inside a face only adds points of the intersection).
fn polytope_from_triangles(
    vertices: Vec<DVec3>,
    triangles: &[[u32; 3]],
    outward: f64,
) -> ConvexPolytope {
    let mut edges: Vec<[usize; 2]> = Vec::new();
    let mut planes = Vec::new();
    for t in triangles {
        let [a, b, c] = t.map(|i| i as usize);
        for (i, j) in [(a, b), (b, c), (c, a)] {
            let e = [i.min(j), i.max(j)];
            if !edges.contains(&e) {
                edges.push(e);
            }
        }
        let n = (vertices[b] - vertices[a]).cross(vertices[c] - vertices[a]) * outward;
        let len = n.length();
        if len > 1e-12 {
            let n = n / len;
            planes.push((n, n.dot(vertices[a])));
        }
    }
    ConvexPolytope::new(vertices, edges, planes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_cube_overlaps_by_hand() {
        let tol = VolumeTolerances::default();
        let a = ConvexPolytope::from_block(&Block::new("b15", DVec3::new(0.0, 7.5, 0.0), 0.0));
        let b = ConvexPolytope::from_block(&Block::new("b15", DVec3::new(7.5, 7.5, 0.0), 0.0));
        let (_, v) = a.intersect(&b, &tol).unwrap().unwrap();
        assert!((v - 7.5 * 15.0 * 15.0).abs() < 1e-3, "{v}");
        let c = ConvexPolytope::from_block(&Block::new("b15", DVec3::new(15.0, 7.5, 0.0), 0.0));
        assert!(
            a.intersect(&c, &tol).unwrap().is_none(),
            "touching has no volume"
        );
        let d = ConvexPolytope::from_block(&Block::new("b15", DVec3::new(40.0, 7.5, 0.0), 0.0));
        assert!(a.intersect(&d, &tol).unwrap().is_none());
    }

    #[test]
    fn triple_intersection_chains() {
        // Three unit-shifted cubes: a ∩ b ∩ c is a 7.5 x 7.5 x 15 prism.
        let tol = VolumeTolerances::default();
        let p = |x: f64, z: f64| {
            ConvexPolytope::from_block(&Block::new("b15", DVec3::new(x, 7.5, z), 0.0))
        };
        let (ab, _) = p(0.0, 0.0).intersect(&p(7.5, 0.0), &tol).unwrap().unwrap();
        let (_, v) = ab.intersect(&p(0.0, 7.5), &tol).unwrap().unwrap();
        assert!((v - 7.5 * 7.5 * 15.0).abs() < 1e-3, "{v}");
    }
}
