//! The scorer's own regression test (docs/accuracy.md "Scoring and the accuracy suite"): the committed
//! suite (`scenes/bench/`) scored with the constructed reference reconstructions
//! (`golden/recon_reference/`, made to known verdicts, not by a recognizer) must give the
//! scores in `golden/scorer_reference.json`, and the gate logic must fail on a worse set. The
//! accuracy gate on the recognizer itself is `tests/accuracy_gate.rs`.
//!
//! Re-bless on purpose with `BLESS=1 cargo test --test scorer_reference` (or `make bless`) and
//! review the diff of `golden/scorer_reference.json`. The reference set is regenerated with
//! `cargo run -- bench accuracy --make-reference golden/recon_reference`.

mod common;
use common::{json_files, stem};

use blockworld::scene::{
    read_reconstruction, read_scene, reconstruction_to_json, Block, ReconStatus, Reconstruction,
    Scene,
};
use blockworld::score::{
    check_gate, make_reference_reconstructions, score_suite_scene, GateFailure, Golden,
    NoReconstruction, SceneResult, ScoreOptions, Verdict,
};
use std::path::PathBuf;

const SUITE_DIR: &str = "scenes/bench";
const REFERENCE_DIR: &str = "golden/recon_reference";
const GOLDEN: &str = "golden/scorer_reference.json";
const BLESS: &str = "BLESS=1 cargo test --test scorer_reference";

fn root(rel: &str) -> PathBuf {
    common::root().join(rel)
}

fn suite() -> Vec<(String, Scene)> {
    json_files(&root(SUITE_DIR))
        .iter()
        .map(|p| (stem(p), read_scene(p).unwrap_or_else(|e| panic!("{e}"))))
        .collect()
}

fn reference_set() -> Vec<(String, Reconstruction)> {
    json_files(&root(REFERENCE_DIR))
        .iter()
        .map(|p| {
            (
                stem(p),
                read_reconstruction(p).unwrap_or_else(|e| panic!("{e}")),
            )
        })
        .collect()
}

fn score_all(suite: &[(String, Scene)], recons: &[(String, Reconstruction)]) -> Vec<SceneResult> {
    suite
        .iter()
        .map(|(id, truth)| {
            let recon = recons
                .iter()
                .find(|(rid, _)| rid == id)
                .map(|(_, s)| s)
                .ok_or_else(|| NoReconstruction(format!("no reconstruction for {id}")));
            score_suite_scene(id, truth, recon, &ScoreOptions::default())
        })
        .collect()
}

#[test]
fn suite_covers_the_families_and_the_failure_cases() {
    let suite = suite();
    // Hand-made stand-in suite until the generator lands (scenes/bench/README.md); raise to 60.
    assert!(
        suite.len() >= 12,
        "only {} scenes in {SUITE_DIR}",
        suite.len()
    );
    let mut families: Vec<String> = suite
        .iter()
        .map(|(_, s)| blockworld::score::scene_family(s))
        .collect();
    families.sort();
    families.dedup();
    // The generator's families (docs/datasets.md "Settling"), the Chapter VII failure cases included.
    for f in [
        "single",
        "row",
        "l_shape",
        "two_layer",
        "three_layer",
        "tower",
        "staircase",
        "separated",
        "random_stack",
        "upper_larger",
        "yaw",
    ] {
        assert!(
            families.iter().any(|g| g == f),
            "family {f} missing from {families:?}"
        );
    }
    let unsupported: Vec<&Scene> = suite
        .iter()
        .map(|(_, s)| s)
        .filter(|s| !s.is_supported())
        .collect();
    assert!(unsupported.len() >= 4);
    for s in unsupported {
        let family = blockworld::score::scene_family(s);
        assert!(
            family == "upper_larger" || family == "yaw",
            "{} ({family}) marked unsupported",
            s.name
        );
    }
    // Every scene records its generator seed.
    for (id, s) in &suite {
        assert!(
            s.meta
                .as_ref()
                .is_some_and(|m| m.get("seed").is_some_and(|v| v.is_u64())),
            "{id} has no meta.seed"
        );
    }
}

#[test]
fn reference_set_is_what_its_generator_makes() {
    let made = make_reference_reconstructions(&suite());
    let committed = reference_set();
    assert_eq!(
        made.iter().map(|(id, _)| id).collect::<Vec<_>>(),
        committed.iter().map(|(id, _)| id).collect::<Vec<_>>(),
        "regenerate with: cargo run -- bench accuracy --make-reference {REFERENCE_DIR}"
    );
    for (id, recon) in &made {
        let text = std::fs::read_to_string(root(REFERENCE_DIR).join(format!("{id}.json"))).unwrap();
        assert_eq!(
            text,
            reconstruction_to_json(recon),
            "{id} differs; regenerate with: cargo run -- bench accuracy --make-reference {REFERENCE_DIR}"
        );
    }
}

