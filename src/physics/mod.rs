//! Settling scenes with rapier3d (docs/datasets.md "Settling"): the only home of rapier3d.
//! On it: whether blocks stand and why one moves ([`check_standing`]), and the order a robot
//! takes them apart ([`plan_disassembly`], thesis Chapter VII; docs/plan.md).
//!
//! A scene's blocks are dropped from a small gap above their intended poses onto a fixed floor
//! and simulated until the stack is **at rest** (every body below [`SettleParams::rest_speed_mm_s`]
//! and [`SettleParams::rest_spin_rad_s`] for [`SettleParams::rest_hold_s`] of simulated time) or
//! a time limit passes. The scene is **stable** when no
//! block moved more than [`SettleParams::drift_tol_mm`] nor turned more than
//! [`SettleParams::turn_tol_deg`] from its intended pose and no block touches the floor that was
//! not meant to (the thesis's Chapter VII constraint: every block rests on the floor or on other
//! blocks, "contacted at least by one surface").
//!
//! Units (see docs/architecture.md "Dependencies"): rapier runs in **metres** with
//! `length_unit` = 0.01 (block-sized slop, prediction distance and sleep thresholds), gravity
//! -9.81 m/s², a 1/240 s step and stiff contacts (240 Hz between bodies, 480 Hz against the
//! floor), so resting blocks sink only about 0.03 mm into their supports instead of 0.4 mm and
//! tall towers stay up (see [`SettleParams::dt_s`]).
//!
//! Policy for the settled scene (docs/formats.md "The exact line drawing"):
//! a **stable** scene is written back at its *intended* poses, as `rotation` quaternions, and
//! the measured drift goes into `meta.settle`; the exact line drawing keeps every seam and
//! settling it again gives the same bytes. An **unstable** scene carries the simulated poses.

mod fall;
mod grasp;
mod motion;
mod plan;
mod report;
mod stand;
mod support;

pub use fall::{block_cause, label_stability, Cause, StabilityLabel};
pub use grasp::{grasp_of, Grasp, Gripper};
pub use motion::{
    FirstMove, Motion, Trajectory, TrajectoryError, TRAJECTORY_FPS, TRAJECTORY_MAGIC,
};
pub use plan::{plan_disassembly, verify_disassembly, PlanOutcome, PlanParams, PlanStep};
pub use report::{BlockReport, SettleReport};
pub use stand::{check_standing, describe_cause, Movement, StandReport};
pub use support::{
    centre_of_mass_mm, centre_of_mass_overhang_mm, supports_of, Support, CONTACT_TOL_MM,
};

use motion::Recorder;

use crate::geom::{DQuat, DVec3};
use crate::scene::{layer_bottoms_mm, layer_index, Block, Orientation, Scene};
use rapier3d::prelude::{
    ColliderBuilder, IntegrationParameters, PhysicsWorld, RigidBodyBuilder, RigidBodyHandle,
};
use rapier3d::prelude::{Pose, Rotation, Vector};

/// Metres per millimetre: scene files are in mm, the simulation in m.
const M_PER_MM: f64 = 0.001;

