//! `blockworld bench settle`: the cost and the accuracy of settling (docs/datasets.md "Settling") on the peer benchmark's 12-block stack (docs/benchmarks.md "Benchmarks": the same twelve
//! cuboids a PyBullet pipeline settles) and on cube-like stacks of b15: ms (fastest of
//! `--repeat`), simulation steps, simulated time, and how far the settled blocks end from their
//! intended poses (mm, degrees), with the verdict.

use super::fastest_ms;
use super::machine::banner;
use super::scale::grid_stack;
use anyhow::Context;
use blockworld::geom::DVec3;
use blockworld::physics::{settle, SettleParams};
use blockworld::scene::{Block, Scene};

/// Options of `blockworld bench settle`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Settle each scene this many times and keep the fastest.
    #[arg(long, default_value_t = 20, value_parser = crate::cli::at_least_one::<usize>)]
    pub repeat: usize,
    /// Also cube-like stacks of this many b15 (as in `bench scale`), comma separated, each 1 to
    /// 2000.
    #[arg(long, value_delimiter = ',', default_value = "10,100,1000")]
    pub grid: Vec<usize>,
    /// A Python with `pybullet` installed: also settle the 12-block stack in PyBullet (the peer
    /// pipeline's settings, `scripts/pybullet_settle.py`) in this run and print the ratio.
    #[arg(long)]
    pub pybullet: Option<std::path::PathBuf>,
    /// The PyBullet script `--pybullet` runs.
    #[arg(long, default_value = "scripts/pybullet_settle.py")]
    pub pybullet_script: std::path::PathBuf,
}

/// The largest `--grid` entry (docs/limits.md "Benchmarks"): `settle`'s bound,
/// [`blockworld::physics::MAX_SETTLE_BLOCKS`].
pub const MAX_GRID_BLOCKS: usize = blockworld::physics::MAX_SETTLE_BLOCKS;

/// The peer benchmark's 12 cuboids (docs/benchmarks.md "Benchmarks"): a two-layer stack of two b30 and two
/// b15 bridged by a b30 and a b15, two two-high columns of b7_5 and a two-high b15 tower. The
/// peer's table is z-up (x, y, z); here +y is up, so its (x, y, z) becomes (x, z, -y): the same
/// stack turned, not mirrored.
pub fn peer_stack() -> Scene {
    const BLOCKS: [(&str, f64, f64, f64); 12] = [
        ("b30", 15.0, 7.5, 7.5),
        ("b30", 15.0, 22.5, 7.5),
        ("b15", 37.5, 7.5, 7.5),
        ("b15", 37.5, 22.5, 7.5),
        ("b7_5", 52.5, 7.5, 3.75),
        ("b7_5", 52.5, 22.5, 3.75),
        ("b15", 7.5, 45.0, 7.5),
        ("b30", 15.0, 15.0, 22.5),
        ("b15", 37.5, 15.0, 22.5),
        ("b7_5", 52.5, 7.5, 11.25),
        ("b7_5", 52.5, 22.5, 11.25),
        ("b15", 7.5, 45.0, 22.5),
    ];
    let blocks = BLOCKS
        .iter()
        .map(|&(id, x, y, z)| Block::new(id, DVec3::new(x, z, -y), 0.0))
        .collect();
    Scene::new("peer_stack_12", blocks)
}

/// One table row for `scene`, and its ms.
fn row(scene: &Scene, repeat: usize) -> anyhow::Result<(String, f64)> {
    let params = SettleParams::default();
    let (ms, settled) = fastest_ms(repeat, || settle(scene, &params));
    let r = settled
        .with_context(|| format!("settling {}", scene.name))?
        .report;
    let step_s = params.dt_s / f64::from(1u32 << r.stiffenings);
    let text = format!(
        "| {} | {} | {ms:.2} | {} (1/{:.0} s) | {:.0} | {:.4} | {:.4} | {} |",
        scene.name,
        scene.blocks.len(),
        r.steps,
        1.0 / step_s,
        f64::from(r.steps) * step_s * 1e3,
        r.max_drift_mm,
        r.max_turn_deg,
        if r.stable { "stable" } else { "unstable" }
    );
    Ok((text, ms))
}

/// The stack as the PyBullet script reads it: centres and half extents, mm, +y up.
fn pybullet_input(scene: &Scene) -> anyhow::Result<String> {
    let blocks = scene
        .blocks
        .iter()
        .map(|b| {
            let half = b.block_type.cuboid_half_extents_mm().with_context(|| {
                format!(
                    "{} is not a cuboid; the PyBullet peer takes cuboids",
                    b.block_type.id
                )
            })?;
            Ok(serde_json::json!({"center_mm": b.center_mm.to_array(), "half_mm": half.to_array()}))
        })
        .collect::<anyhow::Result<Vec<_>>>()?;
    Ok(serde_json::json!({ "blocks": blocks }).to_string())
}

