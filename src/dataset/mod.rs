//! Synthetic datasets (docs/datasets.md "Settling"): seeded scene families (Chapter VII's supported cases and its
//! named failures), settled with `physics`, rendered with `render`, written one folder per
//! scene with a manifest of sha256 hashes, sliced into shards for Slurm or Kubernetes, resumed
//! after an interruption and merged; and a dataset's line drawings exported as wireframe
//! training sets (`wireframe`).
//!
//! Determinism: a scene's content depends only on its own seed, derived from (dataset seed,
//! scene index), never on `--jobs` or the shard, so every way of producing a dataset gives the
//! same bytes. `writer`, `frames` and `wireframe` are the parts that do file I/O.

mod bop_export;
mod error;
mod export_files;
mod families;
mod frames;
mod generate;
mod lock;
mod manifest;
mod memory;
mod perturb;
mod placement;
mod shard;
mod vision_export;
mod wireframe;
mod writer;

pub use error::DatasetError;
pub use export_files::views_of;
pub use families::{family_scene, Family, GRID_MM, REASON_NOT_UNIFORM, REASON_UPPER_LARGER};
pub use frames::{
    frame_file_name, TrajectoryFrames, DEFAULT_FRAME_EVERY, FRAMES_DIR, MAX_FRAME_PICTURES,
};
pub use generate::{
    draw_scene, draw_stable_scene, scene_id, scene_seed, wants_stable, DrawnScene, SceneSpec,
    StabilityOptions, MAX_ATTEMPTS,
};
pub use manifest::{
    parse_manifest, read_manifest_text, sha256_hex, ManifestEntry, MANIFEST_NAME,
    MAX_MANIFEST_BYTES,
};
pub use memory::keep_freed_pictures_in_heap;
pub use perturb::{perturb, Perturbation};
pub use shard::{Shard, ShardError};
pub use vision_export::{export_vision, VisionExportSummary, VisionFormat};
pub use wireframe::{export_wireframes, WireframeExportOptions, WireframeExportSummary};
pub use writer::{
    generate_dataset, merge_shards, merge_shards_with_progress, DatasetOptions, GenerateSummary,
    MergeSummary, SceneFileEncoder, StageTimes, DATASET_FILE, DONE_FILE, FALL_FILE, MAX_JOBS,
    TRAJECTORY_FILE,
};