#[test]
fn reference_scores_do_not_regress_against_golden() {
    let results = score_all(&suite(), &reference_set());
    for r in &results {
        println!(
            "{:<18} {:<12} iou {:.4} {:<11} f1 {:.3} flagged {}",
            r.id,
            r.family,
            r.iou,
            r.verdict.as_str(),
            r.f1,
            r.flagged
        );
    }
    let path = root(GOLDEN);
    if std::env::var_os("BLESS").is_some() {
        let golden = Golden::from_results(&results, BLESS);
        blockworld::io::write_atomic(
            &path,
            (serde_json::to_string_pretty(&golden).unwrap() + "\n").as_bytes(),
        )
        .unwrap();
        eprintln!("BLESSED {}", path.display());
        return;
    }
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("{}: {e}; create it with {BLESS}", path.display()));
    let golden: Golden =
        serde_json::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let failures = check_gate(&golden, &results);
    assert!(
        failures.is_empty(),
        "accuracy gate failed:\n{}\nfix the regression, or accept it on purpose with {BLESS}",
        failures
            .iter()
            .map(|f| format!("  {f}"))
            .collect::<Vec<_>>()
            .join("\n")
    );
}

/// The reference set makes every supported scene recognized and flags every failure case, so
/// the gate guards something.
#[test]
fn reference_set_recognizes_supported_scenes_and_flags_failure_cases() {
    let results = score_all(&suite(), &reference_set());
    for r in &results {
        if r.supported {
            assert!(r.verdict.is_recognized(), "{r:?}");
        } else {
            assert!(r.flagged && r.verdict == Verdict::Unsupported, "{r:?}");
        }
    }
    assert_eq!(
        results
            .iter()
            .filter(|r| r.verdict == Verdict::Partial)
            .count(),
        1,
        "one partial by construction"
    );
}

/// The gate fails on a deliberately worse reconstruction set: blocks shifted in one scene, a
/// scene left empty, and a known failure case "recognized".
#[test]
fn gate_fails_on_a_worse_reconstruction_set() {
    let suite = suite();
    let reference = reference_set();
    let golden = Golden::from_results(&score_all(&suite, &reference), BLESS);
    let exact: Vec<&String> = golden
        .scenes
        .iter()
        .filter(|g| g.verdict == Verdict::Exact)
        .map(|g| &g.id)
        .collect();
    let (shifted, emptied) = (exact[0].clone(), exact[1].clone());
    let unsupported = golden
        .scenes
        .iter()
        .find(|g| !g.supported)
        .unwrap()
        .id
        .clone();
    let worse: Vec<(String, Reconstruction)> = reference
        .iter()
        .map(|(id, recon)| {
            let mut r = recon.clone();
            if *id == shifted {
                r.blocks = r
                    .blocks
                    .iter()
                    .map(|b| Block {
                        center_mm: b.center_mm + blockworld::geom::DVec3::new(2.0, 0.0, 0.0),
                        ..*b
                    })
                    .collect();
            } else if *id == emptied {
                r.blocks.clear();
            } else if *id == unsupported {
                // "Recognized" with one block missing: neither declined nor exact.
                r.status = ReconStatus::Ok;
                r.blocks = suite
                    .iter()
                    .find(|(sid, _)| sid == id)
                    .unwrap()
                    .1
                    .blocks
                    .clone();
                r.blocks.pop();
            }
            (id.clone(), r)
        })
        .collect();
    let failures = check_gate(&golden, &score_all(&suite, &worse));
    for f in &failures {
        println!("{f}");
    }
    assert!(failures
        .iter()
        .any(|f| matches!(f, GateFailure::IouDropped { id, .. } if *id == shifted)));
    assert!(failures
        .iter()
        .any(|f| matches!(f, GateFailure::NoLongerRecognized { id, .. } if *id == emptied)));
    assert!(failures.iter().any(|f| matches!(
        f,
        GateFailure::NoLongerFlagged { id, .. } | GateFailure::VerdictWorse { id, .. }
            if *id == unsupported
    )));
    // Only the three doctored scenes fail.
    assert!(failures.iter().all(|f| match f {
        GateFailure::IouDropped { id, .. }
        | GateFailure::NoLongerRecognized { id, .. }
        | GateFailure::VerdictWorse { id, .. }
        | GateFailure::NoLongerFlagged { id, .. } =>
            [&shifted, &emptied, &unsupported].contains(&id),
        _ => false,
    }));
    // A missing reconstruction file is a failure too.
    let fewer: Vec<(String, Reconstruction)> = reference
        .iter()
        .filter(|(id, _)| *id != shifted)
        .cloned()
        .collect();
    let results = score_all(&suite, &fewer);
    let r = results.iter().find(|r| r.id == shifted).unwrap();
    assert_eq!(r.verdict, Verdict::Failed);
    assert!(!check_gate(&golden, &results).is_empty());
}
