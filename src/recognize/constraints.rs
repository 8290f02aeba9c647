//! What the method cannot do (thesis Chapter VII), detected and named so the recognizer
//! declines instead of guessing: curved edges (round parts, "circles"), lines in no six-bit
//! direction, blocks not in one direction, an upper layer larger than the layer below
//! (Figure 7.2), blocks with no visible support.

use super::catalog_match::bounds_mm;
use super::Camera;
use crate::drawing::LineDrawing;
use crate::geom::{DVec2, DVec3, UnionFind};
use crate::scene::Block;

/// How far a line may run off a block axis before it means blocks not in one direction: the
/// angle `tol_deg`, or, for a line shorter than `end_tol_px / tan(tol_deg)`, the angle by which
/// one end moved `end_tol_px` across the line turns it, `atan(end_tol_px / length_px)`.
///
/// A line between two vertices takes its direction from their places, and the error of a
/// place does not shrink with the line: a vertex the front end puts 1 px off its corner turns
/// a 20 px line by 2.9 degrees and a 200 px line by 0.3. Step 6 holds every observed vertex to
/// within `tol_px` of the answer's redrawn corner; so a line along a block axis may show
/// either end `tol_px` across it, and the recognizer passes `tol_px` as `end_tol_px`. A
/// turned block's long edges still turn by more than `tol_deg`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisTolerance {
    /// The angle any line may run off an axis, degrees (`RecognizeOptions::axis_tol_deg`).
    pub tol_deg: f64,
    /// How far one end of a line may lie across the axis line through the other, px.
    pub end_tol_px: f64,
}

impl AxisTolerance {
    /// The angle a line of `length_px` may run off an axis, degrees.
    pub fn allowed_deg(&self, length_px: f64) -> f64 {
        let by_ends = (self.end_tol_px / length_px.max(f64::EPSILON))
            .atan()
            .to_degrees();
        self.tol_deg.max(by_ends)
    }
}

/// The angle between the picture line `pa`-`pb` and the picture direction of each world
/// direction of `dirs` at the line's middle, degrees (0 to 90), in `dirs`' order. In
/// perspective views each direction is taken towards its vanishing point: a unit step along it
/// from the point of the scene's centre depth that the middle shows.
pub fn picture_angles_deg(camera: &Camera, (pa, pb): (DVec2, DVec2), dirs: &[DVec3]) -> Vec<f64> {
    let target = DVec3::from_array(camera.target_mm);
    let mid = (pa + pb) / 2.0;
    let (o, d) = camera.ray_through_picture(mid.x, mid.y);
    let at = o + d * (target - o).dot(d);
    let p0 = camera.picture_from_world(at).truncate();
    dirs.iter()
        .map(|dir| {
            let q: DVec2 = camera.picture_from_world(at + *dir).truncate() - p0;
            let ang = q.angle_to(pb - pa).abs().to_degrees();
            ang.min(180.0 - ang)
        })
        .collect()
}

/// Lines of `drawing` whose picture direction is not that of a world axis (x, y or z) seen by
/// `camera` within the angle `tol` allows a line of its length ([`AxisTolerance`]): the edges
/// of a block turned by other than a multiple of 90 degrees (Chapter VII: "the gradients have
/// to be changed to deal with different block directions").
pub fn lines_off_the_axes(
    drawing: &LineDrawing,
    camera: &Camera,
    tol: AxisTolerance,
) -> Vec<usize> {
    let axes = [DVec3::X, DVec3::Y, DVec3::Z];
    drawing
        .lines
        .iter()
        .enumerate()
        .filter(|(_, &[a, b])| {
            let (pa, pb) = (drawing.points[a], drawing.points[b]);
            let allowed = tol.allowed_deg(pa.distance(pb));
            picture_angles_deg(camera, (pa, pb), &axes)
                .iter()
                .all(|&ang| ang > allowed)
        })
        .map(|(i, _)| i)
        .collect()
}

/// A joint of a curved chain turns the line direction by at least this, degrees (collinear
/// pieces of one straight edge turn by less than the 2 degrees of Chapter IV's tolerances).
const MIN_BEND_DEG: f64 = 2.0;
/// ... and by at most this, degrees: a chord of a circle drawn with 64 sides turns by 5.6
/// degrees in the circle's plane, up to about 25 degrees foreshortened at an ellipse's ends,
/// while the corners of blocks (L junctions) turn by far more in corner views.
const MAX_BEND_DEG: f64 = 35.0;
/// A curved chain has at least this many joints: no drawing of blocks in one direction has
/// four gentle bends in a row.
const MIN_CURVED_JOINTS: usize = 4;

