//! Fair but hostile inputs to the labeller, the recognizer and the benches (docs/limits.md):
//! each test pins an input that panicked, ran without bound or answered wrongly, and checks it
//! now ends with an answer, a reasoned `unsupported` or exit 2 and a message.

mod common;
use common::{blockworld, fails_with_2};

use std::path::Path;

/// `copies` copies of PAIP's cube drawing side by side, as drawing JSON.
fn cubes_side_by_side(copies: usize) -> String {
    let cube = std::fs::read_to_string(common::root().join("tests/fixtures/kanade/paip_cube.json"));
    let cube: serde_json::Value = serde_json::from_str(&cube.unwrap()).unwrap();
    let points = cube["points"].as_array().unwrap();
    let lines = cube["lines"].as_array().unwrap();
    let (mut ps, mut ls) = (Vec::new(), Vec::new());
    for k in 0..copies {
        for p in points {
            let x = p[0].as_f64().unwrap() + 300.0 * k as f64;
            ps.push(serde_json::json!([x, p[1]]));
        }
        for l in lines {
            let at = |i: usize| l[i].as_u64().unwrap() as usize + k * points.len();
            ls.push(serde_json::json!([at(0), at(1)]));
        }
    }
    serde_json::json!({ "points": ps, "lines": ls }).to_string()
}

/// Regression: `label --json` panicked (exit 101, "number out of range") when a count exceeded
/// `u64`, as five separate cubes' combinations before filtering do (29,160^5); it is written
/// as a decimal string.
#[test]
fn label_json_writes_counts_beyond_u64() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("five_cubes.json");
    std::fs::write(&path, cubes_side_by_side(5)).unwrap();
    let o = blockworld(["label", &path.to_string_lossy(), "--json", "--limit", "1"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{err}");
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let before = &v["report"]["stats"]["combinations_before"]["exact"];
    let n: u128 = before
        .as_str()
        .expect("a string beyond u64")
        .parse()
        .unwrap();
    assert_eq!(n, 29_160u128.pow(5));
    assert_eq!(v["report"]["count"]["value"], 1024);
}

/// Regression: a camera whose `view_from_world` held one entry of 1e20 was read (invertible,
/// not rigid) and made `recognize` panic in its check; the reader refuses it, naming the field.
#[test]
fn a_camera_that_is_not_rigid_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let cube = common::root().join("tests/fixtures/vision/single_cube");
    for v in ["ne", "se", "sw", "nw"] {
        for f in [format!("camera_{v}.json"), format!("lines_{v}.json")] {
            std::fs::copy(cube.join(&f), dir.path().join(&f)).unwrap();
        }
    }
    let camera = dir.path().join("camera_ne.json");
    let mut c: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&camera).unwrap()).unwrap();
    c["view_from_world"][9] = serde_json::json!(1e20);
    std::fs::write(&camera, c.to_string()).unwrap();
    let out = dir.path().join("r.json");
    let d = dir.path().to_string_lossy().into_owned();
    let o = blockworld([
        "recognize",
        &d,
        "--from-truth",
        "-o",
        &out.to_string_lossy(),
    ]);
    let err = fails_with_2(&o);
    assert!(
        err.contains("camera_ne.json") && err.contains("not a rigid rotation"),
        "{err}"
    );
    assert!(!Path::new(&out).exists());
}

/// Regression: `bench scale --blocks 100000000` and `bench settle --grid 1000000` built their
/// stacks and passed 10 GB of memory; a count beyond the cap (or 0, an empty table) is refused
/// before any work, naming the flag and the bound.
#[test]
fn bench_block_counts_beyond_their_cap_are_refused() {
    for (args, cap) in [
        (["bench", "scale", "--blocks", "100000000"], "10000"),
        (["bench", "scale", "--blocks", "10,0"], "10000"),
        (["bench", "settle", "--grid", "1000000"], "2000"),
        (["bench", "settle", "--grid", "2001"], "2000"),
        (["bench", "render", "--blocks", "1001"], "1000"),
    ] {
        let err = fails_with_2(&blockworld(args));
        assert!(
            err.contains(&format!("--{} ", &args[2][2..]))
                && err.contains(&format!("1 to {cap} blocks")),
            "{args:?}: {err}"
        );
    }
}

/// Regression: `bench render --iterations 0` ran 4 timed renders per scene without a word;
/// fewer than 4 (one per view) is refused before any work, naming the flag.
#[test]
fn bench_render_refuses_fewer_than_four_iterations() {
    for n in ["0", "3"] {
        let err = fails_with_2(&blockworld(["bench", "render", "--iterations", n]));
        assert!(
            err.contains(&format!("--iterations {n}: give at least 4")),
            "{n}: {err}"
        );
    }
}

