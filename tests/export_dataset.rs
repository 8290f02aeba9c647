//! `blockworld export-dataset` end to end (docs/wireframe.md "Wireframe datasets"): each format is read
//! back by a small reader written from the format's published description (plain
//! `serde_json::Value`, not blockworld's writer), and checked against the dataset's own
//! `lines_<view>.json` (read raw as well), its pictures and its manifest.
//!
//! Needs the renderer (it generates a small rendered dataset); skips loudly without one unless
//! `BLOCKWORLD_REQUIRE_GPU` is set.

mod common;
use common::{blockworld, ok, renderer_available};

use serde_json::Value;
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::Output;
use tempfile::TempDir;

/// A temporary folder and its `ds/`: `count` rendered scenes of seed `seed` (several families,
/// 4 views each) generated with one worker, at `size` (`WxH`) or the default picture size.
/// `None` after a loud skip when there is no renderer.
fn rendered_dataset(count: u32, seed: u32, size: Option<&str>) -> Option<(TempDir, PathBuf)> {
    if !renderer_available() {
        return None;
    }
    let tmp = tempfile::tempdir().unwrap();
    let ds = tmp.path().join("ds");
    let (count, seed) = (count.to_string(), seed.to_string());
    let mut args = vec![
        "generate", "--count", &count, "--seed", &seed, "--jobs", "1",
    ];
    if let Some(size) = size {
        args.extend(["--size", size]);
    }
    ok(blockworld(args.iter().chain(&["-o", ds.to_str().unwrap()])));
    Some((tmp, ds))
}

/// An export with half the scenes for training.
fn export(dataset: &Path, format: &str, out: &Path, extra: &[&str]) -> Output {
    let flags: Vec<&str> = ["--split", "0.5"].iter().chain(extra).copied().collect();
    common::export_dataset(dataset, format, out, &flags)
}

fn read_json(path: &Path) -> Value {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_str(&text).unwrap()
}

fn xy(v: &Value) -> [f64; 2] {
    [v[0].as_f64().unwrap(), v[1].as_f64().unwrap()]
}

/// One exported picture as any of the three formats describes it.
#[derive(Debug)]
struct Labelled {
    picture: PathBuf,
    train: bool,
    width: f64,
    height: f64,
    lines: Vec<[[f64; 2]; 2]>,
    /// Junctions where the format lists them (HAWP); line ends otherwise.
    junctions: Vec<[f64; 2]>,
    kinds: Vec<String>,
    /// Per line, whether each end is marked as a border clip point.
    border: Vec<[bool; 2]>,
    /// How far apart two coinciding line ends may be: 0 where the format stores ends as
    /// coordinates; LETR stores `[x, y, dx, dy]` and `x + dx` cannot always hit the shared
    /// coordinate in f64, so 1e-9 px there.
    same_point_tol_px: f64,
}

fn kinds(v: &Value) -> Vec<String> {
    v.as_array()
        .map(|a| {
            a.iter()
                .map(|k| k.as_str().unwrap_or("").to_string())
                .collect()
        })
        .unwrap_or_default()
}

fn common(root: &Path, dir: &str, item: &Value, train: bool, name_key: &str) -> Labelled {
    Labelled {
        picture: root.join(dir).join(item[name_key].as_str().unwrap()),
        train,
        width: item["width"].as_f64().unwrap(),
        height: item["height"].as_f64().unwrap(),
        lines: Vec::new(),
        junctions: Vec::new(),
        kinds: kinds(&item["line_kind"]),
        border: Vec::new(),
        same_point_tol_px: 0.0,
    }
}

