//! The accuracy suite: per-scene results, per-family summaries, and the golden gate that CI
//! enforces (docs/accuracy.md "Scoring and the accuracy suite"; a scene marked unsupported that starts
//! passing is itself a failure until someone changes its mark on purpose).

use super::detection::{Detection, DETECTION_MIN_IOU};
use super::verdict::{score_reconstruction_with_options, ScoreOptions, Verdict};
use crate::scene::{Reconstruction, Scene};
use serde::{Deserialize, Serialize};

/// One suite scene's result.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SceneResult {
    /// The scene id (its file stem in the suite).
    pub id: String,
    /// Its family ([`scene_family`]).
    pub family: String,
    /// `expect.supported` of the truth (true when absent).
    pub supported: bool,
    /// The verdict.
    pub verdict: Verdict,
    /// Volume IoU (0 when no reconstruction was given or it could not be scored).
    pub iou: f64,
    /// Block F1.
    pub f1: f64,
    /// Blocks in the truth.
    #[serde(default)]
    pub truth_blocks: usize,
    /// Blocks in the reconstruction (0 when there is none).
    #[serde(default)]
    pub recon_blocks: usize,
    /// Blocks matched one to one at 3D IoU ≥ [`DETECTION_MIN_IOU`] (`super::detection`).
    #[serde(default)]
    pub detected_blocks: usize,
    /// Mean centre error of matched blocks, mm.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mean_center_error_mm: Option<f64>,
    /// Whether the layer count is right.
    pub layers_right: bool,
    /// A known failure case (`supported == false`) that came out `unsupported` or `failed`, as
    /// it should.
    pub flagged: bool,
    /// A known failure case that came out `partial`: neither declined nor exact.
    pub unexpected_pass: bool,
    /// The recognizer answered `ok` but the answer is not `exact`: the worst outcome
    /// (docs/recognizer.md "Recognizer").
    #[serde(default)]
    pub confidently_wrong: bool,
    /// Why the scene has no score (missing reconstruction file, scoring error).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
}

/// The family of a suite scene: `meta.family` when present, else its name without a trailing
/// `_<digits>` or `-<digits>` (`tower_003` -> `tower`).
pub fn scene_family(scene: &Scene) -> String {
    if let Some(f) = scene
        .meta
        .as_ref()
        .and_then(|m| m.get("family"))
        .and_then(|v| v.as_str())
    {
        return f.to_string();
    }
    let name = scene.name.as_str();
    match name.rfind(['_', '-']) {
        Some(i)
            if i > 0 && name[i + 1..].chars().all(|c| c.is_ascii_digit()) && i + 1 < name.len() =>
        {
            name[..i].to_string()
        }
        _ => name.to_string(),
    }
}

/// Why a suite scene has no reconstruction to score (a missing or unreadable file, a recognizer
/// that failed): counted as `failed`, with this note.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct NoReconstruction(pub String);

/// Scores one suite scene; a missing reconstruction counts as `failed`.
pub fn score_suite_scene(
    id: &str,
    truth: &Scene,
    recon: Result<&Reconstruction, NoReconstruction>,
    opts: &ScoreOptions,
) -> SceneResult {
    let supported = truth.is_supported();
    let answered_ok = recon.as_ref().is_ok_and(|r| r.is_ok());
    let scored = recon
        .map_err(|e| e.0)
        .and_then(|r| score_reconstruction_with_options(truth, r, opts).map_err(|e| e.to_string()));
    let nothing = Detection::from_counts(DETECTION_MIN_IOU, 0, truth.blocks.len(), 0);
    let (verdict, iou, f1, mean_center_error_mm, layers_right, detection, note) = match scored {
        Ok(s) => (
            s.verdict,
            s.iou,
            s.f1,
            s.mean_center_error_mm,
            s.layers_right,
            s.detection,
            None,
        ),
        Err(note) => (Verdict::Failed, 0.0, 0.0, None, false, nothing, Some(note)),
    };
    let recognized = verdict.is_recognized();
    SceneResult {
        id: id.to_string(),
        family: scene_family(truth),
        supported,
        verdict,
        iou,
        f1,
        truth_blocks: detection.truth_blocks,
        recon_blocks: detection.recon_blocks,
        detected_blocks: detection.matched,
        mean_center_error_mm,
        layers_right,
        flagged: !supported && !recognized,
        unexpected_pass: !supported && verdict == Verdict::Partial,
        confidently_wrong: answered_ok && verdict != Verdict::Exact,
        note,
    }
}

/// One row of the per-family table.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FamilySummary {
    /// The family.
    pub family: String,
    /// Scenes in it.
    pub scenes: usize,
    /// Mean IoU.
    pub mean_iou: f64,
    /// Share of `exact` verdicts.
    pub exact_share: f64,
    /// Mean block F1.
    pub mean_f1: f64,
    /// Blocks detected at 3D IoU ≥ [`DETECTION_MIN_IOU`], summed over the scenes (precision,
    /// recall and F1 over all their blocks).
    #[serde(default = "no_detection")]
    pub detection: Detection,
    /// Scenes marked unsupported (known failure cases).
    pub expected_failures: usize,
    /// Of those, how many came out unsupported or failed.
    pub flagged: usize,
    /// Of those, how many came out partial.
    pub unexpected_passes: usize,
    /// Scenes answered `ok` that are not exact.
    #[serde(default)]
    pub confidently_wrong: usize,
    /// Scenes declined (`unsupported`).
    #[serde(default)]
    pub declined: usize,
}

