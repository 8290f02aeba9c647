//! Penetration depth of two convex blocks by the separating-axis theorem: the candidate axes
//! are both blocks' face normals and the cross products of their edge directions.

use super::Block;
use crate::geom::DVec3;

/// The smallest overlap of the two blocks' projections over all separating-axis candidates,
/// in mm; zero or negative when they are separated or only touch.
pub fn penetration_depth_mm(a: &Block, b: &Block) -> f64 {
    let (va, vb) = (a.world_vertices(), b.world_vertices());
    let axes = candidate_axes(a, &va)
        .chain(candidate_axes(b, &vb))
        .collect::<Vec<_>>();
    let mut depth = f64::INFINITY;
    let mut test = |axis: DVec3| {
        let len = axis.length();
        if len < 1e-9 {
            return;
        }
        let axis = axis / len;
        let (lo_a, hi_a) = project(&va, axis);
        let (lo_b, hi_b) = project(&vb, axis);
        depth = depth.min(hi_a.min(hi_b) - lo_a.max(lo_b));
    };
    for &n in &axes {
        test(n);
    }
    let (ea, eb) = (edge_dirs(a, &va), edge_dirs(b, &vb));
    for &da in &ea {
        for &db in &eb {
            test(da.cross(db));
        }
    }
    depth
}

fn candidate_axes<'a>(b: &'a Block, _v: &[DVec3]) -> impl Iterator<Item = DVec3> + 'a {
    (0..b.block_type.faces().len()).map(move |f| b.world_face_normal(f))
}

fn edge_dirs(b: &Block, v: &[DVec3]) -> Vec<DVec3> {
    b.block_type
        .edges()
        .iter()
        .map(|&(i, j, _, _)| (v[j] - v[i]).normalize())
        .collect()
}

fn project(v: &[DVec3], axis: DVec3) -> (f64, f64) {
    v.iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
            let d = p.dot(axis);
            (lo.min(d), hi.max(d))
        })
}
