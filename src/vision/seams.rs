//! Seam refinement of fitted lines (`super::lines`): a line on the renderer's dark seam is
//! re-fitted on the seam's pixels, and cut in two where its seam steps across.

use super::lines::{FittedLine, LineOptions};
use crate::geom::{floor_i64, gray_at_px, DVec2};
use image::GrayImage;

/// Refines lines that sit on a dark seam (the renderer draws ~1 px dark lines along block
/// edges between faces): the edge map's band is lopsided when the faces on the two sides differ
/// in brightness, so its centre can miss the seam by most of a pixel. A pixel within
/// `SEAM_SEARCH_PX` of the line is a seam pixel when it is darker, by at least
/// [`MIN_SEAM_CONTRAST`] gray levels, than both pixels `SEAM_SIDE_PX` away across the line (a
/// local test, so faces that change along the line do not matter). When seam pixels cover at
/// least half the line's length, the line is re-fitted by least squares on them, weighted by
/// their darkness; a line whose seam steps across is returned as two
/// ([`split_at_seam_step`]). Other lines (a plain step, e.g. a silhouette against the
/// background, whose band is symmetric) are kept as they are.
pub fn refine_lines_on_seams(
    gray: &GrayImage,
    lines: &[FittedLine],
    _opts: &LineOptions,
) -> Vec<FittedLine> {
    let mut pts: Vec<DVec2> = Vec::new();
    let mut weights: Vec<f64> = Vec::new();
    let mut out = Vec::with_capacity(lines.len());
    for l in lines {
        seam_pixels(gray, l, &mut pts, &mut weights);
        match split_at_seam_step(l, &pts, &weights) {
            Some(parts) => out.extend(parts),
            None => out.push(refine_one(l, &pts, &weights).unwrap_or(*l)),
        }
    }
    out
}

/// Smallest step across the line between two seams that splits a line, px.
const MIN_SEAM_STEP_PX: f64 = 1.5;
/// A line is split only where two seams at constant offsets explain the seam pixels' offsets
/// this much better than one straight seam: the F statistic of the step (the squared residual
/// it removes over the residual per pixel left) is at least this.
const MIN_STEP_F: f64 = 50.0;
/// Each of the two seams of a split line is at least this long, px.
const MIN_SEAM_PART_PX: f64 = 8.0;

/// Two seams of one direction, one ending where the other begins a little aside (in a
/// perspective view an upper block's upright above a lower block's, both inside one vote band),
/// make one fitted line that turns between them. When the seam pixels of `l` (`pts`, with
/// `weights`) lie on two parts along the line at offsets at least [`MIN_SEAM_STEP_PX`] apart,
/// each at least [`MIN_SEAM_PART_PX`] long, and two constant offsets explain them much better
/// than one straight line ([`MIN_STEP_F`]), `l` is cut at the step and each part is
/// re-fitted on its own seam pixels. `None` when there is no such step or a part does not refit.
fn split_at_seam_step(l: &FittedLine, pts: &[DVec2], weights: &[f64]) -> Option<[FittedLine; 2]> {
    let mut order: Vec<(f64, f64, usize)> = pts
        .iter()
        .enumerate()
        .map(|(k, p)| (l.along_px(*p), l.signed_distance_px(*p), k))
        .collect();
    order.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.2.cmp(&b.2)));
    let s = step_index(&order)?;
    let cut_t = (order[s - 1].0 + order[s].0) / 2.0;
    let cut = l.centroid_px + l.direction * cut_t;
    let part = |range: std::ops::Range<usize>, from: DVec2, to: DVec2| {
        let (p, w): (Vec<DVec2>, Vec<f64>) = order[range]
            .iter()
            .map(|o| (pts[o.2], weights[o.2]))
            .unzip();
        let piece = FittedLine {
            centroid_px: (from + to) / 2.0,
            from_px: from,
            to_px: to,
            // Counted in the part's own seam pixels: the band's pixels are not split.
            support: p.len(),
            ..*l
        };
        refine_one(&piece, &p, &w)
    };
    Some([
        part(0..s, l.from_px, cut)?,
        part(s..order.len(), cut, l.to_px)?,
    ])
}

