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
//!
//! Corner views of a block grid see *ghosts*: a block a layer step up and as far back along
//! the view rays has, in every view at once, the top face in the picture of a block the views
//! already gave (rule (1) of Chapter V meets a coincidence of the grid). A ghost shows nothing
//! of its own: none of its sides is seen as a closed parallelogram it fits. Such a candidate
//! waits until the rest is taken, and is left out if a side of it is still uncovered then
//! (a real block there would show that side). Leaving a real block out here costs only time:
//! the direct hypothesis is checked (step 6) and the search takes over.

use super::catalog_match::{blocks_overlap, bounds_mm};
use super::compare::PooledCandidate;
use super::constraints::overhangs;
use super::{Camera, ObservedView, SAME_PLACE_TOL_MM};
use crate::camera::Projector;
use crate::geom::{convex_hull, ConvexRegion, DVec2, DVec3};
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

/// Each view's silhouette bound, the convex hull of its observed points, with the view's
/// projection ready for many points.
pub(super) struct Silhouettes {
    views: Vec<(Projector, ConvexRegion)>,
}

impl Silhouettes {
    /// The silhouettes of `views`, in view order.
    pub(super) fn new(views: &[ObservedView]) -> Silhouettes {
        let views = views
            .iter()
            .map(|v| {
                let hull = convex_hull(&v.drawing.points);
                (Projector::new(&v.camera), ConvexRegion::new(&hull))
            })
            .collect();
        Silhouettes { views }
    }

    /// `true` when the world point `q_mm` projects inside every view's silhouette (within
    /// `tol_px`): a point of the sample is seen inside the sample's outline in every picture.
    pub(super) fn hold(&self, q_mm: DVec3, tol_px: f64) -> bool {
        self.views
            .iter()
            .all(|(proj, region)| region.contains(proj.picture(q_mm), tol_px))
    }
}

/// `true` when every corner of `b` projects inside the convex hull of the observed points of
/// every view (within `tol_px`): a block of the sample lies inside the sample's silhouette in
/// every picture, so a candidate reaching outside any of them is not one.
fn inside_every_view(b: &Block, silhouettes: &Silhouettes, tol_px: f64) -> bool {
    b.world_vertices()
        .into_iter()
        .all(|c| silhouettes.hold(c, tol_px))
}

/// `true` when `b` stands on the floor or on `chosen` without overhanging (Chapter VII: every
/// block rests on the floor or on the layer below, never larger than it, Figure 7.2).
fn rests_on(b: &Block, chosen: &[Block]) -> bool {
    if b.bottom_mm() <= SAME_PLACE_TOL_MM {
        return true;
    }
    !overhangs(b, chosen, SAME_PLACE_TOL_MM, SUPPORT_STEP_MM)
}

/// The sampling step of the support test, mm (a sixth of the smallest catalog side).
const SUPPORT_STEP_MM: f64 = 2.5;

/// The direct hypothesis (Figure 5.3): the [`well_supported`] candidates that lie inside every
/// view's silhouette, put together layer by layer from the lowest, ghosts of lower blocks'
/// top faces left out (module doc).
pub fn direct_hypothesis(
    pool: &[PooledCandidate],
    views: &[ObservedView],
    tol_px: f64,
) -> Vec<Block> {
    direct_hypothesis_within(pool, views, &Silhouettes::new(views), tol_px)
}

/// [`direct_hypothesis`] with the views' silhouettes already made (the recognizer makes them
/// once for the reading of levels and for this).
pub(super) fn direct_hypothesis_within(
    pool: &[PooledCandidate],
    views: &[ObservedView],
    silhouettes: &Silhouettes,
    tol_px: f64,
) -> Vec<Block> {
    let candidates: Vec<usize> = well_supported(pool, views.len())
        .into_iter()
        .filter(|&i| inside_every_view(&pool[i].block, silhouettes, tol_px))
        .collect();
    let ghost = |c: &PooledCandidate, chosen: &[Block], settled: bool| {
        is_ghost(c, chosen, views, tol_px, settled)
    };
    take_lowest_first(pool, candidates, &ghost)
}

/// The picture points of the top face's corners of `b` in `camera`.
fn top_corners_px(b: &Block, camera: &Camera) -> Vec<DVec2> {
    let top = bounds_mm(b).1.y;
    b.world_vertices()
        .into_iter()
        .filter(|v| (v.y - top).abs() <= SAME_PLACE_TOL_MM)
        .map(|v| camera.picture_from_world(v).truncate())
        .collect()
}

