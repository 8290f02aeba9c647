//! Whole-stage tests of the vision front end (docs/vision.md "Vision front end") on pictures drawn here: boxes are ray
//! cast through the real `Camera`, each visible face filled with a flat gray level by its
//! orientation, and the pixels within half a pixel of the visible face's projected edges
//! darkened (the renderer's ~1 px seams). The true vertices are the projected box corners, known
//! exactly. These tests need no GPU; `blockworld bench vision` measures on real renders.

use blockworld::camera::{Camera, CameraOptions, CornerView};
use blockworld::drawing::{EdgeAxis, Junction, LineDrawing};
use blockworld::geom::{DVec2, DVec3};
use blockworld::vision::{
    decode_gray, detect_line_drawing, detect_with_directions, isometric_edge_directions,
    match_vertices, picture_directions, smooth_3x3, sobel_magnitude, SmoothWindow, VisionError,
    VisionOptions,
};
use image::{GrayImage, Luma};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};

mod common;

/// An axis-aligned box, world mm.
#[derive(Clone, Copy)]
struct Aabb {
    lo: DVec3,
    hi: DVec3,
}

fn cube(centre_x: f64, bottom_y: f64, centre_z: f64, side: f64) -> Aabb {
    let h = side / 2.0;
    Aabb {
        lo: DVec3::new(centre_x - h, bottom_y, centre_z - h),
        hi: DVec3::new(centre_x + h, bottom_y + side, centre_z + h),
    }
}

impl Aabb {
    fn corners(&self) -> Vec<DVec3> {
        (0..8)
            .map(|i| {
                DVec3::new(
                    if i & 4 != 0 { self.hi.x } else { self.lo.x },
                    if i & 2 != 0 { self.hi.y } else { self.lo.y },
                    if i & 1 != 0 { self.hi.z } else { self.lo.z },
                )
            })
            .collect()
    }

    /// Ray-box intersection (slabs): entry distance and the axis of the entry face.
    fn hit(&self, o: DVec3, d: DVec3) -> Option<(f64, usize, f64)> {
        let (mut t0, mut t1, mut axis, mut sign) = (f64::NEG_INFINITY, f64::INFINITY, 0, 0.0);
        for a in 0..3 {
            let (oa, da, lo, hi) = (o[a], d[a], self.lo[a], self.hi[a]);
            if da.abs() < 1e-12 {
                if oa < lo || oa > hi {
                    return None;
                }
                continue;
            }
            let (mut n, mut f) = ((lo - oa) / da, (hi - oa) / da);
            let mut s = -1.0;
            if n > f {
                std::mem::swap(&mut n, &mut f);
                s = 1.0;
            }
            if n > t0 {
                t0 = n;
                axis = a;
                sign = s;
            }
            t1 = t1.min(f);
        }
        (t0 <= t1 && t1 > 0.0).then_some((t0, axis, sign))
    }

    /// The four corners of the face on `axis` at side `sign`, in order around the face.
    fn face(&self, axis: usize, sign: f64) -> [DVec3; 4] {
        let v = if sign > 0.0 {
            self.hi[axis]
        } else {
            self.lo[axis]
        };
        let (a, b) = ((axis + 1) % 3, (axis + 2) % 3);
        let at = |ua: f64, ub: f64| {
            let mut p = DVec3::ZERO;
            p[axis] = v;
            p[a] = ua;
            p[b] = ub;
            p
        };
        [
            at(self.lo[a], self.lo[b]),
            at(self.hi[a], self.lo[b]),
            at(self.hi[a], self.hi[b]),
            at(self.lo[a], self.hi[b]),
        ]
    }
}

fn seg_dist(p: DVec2, a: DVec2, b: DVec2) -> f64 {
    let d = b - a;
    let s = ((p - a).dot(d) / d.length_squared().max(1e-12)).clamp(0.0, 1.0);
    p.distance(a + d * s)
}

