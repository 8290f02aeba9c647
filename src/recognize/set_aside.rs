//! One view set aside: Chapter V's comparison of views when one corner view shows lines no
//! block in one direction draws (the edge of a cast shadow, Chapter II's discontinuity of
//! illumination) and Chapter VII's one-direction check therefore declines the four views.
//!
//! Taken only after the four views declined before any search for lines in no block
//! direction (what a cast shadow's edge causes; never after a view not explained, a failure
//! case of Chapter VII, an ambiguity, an imprecise place or a spent budget). Every view in turn
//! is left out and the others recognized alone. The answer is taken only when every view
//! left out that gives an answer gives the same blocks, placed alike to an exact answer's
//! precision (a second reading of their places, [`EXACT_OVERLAP`]), and no view contradicts
//! them: read through its picture ([`pictures_mismatch`]), every line the answer draws is
//! seen or weak in the picture, and every observed line the answer does not explain is one
//! no block draws: off every block axis (a cast shadow's edge, docs/recognizer-pictures.md
//! "What a line can come from"), or along an axis but, away from the answer's lines, wholly
//! outside its outline and not an upright line ending at a junction (a block hidden in the
//! other views would show such a vertical edge; a shadow's edge runs to the picture's border
//! or fades out). Anything else keeps the four views' decline.

use super::answer::{ObservedView, Recognition, RecognizeOptions};
use super::constraints::{lines_off_the_axes, AxisTolerance};
use super::edge_profile::ViewPicture;
use super::picture::pictures_mismatch;
use super::placement::{overlap_after_shift, EXACT_OVERLAP};
use super::verify::{draw_hypothesis, ViewCheck, ViewMismatch};
use super::SAME_PLACE_TOL_MM;
use crate::drawing::LineDrawing;
use crate::geom::{convex_hull, distance_to_segment_px, inside_convex, DVec2};
use crate::scene::{same_blocks, Block, ReconStatus, ViewEvidence};

/// An observed line within this angle of the picture's vertical is upright: a block's
/// vertical edge (the corner views look down 35 degrees and keep verticals vertical in
/// orthographic views; perspective ones tilt them by a few degrees at the picture's edge).
const UPRIGHT_WITHIN_DEG: f64 = 10.0;
/// Observed lines are read every this many px against the answer's drawing.
const SAMPLE_STEP_PX: f64 = 1.0;
/// A line's end this close to the picture's border, px, runs out of the picture.
const BORDER_PX: f64 = 3.0;
/// The answer of the views without one of them, when every view left out in turn that gives
/// an answer gives the same blocks placed alike and no view contradicts them (module doc);
/// `None` otherwise.
/// `recognize` is the recognizer on a subset of the views and their pictures.
pub(super) fn with_one_view_set_aside(
    views: &[ObservedView],
    pictures: &[ViewPicture],
    opts: &RecognizeOptions,
    recognize: &dyn Fn(&[ObservedView], &[ViewPicture]) -> Recognition,
) -> Option<Recognition> {
    if views.len() < 3 || pictures.len() != views.len() {
        return None;
    }
    let answers: Vec<(usize, Recognition)> = (0..views.len())
        .map(|k| (k, recognize(&without(views, k), &without(pictures, k))))
        .filter(|(_, r)| r.status == ReconStatus::Ok)
        .collect();
    let (_, first) = answers.first()?;
    if answers
        .iter()
        .any(|(_, r)| !placed_alike(&r.blocks, &first.blocks))
    {
        return None;
    }
    let checks = views_read(&first.blocks, views, pictures, opts);
    if checks.iter().any(|(contradicts, _)| *contradicts) {
        return None;
    }
    let (k, mut answer) = answers.into_iter().next()?;
    let c = checks[k].1;
    let left_out = ViewEvidence {
        view: views[k].camera.view.name().to_string(),
        unexplained_points: c.unexplained_points,
        extra_points: c.extra_points,
        unexplained_lines: c.unexplained_lines,
        extra_lines: c.extra_lines,
        ..ViewEvidence::default()
    };
    answer.evidence.views.insert(k, left_out);
    Some(answer)
}

