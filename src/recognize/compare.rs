//! Step 4 of the recognizer: compare the views (Chapter V's three rules) and choose the blocks.
//!
//! Every view proposes catalog blocks from its parallelograms ([`super::catalog_match`]). The
//! proposals are pooled across views: a block proposed by several views is one candidate.
//! Rule (1), "the longest length is chosen", holds because each view proposes only blocks at
//! least as long as the sides it sees, so a candidate kept from two views fits the longer of
//! the two; rule (2), a failed search means inconsistent vertices, and rule (3), no
//! parallelogram on a side means no block there, hold because a vertex proposes nothing on a
//! side its code has no line for. A block hidden in one view is recovered from another.
//!
//! The pooled candidates are then chosen by hypothesize-and-test (allowed by the thesis's
//! "further examination of the block connections is necessary", Chapter V): blocks are added
//! one at a time, each time the candidate whose redrawn views (step 6, [`super::verify`])
//! explain the most of the observed drawings, until nothing improves.

use super::budget::SearchBudget;
use super::catalog_match::{blocks_overlap, distinct_yaws_deg, make_touching_flush, Proposal};
use super::verify::{compare_drawings, draw_hypothesis, ViewCheck};
use super::{ObservedView, RecognizeOptions};
use crate::drawing::LineDrawing;
use crate::geom::{DVec2, DVec3};
use crate::scene::{basic_blocks, Block, Orientation};
use std::collections::HashMap;
use std::hash::BuildHasherDefault;

/// A block proposed by one or more views.
#[derive(Debug, Clone, PartialEq)]
pub struct PooledCandidate {
    /// The catalog block, placed in world mm.
    pub block: Block,
    /// Indices of the views whose parallelograms proposed it.
    pub views: Vec<usize>,
    /// Indices of the views where it fits a closed parallelogram exactly
    /// ([`Proposal::closed_fit`]).
    pub fit_views: Vec<usize>,
    /// `true` when some view sees one of its sides as a closed parallelogram it fits exactly
    /// ([`Proposal::side_fit`]).
    pub side_fit: bool,
    /// How many parallelograms proposed it; `block.center_mm` is their mean.
    pub proposals: usize,
}

/// The yaw of a block in degrees (0 for a quaternion; candidates carry yaws).
pub fn yaw_deg(b: &Block) -> f64 {
    match b.orientation {
        Orientation::YawDeg(y) => y,
        Orientation::Quaternion(_) => 0.0,
    }
}

/// Pools per-view proposals: same type, same yaw and centres within `tol_mm` (of the running
/// mean) are one candidate, placed at the mean of its proposals. Order: first proposal first
/// (deterministic).
pub fn pool_candidates(per_view: &[Vec<Block>], tol_mm: f64) -> Vec<PooledCandidate> {
    let per_view: Vec<Vec<Proposal>> = per_view
        .iter()
        .map(|blocks| {
            blocks
                .iter()
                .map(|&block| Proposal {
                    block,
                    closed_fit: false,
                    side_fit: false,
                })
                .collect()
        })
        .collect();
    pool_proposals(&per_view, tol_mm)
}

/// The grid cell of a centre, cells `2 tol_mm` wide, and per axis the neighbouring cell on the
/// side nearer the centre: a candidate within `tol_mm` of the centre lies in one of the 8
/// cells so named.
fn cells_near(c: DVec3, tol_mm: f64) -> ([i64; 3], [i64; 3]) {
    let u = c / (2.0 * tol_mm.max(1e-9));
    let cell = u.floor();
    let side = (u - cell).to_array().map(|f| if f < 0.5 { -1 } else { 1 });
    (cell.to_array().map(|x| x as i64), side)
}

/// A multiplicative hasher for the pooling grid's integer keys (SipHash's protection against
/// chosen keys is not needed for cells of measured centres).
#[derive(Default)]
struct CellHasher(u64);

impl std::hash::Hasher for CellHasher {
    fn write(&mut self, bytes: &[u8]) {
        for chunk in bytes.chunks(8) {
            let mut word = [0u8; 8];
            word[..chunk.len()].copy_from_slice(chunk);
            self.write_u64(u64::from_le_bytes(word));
        }
    }

    fn write_u64(&mut self, x: u64) {
        self.0 = (self.0.rotate_left(5) ^ x).wrapping_mul(0x517c_c1b7_2722_0a95);
    }

