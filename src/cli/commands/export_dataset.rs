//! `blockworld export-dataset DATASET --format hawp|lcnn|letr -o OUT [--split 0.9]
//! [--split-seed S] [--rgb] [--jobs N]` (docs/wireframe.md "Wireframe datasets"): a generated dataset's
//! exact line drawings as training sets for learned wireframe parsers.
//!
//! Streams scene by scene (on `--jobs` threads): each scene's pictures and records are written
//! (atomically, temporary name and rename) before its part file `OUT/.parts/<id>.json`, the
//! resume record; re-running the same command skips the scenes whose part file reads and whose
//! pictures match the sha256 it lists. Because that check catches a lost or torn file, these
//! files are not synced one by one (a sync per file made the disk the bottleneck); the
//! annotation files, assembled from the parts at the end, are. Every file read from the dataset
//! is checked against its sha256 in `manifest.jsonl`.

use anyhow::{bail, Context};
use blockworld::dataset::{parse_manifest, sha256_hex, ManifestEntry, MANIFEST_NAME};
use blockworld::drawing::LineDrawing;
use blockworld::export::wireframe::{
    hawp_test_record, hawp_train_record, lcnn_record, letr_annotations, letr_document, letr_image,
    split_of, wireframe_from_drawing, Split, Wireframe, WireframeFormat,
};
use blockworld::io::{write_atomic, write_atomic_with, FileSync};
use blockworld::output::{encode_png_gray8, encode_png_rgb8};
use blockworld::vision::{decode_gray, DecodedPicture};
use indicatif::{ProgressBar, ProgressStyle};
use serde_json::{json, Value};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::time::Instant;

/// The formats on the command line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum FormatArg {
    /// HAWP: images/, train.json, test.json.
    Hawp,
    /// L-CNN: images/, train.json, valid.json.
    Lcnn,
    /// LETR (COCO style): train2017/, val2017/, annotations/lines_{train2017,val2017}.json.
    Letr,
}

impl FormatArg {
    /// The library's format.
    pub fn format(self) -> WireframeFormat {
        match self {
            FormatArg::Hawp => WireframeFormat::Hawp,
            FormatArg::Lcnn => WireframeFormat::Lcnn,
            FormatArg::Letr => WireframeFormat::Letr,
        }
    }
}

/// Options of `blockworld export-dataset`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// A dataset made by `blockworld generate` (with its manifest.jsonl).
    pub dataset: PathBuf,
    /// Output format.
    #[arg(long, value_enum)]
    pub format: FormatArg,
    /// Output directory (created; re-running the same command resumes).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Fraction of scenes in the training set (by a seeded hash of the scene id).
    #[arg(long, default_value_t = 0.9)]
    pub split: f64,
    /// Seed of the split hash.
    #[arg(long, default_value_t = 0)]
    pub split_seed: u64,
    /// Write three-channel (RGB) PNGs; 8-bit grayscale otherwise. The current HAWP, L-CNN and
    /// LETR loaders take gray; HAWP v1 (its `parsing/` tree) needs RGB.
    #[arg(long)]
    pub rgb: bool,
    /// Scenes exported at once. Pictures and part files are written to a temporary name and
    /// renamed without a sync each (a resumed run re-checks them by sha256); the annotation
    /// files assembled at the end are synced. The output's bytes do not depend on it.
    #[arg(long, default_value_t = DEFAULT_JOBS)]
    pub jobs: usize,
}

/// Default `--jobs`.
pub const DEFAULT_JOBS: usize = 4;

/// The part file's folder: one resume record per scene.
const PARTS_DIR: &str = ".parts";
/// The options stamp of an export folder.
const STAMP_FILE: &str = "export.json";

/// What an export did.
#[derive(Debug, Clone, Copy)]
pub struct ExportSummary {
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
    /// Lines in the export.
    pub lines: usize,
    /// Wall time of this run, s.
    pub wall_s: f64,
}

/// Runs `blockworld export-dataset`.
pub fn run(args: Args) -> anyhow::Result<()> {
    let s = export(&args)?;
    println!(
        "{} scenes ({} kept from an earlier run): {} images, {} lines, {} pictures left out (the loader cannot take them); {} images exported in {:.2} s ({:.1} images/s) -> {}",
        s.scenes,
        s.resumed,
        s.images,
        s.lines,
        s.left_out,
        s.new_images,
        s.wall_s,
        s.new_images as f64 / s.wall_s.max(1e-9),
        args.output.display()
    );
    Ok(())
}