/// Draws `boxes` as the camera sees them: flat faces (top 200, x faces 140, z faces 90, floor and
/// background 70) with 1 px dark seams (20) along the visible faces' edges, plus Gaussian noise.
fn draw(boxes: &[Aabb], camera: &Camera, noise_sigma: f64, seed: u64) -> GrayImage {
    let [w, h] = camera.size_px;
    let proj = |p: DVec3| camera.picture_from_world(p).truncate();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let normal = Normal::new(0.0, noise_sigma.max(1e-9)).unwrap();
    let all_edges: Vec<(DVec2, DVec2)> = boxes
        .iter()
        .flat_map(|b| {
            let c = b.corners();
            let mut e = Vec::new();
            for i in 0..8 {
                for bit in [1, 2, 4] {
                    if i & bit == 0 {
                        e.push((proj(c[i]), proj(c[i | bit])));
                    }
                }
            }
            e
        })
        .collect();
    GrayImage::from_fn(w, h, |col, row| {
        let p = DVec2::new(col as f64 + 0.5, h as f64 - row as f64 - 0.5);
        let (o, d) = camera.ray_through_picture(p.x, p.y);
        let hit = boxes
            .iter()
            .filter_map(|b| b.hit(o, d).map(|x| (x, b)))
            .min_by(|a, b| a.0 .0.total_cmp(&b.0 .0));
        let mut g = match hit {
            Some(((_, axis, sign), b)) => {
                let f = b.face(axis, sign).map(proj);
                let near = (0..4).any(|i| seg_dist(p, f[i], f[(i + 1) % 4]) <= 0.5);
                if near {
                    20.0
                } else {
                    [140.0, 200.0, 90.0][axis]
                }
            }
            None => {
                if all_edges.iter().any(|(a, b)| seg_dist(p, *a, *b) <= 0.5) {
                    20.0
                } else {
                    70.0
                }
            }
        };
        if noise_sigma > 0.0 {
            g += normal.sample(&mut rng);
        }
        Luma([g.round().clamp(0.0, 255.0) as u8])
    })
}

fn camera_for(boxes: &[Aabb], view: CornerView) -> Camera {
    let pts: Vec<DVec3> = boxes.iter().flat_map(|b| b.corners()).collect();
    Camera::frame(&pts, view, &CameraOptions::default())
}

/// The exact drawing of one cube: its corners but the hidden one, its edges not touching it.
fn cube_truth(b: &Aabb, camera: &Camera) -> LineDrawing {
    let c = b.corners();
    let depth = |i: usize| camera.picture_from_world(c[i]).z;
    let hidden = (0..8)
        .max_by(|&i, &j| depth(i).total_cmp(&depth(j)))
        .unwrap();
    let index = |i: usize| if i < hidden { i } else { i - 1 };
    let mut d = LineDrawing::default();
    for (i, p) in c.iter().enumerate() {
        if i != hidden {
            d.points.push(camera.picture_from_world(*p).truncate());
        }
    }
    for i in 0..8 {
        for bit in [1, 2, 4] {
            if i & bit == 0 && i != hidden && (i | bit) != hidden {
                d.lines.push([index(i), index(i | bit)]);
            }
        }
    }
    d.finalize();
    d
}

#[test]
fn one_cube_in_every_view_matches_the_exact_drawing_within_one_pixel() {
    let b = cube(0.0, 0.0, 0.0, 15.0);
    for view in CornerView::ALL {
        let camera = camera_for(&[b], view);
        let truth = cube_truth(&b, &camera);
        let mut codes: Vec<u8> = truth.codes.iter().map(|c| c.0).collect();
        codes.sort();
        assert_eq!(codes, vec![9, 14, 21, 22, 33, 40, 50], "truth of {view:?}");
        for (noise, seed) in [(0.0, 0), (8.0, 7)] {
            let img = draw(&[b], &camera, noise, seed);
            let det = detect_line_drawing(&img, &camera, &VisionOptions::default()).unwrap();
            let m = match_vertices(&det.drawing, &truth);
            assert_eq!(
                (m.pairs.len(), m.found, m.truth),
                (7, 7, 7),
                "{view:?} noise {noise}: {:?}",
                det.drawing.points
            );
            assert_eq!(
                m.codes_equal, 7,
                "{view:?} noise {noise}: codes {:?}",
                det.drawing.codes
            );
            eprintln!("{view:?} noise {noise}: {:?}", m.distances_px);
            let worst = m.distances_px.iter().cloned().fold(0.0, f64::max);
            assert!(
                worst < 1.0,
                "{view:?} noise {noise}: worst vertex {worst} px"
            );
        }
    }
}

