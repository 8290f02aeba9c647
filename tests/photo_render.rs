//! The photographic look (docs/rendering.md "Photographic look"): goldens of two example scenes, ground
//! truth that does not depend on the look, shading order of the faces, the crack between
//! touching blocks, seeded noise and light, the thesis's 2 x 2 averaging with a camera that
//! describes the written picture, and the parts `bench render --photo-parts` times.
//!
//! Every test needs an adapter: without one it prints a loud SKIP unless
//! `BLOCKWORLD_REQUIRE_GPU` is set (`make test` sets it), in which case it fails.

mod common;

use blockworld::camera::CornerView;
use blockworld::geom::DVec3;
use blockworld::render::photo::varied::LookDraw;
use blockworld::render::photo::{sensor, PhotoParts, PhotoSetup};
use blockworld::render::{Look, RenderOptions, RenderedView};
use blockworld::scene::{read_scene, Block, Scene};
use common::{compare_golden, renderer, root, Tolerance};

/// Photo goldens: lavapipe renders them bit-identically run to run on the blessing machine
/// (golden/README.md); the allowance is for another Mesa/LLVM, whose shadow filter (12 + 12 taps
/// on a spiral turned by one angle per pixel) and f32 sensor arithmetic may round a level
/// differently here and there: at most 0.5% of pixels, by at most 12 levels.
const PHOTO_TOLERANCE: Tolerance = Tolerance {
    max_differing_share: 0.005,
    max_abs_diff: 12,
};

fn photo() -> RenderOptions {
    RenderOptions {
        look: Look::Photo,
        ..Default::default()
    }
}

fn example(name: &str) -> Scene {
    read_scene(&root().join(format!("scenes/{name}.json"))).unwrap()
}

fn gray_at(v: &RenderedView, p_mm: DVec3) -> u8 {
    let p = v.camera.picture_from_world(p_mm);
    let h = v.gray.height() as f64;
    v.gray
        .get_pixel(p.x.floor() as u32, (h - p.y).floor() as u32)[0]
}

