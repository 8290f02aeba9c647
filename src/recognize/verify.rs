//! Step 6 of the recognizer, the check before answering: draw the hypothesis's own exact line
//! drawing in every view with the ground-truth hidden-line removal (`linedraw`) and hold
//! it against the observed drawing. A view is explained when every observed point has a drawn
//! point within the tolerance and vice versa, and every line of either lies along a parallel
//! line of the other.

use super::{Camera, ObservedView};
use crate::drawing::LineDrawing;
use crate::geom::{distance_to_segment_px, DVec2};
use crate::linedraw::visible_line_drawing;
use crate::scene::{Block, Scene};

/// What one view's comparison found (all counts, 0 = explained).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ViewCheck {
    /// Observed points with no drawn point within the tolerance.
    pub unexplained_points: usize,
    /// Drawn points that nothing observed is near (the hypothesis draws too much).
    pub extra_points: usize,
    /// Observed lines not along any drawn line.
    pub unexplained_lines: usize,
    /// Drawn lines not along any observed line.
    pub extra_lines: usize,
}

impl ViewCheck {
    /// Total disagreement: the sum of the four counts.
    pub fn mismatch(&self) -> usize {
        self.unexplained_points + self.extra_points + self.unexplained_lines + self.extra_lines
    }

    /// `true` when the view is fully explained.
    pub fn is_explained(&self) -> bool {
        self.mismatch() == 0
    }
}

fn near_point(p: DVec2, pts: &[DVec2], tol_px: f64) -> bool {
    pts.iter().any(|q| q.distance(p) <= tol_px)
}

/// One line of a drawing with what the comparison needs of it, computed once.
struct IndexedLine {
    c: DVec2,
    d: DVec2,
    e: DVec2,
    e_len: f64,
    lo: DVec2,
    hi: DVec2,
}

/// The lines of a drawing bucketed by a uniform grid over their boxes grown by the
/// tolerance, so a sample point meets only the lines whose grown box holds it (step 6's check
/// runs once per view and hypothesis; a linear scan of every line per sample dominated it).
/// The cells are stored flat: cell `k` holds `members[starts[k]..starts[k + 1]]`.
struct LineIndex {
    lines: Vec<IndexedLine>,
    origin: DVec2,
    cols: usize,
    rows: usize,
    starts: Vec<u32>,
    members: Vec<u32>,
}

/// Grid cell side of [`LineIndex`], px (about a block's side in a 512 x 480 corner view).
const LINE_CELL_PX: f64 = 32.0;
/// Most cells along one side of a [`LineIndex`].
const MAX_LINE_CELLS: usize = 64;

impl LineIndex {
    fn new(to: &LineDrawing, tol_px: f64) -> LineIndex {
        let lines: Vec<IndexedLine> = to
            .lines
            .iter()
            .map(|&[i, j]| {
                let (c, d) = (to.points[i], to.points[j]);
                let e = d - c;
                IndexedLine {
                    c,
                    d,
                    e,
                    e_len: e.length(),
                    lo: DVec2::new(c.x.min(d.x), c.y.min(d.y)),
                    hi: DVec2::new(c.x.max(d.x), c.y.max(d.y)),
                }
            })
            .collect();
        let grown = |l: &IndexedLine| (l.lo - DVec2::splat(tol_px), l.hi + DVec2::splat(tol_px));
        let usable = |l: &IndexedLine| l.e_len > 0.0 && l.lo.is_finite() && l.hi.is_finite();
        let bounds = crate::geom::bounds2(lines.iter().filter(|l| usable(l)).flat_map(|l| {
            let (lo, hi) = grown(l);
            [lo, hi]
        }));
        let (origin, top) = bounds.unwrap_or((DVec2::ZERO, DVec2::ZERO));
        let side = |extent: f64| ((extent / LINE_CELL_PX).floor() as usize + 1).min(MAX_LINE_CELLS);
        let mut index = LineIndex {
            lines: Vec::new(),
            origin,
            cols: side(top.x - origin.x),
            rows: side(top.y - origin.y),
            starts: Vec::new(),
            members: Vec::new(),
        };
        let spans: Vec<(u32, [usize; 4])> = (0..lines.len())
            .filter(|&k| usable(&lines[k]))
            .map(|k| {
                let (lo, hi) = grown(&lines[k]);
                let ((c0, r0), (c1, r1)) = (index.cell(lo), index.cell(hi));
                (k as u32, [c0, r0, c1, r1])
            })
            .collect();
        index.fill(&spans);
        index.lines = lines;
        index
    }

