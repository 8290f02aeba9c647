//! Step 6 with the pictures, one move further (docs/recognizer.md "Recognizer", docs/rendering.md "Photographic look"): when
//! the search's best hypothesis is explained neither by the drawings nor by the pictures, its
//! neighbours are tried. The search ranks hypotheses by how many drawing features they leave
//! unexplained, and on camera pictures the front end misses faint edges, so the true blocks
//! can rank below a wrong set that happens to match more of a damaged drawing; the picture
//! check ([`super::picture::pictures_mismatch`]) tells them apart, but only for the
//! hypotheses it is shown.
//!
//! A neighbour differs from the hypothesis by one move over the pooled candidates of step 4
//! (Chapter V's comparison of views): one candidate added, one block removed, one block
//! replaced by a candidate it overlaps (a b15 that was half of a b30), or two touching blocks
//! replaced by two candidates filling the same box (an L of three cells split the other way).
//! Two more moves need no candidate: one block cut in two basic blocks filling its box (a b30
//! into two b15, a b15 into two stacked b7_5: a crack the front end missed under a lamp) and
//! two touching blocks joined into the one basic block filling both (a crack the front end
//! read where there is none). A cut or join changes a crack in every view that sees it, so it
//! may leave up to [`MAX_EXTRA_MISMATCH`] more drawing features per view; those neighbours are
//! shown first. Neighbours are redrawn and ranked by their drawing mismatch, and the best few
//! are shown to the picture check; the first it explains is taken. The answer still passes every final
//! check (the views deciding the blocks, support), so a neighbour only replaces a hypothesis
//! that would have been declined.

use super::catalog_match::{blocks_overlap, bounds_mm, touching_pairs};
use super::compare::{corner_gain, Hypothesis, PooledCandidate, SearchLimits, FLUSH_TOL_MM};
use super::edge_profile::ViewPicture;
use super::ObservedView;
use crate::geom::{DVec3, CONTACT_TOL_MM};
use crate::scene::Block;

/// At most this many neighbours, the fewest drawing mismatches first, are shown to the picture
/// check: each costs a reading of the pictures along every line the redraw and the drawing
/// disagree on.
pub const MAX_PICTURE_CHECKS: usize = 16;

/// A neighbour may leave at most this many more drawing features unexplained than the
/// hypothesis it comes from: the pictures explain a missed faint edge or two per view, not a
/// different scene.
pub const MAX_EXTRA_MISMATCH: usize = 4;

/// Candidates added, those proposed by the most views and then best by [`corner_gain`] first,
/// redrawn per hypothesis.
const ADDS_REDRAWN: usize = 24;

/// Candidates put in place of one block, ranked as added ones, redrawn per block.
const SWAPS_REDRAWN: usize = 3;

/// The cut and join moves are tried only when every picture has at least this many px per
/// mm: a crack the picture must confirm is a fraction of a millimetre wide, and in a held-out
/// draw at 256 x 240 (about 1.5 px per mm) a shading step confirmed a crack that is not there
/// (docs/recognizer-pictures.md "Cracks the front end missed: cut and joined blocks").
pub const CUT_MIN_PX_PER_MM: f64 = 2.5;

/// `true` when every one of `pictures` resolves a crack well enough for the cut and join
/// moves ([`CUT_MIN_PX_PER_MM`]).
pub(super) fn cracks_resolved(pictures: &[ViewPicture]) -> bool {
    pictures.iter().all(|p| p.px_per_mm >= CUT_MIN_PX_PER_MM)
}

