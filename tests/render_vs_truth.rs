//! Every ground-truth visible line lies on an intensity edge of the rendered image, and
//! no rendered intensity edge lacks a line. The drawing comes from geometry (`linedraw`),
//! the picture from wgpu on lavapipe, so this ties the two together, seams included.

use blockworld::camera::CornerView;
use blockworld::drawing::LineDrawing;
use blockworld::geom::DVec3;
use blockworld::render::RenderOptions;
use blockworld::scene::{read_scene, Block, Scene};
use image::GrayImage;

mod common;
use common::{distance_to_segment, renderer};

/// Two neighbouring pixels whose gray levels differ by at least this are an intensity edge.
const EDGE_STEP: i16 = 8;
/// A line sample is "on an edge" when an edge pixel centre lies within this distance (px).
/// Bounded by the seam: about 1 px wide, centred on the exact line.
const ON_EDGE_PX: f64 = 1.5;
/// An edge pixel is "explained" when a drawn line passes within this distance (px) of its centre.
const EXPLAINED_PX: f64 = 2.0;

fn edge_pixels(img: &GrayImage) -> Vec<(u32, u32)> {
    let (w, h) = img.dimensions();
    let at = |x: u32, y: u32| img.get_pixel(x, y)[0] as i16;
    let mut out = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let v = at(x, y);
            let mut edge = false;
            for (dx, dy) in [(1i32, 0i32), (0, 1), (-1, 0), (0, -1)] {
                let (nx, ny) = (x as i32 + dx, y as i32 + dy);
                if nx >= 0 && ny >= 0 && (nx as u32) < w && (ny as u32) < h {
                    edge |= (at(nx as u32, ny as u32) - v).abs() >= EDGE_STEP;
                }
            }
            if edge {
                out.push((x, y));
            }
        }
    }
    out
}

/// Picture coordinates (x right, y up) of a raster pixel's centre.
fn centre(x: u32, row: u32, h: u32) -> (f64, f64) {
    (x as f64 + 0.5, h as f64 - row as f64 - 0.5)
}

fn segments(d: &LineDrawing) -> Vec<((f64, f64), (f64, f64))> {
    d.lines
        .iter()
        .map(|&[a, b]| {
            let (p, q) = (d.points[a], d.points[b]);
            ((p.x, p.y), (q.x, q.y))
        })
        .collect()
}

/// Checks one view; returns a description of each disagreement.
fn check_view(img: &GrayImage, drawing: &LineDrawing) -> Vec<String> {
    let (w, h) = img.dimensions();
    let edges = edge_pixels(img);
    let mut is_edge = vec![false; (w * h) as usize];
    for &(x, y) in &edges {
        is_edge[(y * w + x) as usize] = true;
    }
    let segs = segments(drawing);
    let mut problems = Vec::new();
    // 1. Every line sample (1 px apart, 2 px clear of its ends) has an edge pixel nearby.
    for (i, &(a, b)) in segs.iter().enumerate() {
        let len = ((b.0 - a.0).powi(2) + (b.1 - a.1).powi(2)).sqrt();
        let mut missed = 0;
        let mut s = 2.0;
        while s <= len - 2.0 {
            let t = s / len;
            let p = (a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1));
            let (cx, cy) = (p.0.floor() as i64, (h as f64 - p.1).floor() as i64);
            let mut found = false;
            for yy in cy - 2..=cy + 2 {
                for xx in cx - 2..=cx + 2 {
                    if xx < 0 || yy < 0 || xx >= w as i64 || yy >= h as i64 {
                        continue;
                    }
                    let c = centre(xx as u32, yy as u32, h);
                    let near = ((c.0 - p.0).powi(2) + (c.1 - p.1).powi(2)).sqrt() <= ON_EDGE_PX;
                    found |= near && is_edge[(yy as u32 * w + xx as u32) as usize];
                }
            }
            missed += usize::from(!found);
            s += 1.0;
        }
        if missed > 0 {
            problems.push(format!(
                "line {i} {a:?}-{b:?}: {missed} samples off any intensity edge"
            ));
        }
    }
    // 2. Every intensity edge pixel lies near a drawn line.
    let unexplained: Vec<(u32, u32)> = edges
        .iter()
        .copied()
        .filter(|&(x, y)| {
            let c = centre(x, y, h);
            !segs
                .iter()
                .any(|&(a, b)| distance_to_segment(c.into(), a.into(), b.into()) <= EXPLAINED_PX)
        })
        .collect();
    if !unexplained.is_empty() {
        problems.push(format!(
            "{} intensity-edge pixels with no line within {EXPLAINED_PX} px, e.g. {:?}",
            unexplained.len(),
            &unexplained[..unexplained.len().min(5)]
        ));
    }
    problems
}

