//! Stability datasets end to end (docs/stability.md): `generate --keep-unstable` keeps both
//! classes in the drawn balance, the same bytes whatever `--jobs` or sharding; every label
//! agrees with settling the written scene again; a scene labelled stable stays within the
//! tolerances and one labelled unstable moves beyond them; trajectories read back and end
//! where the simulation ends; bad options exit 2.

mod common;
use common::{assert_same_tree, blockworld, fails_with_2, ok};

use blockworld::physics::{label_stability, settle_recorded, SettleParams, Trajectory};
use blockworld::scene::{read_scene, Scene};
use serde_json::Value;
use std::path::Path;

/// `generate --count COUNT --seed 3 --views "" -o DIR EXTRA...`.
fn run_generate(dir: &Path, count: u32, extra: &[&str]) -> std::process::Output {
    let count = count.to_string();
    let mut args = vec![
        "generate", "--count", &count, "--seed", "3", "--views", "", "-o",
    ];
    args.push(dir.to_str().unwrap());
    args.extend_from_slice(extra);
    blockworld(&args)
}

/// A stability dataset with trajectories; returns its stdout.
fn generate(dir: &Path, count: u32, extra: &[&str]) -> String {
    let mut args = vec!["--keep-unstable", "--trajectory"];
    args.extend_from_slice(extra);
    ok(run_generate(dir, count, &args))
}

fn manifest(dir: &Path) -> Vec<Value> {
    std::fs::read_to_string(dir.join("manifest.jsonl"))
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

/// The scene as drawn: its blocks without the labels and reports `generate` added.
fn drawn(scene: &Scene) -> Scene {
    Scene::new(scene.name.clone(), scene.blocks.clone())
}

#[test]
fn both_classes_in_balance_and_the_same_bytes_whatever_jobs_and_shards() {
    let tmp = tempfile::tempdir().unwrap();
    let (a, b, sharded) = (
        tmp.path().join("a"),
        tmp.path().join("b"),
        tmp.path().join("s"),
    );
    let out = generate(&a, 24, &["--jobs", "1", "--gltf"]);
    generate(&b, 24, &["--jobs", "2", "--gltf"]);
    assert_same_tree(&a, &b);
    for shard in ["0/3", "1/3", "2/3"] {
        generate(&sharded, 24, &["--jobs", "2", "--gltf", "--shard", shard]);
    }
    ok(blockworld(["merge", sharded.to_str().unwrap()]));
    let whole = std::fs::read(a.join("manifest.jsonl")).unwrap();
    assert_eq!(
        whole,
        std::fs::read(sharded.join("manifest.jsonl")).unwrap()
    );
    let unstable = manifest(&a).iter().filter(|e| e["stable"] == false).count();
    assert!(
        (8..=16).contains(&unstable),
        "{unstable} of 24 unstable at 0.5"
    );
    assert!(
        out.contains(&format!("stability: {unstable} of 24 scenes do not stand")),
        "{out}"
    );
    for e in manifest(&a) {
        let files = e["files"].as_object().unwrap();
        for name in ["scene.json", "scene.glb", "trajectory.bin", "fall.glb"] {
            assert!(files.contains_key(name), "{name} in {e}");
        }
    }
    let options: Value =
        serde_json::from_str(&std::fs::read_to_string(a.join("dataset.json")).unwrap()).unwrap();
    assert_eq!(options["stability"]["stable_fraction"], 0.5);
    assert_eq!(options["stability"]["trajectory_fps"], 30.0);
}

/// The stable fraction decides the balance: all, none, and the flag-free dataset has no labels.
#[test]
fn the_stable_fraction_decides_the_classes() {
    let tmp = tempfile::tempdir().unwrap();
    for (fraction, want_unstable) in [("1", 0), ("0", 8)] {
        let dir = tmp.path().join(fraction);
        generate(&dir, 8, &["--stable-fraction", fraction]);
        let unstable = manifest(&dir)
            .iter()
            .filter(|e| e["stable"] == false)
            .count();
        assert_eq!(unstable, want_unstable, "--stable-fraction {fraction}");
    }
    let plain = tmp.path().join("plain");
    ok(run_generate(&plain, 4, &[]));
    let text = std::fs::read_to_string(plain.join("manifest.jsonl")).unwrap();
    assert!(!text.contains("\"stable\""), "{text}");
    let scene = std::fs::read_to_string(plain.join("s000000/scene.json")).unwrap();
    assert!(!scene.contains("stability") && !scene.contains("perturbation"));
}

#[test]
fn labels_agree_with_a_resettle_and_the_classes_with_the_tolerances() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("ds");
    generate(&dir, 22, &["--jobs", "2"]);
    let params = SettleParams::default();
    let mut causes = std::collections::BTreeSet::new();
    for e in manifest(&dir) {
        let folder = dir.join(e["id"].as_str().unwrap());
        let scene = read_scene(&folder.join("scene.json")).unwrap();
        let meta = &scene.meta.as_ref().unwrap()["stability"];
        let (settled, motion) = settle_recorded(&drawn(&scene), &params, true).unwrap();
        let label = label_stability(&drawn(&scene), &settled.report, &motion, &params).unwrap();
        assert_eq!(&label.to_meta(), meta, "{}", folder.display());
        assert_eq!(e["stable"], Value::Bool(label.stable));
        if label.stable {
            assert!(settled.report.max_drift_mm <= params.drift_tol_mm);
            assert!(label.max_displacement_mm < params.drift_tol_mm, "{label:?}");
        } else {
            assert!(label.max_displacement_mm > params.drift_tol_mm, "{label:?}");
            assert!(!settled.report.moved_blocks(&params).is_empty() || !settled.report.at_rest);
            let first = label
                .first_moved
                .expect("an unstable scene has a first mover");
            assert!(label.moved_blocks.contains(&first.block));
            causes.insert(label.cause.unwrap().name());
        }
        let bytes = std::fs::read(folder.join("trajectory.bin")).unwrap();
        let t = Trajectory::from_bytes(&bytes).unwrap();
        assert_eq!(bytes, motion.trajectory.unwrap().to_bytes());
        let last = t.frames.last().unwrap();
        let end = settled.report.steps as f64 * params.dt_s;
        assert!(
            (t.times_s.last().unwrap() - end).abs() < 1e-6,
            "ends at {end} s"
        );
        if !label.stable {
            for (pose, block) in last.iter().zip(&settled.scene.blocks) {
                assert!(
                    pose.0.distance(block.center_mm) < 1e-3,
                    "last frame = settled pose"
                );
            }
        }
    }
    assert!(causes.len() >= 2, "{causes:?}");
}