    fn write_i64(&mut self, x: i64) {
        self.write_u64(x as u64);
    }

    fn write_usize(&mut self, x: usize) {
        self.write_u64(x as u64);
    }

    fn finish(&self) -> u64 {
        self.0
    }
}

/// [`pool_candidates`] keeping the fit marks: the views where a candidate fits a closed
/// parallelogram exactly. Candidates are found through a grid of `2 tol_mm` cells keyed by
/// their first proposal, so pooling stays linear in the proposals.
pub fn pool_proposals(per_view: &[Vec<Proposal>], tol_mm: f64) -> Vec<PooledCandidate> {
    type Grid = HashMap<(u64, [i64; 3]), Vec<usize>, BuildHasherDefault<CellHasher>>;
    let mut pool: Vec<PooledCandidate> = Vec::new();
    let mut grid = Grid::default();
    for (v, proposals) in per_view.iter().enumerate() {
        for p in proposals {
            let b = &p.block;
            // Type (its id's address: one static per catalog entry) and yaw.
            let kind = (b.block_type.id.as_ptr() as u64) ^ yaw_deg(b).to_bits().rotate_left(17);
            let (cell, side) = cells_near(b.center_mm, tol_mm);
            let same = (0..8)
                .map(|k| [0, 1, 2].map(|a| cell[a] + if k >> a & 1 == 1 { side[a] } else { 0 }))
                .filter_map(|c| grid.get(&(kind, c)))
                .flatten()
                .copied()
                .filter(|&k| {
                    let c = &pool[k].block;
                    c.block_type.id == b.block_type.id
                        && yaw_deg(c) == yaw_deg(b)
                        && c.center_mm.distance(b.center_mm) <= tol_mm
                })
                .min();
            match same {
                Some(k) => {
                    // The running mean of every proposal's centre.
                    let c = &mut pool[k];
                    c.proposals += 1;
                    let n = c.proposals as f64;
                    c.block.center_mm += (b.center_mm - c.block.center_mm) / n;
                    if !c.views.contains(&v) {
                        c.views.push(v);
                    }
                    if p.closed_fit && !c.fit_views.contains(&v) {
                        c.fit_views.push(v);
                    }
                    c.side_fit |= p.side_fit;
                }
                None => {
                    grid.entry((kind, cell)).or_default().push(pool.len());
                    pool.push(PooledCandidate {
                        block: *b,
                        views: vec![v],
                        fit_views: if p.closed_fit { vec![v] } else { Vec::new() },
                        side_fit: p.side_fit,
                        proposals: 1,
                    });
                }
            }
        }
    }
    pool
}

/// Faces closer than this are made flush before each redraw, mm (far below any catalog size,
/// far above the measurement error of a vertex).
pub const FLUSH_TOL_MM: f64 = 0.5;

/// The state of the search: chosen blocks (made flush), their exact drawings and per-view
/// checks (step 6), and the observed points no drawn point explains yet.
#[derive(Clone)]
pub(super) struct Hypothesis {
    /// The blocks, touching faces made flush.
    pub blocks: Vec<Block>,
    /// Their exact drawing in every view.
    pub drawn: Vec<LineDrawing>,
    /// Each view's comparison with the observed drawing.
    pub checks: Vec<ViewCheck>,
    unexplained: Vec<Vec<DVec2>>,
}

impl Hypothesis {
    /// Draws `blocks` (made flush) in every view and compares with the observed drawings.
    pub fn new(blocks: Vec<Block>, views: &[ObservedView], tol_px: f64) -> Hypothesis {
        let blocks = make_touching_flush(&blocks, FLUSH_TOL_MM);
        let drawn: Vec<LineDrawing> = views
            .iter()
            .map(|v| draw_hypothesis(&blocks, &v.camera))
            .collect();
        let checks = views
            .iter()
            .zip(&drawn)
            .map(|(v, d)| compare_drawings(d, &v.drawing, tol_px))
            .collect();
        let unexplained = views
            .iter()
            .zip(&drawn)
            .map(|(v, d)| {
                v.drawing
                    .points
                    .iter()
                    .copied()
                    .filter(|p| !d.points.iter().any(|q| q.distance(*p) <= tol_px))
                    .collect()
            })
            .collect();
        Hypothesis {
            blocks,
            drawn,
            checks,
            unexplained,
        }
    }

