//! Step 2b of the vision front end: lines that stop short of where they must end are carried
//! on to it (docs/vision.md "Vision front end", docs/rendering.md "Photographic look").
//!
//! In a line drawing of blocks every line ends in a junction: an "L", a fork, an arrow, or a "T"
//! where it meets another line (Chapter IV's six-bit codes have no one-line vertex). In a
//! camera picture an edge can vanish over part of its length: where a soft shadow darkens a
//! lit face down to the brightness of the dim face beside it, the shading step between the two
//! faces, and with it the Sobel magnitude (eq. 2.1), falls to nothing, and the edge comes back
//! further on. The line finder then gives a piece that ends in the open, a *free end*, and the
//! vertex finder a one-line vertex no block has.
//!
//! [`bridge_free_ends`] carries each free end along its own line to the first line ahead of
//! it, within [`GapOptions::max_gap_px`]: a collinear piece of the same edge (the two pieces
//! become one line, the gap closed) or a line it crosses (the end moves to the crossing, which
//! gives the "T" or "L" the edge really has). An end with nothing ahead stays free, so a
//! shadow's boundary that fades out on an open face is not drawn on. Ends that already meet a
//! line are never moved, so a drawing with no free end (every line-art view) is unchanged.

use super::lines::FittedLine;
use super::vertices::intersect as crossing;
use crate::geom::DVec2;

/// Options of [`bridge_free_ends`], picture px.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GapOptions {
    /// An end is free when no other line's crossing lies this close to it (the vertex
    /// finder's join radius, `VertexOptions::join_radius_px`). Default 7.
    pub join_radius_px: f64,
    /// Longest stretch a free end is carried, px. Default 80: the longest edge hidden by a
    /// contact shadow over the accuracy suite at 512 x 480 was 66 px (a 15 mm block's vertical
    /// edge is about 100 px there).
    pub max_gap_px: f64,
    /// Two pieces of one axis are collinear when both ends of the shorter lie this close to the
    /// longer one's line, px. Default 2 (the recognizer's point tolerance).
    pub collinear_px: f64,
}

impl Default for GapOptions {
    fn default() -> Self {
        GapOptions {
            join_radius_px: 7.0,
            max_gap_px: 80.0,
            collinear_px: 2.0,
        }
    }
}

/// `true` when `t` lies within `l`'s extent along it, grown by `slack_px` at both ends.
fn within_extent(l: &FittedLine, p: DVec2, slack_px: f64) -> bool {
    let t = l.along_px(p);
    let (t0, t1) = (l.along_px(l.from_px), l.along_px(l.to_px));
    t >= t0.min(t1) - slack_px && t <= t0.max(t1) + slack_px
}

/// End `e` (0 = `from_px`, 1 = `to_px`) of a line.
fn end_of(l: &FittedLine, e: usize) -> DVec2 {
    if e == 0 {
        l.from_px
    } else {
        l.to_px
    }
}

/// `true` when end `e` of `lines[i]` meets another line: a crossing within the join radius of
/// it and within that line's extent, or another line's end within the join radius.
fn end_meets_a_line(lines: &[FittedLine], i: usize, e: usize, opts: &GapOptions) -> bool {
    let q = end_of(&lines[i], e);
    lines.iter().enumerate().any(|(j, l)| {
        j != i
            && (crossing(&lines[i], l).is_some_and(|p| {
                p.distance(q) <= opts.join_radius_px && within_extent(l, p, opts.join_radius_px)
            }) || l.from_px.distance(q) <= opts.join_radius_px
                || l.to_px.distance(q) <= opts.join_radius_px)
    })
}

/// What a free end meets first when carried on.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Hit {
    /// A collinear piece of the same edge (its index).
    Piece(usize),
    /// A crossing line, at this point.
    Crossing(DVec2),
}

/// `true` when the shorter of `a` and `b` lies within `tol_px` of the longer one's line (the
/// longer fit gives the edge's direction; a short piece's may be off by a degree or two).
fn collinear(a: &FittedLine, b: &FittedLine, tol_px: f64) -> bool {
    let (long, short) = if a.length_px() >= b.length_px() {
        (a, b)
    } else {
        (b, a)
    };
    [short.from_px, short.to_px]
        .iter()
        .all(|p| long.signed_distance_px(*p).abs() <= tol_px)
}

/// The first line ahead of free end `e` of `lines[i]` within the gap, and how far, px.
fn first_hit(lines: &[FittedLine], i: usize, e: usize, opts: &GapOptions) -> Option<(f64, Hit)> {
    let a = &lines[i];
    let q = end_of(a, e);
    let out = (q - end_of(a, 1 - e)).normalize_or_zero();
    let ahead = |p: DVec2| (p - q).dot(out);
    let mut best: Option<(f64, Hit)> = None;
    let mut take = |s: f64, hit: Hit| {
        if s > 0.0 && s <= opts.max_gap_px && best.is_none_or(|(b, _)| s < b) {
            best = Some((s, hit));
        }
    };
    for (j, l) in lines.iter().enumerate().filter(|&(j, _)| j != i) {
        if l.axis == a.axis && collinear(a, l, opts.collinear_px) {
            let near = ahead(l.from_px).min(ahead(l.to_px));
            if near > 0.0 {
                // A piece starting at a crossing is the edge's own continuation: it wins over
                // the crossing (a short piece's direction may miss the corner by a few px), and
                // the edge passes through there (Chapter V's two collinear "T", a staircase).
                take(
                    (near - opts.join_radius_px).max(f64::MIN_POSITIVE),
                    Hit::Piece(j),
                );
            }
        } else if let Some(p) = crossing(a, l) {
            if within_extent(l, p, opts.join_radius_px) {
                take(ahead(p), Hit::Crossing(p));
            }
        }
    }
    best
}

