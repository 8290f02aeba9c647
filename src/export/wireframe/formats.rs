//! The three formats' records, checked against each tool's own loader (docs/wireframe.md "Wireframe datasets", "Checked against the loaders"):
//! - HAWP (`cherubicXN/hawp`, `hawp/fsl/config/paths_catalog.py` `DatasetCatalog`,
//!   `hawp/fsl/dataset/train_dataset.py` `TrainDataset.__getitem__`,
//!   `hawp/fsl/dataset/test_dataset.py` `TestDatasetWithAnnotations.__getitem__`): train items
//!   `{filename, height, width, junctions, edges_positive, edges_negative}`, test items
//!   `{filename, height, width, lines, junc}`. `edges_negative` holds the junction pairs no line
//!   joins (the HAFM encoder reads the first [`HAWP_NEGATIVE_EDGES_MAX`]; HAWP v1's encoder
//!   fails on an empty list). A picture without lines is left out: the loader indexes
//!   `junctions[:, 0]`, which fails on an empty list.
//! - L-CNN (`zhou13/lcnn`, `dataset/wireframe.py` `main` / `save_heatmap`, reading
//!   `train.json` / `valid.json`): `{filename, height, width, lines: [[x1, y1, x2, y2], ...]}`. A
//!   picture where every pair of line ends is a line is left out: `save_heatmap` asserts that
//!   some junction pair is not a line (its negatives).
//! - LETR (`mlpc-ucsd/LETR`, `src/datasets/coco.py` `ConvertCocoPolysToMask.__call__` and the
//!   crop / flip transforms of `src/datasets/transforms.py`): COCO `images`, `annotations` with
//!   `line: [x, y, dx, dy]`, `category_id` 0 and `area` (read; 1 as LETR's `helper/wireframe.py`
//!   writes), `categories`. The start is the left end (the smaller x; on a vertical line the
//!   upper end, the smaller raster y), as those transforms assume.
//!
//! Extra keys ride along (docs/wireframe.md "Wireframe datasets"): `junction_type`, `six_bit_code` (per
//! junction) and `line_kind` (per line); they describe the picture as rendered and are invalid
//! after flip or rotation augmentation (the six-bit code of Ch. IV is tied to the picture's
//! axes: a left-right flip swaps its left and right bits).

use super::{Split, Wireframe};
use serde_json::{json, Value};
use std::collections::HashSet;

/// At most this many negative edges per HAWP training item: HAWP's HAFM encoder
/// (`hawp/fsl/model/hafm.py`) reads `edges_negative[:2000]`.
pub const HAWP_NEGATIVE_EDGES_MAX: usize = 2000;

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

    /// Why the format's own loader cannot take `wf` (module doc), or `None` when it can: HAWP
    /// needs a line, L-CNN a pair of junctions that is not a line. Such pictures are left out.
    pub fn loader_refusal(self, wf: &Wireframe) -> Option<&'static str> {
        let n = wf.junctions.len();
        match self {
            WireframeFormat::Hawp if wf.edges.is_empty() => {
                Some("no line: HAWP's TrainDataset indexes junctions[:, 0], which fails on none")
            }
            WireframeFormat::Lcnn if wf.edges.len() >= n * n.saturating_sub(1) / 2 => {
                Some("every junction pair is a line: L-CNN's save_heatmap asserts a negative pair")
            }
            _ => None,
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

/// HAWP's negative edges: the junction pairs `[i, j]` (`i < j`) no line joins, in index
/// order, at most [`HAWP_NEGATIVE_EDGES_MAX`] (L-CNN's `save_heatmap` makes its negatives the
/// same way, from every unjoined pair).
pub fn hawp_negative_edges(wf: &Wireframe) -> Vec<[usize; 2]> {
    let joined: HashSet<[usize; 2]> = wf
        .edges
        .iter()
        .map(|&[a, b]| [a.min(b), a.max(b)])
        .collect();
    let n = wf.junctions.len();
    (0..n)
        .flat_map(|i| (i + 1..n).map(move |j| [i, j]))
        .filter(|pair| !joined.contains(pair))
        .take(HAWP_NEGATIVE_EDGES_MAX)
        .collect()
}

/// A HAWP training item: junctions in raster px, `edges_positive` as junction index pairs,
/// `edges_negative` from [`hawp_negative_edges`], plus the extras.
pub fn hawp_train_record(filename: &str, wf: &Wireframe) -> Value {
    let record = json!({
        "filename": filename,
        "height": wf.height_px,
        "width": wf.width_px,
        "junctions": junction_xys(wf),
        "edges_positive": wf.edges,
        "edges_negative": hawp_negative_edges(wf),
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

/// Edge `i` as LETR orders it: `[x1, y1, x2, y2]` with the left end first (on a vertical line
/// the upper end, smaller raster y), and its border flags in the same order (module doc).
pub fn letr_line_px(wf: &Wireframe, i: usize) -> ([f64; 4], [bool; 2]) {
    let [x1, y1, x2, y2] = wf.line_px(i);
    let [b1, b2] = wf.border_ends(i);
    if (x2, y2) < (x1, y1) {
        ([x2, y2, x1, y1], [b2, b1])
    } else {
        ([x1, y1, x2, y2], [b1, b2])
    }
}

/// The COCO `annotations` of one picture for LETR, ids from `first_id`: `line` as
/// `[x, y, dx, dy]` (left end and offset to the right end, raster px, [`letr_line_px`]),
/// `category_id` 0, `area` 1, plus `line_kind` and `border_ends`. The start is the shared
/// junction coordinate exactly; a reader's `x + dx` lands within 1e-12 px of the end junction
/// (f64 cannot always hit it exactly).
pub fn letr_annotations(image_id: u64, first_id: u64, wf: &Wireframe) -> Vec<Value> {
    (0..wf.edges.len())
        .map(|i| {
            let ([x1, y1, x2, y2], border_ends) = letr_line_px(wf, i);
            json!({
                "id": first_id + i as u64,
                "image_id": image_id,
                "category_id": 0,
                "iscrowd": 0,
                "area": 1,
                "line": [x1, y1, x2 - x1, y2 - y1],
                "line_kind": wf.line_kinds[i],
                "border_ends": border_ends,
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