/// Each view read through its picture against `blocks`: whether it contradicts them (an
/// answer's point or line not seen and not weak in the picture, or an observed line along a
/// block axis that the answer does not explain and a block could draw,
/// [`could_be_block_edge`]), and its counts.
fn views_read(
    blocks: &[Block],
    views: &[ObservedView],
    pictures: &[ViewPicture],
    opts: &RecognizeOptions,
) -> Vec<(bool, ViewCheck)> {
    let drawn: Vec<LineDrawing> = views
        .iter()
        .map(|v| draw_hypothesis(blocks, &v.camera))
        .collect();
    let observed: Vec<&LineDrawing> = views.iter().map(|v| &v.drawing).collect();
    let mismatches = pictures_mismatch(&drawn, &observed, pictures, opts.tol_px);
    let tol = AxisTolerance {
        tol_deg: opts.axis_tol_deg,
        end_tol_px: opts.tol_px,
    };
    let contradicts = |k: usize, m: &ViewMismatch| {
        let v = &views[k];
        let off = lines_off_the_axes(&v.drawing, &v.camera, tol);
        let outline = convex_hull(&drawn[k].points);
        let edge_like = |&l: &usize| {
            !off.contains(&l) && could_be_block_edge(v, l, &drawn[k], &outline, opts.tol_px)
        };
        !m.extra_lines.is_empty()
            || !m.extra_points.is_empty()
            || m.unexplained_lines.iter().any(edge_like)
    };
    (0..views.len())
        .map(|k| (contradicts(k, &mismatches[k]), mismatches[k].counts()))
        .collect()
}

/// `true` when observed line `l` of `view` could be a block's edge the answer (drawn as
/// `drawn`, its outline `outline`) lacks: some stretch of it away from every drawn line lies
/// inside the outline, or it is upright and ends where a block's vertical edge would, at a
/// junction inside the picture (a shadow's edge runs to the picture's border or fades out).
fn could_be_block_edge(
    view: &ObservedView,
    l: usize,
    drawn: &LineDrawing,
    outline: &[DVec2],
    tol_px: f64,
) -> bool {
    let drawing = &view.drawing;
    let [a, b] = drawing.lines[l];
    let (pa, pb) = (drawing.points[a], drawing.points[b]);
    let samples = (pa.distance(pb) / SAMPLE_STEP_PX).ceil().max(1.0) as usize;
    let near_drawn = |q: DVec2| {
        drawn
            .lines
            .iter()
            .any(|&[c, d]| distance_to_segment_px(q, drawn.points[c], drawn.points[d]) <= tol_px)
    };
    let inside = (0..=samples)
        .map(|i| pa.lerp(pb, i as f64 / samples as f64))
        .any(|q| !near_drawn(q) && inside_convex(outline, q, -tol_px));
    let d = pb - pa;
    let upright = d.x.abs() <= d.length() * UPRIGHT_WITHIN_DEG.to_radians().sin();
    inside || upright && ![a, b].iter().any(|&e| free_end(view, e, outline, tol_px))
}

/// `true` when point `e` of the view's drawing lies outside `outline` and is a free end: one
/// line only, or within [`BORDER_PX`] of the picture's border.
fn free_end(view: &ObservedView, e: usize, outline: &[DVec2], tol_px: f64) -> bool {
    let drawing = &view.drawing;
    let q = drawing.points[e];
    let [w, h] = view.camera.size_px;
    let degree = drawing.lines.iter().filter(|l| l.contains(&e)).count();
    let at_border = q.x <= BORDER_PX
        || q.y <= BORDER_PX
        || q.x >= f64::from(w) - BORDER_PX
        || q.y >= f64::from(h) - BORDER_PX;
    !inside_convex(outline, q, tol_px) && (degree == 1 || at_border)
}

/// `true` when `a` and `b` are the same catalog blocks placed alike to an exact answer's
/// precision: each block of `a` has one of `b` of its type within [`SAME_PLACE_TOL_MM`] that
/// overlaps it moved by their horizontal difference by at least [`EXACT_OVERLAP`], at the same
/// height.
fn placed_alike(a: &[Block], b: &[Block]) -> bool {
    same_blocks(a, b, SAME_PLACE_TOL_MM)
        && a.iter().all(|x| {
            b.iter().any(|y| {
                let d = y.center_mm - x.center_mm;
                x.block_type.id == y.block_type.id
                    && d.y.abs() <= SAME_PLACE_TOL_MM
                    && overlap_after_shift(x, DVec2::new(d.x, d.z)) >= EXACT_OVERLAP
            })
        })
}