/// Exports the dataset (module doc) and says what it did.
pub fn export(args: &Args) -> anyhow::Result<ExportSummary> {
    if !(0.0..=1.0).contains(&args.split) {
        bail!(
            "--split {} must lie in 0..=1 (the training fraction)",
            args.split
        );
    }
    let started = Instant::now();
    let entries = read_manifest(&args.dataset)?;
    prepare_output(args)?;
    let (resumed, new_images) = export_scenes(args, &entries)?;
    let (images, lines, left_out) = assemble(args, &entries)?;
    Ok(ExportSummary {
        scenes: entries.len(),
        resumed,
        images,
        new_images,
        left_out,
        lines,
        wall_s: started.elapsed().as_secs_f64(),
    })
}

/// Exports every scene on `--jobs` threads, each taking the next scene not yet taken; returns
/// how many scenes an earlier run had done and how many pictures this run wrote. The first
/// error stops the other threads after their current scene (each scene's files are atomic and
/// its part file comes last, so a re-run resumes).
fn export_scenes(args: &Args, entries: &[ManifestEntry]) -> anyhow::Result<(usize, usize)> {
    let total = entries.len() as u64;
    let bar = progress_bar(total);
    let next = AtomicUsize::new(0);
    let done = AtomicU64::new(0);
    let failed = AtomicBool::new(false);
    let worker = || -> anyhow::Result<(usize, usize)> {
        let (mut resumed, mut new_images) = (0, 0);
        while !failed.load(Ordering::Relaxed) {
            let Some(entry) = entries.get(next.fetch_add(1, Ordering::Relaxed)) else {
                break;
            };
            match export_scene(args, entry) {
                Ok(Some(n)) => new_images += n,
                Ok(None) => resumed += 1,
                Err(e) => {
                    failed.store(true, Ordering::Relaxed);
                    return Err(e);
                }
            }
            bar.tick_to(done.fetch_add(1, Ordering::Relaxed) + 1, total);
        }
        Ok((resumed, new_images))
    };
    let results: Vec<_> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..args.jobs.max(1)).map(|_| s.spawn(worker)).collect();
        handles
            .into_iter()
            .map(|h| h.join().unwrap_or_else(|p| std::panic::resume_unwind(p)))
            .collect()
    });
    bar.finish();
    let (mut resumed, mut new_images) = (0, 0);
    for r in results {
        let (a, b) = r?;
        resumed += a;
        new_images += b;
    }
    Ok((resumed, new_images))
}

/// Reads `DATASET/manifest.jsonl`.
fn read_manifest(dataset: &Path) -> anyhow::Result<Vec<ManifestEntry>> {
    let path = dataset.join(MANIFEST_NAME);
    let text = std::fs::read_to_string(&path).with_context(|| {
        format!(
            "reading {}: finish the dataset first (re-run its `blockworld generate`, or `blockworld merge` for shards)",
            path.display()
        )
    })?;
    Ok(parse_manifest(&text, &path)?)
}

/// Creates the output folders and checks (or writes) the options stamp, so a resumed run never
/// mixes two exports.
fn prepare_output(args: &Args) -> anyhow::Result<()> {
    let format = args.format.format();
    for dir in [
        PathBuf::from(PARTS_DIR),
        PathBuf::from(format.image_dir(Split::Train)),
        PathBuf::from(format.image_dir(Split::Test)),
        PathBuf::from(format.annotation_file(Split::Train))
            .parent()
            .map(Path::to_path_buf)
            .unwrap_or_default(),
    ] {
        let path = args.output.join(dir);
        std::fs::create_dir_all(&path).with_context(|| format!("creating {}", path.display()))?;
    }
    let manifest = std::fs::read(args.dataset.join(MANIFEST_NAME))?;
    let stamp = json!({
        "format": format.name(),
        "split": args.split,
        "split_seed": args.split_seed,
        "rgb": args.rgb,
        "manifest_sha256": sha256_hex(&manifest),
    });
    let path = args.output.join(STAMP_FILE);
    if let Ok(text) = std::fs::read_to_string(&path) {
        let old: Value = serde_json::from_str(&text).unwrap_or(Value::Null);
        if old != stamp {
            bail!(
                "{} holds an export made with other options or another dataset ({text}); use another -o or delete it",
                args.output.display()
            );
        }
        return Ok(());
    }
    let text = blockworld::io::pretty_json(&stamp);
    write_atomic(&path, text.as_bytes()).with_context(|| format!("writing {}", path.display()))
}

