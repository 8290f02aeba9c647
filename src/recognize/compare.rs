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

use super::catalog_match::blocks_overlap;
use super::verify::{compare_drawings, draw_hypothesis, ViewCheck};
use super::ObservedView;
use crate::drawing::LineDrawing;
use crate::geom::DVec2;
use crate::scene::{Block, Orientation};

/// A block proposed by one or more views.
#[derive(Debug, Clone, PartialEq)]
pub struct PooledCandidate {
    /// The catalog block, placed in world mm.
    pub block: Block,
    /// Indices of the views whose parallelograms proposed it.
    pub views: Vec<usize>,
}

/// The yaw of a block in degrees (0 for a quaternion; candidates carry yaws).
pub fn yaw_deg(b: &Block) -> f64 {
    match b.orientation {
        Orientation::YawDeg(y) => y,
        Orientation::Quaternion(_) => 0.0,
    }
}

/// Pools per-view proposals: same type, same yaw and centres within `tol_mm` are one candidate.
/// Order: first proposal first (deterministic).
pub fn pool_candidates(per_view: &[Vec<Block>], tol_mm: f64) -> Vec<PooledCandidate> {
    let mut pool: Vec<PooledCandidate> = Vec::new();
    for (v, blocks) in per_view.iter().enumerate() {
        for b in blocks {
            let same = pool.iter_mut().find(|c| {
                c.block.block_type.id == b.block_type.id
                    && yaw_deg(&c.block) == yaw_deg(b)
                    && c.block.center_mm.distance(b.center_mm) <= tol_mm
            });
            match same {
                Some(c) if !c.views.contains(&v) => c.views.push(v),
                Some(_) => {}
                None => pool.push(PooledCandidate {
                    block: *b,
                    views: vec![v],
                }),
            }
        }
    }
    pool
}

/// The state of the search: chosen blocks, their drawings, per-view checks.
struct Hypothesis {
    blocks: Vec<Block>,
    checks: Vec<ViewCheck>,
    unexplained: Vec<Vec<DVec2>>,
}

impl Hypothesis {
    fn new(blocks: Vec<Block>, views: &[ObservedView], tol_px: f64) -> Hypothesis {
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
            checks,
            unexplained,
        }
    }

    fn mismatch(&self) -> usize {
        self.checks.iter().map(ViewCheck::mismatch).sum()
    }
}

/// How many of `b`'s projected corners fall on observed points, over all views, those on
/// still-unexplained points counted first: the cheap estimate that ranks candidates before the
/// exact redraw. A block whose corners are all shared with chosen neighbours (the middle of a
/// row, whose corners are cracks) still ranks by the points it would draw.
fn corner_gain(b: &Block, views: &[ObservedView], h: &Hypothesis, tol_px: f64) -> (usize, usize) {
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

/// Search limits of [`choose_blocks`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SearchLimits {
    /// Picture tolerance of the comparisons, px.
    pub tol_px: f64,
    /// How many best-ranked candidates are redrawn exactly per step.
    pub shortlist: usize,
    /// At most this many blocks are chosen.
    pub max_blocks: usize,
    /// At most this many repair rounds (each forbids one more chosen block).
    pub repair_rounds: usize,
}

/// One greedy pass: adds, one at a time, the shortlisted candidate whose redrawn views
/// disagree least with the observed ones, skipping `banned` pool indices; returns the chosen
/// pool indices and the final hypothesis.
fn greedy(
    pool: &[PooledCandidate],
    views: &[ObservedView],
    limits: &SearchLimits,
    banned: &[usize],
) -> (Vec<usize>, Hypothesis) {
    let mut h = Hypothesis::new(Vec::new(), views, limits.tol_px);
    let mut chosen = Vec::new();
    while h.mismatch() > 0 && h.blocks.len() < limits.max_blocks {
        let mut ranked: Vec<(usize, (usize, usize))> = pool
            .iter()
            .enumerate()
            .filter(|(i, c)| {
                !banned.contains(i) && !h.blocks.iter().any(|b| blocks_overlap(b, &c.block))
            })
            .map(|(i, c)| (i, corner_gain(&c.block, views, &h, limits.tol_px)))
            .filter(|&(_, g)| g.1 > 0)
            .collect();
        ranked.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
        let mut best: Option<(usize, Hypothesis)> = None;
        for &(i, _) in ranked.iter().take(limits.shortlist) {
            let mut blocks = h.blocks.clone();
            blocks.push(pool[i].block);
            let next = Hypothesis::new(blocks, views, limits.tol_px);
            let bar = best.as_ref().map_or(h.mismatch(), |b| b.1.mismatch());
            if next.mismatch() < bar {
                best = Some((i, next));
            }
        }
        match best {
            Some((i, b)) => {
                chosen.push(i);
                h = b;
            }
            None => break,
        }
    }
    (chosen, h)
}

/// Chooses blocks from `pool` by hypothesize-and-test: a greedy pass, then, while views stay
/// unexplained, greedy passes that each forbid one more chosen block (a block that explains
/// much at once, like one b30 where two b15 lie flush, is then replaced by what explains all);
/// at most `limits.repair_rounds` rounds. Returns the chosen blocks and the per-view checks.
pub fn choose_blocks(
    pool: &[PooledCandidate],
    views: &[ObservedView],
    limits: &SearchLimits,
) -> (Vec<Block>, Vec<ViewCheck>) {
    let mut banned: Vec<usize> = Vec::new();
    let (mut chosen, mut best) = greedy(pool, views, limits, &banned);
    for _ in 0..limits.repair_rounds {
        if best.mismatch() == 0 {
            break;
        }
        let mut round: Option<(usize, Vec<usize>, Hypothesis)> = None;
        for &i in &chosen {
            let mut ban = banned.clone();
            ban.push(i);
            let (c, h) = greedy(pool, views, limits, &ban);
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
    (best.blocks, best.checks)
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
}
