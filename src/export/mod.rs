//! glTF 2.0 export of a scene: the block sample as a 3D model any viewer can open.
//!
//! The thesis ends by displaying the final block sample, rebuilt from the database of
//! predefined blocks by constructive solid geometry (Ch. IV "Construction of the Final Sample",
//! Figure 4.6: a union of block primitives, lowest level first; Ch. VI "Display the Final
//! Sample"). This stage writes that union as glTF: one mesh per catalog block type used (the
//! primitives) and one node per block (its pose), so a scene or a reconstruction can be looked
//! at from any viewpoint outside blockworld.
//!
//! Beside it, the vision-tool exports of a dataset's views (docs/exports.md "Exports for vision
//! tools"): [`coco`] and [`bop`] records from [`masks`] (exact visible masks from the id pictures, full
//! masks from projected silhouettes, COCO run lengths) and cameras in [`opencv`]'s convention.
//!
//! Units and axes: glTF is metres, +y up, right-handed. Those are blockworld's axes (docs/formats.md
//! "Conventions"), so the only conversion is mm -> m (x 0.001). Everything here is pure: the
//! functions return bytes and `cli` writes them.

mod animation;
pub mod bop;
pub mod coco;
pub mod masks;
mod mesh;
pub mod opencv;
mod overlay;
#[cfg(feature = "rrd")]
pub mod rrd;
mod thesis;
pub mod wireframe;

pub use animation::{scene_animation_to_gltf, scene_fall_to_glb, scene_fall_to_gltf};
pub use overlay::{reconstruction_with_truth_to_glb, reconstruction_with_truth_to_gltf};

pub use thesis::{
    parse_thesis_files, scene_to_thesis_files, thesis_model_to_scene, thesis_origin_mm,
    ThesisDataFiles, ThesisFormatError, ThesisModel, Truncation, THESIS_UNIT_MM,
};

use crate::scene::{BlockType, Scene};
use gltf::json;
use json::validation::{Checked::Valid, USize64};
use mesh::{flat_mesh, FlatMesh, METRES_PER_MM};
use std::borrow::Cow;
use std::collections::BTreeMap;

/// Why a scene could not be exported.
#[derive(Debug, thiserror::Error)]
pub enum ExportError {
    /// glTF needs at least one node and a non-empty buffer.
    #[error("scene {scene:?} has no blocks; add at least one block to export it")]
    NoBlocks {
        /// The scene's name.
        scene: String,
    },
    /// A block's centre or rotation is NaN or infinite (JSON cannot hold it), or its rotation
    /// quaternion is zero.
    #[error(
        "scene {scene:?}: block {index} has a non-finite centre or a non-finite or zero rotation; fix its pose"
    )]
    BadPose {
        /// The scene's name.
        scene: String,
        /// Block index (0-based, file order).
        index: usize,
    },
    /// A catalog face that cannot be triangulated.
    #[error("block type {block_type:?}, face {face}: {reason}; fix the catalog row")]
    DegenerateFace {
        /// The block type's id.
        block_type: String,
        /// Face index in the catalog row.
        face: usize,
        /// What is wrong with it.
        reason: String,
    },
    /// The glTF JSON could not be serialized.
    #[error("serializing the glTF JSON: {0}")]
    Json(#[from] json::Error),
    /// Animation keyframes that do not fit the scene.
    #[error(
        "scene {scene:?}: the fall animation {reason}; record the trajectory of this scene again"
    )]
    BadAnimation {
        /// The scene's name.
        scene: String,
        /// What is wrong with the keyframes.
        reason: String,
    },
    /// The binary container could not be built (e.g. over 4 GiB).
    #[error("building the GLB container: {0}")]
    Glb(#[from] gltf::Error),
}

/// A scene as a glTF 2.0 document plus its one binary buffer (positions, normals, indices).
/// Buffer 0 carries no `uri`; [`GltfFiles::to_glb`] embeds the buffer, and
/// [`GltfFiles::to_gltf_json`] points it at a `.bin` file.
#[derive(Debug, Clone)]
pub struct GltfFiles {
    /// The glTF JSON document.
    pub root: json::Root,
    /// The bytes of buffer 0, little-endian, every range 4-byte aligned.
    pub bin: Vec<u8>,
}

impl GltfFiles {
    /// The binary glTF (`.glb`): the JSON chunk and the buffer as its BIN chunk.
    pub fn to_glb(&self) -> Result<Vec<u8>, ExportError> {
        let json_bytes = self.root.to_vec()?;
        let glb = gltf::binary::Glb {
            header: gltf::binary::Header {
                magic: *b"glTF",
                version: 2,
                // `to_vec` computes the real length (and pads the chunks) itself.
                length: 0,
            },
            json: Cow::Owned(json_bytes),
            bin: Some(Cow::Borrowed(&self.bin)),
        };
        Ok(glb.to_vec()?)
    }