/// Exports one scene (its pictures, then its part file); returns how many pictures it wrote, or
/// `None` when an earlier run had already done it. Every dataset file read is checked against
/// the manifest.
fn export_scene(args: &Args, entry: &ManifestEntry) -> anyhow::Result<Option<usize>> {
    let part_path = args
        .output
        .join(PARTS_DIR)
        .join(format!("{}.json", entry.id));
    let views = views_of(entry);
    let split = split_of(&entry.id, args.split_seed, args.split);
    let scene_dir = args.dataset.join(&entry.id);
    let mut inputs = Vec::with_capacity(views.len());
    for view in &views {
        let drawing = read_checked(&scene_dir, entry, &format!("lines_{view}.json"))?;
        let picture = read_checked(&scene_dir, entry, &format!("view_{view}.png"))?;
        inputs.push((view, drawing, picture));
    }
    if part_is_complete(&part_path, &args.output) {
        return Ok(None);
    }
    let format = args.format.format();
    let mut records = Vec::with_capacity(views.len());
    let mut images = serde_json::Map::new();
    let mut left_out = 0usize;
    for (view, drawing_bytes, picture_bytes) in inputs {
        let filename = format!("{}_{view}.png", entry.id);
        let (wf, decoded) = view_wireframe(&scene_dir, view, drawing_bytes, &picture_bytes)?;
        if let Some(why) = format.loader_refusal(&wf) {
            eprintln!("export-dataset: {filename} left out: {why}");
            left_out += 1;
            continue;
        }
        let png = picture_png(args.rgb, decoded, picture_bytes)?;
        let image_path = args.output.join(format.image_dir(split)).join(&filename);
        let relative = format!("{}/{filename}", format.image_dir(split));
        images.insert(relative, json!(sha256_hex(&png)));
        write_atomic_with(&image_path, &png, FileSync::Verified)
            .with_context(|| format!("writing {}", image_path.display()))?;
        records.push(format_record(format, split, &filename, &wf));
    }
    let written = records.len();
    let part = json!({
        "split": split_name(split),
        "images": images,
        "records": records,
        "left_out": left_out,
    });
    write_atomic_with(&part_path, part.to_string().as_bytes(), FileSync::Verified)
        .with_context(|| format!("writing {}", part_path.display()))?;
    Ok(Some(written))
}

/// The wireframe of one view from its (already hash-checked) drawing and picture bytes, and the
/// decoded picture (its size is the wireframe's).
fn view_wireframe(
    scene_dir: &Path,
    view: &str,
    drawing_bytes: Vec<u8>,
    picture_bytes: &[u8],
) -> anyhow::Result<(Wireframe, DecodedPicture)> {
    let lines_path = scene_dir.join(format!("lines_{view}.json"));
    let text = String::from_utf8(drawing_bytes)
        .with_context(|| format!("{}: not UTF-8", lines_path.display()))?;
    let drawing =
        LineDrawing::from_json(&text).with_context(|| format!("{}", lines_path.display()))?;
    let picture_path = scene_dir.join(format!("view_{view}.png"));
    let decoded =
        decode_gray(picture_bytes).with_context(|| format!("{}", picture_path.display()))?;
    let (w, h) = decoded.gray.dimensions();
    let wf = wireframe_from_drawing(&drawing, w, h)
        .with_context(|| format!("{}", lines_path.display()))?;
    Ok((wf, decoded))
}

