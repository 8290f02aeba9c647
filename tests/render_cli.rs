//! The `blockworld render` and `blockworld demo` commands end to end (docs/rendering.md "Rendering"): the files they
//! write, what they print, their determinism, and their errors.

mod common;
use common::blockworld;

use std::path::Path;

fn file_names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn render_writes_five_files_per_view_deterministically() {
    if common::renderer().is_none() {
        return;
    }
    let scene = common::root().join("scenes/two_layer.json");
    let tmp = tempfile::tempdir().unwrap();
    let out_a = tmp.path().join("a/nested");
    let out_b = tmp.path().join("b");
    let run = |out: &Path| {
        let o = blockworld([
            "render",
            scene.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ]);
        common::ok(&o);
        String::from_utf8(o.stdout).unwrap()
    };
    let printed_a = run(&out_a);
    let printed_b = run(&out_b);
    let names = file_names(&out_a);
    assert_eq!(names.len(), 20, "{names:?}");
    for view in ["ne", "se", "sw", "nw"] {
        for kind in ["view", "depth", "ids"] {
            assert!(names.contains(&format!("{kind}_{view}.png")));
        }
        for kind in ["lines", "camera"] {
            assert!(names.contains(&format!("{kind}_{view}.json")));
        }
    }
    assert_eq!(
        printed_a
            .lines()
            .filter(|l| l.starts_with("wrote "))
            .count(),
        20
    );
    // Same scene, same bytes: the printed sha256 values agree between the two runs.
    let hashes = |s: &str| -> Vec<String> {
        s.lines()
            .filter_map(|l| l.split("sha256 ").nth(1).map(str::to_string))
            .collect()
    };
    assert_eq!(hashes(&printed_a), hashes(&printed_b));
    // The picture is the golden one; the ground truth files parse.
    let gray = image::open(out_a.join("view_ne.png")).unwrap().into_luma8();
    let golden = image::open(common::root().join("golden/two_layer/view_ne.png"))
        .unwrap()
        .into_luma8();
    assert_eq!(common::diff_stats(&gray, &golden).differing, 0);
    let ids = image::open(out_a.join("ids_ne.png")).unwrap().into_luma16();
    let found: std::collections::BTreeSet<u16> = ids.pixels().map(|p| p[0]).collect();
    assert_eq!(found.into_iter().collect::<Vec<_>>(), vec![0, 1, 2]);
    let camera: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out_a.join("camera_ne.json")).unwrap()).unwrap();
    assert_eq!(camera["size_px"], serde_json::json!([512, 480]));
    assert_eq!(camera["depth_units_per_mm"], 16.0);
    let lines: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out_a.join("lines_ne.json")).unwrap()).unwrap();
    assert!(lines["points"].is_array() && lines["lines"].is_array() && lines["codes"].is_array());
}

#[test]
fn render_options_reach_the_picture() {
    if common::renderer().is_none() {
        return;
    }
    let scene = common::root().join("scenes/single_cube.json");
    let tmp = tempfile::tempdir().unwrap();
    let o = blockworld([
        "render",
        scene.to_str().unwrap(),
        "-o",
        tmp.path().to_str().unwrap(),
        "--views",
        "sw",
        "--size",
        "300x200",
        "--projection",
        "perspective",
        "--fov",
        "40",
        "--msaa",
        "4",
        "--noise",
        "3",
        "--seed",
        "9",
    ]);
    common::ok(&o);
    assert_eq!(file_names(tmp.path()).len(), 5);
    let gray = image::open(tmp.path().join("view_sw.png"))
        .unwrap()
        .into_luma8();
    assert_eq!(gray.dimensions(), (300, 200));
    let camera: serde_json::Value =
        serde_json::from_slice(&std::fs::read(tmp.path().join("camera_sw.json")).unwrap()).unwrap();
    assert_eq!(camera["projection"]["kind"], "perspective");
    assert_eq!(camera["projection"]["fov_y_deg"], 40.0);
}