#[test]
fn photo_goldens_of_the_thesis_sample_and_two_touching_cubes() {
    let Some(r) = renderer() else { return };
    let mut failures = Vec::new();
    for name in ["thesis_sample", "two_cubes_touching"] {
        let scene = example(name);
        for view in [CornerView::Ne, CornerView::Sw] {
            let v = r.render_pixels(&scene, view, &photo()).unwrap();
            let golden = format!("photo/{name}/view_{}", view.name());
            if let Err(e) = compare_golden(&golden, &v.gray, PHOTO_TOLERANCE) {
                failures.push(e);
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn ground_truth_and_camera_do_not_depend_on_the_look() {
    let Some(r) = renderer() else { return };
    let scene = example("thesis_sample");
    for view in [CornerView::Ne, CornerView::Se] {
        let art = r.render(&scene, view, &RenderOptions::default()).unwrap();
        let pic = r.render(&scene, view, &photo()).unwrap();
        assert_eq!(art.camera, pic.camera);
        assert!(art.depth == pic.depth, "depth of the sharp solids");
        assert!(art.ids == pic.ids, "ids of the sharp solids");
        assert_eq!(art.lines, pic.lines, "the exact drawing");
        assert!(art.gray != pic.gray, "but the picture changes");
    }
}

#[test]
fn a_photographed_cube_shows_top_brighter_than_left_than_right_than_floor() {
    let Some(r) = renderer() else { return };
    let cube = Scene::new("c", vec![Block::new("b15", DVec3::new(0.0, 7.5, 0.0), 0.0)]);
    let v = r.render_pixels(&cube, CornerView::Ne, &photo()).unwrap();
    // NE camera at +x, -z: the visible sides are +x (left in the picture) and -z (right).
    let top = gray_at(&v, DVec3::new(0.0, 15.0, 0.0));
    let left = gray_at(&v, DVec3::new(7.5, 7.5, 0.0));
    let right = gray_at(&v, DVec3::new(0.0, 7.5, -7.5));
    let floor = gray_at(&v, DVec3::new(8.5, 0.0, -8.5));
    assert!(
        top > left + 20 && left > right + 20 && right > floor + 20,
        "top {top}, left {left}, right {right}, floor {floor}"
    );
}

#[test]
fn the_crack_between_touching_blocks_is_dark_and_apart_blocks_have_none() {
    let Some(r) = renderer() else { return };
    let scene = example("two_cubes_touching");
    let v = r.render_pixels(&scene, CornerView::Sw, &photo()).unwrap();
    // The contact plane x = 0 meets the common front face z = 7.5 along a vertical crack.
    let crack_min = (-2..=2)
        .map(|d| {
            let p = v.camera.picture_from_world(DVec3::new(0.0, 3.75, 7.5));
            let h = v.gray.height() as f64;
            v.gray
                .get_pixel((p.x.floor() as i64 + d) as u32, (h - p.y).floor() as u32)[0]
        })
        .min()
        .unwrap();
    let beside =
        gray_at(&v, DVec3::new(-2.0, 3.75, 7.5)).min(gray_at(&v, DVec3::new(2.0, 3.75, 7.5)));
    assert!(
        crack_min + 20 < beside,
        "crack {crack_min}, faces beside {beside}"
    );
    // Moved 2 mm apart the faces do not touch: no black sheet.
    let mut apart = scene.clone();
    apart.blocks[1].center_mm.x += 2.0;
    let contacts = blockworld::render::photo::mesh::find_contacts(&apart);
    assert!(contacts.sheets.is_empty());
}

#[test]
fn noise_and_light_are_seeded_and_the_picture_is_deterministic() {
    let Some(r) = renderer() else { return };
    let scene = example("thesis_sample");
    let with = |seed: u64, jitter: f64| {
        let mut o = photo();
        o.seed = seed;
        o.photo.light_jitter_deg = jitter;
        r.render_pixels(&scene, CornerView::Nw, &o).unwrap().gray
    };
    let a = with(3, 0.0);
    assert!(a == with(3, 0.0), "same seed, same bytes");
    assert!(a != with(4, 0.0), "another seed, other noise and albedos");
    let mut quiet = photo();
    quiet.photo.sensor = sensor::SensorModel::IDEAL;
    quiet.photo.block_albedo_range = [0.9, 0.9];
    let q3 = {
        quiet.seed = 3;
        r.render_pixels(&scene, CornerView::Nw, &quiet)
            .unwrap()
            .gray
    };
    let q4 = {
        quiet.seed = 4;
        r.render_pixels(&scene, CornerView::Nw, &quiet)
            .unwrap()
            .gray
    };
    assert!(
        q3 == q4,
        "without noise, jitter or albedo range the seed changes nothing"
    );
    quiet.photo.light_jitter_deg = 20.0;
    let j3 = r
        .render_pixels(&scene, CornerView::Nw, &quiet)
        .unwrap()
        .gray;
    assert!(j3 != q4, "the jittered light turns");
}

#[test]
fn downsampled_views_describe_the_written_picture() {
    let Some(r) = renderer() else { return };
    let scene = example("thesis_sample");
    let full = r
        .render(&scene, CornerView::Ne, &RenderOptions::default())
        .unwrap();
    for look in [Look::LineArt, Look::Photo] {
        for factor in [2u32, 4] {
            let opts = RenderOptions {
                look,
                downsample: factor,
                ..Default::default()
            };
            let small = r.render(&scene, CornerView::Ne, &opts).unwrap();
            let size = [512 / factor, 480 / factor];
            assert_eq!(small.camera.size_px, size);
            assert_eq!(small.gray.dimensions(), (size[0], size[1]));
            assert_eq!(small.depth.dimensions(), (size[0], size[1]));
            assert_eq!(small.ids.dimensions(), (size[0], size[1]));
            assert_eq!(small.lines.lines, full.lines.lines);
            for (p, q) in small.lines.points.iter().zip(&full.lines.points) {
                assert!((*p - *q / factor as f64).length() < 1e-6, "{p} vs {q}");
            }
            if look == Look::LineArt {
                let expected = sensor::downsample(&full.gray, factor);
                assert!(small.gray == expected, "line art averaged {factor}x");
            }
        }
    }
    let bad = RenderOptions {
        downsample: 3,
        ..Default::default()
    };
    let e = r
        .render(&scene, CornerView::Ne, &bad)
        .unwrap_err()
        .to_string();
    assert!(e.contains("downsample 3"), "{e}");
}

#[test]
fn the_photo_parts_give_render_pixels_whole_view_and_leave_out_what_they_say() {
    let Some(r) = renderer() else { return };
    let scene = example("thesis_sample");
    let mut o = photo();
    o.seed = 5;
    let view = CornerView::Ne;
    let setup = PhotoSetup::new(&scene, view, &o);
    let whole = r
        .render_photo_parts(&scene, view, &o, &setup, PhotoParts::ALL)
        .unwrap();
    let direct = r.render_pixels(&scene, view, &o).unwrap();
    assert!(whole.gray == direct.gray, "the bench times the real view");
    assert!(whole.depth == direct.depth && whole.ids == direct.ids);
    assert!(direct.ids.iter().any(|&i| i > 0));
    // Without the sensor and the ground truth: the radiance scaled to 8 bits, blank truth.
    let raw = PhotoParts {
        sensor: false,
        truth: false,
    };
    let shaded = r.render_photo_parts(&scene, view, &o, &setup, raw).unwrap();
    assert!(shaded.depth.iter().all(|&d| d == 0) && shaded.ids.iter().all(|&i| i == 0));
    assert!(
        shaded.gray != whole.gray,
        "no blur, noise, gamma or vignetting"
    );
    // Without shadows no pixel is darker, and the blocks' shadows are gone.
    let bare = r
        .render_photo_parts(&scene, view, &o, &setup.without_shadows(), raw)
        .unwrap();
    let pairs = || bare.gray.iter().zip(shaded.gray.iter());
    assert_eq!(pairs().filter(|(b, s)| b < s).count(), 0);
    let lit = pairs().filter(|(b, s)| b > s).count();
    assert!(lit > 1000, "only {lit} pixels were in shadow");
}

#[test]
fn bench_render_photo_parts_prints_a_row_per_size_and_refuses_photo_only_beside_it() {
    let Some(_) = renderer() else { return };
    let run = |extra: &[&str]| {
        let args = ["bench", "render", "--iterations", "4", "--blocks", "1,3"];
        common::blockworld(args.iter().chain(extra))
    };
    let o = run(&["--photo-parts"]);
    let out = String::from_utf8_lossy(&o.stdout);
    common::ok(&o);
    let rows: Vec<&str> = out
        .lines()
        .filter(|l| l.starts_with("| 1 |") || l.starts_with("| 3 |"))
        .collect();
    assert_eq!(rows.len(), 2, "{out}");
    for row in rows {
        assert_eq!(row.matches('|').count(), 10, "{row}");
        assert!(row.ends_with(" x |"), "{row}");
    }
    let o = run(&["--photo-parts", "--photo-only"]);
    assert_eq!(o.status.code(), Some(2));
}

/// The varied look lights a face turned from every light by the floor's bounce
/// (`KeyLight::floor_bounce`, docs/varied-look.md "What is drawn"): a cube's shaded side is
/// brighter over a light floor than over a dark one, by the block's albedo times the
/// difference of the two floors' bounces, while its top, which sees only the sky, is the same.
#[test]
fn a_shaded_side_is_lit_by_the_floor_beneath_and_the_top_is_not() {
    let Some(r) = renderer() else { return };
    let cube = Scene::new("c", vec![Block::new("b15", DVec3::new(0.0, 7.5, 0.0), 0.0)]);
    let view = CornerView::Ne;
    // NE camera at +x, -z: the visible sides are +x and -z; take a draw with one light that
    // one of them is turned from.
    let (mut draw, side) = (0..200)
        .find_map(|seed| {
            let d = LookDraw::draw(seed, 1, 35.264);
            let l = DVec3::from_array(d.lights[0].in_view(view).towards_light);
            let side = [DVec3::X, -DVec3::Z]
                .into_iter()
                .find(|n| n.dot(l) < -0.1)?;
            (d.lights.len() == 1).then_some((d, side))
        })
        .expect("a one-light draw with a side turned from it");
    let base = RenderOptions {
        look: Look::PhotoVaried,
        ..Default::default()
    };
    let raw = PhotoParts {
        sensor: false,
        truth: false,
    };
    let mut render = |floor_albedo: f64| {
        draw.floor_albedo = floor_albedo;
        let opts = draw.render_options(&base);
        let setup = &PhotoSetup::varied(&cube, view, &opts, &draw)[0];
        let v = r
            .render_photo_parts(&cube, view, &opts, setup, raw)
            .unwrap();
        let bounce = draw.key_lights(view)[0].floor_bounce;
        let at = |p: DVec3| f64::from(gray_at(&v, p));
        (
            at(DVec3::new(0.0, 15.0, 0.0)),
            at(side * 7.5 + DVec3::Y * 7.5),
            bounce,
        )
    };
    let (dark_top, dark_side, dark_bounce) = render(0.1);
    let (light_top, light_side, light_bounce) = render(0.8);
    let albedo = draw.block_albedos[0];
    let expected = 255.0 * albedo * (light_bounce - dark_bounce);
    assert!(
        expected > 10.0,
        "the two floors' bounces differ by {expected} levels"
    );
    assert!(
        (light_side - dark_side - expected).abs() <= 2.0,
        "shaded side {dark_side} over the dark floor, {light_side} over the light one; expected {expected} levels more"
    );
    assert!(
        (light_top - dark_top).abs() <= 1.0,
        "top {dark_top} vs {light_top}"
    );
}