    /// Stores every line of `spans` (index, cell range) in each cell of its range.
    fn fill(&mut self, spans: &[(u32, [usize; 4])]) {
        let cells = self.cols * self.rows;
        let mut counts = vec![0u32; cells + 1];
        let each = |[c0, r0, c1, r1]: [usize; 4]| {
            (r0..=r1).flat_map(move |r| (c0..=c1).map(move |c| (r, c)))
        };
        for &(_, range) in spans {
            for (r, c) in each(range) {
                counts[r * self.cols + c + 1] += 1;
            }
        }
        for k in 0..cells {
            counts[k + 1] += counts[k];
        }
        let mut next = counts.clone();
        self.members = vec![0; counts[cells] as usize];
        for &(line, range) in spans {
            for (r, c) in each(range) {
                let slot = &mut next[r * self.cols + c];
                self.members[*slot as usize] = line;
                *slot += 1;
            }
        }
        self.starts = counts;
    }

    /// The (column, row) of `p`, clamped to the grid; monotone in `p`, so a point inside a
    /// grown box falls in one of the box's cells.
    fn cell(&self, p: DVec2) -> (usize, usize) {
        let k = |v: f64, o: f64, n: usize| {
            let x = ((v - o) / LINE_CELL_PX).floor();
            if x.is_nan() || x < 0.0 {
                0
            } else {
                (x as usize).min(n - 1)
            }
        };
        (
            k(p.x, self.origin.x, self.cols),
            k(p.y, self.origin.y, self.rows),
        )
    }

    /// The lines whose grown box may hold `p`.
    fn near(&self, p: DVec2) -> &[u32] {
        let (c, r) = self.cell(p);
        let k = r * self.cols + c;
        &self.members[self.starts[k] as usize..self.starts[k + 1] as usize]
    }
}

/// `true` when line `[a, b]` of `from` lies along some line of `to` (indexed in `index`): its
/// ends, midpoint and quarter points within `tol_px` of a parallel line of `to` each (one line,
/// or a chain of them).
fn line_explained(from: &LineDrawing, line: [usize; 2], index: &LineIndex, tol_px: f64) -> bool {
    let (a, b) = (from.points[line[0]], from.points[line[1]]);
    let dir = b - a;
    // Parallel within 3 degrees, or within what the point tolerance allows on a short line:
    // the sine of max(3 deg, atan(2 tol / length)), compared with the lines' cross product.
    let x = 2.0 * tol_px / dir.length().max(1e-9);
    let sin_max = (x / (1.0 + x * x).sqrt()).max(3f64.to_radians().sin());
    let dir_len = dir.length();
    if dir_len == 0.0 {
        return false;
    }
    let samples = [a, (a + b) / 2.0, b, a.lerp(b, 0.25), a.lerp(b, 0.75)];
    samples.iter().all(|&s| {
        index.near(s).iter().any(|&k| {
            let l = &index.lines[k as usize];
            let near_box = s.x >= l.lo.x - tol_px
                && s.x <= l.hi.x + tol_px
                && s.y >= l.lo.y - tol_px
                && s.y <= l.hi.y + tol_px;
            near_box
                && l.e.perp_dot(dir).abs() <= sin_max * l.e_len * dir_len
                && distance_to_segment_px(s, l.c, l.d) <= tol_px
        })
    })
}

/// Compares a drawn (hypothesis) drawing with the observed one, tolerance `tol_px`.
pub fn compare_drawings(drawn: &LineDrawing, observed: &LineDrawing, tol_px: f64) -> ViewCheck {
    mismatched_features(drawn, observed, tol_px).counts()
}

/// What one view's comparison found, feature by feature: indices of the points and lines of
/// either drawing that the other does not explain (the counts of [`ViewCheck`]).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct ViewMismatch {
    /// Observed points with no drawn point within the tolerance.
    pub unexplained_points: Vec<usize>,
    /// Drawn points that nothing observed is near.
    pub extra_points: Vec<usize>,
    /// Observed lines not along any drawn line.
    pub unexplained_lines: Vec<usize>,
    /// Drawn lines not along any observed line.
    pub extra_lines: Vec<usize>,
}

impl ViewMismatch {
    /// The four counts.
    pub fn counts(&self) -> ViewCheck {
        ViewCheck {
            unexplained_points: self.unexplained_points.len(),
            extra_points: self.extra_points.len(),
            unexplained_lines: self.unexplained_lines.len(),
            extra_lines: self.extra_lines.len(),
        }
    }
}