/// The columns of the per-family table, which `bench accuracy` prints in Markdown and
/// `blockworld report` shows in HTML ([`FamilySummary::cells`]).
pub const FAMILY_TABLE_HEADINGS: [&str; 8] = [
    "family",
    "scenes",
    "mean IoU",
    "blocks P / R / F1 at 3D IoU ≥ 0.5",
    "exact",
    "declined",
    "confidently wrong",
    "expected failures",
];

impl FamilySummary {
    /// The row's cells under [`FAMILY_TABLE_HEADINGS`]; the last is `-` without known failure
    /// cases, else how many of them were declined, with `(!)` when one came out partial.
    pub fn cells(&self) -> [String; 8] {
        let failures = if self.expected_failures == 0 {
            "-".to_string()
        } else {
            format!(
                "{}/{} declined{}",
                self.flagged,
                self.expected_failures,
                if self.unexpected_passes > 0 {
                    " (!)"
                } else {
                    ""
                }
            )
        };
        let d = &self.detection;
        [
            self.family.clone(),
            self.scenes.to_string(),
            format!("{:.4}", self.mean_iou),
            format!("{:.3} / {:.3} / {:.3}", d.precision, d.recall, d.f1),
            format!("{:.0}%", 100.0 * self.exact_share),
            self.declined.to_string(),
            self.confidently_wrong.to_string(),
            failures,
        ]
    }
}

fn no_detection() -> Detection {
    Detection::from_counts(DETECTION_MIN_IOU, 0, 0, 0)
}

/// Per-family summaries, sorted by family, plus an `"all"` row last.
pub fn summarize_by_family(results: &[SceneResult]) -> Vec<FamilySummary> {
    let mut families: Vec<&str> = results.iter().map(|r| r.family.as_str()).collect();
    families.sort_unstable();
    families.dedup();
    let mut rows: Vec<FamilySummary> = families
        .iter()
        .map(|f| summarize(f, results.iter().filter(|r| r.family == *f)))
        .collect();
    rows.push(summarize("all", results.iter()));
    rows
}

fn summarize<'a>(family: &str, rs: impl Iterator<Item = &'a SceneResult>) -> FamilySummary {
    let rs: Vec<&SceneResult> = rs.collect();
    let n = rs.len().max(1) as f64;
    FamilySummary {
        family: family.to_string(),
        scenes: rs.len(),
        mean_iou: rs.iter().map(|r| r.iou).sum::<f64>() / n,
        exact_share: rs.iter().filter(|r| r.verdict == Verdict::Exact).count() as f64 / n,
        mean_f1: rs.iter().map(|r| r.f1).sum::<f64>() / n,
        detection: Detection::from_counts(
            DETECTION_MIN_IOU,
            rs.iter().map(|r| r.detected_blocks).sum(),
            rs.iter().map(|r| r.truth_blocks).sum(),
            rs.iter().map(|r| r.recon_blocks).sum(),
        ),
        expected_failures: rs.iter().filter(|r| !r.supported).count(),
        flagged: rs.iter().filter(|r| r.flagged).count(),
        unexpected_passes: rs.iter().filter(|r| r.unexpected_pass).count(),
        confidently_wrong: rs.iter().filter(|r| r.confidently_wrong).count(),
        declined: rs
            .iter()
            .filter(|r| r.verdict == Verdict::Unsupported)
            .count(),
    }
}

/// One accepted scene result in `golden/accuracy.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GoldenScene {
    /// Scene id.
    pub id: String,
    /// Accepted IoU, rounded to 1e-6.
    pub iou: f64,
    /// Accepted verdict.
    pub verdict: Verdict,
    /// `expect.supported` when blessed.
    pub supported: bool,
    /// Whether the known failure case was flagged when blessed.
    pub flagged: bool,
}

/// `golden/accuracy.json`: the accepted per-scene results.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Golden {
    /// How the file is re-blessed (for a reader of the file).
    pub bless: String,
    /// An IoU may fall at most this far below its golden value. 0.01 (docs/accuracy.md "Scoring and the accuracy suite").
    pub iou_drop_tolerance: f64,
    /// The scenes, sorted by id.
    pub scenes: Vec<GoldenScene>,
}

/// The command that re-blesses `golden/accuracy.json`.
pub const BLESS_COMMAND: &str = "BLESS=1 cargo test --test accuracy_gate";

impl Golden {
    /// The golden file accepting `results` as they are; `bless` is the command that remakes it.
    pub fn from_results(results: &[SceneResult], bless: &str) -> Golden {
        let mut scenes: Vec<GoldenScene> = results
            .iter()
            .map(|r| GoldenScene {
                id: r.id.clone(),
                iou: (r.iou * 1e6).round() / 1e6,
                verdict: r.verdict,
                supported: r.supported,
                flagged: r.flagged,
            })
            .collect();
        scenes.sort_by(|a, b| a.id.cmp(&b.id));
        Golden {
            bless: bless.to_string(),
            iou_drop_tolerance: 0.01,
            scenes,
        }
    }
}