/// HAWP: train items `{filename, height, width, junctions, edges_positive, edges_negative}`,
/// test items `{filename, height, width, lines, junc}`, pictures in `images/`.
fn read_hawp(root: &Path) -> Vec<Labelled> {
    let mut out = Vec::new();
    for item in read_json(&root.join("train.json")).as_array().unwrap() {
        let mut l = common(root, "images", item, true, "filename");
        let junctions: Vec<[f64; 2]> = item["junctions"]
            .as_array()
            .unwrap()
            .iter()
            .map(xy)
            .collect();
        let types = kinds(&item["junction_type"]);
        let mut positive = BTreeSet::new();
        for e in item["edges_positive"].as_array().unwrap() {
            let (a, b) = (
                e[0].as_u64().unwrap() as usize,
                e[1].as_u64().unwrap() as usize,
            );
            l.lines.push([junctions[a], junctions[b]]);
            l.border.push([types[a] == "border", types[b] == "border"]);
            positive.insert([a.min(b), a.max(b)]);
        }
        // Negatives: junction pairs that are no line.
        for e in item["edges_negative"].as_array().unwrap() {
            let pair = [0, 1].map(|k| e[k].as_u64().unwrap() as usize);
            assert!(pair[0] < pair[1] && pair[1] < junctions.len(), "{e}");
            assert!(!positive.contains(&pair), "negative {e} is a line");
        }
        l.junctions = junctions;
        out.push(l);
    }
    for item in read_json(&root.join("test.json")).as_array().unwrap() {
        let mut l = common(root, "images", item, false, "filename");
        l.lines = lines4(&item["lines"]);
        l.junctions = item["junc"].as_array().unwrap().iter().map(xy).collect();
        let types = kinds(&item["junction_type"]);
        let is_border = |p: [f64; 2]| {
            let j = l.junctions.iter().position(|j| *j == p).unwrap();
            types[j] == "border"
        };
        l.border = l.lines.iter().map(|e| e.map(is_border)).collect();
        out.push(l);
    }
    out
}

fn flags(v: &Value) -> [bool; 2] {
    [v[0].as_bool().unwrap(), v[1].as_bool().unwrap()]
}

fn line4(v: &Value) -> [[f64; 2]; 2] {
    let c: Vec<f64> = v
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c.as_f64().unwrap())
        .collect();
    assert_eq!(c.len(), 4, "{v}");
    [[c[0], c[1]], [c[2], c[3]]]
}

/// A list of `[x1, y1, x2, y2]` lines.
fn lines4(v: &Value) -> Vec<[[f64; 2]; 2]> {
    v.as_array().unwrap().iter().map(line4).collect()
}

fn ends_as_junctions(l: &mut Labelled) {
    l.junctions = l.lines.iter().flatten().copied().collect();
}

/// L-CNN: `train.json` / `valid.json`, lists of `{filename, height, width, lines}` with lines as
/// `[x1, y1, x2, y2]`, pictures in `images/`.
fn read_lcnn(root: &Path) -> Vec<Labelled> {
    let mut out = Vec::new();
    for (file, train) in [("train.json", true), ("valid.json", false)] {
        for item in read_json(&root.join(file)).as_array().unwrap() {
            let mut l = common(root, "images", item, train, "filename");
            l.lines = lines4(&item["lines"]);
            l.border = item["line_border"]
                .as_array()
                .unwrap()
                .iter()
                .map(flags)
                .collect();
            ends_as_junctions(&mut l);
            out.push(l);
        }
    }
    out
}

/// LETR: COCO `annotations/lines_{train2017,val2017}.json` with `images`, `annotations`
/// (`line: [x, y, dx, dy]`, `category_id` 0) and `categories`; pictures in `train2017/` and
/// `val2017/`.
fn read_letr(root: &Path) -> Vec<Labelled> {
    let mut out = Vec::new();
    let mut ann_ids = BTreeSet::new();
    for (split, train) in [("train2017", true), ("val2017", false)] {
        let doc = read_json(&root.join(format!("annotations/lines_{split}.json")));
        assert!(doc["categories"]
            .as_array()
            .unwrap()
            .iter()
            .any(|c| c["id"] == 0));
        let mut by_id: BTreeMap<u64, Labelled> = BTreeMap::new();
        for img in doc["images"].as_array().unwrap() {
            let mut l = common(root, split, img, train, "file_name");
            l.same_point_tol_px = 1e-9;
            assert!(
                by_id.insert(img["id"].as_u64().unwrap(), l).is_none(),
                "{img}"
            );
        }
        for ann in doc["annotations"].as_array().unwrap() {
            assert_eq!(ann["category_id"], 0);
            assert!(ann_ids.insert(ann["id"].as_u64().unwrap()), "{ann}");
            let [x, y, dx, dy] = [0, 1, 2, 3].map(|k| ann["line"][k].as_f64().unwrap());
            // LETR reads `area`, and its crop and flips take the left end first (the upper
            // one on a vertical line).
            assert!(ann["area"].is_number(), "{ann}");
            assert!(dx > 0.0 || (dx == 0.0 && dy >= 0.0), "{ann}");
            let l = by_id.get_mut(&ann["image_id"].as_u64().unwrap()).unwrap();
            l.lines.push([[x, y], [x + dx, y + dy]]);
            l.border.push(flags(&ann["border_ends"]));
            l.kinds.push(ann["line_kind"].as_str().unwrap().to_string());
        }
        for mut l in by_id.into_values() {
            ends_as_junctions(&mut l);
            out.push(l);
        }
    }
    out
}

