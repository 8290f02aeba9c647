//! Unit tests of the view meshes: floor fill, depth and drawing order, checked against ray casts.

use super::*;
use crate::camera::{CameraOptions, CornerView};
use crate::scene::Block;

fn cube() -> Scene {
    Scene::new("c", vec![Block::new("b15", DVec3::new(0.0, 7.5, 0.0), 0.0)])
}

/// The exact depth, in (unrounded) steps of 1/16 mm, of the floor point seen through the
/// centre of raster pixel (`column`, `row`): a ray cast independent of [`FloorFill`].
fn ray_cast_floor_units(camera: &Camera, column: u32, row: u32) -> f64 {
    let h = f64::from(camera.size_px[1]);
    let (o, d) = camera.ray_through_picture(f64::from(column) + 0.5, h - f64::from(row) - 0.5);
    let hit = o + d * (-o.y / d.y);
    camera.picture_from_world(hit).z * crate::camera::DEPTH_UNITS_PER_MM
}

/// Pixels of a grid over the picture whose [`FloorFill`] depth is not the ray cast's, rounded.
fn floor_depths_off(fill: &FloorFill, camera: &Camera) -> usize {
    let [w, h] = camera.size_px;
    let mut off = 0;
    for row in (0..h).step_by(7) {
        for column in (0..w).step_by(5) {
            let want = ray_cast_floor_units(camera, column, row);
            // A depth within 1e-6 of a rounding tie could go either way.
            let tie = (want.fract() - 0.5).abs() < 1e-6;
            let got = f64::from(fill.depth_units(column as usize, row as usize));
            off += usize::from(!tie && got != want.round_ties_even().clamp(1.0, 65535.0));
        }
    }
    off
}

#[test]
fn computed_floor_depth_is_the_ray_cast_depth_rounded_in_both_projections() {
    let scene = cube();
    let pts = scene.blocks[0].world_vertices();
    for projection in crate::camera::BOTH_PROJECTIONS {
        let opts = CameraOptions {
            projection,
            size_px: [333, 97],
            ..Default::default()
        };
        for view in CornerView::ALL {
            let cam = Camera::frame(&pts, view, &opts);
            let fill = floor_fill(&scene, &cam).expect("a corner view is all floor");
            assert_eq!(fill.gray_level, 60);
            assert_eq!(floor_depths_off(&fill, &cam), 0, "{view:?} {projection:?}");
            // A worse input: the fill of a row lower is off almost everywhere.
            let shifted = FloorFill {
                at_first_px: fill.at_first_px + fill.per_row,
                ..fill
            };
            assert!(
                floor_depths_off(&shifted, &cam) > 100,
                "{view:?} {projection:?}"
            );
        }
    }
}

#[test]
fn floor_is_drawn_when_the_horizon_is_in_view_or_a_block_sinks_below_it() {
    let scene = cube();
    let pts = scene.blocks[0].world_vertices();
    let low = CameraOptions {
        projection: crate::camera::Projection::Perspective { fov_y_deg: 40.0 },
        elevation_deg: 8.0,
        ..Default::default()
    };
    let cam = Camera::frame(&pts, CornerView::Ne, &low);
    assert!(
        floor_fill(&scene, &cam).is_none(),
        "the horizon is in the picture"
    );
    let cam = Camera::frame(&pts, CornerView::Ne, &CameraOptions::default());
    assert!(floor_fill(&scene, &cam).is_some());
    let sunk = Scene::new(
        "s",
        vec![Block::new("b15", DVec3::new(0.0, 7.49, 0.0), 0.0)],
    );
    assert!(
        floor_fill(&sunk, &cam).is_none(),
        "the floor must hide what sinks"
    );
}

#[test]
fn computed_floor_depth_rounds_half_to_even_and_clamps_like_the_shader() {
    let at = |depth_mm: f64| FloorFill {
        gray_level: 60,
        at_first_px: depth_mm,
        per_column: 0.0,
        per_row: 0.0,
        reciprocal: false,
    };
    // 16.5 and 17.5 steps of 1/16 mm: ties go to the even step.
    assert_eq!(at(16.5 / 16.0).depth_units(0, 0), 16);
    assert_eq!(at(17.5 / 16.0).depth_units(0, 0), 18);
    assert_eq!(at(17.51 / 16.0).depth_units(0, 0), 18);
    assert_eq!(at(0.001).depth_units(0, 0), 1);
    assert_eq!(at(5000.0).depth_units(0, 0), 65535);
    let reciprocal = FloorFill {
        at_first_px: 1.0 / 100.0,
        reciprocal: true,
        ..at(0.0)
    };
    assert_eq!(reciprocal.depth_units(3, 4), 1600);
}