/// The exported picture: three-channel with `--rgb`; otherwise the dataset's 8-bit gray PNG
/// byte for byte (re-encoded only when it was not 8-bit gray).
fn picture_png(
    rgb: bool,
    decoded: DecodedPicture,
    picture_bytes: Vec<u8>,
) -> anyhow::Result<Vec<u8>> {
    Ok(if rgb {
        encode_png_rgb8(&image::DynamicImage::ImageLuma8(decoded.gray).to_rgb8())?
    } else if decoded.converted_from.is_none() {
        picture_bytes
    } else {
        encode_png_gray8(&decoded.gray)?
    })
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

/// Whether an earlier run finished the scene: its part file reads and every picture it lists
/// is there with the sha256 it lists (like `generate`'s resume, docs/datasets.md "Settling").
fn part_is_complete(part_path: &Path, output: &Path) -> bool {
    let Ok(text) = std::fs::read_to_string(part_path) else {
        return false;
    };
    let Ok(part) = serde_json::from_str::<Value>(&text) else {
        return false;
    };
    let Some(images) = part["images"].as_object() else {
        return false;
    };
    images.iter().all(|(relative, sha)| {
        std::fs::read(output.join(relative))
            .is_ok_and(|bytes| sha.as_str() == Some(sha256_hex(&bytes).as_str()))
    })
}

/// The views of a scene: every `lines_<v>.json` in its manifest line that has a `view_<v>.png`.
fn views_of(entry: &ManifestEntry) -> Vec<String> {
    entry
        .files
        .keys()
        .filter_map(|name| name.strip_prefix("lines_")?.strip_suffix(".json"))
        .filter(|v| entry.files.contains_key(&format!("view_{v}.png")))
        .map(str::to_string)
        .collect()
}

/// Reads `dir/name` and refuses it when its sha256 differs from the manifest's.
fn read_checked(dir: &Path, entry: &ManifestEntry, name: &str) -> anyhow::Result<Vec<u8>> {
    let path = dir.join(name);
    let bytes = std::fs::read(&path).with_context(|| {
        format!(
            "reading {}: the dataset is incomplete; re-run the `blockworld generate` command that made it",
            path.display()
        )
    })?;
    let want = entry.files.get(name).map(String::as_str).unwrap_or("");
    let got = sha256_hex(&bytes);
    if got != want {
        bail!(
            "{}: sha256 {got} does not match {MANIFEST_NAME} ({want}); the dataset is damaged: re-run the `blockworld generate` command that made it (it redoes scenes whose files fail their hash)",
            path.display()
        );
    }
    Ok(bytes)
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

fn push_json(list: &mut String, item: &Value) {
    if !list.is_empty() {
        list.push(',');
    }
    list.push_str(&item.to_string());
}

/// Joins the part files, in scene order, into the format's annotation files; returns the
/// numbers of images, lines and pictures left out. Streams: one part in memory at a time, each
/// record serialized as it is read (the records as JSON values would take 20 times the text).
fn assemble(args: &Args, entries: &[ManifestEntry]) -> anyhow::Result<(usize, usize, usize)> {
    let format = args.format.format();
    let mut texts = [SplitText::default(), SplitText::default()];
    let (mut images, mut lines, mut left_out) = (0, 0, 0);
    let mut next_ids = (1u64, 1u64);
    for entry in entries {
        let mut part = read_part(args, entry)?;
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
        let path = args.output.join(format.annotation_file(split));
        write_atomic(&path, doc.as_bytes())
            .with_context(|| format!("writing {}", path.display()))?;
    }
    Ok((images, lines, left_out))
}

/// Reads a scene's part file.
fn read_part(args: &Args, entry: &ManifestEntry) -> anyhow::Result<Value> {
    let path = args
        .output
        .join(PARTS_DIR)
        .join(format!("{}.json", entry.id));
    let text =
        std::fs::read_to_string(&path).with_context(|| format!("reading {}", path.display()))?;
    serde_json::from_str(&text).with_context(|| {
        format!(
            "{}: damaged; delete it and re-run to redo the scene",
            path.display()
        )
    })
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

/// Progress: an indicatif bar on a terminal, plain log lines (about every 5%) otherwise.
enum Progress {
    Bar(ProgressBar),
    Log { step: u64, started: Instant },
}

fn progress_bar(total: u64) -> Progress {
    if std::io::stderr().is_terminal() {
        let bar = ProgressBar::new(total);
        bar.set_style(
            ProgressStyle::with_template(
                "{bar:40} {pos}/{len} scenes  {per_sec}  ETA {eta}  {elapsed_precise}",
            )
            .expect("valid template"),
        );
        Progress::Bar(bar)
    } else {
        Progress::Log {
            step: (total / 20).max(1),
            started: Instant::now(),
        }
    }
}

impl Progress {
    fn tick_to(&self, done: u64, total: u64) {
        match self {
            Progress::Bar(bar) => bar.set_position(done),
            Progress::Log { step, started } => {
                if done % step == 0 || done == total {
                    let secs = started.elapsed().as_secs_f64().max(1e-9);
                    eprintln!(
                        "export-dataset: {done}/{total} scenes, {:.1} scenes/s",
                        done as f64 / secs
                    );
                }
            }
        }
    }

    fn finish(&self) {
        if let Progress::Bar(bar) = self {
            bar.finish();
        }
    }
}