/// A chain of `lines` segments between seeded random points (picture px), as drawing JSON.
fn random_chain(lines: usize, seed: u64) -> String {
    let mut state = seed;
    let mut next = || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1u64 << 53) as f64 * 10_000.0
    };
    let points: Vec<[f64; 2]> = (0..=lines).map(|_| [next(), next()]).collect();
    let chain: Vec<[usize; 2]> = (0..lines).map(|i| [i, i + 1]).collect();
    serde_json::json!({ "points": points, "lines": chain }).to_string()
}

/// Regression: `label` of 100,000 random lines ran past 60 s at 1.8 GB (each search node cost
/// time in proportion to the drawing); it now ends with a count that names the budget that
/// stopped it, and a drawing beyond the line limit is refused naming the file and the fix.
#[test]
fn label_of_a_hundred_thousand_random_lines_ends_with_its_budget() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("chain.json");
    std::fs::write(&path, random_chain(100_000, 7)).unwrap();
    let o = blockworld([
        "label",
        &path.to_string_lossy(),
        "--json",
        "--limit",
        "1",
        "--time-budget-s",
        "3",
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{err}");
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let count = &v["report"]["count"];
    assert_eq!(count["exact"], false, "{count}");
    assert!(
        count["reason"].as_str().unwrap().contains("budget"),
        "{count}"
    );
    assert_eq!(v["labellings"][0].as_str().unwrap().len(), 100_000);

    let big = dir.path().join("big.json");
    std::fs::write(&big, random_chain(100_001, 7)).unwrap();
    let err = fails_with_2(&blockworld(["label", &big.to_string_lossy()]));
    assert!(
        err.contains("big.json") && err.contains("100001 lines") && err.contains("at most 100000"),
        "{err}"
    );
}

/// Regression: `view --shade` of 5,000 blocks ran 57 s without a word (the wireframe takes
/// 0.1 s); shading beyond 250 block views is refused before drawing, naming the file and the
/// fix, while the wireframe of the same scene is drawn.
#[test]
fn view_shade_beyond_its_cap_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let blocks: Vec<serde_json::Value> = (0..1001)
        .map(|i| {
            let (x, z) = ((i % 40) as f64 * 30.0, (i / 40) as f64 * 30.0);
            serde_json::json!({"type": "b15", "center": [x, 7.5, z]})
        })
        .collect();
    let scene = dir.path().join("grid_1001.json");
    let text = serde_json::json!({"name": "grid_1001", "blocks": blocks}).to_string();
    std::fs::write(&scene, text).unwrap();
    let out = dir.path().join("v.png");
    let (scene, out) = (scene.to_string_lossy(), out.to_string_lossy());
    let err = fails_with_2(&blockworld(["view", &scene, "--shade", "-o", &out]));
    assert!(
        err.contains("grid_1001.json")
            && err.contains("1001 blocks")
            && err.contains("drop --shade"),
        "{err}"
    );
    assert!(!Path::new(out.as_ref()).exists());
    let o = blockworld(["view", &scene, "-o", &out]);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
}

/// Regression: `label` refused a drawing whose `kinds` list had another length than its lines,
/// although its help says the fields beside `points` and `lines` are ignored; and `recognize`
/// of a folder that does not exist reported its first camera file missing.
#[test]
fn label_ignores_other_fields_and_recognize_names_a_missing_folder() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("l.json");
    let drawing =
        r#"{"points": [[0, 0], [10, 0], [0, 10]], "lines": [[0, 1], [0, 2]], "kinds": ["convex"]}"#;
    std::fs::write(&path, drawing).unwrap();
    let o = blockworld(["label", &path.to_string_lossy()]);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let missing = dir.path().join("no_such_folder");
    let out = dir.path().join("r.json");
    let err = fails_with_2(&blockworld([
        "recognize",
        &missing.to_string_lossy(),
        "--from-truth",
        "-o",
        &out.to_string_lossy(),
    ]));
    assert!(
        err.contains("no_such_folder: no such folder") && !err.contains("camera_ne.json: missing"),
        "{err}"
    );
}

