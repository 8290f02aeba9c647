//! `blockworld bench generate`: scenes/s of dataset generation (settle, render four views,
//! write) and the time split between the stages (README "Settling and datasets"; target >= 40 scenes/s
//! for 100 scenes of up to 12 blocks at 512 x 480 on 2 cores).

use crate::cli::commands::generate::{checked_options, renderer_for};
use crate::cli::progress::with_progress;
use crate::cli::view_args::ViewArgs;
use anyhow::Context;
use blockworld::dataset::{generate_dataset, Shard};
use std::time::Instant;

/// Options of `blockworld bench generate`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Scenes to generate (every family cycles, up to 12 blocks each).
    #[arg(long, default_value_t = 100)]
    pub count: u64,
    /// Worker threads (default: all cores).
    #[arg(long, default_value_t = 0)]
    pub jobs: usize,
    /// Families (default all).
    #[arg(long = "family", value_delimiter = ',')]
    pub families: Vec<String>,
    /// View options; `--views ""` measures settling and writing only. `--seed` is the dataset seed.
    #[command(flatten)]
    pub view: ViewArgs,
}

/// Runs the benchmark into a temporary directory (removed afterwards) and prints a table.
pub fn run(args: Args) -> anyhow::Result<()> {
    let opts = checked_options(
        args.count,
        &args.families,
        &args.view,
        args.jobs,
        Shard::WHOLE,
    )?;
    let renderer = renderer_for(&args.view)?;
    let dir = std::env::temp_dir().join(format!("blockworld-bench-{}", std::process::id()));
    let started = Instant::now();
    let result = with_progress("bench generate", "scenes", opts.count, |p| {
        generate_dataset(&dir, &opts, renderer.as_ref(), p)
    });
    let wall_s = started.elapsed().as_secs_f64();
    let _ = std::fs::remove_dir_all(&dir);
    let s = result.context("bench generate")?;
    let threads = if opts.jobs == 0 {
        rayon::current_num_threads()
    } else {
        opts.jobs
    };
    let t = s.times;
    let busy = (t.settle_s + t.render_s + t.write_s).max(1e-12);
    let n = s.generated.max(1) as f64;
    let [w, h] = opts.render.camera.size_px;
    let load = std::fs::read_to_string("/proc/loadavg")
        .map(|l| l.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_else(|_| "unknown".into());
    outln!(
        "bench generate: {} scenes, {} views of {w}x{h}, {threads} threads, load average {load}{}",
        s.generated,
        opts.views.len(),
        renderer
            .as_ref()
            .map(|r| format!(", {}", r.adapter_info()))
            .unwrap_or_default()
    )?;
    outln!("| stage | ms per scene (one thread) | share |")?;
    outln!("|---|---|---|")?;
    for (name, secs) in [
        ("draw + settle", t.settle_s),
        ("render", t.render_s),
        ("write (encode, hash, rename)", t.write_s),
    ] {
        outln!(
            "| {name} | {:.3} | {:.1}% |",
            secs * 1e3 / n,
            100.0 * secs / busy
        )?;
    }
    let blocks = s.blocks;
    outln!(
        "wall {:.3} s: {:.1} scenes/s (mean {:.1} blocks per scene; {} unstable draws redrawn)",
        wall_s,
        s.generated as f64 / wall_s.max(1e-12),
        blocks as f64 / n,
        s.unstable_draws
    )?;
    Ok(())
}
