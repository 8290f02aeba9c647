//! The bounds of docs/limits.md: each command's `--help` states the numbers the page states and
//! the library's constants hold, and one past each bound exits 2 before any work, naming the
//! bound and writing nothing.

mod common;
use common::{blockworld, fails_with_2};

use std::path::Path;

/// A scene file of `n` separate b15 cubes on a grid, 20 mm apart.
fn grid_scene(dir: &Path, n: usize) -> String {
    let side = (n as f64).sqrt().ceil() as usize;
    let blocks: Vec<String> = (0..n)
        .map(|k| {
            let (x, z) = ((k % side) as f64 * 20.0, (k / side) as f64 * 20.0);
            format!(r#"{{"type": "b15", "center": [{x}, 7.5, {z}]}}"#)
        })
        .collect();
    let path = dir.join(format!("grid_{n}.json"));
    let text = format!(r#"{{"name": "grid", "blocks": [{}]}}"#, blocks.join(","));
    std::fs::write(&path, text).unwrap();
    path.to_string_lossy().into_owned()
}

/// The "Limits" paragraph of `blockworld <command> --help`.
fn help_limits(command: &[&str]) -> String {
    let help = common::ok(blockworld(command.iter().chain(&["--help"])));
    let start = help
        .find("Limits (docs/limits.md")
        .expect("a Limits paragraph");
    let end = help[start..].find("\n\n").map_or(help.len(), |e| start + e);
    help[start..end]
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
}

/// docs/limits.md's section under `heading`.
fn limits_section(heading: &str) -> String {
    let page = std::fs::read_to_string(common::root().join("docs/limits.md")).unwrap();
    let start = page
        .find(&format!("\n## {heading}\n"))
        .expect("the heading");
    let rest = &page[start + 4..];
    let end = rest.find("\n## ").unwrap_or(rest.len());
    rest[..end].split_whitespace().collect::<Vec<_>>().join(" ")
}

#[test]
fn help_and_docs_state_the_same_bounds_as_the_constants() {
    use blockworld::{dataset, io, physics, render, score, vision};
    let mib = |b: u64| format!("{} MiB", b >> 20);
    let cases: Vec<(&[&str], &str, Vec<String>)> = vec![
        (
            &["render"],
            "Render",
            vec![
                render::MAX_RENDER_BLOCKS.to_string(),
                vision::MAX_PICTURE_SIDE_PX.to_string(),
                format!("{} px", render::MIN_PICTURE_SIDE_PX),
            ],
        ),
        (
            &["settle"],
            "Settle and plan",
            vec![physics::MAX_SETTLE_BLOCKS.to_string()],
        ),
        (
            &["plan"],
            "Settle and plan",
            vec![physics::MAX_PLAN_BLOCKS.to_string()],
        ),
        (
            &["score"],
            "Score",
            vec![score::MAX_SCORE_BLOCKS.to_string()],
        ),
        (
            &["edges"],
            "Edges and vertices",
            vec![vision::MAX_PICTURE_SIDE_PX.to_string()],
        ),
        (
            &["vertices"],
            "Edges and vertices",
            vec![
                vision::MAX_PICTURE_SIDE_PX.to_string(),
                format!("{} x (width + height)", vision::MAX_EDGE_PX_PER_SIDE_PX),
            ],
        ),
        (
            &["generate"],
            "Generate",
            vec![u64::MAX.to_string(), dataset::MAX_JOBS.to_string()],
        ),
        (&["export"], "Export", vec![mib(io::MAX_TEXT_BYTES)]),
        (
            &["export-dataset"],
            "Datasets",
            vec![mib(dataset::MAX_MANIFEST_BYTES)],
        ),
        (
            &["report"],
            "Datasets",
            vec![mib(dataset::MAX_MANIFEST_BYTES)],
        ),
    ];
    for (command, heading, numbers) in cases {
        let help = help_limits(command);
        assert!(
            help.contains(&format!("\"{heading}\"")),
            "{command:?}: {help}"
        );
        let docs = limits_section(heading);
        for n in &numbers {
            assert!(
                help.contains(n.as_str()),
                "{command:?} --help lacks {n}: {help}"
            );
            assert!(
                docs.contains(n.as_str()),
                "docs/limits.md {heading} lacks {n}"
            );
        }
    }
}

/// One block past `render`'s, `settle`'s, `score`'s and `plan`'s bound is refused before any
/// work, naming the file, the bound and its heading; nothing is written.
#[test]
fn one_block_past_each_bound_is_refused() {
    use blockworld::{physics, render, score};
    let dir = tempfile::tempdir().unwrap();
    let out = |name: &str| dir.path().join(name).to_string_lossy().into_owned();
    let (r, s, p) = (out("r"), out("s.json"), out("p.json"));
    let render_past = grid_scene(dir.path(), render::MAX_RENDER_BLOCKS + 1);
    let settle_past = grid_scene(dir.path(), physics::MAX_SETTLE_BLOCKS + 1);
    let plan_past = grid_scene(dir.path(), physics::MAX_PLAN_BLOCKS + 1);
    let plan_at = grid_scene(dir.path(), 2);
    let score_past = grid_scene(dir.path(), score::MAX_SCORE_BLOCKS + 1);
    assert_eq!(settle_past, score_past, "one grid serves both");
    let cases: Vec<(Vec<&str>, String)> = vec![
        (
            vec!["render", &render_past, "--views", "ne", "-o", &r],
            format!(
                "the {} `render` takes (docs/limits.md \"Render\")",
                render::MAX_RENDER_BLOCKS
            ),
        ),
        (
            vec!["settle", &settle_past, "-o", &s],
            format!("the {} `settle` takes", physics::MAX_SETTLE_BLOCKS),
        ),
        (
            vec!["plan", &plan_past, "-o", &p],
            format!("the {} `plan` takes", physics::MAX_PLAN_BLOCKS),
        ),
        (
            vec!["score", &score_past, &plan_at],
            format!(
                "the {} `score` takes (docs/limits.md \"Score\")",
                score::MAX_SCORE_BLOCKS
            ),
        ),
        (
            vec!["score", &plan_at, &score_past],
            format!("the {} `score` takes", score::MAX_SCORE_BLOCKS),
        ),
    ];
    for (args, says) in cases {
        let err = fails_with_2(&blockworld(&args));
        assert!(
            err.contains(&says) && err.contains("grid_"),
            "{args:?}: {err}"
        );
    }
    for f in [&r, &s, &p] {
        assert!(!Path::new(f).exists(), "{f} written");
    }
    common::ok(blockworld(["plan", &plan_at, "-o", &p]));
}

/// A picture one pixel wider than `vision::MAX_PICTURE_SIDE_PX` is refused by `edges` and
/// `vertices` from its header, naming the bound.
#[test]
fn pictures_past_the_side_bound_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let side = blockworld::vision::MAX_PICTURE_SIDE_PX + 1;
    let pic = dir.path().join("wide.png");
    image::GrayImage::new(side, 8).save(&pic).unwrap();
    let pic = pic.to_string_lossy().into_owned();
    let camera = common::root().join("tests/fixtures/vision/single_cube/camera_ne.json");
    let e = dir.path().join("e.png").to_string_lossy().into_owned();
    let camera = camera.to_string_lossy().into_owned();
    for args in [
        vec!["edges", &pic, "-o", &e],
        vec!["vertices", &pic, "--camera", &camera],
    ] {
        let err = fails_with_2(&blockworld(&args));
        assert!(
            err.contains("8192") && err.contains("wide.png"),
            "{args:?}: {err}"
        );
    }
    assert!(!Path::new(&e).exists());
}

/// A manifest one byte past `dataset::MAX_MANIFEST_BYTES` (a sparse file) is refused by
/// `export-dataset` and `report` from its size, before it is read.
#[test]
fn manifests_past_the_size_bound_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let ds = dir.path().join("ds");
    std::fs::create_dir(&ds).unwrap();
    let manifest = std::fs::File::create(ds.join("manifest.jsonl")).unwrap();
    manifest
        .set_len(blockworld::dataset::MAX_MANIFEST_BYTES + 1)
        .unwrap();
    let d = ds.to_string_lossy().into_owned();
    let out = dir.path().join("out").to_string_lossy().into_owned();
    for args in [
        vec!["export-dataset", &d, "--format", "hawp", "-o", &out],
        vec!["report", &d, "-o", &out],
    ] {
        let err = fails_with_2(&blockworld(&args));
        assert!(
            err.contains("larger than 1024 MiB") && err.contains("manifest.jsonl"),
            "{args:?}: {err}"
        );
        assert!(!Path::new(&out).exists(), "{args:?} wrote its output");
    }
}