/// The single cube's exact NE drawing (tests/fixtures/vision/single_cube) tiled `n` x `n` in
/// the picture, written to `dir` with the NE camera. `aligned`: each step is two cube edges
/// along the floor's axes, so the tiles are cubes on the floor with gaps between them; else
/// steps of 400 px across and 450 px up, which put the tiles at heights no one floor plan
/// explains.
fn tiled_cubes(dir: &Path, n: usize, aligned: bool) {
    let cube = common::root().join("tests/fixtures/vision/single_cube");
    std::fs::copy(cube.join("camera_ne.json"), dir.join("camera_ne.json")).unwrap();
    let text = std::fs::read_to_string(cube.join("lines_ne.json")).unwrap();
    let d: serde_json::Value = serde_json::from_str(&text).unwrap();
    let p: Vec<[f64; 2]> = serde_json::from_value(d["points"].clone()).unwrap();
    let lines: Vec<[usize; 2]> = serde_json::from_value(d["lines"].clone()).unwrap();
    // Points 5 -> 6 and 5 -> 1 are the cube's bottom edges along the floor's two axes.
    let edge = |to: usize| [p[to][0] - p[5][0], p[to][1] - p[5][1]];
    let (ex, ez) = (edge(6), edge(1));
    let (mut points, mut all_lines) = (Vec::new(), Vec::new());
    for i in 0..n {
        for j in 0..n {
            let (i, j) = (i as f64, j as f64);
            let step = if aligned {
                [2.0 * (i * ex[0] + j * ez[0]), 2.0 * (i * ex[1] + j * ez[1])]
            } else {
                [400.0 * i, 450.0 * j]
            };
            let base = points.len();
            points.extend(p.iter().map(|q| [q[0] + step[0], q[1] + step[1]]));
            all_lines.extend(lines.iter().map(|l| [l[0] + base, l[1] + base]));
        }
    }
    let drawing = serde_json::json!({ "points": points, "lines": all_lines });
    std::fs::write(dir.join("lines_ne.json"), drawing.to_string()).unwrap();
}

/// Regression: `recognize --from-truth` of a 20 x 20 tiling of separate cubes (3,600 lines)
/// searched for minutes without a word (10 x 10 at mismatched heights over 300 s); the search
/// now spends at most its node budget, shows its progress on stderr, and declines naming the
/// budget. The aligned 10 x 10 tiling, which the direct path answers, is still 100 cubes.
#[test]
fn recognize_of_a_large_tiling_declines_within_its_search_budget() {
    let dir = tempfile::tempdir().unwrap();
    let (tiles, out) = (dir.path().join("tiles"), dir.path().join("r.json"));
    std::fs::create_dir(&tiles).unwrap();
    let (d, o) = (tiles.to_string_lossy(), out.to_string_lossy());
    let args = ["recognize", &d, "--from-truth", "--views", "ne", "-o", &o];
    tiled_cubes(&tiles, 20, false);
    let (run, in_time) = common::blockworld_within(&args, 240);
    let (stdout, stderr) = (common::ok(&run), common::stderr(&run));
    assert!(in_time, "still searching after 240 s: {stderr}");
    assert!(
        stdout.contains("(unsupported: search budget of 5000000 nodes / 120 s spent: "),
        "{stdout}"
    );
    assert!(stderr.contains("recognize: search, "), "{stderr}");
    let recon = std::fs::read_to_string(&out).unwrap();
    assert!(recon.contains("\"unsupported\""), "{recon}");

    tiled_cubes(&tiles, 10, false);
    let small = [&args[..], &["--node-budget", "1000"]].concat();
    let stdout = common::ok(blockworld(&small));
    assert!(
        stdout.contains("0 blocks in 0 layers")
            && stdout.contains("search budget of 1000 nodes / 120 s spent: the node budget ran out after 990 nodes"),
        "{stdout}"
    );

    tiled_cubes(&tiles, 10, true);
    let stdout = common::ok(blockworld(args));
    assert!(stdout.contains(": 100 blocks in 1 layers ->"), "{stdout}");
    assert!(!stdout.contains("unsupported"), "{stdout}");
}

/// Regression: a number of 300 digits that clap rejects (`generate --count 999...9`) was
/// quoted back in full; it is echoed short, with the flag, exit 2.
#[test]
fn rejected_long_numbers_are_echoed_short() {
    let huge = "9".repeat(300);
    let err = fails_with_2(&blockworld(["generate", "--count", &huge, "-o", "unused"]));
    assert!(
        err.contains("invalid value '1e300' for '--count") && err.len() < 200,
        "{err}"
    );
    assert!(!Path::new("unused").exists());
}

