//! `blockworld settle` end to end (docs/datasets.md "Settling"): a stable scene is written snapped to
//! its intended poses and settling it again changes no byte; an unstable one is reported block
//! by block, exits non-zero and writes nothing unless `--allow-drift`.

mod common;

use std::path::Path;

const STABLE: &str = r#"{"name": "two_layer",
  "blocks": [{"type": "b30", "center": [0, 7.5, 0]},
             {"type": "b15", "center": [0, 22.5, 0], "yaw_deg": 90},
             {"type": "b7_5", "center": [40, 3.75, 0]}],
  "expect": {"supported": true}}"#;

/// A b15 shifted 10 mm on a b15: its centre of mass is 2.5 mm beyond the edge.
const UNSTABLE: &str = r#"{"name": "tips",
  "blocks": [{"type": "b15", "center": [0, 7.5, 0]},
             {"type": "b15", "center": [10, 22.5, 0]}]}"#;

fn settle(input: &Path, output: &Path, extra: &[&str]) -> std::process::Output {
    let (input, output) = (input.to_str().unwrap(), output.to_str().unwrap());
    common::blockworld(["settle", input, "-o", output].iter().chain(extra))
}

#[test]
fn a_stable_scene_is_written_and_settling_again_changes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let (input, once, twice) = (
        dir.path().join("in.json"),
        dir.path().join("once.json"),
        dir.path().join("twice.json"),
    );
    std::fs::write(&input, STABLE).unwrap();
    let out = settle(&input, &once, &[]);
    common::ok(&out);
    let settled = blockworld::scene::read_scene(&once).unwrap();
    let intended = blockworld::scene::read_scene(&input).unwrap();
    for (a, b) in settled.blocks.iter().zip(&intended.blocks) {
        assert_eq!(a.center_mm, b.center_mm, "stable poses are snapped back");
        assert!(a.rotation().angle_between(b.rotation()) < 1e-12);
    }
    let text = std::fs::read_to_string(&once).unwrap();
    assert!(
        text.contains("\"rotation\"") && text.contains("\"max_drift_mm\""),
        "{text}"
    );
    let out = settle(&once, &twice, &[]);
    assert!(out.status.success());
    assert_eq!(
        std::fs::read(&once).unwrap(),
        std::fs::read(&twice).unwrap()
    );
}

#[test]
fn an_unstable_scene_fails_names_the_block_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let (input, output) = (dir.path().join("in.json"), dir.path().join("out.json"));
    std::fs::write(&input, UNSTABLE).unwrap();
    let out = settle(&input, &output, &[]);
    let err = common::fails_with_2(&out);
    assert!(
        err.contains("not stable") && err.contains("block 1 (b15): drift"),
        "{err}"
    );
    assert!(!output.exists(), "nothing written without --allow-drift");
    assert_eq!(
        std::fs::read_dir(dir.path()).unwrap().count(),
        1,
        "no temporary left"
    );

    let out = settle(&input, &output, &["--allow-drift"]);
    common::ok(&out);
    let text = std::fs::read_to_string(&output).unwrap();
    let drifted: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(drifted["meta"]["settle"]["stable"], false);
    let x = drifted["blocks"][1]["center"][0].as_f64().unwrap();
    assert!(x > 12.0, "the drifted pose is written: x = {x}");
    // rapier leaves the drifted blocks within the 0.05 mm contact tolerance: the file validates.
    blockworld::scene::read_scene(&output).unwrap();
}

#[test]
fn a_missing_file_is_a_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    let out = settle(
        &dir.path().join("nope.json"),
        &dir.path().join("o.json"),
        &[],
    );
    let err = common::fails_with_2(&out);
    assert!(err.contains("nope.json"), "{err}");
}