/// Everything that decides how a scene is settled; every field gives its unit and default.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct SettleParams {
    /// Time step in seconds; default 1/240 s. NOTE: at 1/60 s (rapier's default, tuned for
    /// metre-sized bodies) a perfectly aligned tower of three b15 falls over: per step gravity
    /// moves a 15 mm block by a fifth of its size. Measured on aligned towers of 3, 6 and 10
    /// b15/b7_5/b30: 1/240 s with 240/480 Hz contacts and 8 solver iterations keeps all of them
    /// standing (max drift 0.03-0.5 mm from accumulated contact penetration) in 130-170 steps.
    pub dt_s: f64,
    /// Simulated time limit in seconds; default 4 s. A scene that is not at rest by then is
    /// unstable.
    pub max_time_s: f64,
    /// Rest criterion, speed: every body's centre moves slower than this, mm/s; default 1 (the
    /// peer benchmark's threshold, docs/benchmarks.md "Benchmarks").
    pub rest_speed_mm_s: f64,
    /// Rest criterion, spin: every body turns slower than this, rad/s; default 0.05.
    pub rest_spin_rad_s: f64,
    /// Rest criterion, hold: both bounds hold on every step for this long, s; default 0.05 (12
    /// steps of 1/240 s). NOTE: why this is enough. A body that stays below 1 mm/s for 0.05 s
    /// accelerates by less than 20 mm/s² (0.002 g), and a block tipping over an edge or falling
    /// does far more: the overhanging b15 of the unit tests, its centre of mass 2.5 mm beyond
    /// the edge, reaches 0.05 rad/s within a step. The pose tolerances judge the rest.
    pub rest_hold_s: f64,
    /// Largest allowed centre drift from the intended pose, mm; default 0.5 (docs/datasets.md "Settling").
    pub drift_tol_mm: f64,
    /// Largest allowed turn from the intended orientation, degrees; default 1 (docs/datasets.md "Settling").
    pub turn_tol_deg: f64,
    /// Gap per layer the blocks are lifted by before the drop, mm; default 0.05. A block whose
    /// bottom is at layer `k` (counting distinct bottom heights from the floor, `k` = 0 on the
    /// floor) is lifted by `(k + 1) * drop_gap_mm`, so nothing starts interpenetrating.
    pub drop_gap_mm: f64,
    /// A settled block whose lowest vertex is within this height of the floor touches it, mm;
    /// default 0.25.
    pub floor_contact_mm: f64,
    /// Block density, kg/m³; default 1050 (ABS plastic, about 1.05 g/cm³).
    pub density_kg_m3: f64,
    /// Coulomb friction coefficient of blocks and floor; default 0.55 (ABS on ABS).
    pub friction: f64,
    /// rapier's `length_unit` in metres per "unit" of scale; default 0.01 (dependencies.md).
    pub length_unit_m: f64,
    /// Natural frequency of contacts between blocks, Hz; default 240 (rapier's 30 Hz leaves
    /// 0.4 mm of penetration; above about 1/dt the solver becomes unstable and towers fall).
    pub contact_hz: f64,
    /// Natural frequency of contacts with the fixed floor, Hz; default 480.
    pub static_contact_hz: f64,
    /// Solver iterations per step; default 8 (rapier's 4 lets 6-block towers jitter awake).
    pub solver_iterations: usize,
    /// Largest predicted sink of the top layer into the stack below it, mm; default 0.2.
    /// NOTE: why. A soft contact of natural frequency `f` carrying the weight of the blocks
    /// above it rests about `g / (2 pi f)^2` per block of load inside its support (0.0043 mm at
    /// 240 Hz), so a stack of `n` layers sinks about `n (n + 1) / 2` times that at its top:
    /// 0.24 mm predicted, 0.40 mm measured for a tower of ten b15, whose top block then also
    /// leans. Where the prediction exceeds this budget, [`stiffened_for_layers`] halves the step
    /// and doubles both contact frequencies until it fits (a contact stiffer than `1 / dt_s`
    /// makes the solver unstable, so the two go together). Stacks of up to nine layers keep the
    /// defaults; the 1,000-block cube of `bench scale` (ten layers) settles at 1/480 s.
    pub sink_budget_mm: f64,
}

impl Default for SettleParams {
    fn default() -> Self {
        SettleParams {
            dt_s: 1.0 / 240.0,
            max_time_s: 4.0,
            rest_speed_mm_s: 1.0,
            rest_spin_rad_s: 0.05,
            rest_hold_s: 0.05,
            drift_tol_mm: 0.5,
            turn_tol_deg: 1.0,
            drop_gap_mm: 0.05,
            floor_contact_mm: 0.25,
            density_kg_m3: 1050.0,
            friction: 0.55,
            length_unit_m: 0.01,
            contact_hz: 240.0,
            static_contact_hz: 480.0,
            solver_iterations: 8,
            sink_budget_mm: 0.2,
        }
    }
}