/// `recognize` reads the lights and the edge radius of a `look.json` beside the views: one
/// that is not a look file, gives a light below the horizon or a radius below 0 or beyond a
/// block's rounding, exits 2 naming the file and writes nothing; a hand-made one with only
/// `edge_radius_mm` and `views.<v>[].towards_light` is read, and the cube answered.
#[test]
fn recognize_names_a_bad_look_json_and_reads_a_hand_made_one() {
    let dir = tempfile::tempdir().unwrap();
    let cube = common::root().join("tests/fixtures/vision/single_cube");
    let scene = dir.path().join("cube");
    std::fs::create_dir(&scene).unwrap();
    for v in ["ne", "se", "sw", "nw"] {
        for f in [format!("camera_{v}.json"), format!("view_{v}.png")] {
            std::fs::copy(cube.join(&f), scene.join(&f)).unwrap();
        }
    }
    let out = dir.path().join("r.json");
    let run = || {
        blockworld([
            "recognize",
            &scene.to_string_lossy(),
            "-o",
            &out.to_string_lossy(),
        ])
    };
    let look = scene.join("look.json");
    for (text, says) in [
        (r#"{"views": 3}"#, "not a look.json"),
        (r#"{"edge_radius_mm": "round"}"#, "not a look.json"),
        (r#"{"edge_radius_mm": -0.1}"#, "is not a radius from 0 to"),
        (r#"{"edge_radius_mm": 40}"#, "is not a radius from 0 to"),
        (
            r#"{"views": {"ne": [{"towards_light": [1, -1, 0]}]}}"#,
            "not a direction above the horizon",
        ),
    ] {
        std::fs::write(&look, text).unwrap();
        let err = fails_with_2(&run());
        assert!(err.contains("look.json") && err.contains(says), "{err}");
        assert!(!out.exists());
    }
    let lit = r#"{"edge_radius_mm": 0.05, "views": {"ne": [{"towards_light": [0.5, 1, 0.2]}], "sw": []}}"#;
    std::fs::write(&look, lit).unwrap();
    let stdout = common::ok(run());
    assert!(stdout.contains("1 blocks in 1 layers"), "{stdout}");
}

/// `--grid-mm` tells `recognize`, `recognize-dataset` and `bench accuracy` the pitch of the
/// grid the blocks stand on: a pitch that is no number, not over four times the snap or over
/// 1000 mm exits 2 naming the flag and writes nothing; the cube of the vision fixture, which
/// stands on the 7.5 mm grid, is answered with it.
#[test]
fn a_grid_pitch_out_of_range_is_refused_and_the_fischer_technik_grid_read() {
    let dir = tempfile::tempdir().unwrap();
    let cube = common::root().join("tests/fixtures/vision/single_cube");
    let cube = cube.to_string_lossy().into_owned();
    let cube = cube.as_str();
    let out = dir.path().join("r.json");
    let out_s = out.to_string_lossy().into_owned();
    let out_s = out_s.as_str();
    let folder = dir.path().join("recognitions");
    let folder_s = folder.to_string_lossy().into_owned();
    let folder_s = folder_s.as_str();
    for pitch in ["nan", "0", "-7.5", "4", "1000.5"] {
        let grid = format!("--grid-mm={pitch}");
        let grid = grid.as_str();
        for args in [
            vec!["recognize", cube, "-o", out_s, grid],
            vec!["recognize-dataset", cube, "-o", folder_s, grid],
            vec![
                "bench", "accuracy", "--family", "single", "--count", "1", grid,
            ],
        ] {
            let err = fails_with_2(&blockworld(args.iter().copied()));
            assert!(
                err.contains("--grid-mm") && err.contains("more than 4"),
                "{err}"
            );
            assert!(!out.exists() && !folder.exists(), "{args:?}");
        }
    }
    let centre = |grid: &[&str]| {
        let stdout = common::ok(blockworld(
            ["recognize", cube, "-o", out_s].iter().chain(grid),
        ));
        assert!(stdout.contains("1 blocks in 1 layers"), "{stdout}");
        let recon: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
        let c = &recon["blocks"][0]["center"];
        [c[0].as_f64().unwrap(), c[2].as_f64().unwrap()]
    };
    // The cube stands with its least x and z at -7.5 mm: on the grid exactly with it, a few
    // micrometres off without it.
    assert!(centre(&["--grid-mm", "7.5"]).iter().all(|c| c.abs() < 1e-9));
    assert!(centre(&[]).iter().any(|c| c.abs() > 1e-7));
}
