//! `blockworld bench ...`: benchmarks that print a table (speed targets live here, never in
//! timed unit tests).

mod accuracy;
mod export_dataset;
mod generate;
pub mod machine;
mod peers;
mod pictures;
mod recognize;
mod render;
mod scale;
mod settle;
mod vision;
mod vision_scaling;

/// Options of `blockworld bench`.
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(subcommand)]
    which: Which,
}

#[derive(Debug, clap::Subcommand)]
enum Which {
    /// ms per view (render + readback) for scenes of 1, 10 and 50 blocks.
    Render(render::Args),
    /// scenes/s of dataset generation and its time split.
    Generate(generate::Args),
    /// Per-family accuracy of reconstructions against the accuracy suite.
    Accuracy(accuracy::Args),
    /// Vision front end against ground truth: precision, recall, code accuracy, ms per step.
    Vision(vision::Args),
    /// ms per scene of the recognizer alone and of vision plus recognizer, and its memory.
    Recognize(recognize::Args),
    /// images/s of the wireframe export (HAWP, L-CNN, LETR) of a dataset.
    ExportDataset(export_dataset::Args),
    /// How each stage's cost grows from 1 to 10, 100 and 1,000 blocks.
    Scale(scale::Args),
    /// ms, steps and drift of settling the peer benchmark's 12-block stack and cube-like stacks.
    Settle(settle::Args),
    /// generate, render and vision beside their peers (Kubric-style, Blender Workbench,
    /// OpenCV), interleaved over rounds, and the ratios of the medians.
    Peers(peers::Args),
}

/// The fastest of `repeat` runs of `f` (at least one), in ms, with the last run's result: the
/// one timing loop of the benchmarks (the fastest run is the one least disturbed by a shared
/// machine).
fn fastest_ms<T>(repeat: usize, mut f: impl FnMut() -> T) -> (f64, T) {
    let mut best = f64::INFINITY;
    let mut out = None;
    for _ in 0..repeat.max(1) {
        let t = std::time::Instant::now();
        let r = f();
        best = best.min(t.elapsed().as_secs_f64() * 1e3);
        out = Some(r);
    }
    (best, out.expect("at least one run"))
}

/// Refuses a `--<flag>` size list holding an entry outside `1..=max` blocks, before any work:
/// the message names the entry, the bound and why it exists (`why`).
fn check_block_counts(flag: &str, counts: &[usize], max: usize, why: &str) -> anyhow::Result<()> {
    match counts.iter().find(|n| !(1..=max).contains(*n)) {
        Some(n) => anyhow::bail!("--{flag} {n}: use counts from 1 to {max} blocks ({why})"),
        None => Ok(()),
    }
}

/// Runs one benchmark.
pub fn run(args: Args) -> anyhow::Result<()> {
    match args.which {
        Which::Render(a) => render::run(a),
        Which::Scale(a) => scale::run(a),
        Which::Settle(a) => settle::run(a),
        Which::Generate(a) => generate::run(a),
        Which::Accuracy(a) => accuracy::run(a),
        Which::Vision(a) => vision::run(a),
        Which::Recognize(a) => recognize::run(a),
        Which::ExportDataset(a) => export_dataset::run(a),
        Which::Peers(a) => peers::run(a),
    }
}
