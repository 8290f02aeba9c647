//! `blockworld bench accuracy`: scores reconstructions of the accuracy suite (`scenes/bench/`)
//! and prints a per-family table (README "Scoring and the accuracy suite"). Until a recognizer exists, `--recognizer DIR`
//! names a directory of reconstruction files `<scene-id>.json`; a missing file counts as
//! `failed`. `--make-reference DIR` writes the constructed reference set
//! (`score::make_reference_reconstructions`) that `tests/accuracy_gate.rs` scores.

use crate::cli::view_args::ViewArgs;
use anyhow::{bail, Context};
use blockworld::scene::{read_reconstruction, read_scene, reconstruction_to_json, Scene};
use blockworld::score::{
    check_gate, make_reference_reconstructions, score_suite_scene, summarize_by_family,
    FamilySummary, Golden, NoReconstruction, SceneResult, ScoreOptions, BLESS_COMMAND,
};
use std::path::{Path, PathBuf};

/// Options of `blockworld bench accuracy`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// How views would be rendered for a recognizer (recorded in the JSON; with `--recognizer
    /// DIR` nothing is rendered).
    #[command(flatten)]
    pub view: Box<ViewArgs>,
    /// Directory of reconstruction files `<scene-id>.json` (the recognizer's output).
    #[arg(long)]
    pub recognizer: Option<PathBuf>,
    /// The suite: a directory of scene files `<scene-id>.json`.
    #[arg(long, default_value = "scenes/bench")]
    pub suite: PathBuf,
    /// Where to write the per-scene results as JSON.
    #[arg(long, default_value = "out/bench/accuracy.json")]
    pub json_out: PathBuf,
    /// Also compare with this golden file (e.g. golden/accuracy.json) and fail on a regression.
    #[arg(long)]
    pub golden: Option<PathBuf>,
    /// Write the constructed reference reconstructions of the suite into DIR and stop.
    #[arg(long, value_name = "DIR")]
    pub make_reference: Option<PathBuf>,
}

/// Runs `blockworld bench accuracy`.
pub fn run(args: Args) -> anyhow::Result<()> {
    let suite = read_suite(&args.suite)?;
    if let Some(dir) = &args.make_reference {
        return write_reference(dir, &suite);
    }
    let Some(recon_dir) = &args.recognizer else {
        bail!(
            "no recognizer yet: pass --recognizer DIR with one reconstruction file <scene-id>.json \
             per suite scene (e.g. --recognizer golden/recon_reference)"
        );
    };
    let views = args.view.corner_views()?;
    let render = args.view.render_options()?;
    let results = score_suite(&suite, recon_dir, &ScoreOptions::default());
    let families = summarize_by_family(&results);
    print!("{}", family_table(&families));
    for r in results.iter().filter(|r| r.unexpected_pass) {
        println!(
            "UNEXPECTED PASS {}: marked unsupported but came out {}",
            r.id,
            r.verdict.as_str()
        );
    }
    for r in results.iter().filter(|r| r.note.is_some()) {
        println!("FAILED {}: {}", r.id, r.note.as_deref().unwrap_or_default());
    }
    let report = serde_json::json!({
        "suite": args.suite,
        "recognizer": recon_dir,
        "views": views.iter().map(|v| v.name()).collect::<Vec<_>>(),
        "noise_sigma": render.noise_sigma,
        "projection": args.view.projection,
        "families": families,
        "scenes": results,
    });
    if let Some(parent) = args.json_out.parent() {
        std::fs::create_dir_all(parent)
            .with_context(|| format!("creating {}", parent.display()))?;
    }
    blockworld::io::write_atomic(
        &args.json_out,
        format!("{}\n", serde_json::to_string_pretty(&report)?).as_bytes(),
    )
    .with_context(|| format!("writing {}", args.json_out.display()))?;
    println!("per-scene results: {}", args.json_out.display());
    if let Some(golden) = &args.golden {
        gate(golden, &results)?;
    }
    Ok(())
}

/// Reads every `*.json` scene of the suite directory, sorted by id (the file stem).
fn read_suite(dir: &Path) -> anyhow::Result<Vec<(String, Scene)>> {
    let entries = std::fs::read_dir(dir).with_context(|| {
        format!(
            "reading the suite directory {} (see scenes/bench/README.md)",
            dir.display()
        )
    })?;
    let mut paths: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .collect();
    paths.sort();
    if paths.is_empty() {
        bail!("{}: no scene files (*.json) in the suite", dir.display());
    }
    paths
        .iter()
        .map(|p| {
            let id = p
                .file_stem()
                .unwrap_or_default()
                .to_string_lossy()
                .into_owned();
            Ok((id, read_scene(p)?))
        })
        .collect()
}

/// Scores every suite scene against `<recon_dir>/<id>.json`.
fn score_suite(
    suite: &[(String, Scene)],
    recon_dir: &Path,
    opts: &ScoreOptions,
) -> Vec<SceneResult> {
    suite
        .iter()
        .map(|(id, truth)| {
            let path = recon_dir.join(format!("{id}.json"));
            let recon = if path.exists() {
                read_reconstruction(&path).map_err(|e| NoReconstruction(e.to_string()))
            } else {
                Err(NoReconstruction(format!(
                    "no reconstruction file {}",
                    path.display()
                )))
            };
            score_suite_scene(id, truth, recon.as_ref().map_err(Clone::clone), opts)
        })
        .collect()
}

fn write_reference(dir: &Path, suite: &[(String, Scene)]) -> anyhow::Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    for (id, recon) in make_reference_reconstructions(suite) {
        let path = dir.join(format!("{id}.json"));
        blockworld::io::write_atomic(&path, reconstruction_to_json(&recon).as_bytes())
            .with_context(|| format!("writing {}", path.display()))?;
    }
    println!(
        "wrote {} reference reconstructions to {}",
        suite.len(),
        dir.display()
    );
    Ok(())
}

fn gate(golden_path: &Path, results: &[SceneResult]) -> anyhow::Result<()> {
    let text = std::fs::read_to_string(golden_path).with_context(|| {
        format!(
            "reading {}; create it with {BLESS_COMMAND}",
            golden_path.display()
        )
    })?;
    let golden: Golden = serde_json::from_str(&text)
        .with_context(|| format!("{} is not a golden accuracy file", golden_path.display()))?;
    let failures = check_gate(&golden, results);
    if failures.is_empty() {
        println!("gate: ok against {}", golden_path.display());
        return Ok(());
    }
    for f in &failures {
        println!("GATE {f}");
    }
    bail!(
        "{} accuracy regression(s) against {}; fix them, or accept on purpose with {BLESS_COMMAND}",
        failures.len(),
        golden_path.display()
    )
}

/// The per-family table.
fn family_table(rows: &[FamilySummary]) -> String {
    let mut t = format!(
        "{:<16} {:>6} {:>9} {:>7} {:>7} {:>18}\n",
        "family", "scenes", "mean IoU", "exact", "F1", "expected failures"
    );
    for r in rows {
        let failures = if r.expected_failures == 0 {
            "-".to_string()
        } else {
            format!(
                "{}/{} flagged{}",
                r.flagged,
                r.expected_failures,
                if r.unexpected_passes > 0 { " (!)" } else { "" }
            )
        };
        t.push_str(&format!(
            "{:<16} {:>6} {:>9.4} {:>6.0}% {:>7.3} {:>18}\n",
            r.family,
            r.scenes,
            r.mean_iou,
            100.0 * r.exact_share,
            r.mean_f1,
            failures
        ));
    }
    t
}