    /// Total disagreement over the views (0: every view explained).
    pub fn mismatch(&self) -> usize {
        self.checks.iter().map(ViewCheck::mismatch).sum()
    }
}

/// The cheap estimates that rank candidates before the exact redraw: how many of `b`'s
/// projected corners fall on still-unexplained observed points, and on any observed point,
/// over all views. A block whose corners are all shared with chosen neighbours (the middle of
/// a row, whose corners are cracks) still ranks by the second.
pub(super) fn corner_gain(
    b: &Block,
    views: &[ObservedView],
    h: &Hypothesis,
    tol_px: f64,
) -> (usize, usize) {
    let corners = b.world_vertices();
    let mut open_hits = 0;
    let mut all_hits = 0;
    for (v, open) in views.iter().zip(&h.unexplained) {
        for c in &corners {
            let p = v.camera.picture_from_world(*c).truncate();
            open_hits += usize::from(open.iter().any(|q| q.distance(p) <= tol_px));
            all_hits += usize::from(v.drawing.points.iter().any(|q| q.distance(p) <= tol_px));
        }
    }
    (open_hits, all_hits)
}

/// Candidate indices in the order they are redrawn: alternately the best by unexplained
/// corners and the best by all corners on observed points, each once.
fn redraw_order(mut ranked: Vec<(usize, (usize, usize))>) -> Vec<usize> {
    ranked.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
    let by_open: Vec<usize> = ranked.iter().map(|r| r.0).collect();
    ranked.sort_by(|a, b| (b.1 .1, b.1 .0).cmp(&(a.1 .1, a.1 .0)).then(a.0.cmp(&b.0)));
    let by_all: Vec<usize> = ranked.iter().map(|r| r.0).collect();
    let mut order = Vec::with_capacity(by_open.len());
    for (a, b) in by_open.iter().zip(&by_all) {
        for i in [*a, *b] {
            if !order.contains(&i) {
                order.push(i);
            }
        }
    }
    order
}

/// Search limits of [`choose_blocks`].
#[derive(Debug, Clone, Copy)]
pub struct SearchLimits<'a> {
    /// Picture tolerance of the comparisons, px.
    pub tol_px: f64,
    /// How many best-ranked candidates are redrawn exactly per step; when none of them
    /// improves the hypothesis, the next as many, and so on.
    pub shortlist: usize,
    /// At most this many candidates redrawn per step.
    pub max_redraws_per_step: usize,
    /// At most this many blocks are chosen.
    pub max_blocks: usize,
    /// At most this many repair rounds (each forbids one more chosen block).
    pub repair_rounds: usize,
    /// The nodes and time the search may spend; once spent, it stops.
    pub budget: &'a SearchBudget<'a>,
}

impl<'a> SearchLimits<'a> {
    /// The limits `opts` sets, spending `budget`.
    pub fn new(opts: &RecognizeOptions, budget: &'a SearchBudget<'a>) -> SearchLimits<'a> {
        SearchLimits {
            tol_px: opts.tol_px,
            shortlist: opts.shortlist,
            max_redraws_per_step: opts.max_redraws_per_step,
            max_blocks: opts.max_blocks,
            repair_rounds: opts.repair_rounds,
            budget,
        }
    }
}

/// One greedy pass from `start`: adds, one at a time, the shortlisted candidate whose redrawn views
/// disagree least with the observed ones, skipping `banned` pool indices; returns the chosen
/// pool indices and the final hypothesis.
fn greedy(
    pool: &[PooledCandidate],
    views: &[ObservedView],
    limits: &SearchLimits,
    banned: &[usize],
    start: Hypothesis,
) -> (Vec<usize>, Hypothesis) {
    let mut h = start;
    let mut chosen = Vec::new();
    let budget = limits.budget;
    while h.mismatch() > 0 && h.blocks.len() < limits.max_blocks {
        let ranked: Vec<(usize, (usize, usize))> = pool
            .iter()
            .enumerate()
            .filter(|(i, c)| {
                !banned.contains(i) && !h.blocks.iter().any(|b| blocks_overlap(b, &c.block))
            })
            .take_while(|_| budget.spend())
            .map(|(i, c)| (i, corner_gain(&c.block, views, &h, limits.tol_px)))
            .filter(|&(_, g)| g.1 > 0)
            .collect();
        let order = redraw_order(ranked);
        let mut best: Option<(usize, Hypothesis)> = None;
        for (n, &i) in order.iter().take(limits.max_redraws_per_step).enumerate() {
            if (best.is_some() && n % limits.shortlist.max(1) == 0) || !budget.spend() {
                break;
            }
            let mut blocks = h.blocks.clone();
            blocks.push(pool[i].block);
            let next = Hypothesis::new(blocks, views, limits.tol_px);
            let bar = best.as_ref().map_or(h.mismatch(), |b| b.1.mismatch());
            if next.mismatch() < bar {
                best = Some((i, next));
            }
        }
        match best {
            Some((i, b)) if !budget.spent() => {
                chosen.push(i);
                h = b;
            }
            _ => break,
        }
    }
    (chosen, h)
}

