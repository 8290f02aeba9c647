//! What rests on what (thesis Chapter VII: every block rests on the floor or on other blocks,
//! "contacted at least by one surface"): the contacts under each block, the region they span,
//! and where its centre of mass lies over it. Plain geometry on the intended poses; the
//! simulation ([`super::settle`]) decides whether a block moves, this tells why.

use crate::geom::{convex_hull, ConvexRegion, DVec2, DVec3};
use crate::scene::Block;

/// Faces closer than this in height touch, and horizontal overlaps thinner than this do not
/// count as contact, mm; the recognizer's and the scene checker's half millimetre.
pub const CONTACT_TOL_MM: f64 = 0.5;

/// One thing a block rests on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Support {
    /// The floor (y = 0).
    Floor,
    /// Another block, by index.
    Block(usize),
}

/// The contacts under every block of `blocks`, in block order; each list sorted, the floor
/// first. A block rests on another when the other's top face is within [`CONTACT_TOL_MM`] of
/// its bottom face and the two faces overlap by more than that in both horizontal directions.
pub fn supports_of(blocks: &[Block]) -> Vec<Vec<Support>> {
    let faces: Vec<Faces> = blocks.iter().map(Faces::of).collect();
    (0..blocks.len())
        .map(|i| {
            let mut under = Vec::new();
            if faces[i].bottom_y_mm <= CONTACT_TOL_MM {
                under.push(Support::Floor);
            }
            for (j, fj) in faces.iter().enumerate() {
                if j != i && contact_polygon(&faces[i], fj).is_some() {
                    under.push(Support::Block(j));
                }
            }
            under
        })
        .collect()
}

/// How far the centre of mass of block `i` lies outside the region its contacts span
/// (horizontal distance, mm; 0 inside), or `None` when nothing holds it up. The region is the
/// convex hull of its bottom face where it meets the floor and of the overlaps of its bottom
/// face with the top faces of the blocks under it.
pub fn centre_of_mass_overhang_mm(blocks: &[Block], i: usize) -> Option<f64> {
    let faces: Vec<Faces> = blocks.iter().map(Faces::of).collect();
    let mut points: Vec<DVec2> = Vec::new();
    if faces[i].bottom_y_mm <= CONTACT_TOL_MM {
        points.extend(&faces[i].bottom);
    }
    for (j, fj) in faces.iter().enumerate() {
        if j != i {
            points.extend(contact_polygon(&faces[i], fj).unwrap_or_default());
        }
    }
    if points.is_empty() {
        return None;
    }
    let hull = convex_hull(&points);
    let c = centre_of_mass_mm(&blocks[i]);
    let c = DVec2::new(c.x, c.z);
    if hull.len() >= 3 && ConvexRegion::new(&hull).contains(c, 1e-9) {
        return Some(0.0);
    }
    Some(distance_to_polygon(&hull, c))
}

/// A block's centre of mass in world mm: the centre of its box for a cuboid or a round part,
/// the mean of its vertices otherwise (the wedge; within a millimetre of the solid's centroid).
pub fn centre_of_mass_mm(b: &Block) -> DVec3 {
    if b.block_type.cuboid_half_extents_mm().is_some() || b.block_type.round().is_some() {
        return b.center_mm;
    }
    let v = b.world_vertices();
    v.iter().copied().sum::<DVec3>() / v.len() as f64
}

/// A block's bottom and top faces projected on the floor (x, z), with their heights.
struct Faces {
    bottom_y_mm: f64,
    top_y_mm: f64,
    bottom: Vec<DVec2>,
    top: Vec<DVec2>,
}

impl Faces {
    fn of(b: &Block) -> Faces {
        let v = b.world_vertices();
        let lo = v.iter().map(|p| p.y).fold(f64::INFINITY, f64::min);
        let hi = v.iter().map(|p| p.y).fold(f64::NEG_INFINITY, f64::max);
        let at = |y: f64| {
            let pts: Vec<DVec2> = v
                .iter()
                .filter(|p| (p.y - y).abs() <= CONTACT_TOL_MM)
                .map(|p| DVec2::new(p.x, p.z))
                .collect();
            convex_hull(&pts)
        };
        Faces {
            bottom_y_mm: lo,
            top_y_mm: hi,
            bottom: at(lo),
            top: at(hi),
        }
    }
}