/// Runs the PyBullet script on the 12-block stack; its JSON answer.
fn pybullet_peer(args: &Args, python: &std::path::Path) -> anyhow::Result<serde_json::Value> {
    use std::io::Write;
    let mut child = std::process::Command::new(python)
        .arg(&args.pybullet_script)
        .args(["--repeat", &args.repeat.to_string()])
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .with_context(|| format!("running {} (--pybullet)", python.display()))?;
    let input = pybullet_input(&peer_stack())?;
    child
        .stdin
        .take()
        .context("the PyBullet script's stdin")?
        .write_all(input.as_bytes())?;
    let out = child.wait_with_output()?;
    anyhow::ensure!(
        out.status.success(),
        "{} {} failed ({}); install pybullet in that Python or drop --pybullet",
        python.display(),
        args.pybullet_script.display(),
        String::from_utf8_lossy(&out.stderr).trim()
    );
    let text = String::from_utf8_lossy(&out.stdout);
    let last = text.lines().last().unwrap_or_default();
    serde_json::from_str(last)
        .with_context(|| format!("reading the PyBullet script's answer {last:?}"))
}

/// Runs `blockworld bench settle`.
pub fn run(args: Args) -> anyhow::Result<()> {
    super::check_block_counts(
        "grid",
        &args.grid,
        MAX_GRID_BLOCKS,
        "each stack is settled in memory",
    )?;
    outln!("{}", banner(None).trim_end())?;
    let p = SettleParams::default();
    outln!(
        "rest: every body below {} mm/s and {} rad/s for {} s simulated (1/{:.0} s steps, halved while a stack's predicted sink exceeds {} mm); ms = fastest of {}, one thread",
        p.rest_speed_mm_s,
        p.rest_spin_rad_s,
        p.rest_hold_s,
        1.0 / p.dt_s,
        p.sink_budget_mm,
        args.repeat
    )?;
    outln!(
        "| scene | blocks | ms | steps | simulated ms | max drift mm | max turn deg | verdict |"
    )?;
    outln!("|---|---|---|---|---|---|---|---|")?;
    let (text, ours_ms) = row(&peer_stack(), args.repeat)?;
    outln!("{text}")?;
    let peer = match &args.pybullet {
        Some(python) => Some(pybullet_peer(&args, python)?),
        None => None,
    };
    if let Some(v) = &peer {
        let num = |k: &str| v[k].as_f64().unwrap_or(f64::NAN);
        outln!(
            "| peer_stack_12 in PyBullet (240 Hz, its rest test, 1 mm drop gap) | 12 | {:.2} | {} | {:.0} | {:.4} | {:.4} | {} |",
            num("ms"),
            v["steps"],
            num("steps") / 240.0 * 1e3,
            num("max_drift_mm"),
            num("max_turn_deg"),
            if v["at_rest"] == true { "at rest" } else { "moving" }
        )?;
    }
    for &n in &args.grid {
        let repeat = if n >= 100 { 1 } else { args.repeat };
        outln!("{}", row(&grid_stack(n), repeat)?.0)?;
    }
    if let Some(v) = &peer {
        let peer_ms = v["ms"].as_f64().unwrap_or(f64::NAN);
        outln!(
            "12-block stack: blockworld {ours_ms:.2} ms, PyBullet {peer_ms:.2} ms: {:.1}x (target 10x)",
            peer_ms / ours_ms
        )?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_peer_stack_is_a_valid_twelve_block_scene() {
        let s = peer_stack();
        assert_eq!(s.blocks.len(), 12);
        s.validate("peer_stack").unwrap();
        // Two layers: six floor blocks of 15 mm, the b7_5 columns in between.
        let top = s.blocks.iter().map(|b| b.center_mm.y).fold(0.0, f64::max);
        assert_eq!(top, 22.5);
    }

    #[test]
    fn the_pybullet_input_lists_centres_and_half_extents() {
        let v: serde_json::Value =
            serde_json::from_str(&pybullet_input(&peer_stack()).unwrap()).unwrap();
        let blocks = v["blocks"].as_array().unwrap();
        assert_eq!(blocks.len(), 12);
        assert_eq!(blocks[0]["center_mm"], serde_json::json!([15.0, 7.5, -7.5]));
        assert_eq!(blocks[0]["half_mm"], serde_json::json!([15.0, 7.5, 7.5]));
        assert_eq!(blocks[4]["half_mm"], serde_json::json!([7.5, 3.75, 7.5]));
    }
}
