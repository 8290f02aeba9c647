//! The thesis's Figures 6.7-6.12 (Chapter VI "Display the Final Sample") redrawn by the viewer
//! from scenes/thesis_sample.json and compared exactly with `golden/viewer/*.png`: Up at
//! (1, 0, 0), (0, 0, 1), (0, 1, 0) and (2, 1, 3); From moved toward the object until clipping
//! cuts it (view angle 60); the same with view angle 30. The viewer is a CPU rasterizer, so
//! no adapter is needed and the comparison is exact. The thesis's own From and At values are
//! not in the text (its figures are lost), so these views fix their own.

mod common;

use blockworld::geom::DVec3;
use blockworld::scene::read_scene;
use blockworld::view::{
    draw_sheet, rasterize_sheet, wire_model, HiddenLines, Role, Sheet, SheetOptions, ThesisFigure,
    ViewParams, WireModel, THESIS_FIGURES,
};
use common::{compare_golden, Tolerance};
use image::{DynamicImage, GrayImage};

/// Exact: the viewer's lines, fills and font are integer or repeatable floating point on the
/// CPU; nothing but a change of the code moves a pixel.
const EXACT: Tolerance = Tolerance {
    max_differing_share: 0.0,
    max_abs_diff: 0,
};

fn draw(fig: &ThesisFigure) -> Sheet {
    let scene = read_scene(&common::root().join("scenes/thesis_sample.json")).unwrap();
    let model = wire_model(&scene, Role::Model);
    let params = fig.params().unwrap();
    let opts = SheetOptions {
        size_px: [400, 400],
        hidden_lines: HiddenLines::Show,
        ..SheetOptions::default()
    };
    draw_sheet(&[model], &params, &opts).unwrap()
}

/// The picture as gray levels, after checking it has no colour (so nothing is lost).
fn gray(sheet: &Sheet) -> GrayImage {
    let rgb = rasterize_sheet(sheet);
    assert!(
        rgb.pixels().all(|p| p[0] == p[1] && p[1] == p[2]),
        "a plain view is gray"
    );
    DynamicImage::ImageRgb8(rgb).into_luma8()
}

#[test]
fn figures_6_7_to_6_12_match_their_goldens() {
    let mut failures = Vec::new();
    for fig in &THESIS_FIGURES {
        let sheet = draw(fig);
        if let Err(e) = compare_golden(&format!("viewer/{}", fig.name), &gray(&sheet), EXACT) {
            failures.push(e);
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn only_the_moved_from_figures_are_clipped_and_the_smaller_angle_clips_more() {
    let counts: Vec<(usize, usize)> = THESIS_FIGURES
        .iter()
        .map(|f| {
            let p = &draw(f).panels[0];
            (p.clipped_lines, p.lines.len())
        })
        .collect();
    for (fig, (clipped, drawn)) in THESIS_FIGURES.iter().zip(&counts) {
        eprintln!("{}: {clipped} clipped, {drawn} drawn", fig.name);
    }
    // Figures 6.7-6.10: the whole sample is in view, all 60 edges (5 blocks x 12).
    assert!(counts[..4].iter().all(|&(c, d)| c == 0 && d == 60));
    // Figure 6.11: clipping cuts it; Figure 6.12 (30 degrees) cuts more.
    assert!(counts[4].0 > 0);
    assert!(counts[5].0 > counts[4].0 || counts[5].1 < counts[4].1);
}

/// The picture heights (px) of the sample's bottom and top at its middle, through `params`.
fn bottom_and_top_px(params: &ViewParams) -> (f64, f64) {
    let edge = WireModel {
        role: Role::Model,
        vertices_mm: vec![DVec3::new(22.5, 0.0, 7.5), DVec3::new(22.5, 30.0, 7.5)],
        faces: Vec::new(),
        edges: vec![[0, 1]],
    };
    let sheet = draw_sheet(&[edge], params, &SheetOptions::default()).unwrap();
    let l = sheet.panels[0].lines[0];
    (l.a_px.y, l.b_px.y)
}

#[test]
fn the_up_direction_is_up_in_the_picture() {
    // Figure 6.9 (Up = +y): the top of the sample is drawn above its bottom.
    let params = draw(&THESIS_FIGURES[2]).panels[0].params;
    let (bottom, top) = bottom_and_top_px(&params);
    assert!(
        top > bottom + 50.0,
        "top {top} must be above bottom {bottom}"
    );
    // The check can fail: Up = -y (what eq. 2.5's printed U' = A - U amounts to) turns it over.
    let flipped = ViewParams {
        up: -DVec3::Y,
        ..params
    };
    let (bottom, top) = bottom_and_top_px(&flipped);
    assert!(top < bottom);
}

#[test]
fn the_plain_view_is_the_same_bytes_twice() {
    let a = rasterize_sheet(&draw(&THESIS_FIGURES[4]));
    let b = rasterize_sheet(&draw(&THESIS_FIGURES[4]));
    assert_eq!(a.as_raw(), b.as_raw());
}

#[test]
fn the_thesis_viewing_system_is_the_cameras_look_at_with_z_turned_into_the_screen() {
    // The viewer builds eq. 2.2-2.5 itself, in the thesis's left-handed system; the renderer's
    // camera uses glam's right-handed look-at. They must be the same view: x and y agree, z
    // flips sign.
    let cases = [
        (
            DVec3::new(82.5, 60.0, 75.0),
            DVec3::new(22.5, 15.0, 15.0),
            DVec3::Y,
        ),
        (
            DVec3::new(-40.0, 10.0, 5.0),
            DVec3::new(3.0, 4.0, -2.0),
            DVec3::new(2.0, 1.0, 3.0),
        ),
        (DVec3::new(0.0, 0.0, -50.0), DVec3::ZERO, DVec3::X),
    ];
    for (f, a, u) in cases {
        let thesis = blockworld::view::ViewingTransform::new(f, a, u, 60.0, (1.0, 500.0)).unwrap();
        let camera = blockworld::camera::look_at(f, a, u);
        for p in [DVec3::ZERO, DVec3::new(10.0, -3.0, 7.0), a + u] {
            let e = thesis.eye(p);
            let c = camera.transform_point3(p);
            assert!(
                (e - DVec3::new(c.x, c.y, -c.z)).length() < 1e-9,
                "{f} {a} {u}: {e} vs {c}"
            );
        }
    }
}
