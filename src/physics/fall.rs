//! A scene's stability label (docs/stability.md "The label"): whether it stands, the first
//! block to move and when, why it falls, and how far the blocks go.
//!
//! The cause is decided per moved block from what holds it at its intended pose
//! ([`supports_of`], [`centre_of_mass_overhang_mm`]) and from how it moved, most telling first:
//! 1. `unsupported_centre_of_mass`: nothing is under the block (neither the floor nor the top
//!    face of another block), so nothing holds its centre of mass;
//! 2. `overhang_beyond_support`: its centre of mass lies beyond the region its contacts span
//!    (a block pushed over an edge), or it is not level (turned about a horizontal axis, it
//!    stands on an edge or a corner, a support of no area);
//! 3. `toppling`: it is held up by itself but ends turned beyond the 1 degree tolerance (the
//!    load it carries, or the block under it, tips it over);
//! 4. `sliding`: held up, it moved without turning.
//!
//! The scene's cause is that of its **violating block**: among the blocks that moved, the one
//! with the most telling cause (1 before 4), then the lowest, then the first in file order.

use super::motion::{FirstMove, Motion};
use super::support::{centre_of_mass_overhang_mm, supports_of, Support};
use super::{PhysicsError, SettleParams, SettleReport};
use crate::geom::DVec3;
use crate::scene::Scene;
use serde_json::{json, Value};

/// A block whose up axis is off the vertical by more than about 0.0026 degrees (1 - cos) is
/// not level.
const LEVEL_TOL: f64 = 1e-9;

/// Why a block moved (the rules of the module doc, in their order).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Cause {
    /// Nothing is under the block.
    UnsupportedCentreOfMass,
    /// Its centre of mass lies beyond the region its contacts span.
    OverhangBeyondSupport,
    /// Held up by itself, it ends turned beyond the tolerance.
    Toppling,
    /// Held up, it moved without turning.
    Sliding,
}

impl Cause {
    /// Every cause, in the order of the rules.
    pub const ALL: [Cause; 4] = [
        Cause::UnsupportedCentreOfMass,
        Cause::OverhangBeyondSupport,
        Cause::Toppling,
        Cause::Sliding,
    ];

    /// The name written in `meta.stability.cause`.
    pub fn name(self) -> &'static str {
        match self {
            Cause::UnsupportedCentreOfMass => "unsupported_centre_of_mass",
            Cause::OverhangBeyondSupport => "overhang_beyond_support",
            Cause::Toppling => "toppling",
            Cause::Sliding => "sliding",
        }
    }
}

/// A scene's stability label.
#[derive(Debug, Clone, PartialEq)]
pub struct StabilityLabel {
    /// The settle verdict ([`SettleReport::stable`]).
    pub stable: bool,
    /// The stack came to rest before the time limit.
    pub at_rest: bool,
    /// Unstable scenes: the first block beyond a tolerance and when.
    pub first_moved: Option<FirstMove>,
    /// Unstable scenes: the violating block's cause.
    pub cause: Option<Cause>,
    /// Unstable scenes: the violating block (module doc).
    pub violating_block: Option<usize>,
    /// The largest displacement of any block from its intended pose on any step, mm.
    pub max_displacement_mm: f64,
    /// Unstable scenes: every block beyond a tolerance on some step or at the end.
    pub moved_blocks: Vec<usize>,
}

impl StabilityLabel {
    /// The `meta.stability` entry (times and lengths rounded to 6 decimals).
    pub fn to_meta(&self) -> Value {
        let round6 = |x: f64| (x * 1e6).round() / 1e6;
        json!({
            "stable": self.stable,
            "at_rest": self.at_rest,
            "first_moved": self
                .first_moved
                .map(|f| json!({"block": f.block, "time_s": round6(f.time_s)})),
            "cause": self.cause.map(Cause::name),
            "violating_block": self.violating_block,
            "max_displacement_mm": round6(self.max_displacement_mm),
            "moved_blocks": self.moved_blocks,
        })
    }
}

/// Labels `scene` (its intended poses) from its settle report and the motion that led to it.
pub fn label_stability(
    scene: &Scene,
    report: &SettleReport,
    motion: &Motion,
    params: &SettleParams,
) -> Result<StabilityLabel, PhysicsError> {
    let mut label = StabilityLabel {
        stable: report.stable,
        at_rest: report.at_rest,
        first_moved: None,
        cause: None,
        violating_block: None,
        max_displacement_mm: motion.max_displacement_mm(),
        moved_blocks: Vec::new(),
    };
    if report.stable {
        return Ok(label);
    }
    let mut moved = motion.moved_blocks(params);
    moved.extend(report.moved_blocks(params));
    moved.sort_unstable();
    moved.dedup();
    let supports = supports_of(&scene.blocks);
    let violating = moved
        .iter()
        .map(|&i| (block_cause(scene, &supports, report, i, params), i))
        .min_by(|(ca, a), (cb, b)| {
            let bottom = |i: usize| scene.blocks[i].bottom_mm();
            ca.cmp(cb)
                .then(bottom(*a).total_cmp(&bottom(*b)))
                .then(a.cmp(b))
        });
    label.first_moved = motion.first_moved;
    label.cause = violating.map(|(c, _)| c);
    label.violating_block = violating.map(|(_, i)| i);
    label.moved_blocks = moved;
    Ok(label)
}

