//! Where commands write (docs/limits.md "Outputs"): a device node or FIFO given as `-o` is
//! written through, never renamed over; a directory where a file is meant, or an output that is
//! one of the command's inputs, is refused with exit 2 before any work; result lines go to
//! stdout, so a full stdout is an error.

mod common;
use common::{blockworld, fails_with_2};

use std::os::unix::fs::FileTypeExt;
use std::path::{Path, PathBuf};

fn root(rel: &str) -> String {
    common::root().join(rel).to_string_lossy().into_owned()
}

/// A FIFO in `dir` with a thread draining it; the thread returns the bytes read.
fn fifo(dir: &Path, name: &str) -> (PathBuf, std::thread::JoinHandle<Vec<u8>>) {
    let path = dir.join(name);
    let made = std::process::Command::new("mkfifo").arg(&path).status();
    assert!(made.unwrap().success());
    let p = path.clone();
    (path, std::thread::spawn(move || std::fs::read(p).unwrap()))
}

/// Runs `args` with `-o FIFO` appended (the FIFO named `name`) and checks the FIFO is still
/// one and got bytes.
fn writes_through(name: &str, args: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    let (sink, reader) = fifo(dir.path(), name);
    let mut all: Vec<&str> = args.to_vec();
    let s = sink.to_string_lossy().into_owned();
    all.extend(["-o", &s]);
    let o = blockworld(&all);
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    let kind = std::fs::metadata(&sink).unwrap().file_type();
    assert!(
        kind.is_fifo(),
        "{args:?} replaced the FIFO ({kind:?}); {err}"
    );
    assert_eq!(o.status.code(), Some(0), "{args:?}: {err}");
    assert!(!reader.join().unwrap().is_empty(), "{args:?} wrote nothing");
}

/// Regression: `settle`, `export` (.glb and thesis), `vertices`, `recognize` and `view` renamed
/// their temporary file over a device node given as output (`-o /dev/null` became a file).
#[test]
fn a_device_or_fifo_output_is_written_through() {
    let two = root("scenes/two_layer.json");
    let cube = root("tests/fixtures/vision/single_cube");
    let view = format!("{cube}/view_ne.png");
    let camera = format!("{cube}/camera_ne.json");
    writes_through("s.json", &["settle", &two]);
    writes_through("v.png", &["view", &two]);
    writes_through("v.svg", &["view", &two]);
    writes_through("m.glb", &["export", &two]);
    writes_through("r.json", &["recognize", &cube, "--from-truth"]);
    writes_through("l.json", &["vertices", &view, "--camera", &camera]);
    writes_through("e.png", &["edges", &view]);
}

/// A directory where a file is meant is refused by name, and nothing is written in it.
#[test]
fn a_directory_output_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path().to_string_lossy().into_owned();
    let two = root("scenes/two_layer.json");
    let err = fails_with_2(&blockworld(["settle", &two, "-o", &d]));
    assert!(err.contains("is a directory"), "{err}");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}

/// Regression: `recognize DIR -o DIR/lines_ne.json` overwrote its own input without a word;
/// `settle` and `export --format thesis` likewise.
#[test]
fn an_output_that_is_an_input_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let cube = common::root().join("tests/fixtures/vision/single_cube");
    for f in ["camera_ne.json", "lines_ne.json"] {
        std::fs::copy(cube.join(f), dir.path().join(f)).unwrap();
    }
    let lines = dir.path().join("lines_ne.json");
    let before = std::fs::read(&lines).unwrap();
    let d = dir.path().to_string_lossy().into_owned();
    let args = ["recognize", &d, "--from-truth", "--views", "ne", "-o"];
    let err = fails_with_2(&blockworld(
        [&args[..], &[&*lines.to_string_lossy()]].concat(),
    ));
    assert!(err.contains("is the input"), "{err}");
    assert_eq!(std::fs::read(&lines).unwrap(), before);

    let scene = dir.path().join("s.json");
    std::fs::copy(common::root().join("scenes/two_layer.json"), &scene).unwrap();
    let s = scene.to_string_lossy().into_owned();
    let err = fails_with_2(&blockworld(["settle", &s, "-o", &s]));
    assert!(err.contains("is the input"), "{err}");

    let thesis = dir.path().join("t");
    let t = thesis.to_string_lossy().into_owned();
    let o = blockworld(["export", &s, "--format", "thesis", "-o", &t]);
    assert_eq!(o.status.code(), Some(0));
    let err = fails_with_2(&blockworld(["export", &t, "--format", "thesis", "-o", &t]));
    assert!(err.contains("is the input"), "{err}");
}

/// Regression: `recognize --views ne,ne` was accepted (`render` refuses a repeated view).
#[test]
fn a_repeated_view_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("r.json").to_string_lossy().into_owned();
    let cube = root("tests/fixtures/vision/single_cube");
    let o = blockworld([
        "recognize",
        &cube,
        "--from-truth",
        "--views",
        "ne,ne",
        "-o",
        &out,
    ]);
    let err = fails_with_2(&o);
    assert!(err.contains("ne is given twice"), "{err}");
}

/// Regression: `recognize` and `vertices` printed their result line on stderr, so
/// `> /dev/full` exited 0.
#[test]
fn result_lines_go_to_stdout() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("r.json").to_string_lossy().into_owned();
    let cube = root("tests/fixtures/vision/single_cube");
    let view = format!("{cube}/view_ne.png");
    let camera = format!("{cube}/camera_ne.json");
    let runs: [Vec<&str>; 2] = [
        vec!["recognize", &cube, "--from-truth", "-o", &out],
        vec!["vertices", &view, "--camera", &camera, "-o", &out],
    ];
    for args in runs {
        let err = fails_with_2(&common::run::blockworld_to_full_stdout(&args));
        assert!(err.contains("writing to stdout"), "{args:?}: {err}");
    }
}