#[test]
fn bad_input_fails_with_the_file_named_and_writes_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let missing = tmp.path().join("no_such_scene.json");
    let o = blockworld([
        "render",
        missing.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    let err = common::fails_with_2(&o);
    assert!(err.contains("no_such_scene.json"), "{err}");
    assert!(!out.exists(), "no output directory for a failed run");
    let bad = tmp.path().join("bad.json");
    std::fs::write(
        &bad,
        r#"{"name": "x", "blocks": [{"type": "b99", "center": [0, 7.5, 0]}]}"#,
    )
    .unwrap();
    let o = blockworld(["render", bad.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    let err = common::fails_with_2(&o);
    assert!(err.contains("bad.json") && err.contains("b99"), "{err}");
    let scene = common::root().join("scenes/row.json");
    let o = blockworld([
        "render",
        scene.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--msaa",
        "2",
    ]);
    let err = common::fails_with_2(&o);
    assert!(err.contains("--msaa"), "{err}");
    assert!(!out.exists());
}

#[test]
fn demo_renders_the_thesis_sample_and_summarises_each_view() {
    if common::renderer().is_none() {
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("demo");
    let o = common::command()
        .args(["demo", "-o", out.to_str().unwrap()])
        .current_dir(common::root())
        .output()
        .unwrap();
    common::ok(&o);
    let printed = String::from_utf8(o.stdout).unwrap();
    assert!(printed.contains("thesis_sample (5 blocks)"), "{printed}");
    assert!(printed.contains("settle: stable"), "{printed}");
    // 20 render files, the vision front end's vertices_<view>.json, the reconstruction, its six
    // display figures (Figures 6.7-6.12) and two glTF exports (the sample; truth with
    // reconstruction).
    assert_eq!(file_names(&out).len(), 33);
    for fig in blockworld::view::THESIS_FIGURES {
        assert!(
            out.join(format!("{}.png", fig.name)).exists(),
            "{}",
            fig.name
        );
    }
    assert!(out
        .join("thesis_sample_truth_and_reconstruction.glb")
        .exists());
    assert!(out.join("thesis_sample.glb").exists(), "{printed}");
    assert!(out.join("reconstruction.json").exists(), "{printed}");
    let recognized = printed
        .lines()
        .find(|l| l.starts_with("recognize:"))
        .unwrap_or_else(|| panic!("no recognize line: {printed}"));
    assert!(
        recognized.contains("status ok") && recognized.contains("against the truth: exact"),
        "{recognized}"
    );
    for view in ["ne", "se", "sw", "nw"] {
        let line = printed
            .lines()
            .find(|l| l.starts_with(&format!("view {view}:")))
            .unwrap_or_else(|| panic!("no summary for {view}: {printed}"));
        assert!(line.contains("gray levels 5: 35 60 100 150 210"), "{line}");
        assert!(!line.contains(" 0 lines"), "{line}");
        let vision = printed
            .lines()
            .find(|l| l.starts_with(&format!("vision {view}:")))
            .unwrap_or_else(|| panic!("no vision line for {view}: {printed}"));
        // Noise-free orthographic views: the docs/vision.md "Vision front end" target is at least 0.98.
        for field in ["precision", "recall", "six-bit code accuracy"] {
            let value: f64 = vision
                .split(&format!("{field} "))
                .nth(1)
                .and_then(|rest| rest.split([',', ' ']).next())
                .and_then(|v| v.parse().ok())
                .unwrap_or_else(|| panic!("no {field} in {vision}"));
            assert!(value >= 0.98, "{vision}");
        }
        let vertices = std::fs::read_to_string(out.join(format!("vertices_{view}.json"))).unwrap();
        let drawing: blockworld::drawing::LineDrawing = serde_json::from_str(&vertices).unwrap();
        assert!(!drawing.points.is_empty());
    }
}

#[test]
fn no_vulkan_driver_gives_the_install_hint_not_a_panic() {
    // Point the Vulkan loader at a driver list that does not exist: no adapter at all.
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let scene = common::root().join("scenes/single_cube.json");
    let o = common::command()
        .args([
            "render",
            scene.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ])
        .env("VK_ICD_FILENAMES", tmp.path().join("none.json"))
        .env("VK_DRIVER_FILES", tmp.path().join("none.json"))
        .output()
        .unwrap();
    let err = common::fails_with_2(&o);
    assert!(!err.contains("panicked"), "{err}");
    assert!(
        err.contains("mesa-vulkan-drivers")
            && err.contains("libvulkan1")
            && err.contains("--backend gl"),
        "{err}"
    );
    assert!(!out.exists());
}
