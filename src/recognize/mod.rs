//! The modified Kanade recognizer (thesis Chapters IV and V, flow chart Figure 5.3): from the
//! line drawings of one or more corner views and their cameras, the placed catalog blocks.
//!
//! 1. [`select_vertices`]: the "Y" and collinear "T" vertices, sorted by picture y (Figure 5.1).
//! 2. [`ParallelogramSearch`]: from each, along the directions its six-bit code allows, close
//!    the top face (Figure 4.5); vertex, height and side lengths in px, converted to mm through
//!    the camera's rays ([`measure_parallelogram_mm`], [`point_at_height_mm`],
//!    [`drop_below_mm`]).
//! 3. [`catalog_candidates`]: the catalog blocks (yaw 0 or 90) those measurements fit, at every
//!    layer height (sums of catalog heights, bottom layer at y = 0); [`classify_layers`] and
//!    [`touching_pairs`] for the answer. When some view shows a sloped face (Chapter VII,
//!    Figure 7.1: the gradient tells a trapezoidal block from a solid one), also the
//!    trapezoidal blocks its gradient turns and its corners place ([`trapezoid_proposals`]).
//! 4. [`pool_candidates`]: the views compared (Chapter V's three rules), a block hidden in one
//!    view recovered from another; any subset of the four views. Then the direct path of
//!    Figure 5.3 ([`direct_hypothesis`]: well-supported candidates, lowest level first), and
//!    only when its drawing does not explain every view the search [`choose_blocks`].
//! 5. CSG: in the `csg` stage.
//! 6. [`check_hypothesis`]: the answer's own exact line drawing (`linedraw`) held against
//!    every observed view; `ok` only when every view is explained and no split or merged
//!    alternative explains them equally well ([`equally_good_alternative`]), otherwise
//!    `unsupported` with the reason, as also for what Chapter VII says the method cannot do
//!    ([`curved_chain_lines`], [`lines_off_the_axes`], [`overhanging_blocks`],
//!    [`floating_blocks`]).

mod ambiguity;
mod catalog_match;
mod compare;
mod constraints;
mod direct;
mod parallelogram;
mod picture;
mod repair;
mod select;
mod trapezoid;
mod verify;

/// The camera types this stage and `csg` use (the one import of them, so the camera's move to
/// its own module is a one-line change).
pub(crate) use crate::camera::Camera;
#[cfg(test)]
pub(crate) use crate::camera::{CameraOptions, CornerView, Projection};

pub use ambiguity::equally_good_alternative;
pub use catalog_match::{
    blocks_overlap, bounds_mm, catalog_candidates, catalog_proposals, catalog_proposals_where,
    classify_layers, distinct_yaws_deg, level_heights_mm, make_touching_flush,
    measure_parallelogram_mm, touching_pairs, Layer, MatchTolerances, ParallelogramMm, Proposal,
};
pub use compare::{
    catalog_merge, catalog_splits, choose_blocks, pool_candidates, pool_proposals, yaw_deg,
    PooledCandidate, SearchLimits, FLUSH_TOL_MM,
};
pub use constraints::{
    curved_chain_lines, floating_blocks, lines_off_the_axes, overhanging_blocks,
};
pub use direct::{direct_hypothesis, well_supported};
pub use parallelogram::{
    drop_below_mm, horizontal_axis_for, point_at_height_mm, ChainStop, Face, Parallelogram,
    ParallelogramSearch, TopCorner,
};
pub use picture::{
    edge_profile, picture_check, picture_mismatch, pictures_mismatch, without_weak_lines,
    EdgeProfile, ViewPicture, CRACK_ALLOWANCE_MM,
};
pub use select::{is_searched_junction, select_vertices, SelectedVertex};
pub use trapezoid::{
    face_gradients, facing_yaw_deg, line_world_direction, sloped_faces, sloped_lines,
    trapezoid_proposals, trapezoidal_blocks, FaceGradient,
};
pub use verify::{
    blocks_drawn_in_excess, check_hypothesis, compare_drawings, distance_to_segment_px,
    draw_hypothesis, mismatched_features, unexplained_pieces, ViewCheck, ViewMismatch,
};

