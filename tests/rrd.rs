//! `blockworld render|recognize --rrd FILE` read back by Rerun's own reader (docs/rerun.md
//! "Check"): `tests/python/check_rrd.py` loads the recording of the thesis sample with the
//! rerun-sdk wheel of the crate's version and asserts its entities, counts and the pinhole
//! intrinsics against the camera files; recordings with a wrong intrinsic or a missing camera
//! fail it. Without the `rrd` feature, `--rrd` exits 2 naming the feature.
//!
//! Needs the renderer (skips without it unless `BLOCKWORLD_REQUIRE_GPU` is set) and the venv
//! `make setup` installs in target/rerun-venv (skips without it unless CI or
//! `BLOCKWORLD_REQUIRE_RERUN` is set, as `make test` does).

mod common;
use common::{blockworld, root};

#[cfg(not(feature = "rrd"))]
use common::fails_with_2;

#[cfg(feature = "rrd")]
use common::{ok, renderer_available};
#[cfg(feature = "rrd")]
use std::path::{Path, PathBuf};
#[cfg(feature = "rrd")]
use std::process::{Command, Output};

#[cfg(not(feature = "rrd"))]
#[test]
fn rrd_without_the_feature_exits_2_naming_it_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("views");
    let rrd = dir.path().join("sample.rrd");
    let scene = root().join("scenes/thesis_sample.json");
    let o = blockworld([
        "render".as_ref(),
        scene.as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
        "--rrd".as_ref(),
        rrd.as_os_str(),
    ]);
    let err = fails_with_2(&o);
    assert!(
        err.contains("built without the rrd feature; build with `cargo build --features rrd`"),
        "{err}"
    );
    assert!(!out.exists() && !rrd.exists(), "nothing is written");
    let o = blockworld([
        "recognize".as_ref(),
        dir.path().as_os_str(),
        "-o".as_ref(),
        dir.path().join("r.json").as_os_str(),
        "--from-truth".as_ref(),
        "--rrd".as_ref(),
        rrd.as_os_str(),
    ]);
    assert!(fails_with_2(&o).contains("rrd feature"));
    let o = blockworld([
        "export".as_ref(),
        scene.as_os_str(),
        "--format".as_ref(),
        "rrd".as_ref(),
        "-o".as_ref(),
        rrd.as_os_str(),
    ]);
    assert!(fails_with_2(&o).contains("rrd feature"));
    assert!(!rrd.exists());
}

/// The venv's Python with rerun-sdk, or `None` after a loud skip; a failure in CI or with
/// `BLOCKWORLD_REQUIRE_RERUN` set.
#[cfg(feature = "rrd")]
fn rerun_python() -> Option<PathBuf> {
    let python = root().join("target/rerun-venv/bin/python");
    let usable = Command::new(&python)
        .args(["-c", "import rerun.recording"])
        .output()
        .is_ok_and(|o| o.status.success());
    if usable {
        return Some(python);
    }
    let required =
        std::env::var_os("CI").is_some() || std::env::var_os("BLOCKWORLD_REQUIRE_RERUN").is_some();
    assert!(
        !required,
        "{} cannot import rerun.recording: run make setup",
        python.display()
    );
    eprintln!(
        "SKIPPED: no {} with rerun-sdk (make setup installs it)",
        python.display()
    );
    None
}

/// Renders the thesis sample into `dir/<name>` with a recording `dir/<name>.rrd`.
#[cfg(feature = "rrd")]
fn render(dir: &Path, name: &str, extra: &[&str]) -> (PathBuf, PathBuf) {
    let scene = root().join("scenes/thesis_sample.json");
    let (out, rrd) = (dir.join(name), dir.join(format!("{name}.rrd")));
    let mut args: Vec<&std::ffi::OsStr> = vec![
        "render".as_ref(),
        scene.as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
        "--size".as_ref(),
        "256x240".as_ref(),
        "--rrd".as_ref(),
        rrd.as_os_str(),
    ];
    args.extend(extra.iter().map(|s| std::ffi::OsStr::new(*s)));
    ok(blockworld(args));
    (out, rrd)
}

#[cfg(feature = "rrd")]
fn check(python: &Path, rrd: &Path, dir: &Path, extra: &[&str]) -> Output {
    Command::new(python)
        .arg(root().join("tests/python/check_rrd.py"))
        .arg(rrd)
        .arg(dir)
        .arg("--scene")
        .arg(root().join("scenes/thesis_sample.json"))
        .args(extra)
        .output()
        .expect("runs check_rrd.py")
}

