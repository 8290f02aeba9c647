//! Step 6's last question: do the views decide the blocks? Another set of catalog blocks that
//! explains every view equally well (one chosen block split in two, or two merged into one,
//! their crack hidden in every view) means the sample cannot be told, and answering would risk
//! a confident wrong answer (Chapter VII: what the method cannot do is declined).
//!
//! Every alternative is decided by the exact redraw (`linedraw`), except where the
//! hypothesis's own exact drawing already *proves* the alternative draws a point that nothing
//! observed is near (a split block's edge visible across the crack), or lacks every point near
//! an observed one (a crack between two blocks, visible in the hypothesis's drawing, that a
//! merged block would not have). Such proofs only skip redraws; they never accept an answer.
//! The one proof in the other direction, that a split alternative draws exactly what the
//! hypothesis draws ([`split_crack_enclosed`]: the crack's whole rim is wrapped by touching
//! blocks, so no ray reaches it), can only make the recognizer decline, never answer.

use super::catalog_match::bounds_mm;
use super::compare::{catalog_merge, catalog_splits};
use super::edge_profile::{edge_profile, ViewPicture};
use super::shadow::mismatches_under_known_lights;
use super::verify::{compare_drawings, draw_hypothesis, mismatched_features};
use super::{Camera, ObservedView};
use crate::drawing::{LineDrawing, LineKind};
use crate::geom::{DVec2, DVec3};
use crate::scene::Block;

/// A crossing this close to a visible piece's end, mm, proves nothing (the piece may end at
/// the crack itself).
const CROSSING_MARGIN_MM: f64 = 0.5;
/// A point this close to a block's bounding plane, mm, lies on it.
const ON_PLANE_MM: f64 = 0.1;
/// Lines within this angle of straight on at a point continue each other, degrees.
const STRAIGHT_ON_DEG: f64 = 3.0;

/// Where the crack of two halves lies: the world axis across it and its coordinate, mm.
fn crack_plane(halves: &[Block; 2]) -> (usize, f64) {
    let d = (halves[1].center_mm - halves[0].center_mm).abs();
    let k = if d.x >= d.y && d.x >= d.z {
        0
    } else if d.y >= d.z {
        1
    } else {
        2
    };
    (k, (halves[0].center_mm[k] + halves[1].center_mm[k]) / 2.0)
}

/// `true` when `q_mm` lies on an edge of block `b` (on two of its bounding planes, inside the
/// third extent).
fn on_block_edge(b: &Block, q_mm: DVec3) -> bool {
    let (lo, hi) = bounds_mm(b);
    let inside = (0..3).all(|k| q_mm[k] >= lo[k] - ON_PLANE_MM && q_mm[k] <= hi[k] + ON_PLANE_MM);
    let planes = (0..3)
        .filter(|&k| {
            (q_mm[k] - lo[k]).abs() <= ON_PLANE_MM || (q_mm[k] - hi[k]).abs() <= ON_PLANE_MM
        })
        .count();
    inside && planes >= 2
}

/// The world points where visible lines of block `i` in `drawn` cross the crack plane `(k, c)`
/// well inside their visible piece: there the split alternative draws a point (the halves'
/// edges meet, and the crack line ends).
fn visible_crossings(
    drawn: &LineDrawing,
    blocks: &[Block],
    i: usize,
    k: usize,
    c: f64,
) -> Vec<DVec3> {
    drawn
        .edges
        .iter()
        .filter(|e| e.block == i || e.other_block == Some(i))
        .filter_map(|e| {
            let (a, b) = (DVec3::from_array(e.from_mm), DVec3::from_array(e.to_mm));
            let d = b - a;
            let across = d[k].abs() > 0.999 * d.length();
            let (lo, hi) = (a[k].min(b[k]), a[k].max(b[k]));
            let inside = lo < c - CROSSING_MARGIN_MM && hi > c + CROSSING_MARGIN_MM;
            let q = a + d * ((c - a[k]) / d[k]);
            (across && inside && on_block_edge(&blocks[i], q)).then_some(q)
        })
        .collect()
}

fn near_any(p: DVec2, points: &[DVec2], r_px: f64) -> bool {
    points.iter().any(|q| q.distance(p) <= r_px)
}