use crate::drawing::LineDrawing;
use crate::scene::{Block, ReconStatus, ViewEvidence};
use ambiguity::alternative_given_drawings;
use compare::{choose_hypothesis, greedy_and_split_from, Hypothesis};
use direct::{direct_hypothesis_within, Silhouettes};
use repair::repaired_in_pictures;

/// One observed view: its line drawing (ground truth or vision) and its camera.
#[derive(Debug, Clone)]
pub struct ObservedView {
    /// The line drawing in picture px.
    pub drawing: LineDrawing,
    /// The camera that took it.
    pub camera: Camera,
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
}

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
    /// The best hypothesis does not explain a view.
    #[error("view {view} not explained by catalog blocks: {} observed points and {} lines unexplained, {} points and {} lines drawn in excess (shapes outside the catalog or occlusion the views cannot resolve)", .check.unexplained_points, .check.unexplained_lines, .check.extra_points, .check.extra_lines)]
    Unexplained {
        /// The view's name.
        view: String,
        /// Its comparison.
        check: ViewCheck,
    },
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
    fn declined(decline: Decline, evidence: Evidence) -> Recognition {
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

fn check_drawing(view: &ObservedView) -> Result<(), RecognizeError> {
    let d = &view.drawing;
    let bad = |problem: String| RecognizeError::BadDrawing {
        view: view.camera.view.name().to_string(),
        problem,
    };
    if let Some(p) = d.points.iter().find(|p| !p.is_finite()) {
        return Err(bad(format!("point {p} is not finite")));
    }
    if let Some(l) = d
        .lines
        .iter()
        .find(|l| l.iter().any(|&i| i >= d.points.len()))
    {
        return Err(bad(format!(
            "line {l:?} refers to a point beyond the {} points",
            d.points.len()
        )));
    }
    if d.codes.len() != d.points.len() || d.junctions.len() != d.points.len() {
        return Err(bad("codes or junctions are not one per point".to_string()));
    }
    Ok(())
}

/// Chapter VII's constraints on the observed drawings, before any search: no curved edges
/// (round parts), every line in a six-bit direction and along a block axis, except, once some
/// view shows a sloped face (a trapezoidal block, Figure 7.1), the lines along its slopes.
/// `Ok(true)` when a sloped face was seen: trapezoidal blocks join the candidates.
fn check_directions(views: &[ObservedView], opts: &RecognizeOptions) -> Result<bool, Decline> {
    for v in views {
        let curved = curved_chain_lines(&v.drawing);
        if !curved.is_empty() {
            let view = v.camera.view.name().to_string();
            let count = curved.len();
            return Err(Decline::RoundParts { view, count });
        }
    }
    let tol = opts.axis_tol_deg;
    let trapezoids = views
        .iter()
        .any(|v| !sloped_faces(&v.drawing, &v.camera, tol).is_empty());
    for v in views {
        let view = v.camera.view.name().to_string();
        let slopes = if trapezoids {
            sloped_lines(&v.drawing, &v.camera, tol)
        } else {
            Vec::new()
        };
        let unclassified = v.drawing.unclassified_lines.iter();
        let count = unclassified.filter(|l| !slopes.contains(l)).count();
        if count > 0 {
            return Err(Decline::UnclassifiedLines { view, count });
        }
        let off = lines_off_the_axes(&v.drawing, &v.camera, tol);
        let count = off.iter().filter(|l| !slopes.contains(l)).count();
        if count > 0 {
            return Err(Decline::NotOneDirection { view, count });
        }
    }
    Ok(trapezoids)
}

/// Steps 1-3 on one view: its proposals (only those fitting a closed parallelogram exactly,
/// with their top corner where `corner_ok` accepts it, when `fit_only`) and evidence counts.
/// With `trapezoids`, also the trapezoidal blocks its sloped faces propose (Figure 7.1).
fn propose(
    view: &ObservedView,
    levels: &[f64],
    opts: &RecognizeOptions,
    (fit_only, trapezoids): (bool, bool),
    corner_ok: &dyn Fn(crate::geom::DVec3) -> bool,
) -> (Vec<Proposal>, ViewEvidence) {
    let selected = select_vertices(&view.drawing);
    let search = ParallelogramSearch::new(&view.drawing, opts.tol_px);
    let mut ev = ViewEvidence {
        view: view.camera.view.name().to_string(),
        selected_vertices: selected.len(),
        parallelograms: 0,
        closed_parallelograms: 0,
        ..ViewEvidence::default()
    };
    let mut out = Vec::new();
    for v in &selected {
        for face in Face::ALL {
            let Some(p) = search.search(v, face) else {
                continue;
            };
            ev.parallelograms += 1;
            ev.closed_parallelograms += usize::from(p.closed.is_some());
            if fit_only && p.closed.is_none() {
                // Only a closed parallelogram fits a block exactly (`Proposal::closed_fit`).
                continue;
            }
            let (drawing, camera) = (&view.drawing, &view.camera);
            let proposals =
                catalog_proposals_where(&p, drawing, camera, levels, &opts.matching, corner_ok);
            out.extend(proposals.into_iter().filter(|c| c.closed_fit || !fit_only));
        }
    }
    if trapezoids {
        let (drawing, camera, tol) = (&view.drawing, &view.camera, &opts.matching);
        let sloped =
            trapezoid_proposals(drawing, camera, levels, tol, opts.axis_tol_deg, corner_ok);
        out.extend(sloped.into_iter().filter(|c| c.closed_fit || !fit_only));
    }
    ev.proposals = out.len();
    (out, ev)
}

/// Codes, junctions and unclassified lines from each drawing's own geometry
/// (`LineDrawing::finalize`), so the selection does not depend on which front end drew it.
fn normalize_views(views: &[ObservedView]) -> Vec<ObservedView> {
    views
        .iter()
        .map(|v| {
            let mut drawing = v.drawing.clone();
            drawing.finalize();
            ObservedView {
                drawing,
                camera: v.camera,
            }
        })
        .collect()
}

/// Blocks closer than this in mm are one candidate, share a layer, touch, or rest on each
/// other (far below any catalog size, far above the measurement error).
pub const SAME_PLACE_TOL_MM: f64 = 0.5;

/// Steps 1-3 on every view and the pooling of step 4: the pooled candidates, with the views'
/// evidence counts recorded in `evidence`. For the direct path (`direct_within` given: only
/// exact fits), a level is read only where the measured top corner is seen inside every view's
/// silhouette, as the direct path requires of every corner of the blocks it takes
/// ([`direct_hypothesis`]). With `trapezoids`, the sloped faces' trapezoidal blocks too.
fn propose_and_pool(
    views: &[ObservedView],
    opts: &RecognizeOptions,
    (direct_within, trapezoids): (Option<&Silhouettes>, bool),
    evidence: &mut Evidence,
) -> Vec<PooledCandidate> {
    let levels = level_heights_mm(opts.max_height_mm);
    evidence.views.clear();
    let fit_only = direct_within.is_some();
    let corner_ok = |q: crate::geom::DVec3| direct_within.is_none_or(|s| s.hold(q, opts.tol_px));
    let mut per_view = Vec::new();
    for v in views {
        let (proposals, ev) = propose(v, &levels, opts, (fit_only, trapezoids), &corner_ok);
        per_view.push(proposals);
        evidence.views.push(ev);
    }
    let pool = pool_proposals(&per_view, SAME_PLACE_TOL_MM);
    evidence.pooled_candidates = pool.len();
    pool
}

/// Step 4's choice. The direct path first, on the candidates read exactly from closed
/// parallelograms: its hypothesis when its drawing explains every view, else the same without
/// the blocks it draws in excess. Failing that, every candidate is pooled and the search
/// continues from there, then starts from nothing. With the views' `pictures`, a hypothesis
/// that the drawings alone do not explain is taken when the picture-aware check explains it
/// ([`picture_check`]), the direct one before the pruned one.
fn find_hypothesis(
    views: &[ObservedView],
    opts: &RecognizeOptions,
    (limits, trapezoids): (&SearchLimits, bool),
    pictures: &[ViewPicture],
    evidence: &mut Evidence,
) -> Hypothesis {
    let explained = |h: &Hypothesis| {
        !pictures.is_empty()
            && checks_in_pictures(h, views, pictures, limits.tol_px)
                .iter()
                .all(ViewCheck::is_explained)
    };
    let silhouettes = Silhouettes::new(views);
    let direct_within = (Some(&silhouettes), trapezoids);
    let exact = propose_and_pool(views, opts, direct_within, evidence);
    let blocks = direct_hypothesis_within(&exact, views, &silhouettes, limits.tol_px);
    let direct = Hypothesis::new(blocks, views, limits.tol_px);
    if direct.mismatch() == 0 {
        return direct;
    }
    let pruned = without_excess(direct.clone(), views, limits.tol_px);
    if pruned.mismatch() == 0 {
        return pruned;
    }
    if explained(&direct) {
        return direct;
    }
    if explained(&pruned) {
        return pruned;
    }
    let pool = propose_and_pool(views, opts, (None, trapezoids), evidence);
    let (_, continued) = greedy_and_split_from(&pool, views, limits, &[], pruned);
    if continued.mismatch() == 0 || explained(&continued) {
        return continued;
    }
    let chosen = choose_hypothesis(&pool, views, limits);
    if chosen.mismatch() == 0 || pictures.is_empty() || explained(&chosen) {
        return chosen;
    }
    let repaired = repaired_in_pictures(&chosen, &pool, views, limits, &explained).or_else(|| {
        // The same blocks have the same neighbours: tried once.
        (continued.blocks != chosen.blocks)
            .then(|| repaired_in_pictures(&continued, &pool, views, limits, &explained))
            .flatten()
    });
    repaired.unwrap_or(chosen)
}

/// Each view's step-6 comparison of `h`: with the views' pictures, by the picture-aware check
/// ([`pictures_mismatch`]) unless the drawings alone explain every view.
fn checks_in_pictures(
    h: &Hypothesis,
    views: &[ObservedView],
    pictures: &[ViewPicture],
    tol_px: f64,
) -> Vec<ViewCheck> {
    if pictures.len() != views.len() || h.checks.iter().all(ViewCheck::is_explained) {
        return h.checks.clone();
    }
    let observed: Vec<&LineDrawing> = views.iter().map(|v| &v.drawing).collect();
    pictures_mismatch(&h.drawn, &observed, pictures, tol_px)
        .iter()
        .map(ViewMismatch::counts)
        .collect()
}

/// `h` without every block that draws a line no observed line explains, in some view (a
/// candidate that would be seen where nothing is), checked again.
fn without_excess(h: Hypothesis, views: &[ObservedView], tol_px: f64) -> Hypothesis {
    let excess: Vec<usize> = views
        .iter()
        .zip(&h.drawn)
        .flat_map(|(v, d)| blocks_drawn_in_excess(d, &v.drawing, tol_px))
        .collect();
    if excess.is_empty() {
        return h;
    }
    let kept: Vec<Block> = (0..h.blocks.len())
        .filter(|i| !excess.contains(i))
        .map(|i| h.blocks[i])
        .collect();
    Hypothesis::new(kept, views, tol_px)
}

/// Step 6 and Chapter VII on the chosen blocks: why to decline, if at all (step 6 by the
/// picture-aware check when the views' pictures are given).
fn final_checks(
    h: &Hypothesis,
    views: &[ObservedView],
    pictures: &[ViewPicture],
    opts: &RecognizeOptions,
) -> Option<Decline> {
    let blocks = &h.blocks[..];
    let checks = checks_in_pictures(h, views, pictures, opts.tol_px);
    if let Some((v, c)) = views.iter().zip(&checks).find(|(_, c)| !c.is_explained()) {
        let view = v.camera.view.name().to_string();
        return Some(Decline::Unexplained { view, check: *c });
    }
    let alternative = alternative_given_drawings(blocks, views, &h.drawn, opts.tol_px, pictures);
    if let Some(detail) = alternative {
        return Some(Decline::Ambiguous { detail });
    }
    if let Some(&block) = overhanging_blocks(blocks, SAME_PLACE_TOL_MM, 1.0).first() {
        return Some(Decline::UpperLayerLarger { block });
    }
    floating_blocks(blocks, SAME_PLACE_TOL_MM)
        .first()
        .map(|&block| Decline::HiddenSupport { block })
}

/// Recognizes the blocks seen in `views` (any subset of the four corner views): thesis
/// Chapters IV-V with the check of step 6. Declining is an `Ok(Recognition)` with status
/// `Unsupported`; an `Err` means the input itself is malformed.
pub fn recognize(
    views: &[ObservedView],
    opts: &RecognizeOptions,
) -> Result<Recognition, RecognizeError> {
    recognize_in_pictures(views, &[], opts)
}

/// [`recognize`] with the pictures the views' drawings were read from (one per view, in the
/// same order; none = [`recognize`]): step 6 then asks the picture where a hypothesis's exact
/// redraw and a vision drawing differ ([`picture_check`], docs/recognizer.md "Recognizer"): an edge too
/// faint for the front end is confirmed by a step or crack across it, a drawing feature the
/// redraw lacks is tolerated only when the picture shows it weak. The answer still comes from
/// the drawings alone.
pub fn recognize_in_pictures(
    views: &[ObservedView],
    pictures: &[&image::GrayImage],
    opts: &RecognizeOptions,
) -> Result<Recognition, RecognizeError> {
    if views.is_empty() {
        return Err(RecognizeError::NoViews);
    }
    if !pictures.is_empty() && pictures.len() != views.len() {
        return Err(RecognizeError::PictureCount {
            views: views.len(),
            pictures: pictures.len(),
        });
    }
    views.iter().try_for_each(check_drawing)?;
    let pictures = read_pictures(views, pictures, opts);
    let mut views = normalize_views(views);
    drop_weak_off_axis_lines(&mut views, &pictures, opts);
    let views = &views[..];
    let mut evidence = Evidence::default();
    let trapezoids = match check_directions(views, opts) {
        Ok(t) => t,
        Err(d) => return Ok(Recognition::declined(d, evidence)),
    };
    let limits = SearchLimits {
        tol_px: opts.tol_px,
        shortlist: opts.shortlist,
        max_redraws_per_step: opts.max_redraws_per_step,
        max_blocks: opts.max_blocks,
        repair_rounds: opts.repair_rounds,
    };
    let search = (&limits, trapezoids);
    let h = find_hypothesis(views, opts, search, &pictures, &mut evidence);
    for (ev, c) in evidence.views.iter_mut().zip(&h.checks) {
        ev.unexplained_points = c.unexplained_points;
        ev.extra_points = c.extra_points;
        ev.unexplained_lines = c.unexplained_lines;
        ev.extra_lines = c.extra_lines;
    }
    evidence.hypothesis = h.blocks.clone();
    if let Some(d) = final_checks(&h, views, &pictures, opts) {
        let placed = h
            .blocks
            .iter()
            .any(|b| b.block_type.cuboid_half_extents_mm().is_none());
        let d = match d {
            Decline::Unexplained { view, .. } if trapezoids && !placed => {
                Decline::TrapezoidalBlock { view }
            }
            d => d,
        };
        return Ok(Recognition::declined(d, evidence));
    }
    let blocks = h.blocks;
    Ok(Recognition {
        layers: classify_layers(&blocks, SAME_PLACE_TOL_MM),
        touching: touching_pairs(&blocks, SAME_PLACE_TOL_MM),
        blocks,
        status: ReconStatus::Ok,
        reason: None,
        evidence,
    })
}

/// The views' pictures with their noise and scale ([`ViewPicture::new`]); none when any is too
/// coarse for the tolerance (`ViewPicture::fine_enough`): such pictures are not read at all.
fn read_pictures<'a>(
    views: &[ObservedView],
    pictures: &[&'a image::GrayImage],
    opts: &RecognizeOptions,
) -> Vec<ViewPicture<'a>> {
    let pictures: Vec<ViewPicture> = views
        .iter()
        .zip(pictures)
        .map(|(v, g)| ViewPicture::new(g, &v.camera))
        .collect();
    if pictures.iter().all(|p| p.fine_enough(opts.tol_px)) {
        pictures
    } else {
        Vec::new()
    }
}