/// [`compare_drawings`] feature by feature: which points and lines of `drawn` and `observed`
/// the other drawing does not explain (step 6's check, docs/recognizer.md "Recognizer").
pub fn mismatched_features(
    drawn: &LineDrawing,
    observed: &LineDrawing,
    tol_px: f64,
) -> ViewMismatch {
    let points = |from: &LineDrawing, to: &LineDrawing| -> Vec<usize> {
        (0..from.points.len())
            .filter(|&i| !near_point(from.points[i], &to.points, tol_px))
            .collect()
    };
    let lines = |from: &LineDrawing, to: &LineDrawing| -> Vec<usize> {
        let index = LineIndex::new(to, tol_px);
        (0..from.lines.len())
            .filter(|&k| !line_explained(from, from.lines[k], &index, tol_px))
            .collect()
    };
    ViewMismatch {
        unexplained_points: points(observed, drawn),
        extra_points: points(drawn, observed),
        unexplained_lines: lines(observed, drawn),
        extra_lines: lines(drawn, observed),
    }
}

/// The pieces of line `line` of `from` that lie along no line of `to`: its points every px
/// (and its ends) tested as [`compare_drawings`] tests a line's five samples (within `tol_px`
/// of a parallel line of `to`), the maximal runs of untested-or-failing points returned as
/// segments from the first to the last failing point.
pub fn unexplained_pieces(
    from: &LineDrawing,
    line: [usize; 2],
    to: &LineDrawing,
    tol_px: f64,
) -> Vec<[DVec2; 2]> {
    let (a, b) = (from.points[line[0]], from.points[line[1]]);
    let dir = b - a;
    let len = dir.length();
    if len == 0.0 || !len.is_finite() {
        return Vec::new();
    }
    let x = 2.0 * tol_px / len;
    let sin_max = (x / (1.0 + x * x).sqrt()).max(3f64.to_radians().sin());
    let along: Vec<(DVec2, DVec2, f64)> = to
        .lines
        .iter()
        .map(|&[i, j]| {
            (
                to.points[i],
                to.points[j],
                to.points[i].distance(to.points[j]),
            )
        })
        .filter(|&(c, d, l)| l > 0.0 && (d - c).perp_dot(dir).abs() <= sin_max * l * len)
        .collect();
    let steps = len.ceil() as usize;
    let mut pieces = Vec::new();
    let mut run: Option<[DVec2; 2]> = None;
    for k in 0..=steps {
        let s = a.lerp(b, k as f64 / steps as f64);
        let ok = along
            .iter()
            .any(|&(c, d, _)| distance_to_segment_px(s, c, d) <= tol_px);
        match (ok, run.as_mut()) {
            (false, Some(r)) => r[1] = s,
            (false, None) => run = Some([s, s]),
            (true, Some(_)) => pieces.extend(run.take()),
            (true, None) => {}
        }
    }
    pieces.extend(run);
    pieces
}

/// The blocks (indices into the drawn hypothesis) owning a line of `drawn` that no observed
/// line explains: what the hypothesis draws in excess, by block, sorted and without repeats.
pub fn blocks_drawn_in_excess(
    drawn: &LineDrawing,
    observed: &LineDrawing,
    tol_px: f64,
) -> Vec<usize> {
    let index = LineIndex::new(observed, tol_px);
    let mut out: Vec<usize> = drawn
        .lines
        .iter()
        .zip(&drawn.edges)
        .filter(|(l, _)| !line_explained(drawn, **l, &index, tol_px))
        .map(|(_, e)| e.block)
        .collect();
    out.sort_unstable();
    out.dedup();
    out
}

/// Draws `blocks` in `camera` with the exact hidden-line removal of `linedraw`.
pub fn draw_hypothesis(blocks: &[Block], camera: &Camera) -> LineDrawing {
    visible_line_drawing(&Scene::new("hypothesis", blocks.to_vec()), camera)
}

