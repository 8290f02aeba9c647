//! Writing a dataset to disk (the only I/O in `dataset`): `dataset.json` with the options, one
//! folder per scene (`scene.json`, the rendered views and their ground truth, `done.json`), and
//! the manifest; resuming an interrupted run; merging shard manifests.
//!
//! Every file goes through [`crate::io::write_atomic`]. A scene counts as done only when its
//! `done.json` (its manifest line) exists and every file it lists has the listed sha256, so
//! re-running the same command after a kill or a full disk redoes exactly the scenes that are
//! missing or damaged.

use super::generate::{draw_scene, DrawnScene, SceneSpec, StabilityOptions};
use super::manifest::{
    manifest_text, parse_manifest, parse_shard_manifest_name, sha256_hex, shard_manifest_name,
    ManifestEntry, MANIFEST_NAME,
};
use super::{DatasetError, Family, Shard};
use crate::camera::CornerView;
use crate::io::{write_atomic, write_atomic_with, FileSync};
use crate::physics::SettleParams;
use crate::render::{RenderOptions, RenderedView, Renderer};
use crate::scene::{scene_to_json, write_scene_with, Scene};
use rayon::prelude::*;
use serde_json::{json, Value};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

/// The options file at the top of a dataset.
pub const DATASET_FILE: &str = "dataset.json";
/// A scene's completion record: its manifest line, written last.
pub const DONE_FILE: &str = "done.json";
/// The settled scene in each scene folder.
const SCENE_FILE: &str = "scene.json";
/// Version of the dataset layout, bumped when files change meaning.
const LAYOUT_VERSION: u32 = 1;

/// Everything that decides a dataset's content, plus how to slice and parallelise the work.
#[derive(Debug, Clone)]
pub struct DatasetOptions {
    /// Number of scenes in the whole dataset (all shards).
    pub count: u64,
    /// Dataset seed; scene `i` uses `scene_seed(seed, i)`.
    pub seed: u64,
    /// Families, cycled: scene `i` is of `families[i % len]`.
    pub families: Vec<Family>,
    /// Views to render; empty writes `scene.json` only.
    pub views: Vec<CornerView>,
    /// Render options; each scene's noise seed is replaced by its scene seed.
    pub render: RenderOptions,
    /// Settling parameters.
    pub settle: SettleParams,
    /// Which slice this run writes.
    pub shard: Shard,
    /// Worker threads; 0 = all cores. Does not change the content.
    pub jobs: usize,
    /// A further file per scene, beside `scene.json` and in the manifest (`generate --gltf`
    /// adds `scene.glb`); `None` (the default) writes none.
    pub scene_file: Option<SceneFileEncoder>,
    /// When each scene's files reach the disk: [`FileSync::Verified`] (the default of
    /// `generate`) syncs none of them, its done marker included, since a resume parses the
    /// marker and re-hashes every file it lists (docs/datasets.md "Settling", durability);
    /// [`FileSync::EveryFile`] (`--fsync`) syncs every file. Does not change the content.
    pub file_sync: FileSync,
    /// A stability dataset (`--keep-unstable`, docs/stability.md): scenes that do not stand
    /// are kept and every scene is labelled; `None` (the default) keeps stable scenes only.
    pub stability: Option<StabilityOptions>,
}

/// The recorded trajectory in each scene folder of a stability dataset (`--trajectory`).
pub const TRAJECTORY_FILE: &str = "trajectory.bin";
/// The fall as an animated glTF in each scene folder (`--trajectory --gltf`).
pub const FALL_FILE: &str = "fall.glb";

/// A further per-scene file: its name in the scene folder and the function that encodes the
/// settled scene into its bytes. The encoder comes from the caller (the CLI passes the glTF
/// exporter), so this stage does not depend on the exporter.
#[derive(Debug, Clone, Copy)]
pub struct SceneFileEncoder {
    /// File name in the scene folder (`scene.glb`).
    pub name: &'static str,
    /// Encodes a scene; the error message names what is wrong with it.
    pub encode: fn(&Scene) -> Result<Vec<u8>, String>,
}

