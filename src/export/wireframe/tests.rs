use super::*;
use crate::drawing::{Junction, LineDrawing, LineKind, SixBitCode};

/// An asymmetric L of two lines in a 100 x 80 picture (y up): a corner low on the left.
fn corner() -> LineDrawing {
    LineDrawing {
        points: vec![
            DVec2::new(10.0, 10.0),
            DVec2::new(60.0, 10.0),
            DVec2::new(10.0, 70.0),
        ],
        lines: vec![[0, 1], [0, 2]],
        codes: vec![SixBitCode(9), SixBitCode(0), SixBitCode(0)],
        junctions: vec![Junction::L, Junction::End, Junction::End],
        kinds: vec![LineKind::Boundary, LineKind::Convex],
        ..Default::default()
    }
}

#[test]
fn y_is_flipped_exactly_and_extras_ride_along() {
    let wf = wireframe_from_drawing(&corner(), 100, 80).unwrap();
    // y' = H - y: the corner low in the picture (y up 10) is near the bottom row (y down 70).
    assert_eq!(wf.junctions[0].xy_px, [10.0, 70.0]);
    assert_eq!(wf.line_px(1), [10.0, 70.0, 10.0, 10.0]);
    assert_eq!(wf.junctions[0].junction_type, "L");
    assert_eq!(wf.junctions[0].six_bit_code, Some(9));
    assert_eq!(
        wf.line_kinds,
        [Some(LineKind::Boundary), Some(LineKind::Convex)]
    );
    assert_eq!(wf.border_ends(0), [false, false]);
}

#[test]
fn lines_leaving_the_picture_are_clipped_with_border_points() {
    let mut d = corner();
    d.points[1] = DVec2::new(150.0, 10.0); // leaves through the right edge
    d.points.push(DVec2::new(200.0, 200.0)); // a line wholly outside
    d.points.push(DVec2::new(300.0, 250.0));
    d.lines.push([3, 4]);
    d.points.push(DVec2::new(150.0, 10.0)); // a second line to the same outside point
    d.lines.push([2, 5]);
    d.finalize();
    let wf = wireframe_from_drawing(&d, 100, 80).unwrap();
    assert_eq!(wf.edges.len(), 3, "the outside line is dropped");
    assert_eq!(wf.line_px(0), [10.0, 70.0, 100.0, 70.0]);
    assert_eq!(wf.border_ends(0), [false, true]);
    let border = wf.edges[0][1];
    assert_eq!(wf.junctions[border].junction_type, "border");
    assert_eq!(wf.junctions[border].six_bit_code, None);
    // The second line leaves through the right edge at another point: its own border junction.
    let [x1, y1, x2, y2] = wf.line_px(2);
    assert_eq!([x1, y1, x2], [10.0, 10.0, 100.0]);
    assert!(
        (y2 - (80.0 - (70.0 - 60.0 * 90.0 / 140.0))).abs() < 1e-4,
        "{y2}"
    );
}

#[test]
fn coincident_clip_points_share_one_junction() {
    // Two lines leaving through the same border point (100, 40 up) from different sides.
    let d = LineDrawing {
        points: vec![
            DVec2::new(50.0, 20.0),
            DVec2::new(150.0, 60.0),
            DVec2::new(50.0, 60.0),
            DVec2::new(150.0, 20.0),
        ],
        lines: vec![[0, 1], [2, 3]],
        ..Default::default()
    };
    let wf = wireframe_from_drawing(&d, 100, 80).unwrap();
    assert_eq!(wf.junctions.len(), 3);
    assert_eq!(wf.edges[0][1], wf.edges[1][1]);
    assert_eq!(wf.junctions[wf.edges[0][1]].xy_px, [100.0, 40.0]);
}

#[test]
fn bad_input_is_refused() {
    assert!(matches!(
        wireframe_from_drawing(&corner(), 0, 80),
        Err(WireframeError::EmptyPicture { .. })
    ));
    let mut d = corner();
    d.lines.push([0, 9]);
    assert!(matches!(
        wireframe_from_drawing(&d, 100, 80),
        Err(WireframeError::BadLine {
            line: 2,
            point: 9,
            ..
        })
    ));
}

#[test]
fn records_carry_each_formats_keys() {
    let wf = wireframe_from_drawing(&corner(), 100, 80).unwrap();
    let train = hawp_train_record("a.png", &wf);
    assert_eq!(train["edges_positive"], serde_json::json!([[0, 1], [0, 2]]));
    assert_eq!(train["junctions"][2], serde_json::json!([10.0, 10.0]));
    assert_eq!(train["junction_type"][0], "L");
    let test = hawp_test_record("a.png", &wf);
    assert_eq!(
        test["lines"][0],
        serde_json::json!([10.0, 70.0, 60.0, 70.0])
    );
    let lcnn = lcnn_record("a.png", &wf);
    assert_eq!(lcnn["line_kind"][1], "convex");
    let ann = letr_annotations(7, 100, &wf);
    // The vertical line starts at its upper end (raster y 10), as LETR's transforms assume.
    assert_eq!(ann[1]["line"], serde_json::json!([10.0, 10.0, 0.0, 60.0]));
    assert_eq!(ann[1]["id"], 101);
    assert_eq!(ann[1]["category_id"], 0);
    assert_eq!(ann[1]["area"], 1);
    assert_eq!(train["edges_negative"], serde_json::json!([[1, 2]]));
}