/// Distance (px) from `p` to the segment `s`, in the exported formats' plain arrays.
fn distance_to_segment(p: [f64; 2], s: [[f64; 2]; 2]) -> f64 {
    common::distance_to_segment(p.into(), s[0].into(), s[1].into())
}

fn close(a: [f64; 2], b: [f64; 2], tol: f64) -> bool {
    (a[0] - b[0]).abs() <= tol && (a[1] - b[1]).abs() <= tol
}

/// `scene id`, `view` of a picture named `<id>_<view>.png`.
fn scene_and_view(picture: &Path) -> (String, String) {
    let stem = picture.file_stem().unwrap().to_str().unwrap();
    let (id, view) = stem.rsplit_once('_').unwrap();
    (id.to_string(), view.to_string())
}

/// The drawing's lines in raster px (y down) when `flip`, or as written (y up) otherwise.
fn drawing_lines(dataset: &Path, picture: &Path, height: f64, flip: bool) -> Vec<[[f64; 2]; 2]> {
    let (id, view) = scene_and_view(picture);
    let d = read_json(&dataset.join(id).join(format!("lines_{view}.json")));
    let points: Vec<[f64; 2]> = d["points"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| {
            let [x, y] = xy(p);
            [x, if flip { height - y } else { y }]
        })
        .collect();
    d["lines"]
        .as_array()
        .unwrap()
        .iter()
        .map(|l| {
            [
                points[l[0].as_u64().unwrap() as usize],
                points[l[1].as_u64().unwrap() as usize],
            ]
        })
        .collect()
}

/// Share of exported lines that coincide (both ends within 0.01 px) with a drawing line.
fn matched_share(exported: &[[[f64; 2]; 2]], drawing: &[[[f64; 2]; 2]]) -> f64 {
    let hit = exported
        .iter()
        .filter(|e| {
            drawing.iter().any(|d| {
                (close(e[0], d[0], 0.01) && close(e[1], d[1], 0.01))
                    || (close(e[0], d[1], 0.01) && close(e[1], d[0], 0.01))
            })
        })
        .count();
    hit as f64 / exported.len().max(1) as f64
}

/// Local contrast (3x3 max - min) of the picture around raster point `p`.
fn contrast(img: &image::GrayImage, p: [f64; 2]) -> u8 {
    let (cx, cy) = (p[0].floor() as i64, p[1].floor() as i64);
    let mut lo = 255u8;
    let mut hi = 0u8;
    for y in cy - 1..=cy + 1 {
        for x in cx - 1..=cx + 1 {
            if x >= 0 && y >= 0 && (x as u32) < img.width() && (y as u32) < img.height() {
                let v = img.get_pixel(x as u32, y as u32).0[0];
                lo = lo.min(v);
                hi = hi.max(v);
            }
        }
    }
    hi.saturating_sub(lo)
}