/// Seconds spent per stage, summed over the scenes generated (not resumed).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StageTimes {
    /// Drawing, validating and settling (all attempts).
    pub settle_s: f64,
    /// Rendering views and ground truth.
    pub render_s: f64,
    /// Encoding and writing files, hashing.
    pub write_s: f64,
}

impl StageTimes {
    fn add(&mut self, o: &StageTimes) {
        self.settle_s += o.settle_s;
        self.render_s += o.render_s;
        self.write_s += o.write_s;
    }
}

/// What a run did.
#[derive(Debug, Clone)]
pub struct GenerateSummary {
    /// Scenes generated in this run.
    pub generated: u64,
    /// Scenes found complete and kept.
    pub resumed: u64,
    /// Draws rejected because they did not settle stably.
    pub unstable_draws: u64,
    /// Draws rejected before settling.
    pub unplaceable_draws: u64,
    /// Draws rejected because they stood when an unstable scene was wanted (stability datasets).
    pub stood_draws: u64,
    /// Scenes of this run's manifest that do not stand (stability datasets).
    pub unstable_scenes: u64,
    /// Time per stage over the generated scenes.
    pub times: StageTimes,
    /// The manifest written (`manifest.jsonl` or the shard's).
    pub manifest: PathBuf,
    /// Scenes in this run's manifest (generated plus kept).
    pub scenes: u64,
    /// Blocks in those scenes.
    pub blocks: u64,
}

/// Per-scene outcome inside a run.
struct SceneOutcome {
    entry: ManifestEntry,
    generated: Option<(StageTimes, u32, u32, u32)>,
}

pub(super) fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> DatasetError + '_ {
    move |source| DatasetError::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// The `dataset.json` content: everything that decides the files, nothing about jobs or shards.
/// The render and settle parameters are their structs serialized whole, so a new field can
/// never go unrecorded and let a resume mix two datasets.
fn dataset_json(opts: &DatasetOptions) -> Value {
    let mut render = serde_json::to_value(opts.render).expect("render options serialize");
    render["noise_seed"] = json!("the scene's seed");
    let mut v = json!({
        "version": LAYOUT_VERSION,
        "generator": format!("blockworld {}", env!("CARGO_PKG_VERSION")),
        "count": opts.count,
        "seed": opts.seed,
        "scene_seed": "splitmix64(seed ^ splitmix64(index))",
        "families": opts.families.iter().map(|f| f.name()).collect::<Vec<_>>(),
        "family_of_scene": "families[index % len(families)]",
        "views": opts.views.iter().map(|v| v.name()).collect::<Vec<_>>(),
        "render": render,
        "settle": serde_json::to_value(opts.settle).expect("settle parameters serialize"),
    });
    // Listed only when there is one, so datasets without it keep their dataset.json; a resume
    // with or without it is refused as other options.
    if let Some(f) = &opts.scene_file {
        v["scene_files"] = json!([f.name]);
    }
    if let Some(st) = &opts.stability {
        v["stability"] = json!({
            "stable_fraction": st.stable_fraction,
            "scene_is_drawn_stable": "splitmix64(scene seed ^ 0x535441424c452121) / 2^64 < stable_fraction",
            "trajectory": st.trajectory,
            "trajectory_fps": crate::physics::TRAJECTORY_FPS,
            "fall_gltf": st.fall_gltf,
        });
        // Listed only when asked for, so stability datasets without frames keep their file.
        if let Some(f) = &st.frames {
            v["stability"]["trajectory_views"] =
                json!(f.views.iter().map(|v| v.name()).collect::<Vec<_>>());
            v["stability"]["trajectory_every"] = json!(f.every);
            v["stability"]["trajectory_frames"] =
                json!("frames 0, every, 2 every, ... and the last: frames/f<frame>_<file>");
        }
    }
    v
}

