//! One view set aside: Chapter V's comparison of views when one corner view shows lines no
//! block draws (the edge of a cast shadow, Chapter II's discontinuity of illumination; a
//! highlight's line) and Chapter VII's one-direction check or step 6's check therefore
//! declines the four views.
//!
//! Taken only after the four views declined for lines in no block direction (what a cast
//! shadow's edge causes) or for a view not explained (a shadow's or a highlight's line, or one
//! view read a little off the others); never after a failure case of Chapter VII, no block
//! found, an ambiguity, an imprecise place or a spent budget. Every view in turn
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
use super::constraints::lines_off_the_axes;
use super::edge_profile::ViewPicture;
use super::flow::{axis_tolerance, straight_lines_in_no_block_direction};
use super::picture::{
    lines_at, pictures_mismatch, px_per_mm, without_lines, ROUNDING_ALLOWANCE_MM,
};
use super::placement::{misplaced_in_a_view, overlap_after_shift, EXACT_OVERLAP};
use super::shadow::shadow_lines;
use super::verify::{draw_hypothesis, ViewCheck, ViewMismatch};
use super::{Camera, SAME_PLACE_TOL_MM};
use crate::camera::Projector;
use crate::drawing::LineDrawing;
use crate::geom::{convex_hull, distance_to_segment_px, inside_convex, DVec2, UnionFind};
use crate::scene::{same_blocks, Block, ReconStatus, ViewEvidence};

/// An observed line within this angle of the picture's vertical is upright: a block's
/// vertical edge (the corner views look down 35 degrees and keep verticals vertical in
/// orthographic views; perspective ones tilt them by a few degrees at the picture's edge).
const UPRIGHT_WITHIN_DEG: f64 = 10.0;
/// Rounds of [`with_shading_lines_set_aside`]: the declined answer's blocks, then those of
/// the views read without the lines they leave unexplained, twice (the shadows a closer
/// answer casts set aside more of the next reading's lines).
const SET_ASIDE_ROUNDS: usize = 3;
/// Lines within this angle of each other are parallel.
const PARALLEL_WITHIN_DEG: f64 = 5.0;
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

/// The answer of the views with the lines no block draws left out of every view: the lines
/// along no block axis (and the unclassified straight ones), and, against the declined
/// answer's blocks `hypothesis`, the observed lines it does not explain that no block could
/// draw ([`could_be_block_edge`]) or that lie along the edge of a shadow it casts under the
/// view's known lights ([`shadow_lines`]); then recognized again, at most
/// [`SET_ASIDE_ROUNDS`] times, and taken only when no view read whole contradicts it
/// ([`views_read`]); `None` otherwise.
pub(super) fn with_shading_lines_set_aside(
    views: &[ObservedView],
    pictures: &[ViewPicture],
    opts: &RecognizeOptions,
    recognize: &dyn Fn(&[ObservedView], &[ViewPicture]) -> Recognition,
    hypothesis: &[Block],
) -> Option<Recognition> {
    if pictures.len() != views.len() {
        return None;
    }
    let mut hypothesis = hypothesis.to_vec();
    for _ in 0..SET_ASIDE_ROUNDS {
        let kept = without_shading_lines(views, pictures, opts, &hypothesis)?;
        let answer = recognize(&kept, pictures);
        if answer.status == ReconStatus::Ok {
            return stands_against_every_view(&answer.blocks, views, pictures, opts)
                .then_some(answer);
        }
        let next = &answer.evidence.hypothesis;
        if next.is_empty() || same_blocks(next, &hypothesis, SAME_PLACE_TOL_MM) {
            return None;
        }
        hypothesis = next.clone();
    }
    None
}

/// `true` when no view read whole contradicts `blocks` ([`views_read`]) and every view's
/// corners alone place each block exactly ([`misplaced_in_a_view`]).
fn stands_against_every_view(
    blocks: &[Block],
    views: &[ObservedView],
    pictures: &[ViewPicture],
    opts: &RecognizeOptions,
) -> bool {
    let drawn: Vec<LineDrawing> = views
        .iter()
        .map(|v| draw_hypothesis(blocks, &v.camera))
        .collect();
    misplaced_in_a_view(blocks, &drawn, views, opts.tol_px, opts.grid_mm).is_none()
        && views_read(blocks, views, pictures, opts)
            .iter()
            .all(|(contradicts, _)| !contradicts)
}