/// The index of the first of `order` (seam pixels as `(along, across, _)`, ordered along)
/// after a step across; see [`split_at_seam_step`].
fn step_index(order: &[(f64, f64, usize)]) -> Option<usize> {
    let n = order.len();
    if n < 4 || order[n - 1].0 - order[0].0 < 2.0 * MIN_SEAM_PART_PX {
        return None;
    }
    let nf = n as f64;
    let (mt, md) = order
        .iter()
        .fold((0.0, 0.0), |(a, b), o| (a + o.0 / nf, b + o.1 / nf));
    let (stt, std_, sdd) = order.iter().fold((0.0, 0.0, 0.0), |(a, b, c), o| {
        let (dt, dd) = (o.0 - mt, o.1 - md);
        (a + dt * dt, b + dt * dd, c + dd * dd)
    });
    let line_sse = if stt > 0.0 {
        sdd - std_ * std_ / stt
    } else {
        sdd
    };
    // Prefix sums of the offsets about their mean, for each part's mean and residual.
    let mut prefix = vec![(0.0, 0.0)];
    for o in order {
        let (s1, s2) = prefix[prefix.len() - 1];
        prefix.push((s1 + (o.1 - md), s2 + (o.1 - md).powi(2)));
    }
    let part = |a: usize, b: usize| {
        let m = (b - a) as f64;
        let (sum, sq) = (prefix[b].0 - prefix[a].0, prefix[b].1 - prefix[a].1);
        (sum / m, sq - sum * sum / m)
    };
    let (t0, t1) = (order[0].0, order[n - 1].0);
    let (sse, step, s) = (1..n)
        .filter(|&s| order[s - 1].0 - t0 >= MIN_SEAM_PART_PX && t1 - order[s].0 >= MIN_SEAM_PART_PX)
        .map(|s| {
            let ((ma, ea), (mb, eb)) = (part(0, s), part(s, n));
            (ea + eb, (ma - mb).abs(), s)
        })
        .min_by(|a, b| a.0.total_cmp(&b.0))?;
    let f = (line_sse - sse) / (sse / (n as f64 - 3.0)).max(1e-9);
    (step >= MIN_SEAM_STEP_PX && f >= MIN_STEP_F).then_some(s)
}

/// Minimum local darkness of a seam pixel, gray levels. The renderer's seams are 35 against a
/// background of 60 and faces of 100 and more; sensor noise (sigma 8) passes now and then, so
/// each pixel weighs only its darkness beyond three quarters of this value. Measured with
/// `blockworld bench vision`: 15 brings the mean vertex distance from 0.65 px (at 30) to 0.44 px.
pub const MIN_SEAM_CONTRAST: f64 = 15.0;
/// Seam pixels are looked for this close to the band's line, px.
const SEAM_SEARCH_PX: f64 = 2.5;
/// Seam pixels are not taken this close to a line's ends, px.
const SEAM_END_MARGIN_PX: f64 = 5.0;
/// A seam pixel is compared with the pixels this far away on either side, px.
const SEAM_SIDE_PX: f64 = 2.0;

/// The seam pixels of `l` (see [`refine_lines_on_seams`]): the pixels within
/// `SEAM_SEARCH_PX` of the line, between its ends less a margin, darker by at least
/// [`MIN_SEAM_CONTRAST`] than both pixels `SEAM_SIDE_PX` away across it, into `pts`, each with
/// its weight (its darkness beyond three quarters of the contrast) in `weights`. A pixel centre
/// `(x + 0.5, y + 0.5)` moved by a fixed offset lands in the pixel `x + floor(0.5 + offset)`,
/// so the two side pixels are fixed raster steps from it, found once per line.
fn seam_pixels(gray: &GrayImage, l: &FittedLine, pts: &mut Vec<DVec2>, weights: &mut Vec<f64>) {
    pts.clear();
    weights.clear();
    let level = |x: i64, y: i64| gray_at_px(gray, x, y);
    let n = l.direction.perp();
    let side = |s: f64| (floor_i64(0.5 + n.x * s), floor_i64(0.5 + n.y * s));
    let (ahead, behind) = (side(SEAM_SIDE_PX), side(-SEAM_SIDE_PX));
    // Keep clear of the ends, where other lines' seams cross the band.
    let margin = (0.25 * l.length_px()).min(SEAM_END_MARGIN_PX);
    let (t0, t1) = (l.along_px(l.from_px) + margin, l.along_px(l.to_px) - margin);
    let steep = l.direction.y.abs() >= l.direction.x.abs();
    // Walk rows (steep lines) or columns (flat lines) between the ends.
    let (a, b) = (l.from_px, l.to_px);
    let (lo, hi) = if steep {
        (a.y.min(b.y), a.y.max(b.y))
    } else {
        (a.x.min(b.x), a.x.max(b.x))
    };
    let slope_room = if steep {
        l.direction.y.abs()
    } else {
        l.direction.x.abs()
    };
    // Pixel centres `q + 0.5` within SEAM_SEARCH_PX of the line lie within this many px of its
    // crossing along the row/column; one more on each side for rounding.
    let reach_q = SEAM_SEARCH_PX / slope_room.max(0.3);
    let mut s = floor_i64(lo);
    while (s as f64) <= hi.ceil() {
        let s_c = s as f64 + 0.5;
        // Where the line crosses this row/column.
        let other = if steep {
            l.centroid_px.x + (s_c - l.centroid_px.y) * l.direction.x / l.direction.y
        } else {
            l.centroid_px.y + (s_c - l.centroid_px.x) * l.direction.y / l.direction.x
        };
        for q in floor_i64(other - reach_q - 0.5)..=floor_i64(other + reach_q - 0.5) + 1 {
            let (x, y) = if steep { (q, s) } else { (s, q) };
            let p = DVec2::new(x as f64 + 0.5, y as f64 + 0.5);
            let t = l.along_px(p);
            let d = n.dot(p - l.centroid_px);
            if d.abs() > SEAM_SEARCH_PX || t < t0 || t > t1 {
                continue;
            }
            let Some(g) = level(x, y) else { continue };
            let sides = (
                level(x + ahead.0, y + ahead.1),
                level(x + behind.0, y + behind.1),
            );
            let (Some(a), Some(b)) = sides else { continue };
            let darkness = a.min(b) - g;
            if darkness >= MIN_SEAM_CONTRAST {
                pts.push(p);
                // Only the darkness beyond most of the threshold counts: noise that barely
                // passes the test weighs little next to a real seam.
                weights.push(darkness - 0.75 * MIN_SEAM_CONTRAST);
            }
        }
        s += 1;
    }
}

