//! Mutation tests over scene files (docs/cli.md "Exit codes and progress output"): seeded mutants of the example and
//! suite scenes (numbers swapped for extreme values, tokens inserted, spans deleted, duplicated
//! or truncated, bytes flipped) go through the scene readers in-process and through
//! `blockworld export` as a user would run it. Every mutant must end with exit 0 or 2, never a
//! panic; a failure names the input and leaves nothing behind; a success writes no `null`.
//! `tests/fuzz/seeds/scene/` (the cargo-fuzz corpus of the `scene` target) is replayed too.

mod common;

include!("fuzz/fuzz_targets/scene_check.rs");
include!("fuzz/fuzz_targets/drawing_check.rs");
include!("fuzz/fuzz_targets/camera_check.rs");

use common::mutate::mutate;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::path::{Path, PathBuf};

/// The mutation seeds: every example scene and a few suite scenes.
fn seeds() -> Vec<String> {
    let mut paths = common::example_scene_paths();
    let bench: Vec<PathBuf> = common::json_files(&common::root().join("scenes/bench"));
    paths.extend(bench.into_iter().step_by(8));
    paths
        .iter()
        .map(|p| std::fs::read_to_string(p).unwrap())
        .collect()
}

/// Regression: 3,000 mutated scene files found panics and `null` output; the readers must
/// refuse or read back every mutant (20,000 here, in-process).
#[test]
fn scene_readers_survive_twenty_thousand_mutants() {
    let seeds = seeds();
    let mut rng = ChaCha8Rng::seed_from_u64(2026);
    for i in 0..20_000 {
        let text = &seeds[i % seeds.len()];
        let m = mutate(text, &mut rng);
        let outcome = std::panic::catch_unwind(|| check_scene_bytes(&m));
        assert!(
            outcome.is_ok(),
            "mutant {i} broke the readers:\n{}",
            String::from_utf8_lossy(&m)
        );
    }
}

/// The committed fuzz corpus still holds.
#[test]
fn fuzz_corpus_replays() {
    let dir = common::root().join("tests/fuzz/seeds/scene");
    let files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .collect();
    assert!(
        files.len() >= 50,
        "{} holds {} inputs",
        dir.display(),
        files.len()
    );
    for f in files {
        let data = std::fs::read(&f).unwrap();
        let outcome = std::panic::catch_unwind(|| check_scene_bytes(&data));
        assert!(outcome.is_ok(), "{} broke the readers", f.display());
    }
}

