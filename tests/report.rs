//! `blockworld recognize-dataset` and `blockworld report` end to end on a small generated
//! dataset: the site's bytes do not depend on the number of threads, every scene has its page,
//! pictures and models, bad input exits 2 naming the file and leaves an earlier site as it was,
//! and headless Chromium (the Debian package, driven by playwright-core from
//! tests/browser/check_report.js) opens the site from the file system: no console errors, every
//! link and image resolves, the filters change the visible count, the overlay toggles change
//! the picture; and the same check fails on a site with one picture missing.
//!
//! Needs the renderer (skips without it unless `BLOCKWORLD_REQUIRE_GPU` is set). The browser
//! tests need /usr/bin/chromium and target/playwright (`make setup` installs both) and skip
//! without them unless CI or `BLOCKWORLD_REQUIRE_BROWSER` is set, as `make test` does.

mod common;
use common::{blockworld, command, fails_with_2, ok, renderer_available, root};

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

/// Scenes in the test dataset: every default family once, the first one twice.
const SCENES: usize = 12;

/// A generated dataset (12 scenes, four 256 x 240 views, glTF) and its recognitions, made once
/// per test binary; `None` without a renderer.
fn fixture() -> Option<&'static (tempfile::TempDir, PathBuf, PathBuf)> {
    static FIXTURE: OnceLock<Option<(tempfile::TempDir, PathBuf, PathBuf)>> = OnceLock::new();
    FIXTURE
        .get_or_init(|| {
            if !renderer_available() {
                return None;
            }
            let tmp = tempfile::tempdir().unwrap();
            let ds = tmp.path().join("ds");
            let rec = tmp.path().join("rec");
            ok(blockworld(
                [
                    "generate", "--count", "12", "--seed", "7", "--jobs", "1", "--size", "256x240",
                    "--gltf", "-o",
                ]
                .iter()
                .map(|s| s.to_string())
                .chain([ds.display().to_string()]),
            ));
            ok(blockworld([
                "recognize-dataset".as_ref(),
                ds.as_os_str(),
                "-o".as_ref(),
                rec.as_os_str(),
            ]));
            Some((tmp, ds, rec))
        })
        .as_ref()
}

/// Every file under `dir` (relative path -> bytes).
fn tree(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut out = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else {
                out.insert(
                    p.strip_prefix(dir).unwrap().to_path_buf(),
                    std::fs::read(&p).unwrap(),
                );
            }
        }
    }
    out
}

fn with_threads(threads: &str, args: &[&Path]) -> std::process::Output {
    command()
        .env("RAYON_NUM_THREADS", threads)
        .args(args)
        .output()
        .unwrap()
}

/// Runs `report DS --recognitions REC -o SITE`.
fn run_report(ds: &Path, rec: &Path, site: &Path) -> std::process::Output {
    blockworld([
        "report".as_ref(),
        ds.as_os_str(),
        "--recognitions".as_ref(),
        rec.as_os_str(),
        "-o".as_ref(),
        site.as_os_str(),
    ])
}

fn report(ds: &Path, rec: &Path, site: &Path) -> String {
    ok(run_report(ds, rec, site))
}

#[test]
fn recognitions_and_site_have_the_same_bytes_whatever_the_threads() {
    let Some((tmp, ds, rec)) = fixture() else {
        return;
    };
    let rec1 = tmp.path().join("rec1");
    ok(with_threads(
        "1",
        &[Path::new("recognize-dataset"), ds, Path::new("-o"), &rec1],
    ));
    assert_eq!(
        tree(rec),
        tree(&rec1),
        "recognize-dataset: 1 thread against the default"
    );
    assert_eq!(
        tree(rec).len(),
        2 * SCENES + 1,
        "<id>.json and <id>.views.json per scene, and recognitions.json"
    );
    let (a, b) = (tmp.path().join("site_a"), tmp.path().join("site_b"));
    let args = |site: &Path| -> Vec<PathBuf> {
        [
            "report",
            &ds.display().to_string(),
            "--recognitions",
            &rec.display().to_string(),
            "-o",
            &site.display().to_string(),
        ]
        .iter()
        .map(PathBuf::from)
        .collect()
    };
    let (args_a, args_b) = (args(&a), args(&b));
    ok(with_threads(
        "1",
        &args_a.iter().map(PathBuf::as_path).collect::<Vec<_>>(),
    ));
    ok(with_threads(
        "2",
        &args_b.iter().map(PathBuf::as_path).collect::<Vec<_>>(),
    ));
    let first = tree(&a);
    assert_eq!(first, tree(&b), "report: 1 thread against 2");
    report(ds, rec, &a);
    assert_eq!(first, tree(&a), "a report built again over an earlier one");
}

