//! The photographic look's declined scenes, broken down (docs/rendering.md "Photographic look"): for each
//! supported scene of `scenes/bench` the recognizer does not answer exactly from its photo
//! pictures, whether the truth itself passes step 6's check against the vision drawings (then
//! the search never proposed it) or which view and feature refuse it, and what the picture
//! shows along each such feature. The truth is read here, in the analysis, never inside the
//! recognizer. Run with
//! `cargo test --release --test photo_breakdown -- --ignored --nocapture` (`NOISE`, `SEED`,
//! `DOWNSAMPLE` and `ONLY=s000003,s000004` as the names say).

mod common;
use common::same_blocks;

use blockworld::camera::CornerView;
use blockworld::drawing::LineDrawing;
use blockworld::pipeline::{observe, DrawingSource};
use blockworld::recognize::steps::{
    edge_profile, mismatched_features, pictures_mismatch, ViewPicture,
};
use blockworld::recognize::{draw_hypothesis, recognize, recognize_in_pictures, RecognizeOptions};
use blockworld::render::{Look, RenderOptions};
use blockworld::scene::{read_scene, ReconStatus};
use blockworld::vision::VisionOptions;

/// How far (mm) an answer's corners may lie from the truth's for the breakdown to call it the
/// truth's block.
const SAME_CORNER_MM: f64 = 1.0;

fn line_text(d: &LineDrawing, k: usize, pic: &ViewPicture) -> String {
    let [i, j] = d.lines[k];
    let (a, b) = (d.points[i], d.points[j]);
    let p = edge_profile(pic, a, b);
    let contact = d.edges.get(k).is_some_and(|e| e.contact);
    format!(
        "({:.1},{:.1})-({:.1},{:.1}) len {:.1}{} n {} off {:+.1} step {:+.1} share {:.2} crack {:.2}",
        a.x,
        a.y,
        b.x,
        b.y,
        a.distance(b),
        if contact { " contact" } else { "" },
        p.samples,
        p.step_offset_px,
        p.step_levels,
        p.step_share,
        p.crack_share
    )
}

fn nearest(p: blockworld::geom::DVec2, pts: &[blockworld::geom::DVec2]) -> f64 {
    pts.iter()
        .map(|q| q.distance(p))
        .fold(f64::INFINITY, f64::min)
}

