//! The steps of [`super::recognize_in_pictures`] between the input check and the answer:
//! Chapter VII's constraints on the drawings, the proposals of each view and their pooling,
//! the choice of blocks (step 4) and the final checks (step 6 and Chapter VII).

use super::ambiguity::alternative_given_drawings;
use super::answer::{Decline, Evidence, ObservedView, RecognizeError, RecognizeOptions};
use super::catalog_match::{catalog_proposals_where, level_heights_mm, Proposal};
use super::compare::{choose_hypothesis, greedy_and_split_from, pool_proposals, Hypothesis};
use super::compare::{PooledCandidate, SearchLimits};
use super::constraints::overhanging_blocks;
use super::constraints::{curved_chain_lines, floating_blocks, lines_off_the_axes, AxisTolerance};
use super::direct::{direct_hypothesis_within, Silhouettes};
use super::edge_profile::ViewPicture;
use super::parallelogram::{Face, ParallelogramSearch};
use super::picture::without_weak_lines;
use super::placement::{
    imprecisely_placed, misplaced_in_a_view, placed_by_all_views, unmeasured_in_views,
};
use super::repair::{cracks_resolved, repaired_in_pictures};
use super::select::select_vertices;
use super::shadow::mismatches_under_known_lights;
use super::trapezoid::{sloped_faces, sloped_lines, trapezoid_proposals};
use super::verify::{blocks_drawn_in_excess, ViewCheck, ViewMismatch};
use super::SAME_PLACE_TOL_MM;
use crate::scene::{Block, ViewEvidence};

/// The view's drawing checked ([`LineDrawing::check`], the one validation of a drawing).
pub(super) fn check_drawing(view: &ObservedView) -> Result<(), RecognizeError> {
    view.drawing
        .check()
        .map_err(|e| RecognizeError::BadDrawing {
            view: view.camera.view.name().to_string(),
            problem: e.to_string(),
        })
}

/// Chapter VII's constraints on the observed drawings, before any search: no curved edges
/// (round parts), every line in a six-bit direction and along a block axis, except, once some
/// view shows a sloped face (a trapezoidal block, Figure 7.1), the lines along its slopes.
/// `Ok(true)` when a sloped face was seen: trapezoidal blocks join the candidates.
pub(super) fn check_directions(
    views: &[ObservedView],
    opts: &RecognizeOptions,
) -> Result<bool, Decline> {
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
        let off = lines_off_the_axes(&v.drawing, &v.camera, axis_tolerance(opts));
        let count = off.iter().filter(|l| !slopes.contains(l)).count();
        if count > 0 {
            return Err(Decline::NotOneDirection { view, count });
        }
    }
    Ok(trapezoids)
}

/// The tolerance of Chapter VII's one-direction check: `axis_tol_deg`, or, on a short line,
/// either end `tol_px` across the axis line ([`AxisTolerance`]).
pub(super) fn axis_tolerance(opts: &RecognizeOptions) -> AxisTolerance {
    AxisTolerance {
        tol_deg: opts.axis_tol_deg,
        end_tol_px: opts.tol_px,
    }
}

