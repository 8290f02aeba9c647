//! The modified Kanade recognizer (thesis Chapters IV and V, flow chart Figure 5.3): from the
//! line drawings of one or more corner views and their cameras, the placed catalog blocks.
//!
//! 1. [`steps::select_vertices`]: the "Y" and collinear "T" vertices, sorted by picture y (Figure 5.1).
//! 2. [`steps::ParallelogramSearch`]: from each, along the directions its six-bit code allows, close
//!    the top face (Figure 4.5); vertex, height and side lengths in px, converted to mm through
//!    the camera's rays ([`steps::measure_parallelogram_mm`], [`steps::point_at_height_mm`],
//!    [`steps::drop_below_mm`]).
//! 3. [`steps::catalog_candidates`]: the catalog blocks (yaw 0 or 90) those measurements fit, at every
//!    layer height (sums of catalog heights, bottom layer at y = 0); `classify_layers` and
//!    `touching_pairs` for the answer. When some view shows a sloped face (Chapter VII,
//!    Figure 7.1: the gradient tells a trapezoidal block from a solid one), also the
//!    trapezoidal blocks its gradient turns and its corners place (`trapezoid_proposals`).
//! 4. [`steps::pool_candidates`]: the views compared (Chapter V's three rules), a block hidden in one
//!    view recovered from another; any subset of the four views. Then the direct path of
//!    Figure 5.3 ([`steps::direct_hypothesis`]: well-supported candidates, lowest level first), and
//!    only when its drawing does not explain every view the search [`steps::choose_blocks`].
//! 5. CSG: in the `csg` stage.
//! 6. [`check_hypothesis`]: the answer's own exact line drawing (`linedraw`) held against
//!    every observed view; `ok` only when every view is explained and no split or merged
//!    alternative explains them equally well (`equally_good_alternative`), otherwise
//!    `unsupported` with the reason, as also for what Chapter VII says the method cannot do
//!    ([`steps::curved_chain_lines`], `lines_off_the_axes`, `overhanging_blocks`,
//!    `floating_blocks`).

mod ambiguity;
mod budget;
mod catalog_match;
mod compare;
mod constraints;
mod direct;
mod edge_profile;
mod floor_gray;
mod parallelogram;
mod picture;
mod placement;
mod repair;
mod rounding;
mod select;
mod set_aside;
mod shadow;
mod trapezoid;
mod verify;

mod answer;
mod flow;
pub mod steps;
#[cfg(test)]
mod tests;

pub use answer::{
    decline_kind, Evidence, ObservedView, Recognition, RecognizeError, RecognizeOptions,
    DECLINE_KINDS, NOT_STANDING,
};
pub use answer::{DEFAULT_NODE_BUDGET, DEFAULT_TIME_BUDGET_S};
pub use budget::{SearchBudget, SearchProgress};
pub use catalog_match::{Layer, MatchTolerances};
pub use placement::GRID_SNAP_MM;
pub use verify::{check_hypothesis, draw_hypothesis, ViewCheck};

pub(crate) use ambiguity::equally_good_alternative;
pub(crate) use catalog_match::classify_layers;

/// The camera types this stage and `csg` use (the one import of them, so the camera's move to
/// its own module is a one-line change).
pub(crate) use crate::camera::Camera;
#[cfg(test)]
pub(crate) use crate::camera::{CameraOptions, CornerView};

use crate::scene::ReconStatus;
use answer::Decline;
use catalog_match::touching_pairs;
use compare::SearchLimits;
use edge_profile::ViewPicture;
use flow::{check_directions, check_drawing, drop_weak_off_axis_lines, final_checks};
use flow::{find_hypothesis, normalize_views, placed_answer, read_pictures};

/// Blocks closer than this in mm are one candidate, share a layer, touch, or rest on each
/// other (far below any catalog size, far above the measurement error).
pub(crate) const SAME_PLACE_TOL_MM: f64 = 0.5;

