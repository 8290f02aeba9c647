//! The committed fuzz corpora replayed on stable Rust (docs/cli.md "Exit codes and progress output",
//! fuzzing): every file under `tests/fuzz/seeds/<target>/` goes through the property of its
//! cargo-fuzz target, the same `*_check.rs` the target runs under libFuzzer. A crash libFuzzer
//! finds is fixed in the library and its reproducer is added to the target's folder here, so
//! the test keeps it fixed. (`tests/mutants.rs` replays `tests/fuzz/seeds/scene/`.)

include!("fuzz/fuzz_targets/label_check.rs");
include!("fuzz/fuzz_targets/vision_check.rs");
include!("fuzz/fuzz_targets/drawing_check.rs");
include!("fuzz/fuzz_targets/camera_check.rs");
include!("fuzz/fuzz_targets/recognize_check.rs");

use std::path::PathBuf;

/// Every file of a target's committed corpus, in name order, with its bytes.
fn corpus(target: &str) -> Vec<(PathBuf, Vec<u8>)> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fuzz/seeds")
        .join(target);
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    assert!(!files.is_empty(), "{} holds no seeds", dir.display());
    files
        .into_iter()
        .map(|p| {
            let bytes = std::fs::read(&p).unwrap();
            (p, bytes)
        })
        .collect()
}

/// Runs `check` on every seed of `target`, naming the seed that breaks the property.
fn replay(target: &str, check: fn(&[u8])) -> usize {
    let seeds = corpus(target);
    for (path, bytes) in &seeds {
        if std::panic::catch_unwind(|| check(bytes)).is_err() {
            panic!("{} breaks the {target} fuzz property", path.display());
        }
    }
    seeds.len()
}

#[test]
fn label_corpus_replays() {
    replay("label", check_label_bytes);
}

#[test]
fn vision_corpus_replays() {
    replay("vision", check_vision_bytes);
}

#[test]
fn drawing_corpus_replays() {
    replay("drawing", check_drawing_bytes);
}

#[test]
fn camera_corpus_replays() {
    replay("camera", check_camera_bytes);
}

#[test]
fn recognize_corpus_replays() {
    replay("recognize", check_recognizer_bytes);
}

#[test]
fn a_seed_that_breaks_its_property_is_named() {
    // A drawing seed is not a picture, but the vision property only refuses it; a camera file
    // read as a drawing is refused too. A property that panics must name the seed.
    assert!(replay("drawing", check_vision_bytes) > 0);
    let broken = std::panic::catch_unwind(|| replay("drawing", |_| panic!("finding")));
    let message = broken.unwrap_err();
    let message = message.downcast_ref::<String>().unwrap();
    assert!(
        message.contains("paip_cube.json") && message.contains("drawing"),
        "{message}"
    );
}

#[test]
fn the_label_seeds_are_the_paip_drawings() {
    // The seeds are meaningful inputs, not noise: the cube seed is PAIP's cube, 7 points and
    // 9 lines that the labeller reads without error.
    let cube = std::fs::read("tests/fuzz/seeds/label/paip_cube.bin").unwrap();
    let d = label_fuzz_drawing(&cube);
    assert_eq!((d.points.len(), d.lines.len()), (7, 9));
    assert!(blockworld::kanade::validate(&d).is_ok());
}

#[test]
fn the_recognize_seed_of_a_cube_reaches_the_parallelogram_search() {
    // The single cube's exact NE drawing at 2 px steps (framed by the fixture's camera, not
    // the target's, so the recognizer may decline it): the seed gets past the readers' checks
    // into the parallelogram search, so mutations of it explore the recognizer itself.
    use blockworld::recognize::{recognize, RecognizeOptions};
    let seed = std::fs::read("tests/fuzz/seeds/recognize/single_cube_ne.bin").unwrap();
    let views = recognizer_fuzz_views(&seed);
    assert_eq!(views.len(), 1);
    assert!(views[0].drawing.check().is_ok());
    let answer = recognize(&views, &RecognizeOptions::default()).unwrap();
    let ne = &answer.evidence.views[0];
    assert!(ne.parallelograms > 0 && ne.proposals > 0, "{ne:?}");
}