#[cfg(feature = "rrd")]
fn passes(o: &Output) {
    assert!(
        o.status.success(),
        "check_rrd.py: {}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
}

#[cfg(feature = "rrd")]
fn fails_saying(o: &Output, what: &str) {
    let text = String::from_utf8_lossy(&o.stdout);
    assert_eq!(
        o.status.code(),
        Some(1),
        "{text}{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(text.contains(what), "expected {what:?} in: {text}");
}

#[cfg(feature = "rrd")]
#[test]
fn thesis_sample_recordings_read_back_and_wrong_ones_fail() {
    let Some(python) = rerun_python() else { return };
    if !renderer_available() {
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let persp = ["--projection", "perspective", "--fov", "30"];
    let (dir, rrd) = render(tmp.path(), "persp", &persp);
    passes(&check(&python, &rrd, &dir, &[]));
    let (ortho_dir, ortho_rrd) = render(tmp.path(), "ortho", &[]);
    passes(&check(&python, &ortho_rrd, &ortho_dir, &[]));
    // Another field of view: every intrinsic differs from the camera files of `dir`.
    let (_, wide) = render(
        tmp.path(),
        "wide",
        &["--projection", "perspective", "--fov", "40"],
    );
    fails_saying(&check(&python, &wide, &dir, &[]), "intrinsics fx fy cx cy");
    // A recording without the north-west camera, checked against all four camera files.
    let three = [&persp[..], &["--views", "ne,se,sw"]].concat();
    let (_, partial) = render(tmp.path(), "three", &three);
    fails_saying(
        &check(&python, &partial, &dir, &[]),
        "world/cameras/nw: no Transform3D",
    );
}

#[cfg(feature = "rrd")]
#[test]
fn recognize_records_the_reconstruction_beside_the_truth() {
    let Some(python) = rerun_python() else { return };
    if !renderer_available() {
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let (dir, _) = render(tmp.path(), "views", &[]);
    std::fs::copy(
        root().join("scenes/thesis_sample.json"),
        dir.join("scene.json"),
    )
    .unwrap();
    let (recon, rrd) = (tmp.path().join("recon.json"), tmp.path().join("recon.rrd"));
    let args: [&std::ffi::OsStr; 7] = [
        "recognize".as_ref(),
        dir.as_os_str(),
        "-o".as_ref(),
        recon.as_os_str(),
        "--from-truth".as_ref(),
        "--rrd".as_ref(),
        rrd.as_os_str(),
    ];
    ok(blockworld(args));
    let answer: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&recon).unwrap()).unwrap();
    let blocks = answer["blocks"].as_array().unwrap().len();
    assert!(blocks > 0, "the thesis sample is recognized: {answer}");
    let n = blocks.to_string();
    passes(&check(&python, &rrd, &dir, &["--recognized", &n]));
    let one_more = (blocks + 1).to_string();
    fails_saying(
        &check(&python, &rrd, &dir, &["--recognized", &one_more]),
        "world/recognized/blocks",
    );
}

/// `export SCENE --format rrd --trajectory trajectory.bin` of a stability dataset's falling
/// scene puts every frame of the trajectory on the timeline `fall` (check_rrd_fall.py reads
/// it back); the same recording checked against another scene's trajectory fails.
#[cfg(feature = "rrd")]
#[test]
fn a_fall_reads_back_on_its_timeline() {
    let Some(python) = rerun_python() else { return };
    let tmp = tempfile::tempdir().unwrap();
    let ds = tmp.path().join("ds");
    let ds_s = ds.to_str().unwrap();
    ok(blockworld([
        "generate",
        "--count",
        "6",
        "--seed",
        "3",
        "--views",
        "",
        "--keep-unstable",
        "--trajectory",
        "-o",
        ds_s,
    ]));
    let manifest = std::fs::read_to_string(ds.join("manifest.jsonl")).unwrap();
    let entries: Vec<serde_json::Value> = manifest
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    let folder = |e: &serde_json::Value| ds.join(e["id"].as_str().unwrap());
    let fall = entries
        .iter()
        .find(|e| e["stable"] == false)
        .expect("seed 3 draws a fall among 6 scenes");
    let (dir, rrd) = (folder(fall), tmp.path().join("fall.rrd"));
    ok(blockworld([
        "export".as_ref(),
        dir.join("scene.json").as_os_str(),
        "--format".as_ref(),
        "rrd".as_ref(),
        "--trajectory".as_ref(),
        dir.join("trajectory.bin").as_os_str(),
        "-o".as_ref(),
        rrd.as_os_str(),
    ]));
    let check = |trajectory: &Path| {
        Command::new(&python)
            .arg(root().join("tests/python/check_rrd_fall.py"))
            .arg(&rrd)
            .arg(trajectory)
            .output()
            .expect("runs check_rrd_fall.py")
    };
    passes(&check(&dir.join("trajectory.bin")));
    let other = entries
        .iter()
        .find(|e| e["id"] != fall["id"])
        .expect("another scene");
    let o = check(&folder(other).join("trajectory.bin"));
    assert_eq!(
        o.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&o.stdout)
    );
}
