//! Step 2 of the recognizer: the **parallelogram search** of Chapter IV (Figure 4.5). From a
//! selected vertex, along the directions its six-bit code allows, follow the lines (through
//! collinear "T" points) and close the parallelogram of a top face; measure the vertex
//! location, the height (the "down" edge) and the two side lengths, in px and, through the
//! camera's rays, in millimetres (exact for orthographic and perspective views alike).

use super::select::SelectedVertex;
use super::Camera;
use crate::camera::Projector;
use crate::drawing::{Direction, LineDrawing, COLLINEAR_TOL_DEG};
use crate::geom::{DVec2, DVec3};

/// The four corners of a top face as seen in a 45-degree corner view (Figure 4.5): the two
/// picture directions in which the face's sides leave the corner.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TopCorner {
    /// The corner nearest the camera: sides go left-up and right-up (a "Y" fork, code 22).
    Near,
    /// The left corner: sides go right-up and right-down.
    Left,
    /// The right corner: sides go left-up and left-down.
    Right,
    /// The far corner: sides go left-down and right-down (no vertical edge below it is seen).
    Far,
}

impl TopCorner {
    /// All four, nearest first.
    pub const ALL: [TopCorner; 4] = [
        TopCorner::Near,
        TopCorner::Left,
        TopCorner::Right,
        TopCorner::Far,
    ];

    /// The two picture directions of the face's sides at this corner.
    pub fn sides(self) -> [Direction; 2] {
        match self {
            TopCorner::Near => [Direction::LeftUp, Direction::RightUp],
            TopCorner::Left => [Direction::RightUp, Direction::RightDown],
            TopCorner::Right => [Direction::LeftUp, Direction::LeftDown],
            TopCorner::Far => [Direction::LeftDown, Direction::RightDown],
        }
    }
}

/// Which face a parallelogram is (Figure 4.5: a vertex has plane formations on top, on the
/// left and on the right).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Face {
    /// A top face, with the vertex as the given corner.
    Top(TopCorner),
    /// A side face whose top edge leaves the vertex in the given direction, the vertex being a
    /// top corner of it with the vertical edge below: what is left of a block whose top is
    /// hidden under the layer above.
    Side(Direction),
}

impl Face {
    /// Every formation searched: the four top corners, then the four side faces.
    pub const ALL: [Face; 8] = [
        Face::Top(TopCorner::Near),
        Face::Top(TopCorner::Left),
        Face::Top(TopCorner::Right),
        Face::Top(TopCorner::Far),
        Face::Side(Direction::LeftUp),
        Face::Side(Direction::RightUp),
        Face::Side(Direction::LeftDown),
        Face::Side(Direction::RightDown),
    ];

    /// The two picture directions of the parallelogram's sides at the vertex.
    pub fn sides(self) -> [Direction; 2] {
        match self {
            Face::Top(c) => c.sides(),
            Face::Side(d) => [d, Direction::Down],
        }
    }
}

/// One point reached while following a straight line from a vertex: the drawing point and its
/// distance from the start in px.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChainStop {
    /// Index into `LineDrawing::points`.
    pub point: usize,
    /// Distance from the start vertex, px.
    pub length_px: f64,
}

/// A parallelogram found (or left open) by [`ParallelogramSearch`]: the thesis's record of
/// "vertex location (x, y), height, length of left-up side, ... right-up side" (Chapter IV).
#[derive(Debug, Clone, PartialEq)]
pub struct Parallelogram {
    /// The vertex searched from.
    pub vertex: SelectedVertex,
    /// Which face, and which corner of it the vertex is taken to be.
    pub face: Face,
    /// Every point reached along the first and second side direction (collinear lines
    /// followed through "T" points), nearest first; for a side face the second side is the
    /// vertical edge.
    pub sides: [Vec<ChainStop>; 2],
    /// The far ends of the first and second side of the smallest closed parallelogram;
    /// `None` when no stop pair closes (a side occluded: rule (1) of Chapter V then takes the
    /// longest length over the views).
    pub closed: Option<[ChainStop; 2]>,
    /// Length of the vertex's "down" line (the block's visible vertical edge), px, when its
    /// code has the "down" bit (Chapter IV: "the height of a block can be obtained ...").
    pub down_px: Option<f64>,
    /// The far end of the "down" line.
    pub down_end: Option<usize>,
}

impl Parallelogram {
    /// The visible length of each side up to its first point, px: a lower bound of the block's
    /// edge (the edge goes on at least that far).
    pub fn first_side_px(&self) -> [f64; 2] {
        [0, 1].map(|k| self.sides[k].first().map_or(0.0, |s| s.length_px))
    }
}

/// The parallelogram search over one line drawing (Figure 4.5), with its adjacency built once.
#[derive(Debug)]
pub struct ParallelogramSearch<'a> {
    drawing: &'a LineDrawing,
    neighbours: Vec<Vec<usize>>,
    tol_px: f64,
}

