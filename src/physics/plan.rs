//! Off-line robot programming (thesis Chapter VII: the reconstruction tells a robot which block
//! to take first; docs/plan.md): the order in which a robot takes the blocks away, top down,
//! each step verified with rapier, with the grasp of each block; built in the reverse order.

use super::grasp::{grasp_of, Grasp, Gripper};
use super::{check_standing, describe_cause, supports_of, PhysicsError, SettleParams, Support};
use crate::scene::Block;

/// What a plan is made with: how each step is settled and judged, and the gripper.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
pub struct PlanParams {
    /// Settling after each removal, and the tolerance every remaining block must stay within
    /// (`drift_tol_mm`, `turn_tol_deg`); default [`SettleParams::default`], as `generate`.
    pub settle: SettleParams,
    /// The gripper assumed for the grasps.
    pub gripper: Gripper,
}

/// One removal: the block, its grasp, and how still the rest stayed.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct PlanStep {
    /// Block index in the input.
    pub block: usize,
    /// Catalog id.
    pub type_id: &'static str,
    /// The gripper's grasp (`None` when no pair of its faces fits the gripper).
    pub grasp: Option<Grasp>,
    /// Largest drift of a block left standing, settled without this one, mm (0 for the last).
    pub rest_max_drift_mm: f64,
    /// Largest turn of a block left standing, degrees.
    pub rest_max_turn_deg: f64,
}

/// A verified disassembly, or the reason there is none.
#[derive(Debug, Clone, PartialEq)]
pub enum PlanOutcome {
    /// Every block taken away, each step leaving the rest at rest.
    Ordered(Vec<PlanStep>),
    /// No order exists from some point on: the steps that could be taken, and why no next one.
    Declined {
        /// The steps taken before the plan got stuck.
        taken: Vec<PlanStep>,
        /// Why no block can be taken next (or why the blocks do not stand to begin with).
        reason: String,
    },
}

/// Plans the disassembly of `blocks`, top down (docs/plan.md "Order"). The blocks must stand
/// as given. At each step the free blocks (nothing left rests on them) are tried, those with
/// a clear grasp first, then highest top first, then lowest index; the first whose removal
/// leaves every other block within the tolerances is taken. Deterministic.
pub fn plan_disassembly(
    blocks: &[Block],
    params: &PlanParams,
) -> Result<PlanOutcome, PhysicsError> {
    let all: Vec<usize> = (0..blocks.len()).collect();
    if let Some(why) = check_standing(blocks, &params.settle)?.describe() {
        return Ok(PlanOutcome::Declined {
            taken: Vec::new(),
            reason: format!("the blocks do not stand as given: {why}"),
        });
    }
    let mut remaining = all;
    let mut taken = Vec::new();
    while !remaining.is_empty() {
        let mut refused = Vec::new();
        let mut next = None;
        for c in candidates(blocks, &remaining, params) {
            match check_removal(blocks, &remaining, c, params)? {
                Ok(step) => {
                    next = Some(step);
                    break;
                }
                Err(why) => refused.push(why),
            }
        }
        let Some(step) = next else {
            return Ok(PlanOutcome::Declined {
                taken,
                reason: format!(
                    "no block can be taken away without moving another: {}",
                    refused.join("; ")
                ),
            });
        };
        remaining.retain(|&i| i != step.block);
        taken.push(step);
    }
    Ok(PlanOutcome::Ordered(taken))
}

/// Checks a given disassembly `order` (every block once) step by step as [`plan_disassembly`]
/// takes its steps: the verifier of a plan, and of a worse one. `Ok` with the steps, or `Err`
/// naming the first step that fails and why.
pub fn verify_disassembly(
    blocks: &[Block],
    order: &[usize],
    params: &PlanParams,
) -> Result<Result<Vec<PlanStep>, String>, PhysicsError> {
    let mut sorted = order.to_vec();
    sorted.sort_unstable();
    if sorted != (0..blocks.len()).collect::<Vec<_>>() {
        return Ok(Err(format!(
            "the order {order:?} does not name each of the {} blocks once",
            blocks.len()
        )));
    }
    let mut remaining: Vec<usize> = (0..blocks.len()).collect();
    let mut steps = Vec::new();
    for (k, &c) in order.iter().enumerate() {
        match check_removal(blocks, &remaining, c, params)? {
            Ok(step) => steps.push(step),
            Err(why) => return Ok(Err(format!("step {}: {why}", k + 1))),
        }
        remaining.retain(|&i| i != c);
    }
    Ok(Ok(steps))
}

/// The free blocks of `remaining` in the order they are tried.
fn candidates(blocks: &[Block], remaining: &[usize], params: &PlanParams) -> Vec<usize> {
    let mut free: Vec<(bool, f64, usize)> = remaining
        .iter()
        .filter(|&&c| resting_on(blocks, remaining, c).is_empty())
        .map(|&c| {
            let clear = grasp_of(blocks, c, remaining, &params.gripper)
                .is_some_and(|g| g.blocked_by.is_empty());
            let top = blocks[c]
                .world_vertices()
                .iter()
                .map(|v| v.y)
                .fold(f64::NEG_INFINITY, f64::max);
            (!clear, -top, c)
        })
        .collect();
    free.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)).then(a.2.cmp(&b.2)));
    free.into_iter().map(|(_, _, c)| c).collect()
}

