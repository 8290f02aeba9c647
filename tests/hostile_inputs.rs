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
