//! Per-block detection metrics: reconstructed blocks matched one to one to truth blocks at a 3D
//! IoU of at least [`DETECTION_MIN_IOU`], and the precision, recall and F1 of that matching (the
//! measure of the line-drawing-to-assembly literature, e.g. PlankAssembly, ICCV 2023), so the
//! recognizer can be set beside learned methods (docs/accuracy.md "Scoring and the accuracy
//! suite").
//!
//! The IoU of two blocks is that of their catalog solids, exact in any pose through the same
//! convex intersection as the volume IoU ([`super::polytope`]): for the cuboid blocks it is the
//! IoU of their oriented 3D boxes; for the wedge and the round part's prism, of the solid
//! itself (tighter than a box). A pair counts only when both blocks have the same catalog type.
//! The matching is greedy, largest IoU first (ties by truth, then recon index), as COCO's
//! evaluation matches detections.

use super::polytope::ConvexPolytope;
use super::{ScoreError, VolumeTolerances};
use crate::scene::Block;
use serde::{Deserialize, Serialize};

/// The IoU a reconstructed block needs with a truth block to count as detected.
pub const DETECTION_MIN_IOU: f64 = 0.5;

/// Blocks matched at a 3D IoU threshold, and the resulting precision, recall and F1.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Detection {
    /// The IoU a match needs.
    pub min_iou: f64,
    /// Blocks matched one to one.
    pub matched: usize,
    /// Blocks in the truth.
    pub truth_blocks: usize,
    /// Blocks in the reconstruction.
    pub recon_blocks: usize,
    /// matched / recon blocks (1 when both are empty, 0 when only the reconstruction is).
    pub precision: f64,
    /// matched / truth blocks (1 when the truth is empty).
    pub recall: f64,
    /// Harmonic mean of precision and recall (0 when both are 0).
    pub f1: f64,
}

impl Detection {
    /// The metrics of `matched` matches among `truth_blocks` and `recon_blocks`: also the one
    /// home of summing them over many scenes (pass the sums).
    pub fn from_counts(
        min_iou: f64,
        matched: usize,
        truth_blocks: usize,
        recon_blocks: usize,
    ) -> Detection {
        let precision = match (recon_blocks, truth_blocks) {
            (0, 0) => 1.0,
            (0, _) => 0.0,
            (r, _) => matched as f64 / r as f64,
        };
        let recall = match truth_blocks {
            0 => 1.0,
            t => matched as f64 / t as f64,
        };
        let f1 = if precision + recall > 0.0 {
            2.0 * precision * recall / (precision + recall)
        } else {
            0.0
        };
        Detection {
            min_iou,
            matched,
            truth_blocks,
            recon_blocks,
            precision,
            recall,
            f1,
        }
    }
}

/// The IoU of two blocks' solids (module doc).
pub fn block_iou(a: &Block, b: &Block, tol: &VolumeTolerances) -> Result<f64, ScoreError> {
    let (pa, pb) = (ConvexPolytope::from_block(a), ConvexPolytope::from_block(b));
    let inter = pa.intersect(&pb, tol)?.map_or(0.0, |(_, v)| v);
    let union = a.volume_mm3() + b.volume_mm3() - inter;
    Ok(if union > 0.0 {
        (inter / union).clamp(0.0, 1.0)
    } else {
        0.0
    })
}

/// Pairs `(truth index, recon index, IoU)` matched one to one at IoU ≥ `min_iou`, same type
/// only, greedy by IoU (module doc); sorted by truth index.
pub fn match_blocks_by_iou(
    truth: &[Block],
    recon: &[Block],
    min_iou: f64,
    tol: &VolumeTolerances,
) -> Result<Vec<(usize, usize, f64)>, ScoreError> {
    let mut candidates = Vec::new();
    for (ti, t) in truth.iter().enumerate() {
        for (ri, r) in recon.iter().enumerate() {
            if t.block_type.id != r.block_type.id {
                continue;
            }
            let iou = block_iou(t, r, tol)?;
            if iou >= min_iou {
                candidates.push((ti, ri, iou));
            }
        }
    }
    candidates.sort_by(|a, b| b.2.total_cmp(&a.2).then(a.0.cmp(&b.0)).then(a.1.cmp(&b.1)));
    let (mut used_t, mut used_r) = (vec![false; truth.len()], vec![false; recon.len()]);
    let mut out = Vec::new();
    for (t, r, iou) in candidates {
        if !used_t[t] && !used_r[r] {
            used_t[t] = true;
            used_r[r] = true;
            out.push((t, r, iou));
        }
    }
    out.sort_by_key(|m| m.0);
    Ok(out)
}