fn refine_one(l: &FittedLine, pts: &[DVec2], weights: &[f64]) -> Option<FittedLine> {
    // Seam pixels must cover at least half the line (counted along it, one per px).
    let sampled = l.length_px() - 2.0 * (0.25 * l.length_px()).min(SEAM_END_MARGIN_PX);
    if (distinct_along_px(l, pts) as f64) < 0.5 * sampled {
        return None;
    }
    let (c, mut dir) = fit_line_weighted(pts, weights)?;
    if dir.dot(l.direction) < 0.0 {
        dir = -dir;
    }
    if dir.dot(l.direction) < 0.99 {
        return None;
    }
    let project = |p: DVec2| c + dir * dir.dot(p - c);
    Some(FittedLine {
        centroid_px: c,
        direction: dir,
        from_px: project(l.from_px),
        to_px: project(l.to_px),
        ..*l
    })
}

/// How many distinct whole pixels along `l` (`along_px` rounded) the points `pts` fall on:
/// marked in a table over their range (they span the line's length), or sorted when the range
/// is out of proportion to their number.
fn distinct_along_px(l: &FittedLine, pts: &[DVec2]) -> usize {
    let mut along: Vec<i64> = pts.iter().map(|p| l.along_px(*p).round() as i64).collect();
    let (lo, hi) = along
        .iter()
        .fold((i64::MAX, i64::MIN), |(lo, hi), &a| (lo.min(a), hi.max(a)));
    let span = hi.saturating_sub(lo);
    if along.is_empty() || span < 0 || span as u64 > 4 * along.len() as u64 + 64 {
        along.sort_unstable();
        along.dedup();
        return along.len();
    }
    let mut seen = vec![false; span as usize + 1];
    along
        .iter()
        .filter(|&&a| !std::mem::replace(&mut seen[(a - lo) as usize], true))
        .count()
}

