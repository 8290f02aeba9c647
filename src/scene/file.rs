//! The scene file (docs/formats.md "Scene files"): JSON with `name`, `blocks` and optional `expect`;
//! reconstruction files add `status`, `reason`, `csg` and `evidence`; generated files add
//! `meta`. Unknown fields are errors that name the field.

use super::{
    block_type, Block, CsgNode, Evidence, Expect, Orientation, ReconStatus, Reconstruction, Scene,
    SceneError, CATALOG,
};
use crate::geom::DVec3;
use glam::DQuat;
use serde::{Deserialize, Serialize};
use std::path::Path;

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct SceneFile {
    name: String,
    blocks: Vec<BlockEntry>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    expect: Option<Expect>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    status: Option<ReconStatus>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    reason: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    csg: Option<CsgNode>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    evidence: Option<Evidence>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    meta: Option<serde_json::Map<String, serde_json::Value>>,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct BlockEntry {
    #[serde(rename = "type")]
    type_id: String,
    center: [f64; 3],
    #[serde(default, skip_serializing_if = "Option::is_none")]
    yaw_deg: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    rotation: Option<[f64; 4]>,
}

/// Parses and validates a scene from JSON text; `source_name` (usually the path) names the
/// input in every error. Reconstruction fields (`status`, `reason`, `csg`, `evidence`) are
/// refused: read such a file with [`parse_reconstruction`].
pub fn parse_scene(text: &str, source_name: &str) -> Result<Scene, SceneError> {
    parse_scene_with_progress(text, source_name, &|_, _| {})
}

/// [`parse_scene`] reporting the validation's progress as `(done, total)` block pairs
/// ([`Scene::validate_with_progress`]): a stack of a hundred thousand blocks takes seconds.
pub fn parse_scene_with_progress(
    text: &str,
    source_name: &str,
    progress: &(dyn Fn(u64, u64) + Sync),
) -> Result<Scene, SceneError> {
    let (file, blocks) = parse_file(text, source_name)?;
    let recon_field = [
        ("status", file.status.is_some()),
        ("reason", file.reason.is_some()),
        ("csg", file.csg.is_some()),
        ("evidence", file.evidence.is_some()),
    ]
    .into_iter()
    .find(|(_, present)| *present);
    if let Some((field, _)) = recon_field {
        return Err(SceneError::Format {
            source_name: source_name.to_string(),
            message: format!(
                "`{field}` belongs to reconstruction files, not scenes (give this file as a \
                 reconstruction, e.g. the second argument of `blockworld score`)"
            ),
        });
    }
    if blocks.is_empty() {
        return Err(SceneError::NoBlocks {
            source_name: source_name.to_string(),
        });
    }
    let scene = Scene {
        name: file.name,
        blocks,
        expect: file.expect,
        meta: file.meta,
    };
    scene.validate_with_progress(source_name, progress)?;
    Ok(scene)
}

/// Parses a reconstruction file: the scene format plus `status` (default `ok`, so a scene
/// scores against itself), `reason`, `csg` and `evidence`. A recognizer's output is scored,
/// not rejected, so blocks may overlap each other or dip below the floor; non-finite poses and
/// CSG leaves naming missing blocks are errors.
pub fn parse_reconstruction(text: &str, source_name: &str) -> Result<Reconstruction, SceneError> {
    let (file, blocks) = parse_file(text, source_name)?;
    for (index, b) in blocks.iter().enumerate() {
        if !(b.center_mm.is_finite() && b.rotation().is_finite()) {
            return Err(SceneError::NotFinite {
                source_name: source_name.to_string(),
                index,
            });
        }
        super::check_in_world(b, index, source_name)?;
    }
    if let Some(leaf) = file
        .csg
        .as_ref()
        .and_then(|t| t.leaves().into_iter().find(|&i| i >= blocks.len()))
    {
        return Err(SceneError::Format {
            source_name: source_name.to_string(),
            message: format!(
                "csg names block {leaf} but the file has {} blocks; CSG leaves are indices \
                 into `blocks`",
                blocks.len()
            ),
        });
    }
    Ok(Reconstruction {
        name: file.name,
        blocks,
        status: file.status.unwrap_or(ReconStatus::Ok),
        reason: file.reason,
        csg: file.csg,
        evidence: file.evidence,
        meta: file.meta,
    })
}

/// Reads and parses a reconstruction file (see [`parse_reconstruction`]).
pub fn read_reconstruction(path: &Path) -> Result<Reconstruction, SceneError> {
    parse_reconstruction(&read_text(path)?, &path.display().to_string())
}

fn read_text(path: &Path) -> Result<String, SceneError> {
    crate::io::read_text(path).map_err(|source| SceneError::Io {
        path: path.to_path_buf(),
        source,
    })
}

fn parse_file(text: &str, source_name: &str) -> Result<(SceneFile, Vec<Block>), SceneError> {
    let file: SceneFile = serde_json::from_str(text).map_err(|e| SceneError::Format {
        source_name: source_name.to_string(),
        message: e.to_string(),
    })?;
    refuse_positional_records(text, source_name)?;
    let blocks = file
        .blocks
        .iter()
        .enumerate()
        .map(|(index, entry)| block_from_entry(entry, index, source_name))
        .collect::<Result<Vec<_>, _>>()?;
    Ok((file, blocks))
}

/// serde's derive also reads a record written as a positional array (`["name", [..]]`), a
/// form docs/formats.md "Scene files" does not define and no writer produces: the file, each block, and
/// `expect`/`evidence` must be JSON objects with named fields.
fn refuse_positional_records(text: &str, source_name: &str) -> Result<(), SceneError> {
    let value: serde_json::Value = serde_json::from_str(text).map_err(|e| SceneError::Format {
        source_name: source_name.to_string(),
        message: e.to_string(),
    })?;
    let not_object = |what: String| SceneError::Format {
        source_name: source_name.to_string(),
        message: format!("{what} is a JSON array; write it as an object with named fields"),
    };
    if !value.is_object() {
        return Err(not_object("the file".to_string()));
    }
    let records = |key: &str| value.get(key).and_then(|v| v.as_array()).cloned();
    for (i, b) in records("blocks").unwrap_or_default().iter().enumerate() {
        if !b.is_object() {
            return Err(not_object(format!("block {i}")));
        }
    }
    for key in ["expect", "evidence"] {
        if value.get(key).is_some_and(|v| v.is_array()) {
            return Err(not_object(format!("`{key}`")));
        }
    }
    let views = value.pointer("/evidence/views").and_then(|v| v.as_array());
    if let Some(i) = views.and_then(|v| v.iter().position(|e| !e.is_object())) {
        return Err(not_object(format!("evidence view {i}")));
    }
    Ok(())
}

/// A quaternion whose squared length is within this of 1 is kept bit for bit (a normalized
/// quaternion's rounding error is a few 1e-16).
const UNIT_QUAT_TOL: f64 = 1e-14;

fn block_from_entry(entry: &BlockEntry, index: usize, source: &str) -> Result<Block, SceneError> {
    let block_type = block_type(&entry.type_id).ok_or_else(|| SceneError::UnknownBlockType {
        source_name: source.to_string(),
        index,
        type_id: entry.type_id.clone(),
        known: CATALOG.iter().map(|t| t.id).collect::<Vec<_>>().join(", "),
    })?;
    let bad = |message: &str| SceneError::BadRotation {
        source_name: source.to_string(),
        index,
        message: message.to_string(),
    };
    let orientation = match (entry.yaw_deg, entry.rotation) {
        (Some(_), Some(_)) => return Err(bad("give either yaw_deg or rotation, not both")),
        (yaw, None) => Orientation::YawDeg(yaw.unwrap_or(0.0)),
        (None, Some(r)) => {
            let q = DQuat::from_array(r);
            let len = q.length();
            if !len.is_finite() {
                return Err(SceneError::NotFinite {
                    source_name: source.to_string(),
                    index,
                });
            }
            if (len - 1.0).abs() > 1e-3 {
                return Err(bad(&format!(
                    "rotation [x, y, z, w] must be a unit quaternion (length {len:.6})"
                )));
            }
            // Normalize only what is not unit to rounding already: normalize() of a normalized
            // quaternion may move it by an ulp, so written files would not read back the same.
            let unit = (q.length_squared() - 1.0).abs() <= UNIT_QUAT_TOL;
            Orientation::Quaternion(if unit { q } else { q.normalize() })
        }
    };
    Ok(Block {
        block_type,
        center_mm: DVec3::from_array(entry.center),
        orientation,
    })
}

fn block_entries(blocks: &[Block]) -> Vec<BlockEntry> {
    blocks
        .iter()
        .map(|b| {
            let (yaw_deg, rotation) = match b.orientation {
                Orientation::YawDeg(d) => (Some(d), None),
                Orientation::Quaternion(q) => (None, Some(q.to_array())),
            };
            BlockEntry {
                type_id: b.block_type.id.to_string(),
                center: b.center_mm.to_array(),
                yaw_deg,
                rotation,
            }
        })
        .collect()
}

fn file_to_json(file: &SceneFile) -> String {
    crate::io::pretty_json(file)
}

/// Serializes a scene as pretty JSON (one stable field order; the same scene gives the same
/// bytes).
pub fn scene_to_json(scene: &Scene) -> String {
    file_to_json(&SceneFile {
        name: scene.name.clone(),
        blocks: block_entries(&scene.blocks),
        expect: scene.expect.clone(),
        status: None,
        reason: None,
        csg: None,
        evidence: None,
        meta: scene.meta.clone(),
    })
}

/// Serializes a reconstruction as pretty JSON: the scene format plus its fields.
pub fn reconstruction_to_json(recon: &Reconstruction) -> String {
    file_to_json(&SceneFile {
        name: recon.name.clone(),
        blocks: block_entries(&recon.blocks),
        expect: None,
        status: Some(recon.status),
        reason: recon.reason.clone(),
        csg: recon.csg.clone(),
        evidence: recon.evidence.clone(),
        meta: recon.meta.clone(),
    })
}

/// Writes a reconstruction file atomically (temporary name, then rename).
pub fn write_reconstruction(path: &Path, recon: &Reconstruction) -> Result<(), SceneError> {
    crate::io::write_atomic(path, reconstruction_to_json(recon).as_bytes()).map_err(|source| {
        SceneError::Io {
            path: path.to_path_buf(),
            source,
        }
    })
}

/// Reads, parses and validates a scene file.
pub fn read_scene(path: &Path) -> Result<Scene, SceneError> {
    read_scene_with_progress(path, &|_, _| {})
}

/// [`read_scene`] reporting the validation's progress ([`parse_scene_with_progress`]).
pub fn read_scene_with_progress(
    path: &Path,
    progress: &(dyn Fn(u64, u64) + Sync),
) -> Result<Scene, SceneError> {
    parse_scene_with_progress(&read_text(path)?, &path.display().to_string(), progress)
}

/// Writes a scene file atomically (temporary name, then rename). A block with a non-finite
/// pose or outside the world is refused, so no `null` ever stands where a number belongs.
pub fn write_scene(path: &Path, scene: &Scene) -> Result<(), SceneError> {
    write_scene_with(path, scene, crate::io::FileSync::EveryFile)
}

/// [`write_scene`] with the file's sync chosen by `sync` (datasets skip the per-file sync:
/// their resume re-hashes every file).
pub fn write_scene_with(
    path: &Path,
    scene: &Scene,
    sync: crate::io::FileSync,
) -> Result<(), SceneError> {
    let name = path.display().to_string();
    for (index, b) in scene.blocks.iter().enumerate() {
        if !(b.center_mm.is_finite() && b.rotation().is_finite()) {
            return Err(SceneError::NotFinite {
                source_name: name,
                index,
            });
        }
        super::check_in_world(b, index, &name)?;
    }
    crate::io::write_atomic_with(path, scene_to_json(scene).as_bytes(), sync).map_err(|source| {
        SceneError::Io {
            path: path.to_path_buf(),
            source,
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const TWO_LAYER: &str = r#"{"name": "two_layer",
        "blocks": [{"type": "b30", "center": [0, 7.5, 0], "yaw_deg": 0},
                   {"type": "b15", "center": [0, 22.5, 0]}],
        "expect": {"supported": true}}"#;

    #[test]
    fn documented_example_parses_and_round_trips() {
        let s = parse_scene(TWO_LAYER, "two_layer.json").unwrap();
        assert_eq!(s.blocks.len(), 2);
        assert_eq!(s.blocks[1].block_type.id, "b15");
        assert!(s.is_supported());
        let again = parse_scene(&scene_to_json(&s), "again").unwrap();
        assert_eq!(again, s);
    }

    #[test]
    fn unknown_field_is_named() {
        let text = TWO_LAYER.replace("\"yaw_deg\"", "\"yaw\"");
        let err = parse_scene(&text, "x.json").unwrap_err().to_string();
        assert!(
            err.contains("x.json") && err.contains("unknown field `yaw`"),
            "{err}"
        );
        let text = TWO_LAYER.replace("\"expect\"", "\"expected\"");
        let err = parse_scene(&text, "x.json").unwrap_err().to_string();
        assert!(err.contains("unknown field `expected`"), "{err}");
    }

    /// Regression: a scene written as positional arrays (a serde artefact) was accepted.
    #[test]
    fn positional_arrays_are_refused() {
        let whole = r#"["two_layer", [{"type": "b15", "center": [0, 7.5, 0]}]]"#;
        let err = parse_scene(whole, "x.json").unwrap_err().to_string();
        assert!(err.contains("the file is a JSON array"), "{err}");
        let block = r#"{"name": "a", "blocks": [["b15", [0, 7.5, 0]]]}"#;
        let err = parse_scene(block, "x.json").unwrap_err().to_string();
        assert!(err.contains("block 0 is a JSON array"), "{err}");
        let expect = r#"{"name": "a", "blocks": [{"type": "b15", "center": [0, 7.5, 0]}],
            "expect": [false, "why"]}"#;
        let err = parse_scene(expect, "x.json").unwrap_err().to_string();
        assert!(err.contains("`expect` is a JSON array"), "{err}");
        parse_scene(TWO_LAYER, "x.json").unwrap();
    }

    /// Regression: an empty `blocks` was read by render, settle and score but refused by export;
    /// a scene file needs a block, a reconstruction may be empty (nothing reconstructed).
    #[test]
    fn scenes_need_a_block_reconstructions_may_be_empty() {
        let empty = r#"{"name": "a", "blocks": []}"#;
        let err = parse_scene(empty, "x.json").unwrap_err();
        assert!(matches!(err, SceneError::NoBlocks { .. }), "{err}");
        assert!(err.to_string().contains("x.json"), "{err}");
        assert!(parse_reconstruction(empty, "x.json")
            .unwrap()
            .blocks
            .is_empty());
    }

    /// Regression: a block at x = 1e308 mm passed validation and the renderer and glTF export
    /// wrote `null`; blocks outside the world extent are refused, naming the block.
    #[test]
    fn blocks_outside_the_world_are_refused() {
        for (far, axis) in [
            ("[1e308, 7.5, 0]", "x = "),
            ("[0, 7.5, -10010]", "z = "),
            ("[0, 2e4, 0]", "y = "),
        ] {
            let text = TWO_LAYER.replace("[0, 22.5, 0]", far);
            let err = parse_scene(&text, "x.json").unwrap_err();
            assert!(
                matches!(err, SceneError::OutsideWorld { index: 1, .. }),
                "{err}"
            );
            assert!(err.to_string().contains(axis), "{err}");
            let err = parse_reconstruction(&text, "x.json").unwrap_err();
            assert!(
                matches!(err, SceneError::OutsideWorld { index: 1, .. }),
                "{err}"
            );
        }
        let edge = TWO_LAYER.replace("[0, 22.5, 0]", "[9992.5, 7.5, 0]");
        parse_scene(&edge, "x.json").unwrap();
    }

    /// Regression: a rotation within the unit tolerance was normalized on every read, so a
    /// written scene read back an ulp away (found by the scene mutants).
    #[test]
    fn near_unit_rotations_read_back_bit_for_bit() {
        let text = TWO_LAYER.replace(
            "\"yaw_deg\": 0",
            "\"rotation\": [0, 0.7071033905688866, 0, 0.7071101717879502]",
        );
        let once = parse_scene(&text, "x.json").unwrap();
        let twice = parse_scene(&scene_to_json(&once), "x.json").unwrap();
        assert_eq!(scene_to_json(&once), scene_to_json(&twice));
        assert_eq!(once, twice);
    }

    #[test]
    fn unknown_type_and_bad_rotation_name_the_block() {
        let err = parse_scene(&TWO_LAYER.replace("b15", "b45"), "x.json").unwrap_err();
        assert!(
            matches!(err, SceneError::UnknownBlockType { index: 1, .. }),
            "{err}"
        );
        let text = TWO_LAYER.replace("\"yaw_deg\": 0", "\"rotation\": [0, 0, 0, 2]");
        let err = parse_scene(&text, "x.json").unwrap_err();
        assert!(
            matches!(err, SceneError::BadRotation { index: 0, .. }),
            "{err}"
        );
        let err = parse_scene(&TWO_LAYER.replace("22.5", "1e999"), "x.json").unwrap_err();
        assert!(err.to_string().contains("x.json"), "{err}");
    }
}
