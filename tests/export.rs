//! glTF export, end to end: scenes exported as .glb and .gltf + .bin, read back and validated
//! by `gltf::Gltf::from_slice`, and compared with the scene and the block catalog (node poses,
//! mesh bounds, triangle counts, enclosed volumes); the `blockworld export` command.

mod common;
use common::blockworld;

use blockworld::export::{scene_to_glb, scene_to_gltf_json};
use blockworld::geom::DVec3;
use blockworld::scene::{block_type, read_scene, Block, Orientation, Scene};
use glam::DQuat;
use gltf::buffer::Source;
use std::path::Path;

const THESIS_SAMPLE: &str = "scenes/thesis_sample.json";

/// Tolerance on translations and rotations: f32 storage of values below 1 (about 6e-8 each).
const POSE_TOL: f64 = 1e-6;
/// Relative tolerance on volumes from the exported triangles: positions are f32 (24-bit
/// mantissa, about 6e-8 relative per coordinate), so a volume is good to a few 1e-7 (measured:
/// 6.7e-8 for b15, b30 and b7_5); 1e-9 is below what f32 positions can hold.
const VOLUME_REL_TOL: f64 = 1e-6;

fn thesis_sample() -> Scene {
    read_scene(Path::new(THESIS_SAMPLE)).unwrap()
}

/// A scene with turned blocks: a yaw about +y, and a b30 stood on end by a quaternion.
fn turned_scene() -> Scene {
    let mut standing = Block::new("b30", DVec3::new(60.0, 15.0, 0.0), 0.0);
    standing.orientation = Orientation::Quaternion(
        DQuat::from_rotation_z(std::f64::consts::FRAC_PI_2) * DQuat::from_rotation_y(0.3),
    );
    Scene::new(
        "turned",
        vec![
            Block::new("b30", DVec3::new(0.0, 7.5, 0.0), 30.0),
            Block::new("b7_5", DVec3::new(0.0, 18.75, 0.0), -45.0),
            standing,
        ],
    )
}

/// Checks a read-back glTF against its scene; `bin` is the buffer for a .gltf (the GLB's own
/// BIN chunk is used otherwise).
fn check_against_scene(scene: &Scene, gltf: &gltf::Gltf, bin: Option<&[u8]>) {
    let doc = &gltf.document;
    let gltf_scene = doc.default_scene().expect("a default scene");
    assert_eq!(gltf_scene.name(), Some(scene.name.as_str()));
    assert_eq!(gltf_scene.nodes().count(), scene.blocks.len());
    assert_eq!(doc.nodes().count(), scene.blocks.len());
    for (i, (node, block)) in gltf_scene.nodes().zip(&scene.blocks).enumerate() {
        let id = block.block_type.id;
        assert_eq!(node.name(), Some(format!("block_{i}_{id}").as_str()));
        let (t, r, s) = node.transform().decomposed();
        assert_eq!(s, [1.0, 1.0, 1.0]);
        let want_t = block.center_mm * 0.001;
        for k in 0..3 {
            assert!(
                (f64::from(t[k]) - want_t[k]).abs() < POSE_TOL,
                "node {i}: {t:?}"
            );
        }
        let want_r = block.rotation().normalize().to_array();
        for k in 0..4 {
            assert!(
                (f64::from(r[k]) - want_r[k]).abs() < POSE_TOL,
                "node {i}: {r:?}"
            );
        }
        let mesh = node.mesh().expect("every block node has a mesh");
        assert_eq!(mesh.name(), Some(id));
        check_world_vertices(block, &node, gltf, bin);
    }
    for mesh in doc.meshes() {
        check_mesh_against_catalog(&mesh, gltf, bin);
    }
}

/// Positions (as read, widened to f64), triangle indices and the number of normals of a
/// primitive; `bin` is the .gltf's buffer (a GLB's BIN chunk is used otherwise).
fn read_primitive(
    prim: &gltf::Primitive,
    gltf: &gltf::Gltf,
    bin: Option<&[u8]>,
) -> (Vec<DVec3>, Vec<u32>, usize) {
    let reader = prim.reader(|b| match b.source() {
        Source::Bin => gltf.blob.as_deref(),
        Source::Uri(_) => bin,
    });
    let positions = reader
        .read_positions()
        .expect("POSITION")
        .map(|p| DVec3::from_array(p.map(f64::from)))
        .collect();
    let indices = reader.read_indices().expect("indices").into_u32().collect();
    let normal_count = reader.read_normals().expect("NORMAL").count();
    (positions, indices, normal_count)
}