/// A settled scene and the measurements behind its verdict.
#[derive(Debug, Clone, PartialEq)]
pub struct Settled {
    /// Stable: the intended poses as `rotation` quaternions with `meta.settle` set. Unstable:
    /// the simulated poses, also with `meta.settle`.
    pub scene: Scene,
    /// Per-block drift and the verdict.
    pub report: SettleReport,
}

/// Errors of settling; each names the block and the fix.
#[derive(Debug, thiserror::Error)]
pub enum PhysicsError {
    /// A block's pose has a NaN or infinite number.
    #[error("block {index} has a non-finite pose; fix its centre or rotation")]
    NotFinite {
        /// Block index (0-based).
        index: usize,
    },
    /// The block's polyhedron has no convex hull rapier can build.
    #[error("block {index} ({type_id}): its catalog vertices do not form a convex hull; fix the catalog entry")]
    BadShape {
        /// Block index (0-based).
        index: usize,
        /// Catalog id.
        type_id: &'static str,
    },
    /// Parameters out of range.
    #[error("invalid settle parameters: {0}")]
    Params(String),
}

/// Most blocks `settle` takes per scene (docs/limits.md "Settle and plan"): settling
/// costs more than in proportion to the blocks and their contacts (1,000 blocks 1.1 s, 2,000
/// 4 s, 4,000 23 s, 10,000 over 600 s in a debug build).
pub const MAX_SETTLE_BLOCKS: usize = 2_000;

/// Most blocks `plan` takes (docs/limits.md "Settle and plan"): each step of the disassembly
/// settles what is left, so the plan costs about the cube of the blocks (100 blocks 0.9 s,
/// 400 blocks 67 s in a debug build); a reconstruction holds at most 40.
pub const MAX_PLAN_BLOCKS: usize = 100;

/// Settles `scene` with rapier3d and judges its stability (docs/datasets.md "Settling").
///
/// Deterministic: the same scene and parameters give bit-identical results (rapier's
/// `enhanced-determinism`; one thread per scene).
pub fn settle(scene: &Scene, params: &SettleParams) -> Result<Settled, PhysicsError> {
    simulate(scene, params, None)
}

/// [`settle`], watching every step (docs/stability.md "The label"): the same simulation, bit
/// for bit, and its [`Motion`], with the trajectory at [`TRAJECTORY_FPS`] when `trajectory`.
pub fn settle_recorded(
    scene: &Scene,
    params: &SettleParams,
    trajectory: bool,
) -> Result<(Settled, Motion), PhysicsError> {
    let mut recorder = Recorder::new(scene, params, trajectory);
    let (settled, last) = simulate_with(scene, params, Some(&mut recorder))?;
    Ok((settled, recorder.finish(last)))
}

fn simulate(
    scene: &Scene,
    params: &SettleParams,
    recorder: Option<&mut Recorder>,
) -> Result<Settled, PhysicsError> {
    simulate_with(scene, params, recorder).map(|(settled, _)| settled)
}

/// The simulation behind [`settle`] and [`settle_recorded`]; also returns the last poses.
fn simulate_with(
    scene: &Scene,
    params: &SettleParams,
    mut recorder: Option<&mut Recorder>,
) -> Result<(Settled, Vec<(DVec3, DQuat)>), PhysicsError> {
    check_params(params)?;
    let layers = drop_layers(scene);
    let stack_layers = layers.iter().max().map_or(0, |&l| l + 1);
    let (simulated, stiffenings) = stiffened_for_layers(params, stack_layers);
    let params = &simulated;
    let mut world = build_world(scene, &layers, params)?;
    let max_steps = (params.max_time_s / params.dt_s).ceil() as u32;
    let hold_steps = (params.rest_hold_s / params.dt_s).ceil().max(1.0) as u32;
    let (mut steps, mut calm_steps) = (0, 0);
    let mut at_rest = world.bodies.is_empty();
    if let Some(r) = recorder.as_deref_mut() {
        r.start(params.dt_s, world.block_poses_mm());
    }
    while !at_rest && steps < max_steps {
        world.world.step();
        steps += 1;
        if let Some(r) = recorder.as_deref_mut() {
            r.observe(steps, world.block_poses_mm());
        }
        calm_steps = if world.all_calm(params) {
            calm_steps + 1
        } else {
            0
        };
        at_rest = calm_steps >= hold_steps;
    }
    let poses = world.block_poses_mm();
    let mut report = SettleReport::measure(scene, &poses, steps, at_rest, params);
    report.stiffenings = stiffenings;
    let scene = settled_scene(scene, &poses, &report);
    Ok((Settled { scene, report }, poses))
}

