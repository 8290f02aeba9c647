//! Convex polytopes in world millimetres and the exact volume of their intersection through
//! parry3d's convex hull (the route measured in docs/architecture.md "Dependencies": within 5e-7 relative of an f64 clipper; `intersect_meshes` is wrong
//! whenever faces are coplanar, which is the normal case for blocks, so it is not used).
//!
//! The intersection of two convex polytopes A and B is convex, and each of its vertices lies on
//! an edge of A inside B or on an edge of B inside A (a vertex lies on three face planes; two of
//! them belong to the same polytope and meet on one of its edges). So clipping every edge of
//! each polytope to the other and taking the convex hull of the clipped end points gives the
//! intersection exactly; `trimesh_signed_volume_and_center_of_mass` gives its volume. The hull
//! is again a [`ConvexPolytope`] (triangles as faces), so k-fold intersections chain.

use super::{ScoreError, VolumeTolerances};
use crate::geom::{bounds3, DVec3};
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
        let planes = (0..block.block_type.faces().len())
            .map(|f| {
                let n = block.world_face_normal(f);
                let p0 = vertices[block.block_type.faces()[f][0] as usize];
                (n, n.dot(p0))
            })
            .collect();
        ConvexPolytope::new(vertices, edges, planes)
    }

    fn new(vertices: Vec<DVec3>, edges: Vec<[usize; 2]>, planes: Vec<(DVec3, f64)>) -> Self {
        let (lo, hi) = bounds3(vertices.iter().copied())
            .unwrap_or((DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)));
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
    ///
    /// The volume comes from parry3d's hull of the candidate points. parry's quickhull (f32) can
    /// return a non-convex triangulation for slivers with nearly coincident points (seen on 1 in
    /// 2000 random pose pairs: 7.66 instead of 8.85 mm³, see `src/score/tests.rs`), so the hull
    /// is checked for convexity in f64 and, when it fails, the volume is taken from the
    /// intersection's own faces instead (divergence theorem over the face planes of both
    /// polytopes, each face polygon made of the candidate points lying on it).
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
        let planes = merged_planes(&self.planes, &other.planes, tol.plane_mm);
        let volume_mm3 = match parry_hull_volume_mm3(&points)? {
            Some(v) => v,
            None => face_volume_mm3(&points, &planes, tol.plane_mm),
        };
        if volume_mm3 <= tol.min_volume_mm3 {
            return Ok(None);
        }
        let edges = shared_edges(&points, &planes, tol.plane_mm);
        Ok(Some((
            ConvexPolytope::new(points, edges, planes),
            volume_mm3,
        )))
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

/// Both plane sets, a plane coinciding with an earlier one (same direction and offset) once.
fn merged_planes(a: &[(DVec3, f64)], b: &[(DVec3, f64)], tol_mm: f64) -> Vec<(DVec3, f64)> {
    let mut out: Vec<(DVec3, f64)> = a.to_vec();
    for &(n, d) in b {
        if !out
            .iter()
            .any(|&(m, e)| m.dot(n) > 1.0 - 1e-12 && (e - d).abs() <= tol_mm)
        {
            out.push((n, d));
        }
    }
    out
}

/// Indices of the points lying on plane `(n, d)`.
fn on_plane(points: &[DVec3], (n, d): (DVec3, f64), tol_mm: f64) -> Vec<usize> {
    (0..points.len())
        .filter(|&i| (n.dot(points[i]) - d).abs() <= tol_mm)
        .collect()
}

/// Pairs of points that share two non-parallel planes: they lie on one edge of the polytope.
fn shared_edges(points: &[DVec3], planes: &[(DVec3, f64)], tol_mm: f64) -> Vec<[usize; 2]> {
    let tight: Vec<Vec<usize>> = points
        .iter()
        .map(|p| {
            (0..planes.len())
                .filter(|&k| (planes[k].0.dot(*p) - planes[k].1).abs() <= tol_mm)
                .collect()
        })
        .collect();
    let mut edges = Vec::new();
    for i in 0..points.len() {
        for j in i + 1..points.len() {
            let common: Vec<usize> = tight[i]
                .iter()
                .copied()
                .filter(|k| tight[j].contains(k))
                .collect();
            let two_planes = common.iter().enumerate().any(|(x, &k)| {
                common[x + 1..]
                    .iter()
                    .any(|&m| planes[k].0.cross(planes[m].0).length() > 1e-9)
            });
            if two_planes {
                edges.push([i, j]);
            }
        }
    }
    edges
}

