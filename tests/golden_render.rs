//! Whole-renderer tests (docs/rendering.md "Rendering"): golden images of every example scene, gray levels of the
//! faces, the seam between touching blocks, depth and ids against an exact ray cast, noise,
//! MSAA, perspective, odd picture widths, sharing one renderer across threads.
//!
//! Every test needs an adapter: without one it prints a loud SKIP unless
//! `BLOCKWORLD_REQUIRE_GPU` is set (`make test` sets it), in which case it fails.

mod common;

use blockworld::camera::{Camera, CornerView, Projection, DEPTH_UNITS_PER_MM};
use blockworld::geom::{DVec2, DVec3};
use blockworld::render::{
    Backend, RenderError, RenderOptions, RenderedView, Renderer, BACKGROUND_LEVEL, SEAM_LEVEL,
};
use blockworld::scene::{read_scene, Block, Scene};
use common::{compare_golden, distance_to_segment, renderer, Tolerance};
use rayon::prelude::*;

/// Golden tolerance: exact. lavapipe renders bit-identically from run to run, across debug and
/// release, and llvmpipe-GL matches it (docs/architecture.md "Dependencies"); what bounds it is the
/// Mesa/LLVM version of the machine that blessed the goldens (golden/README.md). Loosen only
/// with a written reason, e.g. a Mesa update that moves rasterization by a sub-pixel step.
const GOLDEN_TOLERANCE: Tolerance = Tolerance {
    max_differing_share: 0.0,
    max_abs_diff: 0,
};

/// The gray levels of an unturned block scene without MSAA or noise: top, left, right, floor,
/// seam, background.
const EXACT_LEVELS: [u8; 6] = [210, 150, 100, 60, SEAM_LEVEL, BACKGROUND_LEVEL];

fn cube() -> Scene {
    Scene::new(
        "cube",
        vec![Block::new("b15", DVec3::new(0.0, 7.5, 0.0), 0.0)],
    )
}

fn gray_at(v: &RenderedView, p: DVec2) -> u8 {
    let [x, row] = raster(v, p);
    v.gray.get_pixel(x, row)[0]
}

/// The raster pixel (column, row from the top) containing picture point `p` (y up).
fn raster(v: &RenderedView, p: DVec2) -> [u32; 2] {
    let h = v.gray.height() as f64;
    [p.x.floor() as u32, (h - p.y).floor() as u32]
}

/// Picture point (y up) of the centre of raster pixel (column, row).
fn centre(h: u32, x: u32, row: u32) -> DVec2 {
    DVec2::new(x as f64 + 0.5, h as f64 - row as f64 - 0.5)
}

fn project(c: &Camera, p: DVec3) -> DVec2 {
    c.picture_from_world(p).truncate()
}

/// Signed distances (px) of `p` to the edges of convex polygon `poly`, positive inside.
fn inside_margin(poly: &[DVec2], p: DVec2) -> f64 {
    let n = poly.len();
    let area: f64 = (0..n).map(|k| poly[k].perp_dot(poly[(k + 1) % n])).sum();
    let sign = area.signum();
    (0..n)
        .map(|k| {
            let (a, b) = (poly[k], poly[(k + 1) % n]);
            sign * (b - a).perp_dot(p - a) / (b - a).length()
        })
        .fold(f64::INFINITY, f64::min)
}

/// Convex hull (counter-clockwise) of picture points.
fn hull(mut pts: Vec<DVec2>) -> Vec<DVec2> {
    pts.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    let mut lower: Vec<DVec2> = Vec::new();
    for &p in &pts {
        while lower.len() >= 2
            && (lower[lower.len() - 1] - lower[lower.len() - 2])
                .perp_dot(p - lower[lower.len() - 2])
                <= 0.0
        {
            lower.pop();
        }
        lower.push(p);
    }
    let mut upper: Vec<DVec2> = Vec::new();
    for &p in pts.iter().rev() {
        while upper.len() >= 2
            && (upper[upper.len() - 1] - upper[upper.len() - 2])
                .perp_dot(p - upper[upper.len() - 2])
                <= 0.0
        {
            upper.pop();
        }
        upper.push(p);
    }
    lower.pop();
    upper.pop();
    lower.extend(upper);
    lower
}

