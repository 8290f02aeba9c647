//! Measuring the front end against ground truth (docs/vision.md "Vision front end"):
//! vertices are matched one to one to the exact drawing's points within a distance, and the
//! matched pairs' six-bit codes compared; fitted lines are compared with the exact lines' angles.

use super::lines::FittedLine;
use crate::drawing::LineDrawing;
use crate::geom::distance_to_segment_px;

/// Tolerances of [`match_vertices_with_tolerances`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MatchTolerances {
    /// A found vertex matches a true point at most this far away, px. Default 2.0 (docs/vision.md "Vision front end").
    pub distance_px: f64,
    /// A fitted line is compared with a true line when both make at most this angle, degrees,
    /// and the fitted line's midpoint lies within `distance_px` of the true segment. Default 10.
    pub angle_deg: f64,
}

impl Default for MatchTolerances {
    fn default() -> Self {
        MatchTolerances {
            distance_px: 2.0,
            angle_deg: 10.0,
        }
    }
}

/// The result of matching found vertices to true points.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct VertexMatch {
    /// Matched pairs `(found index, true index)`, one to one.
    pub pairs: Vec<(usize, usize)>,
    /// Number of found vertices.
    pub found: usize,
    /// Number of true points.
    pub truth: usize,
    /// Matched pairs whose six-bit codes are equal.
    pub codes_equal: usize,
    /// Matched pairs whose thesis junction classes ("Y", "T", "L", "other") are equal.
    pub classes_equal: usize,
    /// Distances of the matched pairs, px.
    pub distances_px: Vec<f64>,
}

impl VertexMatch {
    /// Matched / found (1 when nothing was found and nothing was there).
    pub fn precision(&self) -> f64 {
        ratio(self.pairs.len(), self.found)
    }
    /// Matched / true points.
    pub fn recall(&self) -> f64 {
        ratio(self.pairs.len(), self.truth)
    }
    /// Equal codes / matched pairs.
    pub fn code_accuracy(&self) -> f64 {
        ratio(self.codes_equal, self.pairs.len())
    }
}

fn ratio(a: usize, b: usize) -> f64 {
    if b == 0 {
        1.0
    } else {
        a as f64 / b as f64
    }
}

/// [`match_vertices_with_tolerances`] with [`MatchTolerances::default`] (2 px).
pub fn match_vertices(found: &LineDrawing, truth: &LineDrawing) -> VertexMatch {
    match_vertices_with_tolerances(found, truth, &MatchTolerances::default())
}

/// Matches `found` points to `truth` points one to one, closest pairs first, within
/// `tol.distance_px`; counts equal six-bit codes and junction classes among the pairs.
pub fn match_vertices_with_tolerances(
    found: &LineDrawing,
    truth: &LineDrawing,
    tol: &MatchTolerances,
) -> VertexMatch {
    let mut near: Vec<(f64, usize, usize)> = Vec::new();
    for (i, p) in found.points.iter().enumerate() {
        for (j, q) in truth.points.iter().enumerate() {
            let d = p.distance(*q);
            if d <= tol.distance_px {
                near.push((d, i, j));
            }
        }
    }
    near.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
    let mut used_f = vec![false; found.points.len()];
    let mut used_t = vec![false; truth.points.len()];
    let mut m = VertexMatch {
        found: found.points.len(),
        truth: truth.points.len(),
        ..Default::default()
    };
    for (d, i, j) in near {
        if used_f[i] || used_t[j] {
            continue;
        }
        used_f[i] = true;
        used_t[j] = true;
        m.pairs.push((i, j));
        m.distances_px.push(d);
        if found.codes.get(i) == truth.codes.get(j) {
            m.codes_equal += 1;
        }
        let class = |dr: &LineDrawing, k: usize| dr.junctions.get(k).map(|x| x.thesis_class());
        if class(found, i) == class(truth, j) {
            m.classes_equal += 1;
        }
    }
    m
}

/// Angle error in degrees of every fitted line that has a true counterpart (a true line within
/// `tol.angle_deg` whose segment passes within `tol.distance_px` of the fitted line's midpoint).
pub fn line_angle_errors_deg(
    fitted: &[FittedLine],
    truth: &LineDrawing,
    tol: &MatchTolerances,
) -> Vec<f64> {
    let mut errors = Vec::new();
    for f in fitted {
        let mid = (f.from_px + f.to_px) / 2.0;
        let mut best: Option<(f64, f64)> = None;
        for &[a, b] in &truth.lines {
            let (p, q) = (truth.points[a], truth.points[b]);
            let d = q - p;
            if d.length_squared() == 0.0 {
                continue;
            }
            let dist = distance_to_segment_px(mid, p, q);
            let cos = (d.normalize().dot(f.direction)).abs().min(1.0);
            let angle = cos.acos().to_degrees();
            if dist <= tol.distance_px
                && angle <= tol.angle_deg
                && best.is_none_or(|(bd, _)| dist < bd)
            {
                best = Some((dist, angle));
            }
        }
        if let Some((_, a)) = best {
            errors.push(a);
        }
    }
    errors
}

#[cfg(test)]
mod tests {
    use super::*;

    fn drawing(points: &[[f64; 2]], lines: &[[usize; 2]]) -> LineDrawing {
        LineDrawing::from_arrays(points, lines)
    }

    #[test]
    fn matching_is_one_to_one_within_two_pixels() {
        let truth = drawing(&[[0.0, 0.0], [0.0, 50.0], [43.3, 75.0]], &[[0, 1], [1, 2]]);
        let found = drawing(
            &[[0.5, 0.5], [0.0, 51.5], [1.0, 0.0], [60.0, 60.0]],
            &[[0, 1], [2, 3]],
        );
        let m = match_vertices(&found, &truth);
        assert_eq!(m.pairs, vec![(0, 0), (1, 1)]);
        assert!((m.precision() - 0.5).abs() < 1e-12);
        assert!((m.recall() - 2.0 / 3.0).abs() < 1e-12);
        // Point 0 is "up" in both; point 1 has "down" only in found, "down + right-up" in truth.
        assert_eq!(m.codes_equal, 1);
        let empty = match_vertices(&LineDrawing::default(), &LineDrawing::default());
        assert_eq!((empty.precision(), empty.recall()), (1.0, 1.0));
    }
}