#[test]
fn every_scene_has_its_page_pictures_answer_and_model() {
    let Some((tmp, ds, rec)) = fixture() else {
        return;
    };
    let site = tmp.path().join("site_files");
    let out = report(ds, rec, &site);
    assert!(
        out.contains(&format!("{SCENES} scenes ({SCENES} recognized)")),
        "{out}"
    );
    let scenes_js = std::fs::read_to_string(site.join("scenes.js")).unwrap();
    assert_eq!(
        scenes_js.lines().filter(|l| l.starts_with("[\"s0")).count(),
        SCENES
    );
    for k in 0..SCENES {
        let dir = site.join(format!("s{k:06}"));
        for v in ["ne", "se", "sw", "nw"] {
            let depth = image::open(dir.join(format!("depth_{v}.png"))).unwrap();
            assert!(
                matches!(depth, image::DynamicImage::ImageLuma8(_)),
                "8-bit depth for browsers"
            );
            let ids = image::open(dir.join(format!("ids_{v}.png"))).unwrap();
            assert!(
                matches!(ids, image::DynamicImage::ImageRgb8(_)),
                "coloured ids"
            );
            assert!(dir.join(format!("view_{v}.png")).is_file());
        }
        let page = std::fs::read_to_string(dir.join("index.html")).unwrap();
        for link in [
            "href=\"scene.glb\"",
            "href=\"recon.json\"",
            "class=\"ov ov-answer\"",
            "class=\"ov ov-codes\"",
        ] {
            assert!(page.contains(link), "s{k:06}: no {link}");
        }
    }
    let index = std::fs::read_to_string(site.join("index.html")).unwrap();
    assert!(index.contains("<table class=\"accuracy\">") && index.contains("<tr class=\"all\">"));
}

#[test]
fn bad_input_exits_2_naming_the_file_and_keeps_the_earlier_site() {
    let Some((tmp, ds, rec)) = fixture() else {
        return;
    };
    let site = tmp.path().join("site_kept");
    report(ds, rec, &site);
    let before = tree(&site);
    let no_manifest = tmp.path().join("empty");
    std::fs::create_dir_all(&no_manifest).unwrap();
    let run = run_report;
    let err = fails_with_2(&run(&no_manifest, rec, &site));
    assert!(
        err.contains("empty/manifest.jsonl") && err.contains("blockworld generate"),
        "{err}"
    );
    let err = fails_with_2(&run(ds, &no_manifest, &site));
    assert!(
        err.contains("empty/recognitions.json") && err.contains("recognize-dataset"),
        "{err}"
    );
    let stray = tmp.path().join("stray");
    std::fs::create_dir_all(&stray).unwrap();
    std::fs::write(stray.join("notes.txt"), "mine").unwrap();
    let err = fails_with_2(&run(ds, rec, &stray));
    assert!(err.contains("not an earlier report"), "{err}");
    assert_eq!(
        std::fs::read_to_string(stray.join("notes.txt")).unwrap(),
        "mine"
    );
    // A damaged depth picture half way through: the earlier site stays as it was.
    let broken = tmp.path().join("ds_broken");
    copy_tree(ds, &broken);
    std::fs::write(broken.join("s000005/depth_sw.png"), b"not a png").unwrap();
    let err = fails_with_2(&run(&broken, rec, &site));
    assert!(err.contains("s000005/depth_sw.png"), "{err}");
    assert_eq!(before, tree(&site), "the earlier site is untouched");
    let leftovers: Vec<_> = std::fs::read_dir(tmp.path())
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().contains(".tmp-"))
        .collect();
    assert!(
        leftovers.is_empty(),
        "temporary folders left: {leftovers:?}"
    );
}