/// Greedy passes from nothing, each followed by splitting chosen blocks where the halves
/// explain more (one b30 where two b15 lie flush with a visible crack) and more greedy passes.
fn greedy_and_split(
    pool: &[PooledCandidate],
    views: &[ObservedView],
    limits: &SearchLimits,
    banned: &[usize],
) -> (Vec<usize>, Hypothesis) {
    let empty = Hypothesis::new(Vec::new(), views, limits.tol_px);
    greedy_and_split_from(pool, views, limits, banned, empty)
}

/// [`greedy_and_split`] from a given hypothesis (its blocks stay; more are added or split).
pub(super) fn greedy_and_split_from(
    pool: &[PooledCandidate],
    views: &[ObservedView],
    limits: &SearchLimits,
    banned: &[usize],
    start: Hypothesis,
) -> (Vec<usize>, Hypothesis) {
    let (mut chosen, mut h) = greedy(pool, views, limits, banned, start);
    while h.mismatch() > 0 && !limits.budget.spent() {
        let split = (0..h.blocks.len()).find_map(|i| {
            let splits = catalog_splits(&h.blocks[i]).into_iter();
            splits
                .take_while(|_| limits.budget.spend())
                .find_map(|halves| {
                    let mut blocks = h.blocks.clone();
                    blocks.splice(i..=i, halves);
                    let next = Hypothesis::new(blocks, views, limits.tol_px);
                    (next.mismatch() < h.mismatch()).then_some(next)
                })
        });
        let Some(next) = split else {
            break;
        };
        let (more, after) = greedy(pool, views, limits, banned, next);
        chosen.extend(more);
        h = after;
    }
    (chosen, h)
}

/// Chooses blocks from `pool` by hypothesize-and-test: greedy passes with splits, then, while
/// views stay unexplained, passes that each forbid one more chosen block (a block explaining
/// much at once is then replaced by what explains all); at most `limits.repair_rounds` rounds.
/// Returns the chosen blocks and the per-view checks.
pub fn choose_blocks(
    pool: &[PooledCandidate],
    views: &[ObservedView],
    limits: &SearchLimits,
) -> (Vec<Block>, Vec<ViewCheck>) {
    let best = choose_hypothesis(pool, views, limits);
    (best.blocks, best.checks)
}

/// [`choose_blocks`] returning the whole hypothesis, drawings included.
pub(super) fn choose_hypothesis(
    pool: &[PooledCandidate],
    views: &[ObservedView],
    limits: &SearchLimits,
) -> Hypothesis {
    let mut banned: Vec<usize> = Vec::new();
    let (mut chosen, mut best) = greedy_and_split(pool, views, limits, &banned);
    for _ in 0..limits.repair_rounds {
        if best.mismatch() == 0 || limits.budget.spent() {
            break;
        }
        let mut round: Option<(usize, Vec<usize>, Hypothesis)> = None;
        for &i in chosen.iter().take_while(|_| !limits.budget.spent()) {
            let mut ban = banned.clone();
            ban.push(i);
            let (c, h) = greedy_and_split(pool, views, limits, &ban);
            let bar = round.as_ref().map_or(best.mismatch(), |r| r.2.mismatch());
            if h.mismatch() < bar {
                let done = h.mismatch() == 0;
                round = Some((i, c, h));
                if done {
                    break;
                }
            }
        }
        match round {
            Some((i, c, h)) => {
                banned.push(i);
                chosen = c;
                best = h;
            }
            None => break,
        }
    }
    best
}

