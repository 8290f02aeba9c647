//! Picture and block geometry that the checks of several test files share.

use blockworld::geom::DVec2;
use blockworld::scene::Block;

/// Distance (px) from `p` to the segment `a`–`b` in the picture: to the foot of the
/// perpendicular when it falls on the segment, else to the nearer end (to `a` when the segment
/// has no length).
pub fn distance_to_segment(p: DVec2, a: DVec2, b: DVec2) -> f64 {
    let ab = b - a;
    let len2 = ab.length_squared();
    let t = if len2 == 0.0 {
        0.0
    } else {
        ((p - a).dot(ab) / len2).clamp(0.0, 1.0)
    };
    p.distance(a + ab * t)
}

/// `true` when `got` holds the blocks of `truth`: as many blocks, and for each of `truth` one of
/// `got` of the same type with every corner within `tol_mm` of one of its corners (the same
/// solid whatever symmetry its turn has; a wedge has none, so its facing counts).
pub fn same_blocks(got: &[Block], truth: &[Block], tol_mm: f64) -> bool {
    got.len() == truth.len()
        && truth.iter().all(|t| {
            let corners = t.world_vertices();
            got.iter().any(|b| {
                let mine = b.world_vertices();
                b.block_type.id == t.block_type.id
                    && corners
                        .iter()
                        .all(|p| mine.iter().any(|q| q.distance(*p) < tol_mm))
            })
        })
}
