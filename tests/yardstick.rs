//! The numpy half of `bench/blender/render_dataset.py`'s varied look checked without Blender
//! (docs/yardstick.md "The varied look, draw for draw"): `tests/python/check_blender_sensor.py`
//! reads a scene's `look.json` as the script does (and refuses another format, naming the
//! file), runs the script's sensor against an independent computation of blur, vignetting,
//! shot and read noise and quantization, and its 2 x 2 average and PNG writer against Pillow.
//!
//! Needs the renderer for the varied scene (skips without it unless `BLOCKWORLD_REQUIRE_GPU`
//! is set) and the venv `make setup` installs in target/vision-venv (numpy and Pillow).

mod common;
use common::{blockworld, ok, renderer, root, vision_python};

#[test]
fn the_blender_bench_reads_look_json_and_exposes_as_blockworld_s_sensor() {
    if renderer().is_none() {
        return;
    }
    let Some(python) = vision_python() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let ds = dir.path().join("ds");
    ok(blockworld([
        "generate",
        "--count",
        "1",
        "--seed",
        "4",
        "--look",
        "photo_varied",
        "-o",
        ds.to_str().unwrap(),
    ]));
    let out = std::process::Command::new(python)
        .arg(root().join("tests/python/check_blender_sensor.py"))
        .arg(ds.join("s000000"))
        .arg(dir.path())
        .output()
        .expect("runs python");
    let text =
        String::from_utf8_lossy(&out.stdout).to_string() + &String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{text}");
    assert!(text.contains("blender sensor checks: ok"), "{text}");
}