/// Drops from each view's drawing the lines along no block axis (and the unclassified ones,
/// curves kept) that its picture shows weak ([`without_weak_lines`]).
fn drop_weak_off_axis_lines(
    views: &mut [ObservedView],
    pictures: &[ViewPicture],
    opts: &RecognizeOptions,
) {
    for (v, pic) in views.iter_mut().zip(pictures) {
        let mut off = lines_off_the_axes(&v.drawing, &v.camera, opts.axis_tol_deg);
        off.extend(v.drawing.unclassified_lines.iter().copied());
        off.retain(|k| !v.drawing.curved_lines.contains(k));
        if !off.is_empty() {
            v.drawing = without_weak_lines(&v.drawing, &off, pic);
        }
    }
}

/// The exact views of `blocks` from the corner views `which`, framed as `render` frames them:
/// the observed input of the recognizer's unit tests.
#[cfg(test)]
pub(crate) fn views_of(blocks: &[Block], which: &[CornerView]) -> Vec<ObservedView> {
    let pts: Vec<crate::geom::DVec3> = blocks.iter().flat_map(|b| b.world_vertices()).collect();
    which
        .iter()
        .map(|&v| {
            let camera = Camera::frame(&pts, v, &CameraOptions::default());
            let drawing = draw_hypothesis(blocks, &camera);
            ObservedView { drawing, camera }
        })
        .collect()
}