/// The detection metrics of `recon` against `truth` at IoU ≥ `min_iou`.
pub fn detect_blocks(
    truth: &[Block],
    recon: &[Block],
    min_iou: f64,
    tol: &VolumeTolerances,
) -> Result<Detection, ScoreError> {
    let matched = match_blocks_by_iou(truth, recon, min_iou, tol)?.len();
    Ok(Detection::from_counts(
        min_iou,
        matched,
        truth.len(),
        recon.len(),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::DVec3;

    fn at(id: &str, x: f64, y: f64, yaw: f64) -> Block {
        Block::new(id, DVec3::new(x, y, 0.0), yaw)
    }

    fn tol() -> VolumeTolerances {
        VolumeTolerances::default()
    }

    #[test]
    fn box_iou_by_hand() {
        let a = at("b15", 0.0, 7.5, 0.0);
        assert!((block_iou(&a, &a, &tol()).unwrap() - 1.0).abs() < 1e-9);
        // Shifted by a third of its side: overlap 2/3, IoU (2/3) / (4/3) = 1/2.
        let b = at("b15", 5.0, 7.5, 0.0);
        assert!((block_iou(&a, &b, &tol()).unwrap() - 0.5).abs() < 1e-9);
        // Half its side: 1/3.
        let c = at("b15", 7.5, 7.5, 0.0);
        assert!((block_iou(&a, &c, &tol()).unwrap() - 1.0 / 3.0).abs() < 1e-9);
        // A b30 turned a quarter about its centre: a 15 x 15 x 15 overlap of two 30 x 15 x 15,
        // IoU 1/3. Apart: 0.
        let long = at("b30", 0.0, 7.5, 0.0);
        let turned = at("b30", 0.0, 7.5, 90.0);
        assert!((block_iou(&long, &turned, &tol()).unwrap() - 1.0 / 3.0).abs() < 1e-9);
        assert_eq!(
            block_iou(&a, &at("b15", 40.0, 7.5, 0.0), &tol()).unwrap(),
            0.0
        );
    }

    #[test]
    fn a_missing_block_lowers_recall_and_an_extra_one_precision() {
        let truth = [at("b15", 0.0, 7.5, 0.0), at("b15", 15.0, 7.5, 0.0)];
        let all = detect_blocks(&truth, &truth, DETECTION_MIN_IOU, &tol()).unwrap();
        assert_eq!(
            (all.matched, all.precision, all.recall, all.f1),
            (2, 1.0, 1.0, 1.0)
        );
        let missing = detect_blocks(&truth, &truth[..1], DETECTION_MIN_IOU, &tol()).unwrap();
        assert_eq!((missing.precision, missing.recall), (1.0, 0.5));
        assert!((missing.f1 - 2.0 / 3.0).abs() < 1e-12);
        let extra = [truth[0], truth[1], at("b15", 60.0, 7.5, 0.0)];
        let extra = detect_blocks(&truth, &extra, DETECTION_MIN_IOU, &tol()).unwrap();
        assert_eq!(extra.recall, 1.0);
        assert!((extra.precision - 2.0 / 3.0).abs() < 1e-12);
    }

    #[test]
    fn matches_are_one_to_one_same_type_and_at_the_threshold() {
        let truth = [at("b15", 0.0, 7.5, 0.0)];
        // Two candidates for one truth block: only one counts; the better one is taken.
        let recon = [at("b15", 4.9, 7.5, 0.0), at("b15", 1.0, 7.5, 0.0)];
        let m = match_blocks_by_iou(&truth, &recon, DETECTION_MIN_IOU, &tol()).unwrap();
        assert_eq!(m.iter().map(|m| (m.0, m.1)).collect::<Vec<_>>(), [(0, 1)]);
        // IoU 10.1 / 19.9 = 0.508 counts, 9.9 / 20.1 = 0.493 does not; another type never does.
        let half = detect_blocks(&truth, &recon[..1], DETECTION_MIN_IOU, &tol()).unwrap();
        assert_eq!(half.matched, 1);
        let less = detect_blocks(&truth, &[at("b15", 5.1, 7.5, 0.0)], 0.5, &tol()).unwrap();
        assert_eq!(less.matched, 0);
        let other = detect_blocks(&truth, &[at("b7_5", 0.0, 3.75, 0.0)], 0.4, &tol()).unwrap();
        assert_eq!(other.matched, 0);
        let empty = detect_blocks(&truth, &[], 0.5, &tol()).unwrap();
        assert_eq!((empty.precision, empty.recall, empty.f1), (0.0, 0.0, 0.0));
    }
}
