//! The grasp of a parallel two-finger gripper that comes straight down onto a block (thesis
//! Chapter VII, off-line robot programming; docs/plan.md "Grasp model"): the two parallel
//! vertical faces it closes on, the centre, the approach, and the neighbours in its way.

use crate::geom::DVec3;
use crate::scene::Block;

/// The gripper assumed: two flat fingers, each a box, closing along a horizontal axis. Every
/// field gives its unit and default.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Gripper {
    /// Finger width along the face it presses on, horizontal, mm; default 10.
    pub finger_width_mm: f64,
    /// Finger thickness, outward from the face, mm; default 4. A neighbour closer to the face
    /// than this leaves no room for the finger.
    pub finger_thickness_mm: f64,
    /// How far the fingers reach down the faces from the block's top, mm; default 10 (two
    /// thirds of a 15 mm block), at most the block's height.
    pub finger_depth_mm: f64,
    /// Widest opening between the fingers, mm; default 40 (every catalog block fits across
    /// at least one pair of its faces).
    pub max_opening_mm: f64,
}

impl Default for Gripper {
    fn default() -> Self {
        Gripper {
            finger_width_mm: 10.0,
            finger_thickness_mm: 4.0,
            finger_depth_mm: 10.0,
            max_opening_mm: 40.0,
        }
    }
}

/// Where and how the gripper takes one block.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Grasp {
    /// The point between the fingers: the block's centre of mass, world mm.
    pub centre_mm: DVec3,
    /// Unit horizontal axis between the two parallel faces the fingers close on (the outward
    /// normal of the first face).
    pub closing_axis: DVec3,
    /// Distance between the two faces, mm.
    pub opening_mm: f64,
    /// Unit direction the gripper moves in to reach the block: straight down, (0, -1, 0).
    pub approach: DVec3,
    /// Blocks (indices) that stand in the fingers' way or above the block; empty when the
    /// approach is clear.
    pub blocked_by: Vec<usize>,
}

/// Outward normals closer than this to antiparallel (1 - |cos|) count as parallel faces.
const PARALLEL_TOL: f64 = 1e-9;

/// Overlaps thinner than this, mm, are touching, not in the way.
const CLEAR_TOL_MM: f64 = 1e-6;

/// The gripper's grasp of `blocks[target]` with the blocks `others` (indices into `blocks`)
/// still standing: over every pair of parallel vertical faces no farther apart than the
/// gripper opens, the one with the fewest blocks in the way, then the narrowest, then catalog
/// order. `None` when no pair fits.
pub fn grasp_of(
    blocks: &[Block],
    target: usize,
    others: &[usize],
    gripper: &Gripper,
) -> Option<Grasp> {
    let b = &blocks[target];
    let centre_mm = super::centre_of_mass_mm(b);
    face_pairs(b)
        .into_iter()
        .filter(|&(_, opening)| opening <= gripper.max_opening_mm)
        .map(|(axis, opening_mm)| {
            let blocked_by = in_the_way(blocks, target, others, axis, gripper);
            Grasp {
                centre_mm,
                closing_axis: axis,
                opening_mm,
                approach: DVec3::NEG_Y,
                blocked_by,
            }
        })
        .min_by(|a, b| {
            a.blocked_by
                .len()
                .cmp(&b.blocked_by.len())
                .then(a.opening_mm.total_cmp(&b.opening_mm))
        })
}

/// The block's pairs of parallel vertical faces: (outward normal of the first, distance
/// between the two), in catalog face order.
fn face_pairs(b: &Block) -> Vec<(DVec3, f64)> {
    let faces = b.block_type.faces();
    let v = b.world_vertices();
    let normal = |f: usize| b.world_face_normal(f);
    let offset = |f: usize| v[faces[f][0] as usize].dot(normal(f));
    let mut pairs = Vec::new();
    for f in 0..faces.len() {
        let n = normal(f);
        if n.y.abs() > 1e-9 {
            continue;
        }
        for g in f + 1..faces.len() {
            if 1.0 + n.dot(normal(g)) <= PARALLEL_TOL {
                pairs.push((n, offset(f) + offset(g)));
            }
        }
    }
    pairs
}

