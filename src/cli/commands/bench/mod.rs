//! `blockworld bench ...`: benchmarks that print a table (speed targets live here, never in
//! timed unit tests).

mod accuracy;
mod export_dataset;
mod generate;
pub mod machine;
mod recognize;
mod render;
mod scale;
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
}

/// Runs one benchmark.
pub fn run(args: Args) -> anyhow::Result<()> {
    match args.which {
        Which::Render(a) => render::run(a),
        Which::Scale(a) => scale::run(a),
        Which::Generate(a) => generate::run(a),
        Which::Accuracy(a) => accuracy::run(a),
        Which::Vision(a) => vision::run(a),
        Which::Recognize(a) => recognize::run(a),
        Which::ExportDataset(a) => export_dataset::run(a),
    }
}