/// Encodes and writes the per-scene file; returns its name and sha256.
fn write_scene_file(
    scene_dir: &Path,
    id: &str,
    scene: &Scene,
    f: &SceneFileEncoder,
    sync: FileSync,
) -> Result<(String, String), DatasetError> {
    let bytes = (f.encode)(scene).map_err(|message| DatasetError::SceneFile {
        id: id.to_string(),
        name: f.name.to_string(),
        message,
    })?;
    let path = scene_dir.join(f.name);
    write_atomic_with(&path, &bytes, sync).map_err(io_err(&path))?;
    Ok((f.name.to_string(), sha256_hex(&bytes)))
}

fn check_options(opts: &DatasetOptions) -> Result<(), DatasetError> {
    opts.render
        .validate()
        .map_err(|e| DatasetError::Options(e.to_string()))?;
    if opts.count == 0 {
        return Err(DatasetError::Options("--count must be at least 1".into()));
    }
    if opts.families.is_empty() {
        return Err(DatasetError::Options(
            "at least one family is needed".into(),
        ));
    }
    if let Some(f) = opts.stability.as_ref().and_then(|s| s.frames.as_ref()) {
        if !opts.stability.as_ref().is_some_and(|s| s.trajectory) {
            return Err(DatasetError::Options(
                "--trajectory-views needs --trajectory".into(),
            ));
        }
        f.check(&opts.settle, &opts.render)
            .map_err(DatasetError::Options)?;
    }
    if opts.jobs > MAX_JOBS {
        return Err(DatasetError::Options(format!(
            "--jobs {}: at most {MAX_JOBS} worker threads (0 = one per core)",
            opts.jobs
        )));
    }
    Ok(())
}

/// Most worker threads a run starts: `--jobs 1000000` made rayon spawn threads until the run
/// hung; no machine this runs on has more cores than this.
pub const MAX_JOBS: usize = 1024;

/// Writes `dataset.json`, or checks that the one there matches these options.
fn write_or_check_dataset_json(dir: &Path, opts: &DatasetOptions) -> Result<(), DatasetError> {
    let path = dir.join(DATASET_FILE);
    let wanted = dataset_json(opts);
    match std::fs::read_to_string(&path) {
        Ok(text) => {
            let found: Value = serde_json::from_str(&text).unwrap_or(Value::Null);
            if found != wanted {
                let keys: Vec<String> = wanted
                    .as_object()
                    .expect("object")
                    .iter()
                    .filter(|(k, v)| found.get(k.as_str()) != Some(v))
                    .map(|(k, _)| k.clone())
                    .chain(
                        found
                            .get("scene_files")
                            .filter(|_| wanted.get("scene_files").is_none())
                            .map(|_| "scene_files".to_string()),
                    )
                    .collect();
                return Err(DatasetError::OptionsMismatch {
                    path,
                    detail: format!("differs in {}", keys.join(", ")),
                });
            }
            Ok(())
        }
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            let text = crate::io::pretty_json(&wanted);
            // Shards start together: another worker may write the same file first; an identical
            // file is ours.
            write_atomic(&path, text.as_bytes()).or_else(|e| match std::fs::read_to_string(&path) {
                Ok(found) if found == text => Ok(()),
                _ => Err(io_err(&path)(e)),
            })
        }
        Err(e) => Err(io_err(&path)(e)),
    }
}

/// Removes temporary files (`.<name>.tmp.<pid>.<random>`, see `io::temp_path`) an interrupted run left in `dir`, for every
/// name when `only` is `None`, else for that file name only. Call it only on files this run
/// owns: other shards may be writing beside it.
pub(super) fn remove_temporaries(dir: &Path, only: Option<&str>) -> Result<(), DatasetError> {
    let entries = match std::fs::read_dir(dir) {
        Ok(e) => e,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(()),
        Err(e) => return Err(io_err(dir)(e)),
    };
    for entry in entries.flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        let is_temp = match only {
            None => name.starts_with('.') && name.contains(".tmp."),
            Some(file) => name.starts_with(&format!(".{file}.tmp.")),
        };
        if is_temp {
            std::fs::remove_file(entry.path()).map_err(io_err(&entry.path()))?;
        }
    }
    Ok(())
}

