//! Tests of the render mesh and its shadow reach.

use super::polyhedron::*;
use super::reach::*;
use super::*;
use crate::camera::{CameraOptions, CornerView};
use crate::scene::Block;

fn cube() -> Block {
    Block::new("b15", DVec3::new(0.0, 7.5, 0.0), 0.0)
}

/// The corner view `view` framing [`cube`], as `render` frames a scene of it alone.
fn cube_camera(view: CornerView) -> Camera {
    Camera::frame(&cube().world_vertices(), view, &CameraOptions::default())
}

#[test]
fn a_bevelled_cube_has_6_faces_12_strips_8_corners_and_stays_inside() {
    let polygons = bevelled_block(&cube(), BEVEL_MM, &[CRACK_MM / 2.0; 6]);
    assert_eq!(polygons.len(), 6 + 12 + 8);
    assert_eq!(polygons.iter().filter(|p| p.corners.len() == 3).count(), 8);
    let half = 7.5 - CRACK_MM / 2.0;
    for p in &polygons {
        for c in &p.corners {
            let local = *c - DVec3::new(0.0, 7.5, 0.0);
            assert!(local.abs().max_element() <= half + 1e-9, "{c}");
        }
    }
    // A face's inset square: 15 - crack - 2 bevel on a side.
    let top = polygons
        .iter()
        .find(|p| p.outward == DVec3::Y)
        .expect("top face");
    let side = (top.corners[1] - top.corners[0]).length();
    assert!(
        (side - (15.0 - CRACK_MM - 2.0 * BEVEL_MM)).abs() < 1e-9,
        "{side}"
    );
    assert!(top
        .corners
        .iter()
        .all(|c| (c.y - (15.0 - CRACK_MM / 2.0)).abs() < 1e-9));
}

#[test]
fn every_triangle_faces_outward_and_the_bevel_strips_lean_between_faces() {
    let scene = Scene::new("c", vec![cube()]);
    let cam = cube_camera(CornerView::Ne);
    let v = photo_vertices(&scene, &cam, &[1.0]);
    assert_eq!(v.len(), (6 * 2 + 12 * 2 + 8) * 3 + 6);
    let centre = DVec3::new(0.0, 7.5, 0.0);
    for t in v[..v.len() - 6].chunks(3) {
        let p: Vec<DVec3> = t
            .iter()
            .map(|q| DVec3::from(q.position_mm.map(f64::from)))
            .collect();
        let n = (p[1] - p[0]).cross(p[2] - p[0]).normalize();
        assert!(n.dot((p[0] + p[1] + p[2]) / 3.0 - centre) > 0.0);
        assert!((n - DVec3::from(t[0].normal.map(f64::from))).length() < 1e-5);
    }
    let strip_normals = v[..v.len() - 6]
        .chunks(3)
        .filter(|t| {
            let n = DVec3::from(t[0].normal.map(f64::from));
            (n.abs().max_element() - std::f64::consts::FRAC_1_SQRT_2).abs() < 1e-5
        })
        .count();
    assert_eq!(strip_normals, 12 * 2, "twelve 45-degree bevel strips");
}

#[test]
fn the_light_is_seeded_per_scene_and_albedos_stay_in_range() {
    let cam = cube_camera(CornerView::Se);
    let still = key_light(&cam, 0.0, 1);
    let base = light_in_world(&cam).normalize();
    assert!((still.towards_light - base).length() < 1e-9);
    let a = key_light(&cam, 20.0, 1);
    assert_eq!(a, key_light(&cam, 20.0, 1));
    assert_ne!(a, key_light(&cam, 20.0, 2));
    let turn = a.towards_light.dot(base).acos().to_degrees();
    assert!(
        turn > 0.0 && turn <= 20.0 * std::f64::consts::SQRT_2 + 1e-9,
        "{turn}"
    );
    let scene = Scene::new("c", vec![cube(); 20]);
    let albedos = block_albedos(&scene, [0.8, 1.0], 3);
    assert!(albedos.iter().all(|a| (0.8..=1.0).contains(a)));
    assert_ne!(albedos[0], albedos[1]);
    assert_eq!(albedos, block_albedos(&scene, [0.8, 1.0], 3));
    assert_eq!(block_albedos(&scene, [0.9, 0.9], 3), vec![0.9; 20]);
}

