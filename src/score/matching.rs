//! Per-block matching of a reconstruction to the truth, orientation modulo a block's symmetry,
//! and layer counting (Chapter VI's layers: blocks resting at the same height).

use crate::geom::{DQuat, DVec3};
pub use crate::scene::symmetry_rotations;
use crate::scene::Block;

/// One truth block matched to one reconstructed block.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BlockMatch {
    /// Index in the truth scene.
    pub truth: usize,
    /// Index in the reconstruction.
    pub recon: usize,
    /// Distance between the centres, mm.
    pub center_error_mm: f64,
    /// Smallest rotation angle between the two poses modulo the block's symmetry, degrees.
    pub turn_error_deg: f64,
}

/// The smallest rotation angle in degrees taking block `a`'s pose to block `b`'s, modulo
/// `a`'s symmetry rotations (`symmetry`, from [`symmetry_rotations`]). A round part is
/// symmetric under every turn about its axis (and a half turn across it), so for it only the
/// angle between the two axes counts, whatever its prism's symmetries.
pub fn turn_error_deg(a: &Block, b: &Block, symmetry: &[DQuat]) -> f64 {
    let (qa, qb) = (a.rotation(), b.rotation());
    if a.block_type.round().is_some() {
        let (ya, yb) = (qa * DVec3::Y, qb * DVec3::Y);
        return ya.angle_between(yb).min(ya.angle_between(-yb)).to_degrees();
    }
    symmetry
        .iter()
        .map(|s| {
            let d = qb.inverse() * qa * *s;
            2.0 * d.xyz().length().atan2(d.w.abs())
        })
        .fold(f64::INFINITY, f64::min)
        .to_degrees()
}

/// Greedy matching by centre distance: every (truth, recon) pair of the same type within
/// `center_tol_mm` and `turn_tol_deg` is a candidate; candidates are taken shortest distance
/// first (ties by index), each block at most once. For valid truth scenes this is the optimal
/// (Hungarian) matching as well: two truth blocks' centres are at least 7.5 mm apart (the
/// thinnest block), so with a 3 mm tolerance no recon block is a candidate for two truth blocks.
pub fn match_blocks(
    truth: &[Block],
    recon: &[Block],
    center_tol_mm: f64,
    turn_tol_deg: f64,
) -> Vec<BlockMatch> {
    let mut candidates = Vec::new();
    for (ti, t) in truth.iter().enumerate() {
        let symmetry = symmetry_rotations(t.block_type);
        for (ri, r) in recon.iter().enumerate() {
            if r.block_type.id != t.block_type.id {
                continue;
            }
            let center_error_mm = t.center_mm.distance(r.center_mm);
            if center_error_mm > center_tol_mm {
                continue;
            }
            let turn = turn_error_deg(t, r, &symmetry);
            if turn <= turn_tol_deg {
                candidates.push(BlockMatch {
                    truth: ti,
                    recon: ri,
                    center_error_mm,
                    turn_error_deg: turn,
                });
            }
        }
    }
    candidates.sort_by(|a, b| {
        a.center_error_mm
            .total_cmp(&b.center_error_mm)
            .then(a.truth.cmp(&b.truth))
            .then(a.recon.cmp(&b.recon))
    });
    let (mut used_t, mut used_r) = (vec![false; truth.len()], vec![false; recon.len()]);
    let mut out = Vec::new();
    for c in candidates {
        if !used_t[c.truth] && !used_r[c.recon] {
            used_t[c.truth] = true;
            used_r[c.recon] = true;
            out.push(c);
        }
    }
    out.sort_by_key(|m| m.truth);
    out
}

/// Number of layers: distinct resting heights of block bottoms (lowest vertex y), heights
/// within `tol_mm` of the previous one in sorted order joining the same layer.
pub fn count_layers(blocks: &[Block], tol_mm: f64) -> usize {
    crate::scene::layer_bottoms_mm(blocks, tol_mm).len()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::block_type;

    #[test]
    fn symmetry_counts_follow_the_shapes() {
        let n = |id| symmetry_rotations(block_type(id).unwrap()).len();
        assert_eq!((n("b15"), n("b30"), n("b7_5")), (24, 8, 8));
    }

    #[test]
    fn yaw_errors_modulo_symmetry() {
        let at = |id, yaw| Block::new(id, DVec3::new(0.0, 7.5, 0.0), yaw);
        let sym15 = symmetry_rotations(block_type("b15").unwrap());
        assert!(turn_error_deg(&at("b15", 0.0), &at("b15", 90.0), &sym15) < 1e-6);
        assert!((turn_error_deg(&at("b15", 0.0), &at("b15", 93.0), &sym15) - 3.0).abs() < 1e-6);
        let sym30 = symmetry_rotations(block_type("b30").unwrap());
        assert!(turn_error_deg(&at("b30", 0.0), &at("b30", 180.0), &sym30) < 1e-6);
        assert!((turn_error_deg(&at("b30", 0.0), &at("b30", 90.0), &sym30) - 90.0).abs() < 1e-6);
    }

    #[test]
    fn greedy_takes_nearest_and_respects_type() {
        let truth = [
            Block::new("b15", DVec3::new(0.0, 7.5, 0.0), 0.0),
            Block::new("b15", DVec3::new(15.0, 7.5, 0.0), 0.0),
        ];
        let recon = [
            Block::new("b15", DVec3::new(14.0, 7.5, 0.0), 0.0),
            Block::new("b30", DVec3::new(0.0, 7.5, 0.0), 0.0),
            Block::new("b15", DVec3::new(1.0, 7.5, 0.0), 2.0),
        ];
        let m = match_blocks(&truth, &recon, 3.0, 5.0);
        assert_eq!(
            m.iter().map(|m| (m.truth, m.recon)).collect::<Vec<_>>(),
            [(0, 2), (1, 0)]
        );
        assert!((m[0].center_error_mm - 1.0).abs() < 1e-12);
    }

    #[test]
    fn layers_join_within_tolerance() {
        let b = |y| Block::new("b15", DVec3::new(0.0, y, 0.0), 0.0);
        assert_eq!(count_layers(&[b(7.5), b(7.9), b(22.5), b(37.5)], 1.0), 3);
        assert_eq!(count_layers(&[], 1.0), 0);
    }
}