#[test]
fn golden_images_of_every_example_scene() {
    let Some(r) = renderer() else { return };
    let opts = RenderOptions::default();
    let paths = common::example_scene_paths();
    assert!(paths.len() >= 5, "scenes/ holds the five example scenes");
    let mut failures = Vec::new();
    for path in &paths {
        let scene = read_scene(path).unwrap_or_else(|e| panic!("{e}"));
        for view in CornerView::ALL {
            let v = r.render_pixels(&scene, view, &opts).unwrap();
            let name = format!("{}/view_{}", common::stem(path), view.name());
            if let Err(e) = compare_golden(&name, &v.gray, GOLDEN_TOLERANCE) {
                failures.push(e);
            }
            let stray: Vec<u8> = levels(&v.gray)
                .into_iter()
                .filter(|l| !EXACT_LEVELS.contains(l))
                .collect();
            if !stray.is_empty() {
                failures.push(format!(
                    "{name}: gray levels {stray:?} outside {EXACT_LEVELS:?}"
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

fn levels(img: &image::GrayImage) -> Vec<u8> {
    let mut seen = [false; 256];
    for p in img.as_raw() {
        seen[*p as usize] = true;
    }
    (0..=255u8).filter(|l| seen[*l as usize]).collect()
}

#[test]
fn single_cube_top_left_right_and_floor_have_distinct_levels_in_every_view() {
    let Some(r) = renderer() else { return };
    let scene = cube();
    let block = &scene.blocks[0];
    let corners = block.world_vertices();
    for view in CornerView::ALL {
        let v = r.render(&scene, view, &RenderOptions::default()).unwrap();
        let c = &v.camera;
        let (w, h) = v.gray.dimensions();
        // The visible faces, projected; left/right by the picture x of their centres.
        let mut sides = Vec::new();
        let mut top = Vec::new();
        for (f, face) in block.block_type.faces().iter().enumerate() {
            let n = block.world_face_normal(f);
            if n.dot(c.towards_eye()) <= 0.0 {
                continue;
            }
            let poly: Vec<DVec2> = face
                .iter()
                .map(|&k| project(c, corners[k as usize]))
                .collect();
            if n.y > 0.9 {
                top = poly;
            } else {
                sides.push(poly);
            }
        }
        assert_eq!(sides.len(), 2, "{view:?}: two side faces visible");
        let cx = |p: &Vec<DVec2>| p.iter().map(|q| q.x).sum::<f64>() / p.len() as f64;
        sides.sort_by(|a, b| cx(a).total_cmp(&cx(b)));
        let silhouette = hull(corners.iter().map(|p| project(c, *p)).collect());
        let mut found: [Vec<u8>; 4] = Default::default();
        for row in 0..h {
            for x in 0..w {
                let p = centre(h, x, row);
                let g = v.gray.get_pixel(x, row)[0];
                let id = v.ids.get_pixel(x, row)[0];
                let region = if inside_margin(&top, p) > 1.5 {
                    Some(0)
                } else if inside_margin(&sides[0], p) > 1.5 {
                    Some(1)
                } else if inside_margin(&sides[1], p) > 1.5 {
                    Some(2)
                } else if inside_margin(&silhouette, p) < -1.5 && v.depth.get_pixel(x, row)[0] > 0 {
                    assert_eq!(id, 0, "{view:?} floor pixel ({x}, {row}) has id {id}");
                    Some(3)
                } else {
                    None
                };
                if let Some(k) = region {
                    if k < 3 {
                        assert_eq!(id, 1, "{view:?} face pixel ({x}, {row}) has id {id}");
                    }
                    if !found[k].contains(&g) {
                        found[k].push(g);
                    }
                }
            }
        }
        let names = ["top", "left", "right", "floor"];
        let mut levels = Vec::new();
        for k in 0..4 {
            assert_eq!(
                found[k].len(),
                1,
                "{view:?}: {} pixels have levels {:?}",
                names[k],
                found[k]
            );
            levels.push(found[k][0]);
        }
        assert_eq!(
            levels,
            vec![210, 150, 100, 60],
            "{view:?} top/left/right/floor"
        );
    }
}

#[test]
fn crack_between_two_b15_shows_a_seam_and_one_b30_does_not() {
    let Some(r) = renderer() else { return };
    let two = Scene::new(
        "two_b15",
        vec![
            Block::new("b15", DVec3::new(-7.5, 7.5, 0.0), 0.0),
            Block::new("b15", DVec3::new(7.5, 7.5, 0.0), 0.0),
        ],
    );
    let one = Scene::new(
        "one_b30",
        vec![Block::new("b30", DVec3::new(0.0, 7.5, 0.0), 0.0)],
    );
    // The crack lies in the plane x = 0: across the top and down the north and south faces.
    let cracks = [
        (
            DVec3::new(0.0, 15.0, -7.5),
            DVec3::new(0.0, 15.0, 7.5),
            DVec3::Y,
        ),
        (
            DVec3::new(0.0, 0.0, -7.5),
            DVec3::new(0.0, 15.0, -7.5),
            -DVec3::Z,
        ),
        (
            DVec3::new(0.0, 0.0, 7.5),
            DVec3::new(0.0, 15.0, 7.5),
            DVec3::Z,
        ),
    ];
    for view in CornerView::ALL {
        let opts = RenderOptions::default();
        let a = r.render_pixels(&two, view, &opts).unwrap();
        let b = r.render_pixels(&one, view, &opts).unwrap();
        assert_eq!(a.camera, b.camera, "same bounds, same camera");
        let c = &a.camera;
        let visible: Vec<(DVec2, DVec2)> = cracks
            .iter()
            .filter(|(_, _, n)| n.dot(c.towards_eye()) > 0.0)
            .map(|(p, q, _)| (project(c, *p), project(c, *q)))
            .collect();
        assert_eq!(visible.len(), 2, "{view:?}: top and one side crack visible");
        let (w, h) = a.gray.dimensions();
        let mut differing = 0usize;
        for row in 0..h {
            for x in 0..w {
                if a.gray.get_pixel(x, row) == b.gray.get_pixel(x, row) {
                    continue;
                }
                differing += 1;
                let p = centre(h, x, row);
                let d = visible
                    .iter()
                    .map(|(s, e)| distance_to_segment(p, *s, *e))
                    .fold(f64::INFINITY, f64::min);
                // At most 1 px: the crack is a silhouette edge of the block whose inner face
                // turns away, which also darkens the nearest pixel on its side
                // (render::SEAM_HALF_WIDTH_PX).
                assert!(
                    d <= 1.0,
                    "{view:?}: pixel ({x}, {row}) differs {d:.2} px from any crack"
                );
                assert_eq!(a.gray.get_pixel(x, row)[0], SEAM_LEVEL);
            }
        }
        let crack_px: f64 = visible.iter().map(|(s, e)| s.distance(*e)).sum();
        assert!(
            differing as f64 >= 0.8 * crack_px,
            "{view:?}: only {differing} seam pixels along {crack_px:.0} px of crack"
        );
        // Along each crack, the pixel whose centre is nearest the line is seam with two b15 and
        // the face's own level with one b30.
        for (s, e) in &visible {
            let len = s.distance(*e);
            let mut t = 3.0;
            while t < len - 3.0 {
                let p = *s + (*e - *s) * (t / len);
                let [x0, r0] = raster(&a, p);
                let nearest = (x0 - 1..=x0 + 1)
                    .flat_map(|x| (r0 - 1..=r0 + 1).map(move |r| (x, r)))
                    .min_by(|u, v| {
                        let du = distance_to_segment(centre(h, u.0, u.1), *s, *e);
                        let dv = distance_to_segment(centre(h, v.0, v.1), *s, *e);
                        du.total_cmp(&dv)
                    })
                    .unwrap();
                let ga = a.gray.get_pixel(nearest.0, nearest.1)[0];
                let gb = b.gray.get_pixel(nearest.0, nearest.1)[0];
                assert_eq!(ga, SEAM_LEVEL, "{view:?}: two b15, crack at {p:?}");
                assert!(
                    [210, 150, 100].contains(&gb),
                    "{view:?}: one b30 at {p:?}: {gb}"
                );
                t += 1.0;
            }
        }
    }
}

/// Nearest hit of the ray `(o, d)` with the scene (blocks as convex polyhedra, the floor quad
/// the renderer draws) within the camera's clip range: `(block id, depth along the axis mm)`;
/// `None` for background.
fn ray_hit(scene: &Scene, c: &Camera, o: DVec3, d: DVec3) -> Option<(u16, f64)> {
    let mut best: Option<(f64, u16)> = None;
    for (i, b) in scene.blocks.iter().enumerate() {
        let v = b.world_vertices();
        let (mut t0, mut t1) = (0.0f64, f64::INFINITY);
        for (f, face) in b.block_type.faces().iter().enumerate() {
            let n = b.world_face_normal(f);
            let denom = n.dot(d);
            let num = n.dot(v[face[0] as usize] - o);
            if denom.abs() < 1e-15 {
                if num < 0.0 {
                    t0 = f64::INFINITY;
                }
            } else if denom < 0.0 {
                t0 = t0.max(num / denom);
            } else {
                t1 = t1.min(num / denom);
            }
        }
        if t0 <= t1 && best.is_none_or(|(t, _)| t0 < t) {
            best = Some((t0, i as u16 + 1));
        }
    }
    if d.y < 0.0 {
        let t = -o.y / d.y;
        let p = o + d * t;
        let half = c.near_far_mm[1].max(1000.0);
        let [tx, _, tz] = c.target_mm;
        let on_floor = (p.x - tx).abs() <= half && (p.z - tz).abs() <= half;
        if on_floor && t > 0.0 && best.is_none_or(|(b, _)| t < b) {
            best = Some((t, 0));
        }
    }
    let (t, id) = best?;
    let depth = c.picture_from_world(o + d * t).z;
    (depth <= c.near_far_mm[1]).then_some((id, depth))
}

/// Every pixel's id and depth against the exact ray cast; pixels whose centre lies within
/// 0.01 px of an outline (where the rasterizer's sub-pixel grid may decide either way) are skipped.
/// Where the floor is computed instead of drawn (`render::floor_fill`), its depth is the ray
/// cast's rounded to the step, not only within a step of it.
fn check_depth_and_ids(scene: &Scene, v: &RenderedView) {
    let c = &v.camera;
    let floor_computed = blockworld::render::floor_fill(scene, c).is_some();
    let (w, h) = v.gray.dimensions();
    let tol_mm = 1.0 / DEPTH_UNITS_PER_MM;
    let (mut checked, mut skipped) = (0usize, 0usize);
    for row in 0..h {
        for x in 0..w {
            let p = centre(h, x, row);
            let probe = |dx: f64, dy: f64| {
                let (o, d) = c.ray_through_picture(p.x + dx, p.y + dy);
                ray_hit(scene, c, o, d)
            };
            let hit = probe(0.0, 0.0);
            let ids_around: Vec<Option<u16>> =
                [(0.01, 0.0), (-0.01, 0.0), (0.0, 0.01), (0.0, -0.01)]
                    .iter()
                    .map(|(dx, dy)| probe(*dx, *dy).map(|h| h.0))
                    .collect();
            if ids_around.iter().any(|i| *i != hit.map(|h| h.0)) {
                skipped += 1;
                continue;
            }
            checked += 1;
            let id = v.ids.get_pixel(x, row)[0];
            let depth = v.depth.get_pixel(x, row)[0];
            match hit {
                None => assert_eq!((id, depth), (0, 0), "background pixel ({x}, {row})"),
                Some((want_id, want_mm)) => {
                    assert_eq!(id, want_id, "pixel ({x}, {row})");
                    if want_mm * DEPTH_UNITS_PER_MM < 65535.0 {
                        let got_mm = f64::from(depth) / DEPTH_UNITS_PER_MM;
                        assert!(
                            (got_mm - want_mm).abs() <= tol_mm,
                            "pixel ({x}, {row}): depth {got_mm} mm, ray {want_mm} mm"
                        );
                        let steps = want_mm * DEPTH_UNITS_PER_MM;
                        let tie = (steps.fract() - 0.5).abs() < 1e-6;
                        if want_id == 0 && floor_computed && !tie {
                            assert_eq!(
                                f64::from(depth),
                                steps.round_ties_even().max(1.0),
                                "floor pixel ({x}, {row}): ray {want_mm} mm"
                            );
                        }
                    }
                }
            }
        }
    }
    assert!(skipped * 50 < checked, "{skipped} ambiguous of {checked}");
}

#[test]
fn depth_and_ids_match_an_exact_ray_cast_orthographic_perspective_and_odd_sizes() {
    let Some(r) = renderer() else { return };
    let sample = read_scene(&common::root().join("scenes/thesis_sample.json")).unwrap();
    let turned = Scene::new(
        "turned",
        vec![
            Block::new("b30", DVec3::new(0.0, 7.5, 0.0), 30.0),
            Block::new("b7_5", DVec3::new(30.0, 3.75, 10.0), -45.0),
        ],
    );
    turned.validate("turned").unwrap();
    let cases = [
        (cube(), CornerView::Ne, [512, 480], Projection::Orthographic),
        (turned, CornerView::Se, [512, 480], Projection::Orthographic),
        (
            cube(),
            CornerView::Sw,
            [333, 97],
            Projection::Perspective { fov_y_deg: 40.0 },
        ),
        (
            sample.clone(),
            CornerView::Se,
            [300, 200],
            Projection::Orthographic,
        ),
        (
            sample,
            CornerView::Nw,
            [512, 480],
            Projection::Perspective { fov_y_deg: 30.0 },
        ),
    ];
    for (scene, view, size_px, projection) in cases {
        let mut opts = RenderOptions::default();
        opts.camera.size_px = size_px;
        opts.camera.projection = projection;
        let v = r.render(&scene, view, &opts).unwrap();
        assert_eq!(v.gray.dimensions(), (size_px[0], size_px[1]));
        check_depth_and_ids(&scene, &v);
        // The projected centre of block 1's top face shows block 1, lit as a top face.
        let top =
            scene.blocks[0].center_mm + DVec3::Y * scene.blocks[0].block_type.size_mm().y / 2.0;
        let p = project(&v.camera, top);
        let [x, row] = raster(&v, p);
        if scene.blocks.len() == 1 {
            assert_eq!(v.ids.get_pixel(x, row)[0], 1);
            assert_eq!(gray_at(&v, p), 210);
        }
    }
}

#[test]
fn noise_is_deterministic_in_the_seed() {
    let Some(r) = renderer() else { return };
    let scene = cube();
    let clean = r
        .render_pixels(&scene, CornerView::Ne, &RenderOptions::default())
        .unwrap();
    let noisy = |seed| {
        let opts = RenderOptions {
            noise_sigma: 4.0,
            seed,
            ..Default::default()
        };
        r.render_pixels(&scene, CornerView::Ne, &opts).unwrap()
    };
    let (a, b, c) = (noisy(7), noisy(7), noisy(8));
    assert_eq!(a.gray, b.gray, "same seed, same picture");
    assert_ne!(a.gray, c.gray, "different seed, different picture");
    assert_eq!(a.depth, clean.depth, "noise touches the picture only");
    // The noise has about the asked-for spread (levels 20..210 are far from the clamp).
    let diffs: Vec<f64> = a
        .gray
        .as_raw()
        .iter()
        .zip(clean.gray.as_raw())
        .map(|(x, y)| f64::from(*x) - f64::from(*y))
        .collect();
    let n = diffs.len() as f64;
    let mean = diffs.iter().sum::<f64>() / n;
    let sd = (diffs.iter().map(|d| (d - mean).powi(2)).sum::<f64>() / n).sqrt();
    assert!(
        mean.abs() < 0.1 && (sd - 4.0).abs() < 0.2,
        "mean {mean}, sd {sd}"
    );
}

#[test]
fn msaa4_smooths_edges_only_and_keeps_the_ground_truth_exact() {
    let Some(r) = renderer() else { return };
    let scene = read_scene(&common::root().join("scenes/two_layer.json")).unwrap();
    let one = r
        .render_pixels(&scene, CornerView::Se, &RenderOptions::default())
        .unwrap();
    let four = r
        .render_pixels(
            &scene,
            CornerView::Se,
            &RenderOptions {
                msaa: 4,
                ..Default::default()
            },
        )
        .unwrap();
    assert_eq!(one.ids, four.ids, "ids are single-sampled");
    assert_eq!(one.depth, four.depth, "depth is single-sampled");
    let (w, h) = one.gray.dimensions();
    let g = |img: &image::GrayImage, x: u32, y: u32| img.get_pixel(x, y)[0];
    let mut changed = 0;
    for y in 1..h - 1 {
        for x in 1..w - 1 {
            if g(&one.gray, x, y) == g(&four.gray, x, y) {
                continue;
            }
            changed += 1;
            let v = g(&one.gray, x, y);
            let near_edge = [(x - 1, y), (x + 1, y), (x, y - 1), (x, y + 1)]
                .iter()
                .any(|&(a, b)| g(&one.gray, a, b) != v);
            assert!(near_edge, "MSAA changed ({x}, {y}) away from any edge");
        }
    }
    assert!(changed > 100, "MSAA blended {changed} pixels");
    let blended = levels(&four.gray)
        .into_iter()
        .filter(|l| !EXACT_LEVELS.contains(l))
        .count();
    assert!(blended > 0, "MSAA 4 produces intermediate levels");
}

#[test]
fn one_renderer_serves_many_threads_with_the_same_pixels() {
    let Some(r) = renderer() else { return };
    fn assert_shareable<T: Send + Sync>(_: &T) {}
    assert_shareable(&r);
    let scenes: Vec<Scene> = common::example_scene_paths()
        .iter()
        .map(|p| read_scene(p).unwrap())
        .collect();
    let jobs: Vec<(usize, CornerView)> = (0..scenes.len())
        .flat_map(|i| CornerView::ALL.map(|v| (i, v)))
        .collect();
    let opts = RenderOptions::default();
    let serial: Vec<_> = jobs
        .iter()
        .map(|(i, v)| r.render_pixels(&scenes[*i], *v, &opts).unwrap().gray)
        .collect();
    let parallel: Vec<_> = jobs
        .par_iter()
        .map(|(i, v)| r.render_pixels(&scenes[*i], *v, &opts).unwrap().gray)
        .collect();
    assert!(
        serial == parallel,
        "parallel renders differ from serial ones"
    );
}

#[test]
fn bad_options_are_errors_not_panics() {
    let Some(r) = renderer() else { return };
    let scene = cube();
    let bad = [
        RenderOptions {
            msaa: 2,
            ..Default::default()
        },
        {
            let mut o = RenderOptions::default();
            o.camera.size_px = [0, 480];
            o
        },
        {
            let mut o = RenderOptions::default();
            o.camera.size_px = [100_000, 480];
            o
        },
        {
            let mut o = RenderOptions::default();
            o.camera.elevation_deg = f64::NAN;
            o
        },
        RenderOptions {
            noise_sigma: -1.0,
            ..Default::default()
        },
    ];
    for opts in bad {
        match r.render(&scene, CornerView::Ne, &opts) {
            Err(RenderError::Options(msg)) => assert!(!msg.is_empty()),
            other => panic!(
                "expected an options error for {opts:?}, got {:?}",
                other.map(|_| ())
            ),
        }
    }
    // The renderer still works afterwards.
    r.render(&scene, CornerView::Ne, &RenderOptions::default())
        .unwrap();
}

#[test]
fn gl_backend_renders_the_same_pixels_as_vulkan() {
    let Some(vk) = renderer() else { return };
    let gl = match Renderer::new(Backend::Gl) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("\n*** SKIPPED gl_backend_renders_the_same_pixels_as_vulkan: {e}\n");
            return;
        }
    };
    let scene = read_scene(&common::root().join("scenes/thesis_sample.json")).unwrap();
    let opts = RenderOptions::default();
    for view in [CornerView::Ne, CornerView::Sw] {
        let a = vk.render_pixels(&scene, view, &opts).unwrap();
        let b = gl.render_pixels(&scene, view, &opts).unwrap();
        let s = common::diff_stats(&b.gray, &a.gray);
        eprintln!("gl vs vulkan {view:?}: {s:?}");
        assert_eq!(s.differing, 0, "{view:?}: GL differs from Vulkan: {s:?}");
        assert_eq!(a.ids, b.ids, "{view:?}: ids differ between GL and Vulkan");
        // Depth may round the other way where depth * 16 lies within float error of k + 0.5
        // (the two drivers evaluate the f32 shader maths differently; 24 of 245,760 pixels in
        // the NE view when this was written): at most one step, 1/16 mm.
        let steps = a
            .depth
            .as_raw()
            .iter()
            .zip(b.depth.as_raw())
            .map(|(p, q)| p.abs_diff(*q))
            .max()
            .unwrap_or(0);
        assert!(steps <= 1, "{view:?}: depth differs by {steps} steps");
    }
}

/// The cost of `Renderer::render_pixels` for `bench render`'s 10-block stack (b15 in layers of
/// a 3 x 3 square), one view per submission, views cycling through the four corners:
/// `VIEWS=40` and `VIEWS=10` under `valgrind --tool=callgrind`, the difference over 30 is the
/// instructions per view with the device set-up and the shader compilation left out (docs/benchmarks.md
/// "Peers"). Checks only that the last view shows the top block and at least nine in all.
#[test]
#[ignore]
fn print_cost_of_render_pixels_of_the_10_block_stack() {
    let Some(renderer) = renderer() else { return };
    let scene = blockworld::scene::b15_layers(10, 3, "bench_10".to_string());
    let views: usize = std::env::var("VIEWS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(200);
    let opts = RenderOptions::default();
    let start = std::time::Instant::now();
    let mut last = None;
    for k in 0..views {
        last = Some(
            renderer
                .render_pixels(&scene, CornerView::ALL[k % 4], &opts)
                .unwrap(),
        );
    }
    let per = start.elapsed().as_secs_f64() * 1e3 / views.max(1) as f64;
    println!("{views} views of the 10-block stack: {per:.3} ms per view (render + readback)");
    let Some(v) = last else { return };
    let mut seen = [false; 11];
    for p in v.ids.pixels() {
        seen[usize::from(p[0]).min(10)] = true;
    }
    // The block under the top one hides in the view where it is the far corner.
    let blocks_seen = seen[1..].iter().filter(|s| **s).count();
    assert!(
        blocks_seen >= 9 && seen[10],
        "the last view shows {blocks_seen} blocks"
    );
}