#[test]
fn touching_blocks_get_a_crack_with_a_black_sheet_and_apart_blocks_none() {
    let pair = |dx: f64| {
        Scene::new(
            "p",
            vec![cube(), Block::new("b15", DVec3::new(dx, 7.5, 0.0), 0.0)],
        )
    };
    let c = find_contacts(&pair(15.0));
    assert_eq!(c.touching[0].iter().filter(|t| **t).count(), 1);
    assert_eq!(c.touching[1].iter().filter(|t| **t).count(), 1);
    assert_eq!(c.sheets.len(), 2);
    assert!((polygon_area(&c.sheets[0].corners) - 225.0).abs() < 1e-9);
    assert!(c.sheets[0].corners.iter().all(|p| (p.x - 7.5).abs() < 1e-9));
    // Half overlapping (shifted 7.5 mm along z): half the patch.
    let mut shifted = pair(15.0);
    shifted.blocks[1].center_mm.z = 7.5;
    let c = find_contacts(&shifted);
    assert!((polygon_area(&c.sheets[0].corners) - 112.5).abs() < 1e-9);
    let apart = find_contacts(&pair(15.5));
    assert!(apart.sheets.is_empty());
    assert!(apart.touching.iter().flatten().all(|t| !t));
}

#[test]
fn a_swept_box_meets_what_lies_towards_the_light_only() {
    let unit = (DVec3::ZERO, DVec3::ONE);
    let up = DVec3::new(0.0, 1.0, 0.0);
    let above = (DVec3::new(0.0, 5.0, 0.0), DVec3::new(1.0, 6.0, 1.0));
    let below = (DVec3::new(0.0, -6.0, 0.0), DVec3::new(1.0, -5.0, 1.0));
    let aside = (DVec3::new(3.0, 5.0, 0.0), DVec3::new(4.0, 6.0, 1.0));
    assert!(swept_box_meets(unit, up, above));
    assert!(!swept_box_meets(unit, up, below), "behind the light's path");
    assert!(!swept_box_meets(unit, up, aside), "beside the light's path");
    assert!(
        swept_box_meets(grow_box(unit, 2.0), up, aside),
        "within the reach"
    );
    let slanted = DVec3::new(1.0, 1.0, 0.0).normalize();
    assert!(swept_box_meets(unit, slanted, aside));
}

/// Whether triangle `t` (its vertices' normal) turns away from direction `dir`, by more
/// than an f32 normal's rounding (a face seen edge-on does not).
/// A cube with another on top, shifted 7.5 mm across `cam`'s key light (`sign` 1: towards
/// it, -1: away), and the direction towards that light.
fn stacked_across_the_light(cam: &Camera, sign: f64) -> (Scene, DVec3) {
    let light = key_light(cam, 0.0, 1).towards_light;
    let shift = sign * DVec3::new(light.x, 0.0, light.z).normalize() * 7.5;
    let upper = Block::new("b15", DVec3::new(0.0, 22.5, 0.0) + shift, 0.0);
    (Scene::new("s", vec![cube(), upper]), light)
}

fn turned_away(t: &[PhotoVertex], dir: DVec3) -> bool {
    DVec3::from(t[0].normal.map(f64::from)).dot(dir.normalize()) < -1e-6
}

/// Whether triangle `t` runs clockwise in `camera`'s picture (x right, y up) by more than
/// rounding: the back face the radiance pass culls. A face seen edge-on (a sliver whose
/// area is a rounding of its vertices, under 1e-4 of its longest side squared) does not.
fn clockwise_on_screen(t: &[PhotoVertex], camera: &Camera) -> bool {
    let p: Vec<glam::DVec2> = t
        .iter()
        .map(|v| {
            let q = camera.picture_from_world(DVec3::from(v.position_mm.map(f64::from)));
            glam::DVec2::new(q.x, q.y)
        })
        .collect();
    let longest_sq = [p[1] - p[0], p[2] - p[1], p[0] - p[2]]
        .iter()
        .map(|e| e.length_squared())
        .fold(0.0, f64::max);
    (p[1] - p[0]).perp_dot(p[2] - p[0]) < -1e-4 * longest_sq
}