fn copy_tree(from: &Path, to: &Path) {
    for (rel, bytes) in tree(from) {
        let p = to.join(rel);
        std::fs::create_dir_all(p.parent().unwrap()).unwrap();
        std::fs::write(p, bytes).unwrap();
    }
}

/// `node` and the check script's tools, or `None` after a loud skip; a failure in CI or with
/// `BLOCKWORLD_REQUIRE_BROWSER` set.
fn browser_tools() -> Option<()> {
    let chromium = Path::new("/usr/bin/chromium");
    let playwright = root().join("target/playwright/node_modules/playwright-core/package.json");
    let node = Command::new("node")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    if chromium.is_file() && playwright.is_file() && node {
        return Some(());
    }
    let what = format!(
        "{} {}, {} {}, node {}",
        chromium.display(),
        chromium.is_file(),
        playwright.display(),
        playwright.is_file(),
        node
    );
    if std::env::var_os("CI").is_some() || std::env::var_os("BLOCKWORLD_REQUIRE_BROWSER").is_some()
    {
        panic!(
            "the browser check needs chromium, playwright-core and node ({what}): run make setup"
        );
    }
    eprintln!("SKIPPED: no headless browser ({what}); make setup installs it");
    None
}

/// Runs tests/browser/check_report.js on `site`: its exit code, the JSON it found, its stderr.
fn check_in_browser(site: &Path) -> (Option<i32>, serde_json::Value, String) {
    let out = Command::new("node")
        .arg(root().join("tests/browser/check_report.js"))
        .arg(site)
        .output()
        .expect("runs node");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let found = stdout
        .lines()
        .last()
        .and_then(|l| serde_json::from_str(l).ok());
    (
        out.status.code(),
        found.unwrap_or_default(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// A fresh report of the fixture in `name`, when the renderer and the browser are there.
fn site_for_browser(name: &str) -> Option<PathBuf> {
    let (tmp, ds, rec) = fixture()?;
    browser_tools()?;
    let site = tmp.path().join(name);
    report(ds, rec, &site);
    Some(site)
}

#[test]
fn chromium_opens_the_site_filters_and_toggles() {
    let Some(site) = site_for_browser("site_browser") else {
        return;
    };
    let (code, found, err) = check_in_browser(&site);
    assert_eq!(code, Some(0), "{err}");
    assert_eq!(found["pages"], SCENES, "{found}");
    assert_eq!(found["filters"]["all"], SCENES, "{found}");
    let counts = found["filters"]["counts"].as_object().unwrap();
    assert!(
        counts.values().any(|n| n.as_u64() != Some(SCENES as u64)),
        "{found}"
    );
    for overlay in ["truth", "codes", "vision", "answer", "ids", "depth"] {
        assert!(
            found["toggles"][overlay].as_u64().unwrap_or(0) > 0,
            "{overlay}: {found}"
        );
    }
}

/// `scenes.js` without each row's last two fields, the thumbnail's width and height.
fn without_thumbnail_sizes(js: &str) -> String {
    js.lines()
        .map(
            |l| match l.strip_prefix("[\"s").and_then(|r| r.strip_suffix("],")) {
                Some(row) => {
                    let fields: Vec<&str> = row.split(',').collect();
                    format!("[\"s{}],\n", fields[..fields.len() - 2].join(","))
                }
                None => format!("{l}\n"),
            },
        )
        .collect()
}

#[test]
fn chromium_check_fails_on_a_missing_picture_and_unsized_thumbnails() {
    let Some(site) = site_for_browser("site_broken") else {
        return;
    };
    std::fs::remove_file(site.join("s000003/view_se.png")).unwrap();
    let js = std::fs::read_to_string(site.join("scenes.js")).unwrap();
    let stripped = without_thumbnail_sizes(&js);
    assert!(
        stripped.len() < js.len() && stripped.contains("\"ne\"],"),
        "{stripped}"
    );
    std::fs::write(site.join("scenes.js"), stripped).unwrap();
    let (code, _, err) = check_in_browser(&site);
    assert_eq!(code, Some(1), "{err}");
    assert!(
        err.contains("broken link or image") && err.contains("s000003/view_se.png"),
        "{err}"
    );
    assert!(
        err.contains(&format!("{SCENES} thumbnails have no height")),
        "{err}"
    );
}