    /// The JSON glTF (`.gltf`) text with buffer 0 at `bin_file_name` (a file name beside the
    /// `.gltf`, percent-encoded here into a URI). Write [`GltfFiles::bin`] under that name.
    pub fn to_gltf_json(&self, bin_file_name: &str) -> Result<String, ExportError> {
        let mut root = self.root.clone();
        root.buffers[0].uri = Some(uri_from_file_name(bin_file_name));
        let mut text = root.to_string_pretty()?;
        text.push('\n');
        Ok(text)
    }
}

/// Builds the glTF document of `scene`: one mesh per block type used (in order of first use,
/// named by its catalog id, flat-shaded from the catalog's convex faces), one node per block
/// (`block_<index>_<type id>`, translation = centre in metres, rotation = the block's unit
/// quaternion `[x, y, z, w]`), and one glTF scene named after `scene`. Deterministic: the same
/// scene gives the same document and bytes.
pub fn scene_to_gltf(scene: &Scene) -> Result<GltfFiles, ExportError> {
    if scene.blocks.is_empty() {
        return Err(ExportError::NoBlocks {
            scene: scene.name.clone(),
        });
    }
    let mut doc = DocumentBuilder::new(scene)?;
    let nodes = doc.push_block_nodes(scene, None)?;
    Ok(doc.finish(scene, nodes))
}

/// The scene as a binary glTF (`.glb`) file's bytes; see [`scene_to_gltf`].
pub fn scene_to_glb(scene: &Scene) -> Result<Vec<u8>, ExportError> {
    scene_to_gltf(scene)?.to_glb()
}

/// The scene as a JSON glTF (`.gltf`) text referencing `bin_file_name`, and the bytes to write
/// under that name beside it; see [`scene_to_gltf`].
pub fn scene_to_gltf_json(
    scene: &Scene,
    bin_file_name: &str,
) -> Result<(String, Vec<u8>), ExportError> {
    let files = scene_to_gltf(scene)?;
    let text = files.to_gltf_json(bin_file_name)?;
    Ok((text, files.bin))
}

/// Accumulates the JSON objects and the buffer bytes while the document is built.
struct DocumentBuilder {
    root: json::Root,
    bin: Vec<u8>,
    buffer: json::Index<json::Buffer>,
}

impl DocumentBuilder {
    fn new(scene: &Scene) -> Result<DocumentBuilder, ExportError> {
        for (index, b) in scene.blocks.iter().enumerate() {
            if !(b.center_mm.is_finite() && b.rotation().is_finite()) {
                return Err(ExportError::BadPose {
                    scene: scene.name.clone(),
                    index,
                });
            }
        }
        let mut root = json::Root::default();
        root.asset.generator = Some(format!("blockworld {}", env!("CARGO_PKG_VERSION")));
        let buffer = root.push(json::Buffer {
            byte_length: USize64(0), // set in `finish`
            name: None,
            uri: None,
            extensions: Default::default(),
            extras: Default::default(),
        });
        Ok(DocumentBuilder {
            root,
            bin: Vec::new(),
            buffer,
        })
    }

    /// Appends `bytes` to the buffer as one view for `target` (none for animation data).
    fn push_view(
        &mut self,
        bytes: &[u8],
        target: Option<json::buffer::Target>,
    ) -> json::Index<json::buffer::View> {
        let offset = self.bin.len();
        self.bin.extend_from_slice(bytes);
        while self.bin.len() % 4 != 0 {
            self.bin.push(0);
        }
        self.root.push(json::buffer::View {
            buffer: self.buffer,
            byte_length: USize64::from(bytes.len()),
            byte_offset: Some(USize64::from(offset)),
            byte_stride: None,
            name: None,
            target: target.map(Valid),
            extensions: Default::default(),
            extras: Default::default(),
        })
    }

    /// Appends a tightly packed accessor over a new view; `bounds` are its JSON `min` and `max`.
    fn push_accessor(
        &mut self,
        bytes: &[u8],
        count: usize,
        layout: (json::accessor::ComponentType, json::accessor::Type),
        target: Option<json::buffer::Target>,
        bounds: Option<(json::Value, json::Value)>,
    ) -> json::Index<json::Accessor> {
        let view = self.push_view(bytes, target);
        let (min, max) = bounds.unzip();
        self.root.push(json::Accessor {
            buffer_view: Some(view),
            byte_offset: None,
            count: USize64::from(count),
            component_type: Valid(json::accessor::GenericComponentType(layout.0)),
            extensions: Default::default(),
            extras: Default::default(),
            type_: Valid(layout.1),
            min,
            max,
            name: None,
            normalized: false,
            sparse: None,
        })
    }