/// Steps 1-3 on one view: its proposals (only those fitting a closed parallelogram exactly,
/// with their top corner where `corner_ok` accepts it, when `fit_only`) and evidence counts.
/// With `trapezoids`, also the trapezoidal blocks its sloped faces propose (Figure 7.1).
pub(super) fn propose(
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
pub(super) fn normalize_views(views: &[ObservedView]) -> Vec<ObservedView> {
    views
        .iter()
        .map(|v| {
            let mut drawing = v.drawing.clone();
            drawing.finalize();
            v.with_drawing(drawing)
        })
        .collect()
}

/// Steps 1-3 on every view and the pooling of step 4: the pooled candidates, with the views'
/// evidence counts recorded in `evidence`. For the direct path (`direct_within` given: only
/// exact fits), a level is read only where the measured top corner is seen inside every view's
/// silhouette, as the direct path requires of every corner of the blocks it takes
/// ([`direct_hypothesis`]). With `trapezoids`, the sloped faces' trapezoidal blocks too.
pub(super) fn propose_and_pool(
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
/// ([`picture_check`]), the direct one before the pruned one. The search stops when it has
/// spent `limits.budget`, and the answer is then the decline that says so.
pub(super) fn find_hypothesis(
    views: &[ObservedView],
    opts: &RecognizeOptions,
    (limits, trapezoids): (&SearchLimits, bool),
    pictures: &[ViewPicture],
    evidence: &mut Evidence,
) -> Result<Hypothesis, Decline> {
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
        return Ok(direct);
    }
    let pruned = without_excess(direct.clone(), views, limits.tol_px);
    if pruned.mismatch() == 0 {
        return Ok(pruned);
    }
    if explained(&direct) {
        return Ok(direct);
    }
    if explained(&pruned) {
        return Ok(pruned);
    }
    let pool = propose_and_pool(views, opts, (None, trapezoids), evidence);
    let within = |h: Hypothesis| limits.budget.decline().map_or(Ok(h), Err);
    let (_, continued) = greedy_and_split_from(&pool, views, limits, &[], pruned);
    if continued.mismatch() == 0 || explained(&continued) {
        return within(continued);
    }
    let chosen = choose_hypothesis(&pool, views, limits);
    if chosen.mismatch() == 0 || pictures.is_empty() || explained(&chosen) {
        return within(chosen);
    }
    let cracks = cracks_resolved(pictures);
    let repaired = repaired_in_pictures(&chosen, &pool, views, limits, &explained, cracks);
    let repaired = repaired.or_else(|| {
        // The same blocks have the same neighbours: tried once.
        (continued.blocks != chosen.blocks)
            .then(|| repaired_in_pictures(&continued, &pool, views, limits, &explained, cracks))
            .flatten()
    });
    within(repaired.unwrap_or(chosen))
}

/// Each view's step-6 comparison of `h`: with the views' pictures, by the picture-aware check
/// ([`super::picture::pictures_mismatch`]) unless the drawings alone explain every view, the lines along the
/// edges of the shadows `h` casts under a view's known lights left out
/// ([`mismatches_under_known_lights`]).
fn checks_in_pictures(
    h: &Hypothesis,
    views: &[ObservedView],
    pictures: &[ViewPicture],
    tol_px: f64,
) -> Vec<ViewCheck> {
    if pictures.len() != views.len() || h.checks.iter().all(ViewCheck::is_explained) {
        return h.checks.clone();
    }
    mismatches_under_known_lights(&h.blocks, &h.drawn, views, pictures, tol_px)
        .iter()
        .map(ViewMismatch::counts)
        .collect()
}

/// `h` with its groups of touching blocks placed by every view at once
/// ([`placed_by_all_views`]), when the placed blocks explain the views at least as well (by the
/// picture-aware check when the views' pictures are given); else `h`.
pub(super) fn placed_answer(
    h: Hypothesis,
    views: &[ObservedView],
    pictures: &[ViewPicture],
    (tol_px, grid_mm): (f64, Option<f64>),
) -> Hypothesis {
    let blocks = placed_by_all_views(&h.blocks, &h.drawn, views, tol_px, grid_mm);
    if blocks == h.blocks {
        return h;
    }
    let placed = Hypothesis::new(blocks, views, tol_px);
    let left = |x: &Hypothesis| -> usize {
        checks_in_pictures(x, views, pictures, tol_px)
            .iter()
            .map(ViewCheck::mismatch)
            .sum()
    };
    if placed.mismatch() <= h.mismatch() && left(&placed) <= left(&h) {
        placed
    } else {
        h
    }
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
pub(super) fn final_checks(
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
    if let Some((block, shift)) =
        imprecisely_placed(blocks, &h.drawn, views, opts.tol_px, opts.grid_mm)
    {
        let shift_mm = shift.length();
        return Some(Decline::Imprecise { block, shift_mm });
    }
    if opts.two_views_place {
        if let Some((block, n)) = unmeasured_in_views(blocks, &h.drawn, views, opts.tol_px) {
            return Some(Decline::UnmeasuredInViews { block, views: n });
        }
    }
    if opts.every_view_places {
        let misplaced = misplaced_in_a_view(blocks, &h.drawn, views, opts.tol_px, opts.grid_mm);
        if let Some((block, v)) = misplaced {
            let view = views[v].camera.view.name().to_string();
            return Some(Decline::ImpreciseInAView { block, view });
        }
    }
    if let Some(&block) = overhanging_blocks(blocks, SAME_PLACE_TOL_MM, 1.0).first() {
        return Some(Decline::UpperLayerLarger { block });
    }
    floating_blocks(blocks, SAME_PLACE_TOL_MM)
        .first()
        .map(|&block| Decline::HiddenSupport { block })
}

/// The views' pictures with their noise and scale ([`ViewPicture::new`]); none when any is too
/// coarse for the tolerance (`ViewPicture::fine_enough`): such pictures are not read at all.
pub(super) fn read_pictures<'a>(
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

/// The straight lines of `view`'s drawing in no block direction: along no block axis, or
/// unclassified (curves kept out).
pub(super) fn straight_lines_in_no_block_direction(
    view: &ObservedView,
    opts: &RecognizeOptions,
) -> Vec<usize> {
    let d = &view.drawing;
    let mut off = lines_off_the_axes(d, &view.camera, axis_tolerance(opts));
    off.extend(d.unclassified_lines.iter().copied());
    off.retain(|k| !d.curved_lines.contains(k));
    off
}

/// Drops from each view's drawing the lines along no block axis (and the unclassified ones,
/// curves kept) that its picture shows weak ([`without_weak_lines`]).
pub(super) fn drop_weak_off_axis_lines(
    views: &mut [ObservedView],
    pictures: &[ViewPicture],
    opts: &RecognizeOptions,
) {
    for (v, pic) in views.iter_mut().zip(pictures) {
        let off = straight_lines_in_no_block_direction(v, opts);
        if !off.is_empty() {
            v.drawing = without_weak_lines(&v.drawing, &off, pic);
        }
    }
}
