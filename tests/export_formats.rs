//! `blockworld export-dataset --format coco|hf|bop` checked by the tools' own code (docs/exports.md
//! "Checks"): a small rendered dataset is exported, and `tests/python/check_exports.py` loads it
//! with pycocotools (every mask against the id pictures, COCOeval of the truth against itself
//! and against a shifted copy) and with Hugging Face `datasets` (the image folder, offline);
//! `tests/python/check_bop.py`, a reader written from BOP's format description, re-projects the
//! BOP export's models onto its masks and depth pictures (docs/export-bop.md "Checks").
//!
//! Needs the renderer (skips without it unless `BLOCKWORLD_REQUIRE_GPU` is set) and the venv
//! `make setup` installs in target/vision-venv (skips without it unless CI or
//! `BLOCKWORLD_REQUIRE_VISION_TOOLS` is set, as `make test` does).

mod common;
use common::{assert_same_tree, blockworld, fails_with_2, ok, renderer, root, vision_python};

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A small rendered dataset: 6 scenes of several families, four 200 x 160 views each.
fn dataset(dir: &Path) {
    dataset_with(dir, "orthographic");
}

/// [`dataset`] through a camera of `projection`.
fn dataset_with(dir: &Path, projection: &str) {
    ok(blockworld([
        "generate",
        "--count",
        "6",
        "--seed",
        "5",
        "--jobs",
        "1",
        "--size",
        "200x160",
        "--projection",
        projection,
        "-o",
        dir.to_str().unwrap(),
    ]));
}

fn export(dataset: &Path, format: &str, out: &Path, jobs: &str) -> Output {
    common::export_dataset(dataset, format, out, &["--jobs", jobs])
}

/// Runs `tests/python/check_exports.py` `kind` on `dataset` and its export `out`.
fn run_python_check(python: &Path, kind: &str, dataset: &Path, out: &Path) -> Output {
    Command::new(python)
        .arg(root().join("tests/python/check_exports.py"))
        .args([kind, dataset.to_str().unwrap(), out.to_str().unwrap()])
        .env("HF_HOME", out.join(".hf-cache"))
        .output()
        .expect("runs python")
}

/// Runs the Python check of `kind` and returns its one-line JSON report.
fn python_check(python: &Path, kind: &str, dataset: &Path, out: &Path) -> serde_json::Value {
    report(run_python_check(python, kind, dataset, out))
}

/// The one-line JSON report a successful Python check prints last.
fn report(run: Output) -> serde_json::Value {
    let stdout = ok(run);
    serde_json::from_str(stdout.lines().last().unwrap_or(""))
        .unwrap_or_else(|e| panic!("{e}: {stdout}"))
}

/// The venv's Python, a temporary folder and a [`dataset_with`] `projection` in it (`ds`);
/// `None` after a loud skip when the renderer or the venv is missing.
fn tools_and_dataset(projection: &str) -> Option<(PathBuf, tempfile::TempDir, PathBuf)> {
    renderer()?;
    let python = vision_python()?;
    let dir = tempfile::tempdir().unwrap();
    let ds = dir.path().join("ds");
    dataset_with(&ds, projection);
    Some((python, dir, ds))
}

#[test]
fn coco_and_hf_exports_load_in_the_tools_and_match_the_id_pictures() {
    let Some((python, dir, ds)) = tools_and_dataset("orthographic") else {
        return;
    };
    let coco = dir.path().join("coco");
    let summary = ok(export(&ds, "coco", &coco, "2"));
    assert!(
        summary.contains("6 scenes (0 kept from an earlier run): 24 images"),
        "{summary}"
    );
    let report = python_check(&python, "coco", &ds, &coco);
    eprintln!("coco: {report}");
    assert_eq!(report["images"], 24);
    assert_eq!(report["masks_exact"], report["annotations"]);
    assert_eq!(report["ap_segm_truth"], 1.0);
    assert!(report["ap_segm_shifted"].as_f64().unwrap() < 1.0);
    assert!(report["ap_bbox_shifted"].as_f64().unwrap() < 1.0);
    let hf = dir.path().join("hf");
    ok(export(&ds, "hf", &hf, "1"));
    let report = python_check(&python, "hf", &ds, &hf);
    eprintln!("hf: {report}");
    assert_eq!(report["rows"], 24);
    // The checks can fail: the top row of a block's pixels turned to floor in an id picture
    // makes its decoded mask (COCO) and its box (HF) differ from the export.
    let ids_path = ds.join("s000000/ids_ne.png");
    let mut ids = image::open(&ids_path).unwrap().to_luma16();
    let w = ids.width() as usize;
    let first = ids.as_raw().iter().position(|&v| v != 0).unwrap();
    let (row, id) = (first / w, ids.as_raw()[first]);
    for c in 0..w {
        if ids.get_pixel(c as u32, row as u32).0[0] == id {
            ids.put_pixel(c as u32, row as u32, image::Luma([0]));
        }
    }
    ids.save(&ids_path).unwrap();
    for (kind, out, why) in [("coco", &coco, "pixels differ"), ("hf", &hf, "boxes")] {
        let run = run_python_check(&python, kind, &ds, out);
        let err = String::from_utf8_lossy(&run.stderr);
        assert!(!run.status.success() && err.contains(why), "{kind}: {err}");
    }
}