/// `true` when view `(drawn, observed, camera)` proves that splitting block `i` into `halves`
/// is not explained there: the split draws a point where a visible edge of block `i` crosses
/// the crack, and no observed point is within `tol_px` of it (an extra point, step 6).
fn split_refuted(
    blocks: &[Block],
    i: usize,
    halves: &[Block; 2],
    drawn: &LineDrawing,
    observed: &ObservedView,
    tol_px: f64,
) -> bool {
    let (k, c) = crack_plane(halves);
    let camera: &Camera = &observed.camera;
    visible_crossings(drawn, blocks, i, k, c).iter().any(|&q| {
        let p = camera.picture_from_world(q).truncate();
        !near_any(p, &observed.drawing.points, tol_px + 0.05)
    })
}

/// How far outside the split block the enclosure proof asks for other blocks, mm (above the
/// contact and seam tolerances, far below any catalog size).
const ENCLOSE_PROBE_MM: f64 = 0.5;

/// The parameter interval along world axis `run` where the line through `q` parallel to
/// `run` lies inside box `(lo, hi)` by more than [`ON_PLANE_MM`] across the other two axes,
/// if it does.
fn run_inside(lo: DVec3, hi: DVec3, q: DVec3, run: usize) -> Option<[f64; 2]> {
    let across = (0..3)
        .filter(|&a| a != run)
        .all(|a| q[a] > lo[a] + ON_PLANE_MM && q[a] < hi[a] - ON_PLANE_MM);
    across.then_some([lo[run], hi[run]])
}

/// `true` when `intervals` cover `[from, to]` without a gap wider than [`ON_PLANE_MM`].
fn covers(mut intervals: Vec<[f64; 2]>, from: f64, to: f64) -> bool {
    intervals.sort_by(|a, b| a[0].total_cmp(&b[0]));
    let mut reached = from;
    for [a, b] in intervals {
        if a > reached + ON_PLANE_MM {
            break;
        }
        reached = reached.max(b);
    }
    reached >= to
}

/// `true` when splitting block `i` into `halves` provably draws the hypothesis's own drawing
/// in every view: just outside each face the crack plane cuts, along the whole face and a
/// probe's width beyond its edges, other blocks touching that face fill the space a probe's
/// width above and below the crack. The crack's rim then lies inside the union of blocks, no
/// ray from any eye reaches it, and the halves' edges are block `i`'s edges cut where they are
/// hidden (Chapter VII: a crack hidden in every view cannot be told from no crack).
fn split_crack_enclosed(blocks: &[Block], i: usize, halves: &[Block; 2]) -> bool {
    let (k, c) = crack_plane(halves);
    let (lo, hi) = bounds_mm(&blocks[i]);
    let others: Vec<(DVec3, DVec3)> = (0..blocks.len())
        .filter(|&j| j != i)
        .map(|j| bounds_mm(&blocks[j]))
        .collect();
    let p = ENCLOSE_PROBE_MM;
    let axes: Vec<usize> = (0..3).filter(|&a| a != k).collect();
    axes.iter().all(|&fixed| {
        let run = 3 - k - fixed;
        [(lo[fixed], -1.0), (hi[fixed], 1.0)]
            .iter()
            .all(|&(face, out)| {
                let mut q = DVec3::ZERO;
                q[k] = c;
                q[fixed] = face + out * p;
                let touching = |b: &&(DVec3, DVec3)| {
                    let near = if out > 0.0 { b.0[fixed] } else { b.1[fixed] };
                    (near - face).abs() <= ON_PLANE_MM && b.0[k] < c - p && b.1[k] > c + p
                };
                let spans: Vec<[f64; 2]> = others
                    .iter()
                    .filter(touching)
                    .filter_map(|b| run_inside(b.0, b.1, q, run))
                    .collect();
                covers(spans, lo[run] - p, hi[run] + p)
            })
    })
}

/// The lines of `drawn` at point `p` (their indices).
fn lines_at(drawn: &LineDrawing, p: usize) -> Vec<usize> {
    (0..drawn.lines.len())
        .filter(|&l| drawn.lines[l].contains(&p))
        .collect()
}