/// Share of boundary and convex lines (which always separate differently lit regions) whose
/// midpoint sits on an edge of the picture, with the lines' y taken as given (`flip` false) or
/// mirrored (`flip` true, the mistake this catches).
fn lines_on_picture_edges(set: &[Labelled], flip: bool) -> f64 {
    let (mut on, mut all) = (0, 0);
    for l in set {
        let img = image::open(&l.picture).unwrap().to_luma8();
        for (line, kind) in l.lines.iter().zip(&l.kinds) {
            if kind != "boundary" && kind != "convex" {
                continue;
            }
            let mut mid = [
                (line[0][0] + line[1][0]) / 2.0,
                (line[0][1] + line[1][1]) / 2.0,
            ];
            if flip {
                mid[1] = l.height - mid[1];
            }
            all += 1;
            on += usize::from(contrast(&img, mid) >= 10);
        }
    }
    on as f64 / all.max(1) as f64
}

/// Every check of the brief on one read-back export.
fn check_export(dataset: &Path, set: &[Labelled], rgb: bool) {
    assert!(!set.is_empty());
    let manifest_ids: BTreeSet<String> = std::fs::read_to_string(dataset.join("manifest.jsonl"))
        .unwrap()
        .lines()
        .map(|l| {
            serde_json::from_str::<Value>(l).unwrap()["id"]
                .as_str()
                .unwrap()
                .to_string()
        })
        .collect();
    let mut side_of: BTreeMap<String, bool> = BTreeMap::new();
    for l in set {
        // Pictures exist, have the stated size and the asked channel count.
        let img = image::open(&l.picture).unwrap();
        assert_eq!(
            (img.width() as f64, img.height() as f64),
            (l.width, l.height)
        );
        assert_eq!(
            img.color().channel_count(),
            if rgb { 3 } else { 1 },
            "{:?}",
            l.picture
        );
        assert_eq!(l.kinds.len(), l.lines.len());
        assert_eq!(l.border.len(), l.lines.len());
        // Split by scene: all views of a scene on one side.
        let (id, _) = scene_and_view(&l.picture);
        assert_eq!(
            *side_of.entry(id).or_insert(l.train),
            l.train,
            "{:?}",
            l.picture
        );
        check_geometry(dataset, l);
    }
    assert_eq!(
        side_of.keys().cloned().collect::<BTreeSet<_>>(),
        manifest_ids
    );
    assert!(
        side_of.values().any(|t| *t) && side_of.values().any(|t| !*t),
        "{side_of:?}"
    );
    assert_eq!(set.len(), manifest_ids.len() * 4);
}

fn check_geometry(dataset: &Path, l: &Labelled) {
    let inside = |p: [f64; 2]| p[0] >= 0.0 && p[1] >= 0.0 && p[0] <= l.width && p[1] <= l.height;
    for j in &l.junctions {
        assert!(inside(*j), "{j:?} outside {:?}", l.picture);
        let on = l.lines.iter().any(|s| distance_to_segment(*j, *s) <= 0.5);
        assert!(
            on,
            "junction {j:?} of {:?} lies on none of its lines",
            l.picture
        );
    }
    // Junctions that coincide share one exact coordinate.
    let ends: Vec<[f64; 2]> = l.lines.iter().flatten().copied().collect();
    for a in &ends {
        for b in &ends {
            let same = close(*a, *b, l.same_point_tol_px);
            assert!(
                !close(*a, *b, 0.01) || same,
                "{a:?} ~ {b:?} in {:?}",
                l.picture
            );
        }
        assert!(l.junctions.iter().any(|j| close(*a, *j, 0.5)), "{a:?}");
    }
    // Every exported line is a drawing line after the y flip (or a clipped piece of one).
    let drawing = drawing_lines(dataset, &l.picture, l.height, true);
    for e in &l.lines {
        let hit = drawing.iter().any(|d| {
            let on = distance_to_segment(e[0], *d) <= 0.5 && distance_to_segment(e[1], *d) <= 0.5;
            let end_ok = |p: [f64; 2]| {
                close(p, d[0], 0.01)
                    || close(p, d[1], 0.01)
                    || p[0] == 0.0
                    || p[1] == 0.0
                    || p[0] == l.width
                    || p[1] == l.height
            };
            on && end_ok(e[0]) && end_ok(e[1])
        });
        assert!(hit, "line {e:?} of {:?} is no drawing line", l.picture);
    }
    // And every drawing line inside the picture is exported.
    let inside_lines = drawing
        .iter()
        .filter(|d| inside(d[0]) && inside(d[1]))
        .count();
    assert!(l.lines.len() >= inside_lines, "{:?}", l.picture);
}