/// The neighbours of `h` (see the module doc), redrawn, in the order they are worth showing
/// to the picture check: fewest drawing mismatches first, ties in the order of the moves.
fn neighbours(
    h: &Hypothesis,
    pool: &[PooledCandidate],
    views: &[ObservedView],
    limits: &SearchLimits,
    cracks_resolved: bool,
) -> Vec<Hypothesis> {
    let candidates = snapped_candidates(&h.blocks, pool);
    let free = |c: &Block, except: &[usize]| {
        h.blocks
            .iter()
            .enumerate()
            .all(|(i, b)| except.contains(&i) || !blocks_overlap(b, c))
    };
    // The best `n` of `cs`: proposed by the most views, then by [`corner_gain`].
    let best = |cs: Vec<&Snapped>, n: usize| -> Vec<Block> {
        let mut ranked: Vec<(Block, (usize, usize, usize))> = cs
            .into_iter()
            .map(|c| {
                let g = corner_gain(&c.block, views, h, limits.tol_px);
                (c.block, (c.views, g.0, g.1))
            })
            .filter(|(_, g)| g.2 > 0)
            .collect();
        ranked.sort_by_key(|r| std::cmp::Reverse(r.1));
        ranked.into_iter().take(n).map(|(c, _)| c).collect()
    };
    let mut sets: Vec<Vec<Block>> = Vec::new();
    if h.blocks.len() < limits.max_blocks {
        let adds = candidates.iter().filter(|c| free(&c.block, &[])).collect();
        for c in best(adds, ADDS_REDRAWN) {
            sets.push(with_blocks(&h.blocks, &[], &[c]));
        }
    }
    for i in 0..h.blocks.len() {
        sets.push(with_blocks(&h.blocks, &[i], &[]));
        let swaps = candidates
            .iter()
            .filter(|c| blocks_overlap(&h.blocks[i], &c.block) && free(&c.block, &[i]))
            .filter(|c| !same_block(&h.blocks[i], &c.block))
            .collect();
        for c in best(swaps, SWAPS_REDRAWN) {
            sets.push(with_blocks(&h.blocks, &[i], &[c]));
        }
    }
    let cuts = if cracks_resolved {
        cuts_and_joins(h, &free)
    } else {
        Vec::new()
    };
    let blocks: Vec<Block> = candidates.iter().map(|c| c.block).collect();
    for (i, j, a, b) in pair_retilings(&h.blocks, &blocks) {
        sets.push(with_blocks(&h.blocks, &[i, j], &[a, b]));
    }
    let cut_bar = h.mismatch() + MAX_EXTRA_MISMATCH * views.len();
    let mut out = redrawn_within(cuts, cut_bar, views, limits);
    out.extend(redrawn_within(
        sets,
        h.mismatch() + MAX_EXTRA_MISMATCH,
        views,
        limits,
    ));
    out
}

/// `sets` redrawn while the budget lasts, those leaving at most `bar` drawing features
/// unexplained, fewest first (ties in the order of `sets`).
fn redrawn_within(
    sets: Vec<Vec<Block>>,
    bar: usize,
    views: &[ObservedView],
    limits: &SearchLimits,
) -> Vec<Hypothesis> {
    let mut redrawn: Vec<Hypothesis> = sets
        .into_iter()
        .take_while(|_| limits.budget.spend())
        .map(|blocks| Hypothesis::new(blocks, views, limits.tol_px))
        .filter(|n| n.mismatch() <= bar)
        .collect();
    redrawn.sort_by_key(Hypothesis::mismatch);
    redrawn
}

/// The blocks of `h` with one block cut in two basic blocks ([`halvings`]) or two touching
/// blocks joined into one ([`joined`]), where `free` lets the new blocks stand
/// (`free(block, replaced)`).
fn cuts_and_joins(h: &Hypothesis, free: &dyn Fn(&Block, &[usize]) -> bool) -> Vec<Vec<Block>> {
    let mut out = Vec::new();
    for (i, b) in h.blocks.iter().enumerate() {
        for halves in halvings(b) {
            if halves.iter().all(|c| free(c, &[i])) {
                out.push(with_blocks(&h.blocks, &[i], &halves));
            }
        }
    }
    for [i, j] in touching_pairs(&h.blocks, 2.0 * CONTACT_TOL_MM) {
        if let Some(m) = joined(&h.blocks[i], &h.blocks[j]) {
            if free(&m, &[i, j]) {
                out.push(with_blocks(&h.blocks, &[i, j], &[m]));
            }
        }
    }
    out
}

/// A pooled candidate moved onto the blocks' faces ([`snapped_candidates`]).
#[derive(Debug, Clone, Copy)]
struct Snapped {
    block: Block,
    /// How many views proposed it (Chapter V: a block seen from several views).
    views: usize,
}