/// Most halvings of the step [`stiffened_for_layers`] makes (1/3840 s at the default step).
const MAX_STIFFENINGS: u32 = 4;

/// Standard gravity, m/s², as the world's.
const GRAVITY_M_S2: f64 = 9.81;

/// The top layer's predicted sink into a stack of `layers` layers, mm: `n (n + 1) / 2` blocks of
/// load resting on soft contacts of `contact_hz` (see [`SettleParams::sink_budget_mm`]).
pub fn predicted_sink_mm(layers: usize, contact_hz: f64) -> f64 {
    let omega = std::f64::consts::TAU * contact_hz;
    let loads = (layers * (layers + 1) / 2) as f64;
    loads * GRAVITY_M_S2 / (omega * omega) / M_PER_MM
}

/// The parameters a stack of `layers` layers is simulated with, and how many times the step
/// was halved: while [`predicted_sink_mm`] exceeds `sink_budget_mm`, half the step and twice
/// both contact frequencies (at most [`MAX_STIFFENINGS`] times). The rest criterion and the
/// time limit are in seconds, so they mean the same at every step.
pub fn stiffened_for_layers(params: &SettleParams, layers: usize) -> (SettleParams, u32) {
    let mut p = *params;
    let mut halvings = 0;
    while halvings < MAX_STIFFENINGS && predicted_sink_mm(layers, p.contact_hz) > p.sink_budget_mm {
        p.dt_s /= 2.0;
        p.contact_hz *= 2.0;
        p.static_contact_hz *= 2.0;
        halvings += 1;
    }
    (p, halvings)
}

fn check_params(p: &SettleParams) -> Result<(), PhysicsError> {
    let positive = [
        ("dt_s", p.dt_s),
        ("max_time_s", p.max_time_s),
        ("rest_speed_mm_s", p.rest_speed_mm_s),
        ("rest_spin_rad_s", p.rest_spin_rad_s),
        ("density_kg_m3", p.density_kg_m3),
        ("length_unit_m", p.length_unit_m),
        ("contact_hz", p.contact_hz),
        ("static_contact_hz", p.static_contact_hz),
        ("sink_budget_mm", p.sink_budget_mm),
    ];
    for (name, v) in positive {
        if !(v.is_finite() && v > 0.0) {
            return Err(PhysicsError::Params(format!("{name} must be > 0, got {v}")));
        }
    }
    if p.solver_iterations == 0 {
        return Err(PhysicsError::Params(
            "solver_iterations must be >= 1".into(),
        ));
    }
    let non_negative = [
        ("rest_hold_s", p.rest_hold_s),
        ("drift_tol_mm", p.drift_tol_mm),
        ("turn_tol_deg", p.turn_tol_deg),
        ("drop_gap_mm", p.drop_gap_mm),
        ("floor_contact_mm", p.floor_contact_mm),
        ("friction", p.friction),
    ];
    for (name, v) in non_negative {
        if !(v.is_finite() && v >= 0.0) {
            return Err(PhysicsError::Params(format!(
                "{name} must be >= 0, got {v}"
            )));
        }
    }
    Ok(())
}

/// The rapier world of one scene and the body of each block, in block order.
struct SceneWorld {
    world: PhysicsWorld,
    bodies: Vec<RigidBodyHandle>,
    /// Per block, the rotation folded into its collider (see [`canonical_frame`]): a block's
    /// rotation is its body's rotation times this.
    offsets: Vec<DQuat>,
}