#[test]
fn two_cubes_side_by_side_and_stacked_give_ten_points_fourteen_lines_two_ts() {
    // docs/formats.md "The exact line drawing": 10 points, 14 lines, 2 T junctions in every view.
    let side = [cube(-7.5, 0.0, 0.0, 15.0), cube(7.5, 0.0, 0.0, 15.0)];
    let stacked = [cube(0.0, 0.0, 0.0, 15.0), cube(0.0, 15.0, 0.0, 15.0)];
    for boxes in [&side[..], &stacked[..]] {
        for (view, noise) in CornerView::ALL
            .into_iter()
            .flat_map(|v| [(v, 0.0), (v, 8.0)])
        {
            let camera = camera_for(boxes, view);
            let img = draw(boxes, &camera, noise, 3);
            let det = detect_line_drawing(&img, &camera, &VisionOptions::default()).unwrap();
            let d = &det.drawing;
            let ts = d.junctions.iter().filter(|j| **j == Junction::T).count();
            assert_eq!(
                (d.points.len(), d.lines.len(), ts),
                (10, 14, 2),
                "{view:?}: {d:?}"
            );
            // Every projected visible corner is found within 1 px.
            let corners: Vec<DVec2> = boxes
                .iter()
                .flat_map(|b| b.corners())
                .map(|p| camera.picture_from_world(p).truncate())
                .collect();
            for p in &d.points {
                let nearest = corners
                    .iter()
                    .map(|c| c.distance(*p))
                    .fold(f64::MAX, f64::min);
                let on_t =
                    d.junctions[d.points.iter().position(|q| q == p).unwrap()] == Junction::T;
                assert!(
                    on_t || nearest < 1.0,
                    "{view:?}: vertex {p} is {nearest} px from a corner"
                );
            }
        }
    }
}

#[test]
fn wrong_size_and_huge_pictures_are_clear_errors() {
    let b = cube(0.0, 0.0, 0.0, 15.0);
    let camera = camera_for(&[b], CornerView::Ne);
    let img = GrayImage::new(100, 80);
    let err = detect_line_drawing(&img, &camera, &VisionOptions::default()).unwrap_err();
    assert!(matches!(
        err,
        VisionError::SizeMismatch {
            got_w: 100,
            got_h: 80,
            want_w: 512,
            want_h: 480
        }
    ));
    assert!(err.to_string().contains("512x480"), "{err}");
    // A PNG header claiming 9000 x 9000 is refused before decoding.
    let big = png_header_only(9000, 9000);
    let err = decode_gray(&big).unwrap_err();
    assert!(matches!(err, VisionError::TooLarge { .. }), "{err}");
    // A colour PNG is converted and says so.
    let rgb = image::RgbImage::from_pixel(4, 3, image::Rgb([10, 200, 30]));
    let mut bytes = Vec::new();
    image::DynamicImage::ImageRgb8(rgb)
        .write_to(
            &mut std::io::Cursor::new(&mut bytes),
            image::ImageFormat::Png,
        )
        .unwrap();
    let dec = decode_gray(&bytes).unwrap();
    assert_eq!(dec.gray.dimensions(), (4, 3));
    assert_eq!(dec.converted_from.as_deref(), Some("Rgb8"));
    // Constant and empty pictures give an empty drawing.
    let flat = GrayImage::from_pixel(512, 480, Luma([90]));
    let det = detect_line_drawing(&flat, &camera, &VisionOptions::default()).unwrap();
    assert!(det.drawing.points.is_empty() && det.lines.is_empty());
}

