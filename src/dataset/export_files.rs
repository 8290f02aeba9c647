//! The dataset files an export reads and the resume records it writes: the one home of the
//! checks the exports share (docs/wireframe.md "Wireframe datasets", docs/exports.md).

use super::lock::{lock_dataset, DatasetLock};
use super::manifest::{sha256_hex, ManifestEntry, MANIFEST_NAME};
use super::writer::io_err;
use super::{DatasetError, Shard};
use crate::camera::{parse_camera_json, Camera};
use crate::scene::{parse_scene, Scene};
use image::{ImageBuffer, Luma};
use serde_json::Value;
use std::path::{Path, PathBuf};

/// The part files' folder in OUT: one resume record per scene.
pub(super) const PARTS_DIR: &str = ".parts";

/// Reads `DATASET/manifest.jsonl`.
pub(super) fn read_manifest(path: &Path) -> Result<Vec<u8>, DatasetError> {
    super::read_manifest_text(path).map(String::into_bytes).map_err(|e| DatasetError::Input {
        path: path.to_path_buf(),
        message: format!("{e}; finish the dataset first (re-run its `blockworld generate`, or `blockworld merge` for shards)"),
    })
}

/// Creates OUT and takes the dataset lock on it (as `generate` does on its dataset), so a second
/// export into the same OUT is refused; hold it for the whole export.
pub(super) fn lock_export(out: &Path) -> Result<DatasetLock, DatasetError> {
    std::fs::create_dir_all(out).map_err(io_err(out))?;
    lock_dataset(out, Shard::WHOLE).map_err(|e| match e {
        DatasetError::Locked { path, holder } => DatasetError::ExportLocked { path, holder },
        other => other,
    })
}

/// Reads a scene's part file.
pub(super) fn read_part(out: &Path, entry: &ManifestEntry) -> Result<Value, DatasetError> {
    let path = out.join(PARTS_DIR).join(format!("{}.json", entry.id));
    let text = std::fs::read_to_string(&path).map_err(io_err(&path))?;
    serde_json::from_str(&text).map_err(|e| DatasetError::Input {
        path,
        message: format!("{e}: damaged; delete it and re-run to redo the scene"),
    })
}

/// Appends `item`'s JSON to a comma-joined list.
pub(super) fn push_json(list: &mut String, item: &Value) {
    if !list.is_empty() {
        list.push(',');
    }
    list.push_str(&item.to_string());
}

/// Whether an earlier run finished the scene: its part file reads and every picture it lists is
/// there with the sha256 it lists.
pub(super) fn part_is_complete(part_path: &Path, out: &Path) -> bool {
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
        std::fs::read(out.join(relative))
            .is_ok_and(|bytes| sha.as_str() == Some(sha256_hex(&bytes).as_str()))
    })
}

/// The views of a scene: every `lines_<v>.json` in its manifest line that has a `view_<v>.png`.
pub fn views_of(entry: &ManifestEntry) -> Vec<String> {
    entry
        .files
        .keys()
        .filter_map(|name| name.strip_prefix("lines_")?.strip_suffix(".json"))
        .filter(|v| entry.files.contains_key(&format!("view_{v}.png")))
        .map(str::to_string)
        .collect()
}

/// Reads `dir/name` and refuses it when it is missing or its sha256 differs from the manifest's.
pub(super) fn read_checked(
    dir: &Path,
    entry: &ManifestEntry,
    name: &str,
) -> Result<Vec<u8>, DatasetError> {
    let path = dir.join(name);
    let bytes = std::fs::read(&path).map_err(|e| DatasetError::Input {
        path: path.clone(),
        message: format!(
            "{e}: the dataset is incomplete; re-run the `blockworld generate` command that made it"
        ),
    })?;
    let want = entry.files.get(name).map(String::as_str).unwrap_or("");
    let got = sha256_hex(&bytes);
    if got != want {
        return Err(DatasetError::Input {
            path,
            message: format!("sha256 {got} does not match {MANIFEST_NAME} ({want}); the dataset is damaged: re-run the `blockworld generate` command that made it (it redoes scenes whose files fail their hash)"),
        });
    }
    Ok(bytes)
}

/// A dataset file that reads but does not make sense (`error` says why), refused with its path
/// and the command that remakes it.
pub(super) fn remake(path: PathBuf, error: impl std::fmt::Display) -> DatasetError {
    DatasetError::Input {
        path,
        message: format!("{error}; re-run the `blockworld generate` command that made the dataset"),
    }
}

/// Reads and parses a scene's `scene.json`; returns the scene's folder with it.
pub(super) fn read_scene_checked(
    dataset: &Path,
    entry: &ManifestEntry,
) -> Result<(PathBuf, Scene), DatasetError> {
    let scene_dir = dataset.join(&entry.id);
    let bytes = read_checked(&scene_dir, entry, "scene.json")?;
    let scene = parse_scene(
        &String::from_utf8_lossy(&bytes),
        &scene_dir.join("scene.json").display().to_string(),
    )?;
    Ok((scene_dir, scene))
}

/// Reads and parses a view's `camera_<view>.json`.
pub(super) fn read_camera(
    scene_dir: &Path,
    entry: &ManifestEntry,
    view: &str,
) -> Result<Camera, DatasetError> {
    let name = format!("camera_{view}.json");
    let text = read_checked(scene_dir, entry, &name)?;
    parse_camera_json(&String::from_utf8_lossy(&text)).map_err(|e| remake(scene_dir.join(name), e))
}

/// Reads a 16-bit picture of a view (`ids_<v>.png`, `depth_<v>.png`) and refuses it when it is
/// not `camera`'s size.
pub(super) fn read_gray16(
    scene_dir: &Path,
    entry: &ManifestEntry,
    name: &str,
    camera: &Camera,
) -> Result<ImageBuffer<Luma<u16>, Vec<u16>>, DatasetError> {
    let png = read_checked(scene_dir, entry, name)?;
    let picture = image::load_from_memory(&png)
        .map_err(|e| remake(scene_dir.join(name), e))?
        .to_luma16();
    if picture.dimensions() != (camera.size_px[0], camera.size_px[1]) {
        let message = format!(
            "{}x{} px, but its camera says {}x{}",
            picture.width(),
            picture.height(),
            camera.size_px[0],
            camera.size_px[1]
        );
        return Err(remake(scene_dir.join(name), message));
    }
    Ok(picture)
}
