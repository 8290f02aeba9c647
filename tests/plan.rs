//! `blockworld plan` (docs/plan.md): the thesis sample's verified order, every supported suite
//! scene ordered or declined with a reason, a worse order refused by the verifier, and bad
//! input refused with exit 2 and no file written.

mod common;

use blockworld::physics::{plan_disassembly, verify_disassembly, PlanOutcome, PlanParams};
use blockworld::scene::{read_scene, Scene};
use std::path::Path;

fn thesis_sample() -> Scene {
    read_scene(&common::root().join("scenes/thesis_sample.json")).unwrap()
}

#[test]
fn the_thesis_sample_has_a_verified_order_and_the_same_bytes_twice() {
    let tmp = tempfile::tempdir().unwrap();
    let sample = common::root().join("scenes/thesis_sample.json");
    let out = tmp.path().join("plan.json");
    let run = || {
        let o = common::blockworld([
            "plan".as_ref(),
            sample.as_os_str(),
            "-o".as_ref(),
            out.as_os_str(),
        ]);
        common::ok(&o);
        std::fs::read(&out).unwrap()
    };
    let first = run();
    assert_eq!(first, run(), "plan is deterministic");
    let plan: serde_json::Value = serde_json::from_slice(&first).unwrap();
    assert_eq!(plan["status"], "ok", "{plan}");
    let order: Vec<usize> = plan["disassembly"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["block"].as_u64().unwrap() as usize)
        .collect();
    assert_eq!(order.len(), 5);
    let mut building: Vec<usize> = order.clone();
    building.reverse();
    let assembly: Vec<usize> = serde_json::from_value(plan["assembly_order"].clone()).unwrap();
    assert_eq!(assembly, building);
    // The upper layer (the b30 on the two cubes, the b7_5 on the back b30) goes first.
    assert!(
        order[..2].contains(&2) && order[..2].contains(&4),
        "{order:?}"
    );
    let steps = verify_disassembly(&thesis_sample().blocks, &order, &PlanParams::default())
        .unwrap()
        .expect("the verifier accepts the plan's own order");
    assert!(steps.iter().all(|s| s.rest_max_drift_mm <= 0.5));
    for step in plan["disassembly"].as_array().unwrap() {
        let g = &step["grasp"];
        assert_eq!(g["approach"], serde_json::json!([0.0, -1.0, 0.0]), "{step}");
        assert!(g["opening_mm"].as_f64().unwrap() <= 40.0, "{step}");
    }
}

#[test]
fn taking_a_supporting_block_first_is_rejected_by_the_verifier() {
    let blocks = thesis_sample().blocks;
    // Block 0, a cube under the b30 of block 2.
    let why = verify_disassembly(&blocks, &[0, 2, 1, 4, 3], &PlanParams::default())
        .unwrap()
        .unwrap_err();
    assert!(
        why.starts_with("step 1: taking block 0 (b15) moves block 2 (b30)"),
        "{why}"
    );
}

/// Every scene of a suite folder with whether it is meant to be recognized.
fn suite_scenes(dir: &Path) -> Vec<(String, Scene)> {
    common::json_files(dir)
        .into_iter()
        .filter_map(|p| Some((common::stem(&p), read_scene(&p).ok()?)))
        .collect()
}

/// Counts over the suites: (supported ordered, supported declined, others ordered, others
/// declined, steps without a grasp, steps whose grasp a neighbour blocks).
const COUNTS: [usize; 6] = [66, 0, 22, 0, 0, 11];

#[test]
fn every_suite_scene_is_ordered_or_declined_with_a_reason() {
    let params = PlanParams::default();
    let mut counts = [0; 6];
    let mut declined = Vec::new();
    for suite in ["scenes/bench", "scenes/chapter_vii"] {
        for (id, scene) in suite_scenes(&common::root().join(suite)) {
            let other = if scene.is_supported() { 0 } else { 2 };
            match plan_disassembly(&scene.blocks, &params).unwrap() {
                PlanOutcome::Ordered(steps) => {
                    assert_eq!(steps.len(), scene.blocks.len(), "{id}");
                    let order: Vec<usize> = steps.iter().map(|s| s.block).collect();
                    assert!(
                        verify_disassembly(&scene.blocks, &order, &params)
                            .unwrap()
                            .is_ok(),
                        "{suite}/{id}"
                    );
                    counts[other] += 1;
                    counts[4] += steps.iter().filter(|s| s.grasp.is_none()).count();
                    counts[5] += steps
                        .iter()
                        .filter(|s| s.grasp.as_ref().is_some_and(|g| !g.blocked_by.is_empty()))
                        .count();
                }
                PlanOutcome::Declined { reason, .. } => {
                    assert!(!reason.is_empty(), "{id}");
                    declined.push(format!("{suite}/{id}: {reason}"));
                    counts[other + 1] += 1;
                }
            }
        }
    }
    eprintln!("counts {counts:?}, declined: {declined:#?}");
    assert_eq!(counts, COUNTS, "{declined:#?}");
}

#[test]
fn bad_input_exits_2_naming_the_file_and_writes_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("plan.json");
    let missing = tmp.path().join("nothing.json");
    let broken = tmp.path().join("broken.json");
    std::fs::write(&broken, "{\"blocks\": [").unwrap();
    let declined = tmp.path().join("declined.json");
    std::fs::write(
        &declined,
        r#"{"name": "d", "status": "unsupported", "reason": "overhang", "blocks": []}"#,
    )
    .unwrap();
    for input in [&missing, &broken, &declined] {
        let o = common::blockworld([
            "plan".as_ref(),
            input.as_os_str(),
            "-o".as_ref(),
            out.as_os_str(),
        ]);
        let err = common::fails_with_2(&o);
        assert!(err.contains(&input.display().to_string()), "{err}");
        assert!(!out.exists(), "no plan written for {}", input.display());
    }
}

#[test]
fn a_cantilever_held_by_a_counterweight_is_declined_with_the_reason() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = tmp.path().join("cantilever.json");
    std::fs::write(
        &scene,
        r#"{"name": "cantilever", "blocks": [
            {"type": "b15", "center": [0, 7.5, 0]},
            {"type": "b30", "center": [9, 22.5, 0]},
            {"type": "b15", "center": [1.5, 37.5, 0]}]}"#,
    )
    .unwrap();
    let out = tmp.path().join("plan.json");
    let glb = tmp.path().join("plan.glb");
    let o = common::blockworld([
        "plan".as_ref(),
        scene.as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
        "--glb".as_ref(),
        glb.as_os_str(),
    ]);
    let stdout = common::ok(&o);
    assert!(stdout.contains("declined"), "{stdout}");
    let plan: serde_json::Value = serde_json::from_slice(&std::fs::read(&out).unwrap()).unwrap();
    assert_eq!(plan["status"], "declined");
    let reason = plan["reason"].as_str().unwrap();
    assert!(
        reason.contains("moves block 1 (b30)") && reason.contains("overhang"),
        "{reason}"
    );
    assert!(!glb.exists(), "no animation of a plan that does not exist");
}