/// A PNG signature and IHDR chunk for a `w` x `h` 8-bit gray picture, with no pixel data.
fn png_header_only(w: u32, h: u32) -> Vec<u8> {
    let mut ihdr = Vec::new();
    ihdr.extend_from_slice(b"IHDR");
    ihdr.extend_from_slice(&w.to_be_bytes());
    ihdr.extend_from_slice(&h.to_be_bytes());
    ihdr.extend_from_slice(&[8, 0, 0, 0, 0]);
    let crc = crc32(&ihdr);
    let mut out = b"\x89PNG\r\n\x1a\n".to_vec();
    out.extend_from_slice(&13u32.to_be_bytes());
    out.extend_from_slice(&ihdr);
    out.extend_from_slice(&crc.to_be_bytes());
    for name in [&b"IDAT"[..], &b"IEND"[..]] {
        out.extend_from_slice(&0u32.to_be_bytes());
        out.extend_from_slice(name);
        out.extend_from_slice(&crc32(name).to_be_bytes());
    }
    out
}

fn crc32(bytes: &[u8]) -> u32 {
    let mut c = 0xffff_ffffu32;
    for &b in bytes {
        c ^= u32::from(b);
        for _ in 0..8 {
            c = if c & 1 != 0 {
                0xedb8_8320 ^ (c >> 1)
            } else {
                c >> 1
            };
        }
    }
    !c
}

/// The fuzz target's entry point (tests/fuzz/fuzz_targets/vision.rs) on a few hundred seeded random
/// small pictures and byte strings: no panic, and every point lies near the picture.
#[test]
fn random_small_pictures_never_panic() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let dirs = isometric_edge_directions();
    for i in 0..400 {
        let (w, h) = (rng.random_range(0..48u32), rng.random_range(0..48u32));
        let img = match i % 4 {
            0 => GrayImage::from_fn(w, h, |_, _| Luma([rng.random()])),
            1 => GrayImage::from_fn(w, h, |_, _| {
                Luma([if rng.random_bool(0.5) { 0 } else { 255 }])
            }),
            2 => {
                let (a, b) = (rng.random_range(0..50i64), rng.random_range(-30..30i64));
                GrayImage::from_fn(w, h, |x, y| {
                    Luma([if (x as i64 * b / 16 + a) > y as i64 {
                        200
                    } else {
                        30
                    }])
                })
            }
            _ => GrayImage::from_pixel(w, h, Luma([rng.random()])),
        };
        let det = detect_with_directions(&img, &dirs, &VisionOptions::default());
        for p in &det.drawing.points {
            assert!(p.is_finite(), "{p}");
        }
        assert_eq!(det.drawing.codes.len(), det.drawing.points.len());
        let bytes: Vec<u8> = (0..rng.random_range(0..64)).map(|_| rng.random()).collect();
        if let Ok(dec) = decode_gray(&bytes) {
            detect_with_directions(&dec.gray, &dirs, &VisionOptions::default());
        }
    }
    // Camera-derived directions are unit vectors pointing up or right.
    let camera = camera_for(&[cube(0.0, 0.0, 0.0, 15.0)], CornerView::Se);
    for d in picture_directions(&camera, &EdgeAxis::BLOCK_AXES) {
        assert!((d.length() - 1.0).abs() < 1e-9 && (d.y > 0.0 || d.x > 0.0));
    }
}

