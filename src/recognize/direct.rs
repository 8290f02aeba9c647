//! The thesis's direct path (Chapter V, flow chart Figure 5.3): the parallelograms' sizes give
//! the blocks' types, "the positions of the blocks can be estimated from the image and from
//! the database of the predefined blocks", and the blocks are put together "starting from the
//! lowest level to the upper levels", with no search. The result is drawn and checked once
//! (step 6); only when it does not explain every view does the recognizer fall back to the
//! hypothesize-and-test search of [`super::compare`].
//!
//! Which candidates the direct path takes: those the views agree on (rule (1) of Chapter V
//! compares the same vertex over two views: a block proposed from several views sits at its
//! true height, where a single view's depth is ambiguous) and whose sizes some closed
//! parallelogram reads exactly ([`super::Proposal::closed_fit`]).

use super::catalog_match::blocks_overlap;
use super::compare::PooledCandidate;
use super::constraints::overhanging_blocks;
use super::{ObservedView, SAME_PLACE_TOL_MM};
use crate::geom::{convex_hull, inside_convex, DVec2, DVec3};
use crate::scene::Block;
use std::cmp::Reverse;

/// Indices of the pooled candidates the direct path may take: proposed by at least
/// `min(2, view_count)` views and fitting a closed parallelogram exactly in at least one.
pub fn well_supported(pool: &[PooledCandidate], view_count: usize) -> Vec<usize> {
    let min_views = view_count.clamp(1, 2);
    (0..pool.len())
        .filter(|&i| pool[i].views.len() >= min_views && !pool[i].fit_views.is_empty())
        .collect()
}

/// The convex hull of each view's observed points, in view order: a bound of the sample's
/// silhouette in that picture.
pub(super) fn silhouettes(views: &[ObservedView]) -> Vec<Vec<DVec2>> {
    views
        .iter()
        .map(|v| convex_hull(&v.drawing.points))
        .collect()
}

/// `true` when the world point `q_mm` projects inside every view's silhouette hull (within
/// `tol_px`): a point of the sample is seen inside the sample's outline in every picture.
pub(super) fn inside_every_silhouette(
    q_mm: DVec3,
    views: &[ObservedView],
    hulls: &[Vec<DVec2>],
    tol_px: f64,
) -> bool {
    views.iter().zip(hulls).all(|(v, hull)| {
        let p = v.camera.picture_from_world(q_mm).truncate();
        inside_convex(hull, p, tol_px)
    })
}

/// `true` when every corner of `b` projects inside the convex hull of the observed points of
/// every view (within `tol_px`): a block of the sample lies inside the sample's silhouette in
/// every picture, so a candidate reaching outside any of them is not one.
fn inside_every_view(b: &Block, views: &[ObservedView], hulls: &[Vec<DVec2>], tol_px: f64) -> bool {
    b.world_vertices()
        .into_iter()
        .all(|c| inside_every_silhouette(c, views, hulls, tol_px))
}

/// `true` when `b` stands on the floor or on `chosen` without overhanging (Chapter VII: every
/// block rests on the floor or on the layer below, never larger than it, Figure 7.2).
fn rests_on(b: &Block, chosen: &[Block]) -> bool {
    if b.bottom_mm() <= SAME_PLACE_TOL_MM {
        return true;
    }
    let mut with = chosen.to_vec();
    with.push(*b);
    !overhanging_blocks(&with, SAME_PLACE_TOL_MM, SUPPORT_STEP_MM).contains(&chosen.len())
}

/// The sampling step of the support test, mm (a sixth of the smallest catalog side).
const SUPPORT_STEP_MM: f64 = 2.5;

/// The direct hypothesis (Figure 5.3): the [`well_supported`] candidates that lie inside every
/// view's silhouette, put together layer by layer from the lowest.
pub fn direct_hypothesis(
    pool: &[PooledCandidate],
    views: &[ObservedView],
    tol_px: f64,
) -> Vec<Block> {
    let hulls = silhouettes(views);
    let candidates: Vec<usize> = well_supported(pool, views.len())
        .into_iter()
        .filter(|&i| inside_every_view(&pool[i].block, views, &hulls, tol_px))
        .collect();
    take_lowest_first(pool, candidates)
}