/// Why the gate fails.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum GateFailure {
    /// IoU fell more than the tolerance below golden.
    IouDropped {
        /// Scene id.
        id: String,
        /// Golden IoU.
        golden: f64,
        /// IoU now.
        now: f64,
    },
    /// A supported scene recognized (exact/partial) in golden is now failed or unsupported.
    NoLongerRecognized {
        /// Scene id.
        id: String,
        /// Golden verdict.
        golden: Verdict,
        /// Verdict now.
        now: Verdict,
    },
    /// A scene's verdict ranks below its golden one ([`Verdict::rank`]).
    VerdictWorse {
        /// Scene id.
        id: String,
        /// Golden verdict.
        golden: Verdict,
        /// Verdict now.
        now: Verdict,
    },
    /// A known failure case declined in golden is now neither declined nor exact.
    NoLongerFlagged {
        /// Scene id.
        id: String,
        /// Verdict now.
        now: Verdict,
    },
    /// A golden scene has no result now.
    MissingResult {
        /// Scene id.
        id: String,
    },
    /// A result for a scene the golden file does not know.
    NotInGolden {
        /// Scene id.
        id: String,
    },
}

impl std::fmt::Display for GateFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            GateFailure::IouDropped { id, golden, now } => {
                write!(f, "{id}: IoU {now:.4} is more than 0.01 below golden {golden:.4}")
            }
            GateFailure::NoLongerRecognized { id, golden, now } => write!(
                f,
                "{id}: supported scene no longer recognized ({} -> {})",
                golden.as_str(),
                now.as_str()
            ),
            GateFailure::NoLongerFlagged { id, now } => write!(
                f,
                "{id}: known failure case now passes as {}; if that is real, change its expect mark",
                now.as_str()
            ),
            GateFailure::VerdictWorse { id, golden, now } => write!(
                f,
                "{id}: verdict got worse ({} -> {})",
                golden.as_str(),
                now.as_str()
            ),
            GateFailure::MissingResult { id } => write!(f, "{id}: in golden but not scored"),
            GateFailure::NotInGolden { id } => write!(f, "{id}: scored but not in golden ({BLESS_COMMAND})"),
        }
    }
}

/// Compares results with the golden file; an empty list means the gate passes.
pub fn check_gate(golden: &Golden, results: &[SceneResult]) -> Vec<GateFailure> {
    let mut failures = Vec::new();
    for g in &golden.scenes {
        let Some(r) = results.iter().find(|r| r.id == g.id) else {
            failures.push(GateFailure::MissingResult { id: g.id.clone() });
            continue;
        };
        if r.iou < g.iou - golden.iou_drop_tolerance {
            failures.push(GateFailure::IouDropped {
                id: g.id.clone(),
                golden: g.iou,
                now: r.iou,
            });
        }
        if g.supported && g.verdict.is_recognized() && !r.verdict.is_recognized() {
            failures.push(GateFailure::NoLongerRecognized {
                id: g.id.clone(),
                golden: g.verdict,
                now: r.verdict,
            });
        }
        if r.verdict.rank() < g.verdict.rank() {
            failures.push(GateFailure::VerdictWorse {
                id: g.id.clone(),
                golden: g.verdict,
                now: r.verdict,
            });
        }
        if g.flagged && !(r.flagged || r.verdict == Verdict::Exact) {
            failures.push(GateFailure::NoLongerFlagged {
                id: g.id.clone(),
                now: r.verdict,
            });
        }
    }
    for r in results {
        if !golden.scenes.iter().any(|g| g.id == r.id) {
            failures.push(GateFailure::NotInGolden { id: r.id.clone() });
        }
    }
    failures
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn family_from_meta_or_name() {
        let mut s = Scene::new("tower_003", vec![]);
        assert_eq!(scene_family(&s), "tower");
        s.name = "two_layer-12".into();
        assert_eq!(scene_family(&s), "two_layer");
        s.name = "thesis_sample".into();
        assert_eq!(scene_family(&s), "thesis_sample");
        let mut meta = serde_json::Map::new();
        meta.insert("family".into(), "overhang".into());
        s.meta = Some(meta);
        assert_eq!(scene_family(&s), "overhang");
    }

    #[test]
    fn missing_reconstruction_fails_and_flags_a_failure_case() {
        let mut truth = Scene::new("yaw_000", vec![]);
        truth.expect = Some(crate::scene::Expect {
            supported: false,
            reason: None,
        });
        let r = score_suite_scene(
            "yaw_000",
            &truth,
            Err(NoReconstruction("no file".into())),
            &ScoreOptions::default(),
        );
        assert_eq!(
            (r.verdict, r.flagged, r.unexpected_pass),
            (Verdict::Failed, true, false)
        );
        assert_eq!(r.note.as_deref(), Some("no file"));
    }
}