/// The declines after which one view is set aside and then the lines no block draws
/// (`set_aside`, docs/recognizer-pictures.md "One view set aside" and "Lines set aside"):
/// lines in no block direction (what a cast shadow's edge causes, before any search), and a
/// view not explained (a shadow's or a highlight's line the answer lacks, one view read off
/// the others); [`DECLINE_KINDS`] names.
const SET_ASIDE_DECLINES: [&str; 3] = [
    "not one direction",
    "unclassified lines",
    "view not explained",
];

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
/// redraw and a vision drawing differ ([`steps::picture_check`], docs/recognizer.md "Recognizer"): an edge too
/// faint for the front end is confirmed by a step or crack across it, a drawing feature the
/// redraw lacks is tolerated only when the picture shows it weak. The answer still comes from
/// the drawings alone.
pub fn recognize_in_pictures(
    views: &[ObservedView],
    pictures: &[&image::GrayImage],
    opts: &RecognizeOptions,
) -> Result<Recognition, RecognizeError> {
    recognize_with_progress(views, pictures, opts, &|_| {})
}

/// [`recognize_in_pictures`] reporting the search's progress to `progress` (every 1,024
/// nodes of its budget, `opts.node_budget` nodes and `opts.time_budget_s` seconds; once spent,
/// the answer declines, docs/limits.md "Recognizer").
pub fn recognize_with_progress(
    views: &[ObservedView],
    pictures: &[&image::GrayImage],
    opts: &RecognizeOptions,
    progress: &dyn Fn(SearchProgress),
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
    let (views, pictures) = prepared(views, pictures, opts);
    let all = recognize_prepared(&views, &pictures, opts, progress);
    let reason = all.reason.as_deref().unwrap_or_default();
    let kind = decline_kind(reason);
    if all.status == ReconStatus::Ok || !SET_ASIDE_DECLINES.contains(&kind) {
        return Ok(all);
    }
    let recognize =
        |v: &[ObservedView], p: &[ViewPicture]| recognize_prepared(v, p, opts, progress);
    let one = set_aside::with_one_view_set_aside(&views, &pictures, opts, &recognize);
    let hypothesis = &all.evidence.hypothesis;
    let lines =
        || set_aside::with_shading_lines_set_aside(&views, &pictures, opts, &recognize, hypothesis);
    Ok(one.or_else(lines).unwrap_or(all))
}

/// The views with their drawings normalized and their weak off-axis lines dropped, and their
/// pictures read (none when any is too coarse): what [`recognize_prepared`] takes.
pub(super) fn prepared<'a>(
    views: &[ObservedView],
    pictures: &[&'a image::GrayImage],
    opts: &RecognizeOptions,
) -> (Vec<ObservedView>, Vec<ViewPicture<'a>>) {
    let pictures = read_pictures(views, pictures, opts);
    let mut views = normalize_views(views);
    drop_weak_off_axis_lines(&mut views, &pictures, opts);
    (views, pictures)
}

/// The recognizer on views whose drawings are normalized and whose weak off-axis lines are
/// dropped, with their pictures read (none: drawings alone).
pub(super) fn recognize_prepared(
    views: &[ObservedView],
    pictures: &[ViewPicture],
    opts: &RecognizeOptions,
    progress: &dyn Fn(SearchProgress),
) -> Recognition {
    let mut evidence = Evidence::default();
    let trapezoids = match check_directions(views, opts) {
        Ok(t) => t,
        Err(d) => return Recognition::declined(d, evidence),
    };
    let points = views.iter().map(|v| v.drawing.points.len()).sum();
    let budgets = (opts.node_budget, opts.time_budget_s);
    let budget = SearchBudget::new(budgets, budget::node_cost(points), progress);
    let search = (&SearchLimits::new(opts, &budget), trapezoids);
    let h = find_hypothesis(views, opts, search, pictures, &mut evidence);
    let h = match h {
        Ok(h) => placed_answer(h, views, pictures, (opts.tol_px, opts.grid_mm)),
        Err(d) => return Recognition::declined(d, evidence),
    };
    for (ev, c) in evidence.views.iter_mut().zip(&h.checks) {
        ev.unexplained_points = c.unexplained_points;
        ev.extra_points = c.extra_points;
        ev.unexplained_lines = c.unexplained_lines;
        ev.extra_lines = c.extra_lines;
    }
    evidence.hypothesis = h.blocks.clone();
    if h.blocks.is_empty() {
        let lines = views.iter().map(|v| v.drawing.lines.len()).sum();
        let d = Decline::NoBlocks { points, lines };
        return Recognition::declined(d, evidence);
    }
    if let Some(d) = final_checks(&h, views, pictures, opts) {
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
        return Recognition::declined(d, evidence);
    }
    let blocks = h.blocks;
    Recognition {
        layers: classify_layers(&blocks, SAME_PLACE_TOL_MM),
        touching: touching_pairs(&blocks, SAME_PLACE_TOL_MM),
        blocks,
        status: ReconStatus::Ok,
        reason: None,
        evidence,
    }
}

