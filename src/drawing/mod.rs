//! The line drawing: points in picture coordinates, straight lines between them, and per point
//! the thesis's **six-bit code** (Chapter IV) and junction class (Chapter V, Figure 5.1;
//! Kanade's catalog of Chapter II). Ground truth (`linedraw`) and the vision front end
//! (`vision`) both produce a [`LineDrawing`], so any tool can compare the two.
//!
//! ## Bit order
//! Chapter IV: bit 0 up, 1 down, 2 left-up, 3 left-down, 4 right-up, 5 right-down; its worked
//! example up + down + ld + ru = 27. Appendix A (Figure A.6) prints another order and its
//! row E contradicts it; this crate follows Chapter IV (see docs/thesis-readings.md "Thesis readings").

mod axis;
mod code;
mod junction;
mod read;

pub use axis::EdgeAxis;
pub use code::{Direction, SixBitCode, HORIZONTAL_TOL_DEG, VERTICAL_TOL_DEG};
pub use junction::{classify_junction, Junction, ThesisClass, COLLINEAR_TOL_DEG};
pub use read::{DrawingError, MAX_POINT_COORD_PX};

use crate::geom::{DVec2, DVec3};
use serde::{Deserialize, Serialize};

/// What a line depicts (Huffman-Clowes vocabulary, plus the crack between touching blocks).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum LineKind {
    /// Silhouette against the background or the floor, including bottom edges on the floor
    /// (Kanade's occluding label).
    Boundary,
    /// Both faces of the edge visible, meeting in a convexity ("+").
    Convex,
    /// Two faces meeting in a concavity ("-"), e.g. an upper block's side on the top below.
    Concave,
    /// A flat seam where coplanar faces of two touching blocks meet flush.
    Crack,
}

/// The 3D edge a ground-truth line depicts.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct EdgeRef {
    /// Index of the block (in scene order) whose edge this is.
    pub block: usize,
    /// The edge's two vertex indices in the block's catalog polyhedron.
    pub vertices: [usize; 2],
    /// For cracks and contact edges: the touching block.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub other_block: Option<usize>,
    /// World position (mm) of the visible piece's first end (at `lines[i][0]`).
    pub from_mm: [f64; 3],
    /// World position (mm) of the visible piece's second end (at `lines[i][1]`).
    pub to_mm: [f64; 3],
    /// `true` when the edge lies on a contact between two blocks (a crack, or a concave edge
    /// where one block rests on another).
    #[serde(default)]
    pub contact: bool,
}

/// A line drawing in picture coordinates (pixels, x right, y up, origin at the bottom-left
/// corner; see `geom`). `codes` and `junctions` are parallel to `points`; `kinds` and `edges`
/// are parallel to `lines` when known (ground truth) and empty otherwise (vision).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct LineDrawing {
    /// Junction points, picture px.
    #[serde(with = "points_serde")]
    pub points: Vec<DVec2>,
    /// Straight lines as pairs of point indices.
    pub lines: Vec<[usize; 2]>,
    /// Six-bit code of every point (Chapter IV).
    pub codes: Vec<SixBitCode>,
    /// Junction class of every point.
    pub junctions: Vec<Junction>,
    /// Kind of every line (ground truth only).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub kinds: Vec<LineKind>,
    /// The 3D edge of every line (ground truth only).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub edges: Vec<EdgeRef>,
    /// Lines that fall in none of the six directions (seen edge-on as horizontal, e.g. a block
    /// turned 45 degrees in a corner view): flagged, not guessed.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub unclassified_lines: Vec<usize>,
    /// Lines that are chords of a curved edge (a round part's rim, Chapter VII's "circles"):
    /// consecutive curved lines form a polyline whose every point lies exactly on the
    /// projected circle. Absent from the JSON when empty, so straight-line drawings keep their
    /// bytes (docs/formats.md "The exact line drawing").
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub curved_lines: Vec<usize>,
}

impl LineDrawing {
    /// Recomputes `codes`, `junctions` and `unclassified_lines` from `points` and `lines`.
    pub fn finalize(&mut self) {
        let mut incident: Vec<Vec<DVec2>> = vec![Vec::new(); self.points.len()];
        self.unclassified_lines.clear();
        for (li, &[a, b]) in self.lines.iter().enumerate() {
            let d = self.points[b] - self.points[a];
            incident[a].push(d);
            incident[b].push(-d);
            if Direction::from_picture_vector(d).is_none() {
                self.unclassified_lines.push(li);
            }
        }
        self.codes = incident
            .iter()
            .map(|dirs| SixBitCode::from_picture_vectors(dirs))
            .collect();
        self.junctions = incident.iter().map(|d| classify_junction(d)).collect();
    }

