//! A generated dataset's exact line drawings as training sets for learned wireframe parsers
//! (docs/wireframe.md "Wireframe datasets"): `blockworld export-dataset DATASET --format
//! hawp|lcnn|letr -o OUT`.
//!
//! Streams scene by scene (on `jobs` threads): each scene's pictures and records are written
//! (atomically, temporary name and rename) before its part file `OUT/.parts/<id>.json`, the
//! resume record; re-running the same export skips the scenes whose part file reads and whose
//! pictures match the sha256 it lists. Because that check catches a lost or torn file, these
//! files are not synced one by one (a sync per file made the disk the bottleneck); the
//! annotation files, assembled from the parts at the end, are. Every file read from the dataset
//! is checked against its sha256 in `manifest.jsonl`.
//!
//! An export holds the dataset lock on OUT (`lock::lock_dataset`, as `generate` holds it on its
//! dataset), so a second export into the same OUT is refused instead of deleting the first's
//! temporary files; holding it, an export first removes the temporary files a killed export
//! left (`writer::remove_temporaries`, as `generate` does). The pictures and records of a scene
//! are made by [`scene_part`] from bytes in memory; the file I/O is at the edges.

use super::export_files::{
    lock_export, part_is_complete, push_json, read_checked, read_manifest, read_part, views_of,
    PARTS_DIR,
};
use super::manifest::{parse_manifest, sha256_hex, ManifestEntry, MANIFEST_NAME};
use super::writer::{io_err, remove_temporaries};
use super::DatasetError;
use crate::drawing::LineDrawing;
use crate::export::wireframe::{
    hawp_test_record, hawp_train_record, lcnn_record, letr_annotations, letr_document, letr_image,
    split_of, wireframe_from_drawing, Split, Wireframe, WireframeFormat,
};
use crate::io::{write_atomic, write_atomic_with, FileSync};
use crate::output::{encode_png_gray8, encode_png_rgb8};
use crate::vision::{decode_gray, DecodedPicture};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::Mutex;

/// The options stamp of an export folder.
const STAMP_FILE: &str = "export.json";

/// Everything that decides an export's bytes, and how many scenes run at once.
#[derive(Debug, Clone, Copy)]
pub struct WireframeExportOptions {
    /// The wireframe format.
    pub format: WireframeFormat,
    /// Fraction of scenes in the training set (by a seeded hash of the scene id), in `0..=1`.
    pub split: f64,
    /// Seed of the split hash.
    pub split_seed: u64,
    /// Three-channel (RGB) PNGs; 8-bit grayscale otherwise.
    pub rgb: bool,
    /// Scenes exported at once (at least 1); does not change the bytes.
    pub jobs: usize,
}

/// What an export did.
#[derive(Debug, Clone, Default)]
pub struct WireframeExportSummary {
    /// Scenes in the dataset.
    pub scenes: usize,
    /// Scenes an earlier run had finished.
    pub resumed: usize,
    /// Pictures in the export.
    pub images: usize,
    /// Pictures written by this run.
    pub new_images: usize,
    /// Pictures left out because the format's loader cannot take them
    /// (`WireframeFormat::loader_refusal`).
    pub left_out: usize,
    /// The pictures this run left out, each as "<file>: <why>".
    pub left_out_notes: Vec<String>,
    /// Lines in the export.
    pub lines: usize,
}

/// Exports the dataset in `dataset` into `out` (module doc); `progress(done, total)` is called
/// after each scene.
pub fn export_wireframes(
    dataset: &Path,
    out: &Path,
    opts: &WireframeExportOptions,
    progress: &(dyn Fn(u64, u64) + Sync),
) -> Result<WireframeExportSummary, DatasetError> {
    if !(0.0..=1.0).contains(&opts.split) {
        return Err(DatasetError::Options(format!(
            "--split {} must lie in 0..=1 (the training fraction)",
            crate::io::echo_number(opts.split)
        )));
    }
    let manifest_path = dataset.join(MANIFEST_NAME);
    let manifest = read_manifest(&manifest_path)?;
    let entries = parse_manifest(&String::from_utf8_lossy(&manifest), &manifest_path)?;
    let _lock = lock_export(out)?;
    prepare_output(out, opts, &sha256_hex(&manifest))?;
    let mut summary = export_scenes(dataset, out, opts, &entries, progress)?;
    let (images, lines, left_out) = assemble(out, opts.format, &entries)?;
    summary.scenes = entries.len();
    summary.images = images;
    summary.lines = lines;
    summary.left_out = left_out;
    Ok(summary)
}

