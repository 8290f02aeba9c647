//! Unit tests of settling on scenes a reader can check by eye.

use super::*;
use crate::scene::scene_to_json;

fn two_layer() -> Scene {
    Scene::new(
        "two_layer",
        vec![
            Block::new("b30", DVec3::new(0.0, 7.5, 0.0), 0.0),
            Block::new("b15", DVec3::new(0.0, 22.5, 0.0), 90.0),
        ],
    )
}

/// A b15 on a b15, shifted 10 mm: its centre of mass is 2.5 mm beyond the edge, so it tips.
fn overhanging() -> Scene {
    Scene::new(
        "tips",
        vec![
            Block::new("b15", DVec3::new(0.0, 7.5, 0.0), 0.0),
            Block::new("b15", DVec3::new(10.0, 22.5, 0.0), 0.0),
        ],
    )
}

#[test]
fn a_two_layer_stack_is_stable_and_snapped_back() {
    let s = settle(&two_layer(), &SettleParams::default()).unwrap();
    assert!(s.report.stable, "{:?}", s.report);
    assert!(s.report.at_rest);
    // rapier leaves the blocks a little into their supports, but well inside the tolerance.
    assert!(
        s.report.max_drift_mm > 0.0 && s.report.max_drift_mm < 0.2,
        "{:?}",
        s.report
    );
    assert!(s.report.max_turn_deg < 0.1);
    assert!(s.report.blocks[0].touches_floor && !s.report.blocks[1].touches_floor);
    for (a, b) in s.scene.blocks.iter().zip(&two_layer().blocks) {
        assert_eq!(a.center_mm, b.center_mm);
        assert!(matches!(a.orientation, Orientation::Quaternion(_)));
        assert!(a.rotation().angle_between(b.rotation()) < 1e-12);
    }
    assert!(s.scene.meta.as_ref().unwrap().contains_key("settle"));
    s.scene.validate("settled").unwrap();
}

#[test]
fn an_overhanging_block_is_unstable_and_reported() {
    let params = SettleParams::default();
    let s = settle(&overhanging(), &params).unwrap();
    assert!(!s.report.stable);
    assert!(
        s.report.moved_blocks(&params).contains(&1),
        "{:?}",
        s.report
    );
    assert!(s.report.blocks[1].drift_mm > 2.0, "{:?}", s.report);
    assert!(s.report.blocks[1].turn_deg > 10.0, "{:?}", s.report);
    let text = s.report.describe_moved(&s.scene, &params);
    assert!(text.contains("block 1 (b15)"), "{text}");
    // The drifted poses are written as simulated.
    assert!(s.scene.blocks[1].center_mm.x > 10.0);
}

#[test]
fn a_block_placed_in_the_air_falls_and_touches_the_floor() {
    let scene = Scene::new(
        "floating",
        vec![Block::new("b15", DVec3::new(0.0, 27.5, 0.0), 0.0)],
    );
    let params = SettleParams::default();
    let s = settle(&scene, &params).unwrap();
    assert!(!s.report.stable);
    let b = s.report.blocks[0];
    assert!(
        b.touches_floor && !b.should_touch_floor && b.drift_mm > 19.0,
        "{b:?}"
    );
}

#[test]
fn settling_is_bitwise_deterministic() {
    let a = settle(&overhanging(), &SettleParams::default()).unwrap();
    let b = settle(&overhanging(), &SettleParams::default()).unwrap();
    for (x, y) in a.scene.blocks.iter().zip(&b.scene.blocks) {
        let bits = |v: DVec3| v.to_array().map(f64::to_bits);
        assert_eq!(bits(x.center_mm), bits(y.center_mm));
        let q = |b: &Block| b.rotation().to_array().map(f64::to_bits);
        assert_eq!(q(x), q(y));
    }
    assert_eq!(a.report.steps, b.report.steps);
    assert_eq!(
        a.report.max_drift_mm.to_bits(),
        b.report.max_drift_mm.to_bits()
    );
}

#[test]
fn settling_a_settled_scene_changes_nothing() {
    let once = settle(&two_layer(), &SettleParams::default()).unwrap();
    let twice = settle(&once.scene, &SettleParams::default()).unwrap();
    assert_eq!(scene_to_json(&once.scene), scene_to_json(&twice.scene));
}

#[test]
fn a_turned_block_and_a_wide_stack_are_stable() {
    let scene = Scene::new(
        "mixed",
        vec![
            Block::new("b30", DVec3::new(0.0, 7.5, 0.0), 0.0),
            Block::new("b30", DVec3::new(0.0, 7.5, 15.0), 0.0),
            Block::new("b30", DVec3::new(0.0, 22.5, 7.5), 90.0),
            Block::new("b7_5", DVec3::new(0.0, 33.75, 7.5), 0.0),
            Block::new("b15", DVec3::new(40.0, 7.5, 0.0), 30.0),
        ],
    );
    scene.validate("mixed").unwrap();
    let s = settle(&scene, &SettleParams::default()).unwrap();
    assert!(s.report.stable, "{:?}", s.report);
}