#[test]
fn each_pass_gets_the_triangles_it_does_not_cull() {
    // A stack, a touching neighbour (cracks and their sheets) and a jittered light.
    let upper = Block::new("b15", DVec3::new(3.0, 22.5, 2.0), 0.0);
    let beside = Block::new("b15", DVec3::new(15.0, 7.5, 0.0), 0.0);
    let scene = Scene::new("s", vec![cube(), upper, beside]);
    let albedos = [0.9, 0.8, 0.85];
    for view in CornerView::ALL {
        let cam = cube_camera(view);
        let light = key_light(&cam, 20.0, 3).towards_light;
        let m = photo_mesh(&scene, &cam, &albedos, light, 9.0);
        let tris = |r: std::ops::Range<usize>| m.vertices[r].to_vec();
        let drawn = [
            tris(m.shadowed.clone()),
            tris(m.behind.clone()),
            tris(m.unshadowed.clone()),
        ]
        .concat();
        assert!(!drawn.is_empty());
        for t in drawn.chunks_exact(3) {
            assert!(
                !clockwise_on_screen(t, &cam),
                "{view:?}: a triangle turned away from the eye"
            );
        }
        let casters = tris(m.casters.clone());
        assert!(casters.chunks_exact(3).all(|t| !turned_away(t, -light)));
        // Every face turned away from the light casts, as in the plain mesh.
        let plain = photo_vertices(&scene, &cam, &albedos);
        let away = plain
            .chunks_exact(3)
            .filter(|t| !turned_away(t, -light))
            .count();
        assert_eq!(casters.len() / 3, away, "{view:?}");
        // The ranges cover every vertex, so nothing is uploaded that no pass draws.
        assert_eq!(m.shadowed.start, 0);
        assert_eq!(
            (m.shadowed.end, m.behind.end),
            (m.behind.start, m.unshadowed.start)
        );
        assert!(m.casters.start >= m.unshadowed.start && m.casters.start <= m.unshadowed.end);
        assert_eq!(m.casters.end, m.vertices.len());
    }
}

#[test]
fn only_faces_and_floor_near_another_block_get_the_shadow_test() {
    let cam = cube_camera(CornerView::Ne);
    let light = key_light(&cam, 0.0, 1).towards_light;
    let lone = Scene::new("c", vec![cube()]);
    let m = photo_mesh(&lone, &cam, &[0.9], light, 9.0);
    // A lone convex block shades no face of its own: only the floor near it is shadowed.
    let shadowed = &m.vertices[m.shadowed.clone()];
    assert!(!shadowed.is_empty() && shadowed.iter().all(|v| v.albedo == 0.15));
    assert!(shadowed.iter().all(|v| v.position_mm[1] == 0.0));
    // Every block triangle turned to the eye is drawn once, whichever pipeline draws it.
    let all = photo_vertices(&lone, &cam, &[0.9]);
    let seen: Vec<PhotoVertex> = all
        .chunks_exact(3)
        .filter(|t| !clockwise_on_screen(t, &cam))
        .flatten()
        .copied()
        .collect();
    let blocks = |v: &[PhotoVertex]| v.iter().filter(|v| v.albedo != 0.15).count();
    let radiance = [
        &m.vertices[m.shadowed.clone()],
        &m.vertices[m.unshadowed.clone()],
    ];
    assert_eq!(blocks(&radiance.concat()), blocks(&seen));
    assert!(m.behind.is_empty());
    // A cube on top of another, shifted towards the light: the lower one's top faces it.
    let (stack, _) = stacked_across_the_light(&cam, 1.0);
    let m = photo_mesh(&stack, &cam, &[0.9, 0.8], light, 9.0);
    let shadowed = &m.vertices[m.shadowed.clone()];
    assert!(shadowed
        .iter()
        .any(|v| v.albedo == 0.9 && v.normal[1] > 0.99));
    assert!(!shadowed
        .iter()
        .any(|v| v.albedo == 0.8 && v.normal[1] > 0.99));
    let rest = &m.vertices[m.unshadowed.clone()];
    assert!(rest
        .iter()
        .any(|v| v.position_mm[1] == -OUTER_FLOOR_DROP_MM as f32));
}

