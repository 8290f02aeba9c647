//! What the recognizer takes and gives: the observed views and options, the answer with its
//! evidence, why it declined, and the errors of malformed input.

use super::{Layer, MatchTolerances, ViewCheck};
use crate::camera::Camera;
use crate::drawing::LineDrawing;
use crate::geom::DVec3;
use crate::scene::{Block, ReconStatus, ViewEvidence};

/// One observed view: its line drawing (ground truth or vision), its camera, and the lights
/// known to have lit its picture.
#[derive(Debug, Clone)]
pub struct ObservedView {
    /// The line drawing in picture px.
    pub drawing: LineDrawing,
    /// The camera that took it.
    pub camera: Camera,
    /// Unit vectors from the scene towards each light that lit the picture (world frame, y
    /// up); empty when the lighting is unknown. With the pictures, step 6 tells the edges of
    /// the shadows an answer casts under them from block edges (docs/recognizer-pictures.md
    /// "Known lights").
    pub towards_lights: Vec<DVec3>,
    /// Radius of the blocks' rounded edges, mm, when known; 0 for sharp or unknown edges.
    /// Placement then expects outline corners where rounded outlines put them
    /// (docs/recognizer-pictures.md "Known edge rounding").
    pub edge_radius_mm: f64,
}

impl ObservedView {
    /// `drawing` seen by `camera` under unknown lights.
    pub fn new(drawing: LineDrawing, camera: Camera) -> ObservedView {
        ObservedView {
            drawing,
            camera,
            towards_lights: Vec::new(),
            edge_radius_mm: 0.0,
        }
    }

    /// This view with its drawing replaced by `drawing` (the same camera and lights).
    pub fn with_drawing(&self, drawing: LineDrawing) -> ObservedView {
        ObservedView {
            drawing,
            camera: self.camera,
            towards_lights: self.towards_lights.clone(),
            edge_radius_mm: self.edge_radius_mm,
        }
    }
}

/// Options of [`recognize`]: tolerances and search limits, with the unit in each name.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RecognizeOptions {
    /// Points closer than this are the same point, px; default 2 (the vision front end's
    /// vertices lie within 0.5 px on average, docs/vision.md "Vision front end").
    pub tol_px: f64,
    /// Highest top face considered, mm; default 120 (eight 15 mm layers).
    pub max_height_mm: f64,
    /// Catalog-match tolerances.
    pub matching: MatchTolerances,
    /// Lines more than this off every world axis mean blocks not in one direction, degrees;
    /// default 3.
    pub axis_tol_deg: f64,
    /// Candidates redrawn exactly per search step before looking further; default 8.
    pub shortlist: usize,
    /// Most candidates redrawn per search step; default 64.
    pub max_redraws_per_step: usize,
    /// Most blocks in an answer; default 40.
    pub max_blocks: usize,
    /// Repair rounds of the search when views stay unexplained; default 4.
    pub repair_rounds: usize,
    /// Most nodes (candidates weighed) the search spends before declining; default
    /// [`DEFAULT_NODE_BUDGET`] (docs/limits.md "Recognizer").
    pub node_budget: u64,
    /// Most seconds the search spends before declining; default [`DEFAULT_TIME_BUDGET_S`].
    pub time_budget_s: f64,
    /// Each view's corners alone must place every block to an exact answer's precision
    /// (`placement::misplaced_in_a_view`); default `false`, the views' corners together. A
    /// second reading of fainter lines sets it (docs/recognizer-pictures.md "A second reading
    /// of fainter lines").
    pub every_view_places: bool,
    /// At least two views must each fix every group's place by their own corners
    /// (`placement::unmeasured_in_views`); default `false`. The last reading, along the block
    /// directions, sets it (docs/recognizer-pictures.md "Steps read along the block
    /// directions").
    pub two_views_place: bool,
    /// The pitch of the grid the blocks stand on, mm, when it is known: every block's least x
    /// and z a multiple of it in the cameras' world frame (the Fischer-Technik grid of 7.5 mm,
    /// on which `generate`'s supported families put every block, docs/datasets.md
    /// "Families"). Placement then puts each block on the nearest grid place and holds the
    /// views to that place within `placement::GRID_SNAP_MM` (docs/recognizer-pictures.md
    /// "Blocks on a known grid"); default `None`, blocks anywhere.
    pub grid_mm: Option<f64>,
}