    /// Adds the flat-shaded mesh of one block type, named by its catalog id, drawn with
    /// `material` (the glTF default material when `None`).
    fn push_mesh(
        &mut self,
        block_type: &BlockType,
        material: Option<json::Index<json::Material>>,
    ) -> Result<json::Index<json::Mesh>, ExportError> {
        use json::accessor::{ComponentType, Type};
        use json::buffer::Target;
        let m: FlatMesh = flat_mesh(block_type)?;
        let vec3 = (ComponentType::F32, Type::Vec3);
        let positions = self.push_accessor(
            &vec3_bytes(&m.positions_m),
            m.positions_m.len(),
            vec3,
            Some(Target::ArrayBuffer),
            Some((json_array(m.bounds_m().0), json_array(m.bounds_m().1))),
        );
        let normals = self.push_accessor(
            &vec3_bytes(&m.normals),
            m.normals.len(),
            vec3,
            Some(Target::ArrayBuffer),
            None,
        );
        let index_bytes: Vec<u8> = m.indices.iter().flat_map(|i| i.to_le_bytes()).collect();
        let indices = self.push_accessor(
            &index_bytes,
            m.indices.len(),
            (ComponentType::U32, Type::Scalar),
            Some(Target::ElementArrayBuffer),
            None,
        );
        let attributes = BTreeMap::from([
            (Valid(json::mesh::Semantic::Positions), positions),
            (Valid(json::mesh::Semantic::Normals), normals),
        ]);
        Ok(self.root.push(json::Mesh {
            extensions: Default::default(),
            extras: Default::default(),
            name: Some(block_type.id.to_string()),
            primitives: vec![json::mesh::Primitive {
                attributes,
                extensions: Default::default(),
                extras: Default::default(),
                indices: Some(indices),
                material,
                mode: Valid(json::mesh::Mode::Triangles),
                targets: None,
            }],
            weights: None,
        }))
    }

    /// Adds a node per block of `scene` and a mesh per block type it uses (in order of first
    /// use, drawn with `material`); returns the nodes in block order.
    fn push_block_nodes(
        &mut self,
        scene: &Scene,
        material: Option<json::Index<json::Material>>,
    ) -> Result<Vec<json::Index<json::Node>>, ExportError> {
        let mut mesh_of_type: Vec<(&str, json::Index<json::Mesh>)> = Vec::new();
        let mut nodes = Vec::with_capacity(scene.blocks.len());
        for (index, block) in scene.blocks.iter().enumerate() {
            let id = block.block_type.id;
            let mesh = match mesh_of_type.iter().find(|(t, _)| *t == id) {
                Some((_, m)) => *m,
                None => {
                    let m = self.push_mesh(block.block_type, material)?;
                    mesh_of_type.push((id, m));
                    m
                }
            };
            nodes.push(self.push_node(scene, index, mesh)?);
        }
        Ok(nodes)
    }

    /// Adds the node of block `index`: its mesh at its pose (centre in metres, unit quaternion).
    fn push_node(
        &mut self,
        scene: &Scene,
        index: usize,
        mesh: json::Index<json::Mesh>,
    ) -> Result<json::Index<json::Node>, ExportError> {
        let block = &scene.blocks[index];
        let t = block.center_mm * METRES_PER_MM;
        let q = block.rotation();
        let length = q.length();
        if !(length.is_finite() && length > 0.0) {
            return Err(ExportError::BadPose {
                scene: scene.name.clone(),
                index,
            });
        }
        Ok(self.root.push(json::Node {
            mesh: Some(mesh),
            name: Some(format!("block_{index}_{}", block.block_type.id)),
            translation: Some([t.x as f32, t.y as f32, t.z as f32]),
            rotation: Some(json::scene::UnitQuaternion(
                q.to_array().map(|c| (c / length) as f32),
            )),
            ..Default::default()
        }))
    }

    /// Adds the glTF scene and fixes the buffer length.
    fn finish(mut self, scene: &Scene, nodes: Vec<json::Index<json::Node>>) -> GltfFiles {
        let gltf_scene = self.root.push(json::Scene {
            extensions: Default::default(),
            extras: Default::default(),
            name: Some(scene.name.clone()),
            nodes,
        });
        self.root.scene = Some(gltf_scene);
        self.root.buffers[0].byte_length = USize64::from(self.bin.len());
        GltfFiles {
            root: self.root,
            bin: self.bin,
        }
    }
}

fn vec3_bytes(v: &[[f32; 3]]) -> Vec<u8> {
    v.iter().flatten().flat_map(|c| c.to_le_bytes()).collect()
}