#[test]
fn hawp_negatives_are_the_unjoined_junction_pairs_capped() {
    // A fan of n lines from one point: n + 1 junctions, every pair of fan tips unjoined.
    let fan = |n: usize| {
        let mut d = LineDrawing {
            points: vec![DVec2::new(1.0, 1.0)],
            ..Default::default()
        };
        for i in 0..n {
            d.points.push(DVec2::new(2.0 + i as f64 * 0.01, 50.0));
            d.lines.push([0, i + 1]);
        }
        wireframe_from_drawing(&d, 100, 80).unwrap()
    };
    let small = hawp_negative_edges(&fan(3));
    assert_eq!(small, [[1, 2], [1, 3], [2, 3]]);
    // 70 tips: 70 * 69 / 2 = 2415 unjoined pairs, cut to HAWP's 2000.
    let big = hawp_negative_edges(&fan(70));
    assert_eq!(big.len(), HAWP_NEGATIVE_EDGES_MAX);
    assert!(big.iter().all(|&[i, j]| i >= 1 && i < j));
}

#[test]
fn letr_lines_start_at_the_left_end_with_their_border_flags() {
    let mut d = corner();
    // Line 0 runs right to left and leaves through the left edge: x from 60 to -40.
    d.points[1] = DVec2::new(-40.0, 10.0);
    d.points[0] = DVec2::new(60.0, 10.0);
    d.points[2] = DVec2::new(60.0, 70.0);
    let wf = wireframe_from_drawing(&d, 100, 80).unwrap();
    assert_eq!(wf.line_px(0), [60.0, 70.0, 0.0, 70.0]);
    assert_eq!(wf.border_ends(0), [false, true]);
    let (line, border) = letr_line_px(&wf, 0);
    assert_eq!(line, [0.0, 70.0, 60.0, 70.0]);
    assert_eq!(border, [true, false]);
    let ann = letr_annotations(1, 1, &wf);
    assert_eq!(ann[0]["line"], serde_json::json!([0.0, 70.0, 60.0, 0.0]));
    assert_eq!(ann[0]["border_ends"], serde_json::json!([true, false]));
    // Every exported line: dx > 0, or dx == 0 and dy >= 0.
    for a in &ann {
        let (dx, dy) = (
            a["line"][2].as_f64().unwrap(),
            a["line"][3].as_f64().unwrap(),
        );
        assert!(dx > 0.0 || (dx == 0.0 && dy >= 0.0), "{a}");
    }
}

#[test]
fn pictures_the_loaders_cannot_take_are_refused_by_format() {
    let empty = wireframe_from_drawing(&LineDrawing::default(), 100, 80).unwrap();
    assert!(WireframeFormat::Hawp.loader_refusal(&empty).is_some());
    assert!(WireframeFormat::Lcnn.loader_refusal(&empty).is_some());
    assert!(WireframeFormat::Letr.loader_refusal(&empty).is_none());
    // A triangle: every junction pair is a line, so L-CNN has no negative; HAWP takes it.
    let triangle = LineDrawing {
        points: vec![
            DVec2::new(10.0, 10.0),
            DVec2::new(60.0, 10.0),
            DVec2::new(10.0, 70.0),
        ],
        lines: vec![[0, 1], [1, 2], [2, 0]],
        ..Default::default()
    };
    let wf = wireframe_from_drawing(&triangle, 100, 80).unwrap();
    assert!(WireframeFormat::Lcnn.loader_refusal(&wf).is_some());
    assert!(WireframeFormat::Hawp.loader_refusal(&wf).is_none());
    // The open corner has the unjoined pair of its two ends.
    let wf = wireframe_from_drawing(&corner(), 100, 80).unwrap();
    assert!(WireframeFormat::Lcnn.loader_refusal(&wf).is_none());
}

#[test]
fn letr_lines_start_on_the_exact_junction_and_end_within_1e_12_px() {
    // 184 + (37.9689 - 184) is not 37.9689 in f64: the offset form can miss the shared end
    // coordinate by an ulp, and no other f64 offset hits it either.
    let d = LineDrawing {
        points: vec![
            DVec2::new(184.0, 80.0 - 37.9689),
            DVec2::new(120.7379, 80.0 - 57.6),
        ],
        lines: vec![[1, 0]],
        ..Default::default()
    };
    let wf = wireframe_from_drawing(&d, 200, 80).unwrap();
    let ann = &letr_annotations(1, 1, &wf)[0]["line"];
    let [x, y, dx, dy] = [0, 1, 2, 3].map(|k| ann[k].as_f64().unwrap());
    assert_eq!([x, y], wf.junctions[0].xy_px);
    let [ex, ey] = wf.junctions[1].xy_px;
    assert!((x + dx - ex).abs() <= 1e-12 && (y + dy - ey).abs() <= 1e-12);
}
