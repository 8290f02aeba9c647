//! The score of one reconstruction against its truth: volume IoU, block matching, layers and
//! the verdict.

use super::detection::{detect_blocks, Detection, DETECTION_MIN_IOU};
use super::matching::{count_layers, match_blocks};
use super::volume::{volume_overlap, VolumeTolerances};
use super::ScoreError;
use crate::scene::{ReconStatus, Reconstruction, Scene};
use serde::{Deserialize, Serialize};

/// Tolerances and bars of [`score_reconstruction_with_options`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScoreOptions {
    /// Volume computation tolerances.
    pub volume: VolumeTolerances,
    /// A matched block's centre lies within this distance of the truth's, mm. Default 3 mm
    /// (a fifth of a 15 mm block).
    pub center_tol_mm: f64,
    /// A matched block's orientation lies within this angle of the truth's modulo the block's
    /// symmetry, degrees. Default 5°.
    pub turn_tol_deg: f64,
    /// Block bottoms within this height share a layer, mm. Default 1 mm.
    pub layer_tol_mm: f64,
    /// `exact` needs every block matched and at least this IoU. Default 0.99.
    pub exact_iou: f64,
    /// Below this IoU the verdict is `failed`. Default 0.5.
    pub failed_below_iou: f64,
}

impl Default for ScoreOptions {
    fn default() -> Self {
        ScoreOptions {
            volume: VolumeTolerances::default(),
            center_tol_mm: 3.0,
            turn_tol_deg: 5.0,
            layer_tol_mm: 1.0,
            exact_iou: 0.99,
            failed_below_iou: 0.5,
        }
    }
}

/// The verdict on a reconstruction.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Verdict {
    /// Every block matched and IoU ≥ [`ScoreOptions::exact_iou`].
    Exact,
    /// Neither exact nor failed.
    Partial,
    /// IoU below [`ScoreOptions::failed_below_iou`], or no blocks reconstructed.
    Failed,
    /// The recognizer declined the scene (`status: unsupported`).
    Unsupported,
}

impl Verdict {
    /// `exact` or `partial`: the scene was recognized.
    pub fn is_recognized(self) -> bool {
        matches!(self, Verdict::Exact | Verdict::Partial)
    }

    /// How good the verdict is, for the gate: `exact` 3, `unsupported` 2 (an honest decline),
    /// `partial` 1, `failed` 0. A decline ranks above a partial answer because a recognizer
    /// must never be confidently wrong (docs/recognizer.md "Recognizer").
    pub fn rank(self) -> u8 {
        match self {
            Verdict::Exact => 3,
            Verdict::Unsupported => 2,
            Verdict::Partial => 1,
            Verdict::Failed => 0,
        }
    }

    /// The lowercase name used in files and tables.
    pub fn as_str(self) -> &'static str {
        match self {
            Verdict::Exact => "exact",
            Verdict::Partial => "partial",
            Verdict::Failed => "failed",
            Verdict::Unsupported => "unsupported",
        }
    }
}

/// The score of a reconstruction (plain data, serialized by `blockworld score --json`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Score {
    /// volume(truth ∩ recon) / volume(truth ∪ recon).
    pub iou: f64,
    /// volume(truth), mm³.
    pub truth_volume_mm3: f64,
    /// volume(recon), mm³.
    pub recon_volume_mm3: f64,
    /// volume(truth ∩ recon), mm³.
    pub intersection_volume_mm3: f64,
    /// Blocks in the truth.
    pub truth_blocks: usize,
    /// Blocks in the reconstruction.
    pub recon_blocks: usize,
    /// Blocks matched one to one (type, centre and turn within tolerance).
    pub matched_blocks: usize,
    /// matched / recon blocks (0 when the reconstruction is empty and the truth is not).
    pub precision: f64,
    /// matched / truth blocks.
    pub recall: f64,
    /// Harmonic mean of precision and recall.
    pub f1: f64,
    /// Mean centre distance of matched blocks, mm; `None` when nothing matched.
    pub mean_center_error_mm: Option<f64>,
    /// Blocks matched one to one at 3D IoU ≥ [`DETECTION_MIN_IOU`], with precision, recall
    /// and F1 (`super::detection`).
    pub detection: Detection,
    /// Layers in the truth (distinct bottom heights).
    pub truth_layers: usize,
    /// Layers in the reconstruction.
    pub recon_layers: usize,
    /// Whether the layer counts agree.
    pub layers_right: bool,
    /// The verdict.
    pub verdict: Verdict,
    /// The reconstruction's `reason`, if it gave one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
}

