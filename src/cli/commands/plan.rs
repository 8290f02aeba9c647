//! `blockworld plan RECON.json -o PLAN.json [--glb PLAN.glb]`: off-line robot programming
//! (thesis Chapter VII; docs/plan.md): the order a robot takes the blocks of a reconstruction
//! (or scene) away, top down, each step verified with rapier, the grasp of each block, and the
//! reverse order for building it. With `--glb`, the disassembly as a glTF animation.

use anyhow::Context;
use blockworld::export::scene_animation_to_gltf;
use blockworld::geom::{DQuat, DVec3};
use blockworld::io::write_atomic;
use blockworld::physics::{plan_disassembly, Gripper, PlanOutcome, PlanParams, PlanStep};
use blockworld::scene::{read_reconstruction, Block, ReconStatus, Scene};
use serde::Serialize;
use std::path::{Path, PathBuf};

/// Options of `blockworld plan`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The reconstruction (`blockworld recognize -o`) or scene file whose blocks to take apart.
    pub recon: PathBuf,
    /// The plan to write (JSON): the disassembly steps with their grasps, the building order,
    /// the tolerance and the gripper assumed; `status` is `declined`, with the reason, when no
    /// order exists.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Also write the disassembly as a binary glTF animation: each block lifted, carried
    /// aside and set down on the floor in turn, one second per step.
    #[arg(long, value_name = "GLB")]
    pub glb: Option<PathBuf>,
}

/// Runs `blockworld plan`.
pub fn run(args: Args) -> anyhow::Result<()> {
    let inputs = [args.recon.as_path()];
    crate::cli::files::check_output(&args.output, &inputs)?;
    if let Some(glb) = &args.glb {
        crate::cli::files::check_output(glb, &inputs)?;
    }
    let recon = read_reconstruction(&args.recon)
        .with_context(|| format!("reading the reconstruction {}", args.recon.display()))?;
    if recon.status != ReconStatus::Ok {
        anyhow::bail!(
            "{}: the reconstruction is unsupported ({}); there are no blocks to plan: give an `ok` reconstruction or a scene file",
            args.recon.display(),
            recon.reason.as_deref().unwrap_or("no reason given")
        );
    }
    if recon.blocks.is_empty() {
        anyhow::bail!(
            "{}: no blocks to plan; give a file with at least one block",
            args.recon.display()
        );
    }
    let max = blockworld::physics::MAX_PLAN_BLOCKS;
    let section = "Settle and plan";
    crate::cli::check_block_count(&args.recon, recon.blocks.len(), max, "plan", section)?;
    let params = PlanParams::default();
    let outcome = plan_disassembly(&recon.blocks, &params)
        .with_context(|| format!("planning {}", args.recon.display()))?;
    let text = plan_text(
        &args.recon,
        &recon.name,
        recon.blocks.len(),
        &outcome,
        &params,
    )?;
    let glb = match (&args.glb, &outcome) {
        (Some(_), PlanOutcome::Ordered(steps)) => {
            let scene = Scene::new(recon.name.clone(), recon.blocks.clone());
            let (times, frames) = disassembly_frames(&recon.blocks, steps);
            Some(scene_animation_to_gltf(&scene, "disassembly", &times, &frames)?.to_glb()?)
        }
        _ => None,
    };
    write_atomic(&args.output, text.as_bytes())
        .with_context(|| format!("writing {}", args.output.display()))?;
    if let (Some(path), Some(bytes)) = (&args.glb, &glb) {
        write_atomic(path, bytes).with_context(|| format!("writing {}", path.display()))?;
    }
    match &outcome {
        PlanOutcome::Ordered(steps) => outln!(
            "{}: {} blocks taken away in the order {:?} -> {}{}",
            args.recon.display(),
            steps.len(),
            steps.iter().map(|s| s.block).collect::<Vec<_>>(),
            args.output.display(),
            glb.as_ref().map_or(String::new(), |_| format!(
                " and {}",
                args.glb.as_ref().unwrap().display()
            ))
        )?,
        PlanOutcome::Declined { reason, .. } => outln!(
            "{}: declined: {reason} -> {}{}",
            args.recon.display(),
            args.output.display(),
            args.glb.as_ref().map_or(String::new(), |p| format!(
                " (no animation written to {})",
                p.display()
            ))
        )?,
    }
    Ok(())
}

/// Rounded to a thousandth (and -0 written as 0), so the file reads well and keeps its bytes.
fn round3(x: f64) -> f64 {
    (x * 1000.0).round() / 1000.0 + 0.0
}

fn vec3(v: DVec3) -> [f64; 3] {
    [round3(v.x), round3(v.y), round3(v.z)]
}

/// The plan file (docs/plan.md "Output"), fields in the order they are written.
#[derive(Serialize)]
struct PlanFile<'a> {
    source: String,
    name: &'a str,
    blocks: usize,
    status: &'static str,
    reason: Option<&'a str>,
    tolerance: Tolerance,
    gripper: &'a Gripper,
    disassembly: Vec<StepOut>,
    assembly_order: Vec<usize>,
}