fn json_array(v: [f32; 3]) -> json::Value {
    json::Value::from(v.to_vec())
}

/// A file name as a relative URI: every byte outside RFC 3986's unreserved set
/// (`A-Z a-z 0-9 - . _ ~`) percent-encoded, so names with spaces or `#` still resolve.
fn uri_from_file_name(name: &str) -> String {
    name.bytes()
        .map(|b| match b {
            b'A'..=b'Z' | b'a'..=b'z' | b'0'..=b'9' | b'-' | b'.' | b'_' | b'~' => {
                (b as char).to_string()
            }
            _ => format!("%{b:02X}"),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::DVec3;
    use crate::scene::{Block, Orientation};
    use glam::DQuat;

    fn two_blocks() -> Scene {
        Scene::new(
            "pair",
            vec![
                Block::new("b30", DVec3::new(0.0, 7.5, 0.0), 0.0),
                Block::new("b15", DVec3::new(0.0, 22.5, 0.0), 30.0),
                Block::new("b30", DVec3::new(40.0, 7.5, 0.0), 90.0),
            ],
        )
    }

    #[test]
    fn one_mesh_per_type_one_node_per_block() {
        let files = scene_to_gltf(&two_blocks()).unwrap();
        let names: Vec<_> = files.root.meshes.iter().map(|m| m.name.clone()).collect();
        assert_eq!(names, [Some("b30".into()), Some("b15".into())]);
        let nodes: Vec<_> = files.root.nodes.iter().map(|n| n.name.clone()).collect();
        assert_eq!(
            nodes,
            [
                Some("block_0_b30".into()),
                Some("block_1_b15".into()),
                Some("block_2_b30".into())
            ]
        );
        assert_eq!(files.root.nodes[2].mesh, files.root.nodes[0].mesh);
        assert_eq!(files.root.nodes[0].translation, Some([0.0, 0.0075, 0.0]));
        assert_eq!(files.root.scenes[0].name.as_deref(), Some("pair"));
        assert_eq!(
            files.root.buffers[0].byte_length.0 as usize,
            files.bin.len()
        );
        // 2 meshes x (24 positions + 24 normals) x 12 bytes + 2 x 36 indices x 4 bytes.
        assert_eq!(files.bin.len(), 2 * 48 * 12 + 2 * 36 * 4);
    }

    #[test]
    fn glb_and_gltf_pass_gltf_validation() {
        let glb = scene_to_glb(&two_blocks()).unwrap();
        assert_eq!(&glb[..4], b"glTF");
        let read = gltf::Gltf::from_slice(&glb).unwrap();
        assert_eq!(read.document.nodes().count(), 3);
        let (text, bin) = scene_to_gltf_json(&two_blocks(), "pair.bin").unwrap();
        assert!(text.contains("\"uri\": \"pair.bin\""), "{text}");
        let read = gltf::Gltf::from_slice(text.as_bytes()).unwrap();
        assert_eq!(read.document.buffers().next().unwrap().length(), bin.len());
    }

    #[test]
    fn empty_and_non_finite_scenes_are_refused() {
        let empty = Scene::new("nothing", vec![]);
        assert!(matches!(
            scene_to_glb(&empty),
            Err(ExportError::NoBlocks { .. })
        ));
        let mut nan = two_blocks();
        nan.blocks[1].center_mm.x = f64::NAN;
        let msg = scene_to_glb(&nan).unwrap_err().to_string();
        assert!(msg.contains("block 1") && msg.contains("pair"), "{msg}");
        let mut zero = two_blocks();
        zero.blocks[2].orientation = Orientation::Quaternion(DQuat::from_xyzw(0.0, 0.0, 0.0, 0.0));
        assert!(matches!(
            scene_to_glb(&zero),
            Err(ExportError::BadPose { index: 2, .. })
        ));
    }

    #[test]
    fn rotations_are_written_as_unit_quaternions() {
        let mut s = two_blocks();
        let q = DQuat::from_rotation_y(0.5) * 2.0;
        s.blocks[0].orientation = Orientation::Quaternion(q);
        let files = scene_to_gltf(&s).unwrap();
        let r = files.root.nodes[0].rotation.unwrap().0;
        let want = (q / 2.0).to_array();
        for k in 0..4 {
            assert!(
                (f64::from(r[k]) - want[k]).abs() < 1e-7,
                "{r:?} vs {want:?}"
            );
        }
    }

    #[test]
    fn bin_file_names_become_uris() {
        assert_eq!(uri_from_file_name("scene-1_a.bin"), "scene-1_a.bin");
        assert_eq!(uri_from_file_name("my scene#2.bin"), "my%20scene%232.bin");
        assert_eq!(uri_from_file_name("ü.bin"), "%C3%BC.bin");
    }
}