/// One past the time budgets' bound (1,000,000 s, docs/limits.md "Labeller" and "Recognizer")
/// and `export-dataset --split` past 1 are refused before any work, naming the flag and bound.
#[test]
fn budgets_and_shares_past_their_bound_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let fixture = common::root().join("tests/fixtures/vision/single_cube");
    let lines = fixture.join("lines_ne.json").to_string_lossy().into_owned();
    let fix = fixture.to_string_lossy().into_owned();
    let r = dir.path().join("r.json").to_string_lossy().into_owned();
    let out = dir.path().join("out").to_string_lossy().into_owned();
    let cases: [(Vec<&str>, &str); 3] = [
        (
            vec!["label", &lines, "--time-budget-s", "1000001"],
            "--time-budget-s 1000001 is out of range; use a positive number of seconds, at most 1000000",
        ),
        (
            vec!["recognize", &fix, "-o", &r, "--time-budget-s", "1000001"],
            "--time-budget-s 1000001 is out of range",
        ),
        (
            vec!["export-dataset", &fix, "--format", "hawp", "-o", &out, "--split", "1.5"],
            "--split 1.5 must lie in 0..=1",
        ),
    ];
    for (args, says) in cases {
        let err = fails_with_2(&blockworld(&args));
        assert!(err.contains(says), "{args:?}: {err}");
    }
    assert!(!Path::new(&r).exists() && !Path::new(&out).exists());
}

/// One past `render`'s `--size` bound (8192 px a side) and `generate`'s `--jobs` bound
/// (`dataset::MAX_JOBS`) is refused before any work, naming the bound.
#[test]
fn sizes_and_jobs_past_their_bound_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out").to_string_lossy().into_owned();
    let one = common::root().join("scenes/single_cube.json");
    let one = one.to_string_lossy().into_owned();
    let jobs = (blockworld::dataset::MAX_JOBS + 1).to_string();
    let cases: [(Vec<&str>, String); 2] = [
        (
            vec![
                "render", &one, "--views", "ne", "--size", "8193x8", "-o", &out,
            ],
            "each side must be 8..=8192 pixels".to_string(),
        ),
        (
            vec![
                "generate", "--count", "1", "--views", "", "--jobs", &jobs, "-o", &out,
            ],
            format!("--jobs {jobs}: at most {}", blockworld::dataset::MAX_JOBS),
        ),
    ];
    for (args, says) in cases {
        let err = fails_with_2(&blockworld(&args));
        assert!(err.contains(&says), "{args:?}: {err}");
        assert!(!Path::new(&out).exists(), "{args:?} wrote its output");
    }
}