/// The folders of an export in `format`, OUT itself first.
fn output_dirs(out: &Path, format: WireframeFormat) -> Vec<PathBuf> {
    let annotations = Path::new(format.annotation_file(Split::Train))
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_default();
    [
        PathBuf::new(),
        PathBuf::from(PARTS_DIR),
        PathBuf::from(format.image_dir(Split::Train)),
        PathBuf::from(format.image_dir(Split::Test)),
        annotations,
    ]
    .iter()
    .map(|d| out.join(d))
    .collect()
}

/// Creates the output folders, removes the temporary files a killed export left in them, and
/// checks (or writes) the options stamp, so a resumed run never mixes two exports.
fn prepare_output(
    out: &Path,
    opts: &WireframeExportOptions,
    manifest_sha256: &str,
) -> Result<(), DatasetError> {
    for dir in output_dirs(out, opts.format) {
        std::fs::create_dir_all(&dir).map_err(io_err(&dir))?;
        remove_temporaries(&dir, None)?;
    }
    let stamp = json!({
        "format": opts.format.name(),
        "split": opts.split,
        "split_seed": opts.split_seed,
        "rgb": opts.rgb,
        "manifest_sha256": manifest_sha256,
    });
    let path = out.join(STAMP_FILE);
    if let Ok(text) = std::fs::read_to_string(&path) {
        let old: Value = serde_json::from_str(&text).unwrap_or(Value::Null);
        if old != stamp {
            return Err(DatasetError::OptionsMismatch {
                path,
                detail: format!(
                    "an export made with other options or another dataset: {}",
                    text.trim()
                ),
            });
        }
        return Ok(());
    }
    let text = crate::io::pretty_json(&stamp);
    write_atomic(&path, text.as_bytes()).map_err(io_err(&path))
}

/// Exports every scene on `opts.jobs` threads, each taking the next scene not yet taken. The
/// first error stops the other threads after their current scene (each scene's files are
/// atomic and its part file comes last, so a re-run resumes).
fn export_scenes(
    dataset: &Path,
    out: &Path,
    opts: &WireframeExportOptions,
    entries: &[ManifestEntry],
    progress: &(dyn Fn(u64, u64) + Sync),
) -> Result<WireframeExportSummary, DatasetError> {
    let total = entries.len() as u64;
    let next = AtomicUsize::new(0);
    let done = AtomicU64::new(0);
    let failed = AtomicBool::new(false);
    let summary = Mutex::new(WireframeExportSummary::default());
    let worker = || -> Result<(), DatasetError> {
        while !failed.load(Ordering::Relaxed) {
            let Some(entry) = entries.get(next.fetch_add(1, Ordering::Relaxed)) else {
                break;
            };
            let outcome = export_scene(dataset, out, opts, entry).inspect_err(|_| {
                failed.store(true, Ordering::Relaxed);
            })?;
            let mut s = summary.lock().unwrap_or_else(|p| p.into_inner());
            match outcome {
                Some((written, notes)) => {
                    s.new_images += written;
                    s.left_out_notes.extend(notes);
                }
                None => s.resumed += 1,
            }
            drop(s);
            progress(done.fetch_add(1, Ordering::Relaxed) + 1, total);
        }
        Ok(())
    };
    let results: Vec<_> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..opts.jobs.max(1)).map(|_| s.spawn(worker)).collect();
        handles
            .into_iter()
            .map(|h| h.join().unwrap_or_else(|p| std::panic::resume_unwind(p)))
            .collect()
    });
    results.into_iter().collect::<Result<(), _>>()?;
    let mut summary = summary.into_inner().unwrap_or_else(|p| p.into_inner());
    summary.left_out_notes.sort();
    Ok(summary)
}

/// One picture of a scene read from the dataset (hash-checked): its view, drawing and picture.
struct ViewInput {
    /// The view's name (`ne`).
    view: String,
    /// `lines_<view>.json`'s bytes.
    drawing: Vec<u8>,
    /// `view_<view>.png`'s bytes.
    picture: Vec<u8>,
}