    /// A drawing of `points` (picture px, y up) joined by `lines`, codes and junctions computed
    /// ([`LineDrawing::finalize`]): the hand-made drawings of the unit tests.
    pub fn from_arrays(points: &[[f64; 2]], lines: &[[usize; 2]]) -> LineDrawing {
        let mut d = LineDrawing {
            points: points.iter().map(|p| DVec2::from_array(*p)).collect(),
            lines: lines.to_vec(),
            ..Default::default()
        };
        d.finalize();
        d
    }

    /// The isometric cube of Appendix A's Figure A.2 (Chapter IV's worked example): a hexagon
    /// of corners A..F, top vertex first, clockwise, around the middle fork G, the hexagon's
    /// radius `scale_px` and G at `origin_px`; codes and junctions computed. Chapter IV's bit
    /// order gives A..G the codes 40, 14, 9, 21, 33, 50, 22 (docs/thesis-readings.md "Thesis readings").
    pub fn isometric_cube(scale_px: f64, origin_px: DVec2) -> LineDrawing {
        let s = 3f64.sqrt() / 2.0;
        let unit = [
            (0.0, 1.0),
            (s, 0.5),
            (s, -0.5),
            (0.0, -1.0),
            (-s, -0.5),
            (-s, 0.5),
            (0.0, 0.0),
        ];
        let mut d = LineDrawing {
            points: unit
                .iter()
                .map(|&(x, y)| origin_px + DVec2::new(x, y) * scale_px)
                .collect(),
            lines: vec![
                [0, 1],
                [1, 2],
                [2, 3],
                [3, 4],
                [4, 5],
                [5, 0],
                [6, 1],
                [6, 3],
                [6, 5],
            ],
            ..Default::default()
        };
        d.finalize();
        d
    }

    /// Length of line `i` in px.
    pub fn line_length_px(&self, i: usize) -> f64 {
        let [a, b] = self.lines[i];
        self.points[a].distance(self.points[b])
    }

    /// Number of lines of each kind, in [`LineKind`] order (boundary, convex, concave, crack).
    pub fn kind_counts(&self) -> [usize; 4] {
        let mut n = [0; 4];
        for k in &self.kinds {
            n[*k as usize] += 1;
        }
        n
    }

    /// Pretty JSON, the `lines_<view>.json` format.
    pub fn to_json(&self) -> String {
        crate::io::pretty_json(self)
    }

    /// Points as `[x, y]` pairs (for callers that want plain arrays).
    pub fn point_arrays(&self) -> Vec<[f64; 2]> {
        self.points.iter().map(|p| p.to_array()).collect()
    }

    /// World positions are plain arrays in JSON; this reads one back.
    pub fn edge_world_mm(&self, i: usize) -> Option<(DVec3, DVec3)> {
        self.edges
            .get(i)
            .map(|e| (DVec3::from_array(e.from_mm), DVec3::from_array(e.to_mm)))
    }
}

/// Points serialize as `[[x, y], ...]`, rounded to 1e-4 px so files are stable and small.
mod points_serde {
    use crate::geom::DVec2;
    use serde::{Deserialize, Deserializer, Serializer};

    pub fn serialize<S: Serializer>(points: &[DVec2], s: S) -> Result<S::Ok, S::Error> {
        let round = |v: f64| (v * 1e4).round() / 1e4;
        s.collect_seq(points.iter().map(|p| [round(p.x), round(p.y)]))
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<DVec2>, D::Error> {
        let raw: Vec<[f64; 2]> = Vec::deserialize(d)?;
        Ok(raw.into_iter().map(DVec2::from_array).collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube() -> LineDrawing {
        LineDrawing::isometric_cube(1.0, DVec2::ZERO)
    }

    #[test]
    fn cube_codes_follow_chapter_iv_bit_order() {
        let d = cube();
        let codes: Vec<u8> = d.codes.iter().map(|c| c.0).collect();
        // The set of docs/formats.md "The exact line drawing": top 40, middle fork 22.
        assert_eq!(codes, vec![40, 14, 9, 21, 33, 50, 22]);
        assert_eq!(d.junctions[6], Junction::Fork);
        assert_eq!(d.junctions[0], Junction::L);
        assert_eq!(d.junctions[1], Junction::Arrow);
    }

    #[test]
    fn json_has_the_documented_field_names() {
        let v: serde_json::Value = serde_json::from_str(&cube().to_json()).unwrap();
        for key in ["points", "lines", "codes", "junctions"] {
            assert!(v.get(key).is_some(), "{key}");
        }
        assert_eq!(v["codes"][6], 22);
        let back: LineDrawing = serde_json::from_value(v).unwrap();
        assert_eq!(back.lines, cube().lines);
    }
}