/// Volume of the convex polytope with vertices `points` and face planes among `planes`, in f64:
/// V = 1/3 Σ d · area over the faces (the divergence theorem), each face the points on its plane
/// ordered by angle about their centroid.
fn face_volume_mm3(points: &[DVec3], planes: &[(DVec3, f64)], tol_mm: f64) -> f64 {
    let mut volume = 0.0;
    for &(n, d) in planes {
        let idx = on_plane(points, (n, d), tol_mm);
        if idx.len() < 3 {
            continue;
        }
        let c = idx.iter().map(|&i| points[i]).sum::<DVec3>() / idx.len() as f64;
        let u = n.any_orthonormal_vector();
        let w = n.cross(u);
        let mut ring: Vec<DVec3> = idx.iter().map(|&i| points[i]).collect();
        ring.sort_by(|a, b| {
            let (pa, pb) = (*a - c, *b - c);
            pa.dot(w)
                .atan2(pa.dot(u))
                .total_cmp(&pb.dot(w).atan2(pb.dot(u)))
        });
        let area: f64 = (0..ring.len())
            .map(|k| (ring[k] - c).cross(ring[(k + 1) % ring.len()] - c).dot(n) / 2.0)
            .sum();
        volume += d * area / 3.0;
    }
    volume.max(0.0)
}

/// The volume of the convex hull of `points` through parry3d (hull in f32 around the points'
/// mean, so that rounding is relative to the overlap's size, then
/// `trimesh_signed_volume_and_center_of_mass`), or `None` when parry gives no hull or a hull that
/// is not convex (a point more than [`HULL_CHECK_MM`] outside a triangle's plane).
fn parry_hull_volume_mm3(points: &[DVec3]) -> Result<Option<f64>, ScoreError> {
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
        // Too few or (almost) coplanar points: let the face volume decide.
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
    let outward = if signed >= 0.0 { 1.0 } else { -1.0 };
    let hull: Vec<DVec3> = hull_vertices
        .iter()
        .map(|v| DVec3::new(v.x.into(), v.y.into(), v.z.into()))
        .collect();
    let relative: Vec<DVec3> = points.iter().map(|p| *p - origin).collect();
    let convex = triangles.iter().all(|t| {
        let [a, b, c] = t.map(|i| hull[i as usize]);
        let n = (b - a).cross(c - a) * outward;
        let len = n.length();
        // Slivers' normals are dominated by f32 rounding; their volume share is tiny anyway.
        len < 2.0 * SLIVER_AREA_MM2
            || relative
                .iter()
                .all(|q| n.dot(*q - a) / len <= HULL_CHECK_MM)
    });
    Ok(convex.then_some(f64::from(signed.abs())))
}

/// A point this far (mm) outside a parry hull triangle's plane makes the hull invalid; f32
/// rounding of coordinates up to ~50 mm is ~4e-6 mm, and the invalid hulls seen are off by
/// 0.3 mm and more.
const HULL_CHECK_MM: f64 = 1e-3;
/// Hull triangles below this area (mm²) are not checked (their normals are rounding noise).
const SLIVER_AREA_MM2: f64 = 0.05;

/// Whether parry's hull of `a ∩ b`'s candidate points passes the convexity check (for the
/// measurements in `src/score/tests.rs`); `None` when there is no overlap to hull.
#[cfg(test)]
pub(crate) fn parry_hull_accepted(a: &ConvexPolytope, b: &ConvexPolytope) -> Option<bool> {
    let tol = VolumeTolerances::default();
    let mut points = Vec::new();
    a.clipped_edge_points(b, tol.plane_mm, &mut points);
    b.clipped_edge_points(a, tol.plane_mm, &mut points);
    dedup_points(&mut points, tol.plane_mm);
    (points.len() >= 4).then(|| parry_hull_volume_mm3(&points).ok().flatten().is_some())
}

/// `a ∩ b`'s volume by the f64 face route alone (the fallback), for the cross-checks in
/// `src/score/tests.rs`.
#[cfg(test)]
pub(crate) fn face_route_volume_mm3(a: &ConvexPolytope, b: &ConvexPolytope) -> f64 {
    let tol = VolumeTolerances::default();
    let mut points = Vec::new();
    a.clipped_edge_points(b, tol.plane_mm, &mut points);
    b.clipped_edge_points(a, tol.plane_mm, &mut points);
    dedup_points(&mut points, tol.plane_mm);
    face_volume_mm3(
        &points,
        &merged_planes(&a.planes, &b.planes, tol.plane_mm),
        tol.plane_mm,
    )
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
