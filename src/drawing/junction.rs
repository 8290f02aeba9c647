//! Junction classes of a point in a line drawing: the thesis's "Y" and collinear "T"
//! (Chapter V, Figure 5.1) and Kanade's catalog (L, arrow, fork, T, K, X, psi; Chapter II).

use crate::geom::DVec2;
use serde::{Deserialize, Serialize};

/// Two lines leaving a point are collinear (opposite) within this many degrees of 180: the two
/// fitted pieces of an edge split at a collinear T (Chapter V, Figure 5.1) disagree by less,
/// other lines at a corner by 60° (docs/vision.md "Tolerances").
pub const COLLINEAR_TOL_DEG: f64 = 3.0;

/// The class of a junction by the number and arrangement of its lines.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Junction {
    /// One line ends here.
    #[serde(rename = "end")]
    End,
    /// Two lines that are not collinear.
    #[serde(rename = "L")]
    L,
    /// Two collinear lines (a line that changes kind here).
    #[serde(rename = "straight")]
    Straight,
    /// Three lines, every angle between neighbours under 180 degrees (the thesis's "Y").
    #[serde(rename = "fork")]
    Fork,
    /// Three lines within a half-plane (also a "Y" in the thesis's count).
    #[serde(rename = "arrow")]
    Arrow,
    /// Three lines, two of them collinear (the thesis's collinear "T").
    #[serde(rename = "T")]
    T,
    /// Four lines, one collinear pair, the other two on the same side of it.
    #[serde(rename = "K")]
    K,
    /// Four lines, one collinear pair, the other two on opposite sides.
    #[serde(rename = "psi")]
    Psi,
    /// Four lines in two collinear pairs.
    #[serde(rename = "X")]
    X,
    /// Anything else (no lines, or five and more).
    #[serde(rename = "other")]
    Other,
}

/// The thesis's coarse classes (Chapter V, Figure 5.1): the "Y" and collinear "T" vertices the
/// parallelogram search starts from, the "L" corners, and everything else.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum ThesisClass {
    /// Fork or arrow.
    #[serde(rename = "Y")]
    Y,
    /// Three lines, two collinear.
    #[serde(rename = "T")]
    T,
    /// Two lines that are not collinear.
    #[serde(rename = "L")]
    L,
    /// Any other junction.
    #[serde(rename = "other")]
    Other,
}

impl ThesisClass {
    /// `Y`, `T`, `L` or `other`, as the thesis writes them.
    pub fn as_str(self) -> &'static str {
        match self {
            ThesisClass::Y => "Y",
            ThesisClass::T => "T",
            ThesisClass::L => "L",
            ThesisClass::Other => "other",
        }
    }
}

impl Junction {
    /// The thesis's coarse class: "Y" (fork or arrow), "T", "L", or other.
    pub fn thesis_class(self) -> ThesisClass {
        match self {
            Junction::Fork | Junction::Arrow => ThesisClass::Y,
            Junction::T => ThesisClass::T,
            Junction::L => ThesisClass::L,
            _ => ThesisClass::Other,
        }
    }
}

fn angle_deg(v: DVec2) -> f64 {
    v.y.atan2(v.x).to_degrees().rem_euclid(360.0)
}

fn collinear(a: DVec2, b: DVec2) -> bool {
    a.angle_to(b).abs().to_degrees() >= 180.0 - COLLINEAR_TOL_DEG
}

/// Classifies a junction from the picture vectors of the lines leaving it.
pub fn classify_junction(vectors: &[DVec2]) -> Junction {
    match vectors.len() {
        1 => Junction::End,
        2 if collinear(vectors[0], vectors[1]) => Junction::Straight,
        2 => Junction::L,
        3 => classify_three(vectors),
        4 => classify_four(vectors),
        _ => Junction::Other,
    }
}

fn classify_three(v: &[DVec2]) -> Junction {
    let pairs = [(0, 1), (0, 2), (1, 2)];
    if pairs.iter().any(|&(i, j)| collinear(v[i], v[j])) {
        return Junction::T;
    }
    let mut a: Vec<f64> = v.iter().map(|x| angle_deg(*x)).collect();
    a.sort_by(f64::total_cmp);
    let gaps = [a[1] - a[0], a[2] - a[1], 360.0 - (a[2] - a[0])];
    if gaps.iter().any(|g| *g > 180.0) {
        Junction::Arrow
    } else {
        Junction::Fork
    }
}

fn classify_four(v: &[DVec2]) -> Junction {
    let mut pairs = Vec::new();
    for i in 0..4 {
        for j in i + 1..4 {
            if collinear(v[i], v[j]) {
                pairs.push((i, j));
            }
        }
    }
    match pairs.len() {
        0 => Junction::Other,
        1 => {
            let (i, j) = pairs[0];
            let rest: Vec<usize> = (0..4).filter(|k| *k != i && *k != j).collect();
            let side = |k: usize| v[i].perp_dot(v[k]).signum();
            if side(rest[0]) == side(rest[1]) {
                Junction::K
            } else {
                Junction::Psi
            }
        }
        _ => Junction::X,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64) -> DVec2 {
        DVec2::new(x, y)
    }

    #[test]
    fn classes() {
        assert_eq!(classify_junction(&[v(1.0, 0.5)]), Junction::End);
        assert_eq!(classify_junction(&[v(1.0, 0.5), v(-1.0, 0.5)]), Junction::L);
        assert_eq!(
            classify_junction(&[v(1.0, 0.5), v(-1.0, -0.5)]),
            Junction::Straight
        );
        assert_eq!(
            classify_junction(&[v(0.0, -1.0), v(0.87, 0.5), v(-0.87, 0.5)]),
            Junction::Fork
        );
        assert_eq!(
            classify_junction(&[v(0.0, 1.0), v(-0.87, -0.5), v(0.87, -0.5)]),
            Junction::Fork
        );
        assert_eq!(
            classify_junction(&[v(0.0, 1.0), v(-0.87, 0.5), v(0.87, 0.5)]),
            Junction::Arrow
        );
        assert_eq!(
            classify_junction(&[v(0.87, 0.5), v(-0.87, -0.5), v(0.0, 1.0)]),
            Junction::T
        );
        assert_eq!(Junction::T.thesis_class(), ThesisClass::T);
        assert_eq!(Junction::Arrow.thesis_class(), ThesisClass::Y);
        assert_eq!(ThesisClass::Y.as_str(), "Y");
        let x = [v(1.0, 0.0), v(-1.0, 0.0), v(0.0, 1.0), v(0.0, -1.0)];
        assert_eq!(classify_junction(&x), Junction::X);
        let k = [v(0.0, 1.0), v(0.0, -1.0), v(1.0, 0.5), v(1.0, -0.5)];
        assert_eq!(classify_junction(&k), Junction::K);
        let psi = [v(0.0, 1.0), v(0.0, -1.0), v(1.0, 0.5), v(-1.0, 0.5)];
        assert_eq!(classify_junction(&psi), Junction::Psi);
    }
}
