//! The committed fuzz corpora replayed on stable Rust (docs/cli.md "Exit codes and progress output",
//! fuzzing): every file under `tests/fuzz/seeds/<target>/` goes through the property of its
//! cargo-fuzz target, the same `*_check.rs` the target runs under libFuzzer. A crash libFuzzer
//! finds is fixed in the library and its reproducer is added to the target's folder here, so
//! the test keeps it fixed. (`tests/mutants.rs` replays `tests/fuzz/seeds/scene/`.)
//!
//! Beside the corpora, a seeded mutation run of the commands' whole paths (docs/testing.md
//! "Fuzzing"): mutants of the single cube's cameras and drawings and of the thesis sample's
//! Appendix B files through the recognizer, the labeller and the Appendix B reader in-process, and a few hundred
//! through `recognize --from-truth`, `label`, `export` and `view` as a user runs them; the
//! interesting ones are kept in `tests/fuzz/seeds/cli/` and replayed.

mod common;

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

use common::mutate::mutate;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::path::Path;
use std::time::{Duration, Instant};

/// The longest one case of the mutation runs may take: a case is bounded by its command's
/// budgets (docs/limits.md), and a hang is a finding.
const CASE_LIMIT_S: u64 = 60;

/// What a mutant replaces: one file of a `recognize --from-truth --views ne` folder, the
/// drawing given to `label`, or one of the two Appendix B files given to `export` and `view`.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Kind {
    Camera,
    Lines,
    Label,
    ThesisVertices,
    ThesisConnections,
}

impl Kind {
    const ALL: [Kind; 5] = [
        Kind::Camera,
        Kind::Lines,
        Kind::Label,
        Kind::ThesisVertices,
        Kind::ThesisConnections,
    ];

    /// The corpus file name prefix.
    fn name(self) -> &'static str {
        match self {
            Kind::Camera => "camera",
            Kind::Lines => "lines",
            Kind::Label => "label",
            Kind::ThesisVertices => "thesis_vertices",
            Kind::ThesisConnections => "thesis_connections",
        }
    }

    /// The unmutated file this kind mutates: the single cube's NE camera and drawing, and the
    /// Appendix B files of the thesis sample (scenes/thesis_sample.json, all five blocks).
    fn seed(self) -> String {
        let rel = match self {
            Kind::Camera => "vision/single_cube/camera_ne.json",
            Kind::Lines | Kind::Label => "vision/single_cube/lines_ne.json",
            Kind::ThesisVertices | Kind::ThesisConnections => {
                let sample = common::root().join("scenes/thesis_sample.json");
                let scene = blockworld::scene::read_scene(&sample).unwrap();
                let files = blockworld::export::scene_to_thesis_files(&scene).unwrap();
                return match self {
                    Kind::ThesisVertices => files.vertices,
                    _ => files.connections,
                };
            }
        };
        std::fs::read_to_string(common::root().join("tests/fixtures").join(rel)).unwrap()
    }
}

/// `count` seeded mutants, the kinds in turn.
fn mutants(seed: u64, count: usize) -> Vec<(Kind, Vec<u8>)> {
    let seeds: Vec<String> = Kind::ALL.iter().map(|k| k.seed()).collect();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..count)
        .map(|i| {
            let k = i % Kind::ALL.len();
            let mut m = mutate(&seeds[k], &mut rng);
            if rng.random_range(0..4) == 0 {
                m = mutate(&String::from_utf8_lossy(&m), &mut rng);
            }
            (Kind::ALL[k], m)
        })
        .collect()
}