impl<'a> ParallelogramSearch<'a> {
    /// Prepares the search; `tol_px` is how close two points must be to be the same corner.
    pub fn new(drawing: &'a LineDrawing, tol_px: f64) -> Self {
        let mut neighbours = vec![Vec::new(); drawing.points.len()];
        for &[a, b] in &drawing.lines {
            if a < neighbours.len() && b < neighbours.len() && a != b {
                neighbours[a].push(b);
                neighbours[b].push(a);
            }
        }
        ParallelogramSearch {
            drawing,
            neighbours,
            tol_px,
        }
    }

    fn at(&self, i: usize) -> DVec2 {
        self.drawing.points[i]
    }

    /// Follows the line leaving `start` in direction `dir`, and on through every point where a
    /// collinear line continues it (a collinear "T"), returning every point reached.
    pub fn follow(&self, start: usize, dir: Direction) -> Vec<ChainStop> {
        let mut stops = Vec::new();
        let first = self.neighbours[start]
            .iter()
            .copied()
            .find(|&n| Direction::from_picture_vector(self.at(n) - self.at(start)) == Some(dir));
        let Some(mut cur) = first else {
            return stops;
        };
        let mut prev = start;
        let origin = self.at(start);
        while stops.len() <= self.drawing.points.len() {
            stops.push(ChainStop {
                point: cur,
                length_px: origin.distance(self.at(cur)),
            });
            let heading = self.at(cur) - origin;
            let next = self.neighbours[cur].iter().copied().find(|&n| {
                let step = self.at(n) - self.at(cur);
                // Collinear within COLLINEAR_TOL_DEG, or within the point tolerance: the
                // cosine of max(COLLINEAR_TOL_DEG, atan(tol / step)), against the dot product.
                let x = self.tol_px / step.length().max(1e-9);
                let cos_tol =
                    (1.0 / (1.0 + x * x).sqrt()).min(COLLINEAR_TOL_DEG.to_radians().cos());
                n != prev && step.dot(heading) > cos_tol * step.length() * heading.length()
            });
            match next {
                Some(n) => (prev, cur) = (cur, n),
                None => break,
            }
        }
        stops
    }

    /// Searches the parallelogram `face` at `v`: `None` when the code lacks either side
    /// direction (rule (3) of Chapter V: no block on that side).
    pub fn search(&self, v: &SelectedVertex, face: Face) -> Option<Parallelogram> {
        let [d1, d2] = face.sides();
        if !(v.code.has(d1) && v.code.has(d2)) {
            return None;
        }
        let sides = [self.follow(v.index, d1), self.follow(v.index, d2)];
        let closed = self.close(&sides, d1, d2);
        let down = v
            .code
            .has(Direction::Down)
            .then(|| self.follow(v.index, Direction::Down))
            .and_then(|c| c.first().copied());
        Some(Parallelogram {
            vertex: *v,
            face,
            sides,
            closed,
            down_px: down.map(|s| s.length_px),
            down_end: down.map(|s| s.point),
        })
    }

    /// The smallest stop pair whose far sides meet at a common point (the fourth corner).
    fn close(
        &self,
        sides: &[Vec<ChainStop>; 2],
        d1: Direction,
        d2: Direction,
    ) -> Option<[ChainStop; 2]> {
        for a in &sides[0] {
            let from_a = self.follow(a.point, d2);
            for b in &sides[1] {
                let from_b = self.follow(b.point, d1);
                let meets = from_a.iter().any(|x| {
                    from_b
                        .iter()
                        .any(|y| self.at(x.point).distance(self.at(y.point)) <= self.tol_px)
                });
                if meets {
                    return Some([*a, *b]);
                }
            }
        }
        None
    }
}

/// The world point (mm) seen at picture point `p_px` that lies at height `y_mm`: the camera
/// ray through the pixel meets the horizontal plane (exact in any projection). `None` when the
/// ray is parallel to the plane.
pub fn point_at_height_mm(camera: &Camera, p_px: DVec2, y_mm: f64) -> Option<DVec3> {
    point_at_height_on(&Projector::new(camera), p_px, y_mm)
}

/// [`point_at_height_mm`] with the camera's projector made once (the measurements of
/// Chapter IV convert many points of one view).
pub(super) fn point_at_height_on(proj: &Projector, p_px: DVec2, y_mm: f64) -> Option<DVec3> {
    ray_at_height(proj.ray(p_px), y_mm)
}

/// Where the ray `(origin, unit direction)` meets the horizontal plane at height `y_mm`.
pub(super) fn ray_at_height((o, d): (DVec3, DVec3), y_mm: f64) -> Option<DVec3> {
    if d.y.abs() < 1e-12 {
        return None;
    }
    let t = (y_mm - o.y) / d.y;
    Some(o + d * t)
}

/// How far below the world point `top_mm` the vertical edge through it reaches when its lower
/// end is seen at `bottom_px`, mm (the point of the vertical line closest to that ray).
pub fn drop_below_mm(camera: &Camera, top_mm: DVec3, bottom_px: DVec2) -> f64 {
    drop_below_on(&Projector::new(camera), top_mm, bottom_px)
}