/// The pooled candidates moved onto the faces of `blocks` they nearly share (each axis by the
/// smallest shift up to [`FLUSH_TOL_MM`] that puts one of its faces on a block's face or the
/// floor), once each: a candidate is placed from the mean of measured corners, a few tenths of
/// a millimetre off the blocks it touches, which would read as an overlap.
fn snapped_candidates(blocks: &[Block], pool: &[PooledCandidate]) -> Vec<Snapped> {
    let bounds: Vec<(DVec3, DVec3)> = blocks.iter().map(bounds_mm).collect();
    let faces: [Vec<f64>; 3] = std::array::from_fn(|k| {
        let mut f: Vec<f64> = bounds.iter().flat_map(|(lo, hi)| [lo[k], hi[k]]).collect();
        if k == 1 {
            f.push(0.0);
        }
        f
    });
    let mut out: Vec<Snapped> = Vec::new();
    let mut seen = std::collections::HashMap::new();
    for c in pool {
        let mut b = c.block;
        let (lo, hi) = bounds_mm(&b);
        for k in 0..3 {
            let shift = faces[k]
                .iter()
                .flat_map(|f| [f - lo[k], f - hi[k]])
                .filter(|d| d.abs() <= FLUSH_TOL_MM)
                .min_by(|a, b| a.abs().total_cmp(&b.abs()));
            if let Some(d) = shift {
                b.center_mm[k] += d;
            }
        }
        let key = (
            b.block_type.id,
            (super::compare::yaw_deg(&b) * 10.0).round() as i64,
            (b.center_mm * 4.0).round().as_i64vec3().to_array(),
        );
        match seen.get(&key) {
            Some(&k) => {
                let o: &mut Snapped = &mut out[k];
                o.views = o.views.max(c.views.len());
            }
            None => {
                seen.insert(key, out.len());
                out.push(Snapped {
                    block: b,
                    views: c.views.len(),
                });
            }
        }
    }
    out
}

/// The basic catalog block (turned 0 or 90 degrees about +y) whose box is `lo..hi`, if any.
fn basic_block_filling(lo: DVec3, hi: DVec3) -> Option<Block> {
    let size = hi - lo;
    crate::scene::basic_blocks().find_map(|t| {
        [0.0, 90.0].into_iter().find_map(|yaw| {
            let b = Block::new(t.id, (lo + hi) * 0.5, yaw);
            let (l, h) = bounds_mm(&b);
            ((h - l - size).abs().max_element() <= FILL_TOL_MM).then_some(b)
        })
    })
}

/// Every way to cut block `b` in two halves along an axis, each a basic catalog block (a b30
/// into two b15, a b15 into two b7_5): the blocks a crack the front end missed would show.
fn halvings(b: &Block) -> Vec<[Block; 2]> {
    let (lo, hi) = bounds_mm(b);
    let mid = (lo + hi) * 0.5;
    (0..3)
        .filter_map(|k| {
            let (mut hi_a, mut lo_b) = (hi, lo);
            hi_a[k] = mid[k];
            lo_b[k] = mid[k];
            Some([
                basic_block_filling(lo, hi_a)?,
                basic_block_filling(lo_b, hi)?,
            ])
        })
        .collect()
}

/// The basic catalog block filling the box two touching blocks fill together, if they do.
fn joined(a: &Block, b: &Block) -> Option<Block> {
    let ((la, ha), (lb, hb)) = (bounds_mm(a), bounds_mm(b));
    let (lo, hi) = (la.min(lb), ha.max(hb));
    let filled = (hi - lo).element_product();
    ((a.volume_mm3() + b.volume_mm3() - filled).abs() <= FILL_TOL_MM3)
        .then(|| basic_block_filling(lo, hi))
        .flatten()
}

/// `blocks` without those at `removed` (indices), with `added` appended.
fn with_blocks(blocks: &[Block], removed: &[usize], added: &[Block]) -> Vec<Block> {
    blocks
        .iter()
        .enumerate()
        .filter(|(i, _)| !removed.contains(i))
        .map(|(_, b)| *b)
        .chain(added.iter().copied())
        .collect()
}

/// `true` when `a` and `b` are the same catalog block in the same box (to [`FILL_TOL_MM`]).
fn same_block(a: &Block, b: &Block) -> bool {
    a.block_type.id == b.block_type.id && same_box(bounds_mm(a), bounds_mm(b))
}

/// `true` when two boxes agree to [`FILL_TOL_MM`] on every face.
fn same_box((la, ha): (DVec3, DVec3), (lb, hb): (DVec3, DVec3)) -> bool {
    (la - lb).abs().max_element() <= FILL_TOL_MM && (ha - hb).abs().max_element() <= FILL_TOL_MM
}

/// Two boxes' faces within this are one face, mm: pooled candidates are placed from measured
/// corners, a fraction of a millimetre off the hypothesis's blocks.
const FILL_TOL_MM: f64 = 1.0;