#[test]
fn a_face_partly_within_reach_is_split_and_drawn_whole_behind() {
    let cam = cube_camera(CornerView::Ne);
    // A cube on top of another, shifted away from the light: the lower top's half on the
    // light's side is lit beyond 3 mm from the upper block.
    let (stack, light) = stacked_across_the_light(&cam, -1.0);
    let m = photo_mesh(&stack, &cam, &[0.9, 0.8], light, 3.0);
    let lower_top = |t: &&[PhotoVertex]| t[0].albedo == 0.9 && t[0].normal[1] > 0.99;
    let top_area = |v: &[PhotoVertex]| -> f64 {
        v.chunks_exact(3)
            .filter(lower_top)
            .map(|t| {
                let p = t.iter().map(|v| DVec3::from(v.position_mm.map(f64::from)));
                polygon_area(&p.collect::<Vec<_>>())
            })
            .sum()
    };
    let behind = &m.vertices[m.behind.clone()];
    let shadowed = &m.vertices[m.shadowed.clone()];
    let (part, whole) = (top_area(shadowed), top_area(behind));
    // The lower top: its sides touch nothing, so only the bevel insets them.
    let side = 15.0 - 2.0 * BEVEL_MM;
    assert!((whole - side * side).abs() < 1e-3, "{whole}");
    assert!(
        part > 0.3 * whole && part < 0.9 * whole,
        "{part} of {whole}"
    );
    // The whole top is drawn once behind, not also in front.
    let front = &m.vertices[m.unshadowed.clone()];
    assert_eq!(top_area(front), 0.0);
    // With the reach of the shader, the whole top is within reach: shadowed, drawn once.
    let m = photo_mesh(&stack, &cam, &[0.9, 0.8], light, 9.0);
    assert!((top_area(&m.vertices[m.shadowed.clone()]) - side * side).abs() < 1e-3);
    assert_eq!(top_area(&m.vertices[m.shadowed.end..]), 0.0);
}

#[test]
fn without_shadows_every_seen_triangle_is_drawn_without_the_test_and_nothing_casts() {
    let cam = cube_camera(CornerView::Ne);
    let (stack, light) = stacked_across_the_light(&cam, -1.0);
    let m = photo_mesh(&stack, &cam, &[0.9, 0.8], light, 3.0);
    assert!(!m.shadowed.is_empty() && !m.behind.is_empty() && !m.casters.is_empty());
    let bare = m.without_shadows();
    assert!(bare.shadowed.is_empty() && bare.casters.is_empty());
    assert_eq!(bare.behind, 0..m.behind.len());
    assert_eq!(bare.unshadowed, m.behind.len()..bare.vertices.len());
    // The whole faces first (drawn behind), then the parts that had the shadow test and
    // the rest, all drawn without it; no caster, as no shadow map is needed.
    let expected = [
        &m.vertices[m.behind.clone()],
        &m.vertices[m.shadowed.clone()],
        &m.vertices[m.unshadowed.clone()],
    ]
    .concat();
    assert_eq!(bare.vertices, expected);
}