#[test]
fn bad_stability_options_exit_2_naming_the_fix() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("ds");
    let o = run_generate(&out, 2, &["--keep-unstable", "--stable-fraction", "1.5"]);
    let err = fails_with_2(&o);
    assert!(
        err.contains("--stable-fraction 1.5") && err.contains("from 0 to 1"),
        "{err}"
    );
    assert!(!out.exists(), "nothing written");
    let o = run_generate(&out, 2, &["--trajectory"]);
    let err = fails_with_2(&o);
    assert!(err.contains("--keep-unstable"), "{err}");
}

/// The files `generate --trajectory-views ne,sw --trajectory-every 4` writes for a trajectory
/// of `frames` frames: frames 0, 4, 8, ... and the last, each view's five files.
fn expected_frame_files(frames: usize) -> std::collections::BTreeSet<String> {
    let mut chosen: Vec<usize> = (0..frames).step_by(4).collect();
    if chosen.last() != Some(&(frames - 1)) {
        chosen.push(frames - 1);
    }
    let mut names = std::collections::BTreeSet::new();
    for k in chosen {
        for v in ["ne", "sw"] {
            for file in ["view_", "depth_", "ids_"].map(|f| format!("{f}{v}.png")) {
                names.insert(format!("frames/f{k:04}_{file}"));
            }
            for file in ["lines_", "camera_"].map(|f| format!("{f}{v}.json")) {
                names.insert(format!("frames/f{k:04}_{file}"));
            }
        }
    }
    names
}