/// A scene's export, made in memory: the pictures to write (path relative to OUT, PNG bytes)
/// and its part file, the resume record.
struct ScenePart {
    /// (path relative to OUT, PNG bytes) of each picture exported.
    pictures: Vec<(String, Vec<u8>)>,
    /// The part file's JSON: split, picture hashes, records, pictures left out.
    part: Value,
    /// The pictures left out, each as "<file>: <why>".
    left_out_notes: Vec<String>,
}

/// Exports one scene (its pictures, then its part file); returns how many pictures it wrote
/// and the ones it left out, or `None` when an earlier run had already done it.
fn export_scene(
    dataset: &Path,
    out: &Path,
    opts: &WireframeExportOptions,
    entry: &ManifestEntry,
) -> Result<Option<(usize, Vec<String>)>, DatasetError> {
    let part_path = out.join(PARTS_DIR).join(format!("{}.json", entry.id));
    let scene_dir = dataset.join(&entry.id);
    let mut inputs = Vec::new();
    for view in views_of(entry) {
        let drawing = read_checked(&scene_dir, entry, &format!("lines_{view}.json"))?;
        let picture = read_checked(&scene_dir, entry, &format!("view_{view}.png"))?;
        inputs.push(ViewInput {
            view,
            drawing,
            picture,
        });
    }
    if part_is_complete(&part_path, out) {
        return Ok(None);
    }
    let part = scene_part(&scene_dir, &entry.id, opts, inputs)?;
    for (relative, png) in &part.pictures {
        let path = out.join(relative);
        write_atomic_with(&path, png, FileSync::Verified).map_err(io_err(&path))?;
    }
    let text = part.part.to_string();
    write_atomic_with(&part_path, text.as_bytes(), FileSync::Verified)
        .map_err(io_err(&part_path))?;
    Ok(Some((part.pictures.len(), part.left_out_notes)))
}

/// A scene's pictures and part file from its views' bytes (no file I/O; `scene_dir` names the
/// files in errors).
fn scene_part(
    scene_dir: &Path,
    id: &str,
    opts: &WireframeExportOptions,
    inputs: Vec<ViewInput>,
) -> Result<ScenePart, DatasetError> {
    let split = split_of(id, opts.split_seed, opts.split);
    let (mut records, mut images) = (Vec::new(), serde_json::Map::new());
    let (mut pictures, mut left_out_notes) = (Vec::new(), Vec::new());
    for input in inputs {
        let filename = format!("{id}_{}.png", input.view);
        let (wf, decoded) = view_wireframe(scene_dir, &input)?;
        if let Some(why) = opts.format.loader_refusal(&wf) {
            left_out_notes.push(format!("{filename}: {why}"));
            continue;
        }
        let picture_path = scene_dir.join(format!("view_{}.png", input.view));
        let png = picture_png(opts.rgb, decoded, input.picture).map_err(|message| {
            DatasetError::Input {
                path: picture_path,
                message,
            }
        })?;
        let relative = format!("{}/{filename}", opts.format.image_dir(split));
        images.insert(relative.clone(), json!(sha256_hex(&png)));
        records.push(format_record(opts.format, split, &filename, &wf));
        pictures.push((relative, png));
    }
    let part = json!({
        "split": split_name(split),
        "images": images,
        "records": records,
        "left_out": left_out_notes.len(),
    });
    Ok(ScenePart {
        pictures,
        part,
        left_out_notes,
    })
}

/// The wireframe of one view from its (already hash-checked) drawing and picture bytes, and the
/// decoded picture (its size is the wireframe's).
fn view_wireframe(
    scene_dir: &Path,
    input: &ViewInput,
) -> Result<(Wireframe, DecodedPicture), DatasetError> {
    let lines_path = scene_dir.join(format!("lines_{}.json", input.view));
    let bad = |path: &Path, message: String| DatasetError::Input {
        path: path.to_path_buf(),
        message: format!("{message}; re-run the `blockworld generate` command that made it"),
    };
    let text = std::str::from_utf8(&input.drawing)
        .map_err(|e| bad(&lines_path, format!("not UTF-8 ({e})")))?;
    let drawing = LineDrawing::from_json(text).map_err(|e| bad(&lines_path, e.to_string()))?;
    let picture_path = scene_dir.join(format!("view_{}.png", input.view));
    let decoded = decode_gray(&input.picture).map_err(|e| bad(&picture_path, e.to_string()))?;
    let (w, h) = decoded.gray.dimensions();
    let wf = wireframe_from_drawing(&drawing, w, h).map_err(|e| bad(&lines_path, e.to_string()))?;
    Ok((wf, decoded))
}