/// Whether point `p` of `drawn` disappears when blocks `i` and `j` become one: every line at it
/// belongs to the pair, one at least is their crack, and the others are none or two lines
/// continuing each other straight on (the merged block's edge, now unbroken).
fn vanishes_when_merged(drawn: &LineDrawing, p: usize, pair: [usize; 2]) -> bool {
    let ours = |b: Option<usize>| b.is_none_or(|b| pair.contains(&b));
    let lines = lines_at(drawn, p);
    let is_crack = |l: usize| {
        let e = &drawn.edges[l];
        drawn.kinds.get(l) == Some(&LineKind::Crack)
            && pair.contains(&e.block)
            && e.other_block
                .is_some_and(|o| pair.contains(&o) && o != e.block)
    };
    if lines.is_empty()
        || !lines
            .iter()
            .all(|&l| ours(Some(drawn.edges[l].block)) && ours(drawn.edges[l].other_block))
    {
        return false;
    }
    if !lines.iter().any(|&l| is_crack(l)) {
        return false;
    }
    let rest: Vec<usize> = lines.into_iter().filter(|&l| !is_crack(l)).collect();
    let away = |l: usize| {
        let [a, b] = drawn.lines[l];
        let other = if a == p { b } else { a };
        drawn.points[other] - drawn.points[p]
    };
    match rest[..] {
        [] => true,
        [l, m] => away(l).angle_to(away(m)).abs().to_degrees() >= 180.0 - STRAIGHT_ON_DEG,
        _ => false,
    }
}

/// `true` when the view proves that merging blocks `i` and `j` is not explained there: a point
/// of the hypothesis's drawing that vanishes in the merge has an observed point within
/// `tol_px`, and every drawn point within `2 tol_px` of it vanishes too, so the merged drawing
/// has no point near that observed one (an unexplained point, step 6).
fn merge_refuted(
    pair: [usize; 2],
    drawn: &LineDrawing,
    observed: &LineDrawing,
    tol_px: f64,
) -> bool {
    if drawn.edges.len() != drawn.lines.len() || drawn.kinds.len() != drawn.lines.len() {
        return false;
    }
    (0..drawn.points.len()).any(|p| {
        let at = drawn.points[p];
        vanishes_when_merged(drawn, p, pair)
            && near_any(at, &observed.points, tol_px)
            && (0..drawn.points.len()).all(|q| {
                drawn.points[q].distance(at) > 2.0 * tol_px || vanishes_when_merged(drawn, q, pair)
            })
    })
}

/// Another hypothesis that explains every view equally well, found by splitting one chosen
/// block or merging two (a crack hidden in every view): then the views cannot tell which is
/// the sample, and answering would risk a confident wrong answer. Returns a description.
pub fn equally_good_alternative(
    blocks: &[Block],
    views: &[ObservedView],
    tol_px: f64,
) -> Option<String> {
    let drawn: Vec<LineDrawing> = views
        .iter()
        .map(|v| draw_hypothesis(blocks, &v.camera))
        .collect();
    alternative_given_drawings(blocks, views, &drawn, tol_px, &[])
}

/// One split or merge of the hypothesis's blocks, with what the hypothesis's own drawings
/// already prove about it.
struct Alternative {
    /// Which blocks change.
    change: Change,
    /// Some view's own drawing proves the alternative is not explained there.
    refuted: bool,
    /// The alternative provably draws the hypothesis's own drawing ([`split_crack_enclosed`]).
    hidden: bool,
    /// Its blocks.
    blocks: Vec<Block>,
}

/// A split of block `i` or a merge of blocks `i` and `j`.
#[derive(Debug, Clone, Copy)]
enum Change {
    Split(usize),
    Merge(usize, usize),
}

impl Alternative {
    /// Why the views would not decide, were it explained (`blocks` the hypothesis's).
    fn reason(&self, blocks: &[Block]) -> String {
        match self.change {
            Change::Split(i) => format!(
                "block {i} ({}) could as well be two {} (their crack is hidden in every view)",
                blocks[i].block_type.id, self.blocks[i].block_type.id
            ),
            Change::Merge(i, j) => format!(
                "blocks {i} and {j} could as well be one {} (their crack is hidden in every view)",
                self.blocks[i].block_type.id
            ),
        }
    }
}