/// The search's default node budget: the hardest scene of the suites and the accuracy gate
/// needs 2,953,551 nodes (docs/limits.md "Recognizer").
pub const DEFAULT_NODE_BUDGET: u64 = 5_000_000;

/// The search's default time budget, s: far above what the node budget takes on the test
/// machine, so the node budget, which does not depend on the machine, decides.
pub const DEFAULT_TIME_BUDGET_S: f64 = 120.0;

impl Default for RecognizeOptions {
    fn default() -> Self {
        RecognizeOptions {
            tol_px: 2.0,
            max_height_mm: 120.0,
            matching: MatchTolerances::default(),
            axis_tol_deg: 3.0,
            shortlist: 8,
            max_redraws_per_step: 64,
            max_blocks: 40,
            repair_rounds: 4,
            node_budget: DEFAULT_NODE_BUDGET,
            time_budget_s: DEFAULT_TIME_BUDGET_S,
            every_view_places: false,
            two_views_place: false,
            grid_mm: None,
        }
    }
}

/// Why the recognizer declined (status `unsupported`), in the thesis's words.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Decline {
    /// Curved lines: a round part (Chapter VII's "circles").
    #[error("view {view}: {count} lines form curved chains (ellipse-like: a round part's rim); with blocks like pyramids or circles the parallelogram surface searching fails (Chapter VII)")]
    RoundParts {
        /// The view's name.
        view: String,
        /// How many lines.
        count: usize,
    },
    /// A sloped face (a trapezoidal block, told from the solid blocks by its gradient) where
    /// no catalog trapezoidal block placed from the sloped faces explains the views.
    #[error("view {view} not explained: the drawings show a sloped face, a trapezoidal block distinguished from solid blocks by the gradient constraints (Chapter VII, Figure 7.1), but no trapezoidal block of the catalog placed from its sloped faces explains them")]
    TrapezoidalBlock {
        /// The first view not explained.
        view: String,
    },
    /// Lines within 2 degrees of horizontal (Chapter IV's six directions do not cover them).
    #[error("view {view}: {count} lines fall in no six-bit direction (Chapter IV); blocks are not in one direction (Chapter VII)")]
    UnclassifiedLines {
        /// The view's name.
        view: String,
        /// How many lines.
        count: usize,
    },
    /// Lines along no world axis.
    #[error("view {view}: {count} lines run along no block axis: blocks not in one direction (yaw not a multiple of 90 degrees, Chapter VII)")]
    NotOneDirection {
        /// The view's name.
        view: String,
        /// How many lines.
        count: usize,
    },
    /// The verified answer has an upper block larger than what it rests on.
    #[error("upper layer larger than the layer below (Chapter VII, Figure 7.2): block {block} overhangs its support")]
    UpperLayerLarger {
        /// Index of the overhanging block in the hypothesis.
        block: usize,
    },
    /// Another set of catalog blocks explains every view equally well.
    #[error("the views do not decide the blocks: {detail}")]
    Ambiguous {
        /// Which blocks, and how.
        detail: String,
    },
    /// A block with nothing under it.
    #[error("block {block} has no visible support (Chapter VII: every block touches the floor or another block)")]
    HiddenSupport {
        /// Index of the floating block in the hypothesis.
        block: usize,
    },
    /// The search spent its node or time budget (docs/limits.md "Recognizer").
    #[error("search budget of {node_budget} nodes / {time_budget_s} s spent: {detail}; recognize fewer blocks at a time, or raise the budget (docs/limits.md \"Recognizer\")")]
    SearchBudget {
        /// The node budget.
        node_budget: u64,
        /// The time budget, s.
        time_budget_s: f64,
        /// Which ran out, after how much.
        detail: String,
    },
    /// The views do not place a block as precisely as an exact answer needs.
    #[error("block {block} is not placed to an exact answer's precision: every view's corners together put its group {shift_mm:.2} mm from where it stands and the views do not agree on the shift (step 6 holds each corner to its 2 px tolerance; an answer overlapping the truth by less than 0.99 is not exact)")]
    Imprecise {
        /// Index of the block in the hypothesis.
        block: usize,
        /// Length of the group's fitted horizontal shift, mm.
        shift_mm: f64,
    },
    /// One view's corners alone put a block off its place by more than an exact answer allows
    /// ([`RecognizeOptions::every_view_places`]).
    #[error("block {block} is not placed to an exact answer's precision by view {view} alone (when lines are set aside or read again fainter, every view's corners must place each block)")]
    ImpreciseInAView {
        /// Index of the block in the hypothesis.
        block: usize,
        /// The view whose corners put it off.
        view: String,
    },
    /// Fewer than two views place a block's group by their own corners
    /// ([`RecognizeOptions::two_views_place`]).
    #[error("block {block} is not placed to an exact answer's precision: {views} of the views fix its place by their own corners (when the pictures are read along the block directions, at least two views must)")]
    UnmeasuredInViews {
        /// Index of the block in the hypothesis.
        block: usize,
        /// How many views fix its group's shift by themselves.
        views: usize,
    },
    /// No block in any view: an answer without blocks explains nothing.
    #[error("no block found in the views ({points} points, {lines} lines drawn in all): an answer without blocks explains nothing; give views that show the blocks, pictures at least 8 px a side (docs/limits.md \"Render\")")]
    NoBlocks {
        /// Points of all views' drawings.
        points: usize,
        /// Lines of all views' drawings.
        lines: usize,
    },
    /// The best hypothesis does not explain a view.
    #[error("view {view} not explained by catalog blocks: {} observed points and {} lines unexplained, {} points and {} lines drawn in excess (shapes outside the catalog or occlusion the views cannot resolve)", .check.unexplained_points, .check.unexplained_lines, .check.extra_points, .check.extra_lines)]
    Unexplained {
        /// The view's name.
        view: String,
        /// Its comparison.
        check: ViewCheck,
    },
}