/// `items` without its `k`-th element.
fn without<T: Clone>(items: &[T], k: usize) -> Vec<T> {
    items
        .iter()
        .enumerate()
        .filter(|&(i, _)| i != k)
        .map(|(_, x)| x.clone())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::DVec3;
    use crate::recognize::{recognize_in_pictures, views_of, CornerView, Recognition};
    use image::GrayImage;

    fn inked(view: &ObservedView) -> GrayImage {
        crate::recognize::inked_picture(&view.camera, &view.drawing)
    }

    /// `view` with a line from `from` to `to` added to its drawing.
    fn with_line(view: &ObservedView, from: DVec2, to: DVec2) -> ObservedView {
        let mut drawing = view.drawing.clone();
        drawing.kinds.clear();
        drawing.edges.clear();
        let at = |d: &mut LineDrawing, q: DVec2| {
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
        ObservedView {
            drawing,
            camera: view.camera,
        }
    }

    fn recognized(views: &[ObservedView]) -> Recognition {
        let grays: Vec<GrayImage> = views.iter().map(inked).collect();
        let refs: Vec<&GrayImage> = grays.iter().collect();
        recognize_in_pictures(views, &refs, &RecognizeOptions::default()).unwrap()
    }

    /// A cast shadow's edge in one view: a strong level line from the outline's lowest
    /// corner to the picture's border, off every block axis. The four views decline (Chapter
    /// VII's one-direction check); the other three views answer the cube, and the view set
    /// aside does not contradict it. The same view with also a line along a block axis across
    /// the top face, which no shading draws and the answer lacks, keeps the decline.
    #[test]
    fn a_shadow_edge_in_one_view_sets_it_aside_but_an_unexplained_edge_does_not() {
        let truth = vec![Block::new("b15", DVec3::new(0.0, 7.5, 0.0), 0.0)];
        let mut views = views_of(&truth, &CornerView::ALL);
        let lowest = *views[0]
            .drawing
            .points
            .iter()
            .min_by(|a, b| a.y.total_cmp(&b.y))
            .unwrap();
        let border = DVec2::new(f64::from(views[0].camera.size_px[0]) - 1.0, lowest.y);
        let shadowed = with_line(&views[0], lowest, border);
        let mut alone = views.clone();
        alone[0] = shadowed.clone();
        let four = recognize_prepared_only(&alone);
        assert_eq!(four.status, ReconStatus::Unsupported, "{:?}", four.reason);
        let answer = recognized(&alone);
        assert_eq!(answer.status, ReconStatus::Ok, "{:?}", answer.reason);
        assert!(
            same_blocks(&answer.blocks, &truth, 0.1),
            "{:?}",
            answer.blocks
        );
        let named: Vec<&str> = answer
            .evidence
            .views
            .iter()
            .map(|v| v.view.as_str())
            .collect();
        assert_eq!(named, ["ne", "se", "sw", "nw"]);
        // Worse: a line along a top edge through the top face's centre (between the highest
        // corner and the central "Y", the point nearest the drawing's centroid).
        let d = &views[0].drawing;
        let highest = (0..d.points.len())
            .max_by(|&a, &b| d.points[a].y.total_cmp(&d.points[b].y))
            .unwrap();
        let mean = d.points.iter().fold(DVec2::ZERO, |s, p| s + *p) / d.points.len() as f64;
        let central = *d
            .points
            .iter()
            .min_by(|a, b| a.distance(mean).total_cmp(&b.distance(mean)))
            .unwrap();
        let [i, j] = *d.lines.iter().find(|l| l.contains(&highest)).unwrap();
        let edge = d.points[j] - d.points[i];
        let centre = (d.points[highest] + central) * 0.5;
        views[0] = with_line(&shadowed, centre - edge * 0.25, centre + edge * 0.25);
        let declined = recognized(&views);
        assert_eq!(
            declined.status,
            ReconStatus::Unsupported,
            "{:?}",
            declined.blocks
        );
    }

    /// The four views' answer alone, without any view set aside.
    fn recognize_prepared_only(views: &[ObservedView]) -> Recognition {
        let grays: Vec<GrayImage> = views.iter().map(inked).collect();
        let refs: Vec<&GrayImage> = grays.iter().collect();
        let opts = RecognizeOptions::default();
        let (views, pictures) = super::super::prepared(views, &refs, &opts);
        super::super::recognize_prepared(&views, &pictures, &opts, &|_| {})
    }
}
