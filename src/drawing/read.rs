//! Reading a line drawing from JSON, checked: a drawing that names a missing point, holds a
//! coordinate that is not finite, a six-bit code outside 0..=63 (Chapter IV has six bits), or
//! parallel arrays of unequal length is refused with the reason, never half-read. `codes` and
//! `junctions` may be left out (a hand-made `{"points", "lines"}` drawing); they are then
//! computed from the geometry. Fields this crate does not know are ignored, so drawings from
//! other tools read too.

use super::{EdgeRef, Junction, LineDrawing, LineKind, SixBitCode};
use crate::geom::DVec2;
use serde::Deserialize;

/// Why a drawing was refused.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum DrawingError {
    /// Not JSON, or JSON without the drawing's fields.
    #[error("not a line drawing: {0} (expected {{\"points\": [[x, y], ...], \"lines\": [[i, j], ...]}}, docs/formats.md \"The exact line drawing\")")]
    Format(String),
    /// A point with a NaN or infinite coordinate.
    #[error("point {index} has a coordinate that is not finite")]
    NotFinite {
        /// The point's index.
        index: usize,
    },
    /// A point farther than [`MAX_POINT_COORD_PX`] from the picture's origin: no picture is
    /// that large, and such values overflow when written (`null` in the JSON).
    #[error("point {index} has a coordinate beyond +/-{max} px, outside any picture", max = MAX_POINT_COORD_PX)]
    OutOfRange {
        /// The point's index.
        index: usize,
    },
    /// A line naming a point that does not exist, or a line from a point to itself.
    #[error("line {index} joins points {a} and {b}, but the drawing has {points} points (indices 0..{points}, two different ones)")]
    BadLine {
        /// The line's index.
        index: usize,
        /// Its first point.
        a: usize,
        /// Its second point.
        b: usize,
        /// Number of points.
        points: usize,
    },
    /// A six-bit code with bits above bit 5.
    #[error("point {index} has six-bit code {code}, outside 0..=63 (Chapter IV: six bits)")]
    BadCode {
        /// The point's index.
        index: usize,
        /// The code as written.
        code: u8,
    },
    /// Arrays that must be parallel have different lengths.
    #[error("`{field}` has {got} entries but must have {want} (one per {per})")]
    Length {
        /// The field.
        field: &'static str,
        /// Its length.
        got: usize,
        /// The length it must have.
        want: usize,
        /// What it is parallel to: `point` or `line`.
        per: &'static str,
    },
    /// `unclassified_lines` names a line that does not exist.
    #[error("unclassified_lines names line {line}, but the drawing has {lines} lines")]
    BadUnclassified {
        /// The line index as written.
        line: usize,
        /// Number of lines.
        lines: usize,
    },
    /// A line whose two points lie at the same place: it has no direction.
    #[error("line {index} has zero length (its points {a} and {b} lie at the same place); remove it or merge its points")]
    ZeroLength {
        /// The line's index.
        index: usize,
        /// Its first point.
        a: usize,
        /// Its second point.
        b: usize,
    },
    /// `curved_lines` names a line that does not exist.
    #[error("curved_lines names line {line}, but the drawing has {lines} lines")]
    BadCurved {
        /// The line index as written.
        line: usize,
        /// Number of lines.
        lines: usize,
    },
}

/// Largest coordinate a drawing's point may have, px: over a hundred times the largest picture
/// side (8192 px), far below where writing overflows.
pub const MAX_POINT_COORD_PX: f64 = 1e6;

#[derive(Deserialize)]
struct DrawingFile {
    points: Vec<[f64; 2]>,
    lines: Vec<[usize; 2]>,
    #[serde(default)]
    codes: Option<Vec<SixBitCode>>,
    #[serde(default)]
    junctions: Option<Vec<Junction>>,
    #[serde(default)]
    kinds: Vec<LineKind>,
    #[serde(default)]
    edges: Vec<EdgeRef>,
    #[serde(default)]
    unclassified_lines: Option<Vec<usize>>,
    #[serde(default)]
    curved_lines: Vec<usize>,
}