/// Every split of one block and merge of two (in that order, by block index), made lazily so
/// that a search stops at the first that counts.
fn alternatives<'a>(
    blocks: &'a [Block],
    views: &'a [ObservedView],
    drawn: &'a [LineDrawing],
    tol_px: f64,
) -> impl Iterator<Item = Alternative> + 'a {
    let splits = blocks.iter().enumerate().flat_map(move |(i, b)| {
        catalog_splits(b).into_iter().map(move |halves| {
            let refuted = views
                .iter()
                .zip(drawn)
                .any(|(v, d)| split_refuted(blocks, i, &halves, d, v, tol_px));
            let hidden = !refuted && split_crack_enclosed(blocks, i, &halves);
            let mut alt = blocks.to_vec();
            alt.splice(i..=i, halves);
            Alternative {
                change: Change::Split(i),
                refuted,
                hidden,
                blocks: alt,
            }
        })
    });
    let n = blocks.len();
    let merges = (0..n).flat_map(move |i| {
        (i + 1..n).filter_map(move |j| {
            let m = catalog_merge(&blocks[i], &blocks[j])?;
            let refuted = views
                .iter()
                .zip(drawn)
                .any(|(v, d)| merge_refuted([i, j], d, &v.drawing, tol_px));
            let mut alt: Vec<Block> = blocks.to_vec();
            alt.remove(j);
            alt[i] = m;
            Some(Alternative {
                change: Change::Merge(i, j),
                refuted,
                hidden: false,
                blocks: alt,
            })
        })
    });
    splits.chain(merges)
}

/// `true` when the exact redraw of `alt` explains every observed view.
fn redraw_explains(alt: &[Block], views: &[ObservedView], tol_px: f64) -> bool {
    views.iter().all(|v| {
        compare_drawings(&draw_hypothesis(alt, &v.camera), &v.drawing, tol_px).is_explained()
    })
}

/// [`equally_good_alternative`] given the hypothesis's own exact drawing in every view (as
/// step 6 made it): alternatives those drawings refute are not redrawn, nor those they prove
/// hidden. With the views' `pictures` (one per view, or none), step 6 is the picture-aware
/// check ([`picture_check`]) for the alternatives as for the answer: the drawings' proofs that
/// an alternative draws a point nothing observed is near no longer hold (the picture may
/// confirm it), so every alternative not proved hidden is redrawn, and it is refuted also
/// where the picture confirms a line of the answer that the alternative lacks.
pub(super) fn alternative_given_drawings(
    blocks: &[Block],
    views: &[ObservedView],
    drawn: &[LineDrawing],
    tol_px: f64,
    pictures: &[ViewPicture],
) -> Option<String> {
    if pictures.len() != views.len() || views.is_empty() {
        return alternatives(blocks, views, drawn, tol_px)
            .find(|a| !a.refuted && (a.hidden || redraw_explains(&a.blocks, views, tol_px)))
            .map(|a| a.reason(blocks));
    }
    alternatives(blocks, views, drawn, tol_px)
        .find(|a| {
            a.hidden || redraw_explains_in_pictures(&a.blocks, views, drawn, pictures, tol_px)
        })
        .map(|a| a.reason(blocks))
}