#[test]
fn every_format_reads_back_flipped_split_by_scene_and_on_the_drawing() {
    let Some((tmp, ds)) = rendered_dataset(8, 5, Some("200x160")) else {
        return;
    };
    for (format, reader, rgb) in [
        ("hawp", read_hawp as fn(&Path) -> Vec<Labelled>, true),
        ("lcnn", read_lcnn, false),
        ("letr", read_letr, false),
    ] {
        let out = tmp.path().join(format);
        let extra: &[&str] = if rgb { &["--rgb"] } else { &[] };
        ok(export(&ds, format, &out, extra));
        let set = reader(&out);
        check_export(&ds, &set, rgb);
        // The y flip against the pictures: lines sit on picture edges, and mirrored they would
        // not (the scenes are not symmetric top to bottom, so the check can fail).
        let right = lines_on_picture_edges(&set, false);
        let mirrored = lines_on_picture_edges(&set, true);
        eprintln!("{format}: {right:.3} of lines on picture edges, {mirrored:.3} mirrored");
        assert!(right >= 0.95, "{format}: {right} of lines on picture edges");
        assert!(mirrored <= 0.6, "{format}: mirrored {mirrored}");
        // And against the drawing: unflipped, few exported lines are drawing lines.
        let unflipped: f64 = set
            .iter()
            .map(|l| matched_share(&l.lines, &drawing_lines(&ds, &l.picture, l.height, false)))
            .sum::<f64>()
            / set.len() as f64;
        eprintln!("{format}: {unflipped:.3} of lines on the drawing unflipped");
        assert!(unflipped < 0.5, "{format}: {unflipped}");
    }
}

#[test]
fn a_damaged_dataset_is_refused_and_a_rerun_resumes_to_the_same_bytes_on_any_jobs() {
    let Some((tmp, ds)) = rendered_dataset(3, 5, Some("200x160")) else {
        return;
    };
    let out = tmp.path().join("hawp");
    ok(export(&ds, "hawp", &out, &[]));
    let train = std::fs::read(out.join("train.json")).unwrap();
    let test = std::fs::read(out.join("test.json")).unwrap();
    // One thread or four (the default): the same bytes.
    let serial = tmp.path().join("serial");
    ok(export(&ds, "hawp", &serial, &["--jobs", "1"]));
    assert_eq!(std::fs::read(serial.join("train.json")).unwrap(), train);
    assert_eq!(std::fs::read(serial.join("test.json")).unwrap(), test);
    // Interrupted: a scene's part file and a picture gone, the annotation files not written.
    std::fs::remove_file(out.join(".parts/s000001.json")).unwrap();
    std::fs::remove_file(out.join("images/s000001_se.png")).unwrap();
    std::fs::remove_file(out.join("train.json")).unwrap();
    // And a picture of a finished scene damaged: its scene is redone too.
    let damaged = out.join("images/s000002_ne.png");
    let picture = std::fs::read(&damaged).unwrap();
    std::fs::write(&damaged, &picture[..picture.len() / 2]).unwrap();
    let stdout = ok(export(&ds, "hawp", &out, &[]));
    assert!(stdout.contains("(1 kept from an earlier run)"), "{stdout}");
    assert_eq!(std::fs::read(&damaged).unwrap(), picture);
    assert_eq!(std::fs::read(out.join("train.json")).unwrap(), train);
    assert_eq!(std::fs::read(out.join("test.json")).unwrap(), test);
    assert!(out.join("images/s000001_se.png").exists());
    // Other options into the same folder are refused.
    let refused = export(&ds, "hawp", &out, &["--rgb"]);
    let err = common::fails_with_2(&refused);
    assert!(err.contains("other options"), "{err}");
    // A file that fails its manifest hash is refused, naming it; nothing is written.
    let lines = ds.join("s000002/lines_nw.json");
    let mut text = std::fs::read_to_string(&lines).unwrap();
    text = text.replacen('1', "2", 1);
    std::fs::write(&lines, text).unwrap();
    let fresh = tmp.path().join("fresh");
    let out2 = export(&ds, "lcnn", &fresh, &[]);
    let err = String::from_utf8_lossy(&out2.stderr);
    assert_eq!(out2.status.code(), Some(2), "{err}");
    assert!(
        err.contains("lines_nw.json") && err.contains("does not match"),
        "{err}"
    );
    assert!(!fresh.join("train.json").exists() && !fresh.join("valid.json").exists());
}