/// `true` when the two corner sets are the same points within `tol_px`.
fn same_corners(a: &[DVec2], b: &[DVec2], tol_px: f64) -> bool {
    a.len() == b.len() && a.iter().all(|p| b.iter().any(|q| q.distance(*p) <= tol_px))
}

/// How far outside a side face [`sides_covered`] probes, mm (above the contact tolerance, far
/// below any catalog size).
const SIDE_PROBE_MM: f64 = 0.5;

/// `true` when every side face of `b` is covered by blocks of `chosen` touching it: probes just
/// outside each side (its centre and four points 1 mm in from its corners) all lie inside
/// chosen blocks. Such a block's sides cannot be seen, so a missing side fit says nothing.
fn sides_covered(b: &Block, chosen: &[Block]) -> bool {
    let (lo, hi) = bounds_mm(b);
    let boxes: Vec<(DVec3, DVec3)> = chosen.iter().map(bounds_mm).collect();
    let inside = |q: DVec3| {
        boxes
            .iter()
            .any(|(l, h)| (0..3).all(|k| q[k] > l[k] && q[k] < h[k]))
    };
    [(0, 2), (2, 0)].iter().all(|&(fixed, run)| {
        [(lo[fixed], -1.0), (hi[fixed], 1.0)]
            .iter()
            .all(|&(face, out)| {
                let at = |r: f64, y: f64| {
                    let mut q = DVec3::new(0.0, y, 0.0);
                    q[fixed] = face + out * SIDE_PROBE_MM;
                    q[run] = r;
                    q
                };
                let (r0, r1, y0, y1) = (lo[run] + 1.0, hi[run] - 1.0, lo.y + 1.0, hi.y - 1.0);
                let mid = at((lo[run] + hi[run]) / 2.0, (lo.y + hi.y) / 2.0);
                [mid, at(r0, y0), at(r0, y1), at(r1, y0), at(r1, y1)]
                    .into_iter()
                    .all(inside)
            })
    })
}

/// `true` when candidate `c`, above the floor, may be a ghost of `chosen`'s lower blocks
/// (module doc): no side of it fits a closed parallelogram, and in every view its top face is
/// the top face of a lower chosen block. With `settled` (all else taken), only if some side of
/// it is also uncovered by the chosen blocks, so that a real block there would show it.
fn is_ghost(
    c: &PooledCandidate,
    chosen: &[Block],
    views: &[ObservedView],
    tol_px: f64,
    settled: bool,
) -> bool {
    let b = &c.block;
    if c.side_fit || b.bottom_mm() <= SAME_PLACE_TOL_MM {
        return false;
    }
    if settled && sides_covered(b, chosen) {
        return false;
    }
    let top = bounds_mm(b).1.y;
    let lower: Vec<&Block> = chosen
        .iter()
        .filter(|l| bounds_mm(l).1.y < top - SAME_PLACE_TOL_MM)
        .collect();
    views.iter().all(|v| {
        let mine = top_corners_px(b, &v.camera);
        lower
            .iter()
            .any(|l| same_corners(&mine, &top_corners_px(l, &v.camera), tol_px))
    })
}