impl SceneWorld {
    /// Every body slower than the rest bounds of `params` on this step (a sleeping body is
    /// still).
    fn all_calm(&self, params: &SettleParams) -> bool {
        let speed_m_s = (params.rest_speed_mm_s * M_PER_MM) as f32;
        let spin_rad_s = params.rest_spin_rad_s as f32;
        self.bodies.iter().all(|h| {
            let body = &self.world.bodies[*h];
            body.is_sleeping()
                || (body.linvel().length() < speed_m_s && body.angvel().length() < spin_rad_s)
        })
    }

    /// Each block's simulated (centre mm, rotation), in f64.
    fn block_poses_mm(&self) -> Vec<(DVec3, DQuat)> {
        self.bodies
            .iter()
            .map(|h| {
                let pose = self.world.bodies[*h].position();
                let t = pose.translation.as_dvec3() / M_PER_MM;
                (t, pose.rotation.as_dquat())
            })
            .zip(&self.offsets)
            .map(|((t, q), offset)| (t, (q * *offset).normalize()))
            .collect()
    }
}

fn build_world(
    scene: &Scene,
    layers: &[usize],
    params: &SettleParams,
) -> Result<SceneWorld, PhysicsError> {
    let mut world = PhysicsWorld::new();
    world.gravity = Vector::new(0.0, -9.81, 0.0);
    world.integration_parameters = integration_parameters(params);
    let floor_half_m = 1.0f32;
    let floor_side_half_m = (crate::geom::WORLD_HALF_EXTENT_MM / 1000.0) as f32;
    world.insert(
        RigidBodyBuilder::fixed().translation(Vector::new(0.0, -floor_half_m, 0.0)),
        ColliderBuilder::cuboid(floor_side_half_m, floor_half_m, floor_side_half_m)
            .friction(params.friction as f32),
    );
    let mut bodies = Vec::with_capacity(scene.blocks.len());
    let mut offsets = Vec::with_capacity(scene.blocks.len());
    for (index, block) in scene.blocks.iter().enumerate() {
        if !(block.center_mm.is_finite() && block.rotation().is_finite()) {
            return Err(PhysicsError::NotFinite { index });
        }
        let lift_mm = (layers[index] as f64 + 1.0) * params.drop_gap_mm;
        let (offset, swap_xz) = canonical_frame(block);
        let body_q = block.rotation().normalize() * offset.inverse();
        let body = RigidBodyBuilder::dynamic().pose(block_pose_m(block, body_q, lift_mm));
        let collider = block_collider(block, index, swap_xz)?
            .density(params.density_kg_m3 as f32)
            .friction(params.friction as f32);
        let (handle, _) = world.insert(body, collider);
        bodies.push(handle);
        offsets.push(offset);
    }
    Ok(SceneWorld {
        world,
        bodies,
        offsets,
    })
}

fn integration_parameters(params: &SettleParams) -> IntegrationParameters {
    let mut ip = IntegrationParameters {
        dt: params.dt_s as f32,
        length_unit: params.length_unit_m as f32,
        ..IntegrationParameters::default()
    };
    ip.num_solver_iterations = params.solver_iterations;
    ip.contact_softness.natural_frequency = params.contact_hz as f32;
    ip.static_contact_softness.natural_frequency = params.static_contact_hz as f32;
    ip
}

/// For a cuboid turned about +y by an exact multiple of 90 degrees: that rotation (folded into
/// the collider, whose x and z half extents swap for odd quarter turns) and whether to swap.
/// Otherwise the identity and no swap.
///
/// NOTE: why. A yaw of 90 degrees is not exact in f32 (the quaternion's 0.70710677 is off by
/// 1e-8), and stacks of such bodies were measured to lose contacts in parry's cuboid-cuboid
/// manifold (a supported three-layer stack shed a block 52 mm). With the turn folded into the
/// collider, every grid-aligned body starts at the identity rotation, exactly.
fn canonical_frame(block: &Block) -> (DQuat, bool) {
    if block.block_type.cuboid_half_extents_mm().is_none() {
        return (DQuat::IDENTITY, false);
    }
    let q = block.rotation().normalize();
    if (q * DVec3::Y).angle_between(DVec3::Y) > 1e-9 {
        return (DQuat::IDENTITY, false);
    }
    let yaw_deg = crate::geom::heading_deg(q);
    let quarters = (yaw_deg / 90.0).round();
    if (yaw_deg - quarters * 90.0).abs() > 1e-6 {
        return (DQuat::IDENTITY, false);
    }
    (q, (quarters as i64).rem_euclid(2) == 1)
}