/// Lines of `drawing` that form curved chains: runs of lines joined at points of exactly two
/// lines where the direction turns gently (between [`MIN_BEND_DEG`] and [`MAX_BEND_DEG`]), at
/// least [`MIN_CURVED_JOINTS`] joints to a run, plus the lines the drawing itself flags as
/// curved. A round part's rim projects to an ellipse, drawn (by the exact drawing or by a
/// front end that follows the curve) as such a chain; Chapter VII: "with other kinds of blocks
/// like pyramids or circles, the parallelogram surface searching fails". Read from the picture
/// geometry, so a drawing without flags is judged the same.
pub fn curved_chain_lines(drawing: &LineDrawing) -> Vec<usize> {
    let n = drawing.lines.len();
    let mut incident: Vec<Vec<usize>> = vec![Vec::new(); drawing.points.len()];
    for (li, &[a, b]) in drawing.lines.iter().enumerate() {
        incident[a].push(li);
        incident[b].push(li);
    }
    let mut chains = UnionFind::new(n);
    let mut joints = Vec::new();
    for (p, lines) in incident.iter().enumerate() {
        let &[l1, l2] = lines.as_slice() else {
            continue;
        };
        let away = |l: usize| {
            let [a, b] = drawing.lines[l];
            let other = if a == p { b } else { a };
            drawing.points[other] - drawing.points[p]
        };
        // The turn between arriving along l1 (reversed) and leaving along l2.
        let bend = (-away(l1)).angle_to(away(l2)).abs().to_degrees();
        if (MIN_BEND_DEG..=MAX_BEND_DEG).contains(&bend) {
            chains.union(l1, l2);
            joints.push(l1);
        }
    }
    let mut per_chain = vec![0usize; n];
    for l in joints {
        per_chain[chains.find(l)] += 1;
    }
    (0..n)
        .filter(|&l| {
            per_chain[chains.find(l)] >= MIN_CURVED_JOINTS || drawing.curved_lines.contains(&l)
        })
        .collect()
}

/// The blocks directly below `b` (touching its bottom face, footprints overlapping).
fn supports<'a>(b: &Block, blocks: &'a [Block], tol_mm: f64) -> Vec<&'a Block> {
    let (lo, hi) = bounds_mm(b);
    blocks
        .iter()
        .filter(|o| {
            let (olo, ohi) = bounds_mm(o);
            (ohi.y - lo.y).abs() <= tol_mm
                && ohi.x.min(hi.x) - olo.x.max(lo.x) > tol_mm
                && ohi.z.min(hi.z) - olo.z.max(lo.z) > tol_mm
        })
        .collect()
}

/// Blocks above the floor with no block under them (Chapter VII: every block touches the
/// floor or another block): their support is hidden in every view.
pub fn floating_blocks(blocks: &[Block], tol_mm: f64) -> Vec<usize> {
    (0..blocks.len())
        .filter(|&i| {
            bounds_mm(&blocks[i]).0.y > tol_mm && supports(&blocks[i], blocks, tol_mm).is_empty()
        })
        .collect()
}

/// Blocks whose footprint is not covered by the blocks they rest on: the upper layer larger
/// than the layer below of Figure 7.2, where "parallelogram surfaces cannot be found from each
/// corner direction". Sampled on a `step_mm` grid inside the footprint.
pub fn overhanging_blocks(blocks: &[Block], tol_mm: f64, step_mm: f64) -> Vec<usize> {
    (0..blocks.len())
        .filter(|&i| overhangs(&blocks[i], blocks, tol_mm, step_mm))
        .collect()
}