/// The scene's completion record, if it exists, matches `spec` and every file it lists has
/// its sha256.
fn completed_entry(scene_dir: &Path, spec: &SceneSpec) -> Option<ManifestEntry> {
    let text = std::fs::read_to_string(scene_dir.join(DONE_FILE)).ok()?;
    let entry: ManifestEntry = serde_json::from_str(&text).ok()?;
    let matches = entry.id == spec.id()
        && entry.index == spec.index
        && entry.seed == spec.seed
        && entry.family == spec.family.name();
    let intact = entry.files.iter().all(|(name, sha)| {
        std::fs::read(scene_dir.join(name)).is_ok_and(|bytes| sha256_hex(&bytes) == *sha)
    });
    (matches && intact).then_some(entry)
}

/// Generates, renders and writes one scene; returns its manifest entry.
fn produce_scene(
    dir: &Path,
    spec: &SceneSpec,
    opts: &DatasetOptions,
    renderer: Option<&Renderer>,
) -> Result<SceneOutcome, DatasetError> {
    let scene_dir = dir.join(spec.id());
    if let Some(entry) = completed_entry(&scene_dir, spec) {
        return Ok(SceneOutcome {
            entry,
            generated: None,
        });
    }
    let mut times = StageTimes::default();
    let t = Instant::now();
    let drawn = draw_scene(spec, &opts.settle, opts.stability.as_ref())?;
    times.settle_s = t.elapsed().as_secs_f64();

    let t = Instant::now();
    let views = render_scene_views(spec, opts, renderer, &drawn.scene)?;
    times.render_s = t.elapsed().as_secs_f64();

    let t = Instant::now();
    let mut files = write_scene_files(&scene_dir, spec, opts, &drawn.scene, &views)?;
    files.extend(write_fall_files(&scene_dir, spec, opts, &drawn)?);
    let t_frames = Instant::now();
    files.extend(super::frames::write_trajectory_frames(
        &scene_dir, spec, opts, &drawn, renderer,
    )?);
    times.render_s += t_frames.elapsed().as_secs_f64();
    let expect = drawn.scene.expect.clone().unwrap_or(crate::scene::Expect {
        supported: true,
        reason: None,
    });
    let entry = ManifestEntry {
        id: spec.id(),
        index: spec.index,
        family: spec.family.name().to_string(),
        seed: spec.seed,
        blocks: drawn.scene.blocks.len(),
        supported: expect.supported,
        reason: expect.reason,
        attempts: drawn.attempts,
        stable: opts.stability.as_ref().map(|_| drawn.report.stable),
        files,
    };
    // Written last and, by default, not synced: after a power loss a marker that did not reach
    // the disk whole fails to parse, or lists hashes its files fail, and the scene is redone.
    let done = scene_dir.join(DONE_FILE);
    write_atomic_with(&done, entry.to_line().as_bytes(), opts.file_sync).map_err(io_err(&done))?;
    times.write_s = t.elapsed().as_secs_f64();
    Ok(SceneOutcome {
        entry,
        generated: Some((times, drawn.unstable, drawn.unplaceable, drawn.stood)),
    })
}

/// A stability dataset's `trajectory.bin` and `fall.glb` when asked for; each name and sha256.
fn write_fall_files(
    scene_dir: &Path,
    spec: &SceneSpec,
    opts: &DatasetOptions,
    drawn: &DrawnScene,
) -> Result<BTreeMap<String, String>, DatasetError> {
    let mut files = BTreeMap::new();
    let (Some(st), Some(t)) = (&opts.stability, &drawn.trajectory) else {
        return Ok(files);
    };
    let mut write = |name: &str, bytes: &[u8]| -> Result<(), DatasetError> {
        let path = scene_dir.join(name);
        write_atomic_with(&path, bytes, opts.file_sync).map_err(io_err(&path))?;
        files.insert(name.to_string(), sha256_hex(bytes));
        Ok(())
    };
    write(TRAJECTORY_FILE, &t.to_bytes())?;
    if st.fall_gltf {
        let glb =
            crate::export::scene_fall_to_glb(&drawn.scene, &t.times_s, &t.frames).map_err(|e| {
                DatasetError::SceneFile {
                    id: spec.id(),
                    name: FALL_FILE.to_string(),
                    message: e.to_string(),
                }
            })?;
        write(FALL_FILE, &glb)?;
    }
    Ok(files)
}