/// Most blocks `score` takes in each file (docs/limits.md "Score"): matching and the volume
/// overlap compare every truth block with every reconstructed one (1,000 against 1,000 take
/// 3.8 s in a debug build, 10,000 against 10,000 over 120 s).
pub const MAX_SCORE_BLOCKS: usize = 2_000;

/// Scores `recon` against `truth` with [`ScoreOptions::default`].
pub fn score_reconstruction(truth: &Scene, recon: &Reconstruction) -> Result<Score, ScoreError> {
    score_reconstruction_with_options(truth, recon, &ScoreOptions::default())
}

/// The verdict of a reconstruction with `status`, its block matches counted in `matches` and
/// its volume IoU `iou` against the truth.
fn verdict_of(status: ReconStatus, matches: &Detection, iou: f64, opts: &ScoreOptions) -> Verdict {
    let (nt, nr, nm) = (matches.truth_blocks, matches.recon_blocks, matches.matched);
    if status == ReconStatus::Unsupported {
        Verdict::Unsupported
    } else if nr == 0 && nt > 0 || iou < opts.failed_below_iou {
        Verdict::Failed
    } else if nm == nt && nm == nr && iou >= opts.exact_iou {
        Verdict::Exact
    } else {
        Verdict::Partial
    }
}

/// Scores `recon` against `truth`. The reconstruction's solid is the union of its blocks
/// (the thesis's CSG adds blocks together, Figure 4.6); a CSG tree with differences or
/// intersections is refused rather than scored as something it is not.
pub fn score_reconstruction_with_options(
    truth: &Scene,
    recon: &Reconstruction,
    opts: &ScoreOptions,
) -> Result<Score, ScoreError> {
    if recon.csg.as_ref().is_some_and(|t| !t.is_pure_union()) {
        return Err(ScoreError::NotAUnion);
    }
    let overlap = volume_overlap(&truth.blocks, &recon.blocks, &opts.volume)?;
    let iou = overlap.iou();
    let matches = match_blocks(
        &truth.blocks,
        &recon.blocks,
        opts.center_tol_mm,
        opts.turn_tol_deg,
    );
    let (nt, nr, nm) = (truth.blocks.len(), recon.blocks.len(), matches.len());
    let rates = Detection::from_counts(0.0, nm, nt, nr);
    let mean_center_error_mm =
        (nm > 0).then(|| matches.iter().map(|m| m.center_error_mm).sum::<f64>() / nm as f64);
    let detection = detect_blocks(
        &truth.blocks,
        &recon.blocks,
        DETECTION_MIN_IOU,
        &opts.volume,
    )?;
    let truth_layers = count_layers(&truth.blocks, opts.layer_tol_mm);
    let recon_layers = count_layers(&recon.blocks, opts.layer_tol_mm);
    let verdict = verdict_of(recon.status, &rates, iou, opts);
    Ok(Score {
        iou,
        truth_volume_mm3: overlap.truth_mm3,
        recon_volume_mm3: overlap.recon_mm3,
        intersection_volume_mm3: overlap.intersection_mm3,
        truth_blocks: nt,
        recon_blocks: nr,
        matched_blocks: nm,
        precision: rates.precision,
        recall: rates.recall,
        f1: rates.f1,
        mean_center_error_mm,
        detection,
        truth_layers,
        recon_layers,
        layers_right: truth_layers == recon_layers,
        verdict,
        reason: recon.reason.clone(),
    })
}
