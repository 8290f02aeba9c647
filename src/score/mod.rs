//! Scoring reconstructions against ground truth with parry3d volume overlap.
//! The only home of parry3d.
//!
//! The thesis ends by reconstructing "the final object … from the primitive blocks"
//! (Chapter VII) and names where its method fails: an upper layer larger than the one below
//! (Figure 7.2) and blocks not in a uniform direction. This stage measures a reconstruction
//! against the truth it came from:
//!
//! * [`volume_iou`]: volume(truth ∩ recon) / volume(truth ∪ recon) of the two solids, each the
//!   union of its blocks, exact for convex catalog blocks in any pose (parry3d convex hull of the
//!   clipped edges, inclusion–exclusion for overlapping blocks; see `polytope` and `volume`);
//! * [`score_reconstruction`]: the [`Score`]: IoU, per-block matching (precision, recall, F1,
//!   centre error), blocks detected at 3D IoU ≥ 0.5 ([`detect_blocks`]: precision, recall, F1),
//!   layer count, and the [`Verdict`];
//! * the accuracy suite ([`score_suite_scene`], [`summarize_by_family`]) and its golden gate
//!   ([`check_gate`]), with known failure cases that must stay flagged;
//! * [`make_reference_reconstructions`]: the constructed reconstruction set the gate is proven on.
//!
//! Plain data in, plain data out; no file I/O (the `cli` reads and writes the files).

mod detection;
mod matching;
mod polytope;
mod reference;
mod suite;
mod verdict;
mod volume;

#[cfg(test)]
mod tests;

pub use detection::{block_iou, detect_blocks, match_blocks_by_iou, Detection, DETECTION_MIN_IOU};
pub use matching::{count_layers, match_blocks, symmetry_rotations, turn_error_deg, BlockMatch};
pub use reference::{
    make_reference_reconstruction, make_reference_reconstructions, READING_ERROR_DEG,
    READING_ERROR_MM,
};
pub use suite::{
    check_gate, scene_family, score_suite_scene, summarize_by_family, FamilySummary, GateFailure,
    Golden, GoldenScene, NoReconstruction, SceneResult, BLESS_COMMAND, FAMILY_TABLE_HEADINGS,
};
pub use verdict::{
    score_reconstruction, score_reconstruction_with_options, Score, ScoreOptions, Verdict,
    MAX_SCORE_BLOCKS,
};
pub use volume::{
    union_volume_mm3, volume_iou, volume_iou_with_tolerances, volume_overlap, VolumeOverlap,
    VolumeTolerances,
};

/// Why a score could not be computed.
#[derive(Debug, thiserror::Error)]
pub enum ScoreError {
    /// Too many mutually overlapping blocks for inclusion–exclusion.
    #[error(
        "{blocks} blocks overlap one another too much: the union volume needs more than {limit} \
         inclusion–exclusion terms; remove duplicate or piled-up blocks from the reconstruction \
         or raise VolumeTolerances::max_overlap_terms"
    )]
    TooManyOverlapTerms {
        /// Distinct blocks in the union.
        blocks: usize,
        /// The limit that was hit.
        limit: usize,
    },
    /// A CSG tree that is not a union of blocks (scoring measures the union of `blocks`).
    #[error("the reconstruction's csg holds a difference or intersection; scoring measures the union of its blocks, so give a union tree (or none)")]
    NotAUnion,
    /// parry3d's convex hull failed on an overlap's points (a parry bug; report the scene).
    #[error("convex hull of an overlap failed in parry3d: {0}")]
    Hull(String),
}
