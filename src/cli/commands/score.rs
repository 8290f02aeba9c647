//! `blockworld score TRUTH.json RECON.json [--json]`: the volume IoU, block matching, layer
//! count and verdict of a reconstruction against its truth (docs/accuracy.md "Scoring and the accuracy suite").

use anyhow::Context;
use blockworld::export::Truncation;
use blockworld::scene::{read_reconstruction, Reconstruction};
use blockworld::score::{score_reconstruction, Score, ScoreOptions};
use std::path::PathBuf;

/// Options of `blockworld score`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The ground-truth scene file.
    pub truth: PathBuf,
    /// The reconstruction: a scene file with `status` (ok or unsupported, with `reason`); its
    /// blocks may overlap. Appendix B data files (PREFIX_vertices.txt) are read too.
    pub recon: PathBuf,
    /// Print the score as JSON instead of a table.
    #[arg(long)]
    pub json: bool,
}

/// Runs `blockworld score`.
pub fn run(args: Args) -> anyhow::Result<()> {
    // Appendix B data files are read back too (Chapter VI menu r, "read blocksample").
    let truth = match super::view::thesis_pair(&args.truth) {
        Some(_) => super::view::read_model(&args.truth, Truncation::Strict)?,
        None => crate::cli::files::read_scene_shown(&args.truth)
            .with_context(|| format!("reading the truth scene {}", args.truth.display()))?,
    };
    let recon = match super::view::thesis_pair(&args.recon) {
        Some(_) => {
            let s = super::view::read_model(&args.recon, Truncation::Strict)?;
            Reconstruction::ok(s.name, s.blocks)
        }
        None => read_reconstruction(&args.recon)
            .with_context(|| format!("reading the reconstruction {}", args.recon.display()))?,
    };
    let max = blockworld::score::MAX_SCORE_BLOCKS;
    crate::cli::check_block_count(&args.truth, truth.blocks.len(), max, "score", "Score")?;
    crate::cli::check_block_count(&args.recon, recon.blocks.len(), max, "score", "Score")?;
    let score = score_reconstruction(&truth, &recon).with_context(|| {
        format!(
            "scoring {} against {}",
            args.recon.display(),
            args.truth.display()
        )
    })?;
    if args.json {
        outln!("{}", serde_json::to_string_pretty(&score)?)?;
    } else {
        out!("{}", score_table(&score))?;
    }
    Ok(())
}

/// The human-readable table of a score.
pub fn score_table(s: &Score) -> String {
    let o = ScoreOptions::default();
    let mut t = String::new();
    let mut row = |k: &str, v: String| t.push_str(&format!("{k:<22} {v}\n"));
    row("verdict", s.verdict.as_str().to_string());
    row(
        "volume IoU",
        format!(
            "{:.4}  (truth {:.1} mm³, recon {:.1} mm³, overlap {:.1} mm³)",
            s.iou, s.truth_volume_mm3, s.recon_volume_mm3, s.intersection_volume_mm3
        ),
    );
    row(
        "blocks matched",
        format!(
            "{} of {} truth, {} recon  (centre ≤ {} mm, turn ≤ {}° modulo symmetry)",
            s.matched_blocks, s.truth_blocks, s.recon_blocks, o.center_tol_mm, o.turn_tol_deg
        ),
    );
    row(
        "precision/recall/F1",
        format!("{:.3} / {:.3} / {:.3}", s.precision, s.recall, s.f1),
    );
    let d = &s.detection;
    row(
        "3D IoU ≥ 0.5 P/R/F1",
        format!(
            "{:.3} / {:.3} / {:.3}  ({} of {} truth, {} recon matched one to one, same type)",
            d.precision, d.recall, d.f1, d.matched, d.truth_blocks, d.recon_blocks
        ),
    );
    row(
        "mean centre error",
        s.mean_center_error_mm
            .map_or("-".to_string(), |e| format!("{e:.3} mm")),
    );
    row(
        "layers",
        format!(
            "{} truth, {} recon: {}",
            s.truth_layers,
            s.recon_layers,
            if s.layers_right { "right" } else { "wrong" }
        ),
    );
    if let Some(r) = &s.reason {
        row("reason", r.clone());
    }
    t
}