/// The scene's views through `renderer` with the scene's own seed; none when the dataset
/// asks for no views.
fn render_scene_views(
    spec: &SceneSpec,
    opts: &DatasetOptions,
    renderer: Option<&Renderer>,
    scene: &Scene,
) -> Result<Vec<RenderedView>, DatasetError> {
    match (opts.views.is_empty(), renderer) {
        (true, _) => Ok(Vec::new()),
        (false, None) => Err(DatasetError::NoRenderer),
        (false, Some(r)) => {
            let render_opts = RenderOptions {
                seed: spec.seed,
                ..opts.render
            };
            r.render_views(scene, &opts.views, &render_opts)
                .map_err(|source| DatasetError::Render {
                    id: spec.id(),
                    source,
                })
        }
    }
}

/// Writes the scene folder's files but its `done.json` (scene, optional scene file, views,
/// `look.json` of the varied look) and returns each file's name and sha256.
fn write_scene_files(
    scene_dir: &Path,
    spec: &SceneSpec,
    opts: &DatasetOptions,
    scene: &Scene,
    views: &[RenderedView],
) -> Result<BTreeMap<String, String>, DatasetError> {
    std::fs::create_dir_all(scene_dir).map_err(io_err(scene_dir))?;
    remove_temporaries(scene_dir, None)?;
    write_scene_with(&scene_dir.join(SCENE_FILE), scene, opts.file_sync)?;
    let mut files = BTreeMap::new();
    files.insert(
        SCENE_FILE.to_string(),
        sha256_hex(scene_to_json(scene).as_bytes()),
    );
    if let Some(f) = &opts.scene_file {
        let (name, sha) = write_scene_file(scene_dir, &spec.id(), scene, f, opts.file_sync)?;
        files.insert(name, sha);
    }
    if !views.is_empty() {
        let written = crate::output::write_rendered_views_with(scene_dir, views, opts.file_sync)
            .map_err(io_err(scene_dir))?;
        files.extend(written.into_iter().map(|w| (w.name, w.sha256)));
        // The varied look's draw (docs/varied-look.md "look.json").
        let scene_opts = RenderOptions {
            seed: spec.seed,
            ..opts.render
        };
        if let Some(draw) = scene_opts.look_draw(scene.blocks.len()) {
            let path = scene_dir.join(crate::render::photo::varied::LOOK_FILE);
            let text = draw.to_json();
            write_atomic_with(&path, text.as_bytes(), opts.file_sync).map_err(io_err(&path))?;
            files.insert(
                crate::render::photo::varied::LOOK_FILE.to_string(),
                sha256_hex(text.as_bytes()),
            );
        }
    }
    Ok(files)
}

/// Scenes handed to the worker threads at once: memory stays bounded whatever `--count`
/// (docs/datasets.md "Settling": generation streams).
const CHUNK_SCENES: usize = 1024;

