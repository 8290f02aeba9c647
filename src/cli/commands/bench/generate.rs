//! `blockworld bench generate`: scenes/s of dataset generation (settle, render four views,
//! write) and the time split between the stages (docs/datasets.md "Settling"; target >= 40 scenes/s
//! for 100 scenes of up to 12 blocks at 512 x 480 on 2 cores), for each look asked (line art and
//! the photographic look by default, side by side with the photo / line art ratio: docs/rendering.md
//! "Photographic look").

use crate::cli::commands::generate::{checked_options, renderers_for};
use crate::cli::progress::with_progress;
use crate::cli::view_args::ViewArgs;
use anyhow::Context;
use blockworld::dataset::{generate_dataset, Shard};
use std::time::Instant;

/// Options of `blockworld bench generate`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Scenes to generate (every family cycles, up to 12 blocks each).
    #[arg(long, default_value_t = 100, value_parser = crate::cli::at_least_one::<u64>)]
    pub count: u64,
    /// Worker threads (default: all cores).
    #[arg(long, default_value_t = 0)]
    pub jobs: usize,
    /// Families (default all).
    #[arg(long = "family", value_delimiter = ',')]
    pub families: Vec<String>,
    /// Looks to measure, one dataset each, in this order (each overrides `--look`).
    #[arg(long, value_delimiter = ',', default_value = "lineart,photo")]
    pub looks: Vec<String>,
    /// View options; `--views ""` measures settling and writing only. `--seed` is the dataset seed.
    #[command(flatten)]
    pub view: ViewArgs,
}

/// What one look's dataset took.
struct Measured {
    look: String,
    generated: u64,
    wall_s: f64,
    /// Seconds summed over threads: draw + settle, render, write.
    stages_s: [f64; 3],
    blocks: u64,
    unstable_draws: u64,
}

impl Measured {
    /// Milliseconds per scene of each stage, on one thread.
    fn stage_ms(&self) -> [f64; 3] {
        let n = self.generated.max(1) as f64;
        self.stages_s.map(|s| s * 1e3 / n)
    }

    fn scenes_per_s(&self) -> f64 {
        self.generated as f64 / self.wall_s.max(1e-12)
    }
}

const STAGES: [&str; 3] = ["draw + settle", "render", "write (encode, hash, rename)"];

/// Generates one dataset in `look` into a temporary directory (removed afterwards).
fn measure(args: &Args, look: &str) -> anyhow::Result<(Measured, usize, Option<String>)> {
    let view = ViewArgs {
        look: look.to_string(),
        ..args.view.clone()
    };
    let opts = checked_options(args.count, &args.families, &view, args.jobs, Shard::WHOLE)?;
    let renderers = renderers_for(&view, args.jobs)?;
    let dir = std::env::temp_dir().join(format!("blockworld-bench-{}-{look}", std::process::id()));
    let started = Instant::now();
    let result = with_progress(
        &format!("bench generate ({look})"),
        "scenes",
        opts.count,
        |p| generate_dataset(&dir, &opts, &renderers, p),
    );
    let wall_s = started.elapsed().as_secs_f64();
    let _ = std::fs::remove_dir_all(&dir);
    let s = result.with_context(|| format!("bench generate, look {look}"))?;
    let threads = if opts.jobs == 0 {
        rayon::current_num_threads()
    } else {
        opts.jobs
    };
    let t = s.times;
    let measured = Measured {
        look: look.to_string(),
        generated: s.generated,
        wall_s,
        stages_s: [t.settle_s, t.render_s, t.write_s],
        blocks: s.blocks,
        unstable_draws: s.unstable_draws,
    };
    Ok((
        measured,
        threads,
        renderers.first().map(|r| r.adapter_info()),
    ))
}

/// Runs the benchmark, one dataset per look, and prints one table with a column per look.
pub fn run(args: Args) -> anyhow::Result<()> {
    anyhow::ensure!(
        !args.looks.is_empty(),
        "--looks: name at least one look (lineart, photo)"
    );
    outln!("{}", super::machine::machine_line().trim_end())?;
    let mut runs = Vec::new();
    let mut header = None;
    for look in &args.looks {
        let (m, threads, adapter) = measure(&args, look.trim())?;
        header.get_or_insert((threads, adapter));
        runs.push(m);
    }
    let (threads, adapter) = header.unwrap_or_default();
    let [w, h] = args.view.render_options()?.camera.size_px;
    outln!(
        "bench generate: {} scenes, {} views of {w}x{h}, {threads} threads{}",
        runs[0].generated,
        args.view.corner_views()?.len(),
        adapter.map(|a| format!(", {a}")).unwrap_or_default()
    )?;
    let views = args.view.corner_views()?.len();
    outln!("{}", table(&runs, views))?;
    for m in &runs {
        outln!(
            "{}: wall {:.3} s: {:.1} scenes/s (mean {:.1} blocks per scene; {} unstable draws redrawn)",
            m.look,
            m.wall_s,
            m.scenes_per_s(),
            m.blocks as f64 / m.generated.max(1) as f64,
            m.unstable_draws
        )?;
    }
    Ok(())
}

/// The table: ms per scene of each stage on one thread, the render stage per view (`views`
/// per scene), and scenes/s, a column per look, and each later look's ratio to the first
/// (photo / line art).
fn table(runs: &[Measured], views: usize) -> String {
    let first = &runs[0];
    let mut head = String::from("| stage |");
    let mut rule = String::from("|---|");
    for m in runs {
        head += &format!(" {} ms per scene (one thread) |", m.look);
        rule += "---|";
    }
    for m in &runs[1..] {
        head += &format!(" {} / {} |", m.look, first.look);
        rule += "---|";
    }
    let mut out = format!("{head}\n{rule}\n");
    for (i, stage) in STAGES.iter().enumerate() {
        out += &format!("| {stage} |");
        for m in runs {
            out += &format!(" {:.3} |", m.stage_ms()[i]);
        }
        for m in &runs[1..] {
            out += &format!(
                " {:.2}x |",
                m.stage_ms()[i] / first.stage_ms()[i].max(1e-12)
            );
        }
        out += "\n";
    }
    out += "| render per view (ms, one thread) |";
    let per_view = |m: &Measured| m.stage_ms()[1] / views.max(1) as f64;
    for m in runs {
        out += &format!(" {:.3} |", per_view(m));
    }
    for m in &runs[1..] {
        out += &format!(" {:.2}x |", per_view(m) / per_view(first).max(1e-12));
    }
    out += "\n";
    out += "| scenes/s (wall) |";
    for m in runs {
        out += &format!(" {:.1} |", m.scenes_per_s());
    }
    for m in &runs[1..] {
        out += &format!(
            " {:.2}x the time |",
            first.scenes_per_s() / m.scenes_per_s().max(1e-12)
        );
    }
    out.trim_end().to_string()
}