/// Every temporary file (`.<name>.tmp.<pid>.<random>`) under `dir`, as paths relative to it.
fn temporaries(dir: &Path) -> Vec<PathBuf> {
    let mut found = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap().flatten() {
            let name = e.file_name().to_string_lossy().into_owned();
            if e.path().is_dir() {
                stack.push(e.path());
            } else if name.starts_with('.') && name.contains(".tmp.") {
                found.push(e.path().strip_prefix(dir).unwrap().to_path_buf());
            }
        }
    }
    found.sort();
    found
}

/// Regression: a resumed export kept the empty temporary files an export killed with SIGKILL
/// left beside its pictures and part files (its real files were byte-identical, its tree not);
/// the resume removes them as `generate` does, and the tree equals an uninterrupted export's.
#[test]
fn a_resumed_export_removes_a_killed_runs_temporary_files() {
    let Some((tmp, ds)) = rendered_dataset(2, 5, Some("200x160")) else {
        return;
    };
    let out = tmp.path().join("hawp");
    ok(export(&ds, "hawp", &out, &[]));
    // What a run killed mid-write leaves: empty temporaries of a picture, a part file, an
    // annotation file and the stamp, and the scene's part file not yet renamed into place.
    let left = [
        "images/.s000001_ne.png.tmp.4242.00000000deadbeef",
        ".parts/.s000001.json.tmp.4242.0000000000c0ffee",
        ".train.json.tmp.4242.0000000000000001",
        ".export.json.tmp.4242.0000000000000002",
    ];
    for name in left {
        std::fs::write(out.join(name), b"").unwrap();
    }
    std::fs::remove_file(out.join(".parts/s000001.json")).unwrap();
    assert_eq!(temporaries(&out).len(), left.len());
    let stdout = ok(export(&ds, "hawp", &out, &[]));
    assert!(stdout.contains("(1 kept from an earlier run)"), "{stdout}");
    assert_eq!(temporaries(&out), Vec::<PathBuf>::new());
    assert!(out.join(".parts/s000001.json").exists());
    assert!(
        !out.join(".lock").exists(),
        "the lock file is removed when done"
    );
}