/// The ways a block is two catalog blocks flush against each other (one b30 is two b15 end to
/// end, one b15 is two b7_5 stacked), read from the catalog sizes: a type whose size is this
/// type's with one axis halved (its x and z possibly swapped, i.e. turned 90 degrees). Only a
/// cuboid splits so: a trapezoidal block (Figure 7.1) has none.
pub fn catalog_splits(b: &Block) -> Vec<[Block; 2]> {
    if b.block_type.cuboid_half_extents_mm().is_none() {
        return Vec::new();
    }
    let size = b.block_type.size_mm();
    let yaw = yaw_deg(b);
    let rot = b.rotation();
    let mut out = Vec::new();
    for k in 0..3 {
        let mut half = size;
        half[k] /= 2.0;
        for t in basic_blocks() {
            let s = t.size_mm();
            let turn = if s.distance(half) < 1e-9 {
                0.0
            } else if DVec3::new(s.z, s.y, s.x).distance(half) < 1e-9 {
                90.0
            } else {
                continue;
            };
            let mut step = DVec3::ZERO;
            step[k] = size[k] / 4.0;
            let step = rot * step;
            let part_yaw = (yaw + turn).rem_euclid(180.0);
            let part_yaw = if distinct_yaws_deg(t).len() == 1 {
                0.0
            } else {
                part_yaw
            };
            out.push([
                Block::new(t.id, b.center_mm - step, part_yaw),
                Block::new(t.id, b.center_mm + step, part_yaw),
            ]);
        }
    }
    out
}

/// The single catalog block that two blocks flush against each other make, if any (the
/// inverse of [`catalog_splits`]).
pub fn catalog_merge(a: &Block, b: &Block) -> Option<Block> {
    let centre = (a.center_mm + b.center_mm) / 2.0;
    let same = |x: &Block, y: &Block| {
        x.block_type.id == y.block_type.id && x.center_mm.distance(y.center_mm) < 0.1
    };
    basic_blocks().find_map(|t| {
        distinct_yaws_deg(t).into_iter().find_map(|yaw| {
            let m = Block::new(t.id, centre, yaw);
            catalog_splits(&m)
                .iter()
                .any(|[p, q]| (same(p, a) && same(q, b)) || (same(p, b) && same(q, a)))
                .then_some(m)
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::DVec3;

    #[test]
    fn proposals_of_the_same_block_from_two_views_pool_into_one() {
        let a = Block::new("b15", DVec3::new(7.5, 7.5, 7.5), 0.0);
        let mut a2 = a;
        a2.center_mm.x += 0.01;
        let b = Block::new("b30", DVec3::new(15.0, 7.5, 7.5), 90.0);
        let pool = pool_candidates(&[vec![a, b], vec![a2]], 0.5);
        assert_eq!(pool.len(), 2);
        assert_eq!(pool[0].views, vec![0, 1]);
        assert_eq!(pool[1].views, vec![0]);
    }

    #[test]
    fn a_b30_splits_into_two_b15_and_a_b15_into_two_stacked_b7_5() {
        let b30 = Block::new("b30", DVec3::new(15.0, 7.5, 7.5), 90.0);
        let s = catalog_splits(&b30);
        assert_eq!(s.len(), 1);
        assert!(s[0].iter().all(|b| b.block_type.id == "b15"));
        let zs: Vec<f64> = s[0].iter().map(|b| b.center_mm.z.round()).collect();
        assert_eq!(zs, vec![15.0, 0.0], "a b30 turned 90 degrees runs along z");
        let b15 = Block::new("b15", DVec3::new(7.5, 7.5, 7.5), 0.0);
        let s = catalog_splits(&b15);
        assert_eq!(s.len(), 1);
        assert_eq!(s[0][1].center_mm, DVec3::new(7.5, 11.25, 7.5));
        assert!(catalog_splits(&s[0][0]).is_empty(), "a b7_5 does not split");
        let merged = catalog_merge(&s[0][1], &s[0][0]).unwrap();
        assert_eq!(
            (merged.block_type.id, merged.center_mm),
            ("b15", b15.center_mm)
        );
        let apart = Block::new("b15", DVec3::new(40.0, 7.5, 7.5), 0.0);
        assert!(catalog_merge(&b15, &apart).is_none());
    }
}
