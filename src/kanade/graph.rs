//! The drawing as a planar graph: at every point, its lines in the canonical order that the
//! junction catalogs are written in, and the regions (faces of the planar graph) that the
//! surface connection graph (Chapter II) and the outer-boundary constraint (Appendix A step 2)
//! need.

use super::KanadeError;
use crate::drawing::{classify_junction, Junction, LineDrawing};
use crate::geom::DVec2;

/// One end of a line at a junction.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LineEnd {
    /// Index into `LineDrawing::lines`.
    pub line: usize,
    /// `true` when the junction is the line's first point `lines[line][0]`.
    pub at_start: bool,
}

/// A point of the drawing with its junction class (from geometry, `drawing::classify_junction`)
/// and its lines in canonical order:
/// - `L`: the second line is clockwise from the first through the angle under 180°;
/// - arrow: the two barbs, then the shaft; turning counterclockwise, barb 1 → shaft → barb 2;
/// - fork: clockwise;
/// - `T`: the bar's two halves, then the stem; turning counterclockwise, bar 1 → stem → bar 2;
/// - `K`: counterclockwise from the half of the collinear pair that has both others before its
///   partner; five and more lines: counterclockwise from the line after the widest gap; psi,
///   `X`, straight and the rest: counterclockwise from the lowest angle.
///
/// With these orders PAIP's tables (ch. 17) read as written: its cube's free-floating labelling
/// is the one whose arrows run clockwise around the outline.
#[derive(Debug, Clone, PartialEq)]
pub struct JunctionSite {
    /// Index into `LineDrawing::points`.
    pub point: usize,
    /// Junction class from the picture geometry.
    pub junction: Junction,
    /// Incident lines in canonical order.
    pub ends: Vec<LineEnd>,
}

/// A region of the picture: a face of the planar graph, traced with the region on the left of
/// each directed line (bounded regions counterclockwise).
#[derive(Debug, Clone, PartialEq)]
pub struct Region {
    /// The boundary walk as (line, walked from its first point to its second).
    pub walk: Vec<LineEnd>,
    /// Signed area in px² (positive for bounded regions; zero or negative for the outside of a
    /// connected piece of the drawing).
    pub signed_area_px2: f64,
}

impl Region {
    /// Whether this is the outside of a connected piece of the drawing (Appendix A step 2's
    /// "outer boundary").
    pub fn is_outside(&self) -> bool {
        self.signed_area_px2 <= 0.0
    }
}

/// Checks the drawing's geometry ([`LineDrawing::check_geometry`], the one validation of a
/// drawing; the labelling computes junctions from the points, so codes may be absent) and that
/// no two lines join the same pair of points (in either direction: a junction would count the
/// line twice).
pub fn validate(d: &LineDrawing) -> Result<(), KanadeError> {
    d.check_geometry()?;
    let mut seen = std::collections::HashMap::with_capacity(d.lines.len());
    for (i, &[a, b]) in d.lines.iter().enumerate() {
        if let Some(&first) = seen.get(&(a.min(b), a.max(b))) {
            return Err(KanadeError::DuplicateLine { first, second: i });
        }
        seen.insert((a.min(b), a.max(b)), i);
    }
    Ok(())
}

fn out_vector(d: &LineDrawing, e: LineEnd) -> DVec2 {
    let [a, b] = d.lines[e.line];
    if e.at_start {
        d.points[b] - d.points[a]
    } else {
        d.points[a] - d.points[b]
    }
}

fn angle(v: DVec2) -> f64 {
    v.y.atan2(v.x).rem_euclid(std::f64::consts::TAU)
}

/// Ends of every point sorted counterclockwise by angle (ties by line index).
fn ends_ccw(d: &LineDrawing) -> Vec<Vec<LineEnd>> {
    let mut ends = vec![Vec::new(); d.points.len()];
    for (line, &[a, b]) in d.lines.iter().enumerate() {
        ends[a].push(LineEnd {
            line,
            at_start: true,
        });
        ends[b].push(LineEnd {
            line,
            at_start: false,
        });
    }
    for list in &mut ends {
        list.sort_by(|x, y| {
            angle(out_vector(d, *x))
                .total_cmp(&angle(out_vector(d, *y)))
                .then(x.line.cmp(&y.line))
        });
    }
    ends
}