/// The mesh placed by its node's transform lands on the block's world vertices (mm x 0.001):
/// the rotation and translation conventions agree with `Block::world_point`.
fn check_world_vertices(block: &Block, node: &gltf::Node, gltf: &gltf::Gltf, bin: Option<&[u8]>) {
    let (t, r, _) = node.transform().decomposed();
    let q = DQuat::from_array(r.map(f64::from));
    let t = DVec3::from_array(t.map(f64::from));
    let world: Vec<DVec3> = block.world_vertices().iter().map(|v| *v * 0.001).collect();
    let mesh = node.mesh().unwrap();
    for prim in mesh.primitives() {
        let (positions, _, _) = read_primitive(&prim, gltf, bin);
        for p in positions {
            let placed = t + q * p;
            let nearest = world
                .iter()
                .map(|w| w.distance(placed))
                .fold(f64::INFINITY, f64::min);
            assert!(
                nearest < 1e-6,
                "{placed:?} is {nearest} m from every vertex"
            );
        }
    }
}

/// POSITION bounds, triangle count and enclosed volume of one mesh against its catalog row.
fn check_mesh_against_catalog(mesh: &gltf::Mesh, gltf: &gltf::Gltf, bin: Option<&[u8]>) {
    let t = block_type(mesh.name().unwrap()).expect("mesh named by a catalog id");
    let (lo, hi) = t.local_bounds_mm();
    let prims: Vec<_> = mesh.primitives().collect();
    assert_eq!(prims.len(), 1);
    let prim = &prims[0];
    assert_eq!(prim.mode(), gltf::mesh::Mode::Triangles);
    let bbox = prim.bounding_box();
    for k in 0..3 {
        assert!(
            (f64::from(bbox.min[k]) - lo[k] * 0.001).abs() < 1e-9,
            "{}",
            t.id
        );
        assert!(
            (f64::from(bbox.max[k]) - hi[k] * 0.001).abs() < 1e-9,
            "{}",
            t.id
        );
    }
    let (positions, indices, normal_count) = read_primitive(prim, gltf, bin);
    let want_triangles: usize = t.faces().iter().map(|f| f.len() - 2).sum();
    assert_eq!(indices.len(), 3 * want_triangles, "{}", t.id);
    assert_eq!(normal_count, positions.len());
    let volume_m3: f64 = indices
        .chunks(3)
        .map(|tri| {
            let [a, b, c] = [0, 1, 2].map(|k| positions[tri[k] as usize]);
            a.dot(b.cross(c)) / 6.0
        })
        .sum();
    let want = t.volume_mm3() * 1e-9;
    let rel = ((volume_m3 - want) / want).abs();
    eprintln!(
        "{}: volume {volume_m3:e} m^3, catalog {want:e}, relative error {rel:e}",
        t.id
    );
    assert!(rel < VOLUME_REL_TOL, "{}: {volume_m3} vs {want}", t.id);
}

#[test]
fn thesis_sample_glb_reads_back_and_matches_the_scene() {
    let scene = thesis_sample();
    let glb = scene_to_glb(&scene).unwrap();
    let gltf = gltf::Gltf::from_slice(&glb).unwrap();
    assert!(gltf.blob.is_some(), "the GLB carries its BIN chunk");
    assert_eq!(gltf.document.meshes().count(), 3, "b15, b30, b7_5");
    check_against_scene(&scene, &gltf, None);
}

/// The Chapter VII parts export like any block: the wedge as its exact polyhedron, the round
/// part as its inscribed 64-sided prism (docs/formats.md "Block catalog"), each mesh checked against the
/// catalog's bounds, triangles and volume, each node against the scene's world vertices.
#[test]
fn wedge_and_round_part_glb_read_back_and_match_the_scene() {
    let scene = Scene::new(
        "chapter_vii_parts",
        vec![
            Block::new("b30", DVec3::new(0.0, 7.5, 0.0), 0.0),
            Block::new("w30", DVec3::new(0.0, 22.5, 0.0), 90.0),
            Block::new("c15", DVec3::new(30.0, 7.5, 0.0), 0.0),
        ],
    );
    scene.validate("parts").unwrap();
    let glb = scene_to_glb(&scene).unwrap();
    let gltf = gltf::Gltf::from_slice(&glb).unwrap();
    let names: Vec<&str> = gltf.document.meshes().filter_map(|m| m.name()).collect();
    assert_eq!(names.len(), 3, "{names:?}");
    assert!(
        names.contains(&"w30") && names.contains(&"c15"),
        "{names:?}"
    );
    check_against_scene(&scene, &gltf, None);
}