/// Checks a hypothesis against every observed view: one [`ViewCheck`] per view, in order.
pub fn check_hypothesis(blocks: &[Block], views: &[ObservedView], tol_px: f64) -> Vec<ViewCheck> {
    views
        .iter()
        .map(|v| compare_drawings(&draw_hypothesis(blocks, &v.camera), &v.drawing, tol_px))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::DVec3;
    use crate::recognize::{CameraOptions, CornerView};

    /// The definition of [`line_explained`] without the index: every line of `to` tried.
    fn explained_by_scan(from: &LineDrawing, line: [usize; 2], to: &LineDrawing, tol: f64) -> bool {
        let (a, b) = (from.points[line[0]], from.points[line[1]]);
        let dir = b - a;
        let x = 2.0 * tol / dir.length().max(1e-9);
        let sin_max = (x / (1.0 + x * x).sqrt()).max(3f64.to_radians().sin());
        if dir.length() == 0.0 {
            return false;
        }
        [a, (a + b) / 2.0, b, a.lerp(b, 0.25), a.lerp(b, 0.75)]
            .iter()
            .all(|&s| {
                to.lines.iter().any(|&[i, j]| {
                    let (c, d) = (to.points[i], to.points[j]);
                    let e = d - c;
                    e.length() > 0.0
                        && e.perp_dot(dir).abs() <= sin_max * e.length() * dir.length()
                        && distance_to_segment_px(s, c, d) <= tol
                })
            })
    }

    #[test]
    fn the_line_index_finds_exactly_the_lines_a_full_scan_finds() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let random_drawing = |n: usize, rng: &mut rand_chacha::ChaCha8Rng| {
            let mut d = LineDrawing::default();
            for k in 0..n {
                let a = DVec2::new(rng.random_range(0.0..300.0), rng.random_range(0.0..300.0));
                // Mostly the three picture directions of a corner view, some short lines.
                let ang = [30f64, 90.0, 150.0][k % 3].to_radians() + rng.random_range(-0.06..0.06);
                let len = if k % 7 == 0 {
                    rng.random_range(0.0..4.0)
                } else {
                    rng.random_range(5.0..200.0)
                };
                let b = a + DVec2::new(ang.cos(), ang.sin()) * len;
                d.points.extend([a, b]);
                d.lines.push([2 * k, 2 * k + 1]);
            }
            d
        };
        let mut explained = 0;
        for round in 0..40 {
            let to = random_drawing(60, &mut rng);
            // Lines of `to` itself, nudged, and fresh random ones.
            let mut from = to.clone();
            for p in from.points.iter_mut() {
                *p += DVec2::new(rng.random_range(-2.5..2.5), rng.random_range(-2.5..2.5));
            }
            let fresh = random_drawing(60, &mut rng);
            for d in [&from, &fresh, &to] {
                let tol = [0.5, 2.0, 3.0][round % 3];
                let index = LineIndex::new(&to, tol);
                for &l in &d.lines {
                    let want = explained_by_scan(d, l, &to, tol);
                    assert_eq!(
                        line_explained(d, l, &index, tol),
                        want,
                        "round {round} line {l:?}"
                    );
                    explained += usize::from(want);
                }
            }
        }
        assert!(
            explained > 2400,
            "the comparison exercises both answers: {explained}"
        );
    }

    fn two_blocks() -> Vec<Block> {
        vec![
            Block::new("b30", DVec3::new(15.0, 7.5, 7.5), 0.0),
            Block::new("b15", DVec3::new(7.5, 22.5, 7.5), 0.0),
        ]
    }

    fn cam(blocks: &[Block], view: CornerView) -> Camera {
        Camera::frame(
            &crate::scene::world_vertices(blocks),
            view,
            &CameraOptions::default(),
        )
    }

    #[test]
    fn the_true_hypothesis_explains_every_view() {
        let blocks = two_blocks();
        let views: Vec<_> = CornerView::ALL
            .iter()
            .map(|&v| {
                let camera = cam(&blocks, v);
                let drawing = draw_hypothesis(&blocks, &camera);
                ObservedView::new(drawing, camera)
            })
            .collect();
        for check in check_hypothesis(&blocks, &views, 1.0) {
            assert!(check.is_explained(), "{check:?}");
        }
    }

    #[test]
    fn a_dropped_or_moved_block_is_caught() {
        let blocks = two_blocks();
        let c = cam(&blocks, CornerView::Ne);
        let observed = draw_hypothesis(&blocks, &c);
        let dropped = compare_drawings(&draw_hypothesis(&blocks[..1], &c), &observed, 1.0);
        assert!(dropped.unexplained_points > 0, "{dropped:?}");
        let mut moved = blocks.clone();
        moved[1].center_mm.x += 15.0;
        let moved = compare_drawings(&draw_hypothesis(&moved, &c), &observed, 1.0);
        assert!(!moved.is_explained(), "{moved:?}");
    }
}