/// The exported picture: three-channel with `rgb`; otherwise the dataset's 8-bit gray PNG
/// byte for byte (re-encoded only when it was not 8-bit gray).
fn picture_png(rgb: bool, decoded: DecodedPicture, bytes: Vec<u8>) -> Result<Vec<u8>, String> {
    let encoded = if rgb {
        encode_png_rgb8(&image::DynamicImage::ImageLuma8(decoded.gray).to_rgb8())
    } else if decoded.converted_from.is_none() {
        return Ok(bytes);
    } else {
        encode_png_gray8(&decoded.gray)
    };
    encoded.map_err(|e| format!("encoding the exported picture: {e}"))
}

/// The record of one picture in `format` on side `split` (LETR's ids are set at assembly).
fn format_record(format: WireframeFormat, split: Split, filename: &str, wf: &Wireframe) -> Value {
    match (format, split) {
        (WireframeFormat::Hawp, Split::Train) => hawp_train_record(filename, wf),
        (WireframeFormat::Hawp, Split::Test) => hawp_test_record(filename, wf),
        (WireframeFormat::Lcnn, _) => lcnn_record(filename, wf),
        (WireframeFormat::Letr, _) => json!({
            "image": letr_image(0, filename, wf),
            "annotations": letr_annotations(0, 0, wf),
        }),
    }
}

fn split_name(split: Split) -> &'static str {
    match split {
        Split::Train => "train",
        Split::Test => "test",
    }
}

/// One split's annotation text as it is assembled: the serialized items (HAWP, L-CNN) or the
/// COCO images and annotations (LETR), comma-joined.
#[derive(Default)]
struct SplitText {
    items: String,
    annotations: String,
}

/// Joins the part files, in scene order, into the format's annotation files; returns the
/// numbers of images, lines and pictures left out. Streams: one part in memory at a time, each
/// record serialized as it is read (the records as JSON values would take 20 times the text).
fn assemble(
    out: &Path,
    format: WireframeFormat,
    entries: &[ManifestEntry],
) -> Result<(usize, usize, usize), DatasetError> {
    let mut texts = [SplitText::default(), SplitText::default()];
    let (mut images, mut lines, mut left_out) = (0, 0, 0);
    let mut next_ids = (1u64, 1u64);
    for entry in entries {
        let mut part = read_part(out, entry)?;
        let text = &mut texts[usize::from(part["split"] == "test")];
        left_out += part["left_out"].as_u64().unwrap_or(0) as usize;
        let Value::Array(items) = part["records"].take() else {
            continue;
        };
        for item in items {
            images += 1;
            if format == WireframeFormat::Letr {
                lines += push_letr(text, item, &mut next_ids);
            } else {
                lines += line_count(&item);
                push_json(&mut text.items, &item);
            }
        }
    }
    for (text, split) in texts.iter().zip([Split::Train, Split::Test]) {
        let doc = if format == WireframeFormat::Letr {
            let categories = &letr_document(Vec::new(), Vec::new())["categories"];
            format!(
                "{{\"annotations\":[{}],\"categories\":{categories},\"images\":[{}]}}\n",
                text.annotations, text.items
            )
        } else {
            format!("[{}]\n", text.items)
        };
        let path = out.join(format.annotation_file(split));
        write_atomic(&path, doc.as_bytes()).map_err(io_err(&path))?;
    }
    Ok((images, lines, left_out))
}

fn line_count(record: &Value) -> usize {
    let key = if record.get("edges_positive").is_some() {
        "edges_positive"
    } else {
        "lines"
    };
    record[key].as_array().map_or(0, Vec::len)
}

/// Appends one LETR picture (its COCO image and annotations) to `text`, numbering images and
/// annotations from `next_ids` (ids run on across the two splits, so none repeats); returns its
/// number of lines.
fn push_letr(text: &mut SplitText, mut item: Value, next_ids: &mut (u64, u64)) -> usize {
    let image_id = next_ids.0;
    next_ids.0 += 1;
    item["image"]["id"] = json!(image_id);
    push_json(&mut text.items, &item["image"]);
    let Value::Array(anns) = item["annotations"].take() else {
        return 0;
    };
    let n = anns.len();
    for mut ann in anns {
        ann["id"] = json!(next_ids.1);
        ann["image_id"] = json!(image_id);
        next_ids.1 += 1;
        push_json(&mut text.annotations, &ann);
    }
    n
}