/// The body's pose in metres: the block's centre lifted by `lift_mm`, rotation `q`.
fn block_pose_m(block: &Block, q: DQuat, lift_mm: f64) -> Pose {
    let c = (block.center_mm + DVec3::Y * lift_mm) * M_PER_MM;
    Pose::from_parts(c.as_vec3(), Rotation::from_array(q.as_quat().to_array()))
}

/// A cuboid collider when the catalog says the block is one (x and z half extents swapped when
/// `swap_xz`), rapier's exact cylinder for a round part (Chapter VII's "circles", axis along
/// local y as in the catalog), else the convex hull of its catalog vertices (the wedge).
fn block_collider(
    block: &Block,
    index: usize,
    swap_xz: bool,
) -> Result<ColliderBuilder, PhysicsError> {
    let t = block.block_type;
    if let Some(h) = t.cuboid_half_extents_mm() {
        let h = (h * M_PER_MM).as_vec3();
        let h = if swap_xz {
            Vector::new(h.z, h.y, h.x)
        } else {
            h
        };
        return Ok(ColliderBuilder::cuboid(h.x, h.y, h.z));
    }
    if let Some(r) = t.round() {
        let (half_height, radius) = (r.height_mm / 2.0 * M_PER_MM, r.radius_mm * M_PER_MM);
        return Ok(ColliderBuilder::cylinder(half_height as f32, radius as f32));
    }
    let points: Vec<Vector> = t.vertices().map(|v| (v * M_PER_MM).as_vec3()).collect();
    ColliderBuilder::convex_hull(&points).ok_or(PhysicsError::BadShape {
        index,
        type_id: t.id,
    })
}

/// Each block's drop layer: the rank of its lowest point among the scene's distinct bottom
/// heights (0 for blocks on the floor). Heights within 0.01 mm count as the same.
fn drop_layers(scene: &Scene) -> Vec<usize> {
    const SAME_LAYER_MM: f64 = 0.01;
    let layers = layer_bottoms_mm(&scene.blocks, SAME_LAYER_MM);
    scene
        .blocks
        .iter()
        .map(|b| layer_index(&layers, b.bottom_mm(), SAME_LAYER_MM))
        .collect()
}

/// The scene to write: intended poses when stable (snapped back), simulated poses otherwise;
/// both with `rotation` quaternions and `meta.settle`.
fn settled_scene(scene: &Scene, poses: &[(DVec3, DQuat)], report: &SettleReport) -> Scene {
    if report.stable {
        return at_intended_poses(scene, report);
    }
    let mut out = scene.clone();
    for (block, (center_mm, q)) in out.blocks.iter_mut().zip(poses) {
        block.center_mm = *center_mm;
        block.orientation = Orientation::Quaternion(*q);
    }
    with_settle_meta(out, report)
}

/// The scene at its intended poses, as `rotation` quaternions, with `meta.settle` from
/// `report`: what [`settle`] writes for a stable scene, and what a stability dataset writes
/// for every scene, standing or not (docs/stability.md "Files").
pub fn at_intended_poses(scene: &Scene, report: &SettleReport) -> Scene {
    let mut out = scene.clone();
    for block in &mut out.blocks {
        block.orientation = Orientation::Quaternion(block.rotation());
    }
    with_settle_meta(out, report)
}

fn with_settle_meta(mut out: Scene, report: &SettleReport) -> Scene {
    let mut meta = out.meta.take().unwrap_or_default();
    meta.insert("settle".to_string(), report.to_meta());
    out.meta = Some(meta);
    out
}

#[cfg(test)]
mod tests;