/// Every way to replace two touching blocks `i` and `j` of `blocks` by two other pooled
/// candidates `a` and `b` that fill the same space as they do, no more and no less (each
/// inside the two, apart, the same volume together: a box or an L of three cells tiled the
/// other way), each overlapping no other block: `(i, j, a, b)`.
fn pair_retilings(blocks: &[Block], candidates: &[Block]) -> Vec<(usize, usize, Block, Block)> {
    let mut out = Vec::new();
    for [i, j] in touching_pairs(blocks, 2.0 * CONTACT_TOL_MM) {
        let (bi, bj) = (bounds_mm(&blocks[i]), bounds_mm(&blocks[j]));
        let volume = blocks[i].volume_mm3() + blocks[j].volume_mm3();
        let inside: Vec<&Block> = candidates
            .iter()
            .filter(|c| {
                let bc = bounds_mm(c);
                let covered = overlap_volume_mm3(bc, bi) + overlap_volume_mm3(bc, bj);
                (covered - c.volume_mm3()).abs() <= FILL_TOL_MM3
            })
            .filter(|c| !same_block(c, &blocks[i]) && !same_block(c, &blocks[j]))
            .filter(|c| {
                blocks
                    .iter()
                    .enumerate()
                    .all(|(k, b)| k == i || k == j || !blocks_overlap(b, c))
            })
            .collect();
        for (m, a) in inside.iter().enumerate() {
            for b in &inside[m + 1..] {
                let v = a.volume_mm3() + b.volume_mm3();
                if !blocks_overlap(a, b) && (v - volume).abs() <= FILL_TOL_MM3 {
                    out.push((i, j, **a, **b));
                }
            }
        }
    }
    out
}

/// Volumes within this are equal, mm^3: a candidate placed a fraction of a millimetre off
/// changes its overlap with a 15 mm cell by a few mm^3 per face.
const FILL_TOL_MM3: f64 = 60.0;

/// The volume two boxes share, mm^3.
fn overlap_volume_mm3((la, ha): (DVec3, DVec3), (lb, hb): (DVec3, DVec3)) -> f64 {
    (ha.min(hb) - la.max(lb)).max(DVec3::ZERO).element_product()
}

