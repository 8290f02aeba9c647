//! The recognizer end to end on exact views: stacks, perspective, bad input, wedges.

use super::*;
use crate::camera::{CameraOptions, CornerView, Projection};
use crate::geom::DVec3;
use crate::scene::{same_blocks, Block, ReconStatus};

#[test]
fn a_two_layer_stack_is_recognized_from_two_opposite_views() {
    let truth = vec![
        Block::new("b30", DVec3::new(15.0, 7.5, 7.5), 0.0),
        Block::new("b15", DVec3::new(7.5, 22.5, 7.5), 0.0),
    ];
    let views = views_of(&truth, &[CornerView::Ne, CornerView::Sw]);
    let r = recognize(&views, &RecognizeOptions::default()).unwrap();
    assert_eq!(r.status, ReconStatus::Ok, "{:?}", r.reason);
    assert_eq!(r.blocks.len(), 2);
    for t in &truth {
        assert!(r.blocks.iter().any(
            |b| b.block_type.id == t.block_type.id && b.center_mm.distance(t.center_mm) < 1e-6
        ));
    }
    assert_eq!(r.layers.len(), 2);
    assert_eq!(r.touching, vec![[0, 1]]);
}

#[test]
fn a_perspective_view_pair_is_recognized_too() {
    let truth = vec![Block::new("b30", DVec3::new(15.0, 7.5, 7.5), 90.0)];
    let pts: Vec<DVec3> = truth[0].world_vertices();
    let opts = CameraOptions {
        projection: Projection::Perspective { fov_y_deg: 30.0 },
        ..CameraOptions::default()
    };
    let views: Vec<ObservedView> = [CornerView::Ne, CornerView::Sw]
        .iter()
        .map(|&v| {
            let camera = Camera::frame(&pts, v, &opts);
            ObservedView::new(draw_hypothesis(&truth, &camera), camera)
        })
        .collect();
    let r = recognize(&views, &RecognizeOptions::default()).unwrap();
    assert_eq!(r.status, ReconStatus::Ok, "{:?}", r.reason);
    assert!(r.blocks[0].center_mm.distance(truth[0].center_mm) < 0.05);
}

#[test]
fn bad_input_is_an_error_and_a_turned_block_is_declined_by_name() {
    assert_eq!(
        recognize(&[], &RecognizeOptions::default()),
        Err(RecognizeError::NoViews)
    );
    let cube = vec![Block::new("b15", DVec3::new(0.0, 7.5, 0.0), 0.0)];
    let mut views = views_of(&cube, &[CornerView::Ne]);
    views[0].drawing.lines.push([0, 99]);
    assert!(matches!(
        recognize(&views, &RecognizeOptions::default()),
        Err(RecognizeError::BadDrawing { .. })
    ));
    let turned = vec![Block::new("b15", DVec3::new(0.0, 7.5, 0.0), 30.0)];
    let r = recognize(
        &views_of(&turned, &[CornerView::Ne]),
        &RecognizeOptions::default(),
    )
    .unwrap();
    assert_eq!(r.status, ReconStatus::Unsupported);
    assert!(r.reason.unwrap().contains("not in one direction"));
}

/// Chapter VII, Figure 7.1: a trapezoidal block facing each of the four ways, alone, on a
/// Baustein 30 and carrying a cube on its flat top, is reconstructed with its turn from the
/// four views.
#[test]
fn wedges_facing_each_way_are_reconstructed_with_their_turn() {
    for yaw in [0.0, 90.0, 180.0, 270.0] {
        let wedge = |y: f64| Block::new("w30", DVec3::new(0.0, y, 0.0), yaw);
        let flat_top = wedge(0.0).world_point(DVec3::new(-7.5, 22.5, 0.0));
        let b30_yaw = if yaw % 180.0 == 0.0 { 0.0 } else { 90.0 };
        let scenes = [
            vec![wedge(7.5)],
            vec![
                Block::new("b30", DVec3::new(0.0, 7.5, 0.0), b30_yaw),
                wedge(22.5),
            ],
            vec![wedge(7.5), Block::new("b15", flat_top, 0.0)],
        ];
        for truth in scenes {
            let views = views_of(&truth, &CornerView::ALL);
            let r = recognize(&views, &RecognizeOptions::default()).unwrap();
            assert_eq!(
                r.status,
                ReconStatus::Ok,
                "yaw {yaw} {truth:?}: {:?}",
                r.reason
            );
            assert!(
                same_blocks(&r.blocks, &truth, 0.05),
                "yaw {yaw}: {:?}",
                r.blocks
            );
        }
    }
}

/// The check (step 6) refuses a wedge turned the wrong way: the true wedge's drawing explains
/// every view, the same box facing any other way leaves some view unexplained.
#[test]
fn a_wedge_turned_the_wrong_way_is_refused_by_the_check() {
    let truth = [Block::new("w30", DVec3::new(0.0, 7.5, 0.0), 0.0)];
    let views = views_of(&truth, &CornerView::ALL);
    let explained = |b: &[Block]| {
        check_hypothesis(b, &views, 2.0)
            .iter()
            .all(ViewCheck::is_explained)
    };
    assert!(explained(&truth));
    for yaw in [90.0, 180.0, 270.0] {
        let turned = [Block::new("w30", truth[0].center_mm, yaw)];
        assert!(!explained(&turned), "yaw {yaw} explains the views");
    }
    // Nor does the box the wedge fills: a Baustein 30 there.
    assert!(!explained(&[Block::new("b30", truth[0].center_mm, 0.0)]));
}

/// Empty drawings (a blank or tiny picture) hold no block: the answer declines, as an answer
/// without blocks explains nothing.
#[test]
fn empty_views_are_declined_not_answered_with_no_blocks() {
    let cube = vec![Block::new("b15", DVec3::new(0.0, 7.5, 0.0), 0.0)];
    let mut views = views_of(&cube, &[CornerView::Ne, CornerView::Sw]);
    for v in &mut views {
        v.drawing = crate::drawing::LineDrawing::from_arrays(&[], &[]);
    }
    let r = recognize(&views, &RecognizeOptions::default()).unwrap();
    assert_eq!(r.status, ReconStatus::Unsupported);
    let reason = r.reason.unwrap();
    assert!(reason.contains("no block found"), "{reason}");
    assert_eq!(answer::decline_kind(&reason), "no blocks");
}