/// Weighted total least squares: centroid and unit direction.
fn fit_line_weighted(points: &[DVec2], weights: &[f64]) -> Option<(DVec2, DVec2)> {
    let wsum: f64 = weights.iter().sum();
    if points.len() < 2 || wsum <= 0.0 {
        return None;
    }
    let c = points
        .iter()
        .zip(weights)
        .fold(DVec2::ZERO, |a, (p, w)| a + *p * *w)
        / wsum;
    let (mut sxx, mut sxy, mut syy) = (0.0, 0.0, 0.0);
    for (p, w) in points.iter().zip(weights) {
        let d = *p - c;
        sxx += w * d.x * d.x;
        sxy += w * d.x * d.y;
        syy += w * d.y * d.y;
    }
    if sxx + syy <= 0.0 {
        return None;
    }
    let angle = 0.5 * (2.0 * sxy).atan2(sxx - syy);
    Some((c, DVec2::new(angle.cos(), angle.sin())))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::drawing::EdgeAxis;
    use crate::vision::lines::test_segment;
    use image::Luma;

    /// A 100 x 100 picture of faces at gray 150 with a 1 px seam at gray 35 along each
    /// segment (picture px, y up), drawn one pixel per row.
    fn seams_picture(segments: &[(DVec2, DVec2)]) -> GrayImage {
        let mut img = GrayImage::from_pixel(100, 100, Luma([150]));
        for &(a, b) in segments {
            let (lo, hi) = (a.y.min(b.y).ceil() as i64, a.y.max(b.y).floor() as i64);
            for y in lo..=hi {
                let x = a.x + (b.x - a.x) * (y as f64 - a.y) / (b.y - a.y);
                img.put_pixel(x.floor() as u32, (99 - y) as u32, Luma([35]));
            }
        }
        img
    }

    fn turn_deg(l: &FittedLine, u: DVec2) -> f64 {
        let a = l.direction.angle_to(u).to_degrees().abs();
        a.min(180.0 - a)
    }

    #[test]
    fn two_uprights_a_step_apart_are_cut_into_two_lines_but_one_seam_is_not() {
        // A lower upright at x = 40.5 (rows 20-50) and an upper one 3 px aside (rows 51-80),
        // found as one line between them.
        let one_line = test_segment(0, DVec2::new(42.0, 20.0), DVec2::new(42.0, 80.0));
        let img = seams_picture(&[
            (DVec2::new(40.5, 20.5), DVec2::new(40.5, 50.5)),
            (DVec2::new(43.5, 51.0), DVec2::new(43.5, 80.5)),
        ]);
        let out = refine_lines_on_seams(&img, &[one_line], &LineOptions::default());
        assert_eq!(out.len(), 2, "{out:?}");
        for (l, x) in out.iter().zip([40.5, 43.5]) {
            assert!(turn_deg(l, DVec2::Y) < 0.5, "{l:?}");
            assert!((l.centroid_px.x - x).abs() < 0.3, "{l:?} not at {x}");
        }
        // A worse input for the cut: one straight seam, slanted a little, stays one line.
        let img = seams_picture(&[(DVec2::new(40.5, 20.5), DVec2::new(43.5, 80.5))]);
        let out = refine_lines_on_seams(&img, &[one_line], &LineOptions::default());
        assert_eq!(out.len(), 1, "{out:?}");
        // Nor do two seams 1 px apart, under the 1.5 px step that cuts.
        let img = seams_picture(&[
            (DVec2::new(40.5, 20.5), DVec2::new(40.5, 50.5)),
            (DVec2::new(41.5, 51.0), DVec2::new(41.5, 80.5)),
        ]);
        let out = refine_lines_on_seams(&img, &[one_line], &LineOptions::default());
        assert_eq!(out.len(), 1, "{out:?}");
    }

    #[test]
    fn floor_i64_is_floor_everywhere_it_is_used() {
        let xs = [
            -2.5,
            -1.0,
            -0.999,
            -0.0,
            0.0,
            0.3,
            1.0,
            1.5,
            479.999,
            1e15 + 0.5,
            -1e15 - 0.5,
        ];
        for x in xs {
            assert_eq!(floor_i64(x), x.floor() as i64, "{x}");
        }
        for x in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY, 1e300, -1e300] {
            assert_eq!(floor_i64(x), x.floor() as i64, "{x}");
        }
        // It can fail: truncation alone is wrong below zero.
        assert_ne!(-0.5f64 as i64, floor_i64(-0.5));
    }

    #[test]
    fn distinct_pixels_along_a_line_are_counted_once() {
        let l = FittedLine {
            axis: EdgeAxis::Vertical,
            centroid_px: DVec2::new(10.0, 0.0),
            direction: DVec2::Y,
            from_px: DVec2::new(10.0, -50.0),
            to_px: DVec2::new(10.0, 50.0),
            support: 0,
            rms_px: 0.0,
        };
        // Several points per pixel along the line, on both sides of it.
        let pts: Vec<DVec2> = (0..90)
            .map(|i| DVec2::new(9.0 + f64::from(i % 3), f64::from(i / 3) * 0.75 - 20.0))
            .collect();
        let mut plain: Vec<i64> = pts.iter().map(|p| l.along_px(*p).round() as i64).collect();
        plain.sort_unstable();
        plain.dedup();
        assert_eq!(distinct_along_px(&l, &pts), plain.len());
        assert!(plain.len() < pts.len());
        // Far apart (the sorted path) and none.
        let far = [
            DVec2::new(10.0, -1e6),
            DVec2::new(10.0, 1e6),
            DVec2::new(10.0, 1e6),
        ];
        assert_eq!(distinct_along_px(&l, &far), 2);
        assert_eq!(distinct_along_px(&l, &[]), 0);
    }
}