/// `true` when the exact redraw of `alt` explains every observed view by the picture-aware
/// check, and no line of the answer's drawing `drawn` that `alt` does not draw is confirmed by
/// the picture.
fn redraw_explains_in_pictures(
    alt: &[Block],
    views: &[ObservedView],
    drawn: &[LineDrawing],
    pictures: &[ViewPicture],
    tol_px: f64,
) -> bool {
    let alt_drawn: Vec<LineDrawing> = views
        .iter()
        .map(|v| draw_hypothesis(alt, &v.camera))
        .collect();
    let explained = mismatches_under_known_lights(alt, &alt_drawn, views, pictures, tol_px)
        .iter()
        .all(|m| m.counts().is_explained());
    explained
        && drawn
            .iter()
            .zip(&alt_drawn)
            .zip(pictures)
            .all(|((answer, alt), pic)| {
                let lacked = mismatched_features(answer, alt, tol_px).extra_lines;
                !lacked.iter().any(|&k| {
                    let [i, j] = answer.lines[k];
                    edge_profile(pic, answer.points[i], answer.points[j]).confirms()
                })
            })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::recognize::CornerView;

    fn views_of(blocks: &[Block]) -> Vec<ObservedView> {
        crate::recognize::views_of(blocks, &CornerView::ALL)
    }

    /// The 3 x 3 layer of b15 with a row of three on top (`bench render`'s 12-block stack).
    fn stack() -> Vec<Block> {
        let layer: Vec<usize> = (0..9).collect();
        [
            crate::recognize::grid_cubes(0, &layer),
            crate::recognize::grid_cubes(1, &[0, 1, 2]),
        ]
        .concat()
    }

    /// Every split and merge alternative of `blocks`: refuted by some view, and whether the
    /// exact redraw explains every view.
    fn alternatives_of(blocks: &[Block], views: &[ObservedView]) -> Vec<(String, bool, bool)> {
        let drawn: Vec<LineDrawing> = views
            .iter()
            .map(|v| draw_hypothesis(blocks, &v.camera))
            .collect();
        alternatives(blocks, views, &drawn, 2.0)
            .map(|a| {
                let label = match a.change {
                    Change::Split(i) => format!("split {i}"),
                    Change::Merge(i, j) => format!("merge {i} {j}"),
                };
                (label, a.refuted, redraw_explains(&a.blocks, views, 2.0))
            })
            .collect()
    }

    #[test]
    fn a_refuted_alternative_never_explains_the_views_and_most_are_refuted() {
        let row = vec![
            Block::new("b15", DVec3::new(7.5, 7.5, 7.5), 0.0),
            Block::new("b15", DVec3::new(22.5, 7.5, 7.5), 0.0),
            Block::new("b15", DVec3::new(7.5, 22.5, 7.5), 0.0),
        ];
        for blocks in [row, stack()] {
            let views = views_of(&blocks);
            let alts = alternatives_of(&blocks, &views);
            assert!(!alts.is_empty());
            for (what, refuted, explains) in &alts {
                assert!(
                    !(*refuted && *explains),
                    "{what}: refuted, yet the redraw explains"
                );
            }
            // Only alternatives whose crack hides or meets other blocks' lines go to the redraw.
            let refuted = alts.iter().filter(|a| a.1).count();
            assert!(4 * refuted >= 3 * alts.len(), "{alts:?}");
        }
    }

    /// Columns of one to three b15 or b7_5 on a 5 x 5 grid, each column's make-up drawn from
    /// `seed` (every block rests on the floor or the block below).
    fn columns(seed: u64) -> Vec<Block> {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        let mut blocks = Vec::new();
        for cell in 0..25 {
            let (x, z) = ((cell % 5) as f64 * 15.0, (cell / 5) as f64 * 15.0);
            let mut y = 0.0;
            for _ in 0..rng.random_range(1..4) {
                let (id, h) = if rng.random_bool(0.15) {
                    ("b7_5", 7.5)
                } else {
                    ("b15", 15.0)
                };
                blocks.push(Block::new(id, DVec3::new(x, y + h / 2.0, z), 0.0));
                y += h;
            }
        }
        blocks
    }

    #[test]
    fn an_enclosed_crack_is_one_the_exact_redraw_cannot_see() {
        let (mut enclosed, mut open) = (0, 0);
        for seed in 0..24 {
            let blocks = columns(seed);
            let views = views_of(&blocks);
            for (i, b) in blocks.iter().enumerate() {
                for halves in catalog_splits(b) {
                    if !split_crack_enclosed(&blocks, i, &halves) {
                        open += 1;
                        continue;
                    }
                    enclosed += 1;
                    let mut alt = blocks.to_vec();
                    alt.splice(i..=i, halves);
                    for v in &views {
                        let check =
                            compare_drawings(&draw_hypothesis(&alt, &v.camera), &v.drawing, 2.0);
                        assert!(check.is_explained(), "seed {seed} block {i}: {check:?}");
                    }
                }
            }
        }
        assert!(
            enclosed >= 20 && open >= 100,
            "both cases met: {enclosed} enclosed, {open} open"
        );
    }

    #[test]
    fn a_crack_with_one_side_open_or_a_short_neighbour_is_not_enclosed() {
        let cube = |x: f64, y: f64, z: f64| Block::new("b15", DVec3::new(x, y, z), 0.0);
        let ring: Vec<Block> = (0..9)
            .map(|k| cube((k % 3) as f64 * 15.0, 7.5, (k / 3) as f64 * 15.0))
            .collect();
        let middle = 4;
        let split = catalog_splits(&ring[middle])
            .into_iter()
            .find(|h| crack_plane(h).0 == 1)
            .unwrap();
        assert!(
            split_crack_enclosed(&ring, middle, &split),
            "all eight around it"
        );
        let mut corner_gone = ring.clone();
        corner_gone.remove(8);
        assert!(
            !split_crack_enclosed(&corner_gone, middle, &split),
            "a diagonal neighbour missing"
        );
        let mut short = ring.clone();
        short[5] = Block::new("b7_5", DVec3::new(30.0, 3.75, 15.0), 0.0);
        assert!(
            !split_crack_enclosed(&short, middle, &split),
            "a neighbour ending at the crack"
        );
    }

    #[test]
    fn the_stacks_middle_bottom_block_is_not_refuted_and_is_found_ambiguous() {
        let blocks = stack();
        let views = views_of(&blocks);
        let alts = alternatives_of(&blocks, &views);
        let middle = alts.iter().find(|a| a.0 == "split 4").unwrap();
        assert_eq!(
            (middle.1, middle.2),
            (false, true),
            "its sides touch its neighbours: two stacked b7_5 draw the same views"
        );
        let detail = equally_good_alternative(&blocks, &views, 2.0).unwrap();
        assert!(
            detail.starts_with("block 4 (b15) could as well be two b7_5"),
            "{detail}"
        );
        // A lone cube shows its middle: its split is refuted and nothing is ambiguous.
        let cube = vec![Block::new("b15", DVec3::new(7.5, 7.5, 7.5), 0.0)];
        let views = views_of(&cube);
        assert!(
            alternatives_of(&cube, &views)[0].1,
            "a lone cube shows its middle"
        );
        assert_eq!(equally_good_alternative(&cube, &views, 2.0), None);
    }

    /// The stack answered with its enclosed middle bottom cube as two stacked b7_5, its views
    /// read with one more line on the edge of the stack's shadow on the floor under a known
    /// light (inked in the pictures too): the answer's check leaves that line out, and so must
    /// the merged alternative's, which is then found to explain every view as well. Moved 6 px
    /// off the shadow's edge, or with the light unknown, the line is unexplained and no
    /// alternative is.
    #[test]
    fn an_alternative_is_held_to_the_answers_check_of_shadow_lines() {
        let truth = stack();
        let light = DVec3::new(1.0, 2.0, 0.5).normalize();
        let mut answer = truth.clone();
        let c = truth[4].center_mm;
        answer.splice(
            4..=4,
            [-3.75, 3.75].map(|dy| Block::new("b7_5", c + DVec3::Y * dy, 0.0)),
        );
        let edge = crate::recognize::shadow::shadow_edges_mm(&truth, light)
            .into_iter()
            .filter(|[a, b]| a.y.abs() < 1e-6 && b.y.abs() < 1e-6)
            .max_by(|p, q| p[0].distance(p[1]).total_cmp(&q[0].distance(q[1])))
            .expect("the stack casts a shadow on the floor");
        let found = |shift_px: f64, lights: Vec<DVec3>| {
            let views: Vec<ObservedView> = views_of(&truth)
                .into_iter()
                .map(|v| {
                    let projector = crate::camera::Projector::new(&v.camera);
                    let [a, b] = edge.map(|q| projector.picture(q) + DVec2::X * shift_px);
                    ObservedView {
                        towards_lights: lights.clone(),
                        ..crate::recognize::with_line(&v, a, b)
                    }
                })
                .collect();
            let grays: Vec<image::GrayImage> = views
                .iter()
                .map(|v| crate::recognize::inked_picture(&v.camera, &v.drawing))
                .collect();
            let pictures: Vec<ViewPicture> = views
                .iter()
                .zip(&grays)
                .map(|(v, g)| ViewPicture::new(g, &v.camera))
                .collect();
            let drawn: Vec<LineDrawing> = views
                .iter()
                .map(|v| draw_hypothesis(&answer, &v.camera))
                .collect();
            alternative_given_drawings(&answer, &views, &drawn, 2.0, &pictures)
        };
        let detail = found(0.0, vec![light]).expect("the merge explains the views");
        assert!(detail.contains("could as well be one b15"), "{detail}");
        assert_eq!(found(6.0, vec![light]), None);
        assert_eq!(found(0.0, Vec::new()), None);
    }
}
