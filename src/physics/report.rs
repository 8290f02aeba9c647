//! The settling report: how far each block moved and turned, whether it touches the floor, and
//! the verdict (docs/datasets.md "Settling").

use super::SettleParams;
use crate::geom::{DQuat, DVec3};
use crate::scene::Scene;
use serde_json::{json, Value};

/// One block's measurements after settling.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BlockReport {
    /// Distance of the settled centre from the intended centre, mm.
    pub drift_mm: f64,
    /// Angle between the settled and the intended orientation, degrees.
    pub turn_deg: f64,
    /// The settled block's lowest vertex is within `floor_contact_mm` of the floor.
    pub touches_floor: bool,
    /// The intended block rests on the floor (its lowest vertex within `floor_contact_mm`).
    pub should_touch_floor: bool,
}

impl BlockReport {
    /// Within both tolerances and touching the floor only if meant to.
    pub fn is_stable(&self, params: &SettleParams) -> bool {
        self.drift_mm <= params.drift_tol_mm
            && self.turn_deg <= params.turn_tol_deg
            && (self.should_touch_floor || !self.touches_floor)
    }
}

/// The whole scene's measurements and verdict.
#[derive(Debug, Clone, PartialEq)]
pub struct SettleReport {
    /// One entry per block, in scene order.
    pub blocks: Vec<BlockReport>,
    /// Simulation steps taken.
    pub steps: u32,
    /// The stack came to rest (`SettleParams`'s rest criterion) before the time limit.
    pub at_rest: bool,
    /// Largest `drift_mm` over the blocks (0 for an empty scene).
    pub max_drift_mm: f64,
    /// Largest `turn_deg` over the blocks.
    pub max_turn_deg: f64,
    /// All blocks stable and the stack at rest.
    pub stable: bool,
    /// How many times the step was halved for a tall stack (`stiffened_for_layers`); 0 for
    /// stacks within the sink budget.
    pub stiffenings: u32,
}

impl SettleReport {
    /// Measures simulated `poses` (centre mm, rotation) against the scene's intended poses.
    pub fn measure(
        scene: &Scene,
        poses: &[(DVec3, DQuat)],
        steps: u32,
        at_rest: bool,
        params: &SettleParams,
    ) -> SettleReport {
        let blocks: Vec<BlockReport> = scene
            .blocks
            .iter()
            .zip(poses)
            .map(|(b, (c, q))| {
                let intended_q = b.rotation().normalize();
                let low_now = lowest_y(b.block_type.vertices().map(|v| *c + *q * v));
                let low_then = lowest_y(b.world_vertices().into_iter());
                BlockReport {
                    drift_mm: (*c - b.center_mm).length(),
                    turn_deg: intended_q.angle_between(*q).to_degrees(),
                    touches_floor: low_now <= params.floor_contact_mm,
                    should_touch_floor: low_then <= params.floor_contact_mm,
                }
            })
            .collect();
        let max_drift_mm = blocks.iter().map(|b| b.drift_mm).fold(0.0, f64::max);
        let max_turn_deg = blocks.iter().map(|b| b.turn_deg).fold(0.0, f64::max);
        let stable = at_rest && blocks.iter().all(|b| b.is_stable(params));
        SettleReport {
            blocks,
            steps,
            at_rest,
            max_drift_mm,
            max_turn_deg,
            stable,
            stiffenings: 0,
        }
    }

    /// Indices of the blocks that moved, turned or touch the floor beyond the tolerances.
    pub fn moved_blocks(&self, params: &SettleParams) -> Vec<usize> {
        (0..self.blocks.len())
            .filter(|&i| !self.blocks[i].is_stable(params))
            .collect()
    }

    /// A human summary of the blocks that moved: `block 2 (b30): drift 7.41 mm, turn 31.2 deg,
    /// touches the floor`, one per line.
    pub fn describe_moved(&self, scene: &Scene, params: &SettleParams) -> String {
        let mut lines: Vec<String> = self
            .moved_blocks(params)
            .into_iter()
            .map(|i| {
                let b = &self.blocks[i];
                let floor = if b.touches_floor && !b.should_touch_floor {
                    ", touches the floor"
                } else {
                    ""
                };
                format!(
                    "block {i} ({}): drift {:.3} mm, turn {:.3} deg{floor}",
                    scene.blocks[i].block_type.id, b.drift_mm, b.turn_deg
                )
            })
            .collect();
        if !self.at_rest {
            lines.push(format!(
                "bodies still moving after {} steps (time limit)",
                self.steps
            ));
        }
        lines.join("\n")
    }

    /// The `meta.settle` entry: max drift (mm, 6 decimals), max turn (deg), steps, stable, and
    /// `stiffenings` where the step was halved (absent otherwise, so the files of stacks within
    /// the sink budget keep their bytes). Rounded so the file stays readable; the values are
    /// informative, not re-read.
    pub fn to_meta(&self) -> Value {
        let round6 = |x: f64| (x * 1e6).round() / 1e6;
        let mut meta = json!({
            "max_drift_mm": round6(self.max_drift_mm),
            "max_turn_deg": round6(self.max_turn_deg),
            "steps": self.steps,
            "stable": self.stable,
        });
        if self.stiffenings > 0 {
            meta["stiffenings"] = json!(self.stiffenings);
        }
        meta
    }
}

fn lowest_y(points: impl Iterator<Item = DVec3>) -> f64 {
    points.map(|v| v.y).fold(f64::INFINITY, f64::min)
}