#[test]
fn coco_export_is_deterministic_resumable_and_refuses_a_damaged_dataset() {
    if renderer().is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let ds = dir.path().join("ds");
    dataset(&ds);
    let (a, b) = (dir.path().join("a"), dir.path().join("b"));
    ok(export(&ds, "coco", &a, "1"));
    ok(export(&ds, "coco", &b, "3"));
    let doc = |d: &Path| std::fs::read(d.join("annotations/instances.json")).unwrap();
    assert_eq!(doc(&a), doc(&b), "the bytes depend on --jobs");
    // Full masks against the id pictures: no visible pixel outside its silhouette, and at
    // most a few pixel centres on an edge that the GPU's rounding puts on the other side.
    let summary = ok(export(&ds, "coco", &a, "2"));
    assert!(
        summary.contains("(6 kept from an earlier run)"),
        "{summary}"
    );
    assert!(summary.contains(" 0 visible px outside"), "{summary}");
    let on_background: u64 = summary
        .split(" visible px outside, ")
        .nth(1)
        .and_then(|s| s.split(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap();
    assert!(on_background <= 20, "{summary}");
    assert_eq!(doc(&a), doc(&b));
    // A damaged id picture is refused with its path and exit 2, and nothing is written.
    let ids = ds.join("s000001/ids_se.png");
    let mut bytes = std::fs::read(&ids).unwrap();
    let last = bytes.len() - 20;
    bytes[last] ^= 0xff;
    std::fs::write(&ids, &bytes).unwrap();
    let fresh = dir.path().join("c");
    let out = export(&ds, "coco", &fresh, "1");
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("s000001/ids_se.png") && err.contains("re-run"),
        "{err}"
    );
    assert!(!fresh.join("annotations/instances.json").exists());
}

/// Runs `tests/python/check_bop.py` on a BOP export.
fn run_bop_check(python: &Path, out: &Path) -> Output {
    Command::new(python)
        .arg(root().join("tests/python/check_bop.py"))
        .arg(out)
        .output()
        .expect("runs python")
}

#[test]
fn bop_export_reprojects_onto_its_masks_and_depth_and_resumes_byte_for_byte() {
    let Some((python, dir, ds)) = tools_and_dataset("perspective") else {
        return;
    };
    let (a, b) = (dir.path().join("a"), dir.path().join("b"));
    let summary = ok(export(&ds, "bop", &a, "1"));
    assert!(
        summary.contains("6 scenes (0 kept from an earlier run): 24 images"),
        "{summary}"
    );
    ok(export(&ds, "bop", &b, "3"));
    assert_same_tree(&a, &b);
    let summary = ok(export(&ds, "bop", &a, "2"));
    assert!(
        summary.contains("(6 kept from an earlier run)"),
        "{summary}"
    );
    assert_same_tree(&a, &b);
    let counts = report(run_bop_check(&python, &a));
    eprintln!("bop: {counts}");
    assert_eq!(counts["images"], 24);
    assert!(counts["vertices_visible"].as_u64().unwrap() > 0);
    // The check can fail: one instance moved 1 mm along the camera's x.
    let gt_path = b.join("train_pbr/000003/scene_gt.json");
    let mut gt: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&gt_path).unwrap()).unwrap();
    let t = &mut gt["2"][0]["cam_t_m2c"][0];
    *t = serde_json::json!(t.as_f64().unwrap() + 1.0);
    std::fs::write(&gt_path, gt.to_string()).unwrap();
    let run = run_bop_check(&python, &b);
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(
        !run.status.success() && err.contains("instance 0") && err.contains("from the mask"),
        "{err}"
    );
}

#[test]
fn bop_export_refuses_an_orthographic_dataset_before_writing() {
    if renderer().is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let ds = dir.path().join("ds");
    dataset(&ds);
    let out = dir.path().join("bop");
    let err = fails_with_2(&export(&ds, "bop", &out, "1"));
    assert!(
        err.contains("s000000/camera_") && err.contains("generate --projection perspective"),
        "{err}"
    );
    assert!(!out.exists());
}

/// Runs `tests/python/check_fiftyone.py` on the COCO and HF exports of `dataset`, with FiftyOne's
/// database in `db`.
fn run_fiftyone_check(python: &Path, dataset: &Path, coco: &Path, hf: &Path, db: &Path) -> Output {
    Command::new(python)
        .arg(root().join("tests/python/check_fiftyone.py"))
        .args([dataset, coco, hf])
        .env("FIFTYONE_DATABASE_DIR", db)
        .env("FIFTYONE_DO_NOT_TRACK", "true")
        .output()
        .expect("runs python")
}

#[test]
fn fiftyone_imports_the_coco_and_hf_exports_with_every_picture_and_block() {
    let Some((python, dir, ds)) = tools_and_dataset("orthographic") else {
        return;
    };
    let (coco, hf) = (dir.path().join("coco"), dir.path().join("hf"));
    let summary = ok(export(&ds, "coco", &coco, "2"));
    ok(export(&ds, "hf", &hf, "2"));
    let annotations: u64 = summary
        .split(" images, ")
        .nth(1)
        .and_then(|s| s.split(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("{summary}"));
    let db = dir.path().join("fiftyone-db");
    let counts = report(run_fiftyone_check(&python, &ds, &coco, &hf, &db));
    eprintln!("fiftyone: {counts}");
    assert_eq!(counts["samples"], 24);
    assert_eq!(counts["coco_boxes"], annotations);
    assert_eq!(counts["coco_masks"], annotations);
    assert_eq!(counts["hf_labels"], annotations);
    // The check can fail: a COCO file with one annotation removed.
    let path = coco.join("annotations/instances.json");
    let mut doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    doc["annotations"].as_array_mut().unwrap().pop();
    std::fs::write(&path, doc.to_string()).unwrap();
    let run = run_fiftyone_check(&python, &ds, &coco, &hf, &db);
    let err = String::from_utf8_lossy(&run.stderr);
    let want = format!("{} labels from the COCO export", annotations - 1);
    assert!(!run.status.success() && err.contains(&want), "{err}");
}