/// Candidates `indices` of `pool` lowest layer first ("starting from the lowest level to the
/// upper levels", Chapter V), within a layer best supported first (views with an exact fit,
/// then views proposing it), then the smaller block and the more proposals; each taken unless
/// it overlaps one already taken or does not rest on them.
fn take_lowest_first(pool: &[PooledCandidate], mut indices: Vec<usize>) -> Vec<Block> {
    indices.sort_by_key(|&i| {
        let c = &pool[i];
        let size = c.block.block_type.size_mm();
        (
            (c.block.bottom_mm() / SAME_PLACE_TOL_MM).round() as i64,
            Reverse(c.fit_views.len()),
            Reverse(c.views.len()),
            (size.x * size.y * size.z).round() as i64,
            Reverse(c.proposals),
            i,
        )
    });
    let mut chosen: Vec<Block> = Vec::new();
    for i in indices {
        let b = pool[i].block;
        if !chosen.iter().any(|c| blocks_overlap(c, &b)) && rests_on(&b, &chosen) {
            chosen.push(b);
        }
    }
    chosen
}

#[cfg(test)]
mod tests {
    use super::*;

    fn candidate(id: &'static str, y: f64, views: usize, fits: usize) -> PooledCandidate {
        PooledCandidate {
            block: Block::new(id, DVec3::new(7.5, y, 7.5), 0.0),
            views: (0..views).collect(),
            fit_views: (0..fits).collect(),
            proposals: views,
        }
    }

    #[test]
    fn the_best_supported_candidate_wins_its_place_and_a_single_view_one_is_left_out() {
        let pool = vec![
            candidate("b7_5", 11.25, 2, 1),
            candidate("b15", 7.5, 3, 2),
            candidate("b30", 7.5, 1, 1),
            candidate("b15", 37.5, 4, 0),
        ];
        assert_eq!(well_supported(&pool, 4), vec![0, 1]);
        let h = take_lowest_first(&pool, well_supported(&pool, 4));
        assert_eq!(h.len(), 1, "the b7_5 overlaps the b15");
        assert_eq!(h[0].block_type.id, "b15");
        // One view: a single view's candidates are all the evidence there is.
        assert_eq!(well_supported(&pool, 1), vec![0, 1, 2]);
    }

    #[test]
    fn the_lower_block_is_taken_first_and_a_block_over_nothing_is_not_taken() {
        let pool = vec![
            candidate("b7_5", 11.25, 4, 4),
            candidate("b15", 7.5, 2, 2),
            candidate("b15", 37.5, 2, 2),
        ];
        let h = take_lowest_first(&pool, vec![0, 1, 2]);
        assert_eq!(h.len(), 1, "{h:?}");
        assert_eq!(h[0].block_type.id, "b15", "the block reaching the floor");
        let on_top = candidate("b15", 22.5, 2, 2);
        let h = take_lowest_first(&[pool[1].clone(), on_top], vec![1, 0]);
        assert_eq!(h.len(), 2, "a block resting on the first is taken after it");
    }

    #[test]
    fn a_candidate_outside_a_views_silhouette_is_left_out() {
        use crate::camera::{Camera, CameraOptions, CornerView};
        let truth = [Block::new("b15", DVec3::new(7.5, 7.5, 7.5), 0.0)];
        let views: Vec<ObservedView> = [CornerView::Ne, CornerView::Sw]
            .iter()
            .map(|&v| {
                let camera =
                    Camera::frame(&truth[0].world_vertices(), v, &CameraOptions::default());
                let drawing = super::super::draw_hypothesis(&truth, &camera);
                ObservedView { drawing, camera }
            })
            .collect();
        let pool = vec![candidate("b15", 7.5, 2, 2), candidate("b15", 22.5, 2, 2)];
        let h = direct_hypothesis(&pool, &views, 2.0);
        assert_eq!(
            h,
            vec![truth[0]],
            "the block on top would stick out of both pictures"
        );
    }
}