/// Generates (or resumes) this shard of the dataset in `dir`, in parallel on `opts.jobs`
/// threads, rendering through `renderers` (none when `opts.views` is empty): worker `k` renders
/// through `renderers[k % renderers.len()]`, so with a device per worker two scenes render at
/// once instead of queueing for one device's lock (docs/benchmarks.md "Benchmarks"; every device renders
/// the same bytes). `progress(done, total)` is called
/// after each scene. Holds the dataset lock (a second writer of the same scenes is refused),
/// streams the scenes in chunks of [`CHUNK_SCENES`] and their manifest lines into a temporary
/// file that is renamed into place last, so memory does not grow with `opts.count`.
pub fn generate_dataset(
    dir: &Path,
    opts: &DatasetOptions,
    renderers: &[Renderer],
    progress: &(dyn Fn(u64, u64) + Sync),
) -> Result<GenerateSummary, DatasetError> {
    check_options(opts)?;
    let frames = opts.stability.as_ref().is_some_and(|s| s.frames.is_some());
    if (!opts.views.is_empty() || frames) && renderers.is_empty() {
        return Err(DatasetError::NoRenderer);
    }
    super::memory::keep_freed_pictures_in_heap();
    let new_folder = !dir.exists();
    std::fs::create_dir_all(dir).map_err(io_err(dir))?;
    if new_folder {
        // Only a folder this run made: a user's existing folder keeps its attributes.
        let spread = super::placement::spread_scene_folders(dir);
        tracing::debug!(
            spread,
            "scene folders spread over the file system's block groups"
        );
    }
    let _lock = super::lock::lock_dataset(dir, opts.shard)?;
    let manifest_name = if opts.shard.is_whole() {
        MANIFEST_NAME.to_string()
    } else {
        shard_manifest_name(opts.shard.index, opts.shard.count)
    };
    remove_temporaries(dir, Some(&manifest_name))?;
    write_or_check_dataset_json(dir, opts)?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(opts.jobs)
        .build()
        .map_err(|e| DatasetError::Options(format!("--jobs: {e}")))?;
    let manifest = dir.join(manifest_name);
    let tmp = crate::io::temp_path(&manifest);
    let result = stream_scenes(dir, opts, renderers, progress, &pool, &tmp).and_then(|mut s| {
        std::fs::rename(&tmp, &manifest).map_err(io_err(&manifest))?;
        s.manifest = manifest.clone();
        Ok(s)
    });
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// The renderer of the calling worker thread: `renderers[k % len]` for worker `k` of the pool
/// (the first outside a pool); `None` when there are none.
fn worker_renderer(renderers: &[Renderer]) -> Option<&Renderer> {
    let k = rayon::current_thread_index().unwrap_or(0);
    renderers.get(k % renderers.len().max(1))
}

/// Produces the shard's scenes chunk by chunk and appends their manifest lines, in index
/// order, to `manifest_tmp`.
fn stream_scenes(
    dir: &Path,
    opts: &DatasetOptions,
    renderers: &[Renderer],
    progress: &(dyn Fn(u64, u64) + Sync),
    pool: &rayon::ThreadPool,
    manifest_tmp: &Path,
) -> Result<GenerateSummary, DatasetError> {
    use std::io::Write;
    let file = std::fs::File::create(manifest_tmp).map_err(io_err(manifest_tmp))?;
    let mut lines = std::io::BufWriter::new(file);
    let total = opts.shard.len(opts.count);
    let done = AtomicU64::new(0);
    let mut summary = GenerateSummary {
        generated: 0,
        resumed: 0,
        scenes: 0,
        blocks: 0,
        unstable_draws: 0,
        unplaceable_draws: 0,
        stood_draws: 0,
        unstable_scenes: 0,
        times: StageTimes::default(),
        manifest: PathBuf::new(),
    };
    let mut indices = opts.shard.indices(opts.count);
    loop {
        let specs: Vec<SceneSpec> = indices
            .by_ref()
            .take(CHUNK_SCENES)
            .map(|i| SceneSpec::new(opts.seed, i, &opts.families))
            .collect();
        if specs.is_empty() {
            break;
        }
        let outcomes: Vec<SceneOutcome> = pool.install(|| {
            specs
                .par_iter()
                .map(|spec| {
                    let out = produce_scene(dir, spec, opts, worker_renderer(renderers));
                    progress(done.fetch_add(1, Ordering::Relaxed) + 1, total);
                    out
                })
                .collect::<Result<Vec<_>, _>>()
        })?;
        for o in outcomes {
            summary.tally(&o);
            lines
                .write_all(o.entry.to_line().as_bytes())
                .map_err(io_err(manifest_tmp))?;
        }
    }
    let file = lines
        .into_inner()
        .map_err(|e| io_err(manifest_tmp)(e.into_error()))?;
    file.sync_data().map_err(io_err(manifest_tmp))?;
    Ok(summary)
}

impl GenerateSummary {
    fn tally(&mut self, o: &SceneOutcome) {
        self.scenes += 1;
        self.blocks += o.entry.blocks as u64;
        self.unstable_scenes += u64::from(o.entry.stable == Some(false));
        match o.generated {
            Some((times, unstable, unplaceable, stood)) => {
                self.generated += 1;
                self.unstable_draws += unstable as u64;
                self.unplaceable_draws += unplaceable as u64;
                self.stood_draws += stood as u64;
                self.times.add(&times);
            }
            None => self.resumed += 1,
        }
    }
}

/// What a merge found.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MergeSummary {
    /// Shard manifests joined.
    pub shards: u64,
    /// Scenes in the merged manifest.
    pub scenes: u64,
    /// The merged manifest's path.
    pub manifest: PathBuf,
}

