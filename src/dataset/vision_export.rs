//! A generated dataset's views as the files vision tools load unchanged (docs/exports.md
//! "Exports for vision tools"): `blockworld export-dataset DATASET --format
//! coco|hf -o OUT`.
//!
//! Streams scene by scene on `jobs` threads: each scene's pictures are copied (atomically,
//! temporary name and rename) before its part file `OUT/.parts/<id>.json`, which holds its
//! records and its pictures' sha256; re-running the same export skips the scenes whose part file
//! reads and whose pictures match it. The annotation file is assembled from the parts, in scene
//! order, at the end, so the bytes do not depend on `jobs`. Every dataset file read is checked
//! against its sha256 in `manifest.jsonl`; a missing or damaged one is refused with its path.
//! Like the wireframe exports, an export holds the dataset lock on OUT and first removes the
//! temporary files a killed export left.

use super::bop_export::{assemble_bop, export_bop_scene, refuse_orthographic};
use super::export_files::{
    lock_export, part_is_complete, push_json, read_camera, read_checked, read_gray16,
    read_manifest, read_part, read_scene_checked, remake, views_of, PARTS_DIR,
};
use super::manifest::{parse_manifest, sha256_hex, ManifestEntry, MANIFEST_NAME};
use super::writer::{io_err, remove_temporaries};
use super::DatasetError;
use crate::drawing::LineDrawing;
use crate::export::coco::{coco_categories, coco_view, SilhouetteAgreement, ViewInput};
use crate::io::{write_atomic, write_atomic_with, FileSync};
use serde_json::{json, Value};
use std::path::Path;
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};

/// The options stamp of an export folder.
const STAMP_FILE: &str = "export.json";

/// The vision-tool formats.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum VisionFormat {
    /// COCO `instances`: `images/`, `annotations/instances.json`.
    Coco,
    /// Hugging Face image folder: `train/` with the pictures and `metadata.jsonl`.
    HuggingFace,
    /// BOP: `models/`, `train_pbr/<scene>/`, `camera.json` (docs/export-bop.md).
    Bop,
}

impl VisionFormat {
    /// The format's name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            VisionFormat::Coco => "coco",
            VisionFormat::HuggingFace => "hf",
            VisionFormat::Bop => "bop",
        }
    }

    /// The folder of the pictures, relative to OUT.
    pub fn image_dir(self) -> &'static str {
        match self {
            VisionFormat::Coco => "images",
            VisionFormat::HuggingFace => "train",
            VisionFormat::Bop => "train_pbr",
        }
    }

    /// The annotation file, relative to OUT.
    pub fn annotation_file(self) -> &'static str {
        match self {
            VisionFormat::Coco => "annotations/instances.json",
            VisionFormat::HuggingFace => "train/metadata.jsonl",
            VisionFormat::Bop => "models/models_info.json",
        }
    }
}

/// What an export did.
#[derive(Debug, Clone, Copy, Default)]
pub struct VisionExportSummary {
    /// Scenes in the dataset.
    pub scenes: usize,
    /// Scenes an earlier run had finished.
    pub resumed: usize,
    /// Pictures in the export.
    pub images: usize,
    /// Pictures written by this run.
    pub new_images: usize,
    /// Annotations (blocks seen, one per block and view).
    pub annotations: usize,
    /// How the full masks agree with the id pictures, over the whole export.
    pub agreement: SilhouetteAgreement,
}

/// Exports `dataset` into `out` in `format` on `jobs` threads (module doc); `progress(done,
/// total)` is called after each scene.
pub fn export_vision(
    dataset: &Path,
    out: &Path,
    format: VisionFormat,
    jobs: usize,
    progress: &(dyn Fn(u64, u64) + Sync),
) -> Result<VisionExportSummary, DatasetError> {
    let manifest_path = dataset.join(MANIFEST_NAME);
    let manifest = read_manifest(&manifest_path)?;
    let entries = parse_manifest(&String::from_utf8_lossy(&manifest), &manifest_path)?;
    if format == VisionFormat::Bop {
        refuse_orthographic(dataset, &entries)?;
    }
    let _lock = lock_export(out)?;
    prepare_output(out, format, &sha256_hex(&manifest))?;
    let resumed = export_scenes(jobs, &entries, progress, |index, entry| match format {
        VisionFormat::Bop => export_bop_scene(dataset, out, index, entry),
        _ => export_scene(dataset, out, format, entry),
    })?;
    let mut summary = match format {
        VisionFormat::Bop => assemble_bop(out, &entries)?,
        _ => assemble(out, format, &entries)?,
    };
    summary.scenes = entries.len();
    summary.resumed = resumed;
    Ok(summary)
}

