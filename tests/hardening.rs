//! What a hostile but fair user does to the command line (README "Exit codes"): full or closed
//! stdout, huge coordinates, loose edges of the file formats, odd encodings. Each test pins one
//! failure that once passed with a panic, `null` in the output or a misleading message.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

fn blockworld(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_blockworld"))
        .args(args)
        .output()
        .expect("the binary runs")
}

fn scene(name: &str) -> String {
    common::root()
        .join("scenes")
        .join(name)
        .to_string_lossy()
        .into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Asserts exit code 2 with a message (no panic) and returns stderr.
fn fails_with_2(o: &Output) -> String {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(2), "stderr: {err}");
    assert!(!err.contains("panicked"), "{err}");
    err
}

fn write(dir: &Path, name: &str, text: &[u8]) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// Regression: every printing command panicked ("failed printing to stdout", exit 101) on a
/// full stdout; it must be an error with exit 2.
#[test]
fn full_stdout_is_an_error_with_exit_2() {
    let full = std::fs::OpenOptions::new()
        .write(true)
        .open("/dev/full")
        .expect("/dev/full exists on Linux");
    let two = scene("two_layer.json");
    let o = Command::new(env!("CARGO_BIN_EXE_blockworld"))
        .args(["score", &two, &two])
        .stdout(full)
        .output()
        .unwrap();
    let err = fails_with_2(&o);
    assert!(err.contains("writing to stdout"), "{err}");
}

/// Regression: a stdout pipe whose reader had gone (`| head -1`) made commands panic; a closed
/// pipe ends the command quietly with exit 0, as Unix tools do.
#[test]
fn closed_stdout_pipe_ends_quietly() {
    let two = scene("two_layer.json");
    for _ in 0..5 {
        let mut child = Command::new(env!("CARGO_BIN_EXE_blockworld"))
            .args(["score", &two, &two])
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        drop(child.stdout.take());
        let o = child.wait_with_output().unwrap();
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(0), "stderr: {err}");
        assert!(err.is_empty(), "{err}");
    }
}
