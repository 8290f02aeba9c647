//! Whether a set of blocks stands: settled with the same parameters `generate` uses
//! ([`SettleParams::default`]), each block that moves beyond the tolerances named, with how
//! far it moved and why (docs/recognizer.md "Reconstructions that must stand"). The recognizer's answers go through it
//! before `ok` (`pipeline::recognize_standing`), and `plan` through it after every removal.

use super::fall::{block_cause, Cause};
use super::support::supports_of;
use super::{settle, PhysicsError, SettleParams, SettleReport};
use crate::scene::{Block, Scene};

/// A cause in words, as a decline reason says it.
pub fn describe_cause(cause: Cause) -> &'static str {
    match cause {
        Cause::UnsupportedCentreOfMass => "hanging in the air",
        Cause::OverhangBeyondSupport => "overhang: its centre of mass is beyond its support",
        Cause::Toppling => "toppling",
        Cause::Sliding => "sliding",
    }
}

/// One block that does not stay where it is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Movement {
    /// Block index.
    pub block: usize,
    /// Catalog id.
    pub type_id: &'static str,
    /// Distance its centre moved, mm.
    pub displacement_mm: f64,
    /// Angle it turned, degrees.
    pub turn_deg: f64,
    /// Why ([`block_cause`], the rules a stability label uses).
    pub cause: Cause,
}

/// The verdict on a set of blocks: the blocks that move, the most telling first.
#[derive(Debug, Clone, PartialEq)]
pub struct StandReport {
    /// Blocks that move beyond the tolerances, sorted by cause, then by displacement (largest
    /// first), then by index. Empty when everything stands.
    pub moved: Vec<Movement>,
    /// The settling measurements behind it.
    pub settle: SettleReport,
}

impl StandReport {
    /// Every block stays within the tolerances and the stack comes to rest.
    pub fn stands(&self) -> bool {
        self.moved.is_empty() && self.settle.at_rest
    }

    /// Why it does not stand, naming the first block of [`StandReport::moved`]:
    /// `block 2 (b15) moves 14.302 mm, hanging in the air; 1 more block moves`. `None` when it
    /// stands.
    pub fn describe(&self) -> Option<String> {
        if self.stands() {
            return None;
        }
        let Some(m) = self.moved.first() else {
            return Some(format!(
                "the blocks are still moving after {} steps (time limit)",
                self.settle.steps
            ));
        };
        let more = match self.moved.len() - 1 {
            0 => String::new(),
            1 => "; 1 more block moves".to_string(),
            n => format!("; {n} more blocks move"),
        };
        Some(format!(
            "block {} ({}) moves {:.3} mm and turns {:.1} deg, {}{more}",
            m.block,
            m.type_id,
            m.displacement_mm,
            m.turn_deg,
            describe_cause(m.cause)
        ))
    }
}

/// Settles `blocks` with `params` and names the blocks that move beyond `params`'s drift, turn
/// and floor tolerances, with their causes. Deterministic, like [`settle`].
pub fn check_standing(
    blocks: &[Block],
    params: &SettleParams,
) -> Result<StandReport, PhysicsError> {
    let scene = Scene::new("standing", blocks.to_vec());
    let settled = settle(&scene, params)?;
    let report = settled.report;
    let supports = supports_of(blocks);
    let mut moved: Vec<Movement> = report
        .moved_blocks(params)
        .into_iter()
        .map(|i| {
            let b = &report.blocks[i];
            let cause = block_cause(&scene, &supports, &report, i, params);
            Movement {
                block: i,
                type_id: blocks[i].block_type.id,
                displacement_mm: b.drift_mm,
                turn_deg: b.turn_deg,
                cause,
            }
        })
        .collect();
    moved.sort_by(|a, b| {
        a.cause
            .cmp(&b.cause)
            .then(b.displacement_mm.total_cmp(&a.displacement_mm))
            .then(a.block.cmp(&b.block))
    });
    Ok(StandReport {
        moved,
        settle: report,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::DVec3;

    fn b15(x: f64, y: f64) -> Block {
        Block::new("b15", DVec3::new(x, y, 0.0), 0.0)
    }

    #[test]
    fn a_two_layer_stack_stands() {
        let blocks = [
            Block::new("b30", DVec3::new(0.0, 7.5, 0.0), 0.0),
            Block::new("b15", DVec3::new(0.0, 22.5, 0.0), 90.0),
        ];
        let r = check_standing(&blocks, &SettleParams::default()).unwrap();
        assert!(r.stands(), "{r:?}");
        assert_eq!(r.describe(), None);
    }

    #[test]
    fn a_block_in_the_air_falls_and_is_named() {
        let blocks = [b15(0.0, 7.5), b15(40.0, 30.0)];
        let r = check_standing(&blocks, &SettleParams::default()).unwrap();
        assert!(!r.stands());
        let m = r.moved[0];
        assert_eq!((m.block, m.cause), (1, Cause::UnsupportedCentreOfMass));
        assert!(m.displacement_mm > 20.0, "{m:?}");
        let why = r.describe().unwrap();
        assert!(why.starts_with("block 1 (b15) moves 2"), "{why}");
        assert!(why.ends_with("hanging in the air"), "{why}");
    }

    #[test]
    fn a_cube_shifted_past_the_edge_overhangs_and_one_shifted_less_stands() {
        let params = SettleParams::default();
        let tips = check_standing(&[b15(0.0, 7.5), b15(10.0, 22.5)], &params).unwrap();
        assert_eq!(tips.moved[0].block, 1);
        assert_eq!(
            tips.moved[0].cause,
            Cause::OverhangBeyondSupport,
            "{tips:?}"
        );
        let holds = check_standing(&[b15(0.0, 7.5), b15(5.0, 22.5)], &params).unwrap();
        assert!(holds.stands(), "{holds:?}");
    }

    #[test]
    fn a_block_carried_by_a_falling_one_comes_after_it() {
        // The middle cube overhangs; the top cube sits square on it and goes down with it.
        let blocks = [b15(0.0, 7.5), b15(10.0, 22.5), b15(10.0, 37.5)];
        let r = check_standing(&blocks, &SettleParams::default()).unwrap();
        assert_eq!(r.moved[0].block, 1, "{r:?}");
        assert_eq!(r.moved[0].cause, Cause::OverhangBeyondSupport);
        let top = r
            .moved
            .iter()
            .find(|m| m.block == 2)
            .expect("the top cube moves");
        assert_eq!(top.cause, Cause::Toppling, "{r:?}");
        assert!(r.describe().unwrap().contains(" more blocks move"));
    }
}
