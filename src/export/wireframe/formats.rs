//! The three formats' records, from their published descriptions:
//! - HAWP (`hawp/fsl/dataset`, the `*_train` / `*_test` catalog entries): train items
//!   `{filename, height, width, junctions, edges_positive, edges_negative}`, test items
//!   `{filename, height, width, lines, junc}`.
//! - L-CNN (`dataset/wireframe.py` reads `train.json` / `valid.json`): `{filename, height, width,
//!   lines: [[x1, y1, x2, y2], ...]}`.
//! - LETR (COCO style, `lines_{train2017,val2017}.json`): `images`, `annotations` with
//!   `line: [x, y, dx, dy]` and `category_id` 0, `categories`.
//!
//! Extra keys ride along (README "Wireframe datasets"): `junction_type`, `six_bit_code` (per
//! junction) and `line_kind` (per line); they describe the picture as rendered and are invalid
//! after flip or rotation augmentation (the six-bit code of Ch. IV is tied to the picture's
//! axes: a left-right flip swaps its left and right bits).

use super::{Split, Wireframe};
use serde_json::{json, Value};

/// The export formats.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum WireframeFormat {
    /// HAWP: `images/`, `train.json`, `test.json`.
    Hawp,
    /// L-CNN: `images/`, `train.json`, `valid.json`.
    Lcnn,
    /// LETR: `train2017/`, `val2017/`, `annotations/lines_{train2017,val2017}.json`.
    Letr,
}

impl WireframeFormat {
    /// The format's name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            WireframeFormat::Hawp => "hawp",
            WireframeFormat::Lcnn => "lcnn",
            WireframeFormat::Letr => "letr",
        }
    }

    /// The folder (relative to the export root) that holds the pictures of `split`.
    pub fn image_dir(self, split: Split) -> &'static str {
        match (self, split) {
            (WireframeFormat::Letr, Split::Train) => "train2017",
            (WireframeFormat::Letr, Split::Test) => "val2017",
            _ => "images",
        }
    }

    /// The annotation file (relative to the export root) of `split`.
    pub fn annotation_file(self, split: Split) -> &'static str {
        match (self, split) {
            (WireframeFormat::Hawp, Split::Train) | (WireframeFormat::Lcnn, Split::Train) => {
                "train.json"
            }
            (WireframeFormat::Hawp, Split::Test) => "test.json",
            (WireframeFormat::Lcnn, Split::Test) => "valid.json",
            (WireframeFormat::Letr, Split::Train) => "annotations/lines_train2017.json",
            (WireframeFormat::Letr, Split::Test) => "annotations/lines_val2017.json",
        }
    }
}

fn junction_xys(wf: &Wireframe) -> Vec<[f64; 2]> {
    wf.junctions.iter().map(|j| j.xy_px).collect()
}

fn lines(wf: &Wireframe) -> Vec<[f64; 4]> {
    (0..wf.edges.len()).map(|i| wf.line_px(i)).collect()
}

fn line_kinds(wf: &Wireframe) -> Vec<Value> {
    wf.line_kinds.iter().map(|k| json!(k)).collect()
}

fn border_ends(wf: &Wireframe) -> Vec<[bool; 2]> {
    (0..wf.edges.len()).map(|i| wf.border_ends(i)).collect()
}

/// Adds the per-junction extras (`junction_type`, `six_bit_code`) to `record`.
fn with_junction_extras(mut record: Value, wf: &Wireframe) -> Value {
    let types: Vec<&str> = wf
        .junctions
        .iter()
        .map(|j| j.junction_type.as_str())
        .collect();
    let codes: Vec<Option<u8>> = wf.junctions.iter().map(|j| j.six_bit_code).collect();
    record["junction_type"] = json!(types);
    record["six_bit_code"] = json!(codes);
    record
}

/// A HAWP training item: junctions in raster px, `edges_positive` as junction index pairs,
/// no negatives (HAWP samples its own), plus the extras.
pub fn hawp_train_record(filename: &str, wf: &Wireframe) -> Value {
    let record = json!({
        "filename": filename,
        "height": wf.height_px,
        "width": wf.width_px,
        "junctions": junction_xys(wf),
        "edges_positive": wf.edges,
        "edges_negative": [],
        "line_kind": line_kinds(wf),
    });
    with_junction_extras(record, wf)
}

/// A HAWP test item: `lines` as `[x1, y1, x2, y2]` and `junc` as `[x, y]`, plus the extras.
pub fn hawp_test_record(filename: &str, wf: &Wireframe) -> Value {
    let record = json!({
        "filename": filename,
        "height": wf.height_px,
        "width": wf.width_px,
        "lines": lines(wf),
        "junc": junction_xys(wf),
        "line_kind": line_kinds(wf),
    });
    with_junction_extras(record, wf)
}

/// An L-CNN item: `lines` as `[x1, y1, x2, y2]`, plus `line_kind` and `line_border` (per line,
/// whether each end was clipped at the picture border).
pub fn lcnn_record(filename: &str, wf: &Wireframe) -> Value {
    json!({
        "filename": filename,
        "height": wf.height_px,
        "width": wf.width_px,
        "lines": lines(wf),
        "line_kind": line_kinds(wf),
        "line_border": border_ends(wf),
    })
}

/// A COCO `images` entry for LETR.
pub fn letr_image(image_id: u64, file_name: &str, wf: &Wireframe) -> Value {
    json!({
        "id": image_id,
        "file_name": file_name,
        "height": wf.height_px,
        "width": wf.width_px,
    })
}

/// The COCO `annotations` of one picture for LETR, ids from `first_id`: `line` as
/// `[x, y, dx, dy]` (start point and offset to the end, raster px), `category_id` 0, plus
/// `line_kind` and `border_ends`. The start is the shared junction coordinate exactly; a reader's
/// `x + dx` lands within 1e-12 px of the end junction (f64 cannot always hit it exactly).
pub fn letr_annotations(image_id: u64, first_id: u64, wf: &Wireframe) -> Vec<Value> {
    (0..wf.edges.len())
        .map(|i| {
            let [x1, y1, x2, y2] = wf.line_px(i);
            json!({
                "id": first_id + i as u64,
                "image_id": image_id,
                "category_id": 0,
                "iscrowd": 0,
                "line": [x1, y1, x2 - x1, y2 - y1],
                "line_kind": wf.line_kinds[i],
                "border_ends": wf.border_ends(i),
            })
        })
        .collect()
}

/// The COCO document of one LETR split.
pub fn letr_document(images: Vec<Value>, annotations: Vec<Value>) -> Value {
    json!({
        "images": images,
        "annotations": annotations,
        "categories": [{"id": 0, "name": "line", "supercategory": "line"}],
    })
}
