//! `blockworld settle SCENE.json -o SETTLED.json [--allow-drift]` (docs/datasets.md "Settling").

use crate::cli::check_number;
use anyhow::{bail, Context};
use blockworld::physics::{settle, SettleParams};
use blockworld::scene::write_scene;
use std::path::PathBuf;

/// Options of `blockworld settle`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The scene file to settle.
    pub scene: PathBuf,
    /// Where to write the settled scene (intended poses as quaternions when stable).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Write the simulated poses even when blocks moved beyond the tolerances.
    #[arg(long)]
    pub allow_drift: bool,
    /// Largest allowed drift of a block's centre, mm.
    #[arg(long, default_value_t = 0.5)]
    pub drift_tol_mm: f64,
    /// Largest allowed turn of a block, degrees.
    #[arg(long, default_value_t = 1.0)]
    pub turn_tol_deg: f64,
}

/// Runs `blockworld settle`: stable scenes are written snapped to their intended poses;
/// unstable ones are reported block by block and fail unless `--allow-drift`.
pub fn run(args: Args) -> anyhow::Result<()> {
    let (drift, turn) = (args.drift_tol_mm, args.turn_tol_deg);
    check_number("--drift-tol-mm", drift, drift >= 0.0, "use 0 mm or more")?;
    check_number("--turn-tol-deg", turn, turn >= 0.0, "use 0 degrees or more")?;
    crate::cli::files::check_output(&args.output, &[&args.scene])?;
    let scene = crate::cli::files::read_scene_shown(&args.scene)?;
    let max = blockworld::physics::MAX_SETTLE_BLOCKS;
    let section = "Settle and plan";
    crate::cli::check_block_count(&args.scene, scene.blocks.len(), max, "settle", section)?;
    let params = SettleParams {
        drift_tol_mm: args.drift_tol_mm,
        turn_tol_deg: args.turn_tol_deg,
        ..SettleParams::default()
    };
    let settled =
        settle(&scene, &params).with_context(|| format!("settling {}", args.scene.display()))?;
    let r = &settled.report;
    let moved = r.describe_moved(&scene, &params);
    if !r.stable && !args.allow_drift {
        bail!(
            "{} is not stable (tolerances {} mm, {} deg):\n{moved}\nnothing written; fix the scene or pass --allow-drift to write the settled poses",
            args.scene.display(),
            blockworld::io::echo_number(params.drift_tol_mm),
            blockworld::io::echo_number(params.turn_tol_deg)
        );
    }
    if !r.stable {
        // A drifted scene that no command could read back (a block slid off the floor or into
        // another) is not written (docs/datasets.md "Settling").
        settled
            .scene
            .validate(&args.output.display().to_string())
            .with_context(|| {
                format!(
                    "{}: the drifted poses do not form a valid scene; nothing written",
                    args.scene.display()
                )
            })?;
    }
    write_scene(&args.output, &settled.scene)?;
    if r.stable {
        outln!(
            "{}: stable after {} steps (max drift {:.4} mm, max turn {:.4} deg); wrote {}",
            args.scene.display(),
            r.steps,
            r.max_drift_mm,
            r.max_turn_deg,
            args.output.display()
        )?;
    } else {
        eprintln!("warning: {} is not stable:\n{moved}", args.scene.display());
        outln!("wrote the drifted poses to {}", args.output.display())?;
    }
    Ok(())
}