/// `true` when block `b`, above the floor, overhangs what it rests on among `blocks` (the test
/// of [`overhanging_blocks`] for one block; `b` itself may be among `blocks`).
pub fn overhangs(b: &Block, blocks: &[Block], tol_mm: f64, step_mm: f64) -> bool {
    let (lo, hi) = bounds_mm(b);
    if lo.y <= tol_mm {
        return false;
    }
    let under: Vec<(DVec3, DVec3)> = supports(b, blocks, tol_mm)
        .iter()
        .map(|s| bounds_mm(s))
        .collect();
    let nx = ((hi.x - lo.x) / step_mm).ceil().max(1.0) as usize;
    let nz = ((hi.z - lo.z) / step_mm).ceil().max(1.0) as usize;
    (0..=nx).any(|ix| {
        (0..=nz).any(|iz| {
            let x = lo.x + tol_mm + (hi.x - lo.x - 2.0 * tol_mm) * ix as f64 / nx as f64;
            let z = lo.z + tol_mm + (hi.z - lo.z - 2.0 * tol_mm) * iz as f64 / nz as f64;
            !under.iter().any(|(l, h)| {
                x >= l.x - tol_mm && x <= h.x + tol_mm && z >= l.z - tol_mm && z <= h.z + tol_mm
            })
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linedraw::visible_line_drawing;
    use crate::recognize::{CameraOptions, CornerView};
    use crate::scene::Scene;

    #[test]
    fn a_b30_across_a_b30_overhangs_and_a_b15_on_a_b30_does_not() {
        let lower = Block::new("b30", DVec3::new(15.0, 7.5, 7.5), 0.0);
        let crossed = Block::new("b30", DVec3::new(15.0, 22.5, 7.5), 90.0);
        let small = Block::new("b15", DVec3::new(7.5, 22.5, 7.5), 0.0);
        assert_eq!(overhanging_blocks(&[lower, crossed], 0.5, 1.0), vec![1]);
        assert!(overhanging_blocks(&[lower, small], 0.5, 1.0).is_empty());
        // A b30 bridging two towers (Figure 7.2's larger upper layer) overhangs the gap.
        let bridge = [
            Block::new("b15", DVec3::new(7.5, 7.5, 7.5), 0.0),
            Block::new("b15", DVec3::new(37.5, 7.5, 7.5), 0.0),
            Block::new("b30", DVec3::new(22.5, 22.5, 7.5), 0.0),
        ];
        assert_eq!(overhanging_blocks(&bridge, 0.5, 1.0), vec![2]);
    }

    #[test]
    fn a_block_in_the_air_floats() {
        let b = [
            Block::new("b15", DVec3::new(7.5, 7.5, 7.5), 0.0),
            Block::new("b15", DVec3::new(37.5, 22.5, 7.5), 0.0),
        ];
        assert_eq!(floating_blocks(&b, 0.5), vec![1]);
    }

    /// Regression: the varied photo look's short edges, whose ends the front end places to a
    /// pixel, were read as blocks not in one direction. A 15.6 px edge of a 256 x 240
    /// perspective view with its far end 1 px across its axis runs 3.7 degrees off it: along
    /// its axis by the recognizer's tolerance (one end within 2 px of the axis line through
    /// the other), off it by the angle alone; the same 3.7 degrees on a 100 px line is off.
    #[test]
    fn a_short_edge_with_an_end_a_pixel_across_runs_along_its_axis_and_a_long_one_does_not() {
        let b = Block::new("b15", DVec3::new(0.0, 7.5, 0.0), 0.0);
        let cam = Camera::frame(
            &b.world_vertices(),
            CornerView::Ne,
            &CameraOptions::default(),
        );
        let c = DVec3::from_array(cam.target_mm);
        let at = |w: DVec3| cam.picture_from_world(w).truncate();
        let u = (at(c + DVec3::X) - at(c)).normalize();
        let line = |length_px: f64, across_px: f64| {
            let a = at(c);
            let b = a + u * length_px + u.perp() * across_px;
            LineDrawing::from_arrays(&[a.to_array(), b.to_array()], &[[0, 1]])
        };
        let tol = AxisTolerance {
            tol_deg: 3.0,
            end_tol_px: 2.0,
        };
        let angle_only = AxisTolerance {
            end_tol_px: 0.0,
            ..tol
        };
        let short = line(15.6, 1.0);
        assert!(lines_off_the_axes(&short, &cam, tol).is_empty());
        assert_eq!(lines_off_the_axes(&short, &cam, angle_only), vec![0]);
        let long = line(100.0, 100.0 * 1.0 / 15.6);
        assert_eq!(lines_off_the_axes(&long, &cam, tol), vec![0]);
        assert!((tol.allowed_deg(15.6) - (2.0f64 / 15.6).atan().to_degrees()).abs() < 1e-12);
        assert_eq!(tol.allowed_deg(100.0), 3.0);
    }

    #[test]
    fn a_turned_block_draws_lines_off_the_axes() {
        let straight = Block::new("b15", DVec3::new(0.0, 7.5, 0.0), 0.0);
        let turned = Block::new("b15", DVec3::new(0.0, 7.5, 0.0), 30.0);
        for (b, off) in [(straight, false), (turned, true)] {
            let cam = Camera::frame(
                &b.world_vertices(),
                CornerView::Ne,
                &CameraOptions::default(),
            );
            let d = visible_line_drawing(&Scene::new("t", vec![b]), &cam);
            let tol = AxisTolerance {
                tol_deg: 2.0,
                end_tol_px: 2.0,
            };
            assert_eq!(!lines_off_the_axes(&d, &cam, tol).is_empty(), off);
        }
    }
}