/// Creates the folders and checks (or writes) the options stamp, so a resumed run never mixes
/// two exports.
fn prepare_output(
    out: &Path,
    format: VisionFormat,
    manifest_sha: &str,
) -> Result<(), DatasetError> {
    let annotations = Path::new(format.annotation_file())
        .parent()
        .unwrap_or(Path::new(""));
    for dir in [
        Path::new(""),
        Path::new(PARTS_DIR),
        Path::new(format.image_dir()),
        annotations,
    ] {
        let path = out.join(dir);
        std::fs::create_dir_all(&path).map_err(io_err(&path))?;
        remove_temporaries(&path, None)?;
    }
    let stamp = json!({"format": format.name(), "manifest_sha256": manifest_sha});
    let path = out.join(STAMP_FILE);
    if let Ok(text) = std::fs::read_to_string(&path) {
        let old: Value = serde_json::from_str(&text).unwrap_or(Value::Null);
        if old != stamp {
            return Err(DatasetError::Input {
                path,
                message: format!("holds an export made with other options or another dataset ({text}); use another -o or delete it"),
            });
        }
        return Ok(());
    }
    write_atomic(&path, crate::io::pretty_json(&stamp).as_bytes()).map_err(io_err(&path))
}

/// Exports every scene on `jobs` threads with `export(index, entry)` (`false` when an earlier
/// run had done the scene), each thread taking the next scene not yet taken; returns how many
/// scenes an earlier run had done. The first error stops the others after their scene.
fn export_scenes(
    jobs: usize,
    entries: &[ManifestEntry],
    progress: &(dyn Fn(u64, u64) + Sync),
    export: impl Fn(usize, &ManifestEntry) -> Result<bool, DatasetError> + Sync,
) -> Result<usize, DatasetError> {
    let total = entries.len() as u64;
    let (next, done, failed) = (
        AtomicUsize::new(0),
        AtomicU64::new(0),
        AtomicBool::new(false),
    );
    let worker = || -> Result<usize, DatasetError> {
        let mut resumed = 0;
        while !failed.load(Ordering::Relaxed) {
            let index = next.fetch_add(1, Ordering::Relaxed);
            let Some(entry) = entries.get(index) else {
                break;
            };
            match export(index, entry) {
                Ok(fresh) => resumed += usize::from(!fresh),
                Err(e) => {
                    failed.store(true, Ordering::Relaxed);
                    return Err(e);
                }
            }
            progress(done.fetch_add(1, Ordering::Relaxed) + 1, total);
        }
        Ok(resumed)
    };
    let results: Vec<_> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..jobs.max(1)).map(|_| s.spawn(worker)).collect();
        handles
            .into_iter()
            .map(|h| h.join().unwrap_or_else(|p| std::panic::resume_unwind(p)))
            .collect()
    });
    results.into_iter().sum()
}

/// Exports one scene (its pictures, then its part file); `false` when an earlier run had
/// already done it.
fn export_scene(
    dataset: &Path,
    out: &Path,
    format: VisionFormat,
    entry: &ManifestEntry,
) -> Result<bool, DatasetError> {
    let part_path = out.join(PARTS_DIR).join(format!("{}.json", entry.id));
    let (scene_dir, scene) = read_scene_checked(dataset, entry)?;
    let mut records = Vec::new();
    let mut pictures = Vec::new();
    let mut agreement = SilhouetteAgreement::default();
    for view in views_of(entry) {
        let file_name = format!("{}_{view}.png", entry.id);
        let (picture, record, seen) = view_record(&scene_dir, entry, &scene, &view, &file_name)?;
        agreement.add(seen);
        records.push(record);
        pictures.push((format!("{}/{file_name}", format.image_dir()), picture));
    }
    if part_is_complete(&part_path, out) {
        return Ok(false);
    }
    let mut images = serde_json::Map::new();
    for (relative, png) in &pictures {
        images.insert(relative.clone(), json!(sha256_hex(png)));
        let path = out.join(relative);
        write_atomic_with(&path, png, FileSync::Verified).map_err(io_err(&path))?;
    }
    let part =
        json!({"images": images, "records": records, "agreement": agreement_json(agreement)});
    write_atomic_with(&part_path, part.to_string().as_bytes(), FileSync::Verified)
        .map_err(io_err(&part_path))?;
    Ok(true)
}

/// The picture bytes, the COCO records and the silhouette agreement of one view.
fn view_record(
    scene_dir: &Path,
    entry: &ManifestEntry,
    scene: &crate::scene::Scene,
    view: &str,
    file_name: &str,
) -> Result<(Vec<u8>, Value, SilhouetteAgreement), DatasetError> {
    let camera = read_camera(scene_dir, entry, view)?;
    let lines_name = format!("lines_{view}.json");
    let lines_text = read_checked(scene_dir, entry, &lines_name)?;
    let drawing = LineDrawing::from_json(&String::from_utf8_lossy(&lines_text))
        .map_err(|e| remake(scene_dir.join(lines_name), e))?;
    let ids_name = format!("ids_{view}.png");
    let ids = read_gray16(scene_dir, entry, &ids_name, &camera)?;
    let picture = read_checked(scene_dir, entry, &format!("view_{view}.png"))?;
    let input = ViewInput {
        scene_id: &entry.id,
        scene,
        camera: &camera,
        ids: ids.as_raw(),
        drawing: &drawing,
        file_name,
    };
    let coco = coco_view(&input).map_err(|e| remake(scene_dir.join(ids_name), e))?;
    let record = json!({"image": coco.image, "annotations": coco.annotations});
    Ok((picture, record, coco.agreement))
}