#[test]
fn bad_parameters_are_refused() {
    let params = SettleParams {
        dt_s: 0.0,
        ..SettleParams::default()
    };
    assert!(matches!(
        settle(&two_layer(), &params),
        Err(PhysicsError::Params(_))
    ));
}

#[test]
fn aligned_towers_of_six_stay_up() {
    for (id, h) in [("b15", 15.0), ("b7_5", 7.5), ("b30", 15.0)] {
        let blocks = (0..6)
            .map(|i| Block::new(id, DVec3::new(0.0, h / 2.0 + h * i as f64, 0.0), 0.0))
            .collect();
        let s = settle(&Scene::new("tower", blocks), &SettleParams::default()).unwrap();
        assert!(s.report.stable, "{id}: {:?}", s.report);
    }
}

/// Regression: with f32 quarter-turn quaternions on the bodies, this supported three-layer
/// stack (a generator draw) shed block 10 by 52 mm; folding the quarter turns into the
/// colliders keeps it standing.
#[test]
fn a_three_layer_stack_with_quarter_turns_stays_up() {
    let b = |id: &str, x: f64, y: f64, z: f64, yaw: f64| Block::new(id, DVec3::new(x, y, z), yaw);
    let scene = Scene::new(
        "three_layer",
        vec![
            b("b30", 15.0, 7.5, 7.5, 0.0),
            b("b15", 37.5, 7.5, 7.5, 0.0),
            b("b15", 7.5, 7.5, 22.5, 0.0),
            b("b30", 30.0, 7.5, 22.5, 0.0),
            b("b30", 60.0, 7.5, 22.5, 0.0),
            b("b15", 60.0, 22.5, 22.5, 0.0),
            b("b30", 30.0, 22.5, 15.0, 0.0),
            b("b15", 7.5, 22.5, 7.5, 90.0),
            b("b15", 7.5, 22.5, 22.5, 0.0),
            b("b15", 22.5, 37.5, 15.0, 90.0),
            b("b15", 37.5, 37.5, 15.0, 90.0),
            b("b15", 7.5, 37.5, 15.0, 0.0),
        ],
    );
    scene.validate("three_layer").unwrap();
    let s = settle(&scene, &SettleParams::default()).unwrap();
    assert!(s.report.stable, "{:?}", s.report);
}

/// The Chapter VII parts settle by their own shapes: a wedge on a Baustein 30 and a cube on the
/// wedge's flat top stay; a round part on a cube and a cube on a round part stay; a cube on the
/// wedge's 45-degree slope slides off (the convex hull keeps the slope).
///
/// NOTE: measured, a three-high b30 + w30 + b15 tower (cube on the wedge's top) ends 0.68 mm
/// and 0.57 degrees off, beyond the 0.5 mm drift tolerance: rapier's convex-hull contact is
/// softer than its cuboid-cuboid one. The generator keeps only stable scenes, so such towers
/// are simply not drawn.
#[test]
fn stacks_with_a_wedge_and_a_round_part_settle_stable() {
    let params = SettleParams::default();
    let stacks = [
        Scene::new(
            "wedge_on_b30",
            vec![
                Block::new("b30", DVec3::new(0.0, 7.5, 0.0), 0.0),
                Block::new("w30", DVec3::new(0.0, 22.5, 0.0), 0.0),
            ],
        ),
        Scene::new(
            "cube_on_wedge",
            vec![
                Block::new("w30", DVec3::new(0.0, 7.5, 0.0), 0.0),
                Block::new("b15", DVec3::new(-7.5, 22.5, 0.0), 90.0),
            ],
        ),
        Scene::new(
            "round_on_cube_cube_on_round",
            vec![
                Block::new("b15", DVec3::new(0.0, 7.5, 0.0), 0.0),
                Block::new("c15", DVec3::new(0.0, 22.5, 0.0), 0.0),
                Block::new("b15", DVec3::new(0.0, 37.5, 0.0), 0.0),
            ],
        ),
    ];
    for scene in &stacks {
        scene.validate(&scene.name).unwrap();
        let s = settle(scene, &params).unwrap();
        assert!(s.report.stable, "{}: {:?}", scene.name, s.report);
        assert!(
            s.report.max_drift_mm < 0.2,
            "{}: {:?}",
            scene.name,
            s.report
        );
    }
    // A cube whose centre is over the slope (x = 7.5, where the slope is 7.5 mm high, so its
    // bottom rests on the slope's top edge only): it tips or slides off.
    let on_slope = Scene::new(
        "cube_on_slope",
        vec![
            Block::new("w30", DVec3::new(0.0, 7.5, 0.0), 0.0),
            Block::new("b15", DVec3::new(7.5, 22.5, 0.0), 0.0),
        ],
    );
    on_slope.validate("slope").unwrap();
    let s = settle(&on_slope, &params).unwrap();
    assert!(!s.report.stable, "{:?}", s.report);
    assert!(
        s.report.moved_blocks(&params).contains(&1),
        "{:?}",
        s.report
    );
}