/// One mutant through the library: the readers, then what the command does with what they
/// read (the recognizer, the labeller, the Appendix B model to a scene). Panics on a finding.
fn run_in_process(kind: Kind, m: &[u8]) {
    use blockworld::camera::parse_camera_json;
    use blockworld::drawing::LineDrawing;
    use blockworld::export::{parse_thesis_files, thesis_model_to_scene, Truncation};
    use blockworld::kanade::{label_drawing, LabelOptions};
    use blockworld::recognize::{recognize, ObservedView, RecognizeOptions};
    let text = String::from_utf8_lossy(m);
    let seed = |k: Kind| k.seed();
    match kind {
        Kind::Camera | Kind::Lines => {
            let (camera, lines) = match kind {
                Kind::Camera => (text.to_string(), seed(Kind::Lines)),
                _ => (seed(Kind::Camera), text.to_string()),
            };
            let (Ok(camera), Ok(drawing)) =
                (parse_camera_json(&camera), LineDrawing::from_json(&lines))
            else {
                return;
            };
            let _ = recognize(
                &[ObservedView::new(drawing, camera)],
                &RecognizeOptions::default(),
            );
        }
        Kind::Label => {
            let Ok(d) = LineDrawing::from_json(&text) else {
                return;
            };
            let opts = LabelOptions {
                time_budget_s: 10.0,
                ..LabelOptions::default()
            };
            let _ = label_drawing(&d, &opts, &mut |_| {});
        }
        Kind::ThesisVertices | Kind::ThesisConnections => {
            let (v, c) = match kind {
                Kind::ThesisVertices => (text.to_string(), seed(Kind::ThesisConnections)),
                _ => (seed(Kind::ThesisVertices), text.to_string()),
            };
            let names = ("v.txt", "c.txt");
            for t in [Truncation::Strict, Truncation::AllowFragment] {
                if let Ok(model) = parse_thesis_files(&v, &c, names, t) {
                    let _ = thesis_model_to_scene(&model, "v.txt", "c.txt", t);
                }
            }
        }
    }
}

/// Regression: mutants of cameras, drawings and Appendix B files made the recognizer panic
/// (a camera with one entry of 1e20) and the labeller run without bound. 3,000 seeded mutants
/// through the library's whole paths: none panics, none takes over [`CASE_LIMIT_S`].
#[test]
fn three_thousand_mutants_through_the_library() {
    let started = Instant::now();
    for (i, (kind, m)) in mutants(34, 3_000).into_iter().enumerate() {
        let t = Instant::now();
        let outcome = std::panic::catch_unwind(|| run_in_process(kind, &m));
        let text = String::from_utf8_lossy(&m);
        assert!(outcome.is_ok(), "mutant {i} ({kind:?}) panicked:\n{text}");
        let took = t.elapsed();
        assert!(
            took < Duration::from_secs(CASE_LIMIT_S),
            "mutant {i} ({kind:?}) took {took:?}:\n{text}"
        );
    }
    println!("3000 mutants in {:.1} s", started.elapsed().as_secs_f64());
}

/// Writes the mutant of `kind` into `dir` with the unmutated files it needs and runs its
/// commands; `Err` names what went wrong, `Ok` holds the exit codes.
fn run_case(dir: &Path, kind: Kind, m: &[u8]) -> Result<Vec<i32>, String> {
    std::fs::create_dir_all(dir).unwrap();
    let runs: Vec<Vec<String>> = match kind {
        Kind::Camera | Kind::Lines => {
            let (camera, lines) = match kind {
                Kind::Camera => (m.to_vec(), Kind::Lines.seed().into_bytes()),
                _ => (Kind::Camera.seed().into_bytes(), m.to_vec()),
            };
            std::fs::write(dir.join("camera_ne.json"), camera).unwrap();
            std::fs::write(dir.join("lines_ne.json"), lines).unwrap();
            let out = dir.join("r.json");
            let d = dir.to_string_lossy().into_owned();
            let o = out.to_string_lossy().into_owned();
            vec![["recognize", &d, "--from-truth", "--views", "ne", "-o", &o]
                .map(String::from)
                .to_vec()]
        }
        Kind::Label => {
            let f = dir.join("l.json");
            std::fs::write(&f, m).unwrap();
            let f = f.to_string_lossy().into_owned();
            vec![["label", &f, "--time-budget-s", "10"]
                .map(String::from)
                .to_vec()]
        }
        Kind::ThesisVertices | Kind::ThesisConnections => {
            let (v, c) = match kind {
                Kind::ThesisVertices => (m.to_vec(), Kind::ThesisConnections.seed().into_bytes()),
                _ => (Kind::ThesisVertices.seed().into_bytes(), m.to_vec()),
            };
            std::fs::write(dir.join("t_vertices.txt"), v).unwrap();
            std::fs::write(dir.join("t_connections.txt"), c).unwrap();
            let prefix = dir.join("t").to_string_lossy().into_owned();
            let glb = dir.join("t.glb").to_string_lossy().into_owned();
            let png = dir.join("t.png").to_string_lossy().into_owned();
            vec![
                ["export", &prefix, "-o", &glb].map(String::from).to_vec(),
                ["view", &prefix, "-o", &png].map(String::from).to_vec(),
            ]
        }
    };
    runs.iter()
        .map(|args| {
            let (o, in_time) = common::blockworld_within(args, CASE_LIMIT_S);
            let err = common::stderr(&o);
            match o.status.code() {
                _ if !in_time => Err(format!("{args:?}: over {CASE_LIMIT_S} s")),
                _ if err.contains("panicked") => Err(format!("{args:?}: panic: {err}")),
                Some(c @ (0 | 2)) => Ok(c),
                code => Err(format!(
                    "{args:?}: exit {code:?} (a signal when None): {err}"
                )),
            }
        })
        .collect()
}