/// Joins `manifest.shard-I-of-N.jsonl` files into `manifest.jsonl`, checking that every shard
/// and every scene `0..count` is there exactly once and every file has its listed sha256.
pub fn merge_shards(dir: &Path) -> Result<MergeSummary, DatasetError> {
    merge_shards_with_progress(dir, &|_, _| {})
}

/// [`merge_shards`], calling `progress(checked, scenes)` as scenes' hashes are checked (the
/// long part of merging a large dataset).
pub fn merge_shards_with_progress(
    dir: &Path,
    progress: &(dyn Fn(u64, u64) + Sync),
) -> Result<MergeSummary, DatasetError> {
    let merge_err = |message: String| DatasetError::Merge {
        path: dir.to_path_buf(),
        message,
    };
    let count = claimed_count(dir)?;
    let shards = find_shard_manifests(dir)?;
    let n = check_shard_set(&shards).map_err(merge_err)?;
    // Memory follows the manifests on disk, never the count claimed in dataset.json.
    let mut entries: std::collections::BTreeMap<u64, ManifestEntry> = Default::default();
    for (i, shard_n, path) in &shards {
        let text = std::fs::read_to_string(path).map_err(io_err(path))?;
        for e in parse_manifest(&text, path)? {
            if e.index >= count || e.index % shard_n != *i {
                return Err(merge_err(format!(
                    "{} lists scene {} which is not in shard {i}/{shard_n} of {count} scenes",
                    path.display(),
                    e.id
                )));
            }
            let id = e.id.clone();
            if entries.insert(e.index, e).is_some() {
                return Err(merge_err(format!("scene {id} is listed twice")));
            }
        }
    }
    let missing_count = count - entries.len() as u64;
    if missing_count > 0 {
        let first: Vec<String> = (0..count)
            .filter(|i| !entries.contains_key(i))
            .take(5)
            .map(super::scene_id)
            .collect();
        return Err(merge_err(format!(
            "{missing_count} scenes missing ({}{}); re-run their shard to resume",
            first.join(", "),
            if missing_count > 5 { ", ..." } else { "" }
        )));
    }
    let entries: Vec<ManifestEntry> = entries.into_values().collect();
    verify_entries(dir, &entries, progress)?;
    let manifest = dir.join(MANIFEST_NAME);
    write_atomic(&manifest, manifest_text(&entries).as_bytes()).map_err(io_err(&manifest))?;
    Ok(MergeSummary {
        shards: n,
        scenes: count,
        manifest,
    })
}