/// Checks one scene folder's rendered frames against its manifest entry and its trajectory;
/// returns whether its first and last frames differ in every ground-truth file.
fn check_frames(folder: &Path, entry: &Value) -> bool {
    let files = entry["files"].as_object().unwrap();
    let listed: std::collections::BTreeSet<String> = files
        .keys()
        .filter(|k| k.starts_with("frames/"))
        .cloned()
        .collect();
    let on_disk: std::collections::BTreeSet<String> = std::fs::read_dir(folder.join("frames"))
        .unwrap()
        .map(|f| format!("frames/{}", f.unwrap().file_name().to_string_lossy()))
        .collect();
    let scene = read_scene(&folder.join("scene.json")).unwrap();
    let t = Trajectory::from_bytes(&std::fs::read(folder.join("trajectory.bin")).unwrap()).unwrap();
    let last = t.frames.len() - 1;
    assert_eq!(listed, expected_frame_files(t.frames.len()), "{entry}");
    assert_eq!(on_disk, listed, "{}", folder.display());
    for name in &listed {
        let sha = blockworld::dataset::sha256_hex(&std::fs::read(folder.join(name)).unwrap());
        assert_eq!(files[name], Value::String(sha), "{name} of {entry}");
    }
    let read = |k: usize, file: &str| std::fs::read(folder.join(format!("frames/f{k:04}_{file}")));
    let mut moved = true;
    for v in ["ne", "sw"] {
        let camera_text =
            String::from_utf8(read(last, &format!("camera_{v}.json")).unwrap()).unwrap();
        assert_eq!(
            read(0, &format!("camera_{v}.json")).unwrap(),
            camera_text.as_bytes(),
            "every frame is seen by one camera"
        );
        // The last frame's line drawing is the exact drawing of the blocks at its poses.
        let camera = blockworld::camera::parse_camera_json(&camera_text).unwrap();
        let posed = t.scene_at(&drawn(&scene), last).unwrap();
        let exact = blockworld::linedraw::visible_line_drawing(&posed, &camera).to_json();
        assert_eq!(
            String::from_utf8(read(last, &format!("lines_{v}.json")).unwrap()).unwrap(),
            exact,
            "{} frame {last} {v}",
            folder.display()
        );
        for kind in ["ids_", "depth_", "view_"].map(|f| format!("{f}{v}.png")) {
            moved &= read(0, &kind).unwrap() != read(last, &kind).unwrap();
        }
        moved &= read(0, &format!("lines_{v}.json")).unwrap()
            != read(last, &format!("lines_{v}.json")).unwrap();
    }
    moved
}

/// `--trajectory-views` renders frames 0, every 4th and the last of each trajectory with the
/// ground truth of each frame, listed in the manifest with their sha256, the same bytes
/// whatever `--jobs`; a falling scene's first and last frames differ in every file.
#[test]
fn rendered_frames_hold_each_frames_ground_truth_and_the_same_bytes_whatever_jobs() {
    if !common::renderer_available() {
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let (a, b) = (tmp.path().join("a"), tmp.path().join("b"));
    let frames = ["--trajectory-views", "ne,sw", "--size", "128x120"];
    generate(&a, 6, &[&frames[..], &["--jobs", "1"]].concat());
    generate(&b, 6, &[&frames[..], &["--jobs", "2"]].concat());
    assert_same_tree(&a, &b);
    let mut falls = 0;
    for e in manifest(&a) {
        let folder = a.join(e["id"].as_str().unwrap());
        let moved = check_frames(&folder, &e);
        if e["stable"] == false {
            assert!(moved, "{}: first and last frames differ", folder.display());
            falls += 1;
        }
    }
    assert!(falls >= 2, "{falls} falling scenes of 6");
    let options: Value =
        serde_json::from_str(&std::fs::read_to_string(a.join("dataset.json")).unwrap()).unwrap();
    assert_eq!(
        options["stability"]["trajectory_views"],
        serde_json::json!(["ne", "sw"])
    );
    assert_eq!(options["stability"]["trajectory_every"], 4);
}

/// Unknown views, `--trajectory-every 0` and more pictures per scene than the bound exit 2
/// naming the flag, and write nothing.
#[test]
fn bad_frame_options_exit_2_naming_the_flag() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("ds");
    for (extra, want) in [
        (
            &["--trajectory-views", "up"][..],
            "--trajectory-views: unknown view \"up\"",
        ),
        (
            &["--trajectory-views", "ne", "--trajectory-every", "0"][..],
            "--trajectory-every 0",
        ),
        (
            &["--trajectory-views", "ne,se,sw", "--trajectory-every", "2"][..],
            "use --trajectory-every 3 or more",
        ),
        (
            &["--trajectory-views", ""][..],
            "--trajectory-views: name at least one",
        ),
    ] {
        let args = [&["--keep-unstable", "--trajectory"][..], extra].concat();
        let err = fails_with_2(&run_generate(&out, 2, &args));
        assert!(err.contains(want), "{extra:?}: {err}");
        assert!(!out.exists(), "{extra:?}: nothing written");
    }
    let err = fails_with_2(&run_generate(&out, 2, &["--trajectory-every", "2"]));
    assert!(err.contains("--trajectory-views"), "{err}");
}