/// The silhouette agreement as a part file holds it.
pub(super) fn agreement_json(a: SilhouetteAgreement) -> Value {
    json!([
        a.visible_outside_px,
        a.silhouette_on_background_px,
        a.silhouette_px
    ])
}

/// The silhouette agreement a part file holds (zero when it holds none).
pub(super) fn part_agreement(part: &Value) -> SilhouetteAgreement {
    let count = |k: usize| part["agreement"][k].as_u64().unwrap_or(0);
    SilhouetteAgreement {
        visible_outside_px: count(0),
        silhouette_on_background_px: count(1),
        silhouette_px: count(2),
    }
}

/// Joins the part files, in scene order, into the format's annotation file (COCO: image and
/// annotation ids numbered from 1 in that order; HF: one `metadata.jsonl` line per picture).
fn assemble(
    out: &Path,
    format: VisionFormat,
    entries: &[ManifestEntry],
) -> Result<VisionExportSummary, DatasetError> {
    let mut summary = VisionExportSummary::default();
    let mut text = CocoText::default();
    for entry in entries {
        let mut part = read_part(out, entry)?;
        summary.agreement.add(part_agreement(&part));
        let Value::Array(records) = part["records"].take() else {
            continue;
        };
        for record in records {
            summary.images += 1;
            summary.annotations += match format {
                VisionFormat::Coco => push_coco(&mut text, record, summary.images),
                VisionFormat::HuggingFace | VisionFormat::Bop => push_hf(&mut text.images, record),
            };
        }
    }
    let doc = match format {
        VisionFormat::Coco => format!(
            "{{\"info\":{},\"licenses\":[],\"images\":[{}],\"annotations\":[{}],\"categories\":{}}}\n",
            json!({"description": "blockworld dataset", "version": env!("CARGO_PKG_VERSION")}),
            text.images,
            text.annotations,
            coco_categories()
        ),
        VisionFormat::HuggingFace | VisionFormat::Bop => text.images,
    };
    let path = out.join(format.annotation_file());
    write_atomic(&path, doc.as_bytes()).map_err(io_err(&path))?;
    Ok(summary)
}

/// Appends one picture's COCO image (id `image_id`) and annotations (ids running on from the
/// ones already in `annotations`); returns its number of annotations.
fn push_coco(text: &mut CocoText, mut record: Value, image_id: usize) -> usize {
    record["image"]["id"] = json!(image_id);
    push_json(&mut text.images, &record["image"]);
    let Value::Array(anns) = record["annotations"].take() else {
        return 0;
    };
    let n = anns.len();
    for mut ann in anns {
        text.annotation_count += 1;
        ann["id"] = json!(text.annotation_count);
        ann["image_id"] = json!(image_id);
        push_json(&mut text.annotations, &ann);
    }
    n
}

/// The COCO document's lists as they are assembled, serialized and comma-joined (the records
/// as JSON values would take many times the text), and the annotations so far.
#[derive(Default)]
struct CocoText {
    images: String,
    annotations: String,
    annotation_count: usize,
}

/// Appends one picture's `metadata.jsonl` line: `file_name` (beside it in `train/`), `objects`
/// as the Hugging Face detection sets write them (lists of `bbox` in COCO's `[x, y, w, h]`,
/// `category` (the block type), `area`, `block_index`), the scene, the view and the camera;
/// returns its number of objects.
fn push_hf(lines: &mut String, record: Value) -> usize {
    let anns = record["annotations"]
        .as_array()
        .cloned()
        .unwrap_or_default();
    let field = |key: &str| anns.iter().map(|a| a[key].clone()).collect::<Vec<_>>();
    let categories: Vec<Value> = anns
        .iter()
        .map(|a| {
            let k = a["category_id"].as_u64().unwrap_or(0) as usize;
            crate::scene::CATALOG
                .get(k.wrapping_sub(1))
                .map_or(Value::Null, |t| json!(t.id))
        })
        .collect();
    let image = &record["image"];
    let line = json!({
        "file_name": image["file_name"],
        "scene_id": image["scene_id"],
        "view": image["view"],
        "objects": {
            "bbox": field("bbox"),
            "category": categories,
            "area": field("area"),
            "block_index": field("block_index"),
        },
        "camera": image["camera"],
    });
    lines.push_str(&line.to_string());
    lines.push('\n');
    anns.len()
}