/// The blocks among `others` that overlap a finger's box (each finger `finger_thickness_mm`
/// outside its face, `finger_width_mm` wide about the centre, from `finger_depth_mm` below the
/// top upward) or the column above the block. Tested on the intervals of the block's vertices
/// along the closing axis, the face's horizontal direction and y: exact for blocks whose faces
/// lie along those axes (every recognized answer), on the safe side otherwise.
fn in_the_way(
    blocks: &[Block],
    target: usize,
    others: &[usize],
    axis: DVec3,
    g: &Gripper,
) -> Vec<usize> {
    let b = &blocks[target];
    let across = DVec3::Y.cross(axis);
    let (n_lo, n_hi) = extent(b, axis);
    let (t_lo, t_hi) = extent(b, across);
    let (y_lo, y_hi) = extent(b, DVec3::Y);
    let t_mid = super::centre_of_mass_mm(b).dot(across);
    let reach = y_hi - g.finger_depth_mm.min(y_hi - y_lo);
    let w = g.finger_width_mm / 2.0;
    let th = g.finger_thickness_mm;
    let boxes = [
        [
            (n_hi, n_hi + th),
            (t_mid - w, t_mid + w),
            (reach, f64::INFINITY),
        ],
        [
            (n_lo - th, n_lo),
            (t_mid - w, t_mid + w),
            (reach, f64::INFINITY),
        ],
        [(n_lo, n_hi), (t_lo, t_hi), (y_hi, f64::INFINITY)],
    ];
    others
        .iter()
        .copied()
        .filter(|&o| o != target)
        .filter(|&o| {
            let o_iv = [axis, across, DVec3::Y].map(|d| extent(&blocks[o], d));
            boxes.iter().any(|bx| {
                bx.iter()
                    .zip(&o_iv)
                    .all(|(&(lo, hi), &(olo, ohi))| hi.min(ohi) - lo.max(olo) > CLEAR_TOL_MM)
            })
        })
        .collect()
}

/// The block's extent along unit direction `d`, mm.
fn extent(b: &Block, d: DVec3) -> (f64, f64) {
    b.world_vertices()
        .iter()
        .map(|v| v.dot(d))
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
            (lo.min(x), hi.max(x))
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube(x: f64, y: f64) -> Block {
        Block::new("b15", DVec3::new(x, y, 0.0), 0.0)
    }

    #[test]
    fn a_b30_is_taken_across_its_width() {
        let blocks = [Block::new("b30", DVec3::new(0.0, 7.5, 0.0), 0.0)];
        let g = grasp_of(&blocks, 0, &[], &Gripper::default()).unwrap();
        assert!((g.opening_mm - 15.0).abs() < 1e-9, "{g:?}");
        assert!(g.closing_axis.z.abs() > 0.999, "{g:?}");
        assert_eq!(g.approach, DVec3::NEG_Y);
        assert!(g.blocked_by.is_empty());
    }

    #[test]
    fn a_neighbour_touching_one_side_turns_the_grasp_and_two_sides_block_it() {
        let row = [cube(0.0, 7.5), cube(15.0, 7.5)];
        let g = grasp_of(&row, 0, &[1], &Gripper::default()).unwrap();
        assert!(
            g.blocked_by.is_empty() && g.closing_axis.z.abs() > 0.999,
            "{g:?}"
        );
        let boxed = [
            cube(0.0, 7.5),
            cube(15.0, 7.5),
            Block::new("b15", DVec3::new(0.0, 7.5, 15.0), 0.0),
        ];
        let g = grasp_of(&boxed, 0, &[1, 2], &Gripper::default()).unwrap();
        assert_eq!(g.blocked_by.len(), 1, "{g:?}");
        // A neighbour farther than a finger's thickness leaves room.
        let apart = [
            cube(0.0, 7.5),
            cube(20.0, 7.5),
            Block::new("b15", DVec3::new(0.0, 7.5, 20.0), 0.0),
        ];
        let g = grasp_of(&apart, 0, &[1, 2], &Gripper::default()).unwrap();
        assert!(g.blocked_by.is_empty(), "{g:?}");
    }

    #[test]
    fn a_block_above_blocks_the_approach_and_one_below_does_not() {
        let blocks = [cube(0.0, 7.5), cube(0.0, 22.5)];
        let g = grasp_of(&blocks, 0, &[1], &Gripper::default()).unwrap();
        assert_eq!(g.blocked_by, vec![1]);
        let g = grasp_of(&blocks, 1, &[0], &Gripper::default()).unwrap();
        assert!(g.blocked_by.is_empty(), "{g:?}");
    }
}
