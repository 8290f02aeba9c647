//! Wireframe-learning export: the exact line drawing of a view (docs/formats.md "The exact line drawing") as the labels learned wireframe parsers train on — HAWP (Xue et al., "Holistically-
//! Attracted Wireframe Parsing", CVPR 2020), L-CNN (Zhou et al., "End-to-End Wireframe Parsing",
//! ICCV 2019) and LETR (Xu et al., "Line Segment Detection Using Transformers without Edges",
//! CVPR 2021).
//!
//! The thesis's line drawing (Ch. IV, V) is in picture coordinates with y up and the origin at
//! the bottom-left corner (docs/formats.md "Conventions"); these tools use raster coordinates, y down,
//! origin at the top-left corner, pixel `i` spanning `[i, i + 1)`. Both put pixel centres at
//! `+0.5`, so the conversion is `x' = x`, `y' = H - y` exactly. Lines leaving the picture are
//! clipped to `[0, W] x [0, H]` and their border ends marked (`junction_type` `"border"`).
//! Every function here is pure: it turns a [`LineDrawing`] and a picture size into JSON values;
//! the CLI reads and writes the files.
//!
//! Each format was checked against the tool's own loader, not only its description (the
//! files and functions are named in `formats` and in docs/wireframe.md "Wireframe datasets"): HAWP's
//! `TrainDataset` / `TestDatasetWithAnnotations`, L-CNN's `dataset/wireframe.py`, LETR's
//! `src/datasets/coco.py` and `src/datasets/transforms.py`.

mod formats;
mod split;

pub use formats::{
    hawp_negative_edges, hawp_test_record, hawp_train_record, lcnn_record, letr_annotations,
    letr_document, letr_image, letr_line_px, WireframeFormat, HAWP_NEGATIVE_EDGES_MAX,
};
pub use split::{split_of, Split};

use crate::drawing::{LineDrawing, LineKind};
use crate::geom::{clip_segment_to_box, DVec2};
use std::collections::HashMap;

/// Junction coordinates are rounded to 1 / this many px (1e-4 px), so junctions that coincide
/// share one exact coordinate (the drawing's points are written with the same rounding, docs/formats.md
/// "The exact line drawing"); dividing by it gives the shortest decimal in JSON.
pub const JUNCTION_STEPS_PER_PX: f64 = 1e4;

/// Clipped pieces shorter than this are dropped (a line touching the border at one point).
pub const MIN_CLIPPED_LENGTH_PX: f64 = 1e-3;

/// Why a drawing cannot be exported.
#[derive(Debug, thiserror::Error)]
pub enum WireframeError {
    /// The picture has no pixels.
    #[error("picture size {width_px}x{height_px} has no pixels; export views with a real picture")]
    EmptyPicture {
        /// Width in px.
        width_px: u32,
        /// Height in px.
        height_px: u32,
    },
    /// A line names a point the drawing does not have.
    #[error("line {line} names point {point} but the drawing has {points} points; regenerate the drawing")]
    BadLine {
        /// Line index.
        line: usize,
        /// The missing point index.
        point: usize,
        /// Number of points.
        points: usize,
    },
}

/// One junction of the exported wireframe, in raster px (y down).
#[derive(Debug, Clone, PartialEq)]
pub struct WireframeJunction {
    /// `[x, y]` in raster px, y down, rounded by [`JUNCTION_STEPS_PER_PX`].
    pub xy_px: [f64; 2],
    /// The drawing's point index, `None` for a point where a line was clipped at the border.
    pub drawing_point: Option<usize>,
    /// Junction class (`L`, `fork`, `arrow`, `T`, ... of Ch. V; `border` for clip points).
    pub junction_type: String,
    /// The six-bit code of Ch. IV (`None` at clip points, which have no code in the drawing).
    pub six_bit_code: Option<u8>,
}

/// The wireframe of one view: junctions and the lines between them, ready for any format.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Wireframe {
    /// Picture width, px.
    pub width_px: u32,
    /// Picture height, px.
    pub height_px: u32,
    /// Junctions, unique by coordinate.
    pub junctions: Vec<WireframeJunction>,
    /// Lines as junction index pairs, in the drawing's line order (clipped-away lines dropped).
    pub edges: Vec<[usize; 2]>,
    /// Kind of every edge (`None` when the drawing has no kinds, e.g. from vision).
    pub line_kinds: Vec<Option<LineKind>>,
    /// The drawing line each edge comes from.
    pub drawing_lines: Vec<usize>,
}

