//! A reconstruction and its truth in one glTF file (Chapter VI "Display the Final Sample";
//! Chapter IV "Construction of the Final Sample", Figure 4.6): two node groups, `truth` and
//! `reconstruction`, each a parent node over one node per block, and three glTF scenes:
//! `overlay` (both, the default), `truth` and `reconstruction`. Each role has its own material
//! (truth blue, reconstruction red, half transparent so the two can be compared in place). The
//! block type of every block node, and the reconstruction's status, reason and CSG tree, are in
//! `extras`, so a viewer's inspector shows what the recognizer built.

use super::{DocumentBuilder, ExportError, GltfFiles};
use crate::scene::{Reconstruction, Scene};
use gltf::json;
use json::validation::Checked::Valid;
use json::validation::USize64;

/// A material's name and RGBA base colour factor.
type RoleMaterial = (&'static str, [f32; 4]);

/// The truth's material: opaque blue, as in the viewer's overlay.
const TRUTH_MATERIAL: RoleMaterial = ("truth", [0.12, 0.35, 0.86, 1.0]);
/// The reconstruction's material: red, half transparent, so the truth shows through.
const RECONSTRUCTION_MATERIAL: RoleMaterial = ("reconstruction", [0.86, 0.16, 0.16, 0.5]);

/// Builds the glTF document holding `recon` and its `truth` (see the module docs). Empty
/// groups are allowed (an unsupported reconstruction has no blocks), but not both empty.
pub fn reconstruction_with_truth_to_gltf(
    truth: &Scene,
    recon: &Reconstruction,
) -> Result<GltfFiles, ExportError> {
    let recon_scene = recon.to_scene();
    if truth.blocks.is_empty() && recon_scene.blocks.is_empty() {
        return Err(ExportError::NoBlocks {
            scene: truth.name.clone(),
        });
    }
    let mut doc = DocumentBuilder::new(truth)?;
    DocumentBuilder::new(&recon_scene)?; // checks the reconstruction's poses
    let truth_group = push_group(
        &mut doc,
        truth,
        TRUTH_MATERIAL,
        extras_json(&serde_json::json!({"role": "truth"})),
    )?;
    let recon_extras = serde_json::json!({
        "role": "reconstruction",
        "status": recon.status,
        "reason": recon.reason,
        "csg": recon.csg,
    });
    let recon_group = push_group(
        &mut doc,
        &recon_scene,
        RECONSTRUCTION_MATERIAL,
        extras_json(&recon_extras),
    )?;
    for (name, nodes) in [
        ("overlay", vec![truth_group, recon_group]),
        ("truth", vec![truth_group]),
        ("reconstruction", vec![recon_group]),
    ] {
        let index = doc.root.push(json::Scene {
            extensions: Default::default(),
            extras: Default::default(),
            name: Some(name.to_string()),
            nodes,
        });
        if name == "overlay" {
            doc.root.scene = Some(index);
        }
    }
    doc.root.buffers[0].byte_length = USize64::from(doc.bin.len());
    Ok(GltfFiles {
        root: doc.root,
        bin: doc.bin,
    })
}

/// The binary glTF of [`reconstruction_with_truth_to_gltf`].
pub fn reconstruction_with_truth_to_glb(
    truth: &Scene,
    recon: &Reconstruction,
) -> Result<Vec<u8>, ExportError> {
    reconstruction_with_truth_to_gltf(truth, recon)?.to_glb()
}

/// Adds one role's material, meshes (one per block type it uses) and block nodes under a
/// parent node named after the role; returns the parent.
fn push_group(
    doc: &mut DocumentBuilder,
    scene: &Scene,
    (name, colour): RoleMaterial,
    extras: json::extras::Extras,
) -> Result<json::Index<json::Node>, ExportError> {
    let material = doc.root.push(material(name, colour));
    let children = doc.push_block_nodes(scene, Some(material))?;
    for (index, (block, &node)) in scene.blocks.iter().zip(&children).enumerate() {
        let id = block.block_type.id;
        let n = &mut doc.root.nodes[node.value()];
        n.name = Some(format!("{name}_block_{index}_{id}"));
        n.extras = extras_json(&serde_json::json!({ "block_type": id, "block": index }));
        if let Some(mesh) = n.mesh {
            doc.root.meshes[mesh.value()].name = Some(format!("{name}_{id}"));
        }
    }
    Ok(doc.root.push(json::Node {
        name: Some(name.to_string()),
        children: (!children.is_empty()).then_some(children),
        extras,
        ..Default::default()
    }))
}

/// A metallic-roughness material of one flat colour, double-sided off; blended when its alpha
/// is below 1.
fn material(name: &str, colour: [f32; 4]) -> json::Material {
    json::Material {
        name: Some(name.to_string()),
        alpha_mode: Valid(if colour[3] < 1.0 {
            json::material::AlphaMode::Blend
        } else {
            json::material::AlphaMode::Opaque
        }),
        pbr_metallic_roughness: json::material::PbrMetallicRoughness {
            base_color_factor: json::material::PbrBaseColorFactor(colour),
            metallic_factor: json::material::StrengthFactor(0.0),
            roughness_factor: json::material::StrengthFactor(0.9),
            ..Default::default()
        },
        ..Default::default()
    }
}

/// A JSON value as glTF `extras`.
fn extras_json(v: &serde_json::Value) -> json::extras::Extras {
    serde_json::value::to_raw_value(v).ok()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::DVec3;
    use crate::scene::{Block, CsgNode};

    fn truth() -> Scene {
        Scene::new(
            "two_layer",
            vec![
                Block::new("b30", DVec3::new(0.0, 7.5, 0.0), 0.0),
                Block::new("b15", DVec3::new(0.0, 22.5, 0.0), 0.0),
            ],
        )
    }

    fn recon() -> Reconstruction {
        let mut r = Reconstruction::ok("two_layer", truth().blocks);
        r.csg = Some(CsgNode::Union(vec![CsgNode::Block(0), CsgNode::Block(1)]));
        r
    }

    #[test]
    fn two_groups_three_scenes_a_material_per_role_and_extras() {
        let files = reconstruction_with_truth_to_gltf(&truth(), &recon()).unwrap();
        let root = &files.root;
        let names: Vec<_> = root
            .scenes
            .iter()
            .map(|s| s.name.clone().unwrap())
            .collect();
        assert_eq!(names, ["overlay", "truth", "reconstruction"]);
        let materials: Vec<_> = root
            .materials
            .iter()
            .map(|m| m.name.clone().unwrap())
            .collect();
        assert_eq!(materials, ["truth", "reconstruction"]);
        // Two meshes per role (b30, b15), each with its role's material.
        assert_eq!(root.meshes.len(), 4);
        let group = root
            .nodes
            .iter()
            .find(|n| n.name.as_deref() == Some("reconstruction"))
            .unwrap();
        let extras = group.extras.as_ref().unwrap().get();
        assert!(
            extras.contains(r#""csg":{"union":[{"block":0},{"block":1}]}"#),
            "{extras}"
        );
        assert!(extras.contains(r#""status":"ok""#));
        let block = root
            .nodes
            .iter()
            .find(|n| n.name.as_deref() == Some("truth_block_1_b15"))
            .unwrap();
        assert!(block
            .extras
            .as_ref()
            .unwrap()
            .get()
            .contains(r#""block_type":"b15""#));
        // The bytes parse back as glTF.
        let glb = files.to_glb().unwrap();
        let back = gltf::Gltf::from_slice(&glb).unwrap();
        assert_eq!(back.scenes().count(), 3);
        assert_eq!(back.default_scene().unwrap().name(), Some("overlay"));
    }

    /// Read back with the `gltf` crate, every block node of both groups sits at its block's pose
    /// (centre in metres, rotation as the scene's quaternion).
    #[test]
    fn both_groups_read_back_at_their_blocks_poses() {
        let truth = truth();
        let mut recon = recon();
        recon.blocks[1].center_mm.x += 2.0;
        let glb = reconstruction_with_truth_to_glb(&truth, &recon).unwrap();
        let back = gltf::Gltf::from_slice(&glb).unwrap();
        let mut seen = 0;
        for node in back.nodes() {
            let Some(name) = node.name() else { continue };
            let (blocks, rest) = if let Some(r) = name.strip_prefix("truth_block_") {
                (&truth.blocks, r)
            } else if let Some(r) = name.strip_prefix("reconstruction_block_") {
                (&recon.blocks, r)
            } else {
                continue;
            };
            let index: usize = rest.split('_').next().unwrap().parse().unwrap();
            let b = &blocks[index];
            let (t, r, _) = node.transform().decomposed();
            let want = b.center_mm * 1e-3;
            for k in 0..3 {
                assert!(
                    (f64::from(t[k]) - want[k]).abs() < 1e-6,
                    "{name}: {t:?} vs {want}"
                );
            }
            let q = b.rotation();
            let dot = q.x * f64::from(r[0])
                + q.y * f64::from(r[1])
                + q.z * f64::from(r[2])
                + q.w * f64::from(r[3]);
            assert!(dot.abs() > 1.0 - 1e-6, "{name}: rotation {r:?}");
            seen += 1;
        }
        assert_eq!(seen, truth.blocks.len() + recon.blocks.len());
    }

    #[test]
    fn an_unsupported_reconstruction_is_an_empty_group_and_both_empty_is_an_error() {
        let r = Reconstruction::unsupported("two_layer", "overhang");
        let files = reconstruction_with_truth_to_gltf(&truth(), &r).unwrap();
        let group = files
            .root
            .nodes
            .iter()
            .find(|n| n.name.as_deref() == Some("reconstruction"))
            .unwrap();
        assert!(group.children.is_none());
        assert!(group.extras.as_ref().unwrap().get().contains("overhang"));
        let empty = Scene::new("empty", Vec::new());
        assert!(matches!(
            reconstruction_with_truth_to_gltf(&empty, &r),
            Err(ExportError::NoBlocks { .. })
        ));
    }
}
