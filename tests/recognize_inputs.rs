//! The recognizer on hostile input (docs/recognizer.md "Recognizer"): seeded random byte strings through the
//! property of the `recognize` fuzz target (`tests/fuzz/fuzz_targets/recognize_check.rs`), so
//! CI exercises it on stable Rust; plus the bare cases (no views, a line to a missing point).

include!("fuzz/fuzz_targets/recognize_check.rs");

mod common;

use blockworld::recognize::{recognize, RecognizeError, RecognizeOptions};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

#[test]
fn seeded_random_drawings_never_panic_the_recognizer() {
    let mut rng = ChaCha8Rng::seed_from_u64(13);
    for _ in 0..300 {
        let len = rng.random_range(0..256);
        let bytes: Vec<u8> = (0..len).map(|_| rng.random()).collect();
        check_recognizer_bytes(&bytes);
    }
}

#[test]
fn no_views_and_broken_drawings_are_typed_errors() {
    assert!(matches!(
        recognize(&[], &RecognizeOptions::default()),
        Err(RecognizeError::NoViews)
    ));
    // A line to a point that does not exist: byte 1 = 2 points, then a line [0, 9].
    let mut bytes = vec![2u8, 10, 10, 20, 20, 0, 9];
    bytes.resize(64, 0);
    check_recognizer_bytes(&bytes);
}

/// How many of `mutated_real_drawings_are_answered_or_declined`'s 40 mutants the recognizer
/// answers (measured; the test's floor).
const MUTANTS_ANSWERED: usize = 1;

/// Mutants of a real drawing reach the search itself: lines dropped, points moved a few px,
/// the recognizer answers or declines, and an `ok` answer is one whose own drawings it checked.
/// A recognizer that declined everything would pass that alone, so the undamaged drawings must
/// be answered exactly, and at least [`MUTANTS_ANSWERED`] of the 40 mutants (the count measured
/// with seed 29; a regression answers fewer), among them every mutant the dice left whole. A
/// mutation that stopped damaging would decline nothing, so some must be declined, each with its
/// reason (seed 29: 39 damaged, 39 declined).
#[test]
fn mutated_real_drawings_are_answered_or_declined() {
    use blockworld::camera::{CameraOptions, CornerView};
    use blockworld::geom::DVec2;
    use blockworld::recognize::ObservedView;
    use blockworld::scene::{read_scene, ReconStatus};
    let scene = read_scene(std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenes/two_layer.json"
    )))
    .unwrap();
    let exact = common::exact_views(&scene, &CornerView::ALL, &CameraOptions::default());
    let r = recognize(&exact, &RecognizeOptions::default()).unwrap();
    let recon = blockworld::csg::reconstruction(&scene.name, &r, 0.5);
    let score = blockworld::score::score_reconstruction(&scene, &recon).unwrap();
    assert_eq!(
        (r.status, score.verdict),
        (ReconStatus::Ok, blockworld::score::Verdict::Exact),
        "the undamaged drawings: {:?}",
        r.reason
    );
    let mut rng = ChaCha8Rng::seed_from_u64(29);
    let (mut ok, mut declined, mut damaged) = (0, 0, 0);
    for _ in 0..40 {
        let mut changed = false;
        let views: Vec<ObservedView> = exact
            .iter()
            .map(|v| {
                let (mut drawing, camera) = (v.drawing.clone(), v.camera);
                if rng.random_bool(0.2) && !drawing.lines.is_empty() {
                    let k = rng.random_range(0..drawing.lines.len());
                    drawing.lines.remove(k);
                    drawing.kinds.clear();
                    drawing.edges.clear();
                    changed = true;
                }
                for p in &mut drawing.points {
                    if rng.random_bool(0.05) {
                        *p += DVec2::new(rng.random_range(-3.0..3.0), rng.random_range(-3.0..3.0));
                        changed = true;
                    }
                }
                drawing.finalize();
                ObservedView::new(drawing, camera)
            })
            .collect();
        let r = recognize(&views, &RecognizeOptions::default()).unwrap();
        damaged += usize::from(changed);
        // A mutant the dice left whole is the exact drawing: it must be answered.
        assert!(
            changed || r.status == ReconStatus::Ok,
            "an undamaged mutant was declined: {:?}",
            r.reason
        );
        match r.status {
            ReconStatus::Ok => {
                ok += 1;
                // Never confidently wrong: an answer to damaged drawings is still the truth.
                let recon = blockworld::csg::reconstruction(&scene.name, &r, 0.5);
                let score = blockworld::score::score_reconstruction(&scene, &recon).unwrap();
                assert_eq!(
                    score.verdict,
                    blockworld::score::Verdict::Exact,
                    "{recon:?}"
                );
            }
            ReconStatus::Unsupported => {
                assert!(r.reason.is_some(), "a decline without its reason");
                declined += 1;
            }
        }
    }
    println!("{ok} answered, {declined} declined; {damaged} damaged");
    assert!(
        ok >= MUTANTS_ANSWERED,
        "answered {ok} of 40 mutants, fewer than the {MUTANTS_ANSWERED} measured"
    );
    // The damage reaches the search: some mutants are refused, each with its reason.
    assert!(
        declined > 0 && damaged >= declined,
        "{declined} declined, {damaged} damaged"
    );
}
