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
