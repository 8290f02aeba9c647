//! A generated dataset as BOP (docs/export-bop.md): `blockworld export-dataset DATASET --format
//! bop -o OUT`, driven by `vision_export::export_vision` like the COCO and Hugging Face
//! exports (the same lock, options stamp, resume records and threads).
//!
//! Scene `k` of the manifest becomes `OUT/train_pbr/<k, six digits>/` with `gray/`, `depth/`,
//! `mask/`, `mask_visib/` and its `scene_camera.json`, `scene_gt.json` and `scene_gt_info.json`;
//! its resume record lists every one of those files with its sha256. `OUT/models/` (one PLY per
//! catalog block type and `models_info.json`) and `OUT/camera.json` are written last.

use super::export_files::{
    part_is_complete, read_camera, read_checked, read_gray16, read_part, read_scene_checked,
    remake, views_of, PARTS_DIR,
};
use super::manifest::{sha256_hex, ManifestEntry};
use super::vision_export::{agreement_json, part_agreement, VisionExportSummary};
use super::writer::{io_err, remove_temporaries};
use super::DatasetError;
use crate::export::bop::{bop_view, model_file_name, model_info, model_ply, BopInstance};
use crate::export::bop::{BopError, BopViewInput};
use crate::export::coco::SilhouetteAgreement;
use crate::export::masks::Mask;
use crate::io::{write_atomic, write_atomic_with, FileSync};
use crate::output::encode_png_gray8;
use crate::scene::CATALOG;
use serde_json::{json, Map, Value};
use std::path::Path;

/// The image folders of a BOP scene.
const IMAGE_DIRS: [&str; 4] = ["gray", "depth", "mask", "mask_visib"];

/// Refuses a dataset with an orthographic view before anything is written: BOP's cameras are
/// pinhole cameras (`cam_K`). Names the first such camera file.
pub(super) fn refuse_orthographic(
    dataset: &Path,
    entries: &[ManifestEntry],
) -> Result<(), DatasetError> {
    for entry in entries {
        let scene_dir = dataset.join(&entry.id);
        for view in views_of(entry) {
            if read_camera(&scene_dir, entry, &view)?.is_orthographic() {
                return Err(DatasetError::Input {
                    path: scene_dir.join(format!("camera_{view}.json")),
                    message: BopError::Orthographic.to_string(),
                });
            }
        }
    }
    Ok(())
}

/// The files of one BOP scene, relative to OUT, with their bytes, and what they hold.
#[derive(Default)]
struct SceneFiles {
    files: Vec<(String, Vec<u8>)>,
    scene_camera: Map<String, Value>,
    scene_gt: Map<String, Value>,
    scene_gt_info: Map<String, Value>,
    instances: usize,
    agreement: SilhouetteAgreement,
    camera: Value,
}

/// Exports scene `index` of the manifest (its files, then its resume record); `false` when an
/// earlier run had already done it.
pub(super) fn export_bop_scene(
    dataset: &Path,
    out: &Path,
    index: usize,
    entry: &ManifestEntry,
) -> Result<bool, DatasetError> {
    let part_path = out.join(PARTS_DIR).join(format!("{}.json", entry.id));
    let bop_dir = format!("{}/{index:06}", super::VisionFormat::Bop.image_dir());
    let (scene_dir, scene) = read_scene_checked(dataset, entry)?;
    let mut files = SceneFiles::default();
    for (im_id, view) in views_of(entry).iter().enumerate() {
        let camera = read_camera(&scene_dir, entry, view)?;
        let ids_name = format!("ids_{view}.png");
        let ids = read_gray16(&scene_dir, entry, &ids_name, &camera)?;
        let depth_name = format!("depth_{view}.png");
        let depth = read_gray16(&scene_dir, entry, &depth_name, &camera)?;
        let input = BopViewInput {
            scene: &scene,
            camera: &camera,
            ids: ids.as_raw(),
            depth: depth.as_raw(),
        };
        let bop = bop_view(&input).map_err(|e| remake(scene_dir.join(&ids_name), e))?;
        let name = |dir: &str| format!("{bop_dir}/{dir}/{im_id:06}.png");
        files.files.push((
            name("gray"),
            read_checked(&scene_dir, entry, &format!("view_{view}.png"))?,
        ));
        files
            .files
            .push((name("depth"), read_checked(&scene_dir, entry, &depth_name)?));
        push_masks(&mut files.files, &bop_dir, im_id, &bop.instances)?;
        let mut cam = bop.camera;
        cam["blockworld_scene_id"] = json!(entry.id);
        cam["blockworld_view"] = json!(view);
        if files.camera.is_null() {
            files.camera = sensor_camera(&cam, camera.size_px);
        }
        let key = im_id.to_string();
        files.scene_camera.insert(key.clone(), cam);
        let field = |f: fn(&BopInstance) -> &Value| {
            Value::Array(bop.instances.iter().map(|i| f(i).clone()).collect())
        };
        files.scene_gt.insert(key.clone(), field(|i| &i.gt));
        files.scene_gt_info.insert(key, field(|i| &i.info));
        files.instances += bop.instances.len();
        files.agreement.add(bop.agreement);
    }
    if part_is_complete(&part_path, out) {
        return Ok(false);
    }
    write_scene(out, &bop_dir, files, &part_path)?;
    Ok(true)
}