/// A round part lying next to a cube settles as a cylinder, not as its bounding box: dropped
/// 2 mm above the floor with its circle clear of the cube's corner (boxes overlapping), it
/// lands on the floor without being pushed.
#[test]
fn a_round_part_settles_as_a_cylinder() {
    let params = SettleParams::default();
    let scene = Scene::new(
        "round_by_corner",
        vec![
            Block::new("b15", DVec3::new(0.0, 7.5, 0.0), 0.0),
            Block::new("c15", DVec3::new(12.9, 7.5, 12.9), 0.0),
        ],
    );
    let s = settle(&scene, &params).unwrap();
    assert!(s.report.stable, "{:?}", s.report);
    assert!(s.report.blocks[1].touches_floor);
}

#[test]
fn a_stack_stops_after_the_rest_hold_not_a_sleep_timer() {
    let params = SettleParams::default();
    let hold_steps = (params.rest_hold_s / params.dt_s).ceil() as u32;
    let s = settle(&two_layer(), &params).unwrap();
    assert!(s.report.at_rest && s.report.stable, "{:?}", s.report);
    // The drop (2 layers of 0.05 mm) and the landing take a few steps, then the hold.
    assert!(
        s.report.steps >= hold_steps && s.report.steps < hold_steps + 10,
        "{:?}",
        s.report
    );
    // A longer hold simulates longer and comes to the same verdict and nearly the same drift.
    let long = SettleParams {
        rest_hold_s: 0.5,
        ..params
    };
    let l = settle(&two_layer(), &long).unwrap();
    assert!(l.report.stable && l.report.steps >= 120, "{:?}", l.report);
    assert!((l.report.max_drift_mm - s.report.max_drift_mm).abs() < 0.01);
}

#[test]
fn a_scene_still_moving_at_the_time_limit_is_not_at_rest() {
    let scene = Scene::new(
        "floating",
        vec![Block::new("b15", DVec3::new(0.0, 27.5, 0.0), 0.0)],
    );
    // 0.05 s of free fall from 20 mm: the block is still falling when time is up.
    let params = SettleParams {
        max_time_s: 0.05,
        ..SettleParams::default()
    };
    let s = settle(&scene, &params).unwrap();
    assert!(!s.report.at_rest && !s.report.stable, "{:?}", s.report);
    assert_eq!(s.report.steps, 12);
    let text = s.report.describe_moved(&scene, &params);
    assert!(text.contains("still moving after 12 steps"), "{text}");
}

#[test]
fn a_block_tipping_over_an_edge_is_never_at_rest_early() {
    // The overhanging b15 starts at rest; the criterion must not stop before it has tipped.
    let s = settle(&overhanging(), &SettleParams::default()).unwrap();
    assert!(s.report.steps > 30, "{:?}", s.report);
    assert!(s.report.blocks[1].turn_deg > 10.0, "{:?}", s.report);
}

/// `n` b15 in one aligned column.
fn b15_tower(n: usize) -> Scene {
    let blocks = (0..n)
        .map(|i| Block::new("b15", DVec3::new(0.0, 7.5 + 15.0 * i as f64, 0.0), 0.0))
        .collect();
    Scene::new("tower", blocks)
}

#[test]
fn the_predicted_sink_keeps_the_defaults_up_to_nine_layers_and_halves_the_step_at_ten() {
    let d = SettleParams::default();
    assert!((predicted_sink_mm(1, 240.0) - 0.004314).abs() < 1e-5);
    for layers in 0..=9 {
        assert_eq!(stiffened_for_layers(&d, layers), (d, 0), "{layers} layers");
    }
    let (p, halvings) = stiffened_for_layers(&d, 10);
    assert_eq!(halvings, 1);
    assert_eq!(
        (p.dt_s, p.contact_hz, p.static_contact_hz),
        (1.0 / 480.0, 480.0, 960.0)
    );
    assert!(predicted_sink_mm(10, p.contact_hz) <= d.sink_budget_mm);
    let (_, capped) = stiffened_for_layers(&d, 10_000);
    assert_eq!(capped, MAX_STIFFENINGS);
}

/// The stiffening is what keeps a ten-layer tower's top within budget: without it (a budget
/// no stack exceeds) the top block sinks about 0.4 mm, with it about a quarter of that.
#[test]
fn a_ten_layer_tower_sinks_less_with_stiffened_contacts() {
    let tower = b15_tower(10);
    let stiff = settle(&tower, &SettleParams::default()).unwrap();
    let soft_params = SettleParams {
        sink_budget_mm: 1e9,
        ..SettleParams::default()
    };
    let soft = settle(&tower, &soft_params).unwrap();
    assert!(stiff.report.stable, "{:?}", stiff.report);
    assert_eq!((stiff.report.stiffenings, soft.report.stiffenings), (1, 0));
    assert!(
        stiff.report.max_drift_mm < 0.15,
        "{}",
        stiff.report.max_drift_mm
    );
    assert!(
        soft.report.max_drift_mm > 0.3,
        "{}",
        soft.report.max_drift_mm
    );
    let meta = stiff.scene.meta.as_ref().unwrap()["settle"].clone();
    assert_eq!(meta["stiffenings"], 1);
    assert!(soft.scene.meta.as_ref().unwrap()["settle"]
        .get("stiffenings")
        .is_none());
}