/// The first neighbour of `h` (see the module doc) that `explained` accepts, trying at most
/// [`MAX_PICTURE_CHECKS`] of them; `None` when none is.
pub(super) fn repaired_in_pictures(
    h: &Hypothesis,
    pool: &[PooledCandidate],
    views: &[ObservedView],
    limits: &SearchLimits,
    explained: &dyn Fn(&Hypothesis) -> bool,
    cracks_resolved: bool,
) -> Option<Hypothesis> {
    neighbours(h, pool, views, limits, cracks_resolved)
        .into_iter()
        .take(MAX_PICTURE_CHECKS)
        .find(|n| explained(n))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::CornerView;
    use crate::recognize::budget::SearchBudget;
    use crate::recognize::{views_of, RecognizeOptions};

    fn limits<'a>(budget: &'a SearchBudget<'a>) -> SearchLimits<'a> {
        SearchLimits::new(&RecognizeOptions::default(), budget)
    }

    fn unlimited() -> SearchBudget<'static> {
        SearchBudget::new((u64::MAX, f64::INFINITY), 1, &|_| {})
    }

    fn pooled(block: Block) -> PooledCandidate {
        PooledCandidate {
            block,
            views: vec![0, 1],
            fit_views: Vec::new(),
            side_fit: false,
            proposals: 2,
        }
    }

    fn b(id: &str, x: f64, y: f64, z: f64, yaw_deg: f64) -> Block {
        Block::new(id, DVec3::new(x, y, z), yaw_deg)
    }

    #[test]
    fn a_block_the_search_missed_is_added_when_the_check_explains_the_neighbour() {
        let truth = [
            b("b15", 7.5, 7.5, 7.5, 0.0),
            b("b15", 22.5, 7.5, 7.5, 0.0),
            b("b15", 7.5, 22.5, 7.5, 0.0),
        ];
        let views = views_of(&truth, &CornerView::ALL);
        let budget = unlimited();
        let limits = limits(&budget);
        let h = Hypothesis::new(truth[..2].to_vec(), &views, limits.tol_px);
        assert!(h.mismatch() > 0);
        // Measured a few tenths of a millimetre off, overlapping the block below by 0.15 mm.
        let off = b("b15", 7.7, 22.35, 7.6, 0.0);
        let far = b("b15", 45.0, 7.5, 45.0, 0.0);
        let pool = [pooled(far), pooled(off)];
        let explained = |n: &Hypothesis| n.mismatch() == 0;
        let r = repaired_in_pictures(&h, &pool, &views, &limits, &explained, true).unwrap();
        assert_eq!(r.blocks.len(), 3);
        assert!(r.blocks[2].center_mm.distance(truth[2].center_mm) < 1e-9);
        // A check that explains nothing takes no neighbour.
        let nothing = |_: &Hypothesis| false;
        assert!(repaired_in_pictures(&h, &pool, &views, &limits, &nothing, true).is_none());
    }

    /// Two b15 answered as one b30: the cut repairs it where the pictures resolve cracks, and
    /// is not tried where they do not.
    #[test]
    fn a_cut_is_tried_only_where_the_pictures_resolve_cracks() {
        let truth = [b("b15", 7.5, 7.5, 7.5, 0.0), b("b15", 22.5, 7.5, 7.5, 0.0)];
        let views = views_of(&truth, &CornerView::ALL);
        let budget = unlimited();
        let limits = limits(&budget);
        let h = Hypothesis::new(vec![b("b30", 15.0, 7.5, 7.5, 0.0)], &views, limits.tol_px);
        assert!(h.mismatch() > 0);
        let explained = |n: &Hypothesis| n.mismatch() == 0;
        let cut = repaired_in_pictures(&h, &[], &views, &limits, &explained, true).unwrap();
        assert!(crate::scene::same_blocks(&cut.blocks, &truth, 1e-6));
        assert!(repaired_in_pictures(&h, &[], &views, &limits, &explained, false).is_none());
    }

    #[test]
    fn a_b30_cuts_into_two_b15_and_two_stacked_b7_5_join_into_a_b15() {
        let b30 = b("b30", 15.0, 7.5, 7.5, 0.0);
        let cuts = halvings(&b30);
        assert_eq!(cuts.len(), 1, "a b30 halves only along its length");
        let centres: Vec<f64> = cuts[0].iter().map(|c| c.center_mm.x).collect();
        assert_eq!(cuts[0].map(|c| c.block_type.id), ["b15", "b15"]);
        assert_eq!(centres, vec![7.5, 22.5]);
        let b15 = b("b15", 7.5, 7.5, 7.5, 0.0);
        let stacked = halvings(&b15);
        assert_eq!(stacked.len(), 1, "a b15 halves only in height");
        assert_eq!(stacked[0].map(|c| c.center_mm.y), [3.75, 11.25]);
        let [lower, upper] = stacked[0];
        assert_eq!(joined(&lower, &upper).map(|j| j.block_type.id), Some("b15"));
        assert!(
            halvings(&lower).is_empty(),
            "no catalog block is half a b7_5"
        );
        // Two b15 side by side fill a b30 turned 90 degrees.
        let beside = b("b15", 7.5, 7.5, 22.5, 0.0);
        assert_eq!(joined(&b15, &beside).map(|j| j.block_type.id), Some("b30"));
        let apart = b("b15", 7.5, 7.5, 37.5, 0.0);
        assert!(joined(&b15, &apart).is_none(), "blocks apart fill no box");
    }

    #[test]
    fn snapping_moves_a_candidate_onto_faces_it_nearly_shares_and_no_further() {
        let blocks = [b("b15", 7.5, 7.5, 7.5, 0.0)];
        let near = b("b15", 22.35, 7.7, 7.62, 0.0);
        let apart = b("b15", 25.0, 7.5, 7.5, 0.0);
        let s = snapped_candidates(&blocks, &[pooled(near), pooled(apart), pooled(near)]);
        assert_eq!(s.len(), 2, "the same candidate twice is one");
        assert!(s[0].block.center_mm.distance(DVec3::new(22.5, 7.5, 7.5)) < 1e-9);
        assert!(!blocks_overlap(&blocks[0], &s[0].block));
        // 2.5 mm off is another place, not a measurement error: only its floor face moves.
        assert!(s[1].block.center_mm.distance(DVec3::new(25.0, 7.5, 7.5)) < 1e-9);
    }

    #[test]
    fn an_l_of_three_cells_is_retiled_the_other_way_and_nothing_leaving_a_gap() {
        // A b15 and a b30 along z (yaw 90) fill the L; a b30 along x and a b15 fill it too.
        let blocks = [
            b("b15", 7.5, 7.5, 7.5, 0.0),
            b("b30", 22.5, 7.5, 15.0, 90.0),
        ];
        let along_x = b("b30", 15.0, 7.5, 7.5, 0.0);
        let corner = b("b15", 22.5, 7.5, 22.5, 0.0);
        let outside = b("b15", 7.5, 7.5, 22.5, 0.0);
        let r = pair_retilings(&blocks, &[along_x, outside, corner]);
        assert_eq!(r.len(), 1);
        let (i, j, x, y) = r[0];
        assert_eq!((i, j), (0, 1));
        assert!(same_block(&x, &along_x) && same_block(&y, &corner));
        // Without the corner cell the b30 along x leaves the L's far cell empty.
        assert!(pair_retilings(&blocks, &[along_x, outside]).is_empty());
    }
}