/// Committed fixtures (`tests/fixtures/vision/single_cube/{view,camera,lines}_<v>.png/json`,
/// drawn by `draw` above; `BLESS=1 cargo test --test vision` rewrites them) read back through the
/// same files the CLI reads: every true vertex found within 1 px with its code.
#[test]
fn committed_fixtures_are_found_exactly() {
    let dir =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/vision/single_cube");
    let b = cube(0.0, 0.0, 0.0, 15.0);
    if std::env::var_os("BLESS").is_some() {
        std::fs::create_dir_all(&dir).unwrap();
        for view in CornerView::ALL {
            let camera = camera_for(&[b], view);
            let img = draw(&[b], &camera, 0.0, 0);
            img.save(dir.join(format!("view_{}.png", view.name())))
                .unwrap();
            std::fs::write(
                dir.join(format!("camera_{}.json", view.name())),
                serde_json::to_string_pretty(&camera).unwrap(),
            )
            .unwrap();
            std::fs::write(
                dir.join(format!("lines_{}.json", view.name())),
                cube_truth(&b, &camera).to_json(),
            )
            .unwrap();
        }
    }
    for view in CornerView::ALL {
        let read = |name: &str| {
            std::fs::read(dir.join(format!(
                "{name}_{}.{}",
                view.name(),
                if name == "view" { "png" } else { "json" }
            )))
            .unwrap_or_else(|e| {
                panic!(
                    "missing fixture {name}_{} in {}: {e}; run `BLESS=1 cargo test --test vision`",
                    view.name(),
                    dir.display()
                )
            })
        };
        let img = decode_gray(&read("view")).unwrap().gray;
        let camera: Camera = serde_json::from_slice(&read("camera")).unwrap();
        let truth: LineDrawing = serde_json::from_slice(&read("lines")).unwrap();
        let det = detect_line_drawing(&img, &camera, &VisionOptions::default()).unwrap();
        let m = match_vertices(&det.drawing, &truth);
        assert_eq!(
            (m.pairs.len(), m.found, m.truth, m.codes_equal),
            (7, 7, 7, 7),
            "{view:?}"
        );
    }
}

/// The CLI on the committed fixtures: `vertices` writes the JSON of docs/vision.md "Vision front end", `edges` a 0/255
/// PNG; a picture of the wrong size fails naming the file and both sizes.
#[test]
fn cli_vertices_and_edges_on_fixtures() {
    let fx =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/vision/single_cube");
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("v.json");
    let s = |p: &std::path::Path| p.to_str().unwrap().to_string();
    let (view_ne, camera_ne) = (s(&fx.join("view_ne.png")), s(&fx.join("camera_ne.json")));
    common::ok(common::blockworld([
        "vertices",
        &view_ne,
        "--camera",
        &camera_ne,
        "-o",
        &s(&out),
    ]));
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    // The one vertices format is the line-drawing format of `lines_<view>.json`.
    let d = LineDrawing::from_json(&v.to_string()).unwrap();
    assert_eq!(d.points.len(), 7);
    let mut codes: Vec<u8> = d.codes.iter().map(|c| c.0).collect();
    codes.sort();
    assert_eq!(codes, vec![9, 14, 21, 22, 33, 40, 50]);
    assert!(v["junctions"]
        .as_array()
        .unwrap()
        .iter()
        .all(|x| x.is_string()));
    assert_eq!(d.lines.len(), 9);

    let edges = tmp.path().join("e.png");
    let magnitude = tmp.path().join("m.png");
    common::ok(common::blockworld([
        "edges",
        &view_ne,
        "-o",
        &s(&edges),
        "--threshold",
        "80",
        "--magnitude",
        &s(&magnitude),
    ]));
    let e = image::open(&edges).unwrap().into_luma8();
    assert!(e.as_raw().iter().all(|&x| x == 0 || x == 255));
    assert!(e.as_raw().contains(&255));
    // The magnitude PNG holds the smoothed magnitudes themselves (16-bit, not byte-swapped).
    let view = image::open(fx.join("view_ne.png")).unwrap().into_luma8();
    let want = smooth_3x3(&sobel_magnitude(&view), SmoothWindow::Centred);
    let m = image::open(&magnitude).unwrap().into_luma16();
    assert!(
        m == want,
        "the magnitude PNG differs from smooth_3x3(sobel_magnitude(view))"
    );

    let small = tmp.path().join("small.png");
    GrayImage::new(64, 48).save(&small).unwrap();
    let o = common::blockworld(["vertices", &s(&small), "--camera", &camera_ne]);
    let err = common::fails_with_2(&o);
    assert!(
        err.contains("small.png") && err.contains("64x48") && err.contains("512x480"),
        "{err}"
    );
}