/// `views` without the lines [`with_shading_lines_set_aside`] leaves out against
/// `hypothesis` (none: only the off-axis ones); `None` when there are none.
fn without_shading_lines(
    views: &[ObservedView],
    pictures: &[ViewPicture],
    opts: &RecognizeOptions,
    hypothesis: &[Block],
) -> Option<Vec<ObservedView>> {
    let drawn: Vec<LineDrawing> = views
        .iter()
        .map(|v| draw_hypothesis(hypothesis, &v.camera))
        .collect();
    let observed: Vec<&LineDrawing> = views.iter().map(|v| &v.drawing).collect();
    let mismatches = (!hypothesis.is_empty())
        .then(|| pictures_mismatch(&drawn, &observed, pictures, opts.tol_px));
    let mut any = false;
    let kept = views
        .iter()
        .enumerate()
        .map(|(k, v)| {
            let mut off = straight_lines_in_no_block_direction(v, opts);
            if let Some(m) = &mismatches {
                let shadow = shadow_lines(v, hypothesis, opts.tol_px);
                let cast = m[k].unexplained_lines.iter().filter(|l| shadow.contains(l));
                let cast: Vec<usize> = cast.filter(|l| !off.contains(l)).copied().collect();
                off.extend(cast);
                let outline = Outline::of(hypothesis, &v.camera);
                let shading: Vec<usize> = m[k]
                    .unexplained_lines
                    .iter()
                    .copied()
                    .filter(|&l| {
                        !off.contains(&l)
                            && !could_be_block_edge(v, l, &drawn[k], &outline, opts.tol_px)
                    })
                    .collect();
                off.extend(shading);
            }
            any |= !off.is_empty();
            v.with_drawing(without_lines(&v.drawing, &off))
        })
        .collect();
    any.then_some(kept)
}

/// Each view read through its picture against `blocks`: whether it contradicts them (an
/// answer's point or line not seen and not weak in the picture, or an observed line along a
/// block axis that the answer does not explain, a block could draw
/// ([`could_be_block_edge`]) and no shadow of the answer's blocks under the view's known
/// lights casts ([`shadow_lines`])), and its counts.
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
    let tol = axis_tolerance(opts);
    let contradicts = |k: usize, m: &ViewMismatch| {
        let v = &views[k];
        let off = lines_off_the_axes(&v.drawing, &v.camera, tol);
        let outline = Outline::of(blocks, &v.camera);
        let shadow = shadow_lines(v, blocks, opts.tol_px);
        let unexplained: Vec<usize> = m
            .unexplained_lines
            .iter()
            .copied()
            .filter(|l| !shadow.contains(l))
            .collect();
        let edge_like = |&l: &usize| {
            !off.contains(&l) && could_be_block_edge(v, l, &drawn[k], &outline, opts.tol_px)
        };
        !m.extra_lines.is_empty()
            || !m.extra_points.is_empty()
            || unexplained.iter().any(edge_like)
            || !every_piece_hangs_off(&v.drawing, &unexplained, &drawn[k], opts.tol_px)
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
    outline: &Outline,
    tol_px: f64,
) -> bool {
    let drawing = &view.drawing;
    let [a, b] = drawing.lines[l];
    let (pa, pb) = (drawing.points[a], drawing.points[b]);
    let samples = (pa.distance(pb) / SAMPLE_STEP_PX).ceil().max(1.0) as usize;
    let near_drawn = |q: DVec2| on_a_drawn_line(drawn, q, tol_px);
    let inside = (0..=samples)
        .map(|i| pa.lerp(pb, i as f64 / samples as f64))
        .any(|q| !near_drawn(q) && outline.contains(q, -tol_px));
    let d = pb - pa;
    let upright = d.x.abs() <= d.length() * UPRIGHT_WITHIN_DEG.to_radians().sin();
    if along_a_rounded_edge(drawing, l, drawn, tol_px) {
        return false;
    }
    inside || upright && ![a, b].iter().any(|&e| free_end(view, e, outline, tol_px))
}