#[test]
fn the_reach_hulls_only_the_grown_points_that_can_bound_it() {
    // Every point of the 16-gons around every vertex, hulled, against the points within
    // each vertex's cone: the same polygon, on random convex hulls and on a segment.
    let mut rng = rand::rngs::StdRng::seed_from_u64(7);
    let radius = 9.0;
    for case in 0..200 {
        let n = if case % 10 == 0 {
            2
        } else {
            rng.random_range(3..12)
        };
        let points: Vec<glam::DVec2> = (0..n)
            .map(|_| glam::DVec2::new(rng.random_range(-20.0..20.0), rng.random_range(-20.0..20.0)))
            .collect();
        let hull = crate::geom::convex_hull(&points);
        let every: Vec<glam::DVec2> = hull
            .iter()
            .flat_map(|c| REACH_DIRECTIONS.iter().map(move |d| *c + *d * radius))
            .collect();
        let want = crate::geom::convex_hull(&every);
        let kept = grown_corners(&hull, radius);
        assert!(kept.len() < every.len() || hull.len() < 3);
        let got = crate::geom::convex_hull(&kept);
        assert_eq!(got.len(), want.len(), "case {case}");
        for (g, w) in got.iter().zip(&want) {
            assert!(g.distance(*w) < 1e-9, "case {case}: {g} against {w}");
        }
    }
    // The cone test can fail: a vertex is not the farthest against its edges' directions.
    let (e_in, e_out) = (glam::DVec2::X, glam::DVec2::Y);
    assert!(in_cone(
        glam::DVec2::new(1.0, -1.0).normalize(),
        e_in,
        e_out
    ));
    assert!(!in_cone(
        glam::DVec2::new(-1.0, -1.0).normalize(),
        e_in,
        e_out
    ));
    assert!(!in_cone(
        glam::DVec2::new(1.0, 1.0).normalize(),
        e_in,
        e_out
    ));
    // Widened by half a 16-gon side's angle, 11.25 degrees, and no more.
    let at = |deg: f64| glam::DVec2::from_angle(deg.to_radians());
    assert!(in_cone(at(11.0), e_in, e_out) && in_cone(at(-101.0), e_in, e_out));
    assert!(!in_cone(at(11.5), e_in, e_out) && !in_cone(at(-101.5), e_in, e_out));
}

#[test]
fn a_neighbour_flush_with_a_face_casts_no_shadow_on_it() {
    // Two cubes side by side, touching: each top is flush with the other's, so neither top
    // needs the shadow test, though each block's box, grown by the reach, meets the
    // other's.
    let cam = cube_camera(CornerView::Ne);
    let light = key_light(&cam, 0.0, 1).towards_light;
    let beside = Block::new("b15", DVec3::new(15.0, 7.5, 0.0), 0.0);
    let row = Scene::new("r", vec![cube(), beside]);
    let m = photo_mesh(&row, &cam, &[0.9, 0.8], light, 9.0);
    let shadowed = &m.vertices[m.shadowed.clone()];
    assert!(
        !shadowed
            .iter()
            .any(|v| v.albedo != PHOTO_FLOOR_ALBEDO as f32 && v.normal[1] > 0.99),
        "a top face got the shadow test"
    );
    // The reach test itself: a solid flush with the face reaches nothing; lifted a
    // millimetre above it, it reaches the face.
    let frame = LightFrame::new(light);
    let top = [
        DVec3::new(-7.5, 15.0, -7.5),
        DVec3::new(-7.5, 15.0, 7.5),
        DVec3::new(7.5, 15.0, 7.5),
        DVec3::new(7.5, 15.0, -7.5),
    ];
    let flush = beside.world_vertices();
    assert!(shadow_reach(&top, DVec3::Y, &frame, &[&flush], 9.0).is_empty());
    let lifted: Vec<DVec3> = flush.iter().map(|p| *p + DVec3::Y).collect();
    let reached = shadow_reach(&top, DVec3::Y, &frame, &[&lifted], 9.0);
    let near = frame.across(DVec3::new(7.0, 15.0, 0.0));
    assert!(crate::geom::inside_convex(&reached, near, 0.0));
    // Lifted back onto the top's plane, a point of the region stays where it was across
    // the light.
    let on_top = frame.onto_plane(near, top[0], DVec3::Y);
    assert!((on_top - DVec3::new(7.0, 15.0, 0.0)).length() < 1e-9);
}

/// With a floor bounce a top face sees the whole sky and no floor, a side half of each, a
/// face turned down the floor alone (twice a side's bounce); without one the ambient is alike
/// on every face.
#[test]
fn the_ambient_splits_into_sky_above_and_floor_below_the_face() {
    let (sky, bounce) = (0.2, 0.05);
    assert_eq!(ambient_radiance(sky, bounce, DVec3::Y), sky);
    assert!((ambient_radiance(sky, bounce, DVec3::X) - (sky / 2.0 + bounce)).abs() < 1e-12);
    assert!((ambient_radiance(sky, bounce, -DVec3::Y) - 2.0 * bounce).abs() < 1e-12);
    for n in [DVec3::Y, DVec3::X, -DVec3::Z, -DVec3::Y] {
        assert_eq!(ambient_radiance(sky, 0.0, n), sky);
    }
}
