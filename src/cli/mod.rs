//! The command line (clap derive): parse, then run one subcommand. The only module that reads
//! argv or the environment (`SLURM_ARRAY_TASK_ID`, `JOB_COMPLETION_INDEX`).

#[macro_use]
pub mod stdout;
mod commands;
mod docs;
pub mod files;
mod headless;
pub mod progress;
pub mod rrd;
pub mod view_args;

use clap::{Parser, Subcommand};

/// `blockworld --version`: the crate version and the git commit it was built from ("unknown"
/// outside a git checkout; see build.rs).
pub const VERSION: &str = concat!(
    env!("CARGO_PKG_VERSION"),
    " (commit ",
    env!("BLOCKWORLD_COMMIT"),
    ")"
);

/// blockworld: render, simulate and recognize Fischer-Technik block scenes (a modified Kanade
/// model for three-dimensional object recognition).
#[derive(Debug, Parser)]
#[command(name = "blockworld", version = VERSION, about, long_about = None)]
pub struct Cli {
    /// Log more (-v info, -vv debug).
    #[arg(short, long, action = clap::ArgAction::Count, global = true)]
    pub verbose: u8,
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Settle, render, see, recognize, score and export scenes/thesis_sample.json.
    Demo(commands::demo::Args),
    /// Render the four corner views of a scene and their ground truth.
    ///
    /// Limits (docs/limits.md "Render"): at most 10000 blocks; --size at most 8192 px a side
    /// and no more pixels than the device reads back (about 52 Mpx with lavapipe); a written
    /// picture (after --downsample) at least 8 px a side.
    Render(commands::render::Args),
    /// Settle a scene with rapier3d and report whether it rests stably.
    ///
    /// Limits (docs/limits.md "Settle and plan"): at most 2000 blocks.
    Settle(commands::settle::Args),
    /// Generate a synthetic dataset of settled, rendered scenes.
    ///
    /// Limits (docs/limits.md "Generate"): --count up to 18446744073709551615 (scenes are
    /// written as they are made, memory stays small), --jobs at most 1024, at most 128
    /// trajectory pictures per scene, and the picture bounds of `render`.
    Generate(commands::generate::Args),
    /// Join shard manifests of a dataset and check nothing is missing or doubled.
    Merge(commands::merge::Args),
    /// The order a robot takes a reconstruction's blocks away, verified with rapier, with grasps (thesis Ch. VII).
    ///
    /// Limits (docs/limits.md "Settle and plan"): at most 100 blocks.
    Plan(commands::plan::Args),
    /// Score a reconstruction against ground truth (parry3d volume overlap).
    ///
    /// Limits (docs/limits.md "Score"): at most 2000 blocks in each file.
    Score(commands::score::Args),
    /// Sobel edge detection with 3x3 smoothing and a threshold (thesis Ch. II, VI).
    ///
    /// Limits (docs/limits.md "Edges and vertices"): a picture of at most 8192 px a side.
    Edges(commands::edges::Args),
    /// Lines, vertices and six-bit codes of a view (thesis Ch. IV, V).
    ///
    /// Limits (docs/limits.md "Edges and vertices"): a picture of at most 8192 px a side
    /// and at most 200 x (width + height) edge pixels.
    Vertices(commands::vertices::Args),
    /// Recognize the blocks of rendered views (thesis Ch. IV-V): a reconstruction file.
    Recognize(commands::recognize::Args),
    /// Recognize and score every scene of a dataset: the folder `report --recognitions` reads.
    RecognizeDataset(commands::recognize_dataset::Args),
    /// A static web site of a dataset and the recognizer's answers on it (docs/report.md).
    ///
    /// Limits (docs/limits.md "Datasets"): a manifest of at most 1024 MiB (about 580,000
    /// scenes).
    Report(commands::report::Args),
    /// Export a scene as a glTF 2.0 model (.glb, or .gltf + .bin) in metres, y up.
    ///
    /// Limits (docs/limits.md "Export"): each input file at most 128 MiB; the work grows in
    /// proportion to the blocks.
    Export(commands::export::Args),
    /// Kanade's line labelling: junction catalog, Waltz filtering, every consistent labelling.
    Label(commands::label::Args),
    /// Kanade's model against the modified model on the same drawings (thesis Figs. 6.17, 6.18).
    Compare(commands::compare::Args),
    /// Export a dataset for wireframe parsers (HAWP, L-CNN, LETR) or vision tools (COCO, Hugging Face).
    ///
    /// Limits (docs/limits.md "Datasets"): a manifest of at most 1024 MiB (about 580,000
    /// scenes); --split from 0 to 1.
    ExportDataset(commands::export_dataset::Args),
    /// Benchmarks that print tables.
    Bench(commands::bench::Args),
    /// The thesis's viewer: From/At/Up, view angle, 3D clipping (Ch. II, VI, Figures 6.7-6.12).
    View(commands::view::Args),
    /// Print a shell completion script (bash, zsh or fish) on standard output.
    Completions(commands::completions::Args),
    /// Print reference pages generated from this command line (docs/cli.md).
    #[command(hide = true)]
    Docs(docs::Args),
}

/// clap's parser of a count that must be at least 1 (`--repeat`, `--rounds`, `--count` of the
/// benchmarks): 0 would run nothing and print an empty table, so it is refused before any work
/// (exit 2, clap naming the flag).
pub fn at_least_one<T>(text: &str) -> Result<T, String>
where
    T: std::str::FromStr + PartialOrd + From<u8>,
    T::Err: std::fmt::Display,
{
    match text.parse::<T>() {
        Ok(n) if n < T::from(1) => Err("0 runs nothing; give at least 1".into()),
        Ok(n) => Ok(n),
        Err(e) => Err(format!("{e}; give a whole number of at least 1")),
    }
}

