//! The thesis's data files (Appendix B) and the `view` command end to end: the printed
//! fragment read back, `export --format thesis` read back by `view` and `score`, overlays,
//! and the viewer's errors (exit 2, a message naming the fix, no output file).

mod common;
use common::blockworld;

use blockworld::export::{
    parse_thesis_files, thesis_model_to_scene, ThesisFormatError, Truncation,
};
use blockworld::scene::read_scene;
use std::path::Path;

fn fixture(name: &str) -> String {
    let p = common::root().join("tests/fixtures").join(name);
    std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn appendix_b_fragment_gives_the_samples_first_two_blocks() {
    let (v, c) = (
        fixture("appendix_b_vertices.txt"),
        fixture("appendix_b_connections.txt"),
    );
    let model = parse_thesis_files(&v, &c, ("v", "c"), Truncation::AllowFragment).unwrap();
    assert_eq!(model.vertices_units.len(), 22);
    assert_eq!(
        model.faces.len(),
        14,
        "12 faces of blocks 1-2, 2 of block 3 survive"
    );
    let scene =
        thesis_model_to_scene(&model, "appendix_b", "c", Truncation::AllowFragment).unwrap();
    let sample = read_scene(&common::root().join("scenes/thesis_sample.json")).unwrap();
    assert_eq!(scene.blocks.len(), 2);
    for (got, want) in scene.blocks.iter().zip(&sample.blocks[..2]) {
        assert_eq!(got.block_type.id, want.block_type.id);
        assert!((got.center_mm - want.center_mm).length() < 1e-9);
    }
    // Read strictly, the fragment's count (40) does not match its 22 vertices.
    let strict = parse_thesis_files(&v, &c, ("v", "c"), Truncation::Strict);
    assert!(matches!(
        strict,
        Err(ThesisFormatError::CountMismatch {
            declared: 40,
            found: 22,
            ..
        })
    ));
}

#[test]
fn exported_data_files_are_read_back_by_view_and_score() {
    let tmp = tempfile::tempdir().unwrap();
    let sample = common::root().join("scenes/thesis_sample.json");
    let prefix = tmp.path().join("sample");
    let o = blockworld(["export", s(&sample), "--format", "thesis", "-o", s(&prefix)]);
    common::ok(&o);
    let vertices = std::fs::read_to_string(tmp.path().join("sample_vertices.txt")).unwrap();
    assert_eq!(
        vertices.lines().nth(1),
        Some("40"),
        "5 blocks of 8 vertices"
    );
    // The same bytes again.
    let again = tmp.path().join("again");
    blockworld(["export", s(&sample), "--format", "thesis", "-o", s(&again)]);
    assert_eq!(
        vertices,
        std::fs::read_to_string(tmp.path().join("again_vertices.txt")).unwrap()
    );
    let png = tmp.path().join("v.png");
    let o = blockworld(["view", s(&prefix), "-o", s(&png), "--world"]);
    common::ok(&o);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("5 blocks") && out.contains("  40 "), "{out}");
    // Scoring the data files against themselves: a perfect match.
    let vp = tmp.path().join("sample_vertices.txt");
    let o = blockworld(["score", s(&vp), s(&prefix), "--json"]);
    common::ok(&o);
    let score: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(
        (score["iou"].as_f64().unwrap() - 1.0).abs() < 1e-6,
        "{score}"
    );
    // Against the scene in its own frame the thesis's frame is shifted (x = 0 at the least x):
    // the check can fail.
    let o = blockworld(["score", s(&sample), s(&prefix), "--json"]);
    let score: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(score["iou"].as_f64().unwrap() < 0.9, "{score}");
}

#[test]
fn an_overlay_draws_truth_and_reconstruction_in_two_colours() {
    let tmp = tempfile::tempdir().unwrap();
    let truth = common::root().join("scenes/thesis_sample.json");
    let recon = common::root().join("scenes/two_layer.json");
    let png = tmp.path().join("o.png");
    let o = blockworld([
        "view",
        s(&recon),
        "--overlay",
        s(&truth),
        "-o",
        s(&png),
        "--hidden-lines",
        "remove",
    ]);
    common::ok(&o);
    let img = image::open(&png).unwrap().into_rgb8();
    let count = |c: [u8; 3]| img.pixels().filter(|p| p.0 == c).count();
    assert!(count([30, 90, 220]) > 100, "truth lines in blue");
    assert!(count([220, 40, 40]) > 100, "reconstruction lines in red");
}

#[test]
fn shaded_viewports_and_svg_are_written() {
    let tmp = tempfile::tempdir().unwrap();
    let sample = common::root().join("scenes/thesis_sample.json");
    let png = tmp.path().join("s.png");
    let o = blockworld([
        "view",
        s(&sample),
        "-o",
        s(&png),
        "--shade",
        "--viewports",
        "4",
    ]);
    common::ok(&o);
    let img = image::open(&png).unwrap().into_rgb8();
    let gray_fill = img
        .pixels()
        .filter(|p| p[0] == p[1] && p[1] == p[2] && (60..250).contains(&p[0]))
        .count();
    assert!(
        gray_fill > 10_000,
        "shaded faces fill the viewports: {gray_fill}"
    );
    let svg = tmp.path().join("s.svg");
    let o = blockworld(["view", s(&sample), "-o", s(&svg), "--up", "2,1,3"]);
    common::ok(&o);
    let text = std::fs::read_to_string(&svg).unwrap();
    assert_eq!(text.matches("<line ").count(), 60);
    assert!(text.contains("UP 2.0 1.0 3.0"));
}

#[test]
fn bad_views_exit_2_with_the_fix_and_write_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let sample = common::root().join("scenes/thesis_sample.json");
    let png = tmp.path().join("x.png");
    let cases: [(&[&str], &str); 5] = [
        (&["--from", "22.5,40,15", "--at", "22.5,15,15"], "--up"),
        (&["--view-angle", "180"], "--view-angle"),
        (&["--move-from", "1000"], "--move-from"),
        (&["--from", "1,2"], "--from"),
        (&["--hidden-lines", "maybe"], "--hidden-lines"),
    ];
    for (extra, needle) in cases {
        let mut args = vec!["view", s(&sample), "-o", s(&png)];
        args.extend_from_slice(extra);
        let o = blockworld(&args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{extra:?}: {err}");
        assert!(err.contains(needle), "{extra:?}: {err}");
        assert!(!png.exists());
    }
    let o = blockworld(["view", s(&sample), "-o", s(&tmp.path().join("x.jpg"))]);
    assert_eq!(o.status.code(), Some(2));
    let svg = tmp.path().join("x.svg");
    let o = blockworld(["view", s(&sample), "-o", s(&svg), "--shade"]);
    let err = common::fails_with_2(&o);
    assert!(err.contains(".png") && !svg.exists(), "{err}");
    // A declined reconstruction has no blocks to look at.
    let declined = tmp.path().join("declined.json");
    std::fs::write(
        &declined,
        r#"{"name": "d", "blocks": [], "status": "unsupported", "reason": "overhang"}"#,
    )
    .unwrap();
    let o = blockworld(["view", s(&declined), "-o", s(&png)]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        String::from_utf8_lossy(&o.stderr).contains("no blocks"),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let frag = common::root().join("tests/fixtures/appendix_b");
    let o = blockworld(["view", s(&frag), "-o", s(&png)]);
    let err = common::fails_with_2(&o);
    assert!(err.contains("declares 40"), "{err}");
}