/// Candidates `indices` of `pool` lowest layer first ("starting from the lowest level to the
/// upper levels", Chapter V), within a layer the trapezoidal blocks first (a sloped face is
/// seen only on them, while the square top of a wedge's flat half also fits a cube), then the
/// best supported (views with an exact fit,
/// then views proposing it), then the smaller block and the more proposals; each taken unless
/// it overlaps one already taken or does not rest on them. A candidate `ghost` flags (given
/// the blocks taken so far) waits; once the rest is taken it joins unless `ghost`, asked
/// again with everything else in place, still flags it.
fn take_lowest_first(
    pool: &[PooledCandidate],
    mut indices: Vec<usize>,
    ghost: &dyn Fn(&PooledCandidate, &[Block], bool) -> bool,
) -> Vec<Block> {
    indices.sort_by_cached_key(|&i| {
        let c = &pool[i];
        let size = c.block.block_type.size_mm();
        (
            (c.block.bottom_mm() / SAME_PLACE_TOL_MM).round() as i64,
            c.block.block_type.cuboid_half_extents_mm().is_some(),
            Reverse(c.fit_views.len()),
            Reverse(c.views.len()),
            (size.x * size.y * size.z).round() as i64,
            Reverse(c.proposals),
            i,
        )
    });
    let fits = |b: &Block, chosen: &[Block]| {
        !chosen.iter().any(|c| blocks_overlap(c, b)) && rests_on(b, chosen)
    };
    let mut chosen: Vec<Block> = Vec::new();
    let mut waiting: Vec<usize> = Vec::new();
    for i in indices {
        if !fits(&pool[i].block, &chosen) {
            continue;
        }
        if ghost(&pool[i], &chosen, false) {
            waiting.push(i);
        } else {
            chosen.push(pool[i].block);
        }
    }
    for i in waiting {
        if fits(&pool[i].block, &chosen) && !ghost(&pool[i], &chosen, true) {
            chosen.push(pool[i].block);
        }
    }
    chosen
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::recognize::grid_cubes;
    use crate::scene::same_blocks;

    fn candidate(id: &'static str, y: f64, views: usize, fits: usize) -> PooledCandidate {
        PooledCandidate {
            block: Block::new(id, DVec3::new(7.5, y, 7.5), 0.0),
            views: (0..views).collect(),
            fit_views: (0..fits).collect(),
            side_fit: false,
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
        let h = take_lowest_first(&pool, well_supported(&pool, 4), &|_, _, _| false);
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
        let h = take_lowest_first(&pool, vec![0, 1, 2], &|_, _, _| false);
        assert_eq!(h.len(), 1, "{h:?}");
        assert_eq!(h[0].block_type.id, "b15", "the block reaching the floor");
        let on_top = candidate("b15", 22.5, 2, 2);
        let h = take_lowest_first(&[pool[1].clone(), on_top], vec![1, 0], &|_, _, _| false);
        assert_eq!(h.len(), 2, "a block resting on the first is taken after it");
    }

    /// The direct hypothesis from the exact four corner views of `truth`, and the same with
    /// no candidate ever taken for a ghost.
    fn direct_from(truth: &[Block]) -> (Vec<Block>, Vec<Block>) {
        use crate::recognize::{views_of, CornerView, RecognizeOptions};
        let views = views_of(truth, &CornerView::ALL);
        let opts = RecognizeOptions::default();
        let silhouettes = Silhouettes::new(&views);
        let pool = super::super::flow::propose_and_pool(
            &views,
            &opts,
            (Some(&silhouettes), false),
            &mut Default::default(),
        );
        let candidates: Vec<usize> = well_supported(&pool, views.len())
            .into_iter()
            .filter(|&i| inside_every_view(&pool[i].block, &silhouettes, opts.tol_px))
            .collect();
        let blind = take_lowest_first(&pool, candidates, &|_, _, _| false);
        (direct_hypothesis(&pool, &views, opts.tol_px), blind)
    }

    #[test]
    fn ghosts_of_a_grid_layer_are_left_out_and_real_upper_blocks_kept() {
        // The 3 x 3 layer with a row of three on top (`bench render`'s 12-block stack): two
        // b7_5 ghosts over the layer's back half repeat its top faces in all four views.
        let stack = [
            grid_cubes(0, &[0, 1, 2, 3, 4, 5, 6, 7, 8]),
            grid_cubes(1, &[0, 1, 2]),
        ]
        .concat();
        let (direct, blind) = direct_from(&stack);
        assert!(same_blocks(&direct, &stack, 0.01), "{direct:?}");
        assert!(
            blind.iter().any(|b| b.block_type.id == "b7_5"),
            "without the ghost test the direct path takes a ghost: {blind:?}"
        );
        // One cube on the layer's edge: its top face may repeat lower ones, but its sides are
        // seen.
        let on_edge = [
            grid_cubes(0, &[0, 1, 2, 3, 4, 5, 6, 7, 8]),
            grid_cubes(1, &[1]),
        ]
        .concat();
        assert!(same_blocks(&direct_from(&on_edge).0, &on_edge, 0.01));
        // Two full layers: the upper middle shows no side, but its neighbours cover every
        // side, so it is no ghost.
        let all = [0, 1, 2, 3, 4, 5, 6, 7, 8];
        let two_layers = [grid_cubes(0, &all), grid_cubes(1, &all)].concat();
        assert!(same_blocks(&direct_from(&two_layers).0, &two_layers, 0.01));
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
                ObservedView::new(drawing, camera)
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