fn scenes() -> Vec<Scene> {
    let b = |id: &str, x: f64, y: f64, z: f64, yaw: f64| Block::new(id, DVec3::new(x, y, z), yaw);
    let mut out = vec![
        Scene::new("cube", vec![b("b15", 0.0, 7.5, 0.0, 0.0)]),
        Scene::new(
            "two_b15_side_by_side",
            vec![b("b15", -7.5, 7.5, 0.0, 0.0), b("b15", 7.5, 7.5, 0.0, 0.0)],
        ),
        Scene::new(
            "two_b15_stacked",
            vec![b("b15", 0.0, 7.5, 0.0, 0.0), b("b15", 0.0, 22.5, 0.0, 0.0)],
        ),
        Scene::new(
            "b15_on_b30_flush_end",
            vec![b("b30", 0.0, 7.5, 0.0, 0.0), b("b15", 7.5, 22.5, 0.0, 0.0)],
        ),
        Scene::new(
            "mixed",
            vec![
                b("b30", 0.0, 7.5, 0.0, 90.0),
                b("b15", 15.0, 7.5, -7.5, 0.0),
                b("b7_5", 15.0, 18.75, -7.5, 0.0),
                b("b15", 0.0, 22.5, 7.5, 0.0),
            ],
        ),
    ];
    out.push(read_scene(&common::root().join("scenes/thesis_sample.json")).unwrap());
    out
}

/// The accuracy suite's settled scenes (`scenes/bench/*.json`), sorted by name.
fn suite_scenes() -> Vec<Scene> {
    common::json_files(&common::root().join("scenes/bench"))
        .iter()
        .map(|p| read_scene(p).unwrap())
        .collect()
}

#[test]
fn the_accuracy_suite_renders_every_truth_line_and_only_those() {
    let Some(r) = renderer() else { return };
    let opts = RenderOptions::default();
    let scenes = suite_scenes();
    assert!(scenes.len() >= 60, "the suite has {} scenes", scenes.len());
    let mut failures = Vec::new();
    for scene in scenes {
        for view in CornerView::ALL {
            let v = r.render(&scene, view, &opts).unwrap();
            for p in check_view(&v.gray, &v.lines) {
                failures.push(format!("{} {}: {p}", scene.name, view.name()));
            }
        }
    }
    assert!(
        failures.is_empty(),
        "{} views disagree:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

#[test]
fn every_truth_line_is_an_intensity_edge_and_every_edge_a_line() {
    let Some(r) = renderer() else { return };
    let opts = RenderOptions::default();
    let mut failures = Vec::new();
    for scene in scenes() {
        scene.validate(&scene.name).unwrap();
        for view in CornerView::ALL {
            let v = r.render(&scene, view, &opts).unwrap();
            assert!(
                !v.lines.lines.is_empty(),
                "{} {}: empty drawing",
                scene.name,
                view.name()
            );
            for p in check_view(&v.gray, &v.lines) {
                failures.push(format!("{} {}: {p}", scene.name, view.name()));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn the_check_catches_a_missing_line() {
    let Some(r) = renderer() else { return };
    let scene = Scene::new(
        "two_b15_side_by_side",
        vec![
            Block::new("b15", DVec3::new(-7.5, 7.5, 0.0), 0.0),
            Block::new("b15", DVec3::new(7.5, 7.5, 0.0), 0.0),
        ],
    );
    let v = r
        .render(&scene, CornerView::Ne, &RenderOptions::default())
        .unwrap();
    assert!(check_view(&v.gray, &v.lines).is_empty());
    // Drop the cracks: their seams become unexplained edges.
    let mut d = v.lines.clone();
    let keep: Vec<usize> = (0..d.lines.len())
        .filter(|&i| d.kinds[i] != blockworld::drawing::LineKind::Crack)
        .collect();
    assert!(keep.len() < d.lines.len(), "the scene has cracks");
    d.lines = keep.iter().map(|&i| d.lines[i]).collect();
    assert!(!check_view(&v.gray, &d).is_empty());
    // Shift the drawing by 3 px: lines leave their edges.
    let mut shifted = v.lines.clone();
    for p in &mut shifted.points {
        p.x += 3.0;
    }
    assert!(!check_view(&v.gray, &shifted).is_empty());
}