impl LineDrawing {
    /// Parses and checks a drawing's JSON text (see the module doc); `codes`, `junctions` and
    /// `unclassified_lines`, when absent, are computed with [`LineDrawing::finalize`].
    pub fn from_json(text: &str) -> Result<LineDrawing, DrawingError> {
        let f: DrawingFile =
            serde_json::from_str(text).map_err(|e| DrawingError::Format(e.to_string()))?;
        let computed = f.codes.is_none() || f.junctions.is_none();
        let mut d = LineDrawing {
            points: f.points.iter().map(|p| DVec2::from_array(*p)).collect(),
            lines: f.lines,
            codes: f.codes.unwrap_or_default(),
            junctions: f.junctions.unwrap_or_default(),
            kinds: f.kinds,
            edges: f.edges,
            unclassified_lines: f.unclassified_lines.clone().unwrap_or_default(),
            curved_lines: f.curved_lines,
        };
        d.check_geometry()?;
        d.check_line_lists()?;
        if computed || f.unclassified_lines.is_none() {
            let (codes, junctions) = (d.codes.clone(), d.junctions.clone());
            d.finalize();
            if !computed {
                (d.codes, d.junctions) = (codes, junctions);
            }
        }
        d.check()?;
        Ok(d)
    }

    /// The checks of the geometry alone, for stages that compute the rest themselves (Kanade's
    /// labelling classifies junctions from the points): every coordinate finite and within
    /// [`MAX_POINT_COORD_PX`], every line joining two different existing points at different
    /// places.
    pub fn check_geometry(&self) -> Result<(), DrawingError> {
        if let Some(index) = self.points.iter().position(|p| !p.is_finite()) {
            return Err(DrawingError::NotFinite { index });
        }
        let far = |p: &DVec2| p.abs().max_element() > MAX_POINT_COORD_PX;
        if let Some(index) = self.points.iter().position(far) {
            return Err(DrawingError::OutOfRange { index });
        }
        let n = self.points.len();
        for (index, &[a, b]) in self.lines.iter().enumerate() {
            if a >= n || b >= n || a == b {
                return Err(DrawingError::BadLine {
                    index,
                    a,
                    b,
                    points: n,
                });
            }
            if self.points[a] == self.points[b] {
                return Err(DrawingError::ZeroLength { index, a, b });
            }
        }
        Ok(())
    }

    /// `unclassified_lines` and `curved_lines` name existing lines.
    fn check_line_lists(&self) -> Result<(), DrawingError> {
        let nl = self.lines.len();
        if let Some(&line) = self.unclassified_lines.iter().find(|&&l| l >= nl) {
            return Err(DrawingError::BadUnclassified { line, lines: nl });
        }
        if let Some(&line) = self.curved_lines.iter().find(|&&l| l >= nl) {
            return Err(DrawingError::BadCurved { line, lines: nl });
        }
        Ok(())
    }