#[derive(Serialize)]
struct Tolerance {
    drift_mm: f64,
    turn_deg: f64,
}

#[derive(Serialize)]
struct StepOut {
    step: usize,
    block: usize,
    #[serde(rename = "type")]
    type_id: &'static str,
    grasp: Option<GraspOut>,
    rest_max_drift_mm: f64,
    rest_max_turn_deg: f64,
}

#[derive(Serialize)]
struct GraspOut {
    centre_mm: [f64; 3],
    closing_axis: [f64; 3],
    opening_mm: f64,
    approach: [f64; 3],
    blocked_by: Vec<usize>,
}

fn step_out(k: usize, s: &PlanStep) -> StepOut {
    StepOut {
        step: k + 1,
        block: s.block,
        type_id: s.type_id,
        grasp: s.grasp.as_ref().map(|g| GraspOut {
            centre_mm: vec3(g.centre_mm),
            closing_axis: vec3(g.closing_axis),
            opening_mm: round3(g.opening_mm),
            approach: vec3(g.approach),
            blocked_by: g.blocked_by.clone(),
        }),
        rest_max_drift_mm: round3(s.rest_max_drift_mm),
        rest_max_turn_deg: round3(s.rest_max_turn_deg),
    }
}

/// The plan file's text.
fn plan_text(
    source: &Path,
    name: &str,
    n_blocks: usize,
    outcome: &PlanOutcome,
    params: &PlanParams,
) -> anyhow::Result<String> {
    let (status, reason, steps) = match outcome {
        PlanOutcome::Ordered(steps) => ("ok", None, steps),
        PlanOutcome::Declined { taken, reason } => ("declined", Some(reason.as_str()), taken),
    };
    let assembly_order = match outcome {
        PlanOutcome::Ordered(steps) => steps.iter().rev().map(|s| s.block).collect(),
        PlanOutcome::Declined { .. } => Vec::new(),
    };
    let file = PlanFile {
        source: source.display().to_string(),
        name,
        blocks: n_blocks,
        status,
        reason,
        tolerance: Tolerance {
            drift_mm: params.settle.drift_tol_mm,
            turn_deg: params.settle.turn_tol_deg,
        },
        gripper: &params.gripper,
        disassembly: steps
            .iter()
            .enumerate()
            .map(|(k, s)| step_out(k, s))
            .collect(),
        assembly_order,
    };
    let mut text = serde_json::to_string_pretty(&file)?;
    text.push('\n');
    Ok(text)
}

/// Seconds per step of the animation: lifted in the first 0.4, carried over its place on the
/// floor beside the scene by 0.7, set down at 1.
const STEP_S: f64 = 1.0;

/// The phases of a step: (fraction of the step, where the block is): lifted, carried, set down.
const PHASES: [f64; 3] = [0.4, 0.7, 1.0];

/// The disassembly as keyframes for `export::scene_animation_to_gltf`: the times, and every
/// block's pose at each. In its step a block is lifted straight up until it clears the scene by
/// 20 mm, carried over its place in a row on the floor east of the scene and set down; the
/// others stay where they are (or where they were set down). Linear in between.
fn disassembly_frames(
    blocks: &[Block],
    steps: &[PlanStep],
) -> (Vec<f64>, Vec<Vec<(DVec3, DQuat)>>) {
    let pts: Vec<DVec3> = blocks.iter().flat_map(Block::world_vertices).collect();
    let (lo, hi) = blockworld::geom::bounds3(pts).unwrap_or((DVec3::ZERO, DVec3::ZERO));
    let clear_y = hi.y + 20.0;
    let mut park_x = hi.x + 30.0;
    // Per step, the block's centre at each phase.
    let paths: Vec<[DVec3; 3]> = steps
        .iter()
        .map(|s| {
            let b = &blocks[s.block];
            let c = b.center_mm;
            let half = c - blockworld::geom::bounds3(b.world_vertices()).map_or(c, |(l, _)| l);
            let lifted = DVec3::new(c.x, clear_y + half.y, c.z);
            let parked = DVec3::new(park_x + half.x, half.y, c.z.clamp(lo.z, hi.z));
            park_x += 2.0 * half.x + 10.0;
            [lifted, DVec3::new(parked.x, lifted.y, parked.z), parked]
        })
        .collect();
    let mut times = vec![0.0];
    let mut frames = vec![blocks
        .iter()
        .map(|b| (b.center_mm, b.rotation()))
        .collect::<Vec<_>>()];
    for (k, s) in steps.iter().enumerate() {
        for (p, fraction) in PHASES.iter().enumerate() {
            let mut frame = frames[frames.len() - 1].clone();
            frame[s.block].0 = paths[k][p];
            times.push((k as f64 + fraction) * STEP_S);
            frames.push(frame);
        }
    }
    (times, frames)
}