/// The blocks of `remaining` that rest on block `c`.
fn resting_on(blocks: &[Block], remaining: &[usize], c: usize) -> Vec<usize> {
    let subset: Vec<Block> = remaining.iter().map(|&i| blocks[i]).collect();
    let k = remaining.iter().position(|&i| i == c);
    supports_of(&subset)
        .iter()
        .enumerate()
        .filter(|(_, s)| k.is_some_and(|k| s.contains(&Support::Block(k))))
        .map(|(j, _)| remaining[j])
        .collect()
}

/// Takes block `c` away from `remaining`: refused when another block rests on it or when the
/// rest, settled, moves beyond the tolerances (naming the block and the cause).
fn check_removal(
    blocks: &[Block],
    remaining: &[usize],
    c: usize,
    params: &PlanParams,
) -> Result<Result<PlanStep, String>, PhysicsError> {
    let rest: Vec<usize> = remaining.iter().copied().filter(|&i| i != c).collect();
    let rest_blocks: Vec<Block> = rest.iter().map(|&i| blocks[i]).collect();
    let report = check_standing(&rest_blocks, &params.settle)?;
    if let Some(m) = report.moved.first() {
        return Ok(Err(format!(
            "taking block {c} ({}) moves block {} ({}) {:.3} mm, {}",
            blocks[c].block_type.id,
            rest[m.block],
            m.type_id,
            m.displacement_mm,
            describe_cause(m.cause)
        )));
    }
    if !report.stands() {
        return Ok(Err(format!("taking block {c} leaves the rest moving")));
    }
    let above = resting_on(blocks, remaining, c);
    if !above.is_empty() {
        return Ok(Err(format!("block {c} carries block(s) {above:?}")));
    }
    Ok(Ok(PlanStep {
        block: c,
        type_id: blocks[c].block_type.id,
        grasp: grasp_of(blocks, c, &rest, &params.gripper),
        rest_max_drift_mm: report.settle.max_drift_mm,
        rest_max_turn_deg: report.settle.max_turn_deg,
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::DVec3;

    fn cube(x: f64, y: f64) -> Block {
        Block::new("b15", DVec3::new(x, y, 0.0), 0.0)
    }

    #[test]
    fn a_tower_comes_down_from_the_top() {
        let tower = [cube(0.0, 7.5), cube(0.0, 22.5), cube(0.0, 37.5)];
        let PlanOutcome::Ordered(steps) = plan_disassembly(&tower, &PlanParams::default()).unwrap()
        else {
            panic!("a tower has an order")
        };
        let order: Vec<usize> = steps.iter().map(|s| s.block).collect();
        assert_eq!(order, vec![2, 1, 0]);
        assert!(steps.iter().all(|s| s.rest_max_drift_mm <= 0.5));
        assert!(steps
            .iter()
            .all(|s| s.grasp.as_ref().is_some_and(|g| g.blocked_by.is_empty())));
    }

    #[test]
    fn taking_the_support_first_is_refused_by_the_verifier() {
        let tower = [cube(0.0, 7.5), cube(0.0, 22.5)];
        let params = PlanParams::default();
        assert!(verify_disassembly(&tower, &[1, 0], &params)
            .unwrap()
            .is_ok());
        let why = verify_disassembly(&tower, &[0, 1], &params)
            .unwrap()
            .unwrap_err();
        assert!(
            why.starts_with("step 1: taking block 0 (b15) moves block 1 (b15)"),
            "{why}"
        );
        assert!(why.contains("hanging in the air"), "{why}");
        assert!(verify_disassembly(&tower, &[1], &params).unwrap().is_err());
    }

    #[test]
    fn a_cantilever_held_by_a_counterweight_has_no_order() {
        // A b30 reaching 16.5 mm past the cube under it (its centre 1.5 mm beyond the edge) is
        // held by the cube on its other end; taking that cube lets it tip, and nothing else
        // is free.
        let blocks = [
            cube(0.0, 7.5),
            Block::new("b30", DVec3::new(9.0, 22.5, 0.0), 0.0),
            cube(1.5, 37.5),
        ];
        let params = PlanParams::default();
        match plan_disassembly(&blocks, &params).unwrap() {
            PlanOutcome::Declined { taken, reason } => {
                assert!(taken.is_empty());
                assert!(
                    reason.contains("taking block 2 (b15) moves block 1 (b30)"),
                    "{reason}"
                );
                assert!(reason.contains("overhang"), "{reason}");
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn blocks_that_do_not_stand_are_declined_at_once() {
        let blocks = [cube(0.0, 7.5), cube(40.0, 30.0)];
        let PlanOutcome::Declined { reason, .. } =
            plan_disassembly(&blocks, &PlanParams::default()).unwrap()
        else {
            panic!("a block in the air cannot be planned")
        };
        assert!(
            reason.starts_with("the blocks do not stand as given: block 1"),
            "{reason}"
        );
    }
}