/// Two falls with the same glTF document whose buffers agree word for word within 1e-7 (the
/// trajectory file keeps f32 poses, generate keyed the glTF from the simulation's f64: the
/// metres can differ in the last bit).
fn same_fall(a: &Path, b: &Path) {
    let (a, b) = (std::fs::read(a).unwrap(), std::fs::read(b).unwrap());
    let (a, b) = (
        gltf::Glb::from_slice(&a).unwrap(),
        gltf::Glb::from_slice(&b).unwrap(),
    );
    assert_eq!(a.json, b.json, "the glTF documents differ");
    let words = |bin: &[u8]| -> Vec<f32> {
        bin.chunks_exact(4)
            .map(|w| f32::from_le_bytes(w.try_into().unwrap()))
            .collect()
    };
    let (wa, wb) = (
        words(a.bin.as_deref().unwrap()),
        words(b.bin.as_deref().unwrap()),
    );
    assert_eq!(wa.len(), wb.len());
    let apart = wa
        .iter()
        .zip(&wb)
        .filter(|(x, y)| {
            let d = (*x - *y).abs();
            x.to_bits() != y.to_bits() && (d > 1e-7 || d.is_nan())
        })
        .count();
    assert_eq!(apart, 0, "buffer words differ by more than 1e-7");
}

/// `export SCENE --trajectory trajectory.bin -o fall.glb` rebuilds the fall `generate --gltf`
/// wrote (the same document, the same keyframes to f32's last bit); another scene's trajectory (another block count) and a trajectory with
/// the thesis format are refused with exit 2, naming what is wrong, and nothing is written.
#[test]
fn export_rebuilds_the_fall_from_its_trajectory_and_refuses_a_foreign_one() {
    let tmp = tempfile::tempdir().unwrap();
    let ds = tmp.path().join("ds");
    generate(&ds, 6, &["--gltf"]);
    let entries = manifest(&ds);
    let folder = |e: &Value| ds.join(e["id"].as_str().unwrap());
    let falls: Vec<&Value> = entries.iter().filter(|e| e["stable"] == false).collect();
    assert!(!falls.is_empty(), "seed 3 draws a fall among 6 scenes");
    let dir = folder(falls[0]);
    let glb = tmp.path().join("fall.glb");
    let export = |trajectory: &Path, out: &Path, extra: &[&str]| {
        let mut args: Vec<std::ffi::OsString> = vec![
            "export".into(),
            dir.join("scene.json").into(),
            "--trajectory".into(),
            trajectory.into(),
            "-o".into(),
            out.into(),
        ];
        args.extend(extra.iter().map(Into::into));
        blockworld(&args)
    };
    ok(export(&dir.join("trajectory.bin"), &glb, &[]));
    same_fall(&glb, &dir.join("fall.glb"));
    let blocks = |e: &Value| {
        read_scene(&folder(e).join("scene.json"))
            .unwrap()
            .blocks
            .len()
    };
    let foreign = entries
        .iter()
        .find(|e| blocks(e) != blocks(falls[0]))
        .expect("two block counts among 6 scenes");
    let other = tmp.path().join("other.glb");
    let err = fails_with_2(&export(
        &folder(foreign).join("trajectory.bin"),
        &other,
        &[],
    ));
    assert!(err.contains("poses for"), "{err}");
    let prefix = tmp.path().join("thesis");
    let err = fails_with_2(&export(
        &dir.join("trajectory.bin"),
        &prefix,
        &["--format", "thesis"],
    ));
    assert!(err.contains("--trajectory"), "{err}");
    assert!(!other.exists() && !prefix.with_file_name("thesis_vertices.txt").exists());
}