/// The index (in a counterclockwise list of three or four vectors) of the member of the most
/// nearly opposite pair from which the other lines come before its partner, turning
/// counterclockwise (used for T and K).
fn opposite_pair_start(v: &[DVec2]) -> usize {
    let n = v.len();
    let mut best = (0, 1, f64::NEG_INFINITY);
    for i in 0..n {
        for j in i + 1..n {
            let a = v[i].angle_to(v[j]).abs();
            if a > best.2 {
                best = (i, j, a);
            }
        }
    }
    let (i, j, _) = best;
    // Counterclockwise from i, the lines strictly between i and j are j - i - 1; the other
    // lines lie on the other side.
    let between = j - i - 1;
    let others = n - 2 - between;
    if between >= others {
        i
    } else {
        j
    }
}

/// The index (in a counterclockwise list) of the line that follows the widest angle between
/// neighbours, the first such on a tie.
fn after_largest_gap(v: &[DVec2]) -> usize {
    let n = v.len();
    let gap = |k: usize| {
        let (a, b) = (angle(v[(k + n - 1) % n]), angle(v[k]));
        (b - a).rem_euclid(std::f64::consts::TAU)
    };
    (0..n).fold(0, |best, k| if gap(k) > gap(best) { k } else { best })
}

fn canonical(junction: Junction, ccw: &[LineEnd], v: &[DVec2]) -> Vec<LineEnd> {
    let rot = |start: usize| -> Vec<LineEnd> {
        (0..ccw.len())
            .map(|k| ccw[(start + k) % ccw.len()])
            .collect()
    };
    match junction {
        Junction::L => {
            if v[0].perp_dot(v[1]) > 0.0 {
                vec![ccw[1], ccw[0]]
            } else {
                ccw.to_vec()
            }
        }
        Junction::Arrow => {
            // The gap over 180 degrees ends at the first barb (counterclockwise).
            let first = (0..3)
                .find(|&k| v[(k + 2) % 3].perp_dot(v[k]) < 0.0)
                .unwrap_or(0);
            vec![ccw[first], ccw[(first + 2) % 3], ccw[(first + 1) % 3]]
        }
        Junction::Fork => vec![ccw[0], ccw[2], ccw[1]],
        Junction::T => {
            let r = rot(opposite_pair_start(v));
            vec![r[0], r[2], r[1]]
        }
        Junction::K => rot(opposite_pair_start(v)),
        Junction::Other if ccw.len() > 4 => rot(after_largest_gap(v)),
        _ => ccw.to_vec(),
    }
}

/// Every point's junction site, with lines in canonical order. The drawing must be valid
/// ([`validate`]).
pub fn junction_sites(d: &LineDrawing) -> Vec<JunctionSite> {
    ends_ccw(d)
        .into_iter()
        .enumerate()
        .map(|(point, ccw)| {
            let v: Vec<DVec2> = ccw.iter().map(|e| out_vector(d, *e)).collect();
            let junction = if ccw.is_empty() {
                Junction::Other
            } else {
                classify_junction(&v)
            };
            JunctionSite {
                point,
                junction,
                ends: canonical(junction, &ccw, &v),
            }
        })
        .collect()
}

/// Half-edge `2 * line + (0 if walked a → b else 1)`.
fn half_edge(e: LineEnd) -> usize {
    2 * e.line + usize::from(!e.at_start)
}

/// The regions of the drawing (faces of the planar graph), each traced with the region on the
/// left; every directed line lies on exactly one region. The drawing must be valid.
pub fn regions(d: &LineDrawing) -> Vec<Region> {
    let ccw = ends_ccw(d);
    // position of each outgoing half-edge in its point's counterclockwise list
    let mut pos = vec![(0usize, 0usize); 2 * d.lines.len()];
    for (p, list) in ccw.iter().enumerate() {
        for (k, e) in list.iter().enumerate() {
            pos[half_edge(*e)] = (p, k);
        }
    }
    let mut seen = vec![false; 2 * d.lines.len()];
    let mut out = Vec::new();
    for start in 0..seen.len() {
        if seen[start] {
            continue;
        }
        let mut walk = Vec::new();
        let mut h = start;
        while !seen[h] {
            seen[h] = true;
            let e = LineEnd {
                line: h / 2,
                at_start: h % 2 == 0,
            };
            walk.push(e);
            // At the far end, the next line clockwise from the way back.
            let (p, k) = pos[h ^ 1];
            let list = &ccw[p];
            h = half_edge(list[(k + list.len() - 1) % list.len()]);
        }
        let signed_area_px2 = shoelace(d, &walk);
        out.push(Region {
            walk,
            signed_area_px2,
        });
    }
    out
}