/// One line through both pieces: the longer piece's direction through their support-weighted
/// centroid, spanning both.
fn join_pieces(a: &FittedLine, b: &FittedLine) -> FittedLine {
    let (wa, wb) = (a.support.max(1) as f64, b.support.max(1) as f64);
    let centroid = (a.centroid_px * wa + b.centroid_px * wb) / (wa + wb);
    let long = if a.length_px() >= b.length_px() { a } else { b };
    let direction = if long.direction.dot(a.direction) < 0.0 {
        -long.direction
    } else {
        long.direction
    };
    let ts = [a.from_px, a.to_px, b.from_px, b.to_px].map(|p| direction.dot(p - centroid));
    let lo = ts.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = ts.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    FittedLine {
        axis: a.axis,
        centroid_px: centroid,
        direction,
        from_px: centroid + direction * lo,
        to_px: centroid + direction * hi,
        support: a.support + b.support,
        rms_px: ((a.rms_px.powi(2) * wa + b.rms_px.powi(2) * wb) / (wa + wb)).sqrt(),
    }
}

/// Carries every free end of `lines` on to the first line ahead of it (see the module doc):
/// collinear pieces of one edge become one line, an end stopping short of a crossing line is
/// moved to the crossing. Deterministic (lines in order, ends in order); lines without free
/// ends are returned as they are.
pub fn bridge_free_ends(lines: &[FittedLine], opts: &GapOptions) -> Vec<FittedLine> {
    let mut out: Vec<FittedLine> = lines.to_vec();
    // Each pass closes one gap at most per line; a joined line may have a new free end.
    for _ in 0..lines.len().max(1) {
        let mut changed = false;
        let mut i = 0;
        while i < out.len() {
            for e in 0..2 {
                if end_meets_a_line(&out, i, e, opts) {
                    continue;
                }
                match first_hit(&out, i, e, opts) {
                    Some((_, Hit::Piece(j))) => {
                        out[i] = join_pieces(&out[i], &out[j]);
                        out.remove(j);
                        changed = true;
                        break;
                    }
                    Some((_, Hit::Crossing(p))) => {
                        let a = &mut out[i];
                        let p = a.centroid_px + a.direction * a.along_px(p);
                        if e == 0 {
                            a.from_px = p;
                        } else {
                            a.to_px = p;
                        }
                        changed = true;
                    }
                    None => {}
                }
            }
            i += 1;
        }
        if !changed {
            break;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::drawing::EdgeAxis;

    use crate::vision::lines::test_segment as seg;

    const R: DVec2 = DVec2::new(0.866, 0.5);

    /// A vertical edge whose lower part a contact shadow hid: its upper piece ends in the open
    /// 60 px above the lower piece, which meets the floor line in an "L".
    fn shadowed_edge() -> Vec<FittedLine> {
        let foot = DVec2::new(100.0, 100.0);
        vec![
            seg(1, foot, foot + R * 80.0),
            seg(0, foot + DVec2::Y * 2.0, foot + DVec2::Y * 30.0),
            seg(0, foot + DVec2::Y * 90.0, foot + DVec2::Y * 140.0),
        ]
    }

    #[test]
    fn a_vertical_edge_broken_by_a_shadow_is_one_line_again() {
        let out = bridge_free_ends(&shadowed_edge(), &GapOptions::default());
        assert_eq!(out.len(), 2, "{out:?}");
        let v = out
            .iter()
            .find(|l| l.axis == EdgeAxis::BLOCK_AXES[0])
            .unwrap();
        assert!(v.from_px.distance(DVec2::new(100.0, 102.0)) < 1e-9, "{v:?}");
        assert!(v.to_px.distance(DVec2::new(100.0, 240.0)) < 1e-9, "{v:?}");
    }

    #[test]
    fn a_gap_longer_than_the_limit_stays_open() {
        let opts = GapOptions {
            max_gap_px: 50.0,
            ..GapOptions::default()
        };
        assert_eq!(bridge_free_ends(&shadowed_edge(), &opts), shadowed_edge());
    }

    #[test]
    fn a_free_end_short_of_a_crossing_line_reaches_it() {
        let foot = DVec2::new(100.0, 100.0);
        let lines = vec![
            seg(1, foot - R * 40.0, foot + R * 80.0),
            seg(0, foot + DVec2::Y * 25.0, foot + DVec2::Y * 100.0),
        ];
        let out = bridge_free_ends(&lines, &GapOptions::default());
        assert!(out[1].from_px.distance(foot) < 1e-9, "{:?}", out[1]);
        assert_eq!(out[1].to_px, lines[1].to_px);
    }

    #[test]
    fn a_shadow_boundary_fading_out_on_an_open_face_stays_free() {
        // Nothing lies ahead of either end: a free line is left as it is.
        let lines = vec![
            seg(1, DVec2::new(0.0, 0.0), DVec2::new(86.6, 50.0)),
            seg(2, DVec2::new(300.0, 300.0), DVec2::new(260.0, 323.0)),
        ];
        assert_eq!(bridge_free_ends(&lines, &GapOptions::default()), lines);
    }

    #[test]
    fn ends_that_meet_a_line_are_not_moved() {
        // A "T": the stem's foot meets the bar, its top is free with nothing ahead.
        let foot = DVec2::new(100.0, 100.0);
        let lines = vec![
            seg(1, foot - R * 40.0, foot + R * 80.0),
            seg(0, foot + DVec2::Y * 3.0, foot + DVec2::Y * 60.0),
        ];
        assert_eq!(bridge_free_ends(&lines, &GapOptions::default()), lines);
    }
}