/// `true` when every connected piece of the observed lines `lines` (lines sharing a point are
/// one piece) has a line that [`hangs_off`] the answer's drawing `drawn`, or that ends where an
/// observed line the answer explains ends (a block's upright outline runs on into the shadow
/// at its foot when the shaded face and the shadow are one gray): a cast shadow is attached to
/// the block that casts it, where a block the answer lacks, standing apart, is not.
fn every_piece_hangs_off(
    drawing: &LineDrawing,
    lines: &[usize],
    drawn: &LineDrawing,
    tol_px: f64,
) -> bool {
    let mut pieces = UnionFind::new(drawing.points.len());
    for &l in lines {
        let [a, b] = drawing.lines[l];
        pieces.union(a, b);
    }
    let explained_end = |&e: &usize| lines_at(drawing, e).any(|k| !lines.contains(&k));
    let mut attached: Vec<usize> = lines
        .iter()
        .filter(|&&l| {
            hangs_off(drawing, l, drawn, tol_px) || drawing.lines[l].iter().any(explained_end)
        })
        .map(|&l| pieces.find(drawing.lines[l][0]))
        .collect();
    attached.sort_unstable();
    lines.iter().all(|&l| {
        attached
            .binary_search(&pieces.find(drawing.lines[l][0]))
            .is_ok()
    })
}

/// `true` when an end of observed line `l` lies on a line of `drawn` (within `tol_px`): a
/// cast shadow's edge starts where the block casting it stands; a line off every block axis
/// away from the answer could be an edge of a block turned off the axes.
fn hangs_off(drawing: &LineDrawing, l: usize, drawn: &LineDrawing, tol_px: f64) -> bool {
    drawing.lines[l]
        .iter()
        .any(|&e| on_a_drawn_line(drawn, drawing.points[e], tol_px))
}

/// `true` when picture point `q` lies within `tol_px` of a line of `drawn`.
fn on_a_drawn_line(drawn: &LineDrawing, q: DVec2, tol_px: f64) -> bool {
    drawn
        .lines
        .iter()
        .any(|&[c, d]| distance_to_segment_px(q, drawn.points[c], drawn.points[d]) <= tol_px)
}

/// `true` when observed line `l` runs beside one line of `drawn`, parallel to it, every
/// sample within `tol_px` and the largest edge rounding ([`ROUNDING_ALLOWANCE_MM`] twice) of
/// it: the shading band of a rounded edge, not another block's edge.
fn along_a_rounded_edge(drawing: &LineDrawing, l: usize, drawn: &LineDrawing, tol_px: f64) -> bool {
    let [a, b] = drawing.lines[l];
    let (pa, pb) = (drawing.points[a], drawing.points[b]);
    let samples = (pa.distance(pb) / SAMPLE_STEP_PX).ceil().max(1.0) as usize;
    (0..drawn.lines.len()).any(|k| {
        let [c, d] = drawn.lines[k];
        let (qc, qd) = (drawn.points[c], drawn.points[d]);
        let Some(scale) = px_per_mm(drawn, k) else {
            return false;
        };
        let within = tol_px + 2.0 * ROUNDING_ALLOWANCE_MM * scale;
        let (u, v) = ((pb - pa).normalize_or_zero(), (qd - qc).normalize_or_zero());
        u.perp_dot(v).abs() <= PARALLEL_WITHIN_DEG.to_radians().sin()
            && (0..=samples)
                .map(|i| pa.lerp(pb, i as f64 / samples as f64))
                .all(|q| distance_to_segment_px(q, qc, qd) <= within)
    })
}

/// `true` when point `e` of the view's drawing lies outside `outline` and is a free end: one
/// line only, or within [`BORDER_PX`] of the picture's border.
fn free_end(view: &ObservedView, e: usize, outline: &Outline, tol_px: f64) -> bool {
    let drawing = &view.drawing;
    let q = drawing.points[e];
    let [w, h] = view.camera.size_px;
    let degree = drawing.lines.iter().filter(|l| l.contains(&e)).count();
    let at_border = q.x <= BORDER_PX
        || q.y <= BORDER_PX
        || q.x >= f64::from(w) - BORDER_PX
        || q.y >= f64::from(h) - BORDER_PX;
    !outline.contains(q, tol_px) && (degree == 1 || at_border)
}