/// Regression: export-dataset took no lock, so two exports into one OUT could delete each
/// other's temporary files; a second writer is refused with exit 2, naming the holder and the
/// fix, and writes nothing.
#[test]
fn a_second_export_into_the_same_folder_is_refused() {
    let Some((tmp, ds)) = rendered_dataset(1, 5, Some("200x160")) else {
        return;
    };
    let out = tmp.path().join("lcnn");
    std::fs::create_dir_all(&out).unwrap();
    // Another writer holds the folder's lock (flock(1) takes it as `generate` and an export
    // do) until the file `held` is removed.
    let held = tmp.path().join("held");
    let script = format!(
        "touch {0}; while [ -e {0} ]; do sleep 0.05; done",
        held.display()
    );
    let mut holder = std::process::Command::new("flock")
        .args(["--exclusive", out.join(".lock").to_str().unwrap()])
        .args(["sh", "-c", &script])
        .spawn()
        .expect("flock(1) from util-linux");
    while !held.exists() {
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    let refused = export(&ds, "lcnn", &out, &[]);
    std::fs::remove_file(&held).unwrap();
    assert!(holder.wait().unwrap().success());
    let err = String::from_utf8_lossy(&refused.stderr);
    assert_eq!(refused.status.code(), Some(2), "{err}");
    assert!(
        err.contains("is locked") && err.contains("another -o"),
        "{err}"
    );
    assert!(!out.join("train.json").exists() && !out.join("export.json").exists());
    // With the holder gone the same export runs.
    ok(export(&ds, "lcnn", &out, &[]));
}

/// Cuts every view of a generated dataset to the window `x0..x0 + w`, raster rows `0..h` of its
/// picture: the same orthographic camera with a smaller picture, whose blocks now run off it.
/// The picture is cropped, the drawing's points moved by `(-x0, -(H - h))` (picture px, y up,
/// docs/formats.md "Conventions"), and the manifest's hashes of both updated.
fn cut_views(dataset: &Path, x0: u32, w: u32, h: u32) {
    let manifest_path = dataset.join("manifest.jsonl");
    let mut manifest = String::new();
    for line in std::fs::read_to_string(&manifest_path).unwrap().lines() {
        let mut entry: Value = serde_json::from_str(line).unwrap();
        let dir = dataset.join(entry["id"].as_str().unwrap());
        for view in ["ne", "se", "sw", "nw"] {
            let picture = dir.join(format!("view_{view}.png"));
            let full = image::open(&picture).unwrap().to_luma8();
            let shift_y = f64::from(full.height() - h);
            let cut = image::imageops::crop_imm(&full, x0, 0, w, h).to_image();
            cut.save(&picture).unwrap();
            let lines = dir.join(format!("lines_{view}.json"));
            let mut d = read_json(&lines);
            for p in d["points"].as_array_mut().unwrap() {
                let [x, y] = xy(p);
                *p = serde_json::json!([x - f64::from(x0), y - shift_y]);
            }
            std::fs::write(&lines, d.to_string()).unwrap();
            for file in [picture, lines] {
                let name = file.file_name().unwrap().to_str().unwrap().to_string();
                let sha = blockworld::dataset::sha256_hex(&std::fs::read(&file).unwrap());
                entry["files"][name] = Value::String(sha);
            }
        }
        manifest.push_str(&entry.to_string());
        manifest.push('\n');
    }
    std::fs::write(&manifest_path, manifest).unwrap();
}

/// The ends of drawing lines (raster px) that lie outside the picture on lines that still cross
/// it, found by sampling each line (independent of the exporter's clipping).
fn outside_ends_of_crossing_lines(drawing: &[[[f64; 2]; 2]], w: f64, h: f64) -> usize {
    let inside = |p: [f64; 2]| p[0] >= 0.0 && p[1] >= 0.0 && p[0] <= w && p[1] <= h;
    drawing
        .iter()
        .filter(|d| {
            (1..1000).any(|k| {
                let t = f64::from(k) / 1000.0;
                inside([
                    d[0][0] + t * (d[1][0] - d[0][0]),
                    d[0][1] + t * (d[1][1] - d[0][1]),
                ])
            })
        })
        .map(|d| d.iter().filter(|p| !inside(**p)).count())
        .sum()
}

/// Clipping end to end: rendered scenes cut by a smaller picture, exported in every format and
/// read back; every clipped line ends on the border within 0.5 px with that end marked, no
/// other end is marked, as many ends are marked as the drawing has outside ends of lines
/// crossing the picture, and every check of the unclipped export holds too.
#[test]
fn scenes_running_off_the_picture_clip_to_the_border_with_marked_ends() {
    let Some((tmp, ds)) = rendered_dataset(4, 5, Some("240x200")) else {
        return;
    };
    cut_views(&ds, 60, 160, 130);
    for (format, reader) in [
        ("hawp", read_hawp as fn(&Path) -> Vec<Labelled>),
        ("lcnn", read_lcnn),
        ("letr", read_letr),
    ] {
        let out = tmp.path().join(format);
        // Split seed 1 puts two of the four scenes on each side (seed 0 puts all in test).
        ok(export(&ds, format, &out, &["--split-seed", "1"]));
        let set = reader(&out);
        check_export(&ds, &set, false);
        let on_edges = lines_on_picture_edges(&set, false);
        assert!(
            on_edges >= 0.95,
            "{format}: {on_edges} of lines on picture edges"
        );
        let (mut marked, mut expected) = (0, 0);
        for l in &set {
            let on_border = |p: [f64; 2]| {
                p[0].abs().min(p[1].abs()) <= 0.5
                    || (p[0] - l.width).abs() <= 0.5
                    || (p[1] - l.height).abs() <= 0.5
            };
            for (line, border) in l.lines.iter().zip(&l.border) {
                for (p, b) in line.iter().zip(border) {
                    if *b {
                        assert!(on_border(*p), "{format}: marked end {p:?} off the border");
                        marked += 1;
                    }
                }
            }
            let drawing = drawing_lines(&ds, &l.picture, l.height, true);
            expected += outside_ends_of_crossing_lines(&drawing, l.width, l.height);
        }
        eprintln!("{format}: {marked} clipped ends marked, {expected} expected");
        assert!(
            expected >= 20,
            "{format}: the cut should clip many lines ({expected})"
        );
        assert_eq!(marked, expected, "{format}");
    }
}

/// Draws a read-back HAWP item over its picture, 2x enlarged: lines coloured by `line_kind`
/// (boundary red, convex green, concave blue, crack orange), junctions as yellow squares
/// outlined in black. Uses only what the reader got from the files.
fn overlay(l: &Labelled) -> image::RgbImage {
    const SCALE: f64 = 2.0;
    let gray = image::open(&l.picture).unwrap().to_luma8();
    let mut img = image::RgbImage::from_fn(gray.width() * 2, gray.height() * 2, |x, y| {
        let v = gray.get_pixel(x / 2, y / 2).0[0];
        image::Rgb([v, v, v])
    });
    let put = |img: &mut image::RgbImage, x: f64, y: f64, c: [u8; 3]| {
        let (px, py) = ((x * SCALE).floor(), (y * SCALE).floor());
        if px >= 0.0 && py >= 0.0 && (px as u32) < img.width() && (py as u32) < img.height() {
            img.put_pixel(px as u32, py as u32, image::Rgb(c));
        }
    };
    for (line, kind) in l.lines.iter().zip(&l.kinds) {
        let c = match kind.as_str() {
            "boundary" => [220, 30, 30],
            "convex" => [20, 170, 40],
            "concave" => [40, 80, 230],
            _ => [250, 140, 0],
        };
        let len = ((line[1][0] - line[0][0]).hypot(line[1][1] - line[0][1]) * SCALE * 2.0).ceil();
        for k in 0..=len as usize {
            let t = k as f64 / len.max(1.0);
            let p = [
                line[0][0] + t * (line[1][0] - line[0][0]),
                line[0][1] + t * (line[1][1] - line[0][1]),
            ];
            put(&mut img, p[0], p[1], c);
        }
    }
    for j in &l.junctions {
        for dy in -3i32..=3 {
            for dx in -3i32..=3 {
                let edge = dx.abs() == 3 || dy.abs() == 3;
                let c = if edge { [0, 0, 0] } else { [255, 230, 0] };
                let (x, y) = (j[0] + f64::from(dx) / SCALE, j[1] + f64::from(dy) / SCALE);
                put(&mut img, x, y, c);
            }
        }
    }
    img
}

/// `docs/wireframe_hawp_overlay.png`: the richest picture of a 12-scene HAWP export, drawn by
/// the reader above; compared byte for byte (renderer-bound like the goldens, docs/rendering.md "Golden images"); re-bless with `BLESS=1 cargo test --test export_dataset`.
#[test]
fn the_readme_overlay_is_what_the_reader_draws() {
    let Some((tmp, ds)) = rendered_dataset(12, 7, None) else {
        return;
    };
    let out = tmp.path().join("hawp");
    ok(export(&ds, "hawp", &out, &[]));
    let set = read_hawp(&out);
    let richest = set.iter().max_by_key(|l| l.lines.len()).unwrap();
    let mut png = Vec::new();
    overlay(richest)
        .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .unwrap();
    let docs = Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/wireframe_hawp_overlay.png");
    if std::env::var_os("BLESS").is_some() {
        std::fs::write(&docs, &png).unwrap();
        eprintln!("wrote {} from {:?}", docs.display(), richest.picture);
    }
    let committed = std::fs::read(&docs).unwrap_or_else(|e| {
        panic!(
            "{}: {e}; make it with BLESS=1 cargo test --test export_dataset",
            docs.display()
        )
    });
    assert!(
        committed == png,
        "{} differs from the reader's drawing; review and re-bless",
        docs.display()
    );
}
