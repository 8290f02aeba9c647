//! Unit tests of Waltz filtering and the labelling search on drawings a reader can check by eye.

use super::*;
use crate::geom::DVec2;

fn drawing(points: &[[f64; 2]], lines: &[[usize; 2]]) -> LineDrawing {
    LineDrawing::from_arrays(points, lines)
}

fn label(d: &LineDrawing, opts: &LabelOptions) -> LabelReport {
    label_drawing(d, opts, &mut |_| {}).expect("a well-formed drawing")
}

/// The cube of Appendix A's Figure A.2 (PAIP ch. 17's `cube`): a middle fork, three
/// arrows and three Ls.
fn cube() -> LineDrawing {
    LineDrawing::isometric_cube(100.0, DVec2::new(300.0, 300.0))
}

/// PAIP ch. 17: "For 29,160 interpretations" (fork 5 x arrow 3^3 x L 6^3), 216 after
/// filtering, and four labellings of the cube: the free-floating cube and the three ways
/// of setting it against walls or the floor.
#[test]
fn a_cube_has_four_labellings_from_29160_combinations_216_after_filtering() {
    let r = label(&cube(), &LabelOptions::default());
    assert_eq!(r.stats.combinations_before.exact, Some(29_160));
    assert_eq!(r.stats.combinations_after.exact, Some(216));
    assert_eq!((r.count.value, r.count.exact), (4, true));
    assert_eq!(r.labellings.len(), 4);
    assert!(r.uncatalogued.is_empty() && r.free_lines.is_empty());
}

/// Appendix A step 2 on the cube: with its outline occluding, only the free-floating cube
/// is left, the three lines of the middle fork convex.
#[test]
fn a_cube_with_an_occluding_outline_is_the_free_floating_cube() {
    let d = cube();
    let opts = LabelOptions {
        boundary_occluding: true,
        ..Default::default()
    };
    let r = label(&d, &opts);
    assert_eq!(r.count.value, 1);
    for (i, &[a, b]) in d.lines.iter().enumerate() {
        let label = r.labellings[0][i].expect("every line is labelled");
        let inner = a == 6 || b == 6;
        assert_eq!(label == LineLabel::Convex, inner, "line {i}");
        assert!(inner || label.is_occluding(), "line {i}: {label:?}");
    }
}

/// PAIP ch. 17's impossible figure, the poiuyt (Figure 17.10, the points of
/// `tests/fixtures/kanade/paip_poiuyt.json`): every junction is possible alone, yet no
/// labelling is consistent. Filtering leaves 2,073,600 of the 544,195,584 combinations and
/// the search finds none of them consistent.
#[test]
fn the_poiuyt_has_no_labelling() {
    let d = drawing(
        &[
            [100.0, 300.0],
            [100.0, 200.0],
            [180.0, 140.0],
            [190.0, 250.0],
            [150.0, 500.0],
            [300.0, 550.0],
            [500.0, 550.0],
            [600.0, 450.0],
            [700.0, 300.0],
            [600.0, 200.0],
            [650.0, 50.0],
            [700.0, 150.0],
        ],
        &[
            [0, 1],
            [0, 3],
            [0, 4],
            [1, 2],
            [2, 3],
            [4, 5],
            [5, 6],
            [6, 7],
            [7, 8],
            [8, 9],
            [8, 11],
            [9, 10],
            [10, 11],
        ],
    );
    let r = label(&d, &LabelOptions::default());
    assert_eq!(r.stats.combinations_before.exact, Some(544_195_584));
    assert_eq!(r.stats.combinations_after.exact, Some(2_073_600));
    assert_eq!((r.count.value, r.count.exact), (0, true));
    assert!(r.labellings.is_empty());
    assert!(
        r.stats.backtracks > 0,
        "the search, not filtering, rules it out"
    );
}

/// A T-junction occlusion: a square in front of another, overlapping it. Where an edge of
/// the square behind disappears under the one in front, the drawing has a T whose bar is
/// the front square's edge. In every labelling both halves of each bar are occluding, in
/// the same direction, with the front square (away from the stem) as the occluding face.
#[test]
fn a_t_junction_bar_is_occluding_with_the_face_away_from_the_stem() {
    // Behind: (0,0)..(40,30); in front: (20,10)..(60,50). T at (40,10) (stem down) and
    // at (20,30) (stem left).
    let points = [
        [0.0, 0.0],
        [40.0, 0.0],
        [40.0, 10.0],
        [20.0, 30.0],
        [0.0, 30.0],
        [20.0, 10.0],
        [60.0, 10.0],
        [60.0, 50.0],
        [20.0, 50.0],
    ];
    let lines = [
        [0, 1],
        [1, 2],
        [3, 4],
        [4, 0],
        [5, 2],
        [2, 6],
        [6, 7],
        [7, 8],
        [3, 8],
        [3, 5],
    ];
    let d = drawing(&points, &lines);
    assert_eq!(d.junctions[2], Junction::T);
    assert_eq!(d.junctions[3], Junction::T);
    let r = label(&d, &LabelOptions::default());
    assert!(r.count.value >= 1);
    // (bar line, the side of the front square walking from its first to its second point:
    // true = right).
    let bars = [(4, false), (5, false), (8, true), (9, false)];
    for labelling in &r.labellings {
        for (line, front_on_right) in bars {
            let got = labelling[line].expect("bar lines are labelled");
            assert_eq!(got, LineLabel::occluding(front_on_right), "line {line}");
        }
    }
}