#[test]
fn levels_are_210_150_100_and_floor_60_in_every_corner_view_and_elevation() {
    let pts = cube().blocks[0].world_vertices();
    for elevation_deg in [10.0, crate::geom::ISOMETRIC_ELEVATION_DEG, 60.0, 85.0] {
        let opts = CameraOptions {
            elevation_deg,
            ..Default::default()
        };
        for view in CornerView::ALL {
            let cam = Camera::frame(&pts, view, &opts);
            // The two visible side faces: normals with a positive component towards the eye.
            let eye = cam.towards_eye();
            let sides: Vec<DVec3> = [DVec3::X, -DVec3::X, DVec3::Z, -DVec3::Z]
                .into_iter()
                .filter(|n| n.dot(eye) > 0.0)
                .collect();
            assert_eq!(sides.len(), 2);
            let right_dir = cam.view_matrix().row(0).truncate();
            let (left, right) = if sides[0].dot(right_dir) < sides[1].dot(right_dir) {
                (sides[0], sides[1])
            } else {
                (sides[1], sides[0])
            };
            assert_eq!(face_gray_level(DVec3::Y, BLOCK_ALBEDO, &cam), 210);
            assert_eq!(face_gray_level(left, BLOCK_ALBEDO, &cam), 150, "{view:?}");
            assert_eq!(face_gray_level(right, BLOCK_ALBEDO, &cam), 100, "{view:?}");
            assert_eq!(face_gray_level(DVec3::Y, FLOOR_ALBEDO, &cam), 60);
        }
    }
}

#[test]
fn cube_mesh_has_twelve_triangles_then_the_floor_and_exact_edge_lines() {
    let scene = cube();
    let cam = Camera::frame(
        &scene.blocks[0].world_vertices(),
        CornerView::Ne,
        &CameraOptions::default(),
    );
    let v = scene_vertices(&scene, &cam).unwrap();
    assert_eq!(v.len(), 12 * 3 + 6);
    assert!(v[36..].iter().all(|v| v.block_id == 0));
    let h = cam.size_px[1] as f64;
    for t in v[..36].chunks(3) {
        for p in t {
            assert_eq!(p.block_id, 1);
            assert_eq!(
                p.edge_lines_px, t[0].edge_lines_px,
                "one face, one set of lines"
            );
            // Every vertex is a polygon corner: on exactly two of the four lines.
            let q = cam.picture_from_world(DVec3::from(p.position_mm.map(f64::from)));
            let (x, y) = (q.x, h - q.y);
            let on: Vec<f64> = p.edge_lines_px[..4]
                .iter()
                .map(|[a, b, c]| (*a as f64 * x + *b as f64 * y + *c as f64).abs())
                .collect();
            assert_eq!(on.iter().filter(|d| **d < 1e-3).count(), 2, "{on:?}");
            assert!(p.edge_lines_px[4..].iter().all(|l| *l == NO_EDGE_LINE));
        }
        // Counter-clockwise seen from outside: the triangle normal points away from the centre.
        let [a, b, c] = [t[0], t[1], t[2]].map(|p| DVec3::from(p.position_mm.map(f64::from)));
        let n = (b - a).cross(c - a);
        assert!(n.dot((a + b + c) / 3.0 - DVec3::new(0.0, 7.5, 0.0)) > 0.0);
    }
}

/// The stack's faces test four slots, the floor none; a face using slot 5 needs all eight,
/// and runs keep the drawing order.
#[test]
fn seam_line_runs_follow_the_slots_each_face_uses() {
    let scene = cube();
    let cam = Camera::frame(
        &scene.blocks[0].world_vertices(),
        CornerView::Ne,
        &CameraOptions::default(),
    );
    let mut v = scene_vertices(&scene, &cam).unwrap();
    assert_eq!(
        seam_line_runs(&v),
        vec![(0..36, SeamLines::Four), (36..42, SeamLines::None)]
    );
    // A line in slot 5 of the second triangle (its face's first half) splits the run.
    for p in &mut v[3..6] {
        p.edge_lines_px[5] = [0.0, 1.0, -10.0];
    }
    assert_eq!(
        seam_line_runs(&v),
        vec![
            (0..3, SeamLines::Four),
            (3..6, SeamLines::Eight),
            (6..36, SeamLines::Four),
            (36..42, SeamLines::None)
        ]
    );
    let mut only_slot_1 = [NO_EDGE_LINE; MAX_FACE_EDGES];
    only_slot_1[1] = [1.0, 0.0, -3.0];
    assert_eq!(SeamLines::of(&only_slot_1), SeamLines::Four);
    assert_eq!(seam_line_runs(&[]), vec![]);
}