/// [`drop_below_mm`] with the camera's projector made once.
pub(super) fn drop_below_on(proj: &Projector, top_mm: DVec3, bottom_px: DVec2) -> f64 {
    drop_below_ray(proj.ray(bottom_px), top_mm)
}

/// [`drop_below_mm`] for the ray `(origin, unit direction)` through the lower end.
pub(super) fn drop_below_ray((o, d): (DVec3, DVec3), top_mm: DVec3) -> f64 {
    let w0 = top_mm - o;
    let b = DVec3::Y.dot(d);
    let denom = 1.0 - b * b;
    if denom.abs() < 1e-12 {
        return 0.0;
    }
    let s = (b * d.dot(w0) - DVec3::Y.dot(w0)) / denom;
    -s
}

/// The world horizontal axis (±x or ±z, unit) whose picture direction at `at_mm` is closest to
/// `picture_dir`, and the angle between them in degrees (Chapter VII: blocks in one direction
/// have their edges along the world axes).
pub fn horizontal_axis_for(camera: &Camera, at_mm: DVec3, picture_dir: DVec2) -> (DVec3, f64) {
    horizontal_axis_on(&Projector::new(camera), at_mm, picture_dir)
}

/// [`horizontal_axis_for`] with the camera's projector made once.
pub(super) fn horizontal_axis_on(
    proj: &Projector,
    at_mm: DVec3,
    picture_dir: DVec2,
) -> (DVec3, f64) {
    let p0 = proj.picture(at_mm);
    let mut best = (DVec3::X, f64::INFINITY);
    for axis in [DVec3::X, DVec3::NEG_X, DVec3::Z, DVec3::NEG_Z] {
        let q = proj.picture(at_mm + axis);
        let ang = (q - p0).angle_to(picture_dir).abs().to_degrees();
        if ang < best.1 {
            best = (axis, ang);
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::super::select::{select_vertices, tests::cube_drawing};
    use super::*;
    use crate::linedraw::visible_line_drawing;
    use crate::recognize::{CameraOptions, CornerView};
    use crate::scene::{Block, Scene};

    #[test]
    fn the_cube_fork_closes_its_top_rhombus_with_equal_sides() {
        let d = cube_drawing(10.0, DVec2::new(100.0, 100.0));
        let search = ParallelogramSearch::new(&d, 0.5);
        let fork = select_vertices(&d)
            .into_iter()
            .find(|v| v.index == 6)
            .unwrap();
        let p = search.search(&fork, Face::Top(TopCorner::Near)).unwrap();
        let [a, b] = p.closed.unwrap().map(|s| s.length_px);
        assert!(
            (a - 10.0).abs() < 1e-9 && (b - 10.0).abs() < 1e-9,
            "{a} {b}"
        );
        assert!((p.down_px.unwrap() - 10.0).abs() < 1e-9);
        // The fork has no right-down line: no face on that side (rule 3).
        assert!(search.search(&fork, Face::Top(TopCorner::Left)).is_none());
    }

    #[test]
    fn a_side_through_a_collinear_t_is_followed_to_its_end() {
        // Two b15 side by side (the thesis's Figure 6.17 second case): the near top edge runs
        // through the crack's T point, 15 mm then 30 mm.
        let scene = Scene::new(
            "pair",
            vec![
                Block::new("b15", DVec3::new(7.5, 7.5, 7.5), 0.0),
                Block::new("b15", DVec3::new(22.5, 7.5, 7.5), 0.0),
            ],
        );
        let cam = Camera::frame(
            &scene.world_vertices(),
            CornerView::Se,
            &CameraOptions::default(),
        );
        let d = visible_line_drawing(&scene, &cam);
        let search = ParallelogramSearch::new(&d, 0.5);
        let longest = select_vertices(&d)
            .iter()
            .filter_map(|v| search.search(v, Face::Top(TopCorner::Near)))
            .map(|p| p.sides.iter().map(|s| s.len()).max().unwrap_or(0))
            .max()
            .unwrap();
        assert_eq!(longest, 2, "one side passes the T point");
    }

    #[test]
    fn rays_give_millimetres_exactly_in_both_projections() {
        let corner = DVec3::new(15.0, 15.0, 0.0);
        for projection in crate::camera::BOTH_PROJECTIONS {
            let opts = CameraOptions {
                projection,
                ..CameraOptions::default()
            };
            let pts = [DVec3::ZERO, DVec3::new(30.0, 15.0, 15.0)];
            let cam = Camera::frame(&pts, CornerView::Ne, &opts);
            let px = cam.picture_from_world(corner).truncate();
            let back = point_at_height_mm(&cam, px, 15.0).unwrap();
            assert!(back.distance(corner) < 1e-6, "{back}");
            let below = cam.picture_from_world(corner - DVec3::Y * 7.5).truncate();
            assert!((drop_below_mm(&cam, corner, below) - 7.5).abs() < 1e-6);
            let side = cam.picture_from_world(corner + DVec3::X).truncate() - px;
            let (axis, ang) = horizontal_axis_for(&cam, corner, side);
            assert_eq!(axis, DVec3::X);
            assert!(ang < 1e-6);
        }
    }
}