/// What one CLI run of a mutant did wrong (`Err`), else whether it exported (exit 0).
fn judge_export(dir: &Path, i: usize, mutant: &[u8]) -> Result<bool, String> {
    let input = dir.join(format!("m{i}.json"));
    std::fs::write(&input, mutant).unwrap();
    let out_dir = dir.join(format!("out{i}"));
    std::fs::create_dir(&out_dir).unwrap();
    let glb = out_dir.join("m.glb");
    let o = common::blockworld([
        "export",
        input.to_str().unwrap(),
        "-o",
        glb.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    let left: Vec<String> = std::fs::read_dir(&out_dir)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    let verdict = match o.status.code() {
        _ if err.contains("panicked") => Some(format!("panic: {err}")),
        Some(0) if left != ["m.glb"] => Some(format!("exit 0 but left {left:?}")),
        Some(0) if glb_json(&std::fs::read(&glb).unwrap()).contains("null") => {
            Some("exit 0 but the glTF JSON holds null".to_string())
        }
        Some(0) => None,
        Some(2) if !left.is_empty() => Some(format!("failed but left {left:?}: {err}")),
        Some(2) if !err.contains(&format!("m{i}.json")) => Some(format!("input not named: {err}")),
        Some(2) => None,
        code => Some(format!("exit {code:?}: {err}")),
    };
    match verdict {
        Some(v) => Err(format!(
            "mutant {i}: {v}\n{}",
            String::from_utf8_lossy(mutant)
        )),
        None => Ok(o.status.success()),
    }
}

/// The JSON chunk of a GLB file (after the 12-byte header and the chunk's length and type).
fn glb_json(glb: &[u8]) -> String {
    let len = u32::from_le_bytes(glb[12..16].try_into().unwrap()) as usize;
    String::from_utf8_lossy(&glb[20..20 + len]).into_owned()
}

/// Regression: mutated scene files made commands panic, leave files behind or write `null`.
/// 2,000 mutants through `blockworld export` on four threads: exit 0 or 2, no panic, nothing
/// left behind on failure, the input named in the error, no `null` on success.
#[test]
fn export_cli_survives_two_thousand_mutants() {
    const MUTANTS: usize = 2_000;
    const THREADS: usize = 4;
    let seeds = seeds();
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let mutants: Vec<Vec<u8>> = (0..MUTANTS)
        .map(|i| mutate(&seeds[i % seeds.len()], &mut rng))
        .collect();
    let dir = tempfile::tempdir().unwrap();
    let outcomes: Vec<Result<bool, String>> = common::map_on_threads(MUTANTS, THREADS, |i| {
        judge_export(dir.path(), i, &mutants[i])
    });
    let failures: Vec<&String> = outcomes.iter().filter_map(|o| o.as_ref().err()).collect();
    assert!(
        failures.is_empty(),
        "{} of {MUTANTS} mutants failed; first:\n{}",
        failures.len(),
        failures
            .iter()
            .take(3)
            .map(|f| f.as_str())
            .collect::<Vec<_>>()
            .join("\n")
    );
    let exported = outcomes.iter().filter(|o| matches!(o, Ok(true))).count();
    println!("{exported} of {MUTANTS} mutants exported, the rest refused with exit 2");
    // Both paths are exercised: mutants that still read (a moved block) and broken ones.
    assert!(
        (MUTANTS / 20..=MUTANTS * 19 / 20).contains(&exported),
        "{exported}"
    );
}

/// Rewrites `tests/fuzz/seeds/scene/` (the seeds and 100 seeded mutants):
/// `cargo test --test mutants -- --ignored write_fuzz_corpus`.
#[test]
#[ignore]
fn write_fuzz_corpus() {
    let dir = common::root().join("tests/fuzz/seeds/scene");
    std::fs::create_dir_all(&dir).unwrap();
    let seeds = seeds();
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    for (i, s) in seeds.iter().enumerate() {
        std::fs::write(dir.join(format!("seed-{i:02}.json")), s).unwrap();
    }
    for i in 0..100 {
        let m = mutate(&seeds[i % seeds.len()], &mut rng);
        std::fs::write(dir.join(format!("mutant-{i:03}.json")), m).unwrap();
    }
}

/// Line drawings are read checked (docs/vision.md "Vision front end"): 20,000 seeded mutants of the
/// single-cube drawings either fail to read or read back to the same drawing without `null`.
#[test]
fn drawing_reader_survives_twenty_thousand_mutants() {
    let dir = common::root().join("tests/fixtures/vision/single_cube");
    let seeds: Vec<String> = ["ne", "se", "sw", "nw"]
        .iter()
        .map(|v| std::fs::read_to_string(dir.join(format!("lines_{v}.json"))).unwrap())
        .collect();
    let mut rng = ChaCha8Rng::seed_from_u64(31);
    for i in 0..20_000 {
        let m = mutate(&seeds[i % seeds.len()], &mut rng);
        let outcome = std::panic::catch_unwind(|| check_drawing_bytes(&m));
        assert!(
            outcome.is_ok(),
            "mutant {i} broke the drawing reader:\n{}",
            String::from_utf8_lossy(&m)
        );
    }
}

/// Camera files are read checked: 20,000 seeded mutants of the single-cube cameras either fail
/// to read or read back to the same camera, written without `null`.
#[test]
fn camera_reader_survives_twenty_thousand_mutants() {
    let dir = common::root().join("tests/fixtures/vision/single_cube");
    let seeds: Vec<String> = ["ne", "se", "sw", "nw"]
        .iter()
        .map(|v| std::fs::read_to_string(dir.join(format!("camera_{v}.json"))).unwrap())
        .collect();
    let mut rng = ChaCha8Rng::seed_from_u64(41);
    for i in 0..20_000 {
        let m = mutate(&seeds[i % seeds.len()], &mut rng);
        let outcome = std::panic::catch_unwind(|| check_camera_bytes(&m));
        assert!(
            outcome.is_ok(),
            "mutant {i} broke the camera reader:\n{}",
            String::from_utf8_lossy(&m)
        );
    }
}