/// How the pipeline's must-stand check opens its decline (docs/recognizer.md "Reconstructions
/// that must stand"): one phrase for the message and for [`DECLINE_KINDS`].
pub const NOT_STANDING: &str = "the reconstruction would not stand";

/// Each kind of [`Decline`] by a short name (for grouping answers, e.g. in `blockworld report`)
/// and a phrase that its message holds and no other kind's message does.
/// The last kind is the pipeline's must-stand check (docs/recognizer.md "Reconstructions that
/// must stand"), which declines after the recognizer has answered.
pub const DECLINE_KINDS: [(&str, &str); 12] = [
    ("round parts", "curved chains"),
    ("trapezoidal block", "show a sloped face"),
    ("unclassified lines", "fall in no six-bit direction"),
    ("not one direction", "run along no block axis"),
    ("upper layer larger", "upper layer larger"),
    ("ambiguous", "the views do not decide"),
    ("hidden support", "has no visible support"),
    ("search budget spent", "search budget of"),
    (
        "imprecise place",
        "not placed to an exact answer's precision",
    ),
    ("view not explained", "not explained by catalog blocks"),
    ("no blocks", "no block found in the views"),
    ("would not stand", NOT_STANDING),
];

/// The short name of the [`Decline`] whose message is `reason` ([`DECLINE_KINDS`]); `"other"`
/// for a reason no kind's phrase is in.
pub fn decline_kind(reason: &str) -> &'static str {
    DECLINE_KINDS
        .iter()
        .find(|(_, phrase)| reason.contains(phrase))
        .map_or("other", |(name, _)| name)
}

