//! Step 1 of the recognizer (thesis Chapter V, Figure 5.1): select the "Y" (fork, arrow) and the
//! collinear "T" vertices of a view and sort them by picture y, lowest first.

use crate::drawing::{Junction, LineDrawing, SixBitCode};
use crate::geom::DVec2;

/// A vertex chosen for the parallelogram search (Chapter V): its index in the drawing, where it
/// is in the picture, its six-bit code and its junction class.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SelectedVertex {
    /// Index into `LineDrawing::points`.
    pub index: usize,
    /// Picture position in px (x right, y up).
    pub at_px: DVec2,
    /// The six-bit code of Chapter IV.
    pub code: SixBitCode,
    /// Its junction class.
    pub junction: Junction,
}

/// `true` for the junctions Chapter V searches from: the "Y" (fork and arrow) and the collinear
/// "T"; a vertex where two collinear "T" meet (four lines with a collinear pair: Kanade's K, psi
/// and X) is the thesis's "two collinear T" of Figure 5.1, where a block meets the layer above.
pub fn is_searched_junction(j: Junction) -> bool {
    matches!(
        j,
        Junction::Fork | Junction::Arrow | Junction::T | Junction::K | Junction::Psi | Junction::X
    )
}

/// Selects the "Y" and collinear "T" vertices of `drawing` (Figure 5.1) and sorts them by
/// picture y, from the minimum to the maximum (Chapter V), ties by x then index so the order is
/// deterministic.
pub fn select_vertices(drawing: &LineDrawing) -> Vec<SelectedVertex> {
    let mut out: Vec<SelectedVertex> = drawing
        .junctions
        .iter()
        .enumerate()
        .filter(|(_, j)| is_searched_junction(**j))
        .filter_map(|(i, j)| {
            Some(SelectedVertex {
                index: i,
                at_px: *drawing.points.get(i)?,
                code: drawing.codes.get(i).copied().unwrap_or_default(),
                junction: *j,
            })
        })
        .collect();
    out.sort_by(|a, b| {
        a.at_px
            .y
            .total_cmp(&b.at_px.y)
            .then(a.at_px.x.total_cmp(&b.at_px.x))
            .then(a.index.cmp(&b.index))
    });
    out
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// The isometric cube of Chapter IV (unit hexagon around the middle fork), top vertex first,
    /// clockwise, then the middle: codes {40, 14, 9, 21, 33, 50, 22}.
    pub(crate) fn cube_drawing(scale: f64, origin: DVec2) -> LineDrawing {
        LineDrawing::isometric_cube(scale, origin)
    }

    #[test]
    fn a_cube_selects_its_fork_and_two_arrows_sorted_by_picture_y() {
        let d = cube_drawing(10.0, DVec2::new(100.0, 100.0));
        let sel = select_vertices(&d);
        let idx: Vec<usize> = sel.iter().map(|v| v.index).collect();
        // The hexagon's Y vertices: the arrows 1, 3, 5 and the middle fork 6.
        assert!(sel.iter().all(|v| is_searched_junction(v.junction)));
        assert!(idx.contains(&6), "the middle fork is selected: {idx:?}");
        assert!(sel.windows(2).all(|w| w[0].at_px.y <= w[1].at_px.y));
        assert_eq!(sel.iter().find(|v| v.index == 6).unwrap().code.0, 22);
        // The L corners (top 0, bottom-right 2, bottom-left 4) are not selected.
        for l in [0, 2, 4] {
            assert!(!idx.contains(&l), "L vertex {l} selected: {idx:?}");
        }
    }
}