#[test]
fn thesis_sample_gltf_json_and_bin_read_back() {
    let scene = thesis_sample();
    let (text, bin) = scene_to_gltf_json(&scene, "thesis_sample.bin").unwrap();
    let gltf = gltf::Gltf::from_slice(text.as_bytes()).unwrap();
    assert!(gltf.blob.is_none());
    let buffer = gltf.document.buffers().next().unwrap();
    assert!(matches!(buffer.source(), Source::Uri("thesis_sample.bin")));
    assert_eq!(buffer.length(), bin.len());
    check_against_scene(&scene, &gltf, Some(&bin));
}

#[test]
fn turned_blocks_keep_their_rotation() {
    let scene = turned_scene();
    let glb = scene_to_glb(&scene).unwrap();
    let gltf = gltf::Gltf::from_slice(&glb).unwrap();
    assert_eq!(gltf.document.meshes().count(), 2, "b30 (twice) and b7_5");
    check_against_scene(&scene, &gltf, None);
    let (text, bin) = scene_to_gltf_json(&scene, "turned.bin").unwrap();
    let gltf = gltf::Gltf::from_slice(text.as_bytes()).unwrap();
    check_against_scene(&scene, &gltf, Some(&bin));
}

#[test]
fn same_scene_gives_the_same_bytes() {
    let scene = thesis_sample();
    assert_eq!(scene_to_glb(&scene).unwrap(), scene_to_glb(&scene).unwrap());
    assert_eq!(
        scene_to_gltf_json(&scene, "a.bin").unwrap(),
        scene_to_gltf_json(&scene, "a.bin").unwrap()
    );
    let turned = turned_scene();
    assert_ne!(
        scene_to_glb(&turned).unwrap(),
        scene_to_glb(&scene).unwrap()
    );
}

#[test]
fn cli_writes_a_glb_that_reads_back() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("sample.glb");
    let o = blockworld(["export", THESIS_SAMPLE, "-o", out.to_str().unwrap()]);
    common::ok(&o);
    let bytes = std::fs::read(&out).unwrap();
    assert_eq!(bytes, scene_to_glb(&thesis_sample()).unwrap());
    let gltf = gltf::Gltf::from_slice(&bytes).unwrap();
    check_against_scene(&thesis_sample(), &gltf, None);
    assert_eq!(
        std::fs::read_dir(dir.path()).unwrap().count(),
        1,
        "no leftovers"
    );
}

#[test]
fn cli_writes_gltf_with_its_bin_beside_it() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("my sample.gltf");
    let o = blockworld(["export", THESIS_SAMPLE, "-o", out.to_str().unwrap()]);
    common::ok(&o);
    let text = std::fs::read(&out).unwrap();
    let bin = std::fs::read(dir.path().join("my sample.bin")).unwrap();
    let gltf = gltf::Gltf::from_slice(&text).unwrap();
    let buffer = gltf.document.buffers().next().unwrap();
    assert!(matches!(buffer.source(), Source::Uri("my%20sample.bin")));
    check_against_scene(&thesis_sample(), &gltf, Some(&bin));
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 2);
}

#[test]
fn cli_refuses_an_unknown_extension_and_names_the_file() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["sample.obj", "sample"] {
        let out = dir.path().join(name);
        let o = blockworld(["export", THESIS_SAMPLE, "-o", out.to_str().unwrap()]);
        let err = common::fails_with_2(&o);
        assert!(err.contains(out.to_str().unwrap()), "{err}");
        assert!(err.contains(".glb") && err.contains(".gltf"), "{err}");
    }
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}

#[test]
fn cli_names_a_missing_scene_file() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.glb");
    let o = blockworld(["export", "no/such/scene.json", "-o", out.to_str().unwrap()]);
    let err = common::fails_with_2(&o);
    assert!(err.contains("no/such/scene.json"), "{err}");
    assert!(!out.exists());
}