/// The outline of an answer's blocks in one view: the union of each block's projected
/// convex hull (a block is convex), so the floor seen between two blocks lies outside it.
struct Outline {
    hulls: Vec<Vec<DVec2>>,
}

impl Outline {
    fn of(blocks: &[Block], camera: &Camera) -> Outline {
        let projector = Projector::new(camera);
        let hulls = blocks
            .iter()
            .map(|b| {
                let corners: Vec<DVec2> = b
                    .world_vertices()
                    .into_iter()
                    .map(|q| projector.picture(q))
                    .collect();
                convex_hull(&corners)
            })
            .collect();
        Outline { hulls }
    }

    /// `true` when `q` lies inside some block's hull grown by `margin_px` (shrunk when
    /// negative).
    fn contains(&self, q: DVec2, margin_px: f64) -> bool {
        self.hulls.iter().any(|h| inside_convex(h, q, margin_px))
    }
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
    use crate::recognize::{recognize_in_pictures, views_of, with_line, CornerView, Recognition};
    use image::GrayImage;

    fn inked(view: &ObservedView) -> GrayImage {
        crate::recognize::inked_picture(&view.camera, &view.drawing)
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

    /// A `b15` cube's four views, the `ne` one with an extra line from `from` to `to`
    /// (computed from that view's drawing), recognized with their inked pictures.
    fn cube_with_line(line: impl Fn(&LineDrawing) -> (DVec2, DVec2)) -> (Vec<Block>, Recognition) {
        let truth = vec![Block::new("b15", DVec3::new(0.0, 7.5, 0.0), 0.0)];
        let mut views = views_of(&truth, &CornerView::ALL);
        let (from, to) = line(&views[0].drawing);
        views[0] = with_line(&views[0], from, to);
        (truth, recognized(&views))
    }

    /// The drawing's lowest point and the line of the drawing from it that runs rightwards.
    fn lowest_right_edge(d: &LineDrawing) -> (DVec2, DVec2) {
        let low = (0..d.points.len())
            .min_by(|&a, &b| d.points[a].y.total_cmp(&d.points[b].y))
            .unwrap();
        let other = d
            .lines
            .iter()
            .filter(|l| l.contains(&low))
            .map(|&[i, j]| if i == low { j } else { i })
            .max_by(|&a, &b| d.points[a].x.total_cmp(&d.points[b].x))
            .unwrap();
        (d.points[low], d.points[other])
    }

    /// A rounded edge's shading band on a `b15` cube's drawing: a line from its front vertical
    /// edge along its lower right edge, `mm` above it inside the face, to 0.8 of the edge.
    fn band_above_lowest_right_edge(d: &LineDrawing, mm: f64) -> (DVec2, DVec2) {
        let (low, corner) = lowest_right_edge(d);
        let up = DVec2::new(0.0, mm * low.distance(corner) / 15.0);
        (low + up, low.lerp(corner, 0.8) + up)
    }

    /// A shadow's edge along a block axis: the cube's lower right edge continued beyond its
    /// corner on the floor for half its length (the four views decline: view not explained).
    /// Set aside, the cube is answered. The same line starting 6 px beyond the corner, apart
    /// from every line of the answer, could be an edge of a block the answer lacks: declined.
    #[test]
    fn a_shadow_edge_hanging_off_the_blocks_is_set_aside_but_one_standing_apart_is_not() {
        let beyond = |gap_px: f64| {
            move |d: &LineDrawing| {
                let (low, corner) = lowest_right_edge(d);
                let along = (corner - low).normalize();
                let start = corner + along * gap_px;
                (start, start + (corner - low) * 0.5)
            }
        };
        let (truth, answer) = cube_with_line(beyond(0.0));
        assert_eq!(answer.status, ReconStatus::Ok, "{:?}", answer.reason);
        assert!(same_blocks(&answer.blocks, &truth, 0.1));
        let (_, apart) = cube_with_line(beyond(6.0));
        assert_eq!(apart.status, ReconStatus::Unsupported, "{:?}", apart.blocks);
    }

    /// A rounded edge's shading band: a line from the cube's front vertical edge along its
    /// lower right edge, 0.4 mm above it inside the face, is set aside and the cube answered;
    /// 1.5 mm above it, no rounding's band, it could be another block's edge: declined.
    #[test]
    fn a_line_beside_an_edge_by_a_rounding_is_set_aside_but_one_further_in_is_not() {
        let inside = |mm: f64| move |d: &LineDrawing| band_above_lowest_right_edge(d, mm);
        let (truth, answer) = cube_with_line(inside(0.4));
        assert_eq!(answer.status, ReconStatus::Ok, "{:?}", answer.reason);
        assert!(same_blocks(&answer.blocks, &truth, 0.1));
        let (_, further) = cube_with_line(inside(1.5));
        assert_eq!(
            further.status,
            ReconStatus::Unsupported,
            "{:?}",
            further.blocks
        );
    }

    /// A shadow piece starting where an observed outline the answer explains runs on past
    /// the answer's corner (the shaded face and its shadow one gray) hangs off the answer; the
    /// same piece starting at that place but not on that line does not.
    #[test]
    fn a_piece_from_the_end_of_an_explained_line_hangs_off_and_one_beside_it_not() {
        let drawing = |points: Vec<DVec2>, lines: Vec<[usize; 2]>| {
            let mut d = LineDrawing {
                points,
                lines,
                ..LineDrawing::default()
            };
            d.finalize();
            d
        };
        let drawn = drawing(
            vec![DVec2::new(50.0, 20.0), DVec2::new(50.0, 120.0)],
            vec![[0, 1]],
        );
        let (top, foot, far) = (
            DVec2::new(50.0, 120.0),
            DVec2::new(50.0, 10.0),
            DVec2::new(10.0, 30.0),
        );
        let on = drawing(vec![top, foot, far], vec![[0, 1], [1, 2]]);
        assert!(every_piece_hangs_off(&on, &[1], &drawn, 2.0));
        let beside = drawing(vec![top, foot, foot, far], vec![[0, 1], [2, 3]]);
        assert!(!every_piece_hangs_off(&beside, &[1], &drawn, 2.0));
    }

    /// One view read a little off the others (its drawing and picture 1.5 px to the right,
    /// within step 6's 2 px tolerance, about 0.11 mm: a camera misplaced by that much) with a
    /// rounded edge's band beside its lower right edge. The four views decline (view not
    /// explained), and with the band's line set aside the view alone still misplaces the cube;
    /// the other three views place it exactly and the view set aside does not contradict
    /// them. The same view 2.5 px off, beyond the tolerance, contradicts them: declined.
    #[test]
    fn a_view_read_off_the_others_and_not_explained_is_set_aside_but_one_beyond_the_tolerance_is_not(
    ) {
        let answer = |shift_px: f64| {
            let truth = vec![Block::new("b15", DVec3::new(0.0, 7.5, 0.0), 0.0)];
            let mut views = views_of(&truth, &CornerView::ALL);
            let (from, to) = band_above_lowest_right_edge(&views[0].drawing, 0.4);
            let mut off = with_line(&views[0], from, to);
            off.drawing.points.iter_mut().for_each(|p| p.x += shift_px);
            off.drawing.finalize();
            views[0] = off;
            let four = recognize_prepared_only(&views);
            assert_eq!(four.status, ReconStatus::Unsupported, "{:?}", four.blocks);
            let kind = crate::recognize::decline_kind(four.reason.as_deref().unwrap_or_default());
            assert_eq!(kind, "view not explained", "{:?}", four.reason);
            (truth, recognized(&views))
        };
        let (truth, near) = answer(1.5);
        assert_eq!(near.status, ReconStatus::Ok, "{:?}", near.reason);
        assert!(same_blocks(&near.blocks, &truth, 0.05), "{:?}", near.blocks);
        let (_, beyond) = answer(2.5);
        assert_eq!(
            beyond.status,
            ReconStatus::Unsupported,
            "{:?}",
            beyond.blocks
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