/// Refuses `<flag> <value>` unless `ok` (a finite value is also required), before any work:
/// the message echoes the number short ([`blockworld::io::echo_number`]) and says what the flag
/// takes (`takes`, e.g. "use 0 mm or more"), as the render options' errors do.
pub fn check_number(flag: &str, value: f64, ok: bool, takes: &str) -> anyhow::Result<()> {
    if ok && value.is_finite() {
        return Ok(());
    }
    anyhow::bail!(
        "{flag} {} is out of range; {takes}",
        blockworld::io::echo_number(value)
    )
}

/// Refuses an input of more than `max` blocks, before any work (exit 2): names the file, its
/// blocks, the bound of `command` and its docs/limits.md heading `section`.
pub fn check_block_count(
    path: &std::path::Path,
    blocks: usize,
    max: usize,
    command: &str,
    section: &str,
) -> anyhow::Result<()> {
    if blocks <= max {
        return Ok(());
    }
    anyhow::bail!(
        "{}: {blocks} blocks, more than the {max} `{command}` takes ({} \"{section}\"); split the scene into smaller ones",
        path.display(),
        "docs/limits.md"
    )
}

/// `text` with each number longer than [`blockworld::io::MAX_ECHO_CHARS`] characters echoed
/// short ([`blockworld::io::echo_number`]): clap's usage errors quote rejected values as typed.
fn shorten_long_numbers(text: &str) -> String {
    let is_part = |c: char| c.is_ascii_digit() || matches!(c, '.' | 'e' | 'E' | '+' | '-');
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(start) = rest.find(|c: char| c.is_ascii_digit() || c == '-' || c == '+') {
        out.push_str(&rest[..start]);
        let len = rest[start..]
            .find(|c: char| !is_part(c))
            .unwrap_or(rest.len() - start);
        let token = &rest[start..start + len];
        match token.parse::<f64>() {
            Ok(v) if len > blockworld::io::MAX_ECHO_CHARS => {
                out.push_str(&blockworld::io::echo_number(v))
            }
            _ => out.push_str(token),
        }
        rest = &rest[start + len..];
    }
    out.push_str(rest);
    out
}

/// The binary's entry: parses argv, runs, prints the error chain once and returns exit code 2
/// on error (clap reports usage errors itself, also with 2).
pub fn main() -> std::process::ExitCode {
    headless::quiet_device_select_without_session();
    stdout::exit_cleanly_on_stdout_panics();
    blockworld::dataset::keep_freed_pictures_in_heap();
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) if e.use_stderr() => {
            // clap echoes a rejected value as typed: a number of 300 digits is shown short.
            eprint!("{}", shorten_long_numbers(&e.render().to_string()));
            return std::process::ExitCode::from(e.exit_code().clamp(0, 255) as u8);
        }
        Err(e) => e.exit(),
    };
    match run(cli) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(err) if stdout::is_stdout_closed(&err) => std::process::ExitCode::SUCCESS,
        Err(err) => {
            eprintln!("error: {err}");
            let mut last = err.to_string();
            for cause in err.chain().skip(1).map(|c| c.to_string()) {
                // An error that already prints its source (`X: Is a directory`) is followed by
                // that source in the chain: print each message once.
                if !last.contains(&cause) {
                    eprintln!("  caused by: {cause}");
                }
                last = cause;
            }
            std::process::ExitCode::from(2)
        }
    }
}

/// Runs the parsed command line.
pub fn run(cli: Cli) -> anyhow::Result<()> {
    init_tracing(cli.verbose);
    match cli.command {
        Command::Demo(a) => commands::demo::run(a),
        Command::Render(a) => commands::render::run(a),
        Command::Settle(a) => commands::settle::run(a),
        Command::Generate(a) => commands::generate::run(a),
        Command::Merge(a) => commands::merge::run(a),
        Command::Plan(a) => commands::plan::run(a),
        Command::Score(a) => commands::score::run(a),
        Command::Edges(a) => commands::edges::run(a),
        Command::Vertices(a) => commands::vertices::run(a),
        Command::Recognize(a) => commands::recognize::run(a),
        Command::RecognizeDataset(a) => commands::recognize_dataset::run(a),
        Command::Report(a) => commands::report::run(a),
        Command::Export(a) => commands::export::run(a),
        Command::Label(a) => commands::label::run(a),
        Command::Compare(a) => commands::compare::run(a),
        Command::ExportDataset(a) => commands::export_dataset::run(a),
        Command::Bench(a) => commands::bench::run(a),
        Command::View(a) => commands::view::run(a),
        Command::Completions(a) => commands::completions::run(a),
        Command::Docs(a) => docs::run(a),
    }
}

fn init_tracing(verbose: u8) {
    let level = match verbose {
        0 => "warn",
        1 => "info",
        _ => "debug",
    };
    let filter = tracing_subscriber::EnvFilter::try_from_default_env()
        .unwrap_or_else(|_| tracing_subscriber::EnvFilter::new(level));
    let _ = tracing_subscriber::fmt()
        .with_env_filter(filter)
        .with_writer(std::io::stderr)
        .with_ansi(false)
        .try_init();
}