/// Where the bottom face of `upper` rests on the top face of `lower`: their overlap when the
/// heights meet and it is wider than [`CONTACT_TOL_MM`] in both directions.
fn contact_polygon(upper: &Faces, lower: &Faces) -> Option<Vec<DVec2>> {
    if (lower.top_y_mm - upper.bottom_y_mm).abs() > CONTACT_TOL_MM {
        return None;
    }
    let overlap = clip_convex(&upper.bottom, &lower.top);
    let (lo, hi) = crate::geom::bounds2(overlap.iter().copied())?;
    let size = hi - lo;
    (size.x > CONTACT_TOL_MM && size.y > CONTACT_TOL_MM).then_some(overlap)
}

/// The intersection of two counter-clockwise convex polygons: the convex hull of the corners
/// of each inside the other and of the crossings of their edges.
fn clip_convex(a: &[DVec2], b: &[DVec2]) -> Vec<DVec2> {
    if a.len() < 3 || b.len() < 3 {
        return Vec::new();
    }
    let (ra, rb) = (ConvexRegion::new(a), ConvexRegion::new(b));
    let mut points: Vec<DVec2> = a
        .iter()
        .copied()
        .filter(|&p| rb.contains(p, 1e-9))
        .collect();
    points.extend(b.iter().copied().filter(|&p| ra.contains(p, 1e-9)));
    let edges = |poly: &[DVec2]| {
        let n = poly.len();
        (0..n)
            .map(move |k| (poly[k], poly[(k + 1) % n]))
            .collect::<Vec<_>>()
    };
    for (p, q) in edges(a) {
        for (r, s) in edges(b) {
            let d = (q - p).perp_dot(s - r);
            if d.abs() < 1e-12 {
                continue;
            }
            let t = (r - p).perp_dot(s - r) / d;
            let u = (r - p).perp_dot(q - p) / d;
            if (0.0..=1.0).contains(&t) && (0.0..=1.0).contains(&u) {
                points.push(p + (q - p) * t);
            }
        }
    }
    convex_hull(&points)
}

/// Distance from `p` to the nearest point of the polygon `hull` (its edges, or its points when
/// it has fewer than two).
fn distance_to_polygon(hull: &[DVec2], p: DVec2) -> f64 {
    let n = hull.len();
    if n == 1 {
        return hull[0].distance(p);
    }
    (0..n)
        .map(|k| {
            let (a, b) = (hull[k], hull[(k + 1) % n]);
            let t = ((p - a).dot(b - a) / (b - a).length_squared()).clamp(0.0, 1.0);
            (a + (b - a) * t).distance(p)
        })
        .fold(f64::INFINITY, f64::min)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn supports_are_the_floor_and_the_faces_underneath() {
        let blocks = [
            Block::new("b30", DVec3::new(0.0, 7.5, 0.0), 0.0),
            Block::new("b15", DVec3::new(7.5, 22.5, 0.0), 0.0),
            Block::new("b15", DVec3::new(40.0, 22.5, 0.0), 0.0),
        ];
        let s = supports_of(&blocks);
        assert_eq!(s[0], vec![Support::Floor]);
        assert_eq!(s[1], vec![Support::Block(0)]);
        assert!(s[2].is_empty());
        assert_eq!(centre_of_mass_overhang_mm(&blocks, 1), Some(0.0));
        assert_eq!(centre_of_mass_overhang_mm(&blocks, 2), None);
    }

    #[test]
    fn the_overhang_is_the_distance_beyond_the_contact() {
        // A cube over the end of a b30 (x from -15 to 15), its centre at x = 17.5.
        let blocks = [
            Block::new("b30", DVec3::new(0.0, 7.5, 0.0), 0.0),
            Block::new("b15", DVec3::new(17.5, 22.5, 0.0), 0.0),
        ];
        let d = centre_of_mass_overhang_mm(&blocks, 1).unwrap();
        assert!((d - 2.5).abs() < 1e-9, "{d}");
    }
}