/// Appends the masks of view `im_id`, BOP's `mask/<im>_<gt>.png` and `mask_visib/<im>_<gt>.png`
/// (8-bit, 255 on the mask, 0 elsewhere), one per block.
fn push_masks(
    files: &mut Vec<(String, Vec<u8>)>,
    bop_dir: &str,
    im_id: usize,
    instances: &[BopInstance],
) -> Result<(), DatasetError> {
    for (gt_id, instance) in instances.iter().enumerate() {
        for (dir, mask) in [
            ("mask", &instance.mask),
            ("mask_visib", &instance.mask_visib),
        ] {
            let path = format!("{bop_dir}/{dir}/{im_id:06}_{gt_id:06}.png");
            let png = encode_png_gray8(&mask_picture(mask)).map_err(io_err(Path::new(&path)))?;
            files.push((path, png));
        }
    }
    Ok(())
}

/// A mask as an 8-bit picture, 255 on the mask.
fn mask_picture(mask: &Mask) -> image::GrayImage {
    let pixels = mask
        .pixels
        .iter()
        .map(|&p| if p { 255 } else { 0 })
        .collect();
    image::GrayImage::from_raw(mask.width_px, mask.height_px, pixels).unwrap_or_default()
}

/// `camera.json`'s fields (bop_toolkit `inout.load_cam_params`) from a `scene_camera.json` entry.
fn sensor_camera(entry: &Value, size_px: [u32; 2]) -> Value {
    let k = |i: usize| entry["cam_K"][i].clone();
    json!({
        "fx": k(0), "fy": k(4), "cx": k(2), "cy": k(5),
        "width": size_px[0], "height": size_px[1],
        "depth_scale": entry["depth_scale"],
    })
}

/// Writes a scene's files (each atomically, temporary name and rename, after removing what a
/// killed run left), then its three JSON files, then its resume record.
fn write_scene(
    out: &Path,
    bop_dir: &str,
    mut scene: SceneFiles,
    part_path: &Path,
) -> Result<(), DatasetError> {
    let dir = out.join(bop_dir);
    for sub in IMAGE_DIRS.iter().map(|d| dir.join(d)).chain([dir.clone()]) {
        std::fs::create_dir_all(&sub).map_err(io_err(&sub))?;
        remove_temporaries(&sub, None)?;
    }
    for (name, map) in [
        ("scene_camera.json", &scene.scene_camera),
        ("scene_gt.json", &scene.scene_gt),
        ("scene_gt_info.json", &scene.scene_gt_info),
    ] {
        scene
            .files
            .push((format!("{bop_dir}/{name}"), bop_json(map).into_bytes()));
    }
    let mut images = Map::new();
    for (relative, bytes) in &scene.files {
        images.insert(relative.clone(), json!(sha256_hex(bytes)));
        let path = out.join(relative);
        write_atomic_with(&path, bytes, FileSync::Verified).map_err(io_err(&path))?;
    }
    let part = json!({
        "images": images,
        "views": scene.scene_camera.len(),
        "instances": scene.instances,
        "agreement": agreement_json(scene.agreement),
        "camera": scene.camera,
    });
    write_atomic_with(part_path, part.to_string().as_bytes(), FileSync::Verified)
        .map_err(io_err(part_path))
}

/// A JSON object as bop_toolkit's `inout.save_json` lays it out: one key per line, in the order
/// given (image ids ascending).
fn bop_json(map: &Map<String, Value>) -> String {
    let lines: Vec<String> = map
        .iter()
        .map(|(k, v)| format!("  {}: {v}", json!(k)))
        .collect();
    format!("{{\n{}\n}}\n", lines.join(",\n"))
}

/// Writes `models/` (one PLY per catalog block type, `models_info.json`) and `camera.json` (the
/// first view's camera), and sums the scenes' resume records.
pub(super) fn assemble_bop(
    out: &Path,
    entries: &[ManifestEntry],
) -> Result<VisionExportSummary, DatasetError> {
    let mut summary = VisionExportSummary::default();
    let mut camera = Value::Null;
    for entry in entries {
        let part = read_part(out, entry)?;
        summary.images += part["views"].as_u64().unwrap_or(0) as usize;
        summary.annotations += part["instances"].as_u64().unwrap_or(0) as usize;
        summary.agreement.add(part_agreement(&part));
        if camera.is_null() {
            camera = part["camera"].clone();
        }
    }
    let models = out.join("models");
    let mut info = Map::new();
    for (k, block_type) in CATALOG.iter().enumerate() {
        let path = models.join(model_file_name(k + 1));
        write_atomic(&path, model_ply(block_type).as_bytes()).map_err(io_err(&path))?;
        info.insert((k + 1).to_string(), model_info(block_type));
    }
    let path = models.join("models_info.json");
    write_atomic(&path, bop_json(&info).as_bytes()).map_err(io_err(&path))?;
    let path = out.join("camera.json");
    write_atomic(&path, crate::io::pretty_json(&camera).as_bytes()).map_err(io_err(&path))?;
    Ok(summary)
}