/// The scene count `dataset.json` claims: a whole number of at least 1.
fn claimed_count(dir: &Path) -> Result<u64, DatasetError> {
    let merge_err = |message: String| DatasetError::Merge {
        path: dir.to_path_buf(),
        message,
    };
    let options_path = dir.join(DATASET_FILE);
    let options: Value = serde_json::from_str(
        &std::fs::read_to_string(&options_path).map_err(io_err(&options_path))?,
    )
    .map_err(|e| merge_err(format!("{DATASET_FILE}: {e}")))?;
    match &options["count"] {
        Value::Null => Err(merge_err(format!("{DATASET_FILE} has no count"))),
        c => c.as_u64().filter(|&c| c >= 1).ok_or_else(|| {
            merge_err(format!(
                "{DATASET_FILE} has count {c}, not a whole number of at least 1; restore the \
                 dataset.json that `blockworld generate` wrote"
            ))
        }),
    }
}

/// Checks every entry's files against their sha256 in parallel, reporting each scene done.
fn verify_entries(
    dir: &Path,
    entries: &[ManifestEntry],
    progress: &(dyn Fn(u64, u64) + Sync),
) -> Result<(), DatasetError> {
    let checked = AtomicU64::new(0);
    let total = entries.len() as u64;
    entries.par_iter().try_for_each(|e| {
        verify_entry(dir, e)?;
        progress(checked.fetch_add(1, Ordering::Relaxed) + 1, total);
        Ok(())
    })
}

/// Checks that the shard manifests form one whole set `0..N` of one count `N` and returns `N`;
/// a name that no shard can have (`manifest.shard-0-of-0.jsonl`, an index not below its count)
/// is named with the fix.
fn check_shard_set(shards: &[(u64, u64, PathBuf)]) -> Result<u64, String> {
    if let Some((i, n, path)) = shards.iter().find(|(i, n, _)| *n == 0 || i >= n) {
        return Err(format!(
            "{} names shard {i} of {n}, which cannot exist (shards are 0..N with N >= 1); \
             remove the stray file",
            path.display()
        ));
    }
    let n = shards.first().map(|s| s.1).ok_or_else(|| {
        "no manifest.shard-I-of-N.jsonl files; run `blockworld generate --shard I/N` first"
            .to_string()
    })?;
    if let Some(other) = shards.iter().find(|s| s.1 != n) {
        return Err(format!(
            "shard manifests of different shard counts ({n} and {}); remove the stale ones",
            other.1
        ));
    }
    // Sorted and of one count: shard k must sit at position k.
    let missing = (0..n)
        .zip(
            shards
                .iter()
                .map(|s| s.0)
                .chain(std::iter::repeat(u64::MAX)),
        )
        .find(|(want, have)| want != have)
        .map(|(want, _)| want);
    if let Some(missing) = missing {
        return Err(format!(
            "shard {missing} of {n} is missing; run `blockworld generate ... --shard {missing}/{n}` with the same options"
        ));
    }
    Ok(n)
}

/// The shard manifests in `dir` as (I, N, path), sorted.
fn find_shard_manifests(dir: &Path) -> Result<Vec<(u64, u64, PathBuf)>, DatasetError> {
    let mut out: Vec<(u64, u64, PathBuf)> = std::fs::read_dir(dir)
        .map_err(io_err(dir))?
        .flatten()
        .filter_map(|e| {
            let name = e.file_name().to_string_lossy().into_owned();
            parse_shard_manifest_name(&name).map(|(i, n)| (i, n, e.path()))
        })
        .collect();
    out.sort();
    Ok(out)
}

/// Checks every file of a manifest entry against its sha256.
fn verify_entry(dir: &Path, e: &ManifestEntry) -> Result<(), DatasetError> {
    for (name, sha) in &e.files {
        let path = dir.join(&e.id).join(name);
        let bytes = std::fs::read(&path).map_err(io_err(&path))?;
        if sha256_hex(&bytes) != *sha {
            return Err(DatasetError::Merge {
                path,
                message:
                    "sha256 differs from the shard manifest; re-run its shard to regenerate it"
                        .into(),
            });
        }
    }
    Ok(())
}
