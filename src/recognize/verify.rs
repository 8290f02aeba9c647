//! Step 6 of the recognizer, the check before answering: draw the hypothesis's own exact line
//! drawing in every view with the ground-truth hidden-line removal (`render::truth`) and hold
//! it against the observed drawing. A view is explained when every observed point has a drawn
//! point within the tolerance and vice versa, and every line of either lies along a parallel
//! line of the other.

use super::{Camera, ObservedView};
use crate::drawing::LineDrawing;
use crate::geom::DVec2;
use crate::render::truth::visible_line_drawing;
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

/// Distance from `p` to the segment `a`-`b`, px.
pub fn distance_to_segment_px(p: DVec2, a: DVec2, b: DVec2) -> f64 {
    let ab = b - a;
    let len2 = ab.length_squared();
    if len2 == 0.0 {
        return p.distance(a);
    }
    let t = ((p - a).dot(ab) / len2).clamp(0.0, 1.0);
    p.distance(a + ab * t)
}

/// `true` when line `[a, b]` of `from` lies along some line of `to` (its ends and midpoint
/// within `tol_px` of one parallel line of `to`, or of a chain of them).
fn line_explained(from: &LineDrawing, line: [usize; 2], to: &LineDrawing, tol_px: f64) -> bool {
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
        to.lines.iter().any(|&[i, j]| {
            let (c, d) = (to.points[i], to.points[j]);
            let near_box = s.x >= c.x.min(d.x) - tol_px
                && s.x <= c.x.max(d.x) + tol_px
                && s.y >= c.y.min(d.y) - tol_px
                && s.y <= c.y.max(d.y) + tol_px;
            let e = d - c;
            let e_len = e.length();
            near_box
                && e_len > 0.0
                && e.perp_dot(dir).abs() <= sin_max * e_len * dir_len
                && distance_to_segment_px(s, c, d) <= tol_px
        })
    })
}

/// Compares a drawn (hypothesis) drawing with the observed one, tolerance `tol_px`.
pub fn compare_drawings(drawn: &LineDrawing, observed: &LineDrawing, tol_px: f64) -> ViewCheck {
    let count_points = |from: &LineDrawing, to: &LineDrawing| {
        from.points
            .iter()
            .filter(|p| !near_point(**p, &to.points, tol_px))
            .count()
    };
    let count_lines = |from: &LineDrawing, to: &LineDrawing| {
        from.lines
            .iter()
            .filter(|l| !line_explained(from, **l, to, tol_px))
            .count()
    };
    ViewCheck {
        unexplained_points: count_points(observed, drawn),
        extra_points: count_points(drawn, observed),
        unexplained_lines: count_lines(observed, drawn),
        extra_lines: count_lines(drawn, observed),
    }
}

/// The blocks (indices into the drawn hypothesis) owning a line of `drawn` that no observed
/// line explains: what the hypothesis draws in excess, by block, sorted and without repeats.
pub fn blocks_drawn_in_excess(
    drawn: &LineDrawing,
    observed: &LineDrawing,
    tol_px: f64,
) -> Vec<usize> {
    let mut out: Vec<usize> = drawn
        .lines
        .iter()
        .zip(&drawn.edges)
        .filter(|(l, _)| !line_explained(drawn, **l, observed, tol_px))
        .map(|(_, e)| e.block)
        .collect();
    out.sort_unstable();
    out.dedup();
    out
}

/// Draws `blocks` in `camera` with the exact hidden-line removal of `render::truth`.
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

    fn two_blocks() -> Vec<Block> {
        vec![
            Block::new("b30", DVec3::new(15.0, 7.5, 7.5), 0.0),
            Block::new("b15", DVec3::new(7.5, 22.5, 7.5), 0.0),
        ]
    }

    fn cam(blocks: &[Block], view: CornerView) -> Camera {
        let v: Vec<DVec3> = blocks.iter().flat_map(|b| b.world_vertices()).collect();
        Camera::frame(&v, view, &CameraOptions::default())
    }

    #[test]
    fn the_true_hypothesis_explains_every_view() {
        let blocks = two_blocks();
        let views: Vec<_> = CornerView::ALL
            .iter()
            .map(|&v| {
                let camera = cam(&blocks, v);
                let drawing = draw_hypothesis(&blocks, &camera);
                ObservedView { drawing, camera }
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

    #[test]
    fn segment_distance_is_perpendicular_inside_and_to_the_end_outside() {
        let (a, b) = (DVec2::ZERO, DVec2::new(10.0, 0.0));
        assert_eq!(distance_to_segment_px(DVec2::new(5.0, 3.0), a, b), 3.0);
        assert_eq!(distance_to_segment_px(DVec2::new(13.0, 4.0), a, b), 5.0);
    }
}