/// Runs `cases` through the binary on two threads; asserts none fails, and returns each
/// case's exit codes.
fn run_cases(cases: &[(Kind, Vec<u8>)]) -> Vec<Vec<i32>> {
    let dir = tempfile::tempdir().unwrap();
    let results = common::map_on_threads(cases.len(), 2, |i| {
        let (kind, m) = &cases[i];
        run_case(&dir.path().join(format!("c{i}")), *kind, m)
            .map_err(|e| format!("case {i} ({kind:?}): {e}\n{}", String::from_utf8_lossy(m)))
    });
    let failures: Vec<&String> = results.iter().filter_map(|r| r.as_ref().err()).collect();
    assert!(
        failures.is_empty(),
        "{} of {} cases failed; first:\n{}",
        failures.len(),
        cases.len(),
        failures[0]
    );
    results.into_iter().flatten().collect()
}

/// 300 seeded mutants through `recognize --from-truth`, `label`, `export` and `view` as a user
/// runs them: each run exits 0 or 2, never panics (101) or dies of a signal, within
/// [`CASE_LIMIT_S`]; both outcomes are reached.
#[test]
fn three_hundred_mutants_through_the_binary() {
    let cases = mutants(35, 300);
    let codes: Vec<i32> = run_cases(&cases).into_iter().flatten().collect();
    let ok = codes.iter().filter(|&&c| c == 0).count();
    assert!(
        ok > 0 && ok < codes.len(),
        "{ok} of {} runs exit 0",
        codes.len()
    );
}

/// The committed cases of `tests/fuzz/seeds/cli/` (`<kind>-<n>.txt`), each through its commands.
fn cli_corpus() -> Vec<(Kind, Vec<u8>)> {
    corpus("cli")
        .into_iter()
        .map(|(p, bytes)| {
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            let kind = Kind::ALL
                .into_iter()
                .find(|k| name.rsplit_once('-').is_some_and(|(k2, _)| k2 == k.name()))
                .unwrap_or_else(|| panic!("{}: no kind of that name", p.display()));
            (kind, bytes)
        })
        .collect()
}

#[test]
fn cli_corpus_replays() {
    let cases = cli_corpus();
    assert!(cases.len() >= 20, "{} cases", cases.len());
    run_cases(&cases);
}

/// Rewrites `tests/fuzz/seeds/cli/`: of 200 seeded mutants, for each kind and each outcome
/// (the exit codes of its runs: answered, refused, or for Appendix B files exported but not
/// viewed) the first five:
/// `cargo test --test fuzz_corpus -- --ignored write_cli_corpus`.
#[test]
#[ignore]
fn write_cli_corpus() {
    let dir = common::root().join("tests/fuzz/seeds/cli");
    std::fs::create_dir_all(&dir).unwrap();
    let cases = mutants(36, 200);
    let tmp = tempfile::tempdir().unwrap();
    let mut kept = std::collections::HashMap::new();
    for (i, (kind, m)) in cases.iter().enumerate() {
        let codes = run_case(&tmp.path().join(format!("c{i}")), *kind, m).unwrap();
        let key = (kind.name(), codes);
        let n = kept.entry(key).or_insert(0);
        if *n < 5 {
            *n += 1;
            std::fs::write(dir.join(format!("{}-{i:03}.txt", kind.name())), m).unwrap();
        }
    }
}