/// The order that draws nearer blocks first: the reverse of index order in a view where the
/// later blocks are the nearer ones, with every triangle's corners kept.
#[test]
fn draw_order_puts_nearer_blocks_first_and_keeps_each_triangle() {
    let scene = Scene::new(
        "row",
        (0..3)
            .map(|i| Block::new("b15", DVec3::new(15.0 * i as f64, 7.5, 0.0), 0.0))
            .collect(),
    );
    let points = scene.world_vertices();
    let mut orders = Vec::new();
    for view in CornerView::ALL {
        let cam = Camera::frame(&points, view, &CameraOptions::default());
        let v = scene_vertices(&scene, &cam).unwrap();
        let row = cam.view_matrix().row(2).as_vec4().to_array();
        let order = nearer_first_order(&v, row);
        orders.push(order);
        let depth = |p: &Vertex| {
            -cam.view_matrix()
                .row(2)
                .dot(DVec3::from(p.position_mm.map(f64::from)).extend(1.0))
        };
        let ordered = in_draw_order(&v, order);
        let blocks = block_vertex_count(&v);
        assert_eq!(blocks, v.len() - 6);
        // The first block drawn is the nearest one.
        let first_id = ordered[0].block_id;
        let nearest = |id: u32| {
            v.iter()
                .filter(|p| p.block_id == id)
                .map(depth)
                .fold(f64::INFINITY, f64::min)
        };
        assert!(
            (1..=3).all(|id| nearest(first_id) <= nearest(id)),
            "{view:?}"
        );
        // The same triangles, corners in the same order, the floor last.
        let mut a: Vec<_> = v[..blocks].chunks(3).map(|t| format!("{t:?}")).collect();
        let mut b: Vec<_> = ordered[..blocks]
            .chunks(3)
            .map(|t| format!("{t:?}"))
            .collect();
        a.sort();
        b.sort();
        assert_eq!(a, b);
        assert_eq!(v[blocks..], ordered[blocks..]);
    }
    // The row runs along x: two views see block 3 nearest, two block 1.
    assert!(orders.contains(&DrawOrder::Ascending) && orders.contains(&DrawOrder::Descending));
}

/// A round part: 64 side quads and two 64-triangle fans (256 triangles); seams only on rim
/// chords and on the two silhouette generators, never between the side's facets.
#[test]
fn round_part_mesh_seams_only_rims_and_the_two_silhouette_generators() {
    let scene = Scene::new("r", vec![Block::new("c15", DVec3::new(0.0, 7.5, 0.0), 0.0)]);
    let cam = Camera::frame(
        &scene.blocks[0].world_vertices(),
        CornerView::Sw,
        &CameraOptions::default(),
    );
    let v = scene_vertices(&scene, &cam).unwrap();
    assert_eq!(v.len(), 256 * 3 + 6);
    let n = crate::scene::ROUND_PRISM_SIDES;
    let sides = &v[..n * 6];
    let generators = sides
        .chunks(6)
        .filter(|q| {
            [0, 2]
                .iter()
                .any(|&e| q[0].edge_lines_px[e] != NO_EDGE_LINE)
        })
        .count();
    // Each silhouette generator is drawn by the one facet on the visible side of it.
    assert_eq!(generators, 2);
    for q in sides.chunks(6) {
        assert!(q[0].edge_lines_px[1] != NO_EDGE_LINE && q[0].edge_lines_px[3] != NO_EDGE_LINE);
    }
    // Ring fans: only the rim chord (edge 1) carries a line.
    for t in v[n * 6..256 * 3].chunks(3) {
        assert_eq!(t[0].edge_lines_px[0], NO_EDGE_LINE);
        assert_ne!(t[0].edge_lines_px[1], NO_EDGE_LINE);
        assert_eq!(t[0].edge_lines_px[2], NO_EDGE_LINE);
    }
}