/// Rules 1-4 of the module doc for block `i`; `supports` is [`supports_of`] the scene's blocks.
pub fn block_cause(
    scene: &Scene,
    supports: &[Vec<Support>],
    report: &SettleReport,
    i: usize,
    params: &SettleParams,
) -> Cause {
    let level = (scene.blocks[i].rotation().normalize() * DVec3::Y).y > 1.0 - LEVEL_TOL;
    if !level {
        Cause::OverhangBeyondSupport
    } else if supports[i].is_empty() {
        Cause::UnsupportedCentreOfMass
    } else if centre_of_mass_overhang_mm(&scene.blocks, i).is_some_and(|d| d > 0.0) {
        Cause::OverhangBeyondSupport
    } else if report.blocks[i].turn_deg > params.turn_tol_deg {
        Cause::Toppling
    } else {
        Cause::Sliding
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::DQuat;
    use crate::physics::{settle, settle_recorded};
    use crate::scene::{Block, Orientation};

    fn b15(x: f64, y: f64) -> Block {
        Block::new("b15", DVec3::new(x, y, 0.0), 0.0)
    }

    fn label(blocks: Vec<Block>) -> (StabilityLabel, Motion) {
        let scene = Scene::new("t", blocks);
        let params = SettleParams::default();
        let (settled, motion) = settle_recorded(&scene, &params, true).unwrap();
        assert_eq!(
            settled,
            settle(&scene, &params).unwrap(),
            "recording changes nothing"
        );
        let l = label_stability(&scene, &settled.report, &motion, &params).unwrap();
        (l, motion)
    }

    #[test]
    fn a_stack_that_stands_has_no_cause_and_stays_within_the_tolerance() {
        let (l, m) = label(vec![b15(0.0, 7.5), b15(5.0, 22.5)]);
        assert!(
            l.stable && l.cause.is_none() && l.first_moved.is_none(),
            "{l:?}"
        );
        assert!(l.max_displacement_mm < 0.5, "{l:?}");
        assert!(m.first_moved.is_none());
    }

    #[test]
    fn a_cube_past_the_edge_overhangs_and_moves_first() {
        let (l, m) = label(vec![b15(0.0, 7.5), b15(10.0, 22.5)]);
        assert!(!l.stable);
        assert_eq!(l.cause, Some(Cause::OverhangBeyondSupport), "{l:?}");
        assert_eq!(l.violating_block, Some(1));
        let first = l.first_moved.unwrap();
        assert_eq!(first.block, 1);
        assert!(first.time_s > 0.0 && first.time_s < 0.5, "{first:?}");
        assert!(l.max_displacement_mm > 2.0, "{l:?}");
        let t = m.trajectory.unwrap();
        assert!(
            (t.times_s[1] - 1.0 / 30.0).abs() < 1e-12,
            "{:?}",
            &t.times_s[..2]
        );
        assert_eq!(t.frames.len(), t.times_s.len());
        assert!(t.times_s.windows(2).all(|w| w[1] > w[0]));
    }

    #[test]
    fn a_cube_in_the_air_has_an_unsupported_centre_of_mass() {
        let (l, _) = label(vec![b15(0.0, 7.5), b15(40.0, 30.0)]);
        assert_eq!(l.cause, Some(Cause::UnsupportedCentreOfMass), "{l:?}");
        assert_eq!(
            (l.violating_block, l.moved_blocks.clone()),
            (Some(1), vec![1])
        );
    }

    #[test]
    fn a_block_on_its_edge_overhangs() {
        let mut tilted = b15(0.0, 0.0);
        let turn = DQuat::from_rotation_z(0.5);
        let pivot = DVec3::new(7.5, 0.0, 0.0);
        tilted.center_mm = pivot + turn * (DVec3::new(0.0, 7.5, 0.0) - pivot);
        tilted.orientation = Orientation::Quaternion(turn);
        let (l, _) = label(vec![tilted]);
        assert_eq!(l.cause, Some(Cause::OverhangBeyondSupport), "{l:?}");
    }

    /// A b30 across a cube, its own centre of mass over the cube, with a cube on its far end:
    /// together they lean beyond the support and both tip.
    #[test]
    fn a_beam_tipped_by_its_load_topples() {
        let beam = Block::new("b30", DVec3::new(5.0, 22.5, 0.0), 0.0);
        let (l, _) = label(vec![b15(0.0, 7.5), beam, b15(15.0, 37.5)]);
        assert!(!l.stable);
        assert_eq!(l.cause, Some(Cause::Toppling), "{l:?}");
        assert_eq!(l.violating_block, Some(1), "{l:?}");
    }

    #[test]
    fn cause_names_are_distinct_and_in_rule_order() {
        let names: Vec<&str> = Cause::ALL.iter().map(|c| c.name()).collect();
        assert_eq!(
            names,
            [
                "unsupported_centre_of_mass",
                "overhang_beyond_support",
                "toppling",
                "sliding"
            ]
        );
        assert!(Cause::ALL.windows(2).all(|w| w[0] < w[1]));
    }
}