/// `b15` cubes of a 3 x 3 grid, 15 mm apart: the `layer`-th layer's cells `cells` (row-major,
/// x fastest); the stacks of the recognizer's unit tests.
#[cfg(test)]
pub(crate) fn grid_cubes(layer: usize, cells: &[usize]) -> Vec<Block> {
    cells
        .iter()
        .map(|&k| {
            let centre = crate::geom::DVec3::new(
                (k % 3) as f64 * 15.0,
                layer as f64 * 15.0 + 7.5,
                (k / 3) as f64 * 15.0,
            );
            Block::new("b15", centre, 0.0)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::DVec3;

    #[test]
    fn a_two_layer_stack_is_recognized_from_two_opposite_views() {
        let truth = vec![
            Block::new("b30", DVec3::new(15.0, 7.5, 7.5), 0.0),
            Block::new("b15", DVec3::new(7.5, 22.5, 7.5), 0.0),
        ];
        let views = views_of(&truth, &[CornerView::Ne, CornerView::Sw]);
        let r = recognize(&views, &RecognizeOptions::default()).unwrap();
        assert_eq!(r.status, ReconStatus::Ok, "{:?}", r.reason);
        assert_eq!(r.blocks.len(), 2);
        for t in &truth {
            assert!(r
                .blocks
                .iter()
                .any(|b| b.block_type.id == t.block_type.id
                    && b.center_mm.distance(t.center_mm) < 1e-6));
        }
        assert_eq!(r.layers.len(), 2);
        assert_eq!(r.touching, vec![[0, 1]]);
    }

    #[test]
    fn a_perspective_view_pair_is_recognized_too() {
        let truth = vec![Block::new("b30", DVec3::new(15.0, 7.5, 7.5), 90.0)];
        let pts: Vec<DVec3> = truth[0].world_vertices();
        let opts = CameraOptions {
            projection: Projection::Perspective { fov_y_deg: 30.0 },
            ..CameraOptions::default()
        };
        let views: Vec<ObservedView> = [CornerView::Ne, CornerView::Sw]
            .iter()
            .map(|&v| {
                let camera = Camera::frame(&pts, v, &opts);
                ObservedView {
                    drawing: draw_hypothesis(&truth, &camera),
                    camera,
                }
            })
            .collect();
        let r = recognize(&views, &RecognizeOptions::default()).unwrap();
        assert_eq!(r.status, ReconStatus::Ok, "{:?}", r.reason);
        assert!(r.blocks[0].center_mm.distance(truth[0].center_mm) < 0.05);
    }

    #[test]
    fn bad_input_is_an_error_and_a_turned_block_is_declined_by_name() {
        assert_eq!(
            recognize(&[], &RecognizeOptions::default()),
            Err(RecognizeError::NoViews)
        );
        let cube = vec![Block::new("b15", DVec3::new(0.0, 7.5, 0.0), 0.0)];
        let mut views = views_of(&cube, &[CornerView::Ne]);
        views[0].drawing.lines.push([0, 99]);
        assert!(matches!(
            recognize(&views, &RecognizeOptions::default()),
            Err(RecognizeError::BadDrawing { .. })
        ));
        let turned = vec![Block::new("b15", DVec3::new(0.0, 7.5, 0.0), 30.0)];
        let r = recognize(
            &views_of(&turned, &[CornerView::Ne]),
            &RecognizeOptions::default(),
        )
        .unwrap();
        assert_eq!(r.status, ReconStatus::Unsupported);
        assert!(r.reason.unwrap().contains("not in one direction"));
    }

    /// `true` when `got` holds the blocks of `truth`: same types, centres within 0.05 mm and
    /// the same orientation.
    fn same_blocks(got: &[Block], truth: &[Block]) -> bool {
        got.len() == truth.len()
            && truth.iter().all(|t| {
                got.iter().any(|b| {
                    b.block_type.id == t.block_type.id
                        && b.center_mm.distance(t.center_mm) < 0.05
                        && b.orientation == t.orientation
                })
            })
    }

    /// Chapter VII, Figure 7.1: a trapezoidal block facing each of the four ways, alone, on a
    /// Baustein 30 and carrying a cube on its flat top, is reconstructed with its turn from the
    /// four views.
    #[test]
    fn wedges_facing_each_way_are_reconstructed_with_their_turn() {
        for yaw in [0.0, 90.0, 180.0, 270.0] {
            let wedge = |y: f64| Block::new("w30", DVec3::new(0.0, y, 0.0), yaw);
            let flat_top = wedge(0.0).world_point(DVec3::new(-7.5, 22.5, 0.0));
            let b30_yaw = if yaw % 180.0 == 0.0 { 0.0 } else { 90.0 };
            let scenes = [
                vec![wedge(7.5)],
                vec![
                    Block::new("b30", DVec3::new(0.0, 7.5, 0.0), b30_yaw),
                    wedge(22.5),
                ],
                vec![wedge(7.5), Block::new("b15", flat_top, 0.0)],
            ];
            for truth in scenes {
                let views = views_of(&truth, &CornerView::ALL);
                let r = recognize(&views, &RecognizeOptions::default()).unwrap();
                assert_eq!(
                    r.status,
                    ReconStatus::Ok,
                    "yaw {yaw} {truth:?}: {:?}",
                    r.reason
                );
                assert!(same_blocks(&r.blocks, &truth), "yaw {yaw}: {:?}", r.blocks);
            }
        }
    }

    /// The check (step 6) refuses a wedge turned the wrong way: the true wedge's drawing explains
    /// every view, the same box facing any other way leaves some view unexplained.
    #[test]
    fn a_wedge_turned_the_wrong_way_is_refused_by_the_check() {
        let truth = [Block::new("w30", DVec3::new(0.0, 7.5, 0.0), 0.0)];
        let views = views_of(&truth, &CornerView::ALL);
        let explained = |b: &[Block]| {
            check_hypothesis(b, &views, 2.0)
                .iter()
                .all(ViewCheck::is_explained)
        };
        assert!(explained(&truth));
        for yaw in [90.0, 180.0, 270.0] {
            let turned = [Block::new("w30", truth[0].center_mm, yaw)];
            assert!(!explained(&turned), "yaw {yaw} explains the views");
        }
        // Nor does the box the wedge fills: a Baustein 30 there.
        assert!(!explained(&[Block::new("b30", truth[0].center_mm, 0.0)]));
    }
}