impl Wireframe {
    /// Edge `i` as `[x1, y1, x2, y2]` in raster px.
    pub fn line_px(&self, i: usize) -> [f64; 4] {
        let [a, b] = self.edges[i];
        let (p, q) = (self.junctions[a].xy_px, self.junctions[b].xy_px);
        [p[0], p[1], q[0], q[1]]
    }

    /// Whether each end of edge `i` is a border clip point.
    pub fn border_ends(&self, i: usize) -> [bool; 2] {
        self.edges[i].map(|j| self.junctions[j].drawing_point.is_none())
    }
}

/// Converts a line drawing (picture px, y up) of a `width_px` x `height_px` picture into its
/// wireframe in raster px (y down), clipping lines to the picture and merging coincident
/// junctions (module doc).
pub fn wireframe_from_drawing(
    drawing: &LineDrawing,
    width_px: u32,
    height_px: u32,
) -> Result<Wireframe, WireframeError> {
    if width_px == 0 || height_px == 0 {
        return Err(WireframeError::EmptyPicture {
            width_px,
            height_px,
        });
    }
    let size = DVec2::new(f64::from(width_px), f64::from(height_px));
    let mut out = Wireframe {
        width_px,
        height_px,
        ..Default::default()
    };
    let mut index_of: HashMap<[i64; 2], usize> = HashMap::new();
    for (li, &[a, b]) in drawing.lines.iter().enumerate() {
        for point in [a, b] {
            if point >= drawing.points.len() {
                return Err(WireframeError::BadLine {
                    line: li,
                    point,
                    points: drawing.points.len(),
                });
            }
        }
        let p = raster_from_picture(drawing.points[a], size.y);
        let q = raster_from_picture(drawing.points[b], size.y);
        let Some((t0, t1)) = clip_segment_to_box(p, q, DVec2::ZERO, size) else {
            continue;
        };
        let (p0, p1) = (p + (q - p) * t0, p + (q - p) * t1);
        if p0.distance(p1) < MIN_CLIPPED_LENGTH_PX {
            continue;
        }
        let ja = junction_index(
            &mut out,
            &mut index_of,
            drawing,
            p0,
            (t0 == 0.0).then_some(a),
        );
        let jb = junction_index(
            &mut out,
            &mut index_of,
            drawing,
            p1,
            (t1 == 1.0).then_some(b),
        );
        if ja == jb || out.edges.iter().any(|e| *e == [ja, jb] || *e == [jb, ja]) {
            continue;
        }
        out.edges.push([ja, jb]);
        out.line_kinds.push(drawing.kinds.get(li).copied());
        out.drawing_lines.push(li);
    }
    Ok(out)
}

/// docs/formats.md "Conventions": picture y up from the bottom edge; raster y down from the top edge.
/// Both keep pixel centres at +0.5, so the flip is exact: `y' = H - y`.
pub fn raster_from_picture(p: DVec2, height_px: f64) -> DVec2 {
    DVec2::new(p.x, height_px - p.y)
}

/// The index of the junction at `xy` (rounded), adding it when new; `point` is the drawing
/// point it is, or `None` for a border clip point.
fn junction_index(
    out: &mut Wireframe,
    index_of: &mut HashMap<[i64; 2], usize>,
    drawing: &LineDrawing,
    xy: DVec2,
    point: Option<usize>,
) -> usize {
    let key = [xy.x, xy.y].map(|v| (v * JUNCTION_STEPS_PER_PX).round() as i64);
    if let Some(&j) = index_of.get(&key) {
        return j;
    }
    let xy_px = key.map(|k| k as f64 / JUNCTION_STEPS_PER_PX);
    let junction_type = match point.and_then(|i| drawing.junctions.get(i)) {
        Some(j) => serde_json::to_value(j)
            .ok()
            .and_then(|v| v.as_str().map(str::to_string))
            .unwrap_or_else(|| "other".to_string()),
        None if point.is_some() => "unknown".to_string(),
        None => "border".to_string(),
    };
    let six_bit_code = point.and_then(|i| drawing.codes.get(i)).map(|c| c.0);
    out.junctions.push(WireframeJunction {
        xy_px,
        drawing_point: point,
        junction_type,
        six_bit_code,
    });
    index_of.insert(key, out.junctions.len() - 1);
    out.junctions.len() - 1
}

#[cfg(test)]
mod tests;