fn shoelace(d: &LineDrawing, walk: &[LineEnd]) -> f64 {
    let mut s = 0.0;
    for e in walk {
        let [a, b] = d.lines[e.line];
        let (p, q) = if e.at_start { (a, b) } else { (b, a) };
        s += d.points[p].perp_dot(d.points[q]);
    }
    0.5 * s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::drawing::DrawingError;

    fn drawing(points: &[[f64; 2]], lines: &[[usize; 2]]) -> LineDrawing {
        LineDrawing {
            points: points.iter().map(|p| DVec2::from_array(*p)).collect(),
            lines: lines.to_vec(),
            ..Default::default()
        }
    }

    #[test]
    fn a_square_has_one_inside_and_one_outside() {
        let d = drawing(
            &[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
            &[[0, 1], [1, 2], [2, 3], [3, 0]],
        );
        let r = regions(&d);
        assert_eq!(r.len(), 2);
        assert_eq!(r.iter().filter(|x| x.is_outside()).count(), 1);
        let inside = r.iter().find(|x| !x.is_outside()).unwrap();
        assert!((inside.signed_area_px2 - 1.0).abs() < 1e-12);
    }

    #[test]
    fn canonical_orders_follow_the_documented_turns() {
        // L at the origin: lines to (1, 0) and (0, 1); (1, 0) is clockwise from (0, 1).
        let d = drawing(&[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]], &[[0, 1], [0, 2]]);
        let s = &junction_sites(&d)[0];
        assert_eq!(s.junction, Junction::L);
        assert_eq!((s.ends[0].line, s.ends[1].line), (1, 0));
        // T: bar along x, stem up; stem is counterclockwise from the bar half pointing +x.
        let d = drawing(
            &[[0.0, 0.0], [-1.0, 0.0], [1.0, 0.0], [0.0, 1.0]],
            &[[0, 1], [0, 2], [0, 3]],
        );
        let s = &junction_sites(&d)[0];
        assert_eq!(s.junction, Junction::T);
        let order: Vec<usize> = s.ends.iter().map(|e| e.line).collect();
        assert_eq!(order, vec![1, 0, 2]);
        // Arrow opening downwards: barbs at 210 and 330 degrees, shaft at 270.
        let c = 3f64.sqrt() / 2.0;
        let d = drawing(
            &[[0.0, 0.0], [-c, -0.5], [0.0, -1.0], [c, -0.5]],
            &[[0, 1], [0, 2], [0, 3]],
        );
        let s = &junction_sites(&d)[0];
        assert_eq!(s.junction, Junction::Arrow);
        let order: Vec<usize> = s.ends.iter().map(|e| e.line).collect();
        assert_eq!(order, vec![0, 2, 1]);
    }

    #[test]
    fn broken_indices_are_errors_not_panics() {
        let d = drawing(&[[0.0, 0.0]], &[[0, 3]]);
        assert!(matches!(
            validate(&d),
            Err(KanadeError::Drawing(DrawingError::BadLine { .. }))
        ));
        let d = drawing(&[[0.0, 0.0], [0.0, 0.0]], &[[0, 1]]);
        assert!(matches!(
            validate(&d),
            Err(KanadeError::Drawing(DrawingError::ZeroLength { .. }))
        ));
    }

    /// Regression: a line given twice, or once reversed, made its end points four-line
    /// junctions (each copy counted); the labeller refuses it, naming both lines.
    #[test]
    fn a_line_given_twice_is_refused() {
        let points = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
        for repeat in [[0, 1], [1, 0]] {
            let d = drawing(&points, &[[0, 1], [0, 2], repeat]);
            assert_eq!(
                validate(&d),
                Err(KanadeError::DuplicateLine {
                    first: 0,
                    second: 2
                })
            );
        }
        assert!(validate(&drawing(&points, &[[0, 1], [0, 2], [1, 2]])).is_ok());
    }
}