#[test]
#[ignore = "analysis: prints the photo look's declined scenes broken down"]
fn photo_declines_broken_down() {
    let Some(renderer) = common::renderer() else {
        return;
    };
    let noise: f64 = std::env::var("NOISE")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0.0);
    let only = std::env::var("ONLY").ok();
    let render = RenderOptions {
        look: Look::Photo,
        noise_sigma: noise,
        // `bench accuracy`'s default seed 0 (`SEED` as its `--seed`): the sensor's noise is
        // seeded, and the verdicts can change with it.
        seed: std::env::var("SEED")
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(0),
        downsample: std::env::var("DOWNSAMPLE")
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(1),
        ..RenderOptions::default()
    };
    let opts = RecognizeOptions::default();
    let tol = opts.tol_px;
    let (mut exact_plain, mut exact_pictures, mut wrong, mut supported) = (0, 0, 0, 0);
    for path in common::json_files(&common::root().join("scenes/bench")) {
        let id = common::stem(&path);
        if only
            .as_ref()
            .is_some_and(|o| !o.split(',').any(|x| x == id))
        {
            continue;
        }
        let scene = read_scene(&path).unwrap();
        if !scene.is_supported() {
            continue;
        }
        supported += 1;
        let rendered = renderer
            .render_views(&scene, &CornerView::ALL, &render)
            .unwrap();
        let source = DrawingSource::Pictures(VisionOptions::default());
        let (views, _) = observe(&rendered, &source).unwrap();
        let pictures: Vec<_> = rendered.iter().map(|r| &r.gray).collect();
        let plain = recognize(&views, &opts).unwrap();
        let with = recognize_in_pictures(&views, &pictures, &opts).unwrap();
        let ok_plain = plain.status == ReconStatus::Ok
            && same_blocks(&plain.blocks, &scene.blocks, SAME_CORNER_MM);
        let ok_with = with.status == ReconStatus::Ok
            && same_blocks(&with.blocks, &scene.blocks, SAME_CORNER_MM);
        exact_plain += usize::from(ok_plain);
        exact_pictures += usize::from(ok_with);
        if with.status == ReconStatus::Ok && !ok_with {
            wrong += 1;
            println!(
                "!!! {id} CONFIDENTLY WRONG with pictures: {:?}",
                with.blocks
            );
        }
        if ok_plain && ok_with {
            continue;
        }
        let hyp_truth = same_blocks(&with.evidence.hypothesis, &scene.blocks, SAME_CORNER_MM);
        // What a wrong answer's check forgave, else what refuses the truth.
        let shown = if with.status == ReconStatus::Ok && !ok_with {
            println!("   (below: the wrong answer's features)");
            with.blocks.clone()
        } else {
            scene.blocks.clone()
        };
        println!(
            "== {id} ({} blocks): plain {} / pictures {} ({}); hypothesis is truth: {hyp_truth}",
            scene.blocks.len(),
            if ok_plain { "exact" } else { "no" },
            if ok_with { "exact" } else { "no" },
            with.reason.clone().unwrap_or_default()
        );
        // The blocks of a wrong hypothesis that are not the truth's, and the truth's it lacks.
        let describe = |b: &blockworld::scene::Block| {
            format!("{} at {:.1?}", b.block_type.id, b.center_mm.to_array())
        };
        let differs = |a: &[blockworld::scene::Block], b: &[blockworld::scene::Block]| {
            a.iter()
                .filter(|x| !b.iter().any(|t| same_blocks(&[**x], &[*t], SAME_CORNER_MM)))
                .map(describe)
                .collect::<Vec<_>>()
        };
        if !hyp_truth {
            println!(
                "  hypothesis only: {:?}; truth only: {:?}",
                differs(&with.evidence.hypothesis, &scene.blocks),
                differs(&scene.blocks, &with.evidence.hypothesis)
            );
        }
        let truths: Vec<LineDrawing> = views
            .iter()
            .map(|v| draw_hypothesis(&shown, &v.camera))
            .collect();
        let pics: Vec<ViewPicture> = rendered
            .iter()
            .map(|r| ViewPicture::new(&r.gray, &r.camera))
            .collect();
        let observed: Vec<&LineDrawing> = views.iter().map(|v| &v.drawing).collect();
        let lefts = pictures_mismatch(&truths, &observed, &pics, tol);
        for (k, v) in views.iter().enumerate() {
            let (truth, pic, left) = (&truths[k], &pics[k], &lefts[k]);
            let m = mismatched_features(truth, &v.drawing, tol);
            if m.counts().is_explained() {
                continue;
            }
            println!(
                "  view {}: truth vs drawing {:?}; after picture {:?} (noise {:.2})",
                v.camera.view.name(),
                m.counts(),
                left.counts(),
                pic.noise_levels
            );
            let mark = |left: &[usize], k: usize| if left.contains(&k) { "LEFT" } else { "ok  " };
            for &k in &m.extra_lines {
                println!(
                    "    {} missing edge  {}",
                    mark(&left.extra_lines, k),
                    line_text(truth, k, pic)
                );
            }
            for &k in &m.unexplained_lines {
                println!(
                    "    {} unexplained   {}",
                    mark(&left.unexplained_lines, k),
                    line_text(&v.drawing, k, pic)
                );
            }
            for &p in &m.extra_points {
                println!(
                    "    {} missing point ({:.1},{:.1}) nearest observed {:.2}",
                    mark(&left.extra_points, p),
                    truth.points[p].x,
                    truth.points[p].y,
                    nearest(truth.points[p], &v.drawing.points)
                );
            }
            for &p in &m.unexplained_points {
                println!(
                    "    {} extra point   ({:.1},{:.1}) nearest drawn {:.2}",
                    mark(&left.unexplained_points, p),
                    v.drawing.points[p].x,
                    v.drawing.points[p].y,
                    nearest(v.drawing.points[p], &truth.points)
                );
            }
        }
    }
    println!(
        "supported {supported}: exact without pictures {exact_plain}, with pictures {exact_pictures}, confidently wrong with pictures {wrong}"
    );
}