/// Bad input to [`recognize`] (a programming or file error, not a scene the method declines).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RecognizeError {
    /// No views given.
    #[error("no views to recognize: give at least one line drawing with its camera")]
    NoViews,
    /// Pictures given, but not one per view.
    #[error("{pictures} pictures for {views} views: give one picture per view, in the views' order, or none")]
    PictureCount {
        /// How many views.
        views: usize,
        /// How many pictures.
        pictures: usize,
    },
    /// A drawing refers to points it does not have, or has non-finite points.
    #[error("view {view}: {problem}; re-create the drawing (lines_<view>.json) with `blockworld render` or the vision front end")]
    BadDrawing {
        /// The view's name.
        view: String,
        /// What is wrong.
        problem: String,
    },
}

/// The recognizer's evidence: per-view counts, pooled candidates and the hypothesis tested.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Evidence {
    /// One entry per view, in input order: what it contributed and how the final answer's
    /// drawing compares with it (the reconstruction file's `evidence`, one type for both).
    pub views: Vec<ViewEvidence>,
    /// Distinct candidate blocks after pooling the views (when the direct path answered: the
    /// candidates read exactly from closed parallelograms, all it pools).
    pub pooled_candidates: usize,
    /// The blocks the search chose (also when declined).
    pub hypothesis: Vec<Block>,
}

/// The recognizer's answer: placed catalog blocks with a status and reason, the layers and
/// touching pairs, and the evidence. Converts 1:1 to a reconstruction [`Scene`].
#[derive(Debug, Clone, PartialEq)]
pub struct Recognition {
    /// The blocks (empty when declined).
    pub blocks: Vec<Block>,
    /// `Ok` or `Unsupported`.
    pub status: ReconStatus,
    /// Why it declined.
    pub reason: Option<String>,
    /// The layers of `blocks`, lowest first.
    pub layers: Vec<Layer>,
    /// Pairs of `blocks` that touch.
    pub touching: Vec<[usize; 2]>,
    /// How the answer was reached.
    pub evidence: Evidence,
}

impl Recognition {
    /// The answer `Unsupported` for `decline`, with the evidence gathered so far.
    pub(super) fn declined(decline: Decline, evidence: Evidence) -> Recognition {
        Recognition {
            blocks: Vec::new(),
            status: ReconStatus::Unsupported,
            reason: Some(decline.to_string()),
            layers: Vec::new(),
            touching: Vec::new(),
            evidence,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_decline_has_its_own_kind() {
        let check = ViewCheck {
            unexplained_points: 1,
            extra_points: 0,
            unexplained_lines: 2,
            extra_lines: 0,
        };
        let view = || "ne".to_string();
        let all = [
            Decline::RoundParts {
                view: view(),
                count: 3,
            },
            Decline::TrapezoidalBlock { view: view() },
            Decline::UnclassifiedLines {
                view: view(),
                count: 2,
            },
            Decline::NotOneDirection {
                view: view(),
                count: 4,
            },
            Decline::UpperLayerLarger { block: 1 },
            Decline::Ambiguous {
                detail: "a b30 or two b15".into(),
            },
            Decline::HiddenSupport { block: 2 },
            Decline::SearchBudget {
                node_budget: 10,
                time_budget_s: 1.0,
                detail: "10 nodes".into(),
            },
            Decline::Imprecise {
                block: 0,
                shift_mm: 0.2,
            },
            Decline::Unexplained {
                view: view(),
                check,
            },
            Decline::NoBlocks {
                points: 0,
                lines: 0,
            },
        ];
        let mut kinds: Vec<&str> = all.iter().map(|d| decline_kind(&d.to_string())).collect();
        kinds.push(decline_kind(
            "the reconstruction would not stand (settled with rapier): block 1 overhang",
        ));
        let names: Vec<&str> = DECLINE_KINDS.iter().map(|(n, _)| *n).collect();
        assert_eq!(kinds, names);
        assert_eq!(decline_kind("the disk is full"), "other");
    }
}