/// The exact views of `blocks` from the corner views `which`, framed as `render` frames them:
/// the observed input of the recognizer's unit tests.
#[cfg(test)]
pub(crate) fn views_of(blocks: &[crate::scene::Block], which: &[CornerView]) -> Vec<ObservedView> {
    let pts = crate::scene::world_vertices(blocks);
    which
        .iter()
        .map(|&v| {
            let camera = Camera::frame(&pts, v, &CameraOptions::default());
            let drawing = draw_hypothesis(blocks, &camera);
            ObservedView::new(drawing, camera)
        })
        .collect()
}

/// `view` with a line from `from` to `to` added to its drawing: a line the unit tests'
/// pictures show and no block draws.
#[cfg(test)]
pub(crate) fn with_line(
    view: &ObservedView,
    from: crate::geom::DVec2,
    to: crate::geom::DVec2,
) -> ObservedView {
    let mut drawing = view.drawing.clone();
    drawing.kinds.clear();
    drawing.edges.clear();
    let at = |d: &mut crate::drawing::LineDrawing, q: crate::geom::DVec2| {
        d.points
            .iter()
            .position(|p| p.distance(q) < 0.5)
            .unwrap_or_else(|| {
                d.points.push(q);
                d.points.len() - 1
            })
    };
    let (a, b) = (at(&mut drawing, from), at(&mut drawing, to));
    drawing.lines.push([a, b]);
    drawing.finalize();
    view.with_drawing(drawing)
}

/// A line-art picture of `drawing` through `camera`: ink (gray 40) within 0.8 px of every
/// line on a floor of gray 150; the pictures of the recognizer's unit tests.
#[cfg(test)]
pub(crate) fn inked_picture(
    camera: &Camera,
    drawing: &crate::drawing::LineDrawing,
) -> image::GrayImage {
    inked_picture_in(camera, drawing, [40, 150])
}

/// [`inked_picture`] with the gray levels `[ink, floor]`: a faint drawing when they are close.
#[cfg(test)]
pub(crate) fn inked_picture_in(
    camera: &Camera,
    drawing: &crate::drawing::LineDrawing,
    [ink, floor]: [u8; 2],
) -> image::GrayImage {
    painted_picture(camera, floor, |p| {
        let near = drawing.lines.iter().any(|&[i, j]| {
            crate::geom::distance_to_segment_px(p, drawing.points[i], drawing.points[j]) <= 0.8
        });
        near.then_some(ink)
    })
}

/// A picture of `camera`'s size at gray `level`, with `paint` (picture px, y up) applied at
/// every pixel centre where it gives a gray: the painted pictures of the unit tests.
#[cfg(test)]
pub(crate) fn painted_picture(
    camera: &Camera,
    level: u8,
    paint: impl Fn(crate::geom::DVec2) -> Option<u8>,
) -> image::GrayImage {
    let [w, h] = camera.size_px;
    image::GrayImage::from_fn(w, h, |x, r| {
        let p = crate::geom::DVec2::new(f64::from(x) + 0.5, f64::from(h - r) - 0.5);
        image::Luma([paint(p).unwrap_or(level)])
    })
}

/// `b15` cubes of a 3 x 3 grid, 15 mm apart: the `layer`-th layer's cells `cells` (row-major,
/// x fastest); the stacks of the recognizer's unit tests.
#[cfg(test)]
pub(crate) fn grid_cubes(layer: usize, cells: &[usize]) -> Vec<crate::scene::Block> {
    cells
        .iter()
        .map(|&k| {
            let centre = crate::geom::DVec3::new(
                (k % 3) as f64 * 15.0,
                layer as f64 * 15.0 + 7.5,
                (k / 3) as f64 * 15.0,
            );
            crate::scene::Block::new("b15", centre, 0.0)
        })
        .collect()
}
