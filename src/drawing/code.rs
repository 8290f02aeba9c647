//! The six-bit code of Chapter IV: which of the six picture directions (up, down, left-up,
//! left-down, right-up, right-down) have an edge at a vertex. The left and right neighbours of
//! the 3x3 grid (pixels 4 and 6 of Figure 4.3) are not directions (Chapter V).

use crate::geom::DVec2;
use serde::{Deserialize, Serialize};

/// A line within this many degrees of vertical is "up" or "down": every vertical block edge,
/// also leaning in a 30° perspective view (up to 14°), and 45° from the horizontal edges
/// (docs/vision.md "Tolerances").
pub const VERTICAL_TOL_DEG: f64 = 15.0;
/// A line within this many degrees of horizontal falls in no direction: flagged, not guessed (a
/// face seen edge-on; about the angle error of the shortest edge, docs/vision.md "Tolerances").
pub const HORIZONTAL_TOL_DEG: f64 = 2.0;

/// One of the six edge directions at a vertex, numbered by its bit (Chapter IV).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Direction {
    /// bit 0: vertical up.
    Up = 0,
    /// bit 1: vertical down.
    Down = 1,
    /// bit 2: left up.
    LeftUp = 2,
    /// bit 3: left down.
    LeftDown = 3,
    /// bit 4: right up.
    RightUp = 4,
    /// bit 5: right down.
    RightDown = 5,
}

impl Direction {
    /// All six, in bit order.
    pub const ALL: [Direction; 6] = [
        Direction::Up,
        Direction::Down,
        Direction::LeftUp,
        Direction::LeftDown,
        Direction::RightUp,
        Direction::RightDown,
    ];

    /// The bit's value, `1 << bit`.
    pub fn mask(self) -> u8 {
        1 << self as u8
    }

    /// The direction pointing the other way along the same line.
    pub fn opposite(self) -> Direction {
        match self {
            Direction::Up => Direction::Down,
            Direction::Down => Direction::Up,
            Direction::LeftUp => Direction::RightDown,
            Direction::RightDown => Direction::LeftUp,
            Direction::LeftDown => Direction::RightUp,
            Direction::RightUp => Direction::LeftDown,
        }
    }

    /// Classifies a picture vector (px, y up) leaving a vertex: within
    /// [`VERTICAL_TOL_DEG`] of vertical it is up or down; within [`HORIZONTAL_TOL_DEG`] of
    /// horizontal it is `None`; otherwise its quadrant decides.
    pub fn from_picture_vector(v: DVec2) -> Option<Direction> {
        if v.length_squared() == 0.0 || !v.is_finite() {
            return None;
        }
        let from_vertical = v.x.abs().atan2(v.y.abs()).to_degrees();
        if from_vertical <= VERTICAL_TOL_DEG {
            return Some(if v.y > 0.0 {
                Direction::Up
            } else {
                Direction::Down
            });
        }
        if 90.0 - from_vertical <= HORIZONTAL_TOL_DEG {
            return None;
        }
        Some(match (v.x > 0.0, v.y > 0.0) {
            (true, true) => Direction::RightUp,
            (true, false) => Direction::RightDown,
            (false, true) => Direction::LeftUp,
            (false, false) => Direction::LeftDown,
        })
    }

    /// Short thesis name: `up`, `dn`, `lu`, `ld`, `ru`, `rd` (Chapter IV, Figure 4.4).
    pub fn slot(self) -> &'static str {
        ["up", "dn", "lu", "ld", "ru", "rd"][self as usize]
    }
}

/// The six-bit code of a vertex (Chapter IV): bit `d` set when an edge leaves in direction `d`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(transparent)]
pub struct SixBitCode(pub u8);

impl SixBitCode {
    /// The code with `d`'s bit set.
    pub fn with(self, d: Direction) -> SixBitCode {
        SixBitCode(self.0 | d.mask())
    }

    /// Whether an edge leaves in direction `d`.
    pub fn has(self, d: Direction) -> bool {
        self.0 & d.mask() != 0
    }

    /// Number of directions present.
    pub fn count(self) -> u32 {
        self.0.count_ones()
    }

    /// The directions present, in bit order.
    pub fn directions(self) -> impl Iterator<Item = Direction> {
        Direction::ALL.into_iter().filter(move |d| self.has(*d))
    }

    /// The code of a vertex whose edges leave along `vectors` (px, y up); vectors in no
    /// direction contribute nothing.
    pub fn from_picture_vectors(vectors: &[DVec2]) -> SixBitCode {
        vectors
            .iter()
            .filter_map(|v| Direction::from_picture_vector(*v))
            .fold(SixBitCode::default(), SixBitCode::with)
    }
}

impl std::fmt::Display for SixBitCode {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let names: Vec<&str> = self.directions().map(Direction::slot).collect();
        write!(f, "{} ({})", self.0, names.join("+"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chapter_iv_worked_example_is_27() {
        // "if ru = 1, ld = 1, down = 1, up = 1, rd = 0, lu = 0 ... = 27".
        let c = [
            Direction::RightUp,
            Direction::LeftDown,
            Direction::Down,
            Direction::Up,
        ]
        .into_iter()
        .fold(SixBitCode::default(), SixBitCode::with);
        assert_eq!(c.0, 27);
        assert_eq!(c.to_string(), "27 (up+dn+ld+ru)");
    }

    #[test]
    fn directions_by_quadrant_and_tolerance() {
        let d = |x: f64, y: f64| Direction::from_picture_vector(DVec2::new(x, y));
        assert_eq!(d(0.1, 1.0), Some(Direction::Up));
        assert_eq!(d(0.0, -1.0), Some(Direction::Down));
        assert_eq!(d(-1.0, 0.577), Some(Direction::LeftUp));
        assert_eq!(d(1.0, -0.577), Some(Direction::RightDown));
        assert_eq!(d(1.0, 0.01), None);
        assert_eq!(d(0.0, 0.0), None);
        for dir in Direction::ALL {
            assert_eq!(dir.opposite().opposite(), dir);
        }
    }
}