    /// Checks the invariants every stage relies on (see [`DrawingError`]): the one validation
    /// of a drawing, which reading ([`LineDrawing::from_json`]) and the recognizer run;
    /// [`LineDrawing::check_geometry`] is its first half.
    pub fn check(&self) -> Result<(), DrawingError> {
        self.check_geometry()?;
        self.check_line_lists()?;
        let (np, nl) = (self.points.len(), self.lines.len());
        let parallel = [
            ("codes", self.codes.len(), np, "point", false),
            ("junctions", self.junctions.len(), np, "point", false),
            ("kinds", self.kinds.len(), nl, "line", true),
            ("edges", self.edges.len(), nl, "line", true),
        ];
        for (field, got, want, per, may_be_empty) in parallel {
            if got != want && !(may_be_empty && got == 0) {
                return Err(DrawingError::Length {
                    field,
                    got,
                    want,
                    per,
                });
            }
        }
        if let Some((index, c)) = self.codes.iter().enumerate().find(|(_, c)| c.0 > 63) {
            return Err(DrawingError::BadCode { index, code: c.0 });
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SQUARE: &str = r#"{"points": [[0, 0], [10, 10], [0, 20]], "lines": [[0, 1], [1, 2]]}"#;

    #[test]
    fn a_bare_drawing_reads_and_gets_its_codes() {
        let d = LineDrawing::from_json(SQUARE).unwrap();
        assert_eq!(d.codes.len(), 3);
        // Point 1 has a left-down and a left-up line.
        assert_eq!(d.codes[1].0, (1 << 3) | (1 << 2));
        assert_eq!(LineDrawing::from_json(&d.to_json()).unwrap(), d);
    }

    /// Regression: a point at x = 1e308 px read fine and was written back as `null` (found by
    /// the drawing mutants).
    #[test]
    fn huge_coordinates_are_refused() {
        let far = SQUARE.replace("[10, 10]", "[1e308, 10]");
        let err = LineDrawing::from_json(&far).unwrap_err();
        assert_eq!(err, DrawingError::OutOfRange { index: 1 });
        let edge = SQUARE.replace("[10, 10]", "[-1e6, 10]");
        assert!(!LineDrawing::from_json(&edge)
            .unwrap()
            .to_json()
            .contains("null"));
    }

    #[test]
    fn broken_drawings_are_refused_with_the_reason() {
        let bad = |t: &str| LineDrawing::from_json(t).unwrap_err();
        assert!(matches!(
            bad(r#"{"points": [[0, 0]], "lines": [[0, 3]]}"#),
            DrawingError::BadLine { index: 0, b: 3, .. }
        ));
        assert!(matches!(
            bad(r#"{"points": [[0, 0], [1, 1]], "lines": [[1, 1]]}"#),
            DrawingError::BadLine { .. }
        ));
        assert!(matches!(
            bad(r#"{"points": [[0, 0], [1, 1], [0, 0]], "lines": [[0, 2]]}"#),
            DrawingError::ZeroLength {
                index: 0,
                a: 0,
                b: 2
            }
        ));
        assert!(matches!(
            bad(r#"{"points": [[0, 1e999]], "lines": []}"#),
            DrawingError::NotFinite { .. } | DrawingError::Format(_)
        ));
        assert!(matches!(
            bad(
                r#"{"points": [[0, 0], [1, 1]], "lines": [[0, 1]], "codes": [64, 1], "junctions": ["end", "end"]}"#
            ),
            DrawingError::BadCode { index: 0, code: 64 }
        ));
        assert!(matches!(
            bad(
                r#"{"points": [[0, 0], [1, 1]], "lines": [[0, 1]], "codes": [1], "junctions": ["end", "end"]}"#
            ),
            DrawingError::Length { field: "codes", .. }
        ));
        assert!(matches!(
            bad(r#"{"points": [[0, 0], [1, 1]], "lines": [[0, 1]], "unclassified_lines": [4]}"#),
            DrawingError::BadUnclassified { line: 4, .. }
        ));
        assert!(matches!(bad("[1, 2]"), DrawingError::Format(_)));
        assert!(matches!(
            bad(r#"{"points": [[0, 0], [1, 1]], "lines": [[0, 1]], "curved_lines": [1]}"#),
            DrawingError::BadCurved { line: 1, .. }
        ));
    }

    /// `curved_lines` reads back as written and is left out of a straight drawing's JSON
    /// (docs/formats.md "The exact line drawing").
    #[test]
    fn curved_lines_round_trip_and_are_absent_when_empty() {
        let text = r#"{"points": [[0, 0], [1, 1], [3, 1]], "lines": [[0, 1], [1, 2]], "curved_lines": [0, 1]}"#;
        let d = LineDrawing::from_json(text).unwrap();
        assert_eq!(d.curved_lines, [0, 1]);
        assert_eq!(LineDrawing::from_json(&d.to_json()).unwrap(), d);
        let square = LineDrawing::from_json(SQUARE).unwrap();
        assert!(!square.to_json().contains("curved"));
    }
}