/// A small stack at the scale of a 12-block scene (edges about 60 px long): every vertex found
/// lies within 1 px of a projected box corner or is a T junction on a drawn line; with and
/// without noise.
#[test]
fn a_small_stack_gives_vertices_on_corners() {
    let mut boxes = Vec::new();
    for (x, z) in [
        (-7.5, -7.5),
        (7.5, -7.5),
        (-7.5, 7.5),
        (7.5, 7.5),
        (22.5, 7.5),
        (22.5, -7.5),
    ] {
        boxes.push(cube(x, 0.0, z, 15.0));
    }
    boxes.push(cube(0.0, 15.0, 0.0, 15.0));
    boxes.push(cube(15.0, 15.0, 0.0, 15.0));
    boxes.push(cube(0.0, 30.0, 0.0, 15.0));
    for view in CornerView::ALL {
        for noise in [0.0, 8.0] {
            let camera = camera_for(&boxes, view);
            let img = draw(&boxes, &camera, noise, 11);
            if std::env::var_os("VISION_DUMP").is_some() {
                img.save(format!("/tmp/stack_{}_{noise}.png", view.name()))
                    .unwrap();
                std::fs::write(
                    format!("/tmp/stack_{}_{noise}.json", view.name()),
                    serde_json::to_string(&camera).unwrap(),
                )
                .unwrap();
            }
            let det = detect_line_drawing(&img, &camera, &VisionOptions::default()).unwrap();
            let d = &det.drawing;
            let corners: Vec<DVec2> = boxes
                .iter()
                .flat_map(|b| b.corners())
                .map(|p| camera.picture_from_world(p).truncate())
                .collect();
            let mut off = Vec::new();
            for (i, p) in d.points.iter().enumerate() {
                let nearest = corners
                    .iter()
                    .map(|c| c.distance(*p))
                    .fold(f64::MAX, f64::min);
                if nearest >= 1.0 && d.junctions[i] != Junction::T {
                    off.push((*p, nearest, d.junctions[i]));
                }
            }
            eprintln!(
                "{view:?} noise {noise}: {} points, {} lines, {} off corners",
                d.points.len(),
                d.lines.len(),
                off.len()
            );
            assert!(off.is_empty(), "{view:?} noise {noise}: {off:?}");
        }
    }
}

/// The docs/vision.md "Vision front end" accuracy targets on the real renderer (lavapipe) and the exact ground truth, for
/// every scene in `scenes/`: noise-free vertex precision, recall and code accuracy at least 0.98;
/// with sensor noise sigma 8 at least 0.95. Skips loudly without a renderer unless
/// `BLOCKWORLD_REQUIRE_GPU` is set.
#[test]
fn real_renders_meet_the_accuracy_targets() {
    use blockworld::render::RenderOptions;
    let Some(renderer) = common::renderer() else {
        return;
    };
    let files = common::example_scene_paths();
    assert!(!files.is_empty(), "no scenes in scenes/");
    for (noise, bar) in [(0.0, 0.98), (8.0, 0.95)] {
        let (mut found, mut truth, mut matched, mut codes) = (0, 0, 0, 0);
        for f in &files {
            let scene = blockworld::scene::read_scene(f).unwrap();
            let opts = RenderOptions {
                noise_sigma: noise,
                seed: 1,
                ..Default::default()
            };
            for v in renderer
                .render_views(&scene, &CornerView::ALL, &opts)
                .unwrap()
            {
                let det =
                    detect_line_drawing(&v.gray, &v.camera, &VisionOptions::default()).unwrap();
                let m = match_vertices(&det.drawing, &v.lines);
                found += m.found;
                truth += m.truth;
                matched += m.pairs.len();
                codes += m.codes_equal;
            }
        }
        let (p, r, c) = (
            matched as f64 / found.max(1) as f64,
            matched as f64 / truth.max(1) as f64,
            codes as f64 / matched.max(1) as f64,
        );
        eprintln!("noise {noise}: precision {p:.3} recall {r:.3} code accuracy {c:.3} ({truth} true points)");
        assert!(
            p >= bar && r >= bar && c >= bar,
            "noise {noise}: precision {p:.3} recall {r:.3} codes {c:.3} below {bar}"
        );
    }
}
