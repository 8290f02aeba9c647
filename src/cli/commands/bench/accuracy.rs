//! `blockworld bench accuracy`: renders the accuracy suite (`scenes/bench/`) with the view
//! options, runs the vision front end (or, with `--from-truth`, takes the exact drawings) and
//! the modified Kanade recognizer, scores every scene and prints the per-family table with the
//! confidently wrong scenes by name (docs/recognizer.md "Recognizer"; `blockworld::pipeline`).
//! `--recognizer DIR` scores someone else's reconstruction files `<scene-id>.json` instead (a
//! missing file counts as `failed`). `--make-reference DIR` writes the constructed reference
//! set (`score::make_reference_reconstructions`) that `tests/scorer_reference.rs` scores.
//! `--family F --count N --seed S` draws the suite with the generator instead of reading it: the
//! scenes `generate --family F --count N --seed S` writes, settled in memory (docs/accuracy.md "Scoring and the accuracy suite"). With `--look photo_varied` every scene is rendered in its own draw of
//! the varied look (its seed the scene's: `dataset::scene_seed(--seed, index)`, the seed
//! `generate` gives it) and a second table counts the results per factor bin
//! (docs/varied-look.md "Factors and bins").

use crate::cli::commands::generate::parse_families;
use crate::cli::view_args::ViewArgs;
use anyhow::{bail, Context};
use blockworld::dataset::{draw_stable_scene, scene_seed, SceneSpec};
use blockworld::physics::SettleParams;
use blockworld::pipeline::{run_scene, run_suite, DrawingSource, PipelineOptions};
use blockworld::render::photo::varied::{LookDraw, FACTORS};
use blockworld::render::{Look, RenderOptions, Renderer};
use blockworld::scene::{read_reconstruction, read_scene, reconstruction_to_json, Scene};
use blockworld::score::{
    check_gate, make_reference_reconstructions, score_suite_scene, summarize_by_family,
    FamilySummary, Golden, NoReconstruction, SceneResult, ScoreOptions, Verdict, BLESS_COMMAND,
    FAMILY_TABLE_HEADINGS,
};
use blockworld::vision::VisionOptions;
use std::path::{Path, PathBuf};

/// Options of `blockworld bench accuracy`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// How views would be rendered for a recognizer (recorded in the JSON; with `--recognizer
    /// DIR` nothing is rendered).
    #[command(flatten)]
    pub view: Box<ViewArgs>,
    /// Score the reconstruction files `<scene-id>.json` in DIR instead of running the
    /// recognizer.
    #[arg(long)]
    pub recognizer: Option<PathBuf>,
    /// Feed the recognizer the exact line drawings instead of the vision front end's, to tell
    /// recognition errors from vision errors.
    #[arg(long)]
    pub from_truth: bool,
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
    /// Instead of `--suite`: draw the suite with the generator from these families (repeat or
    /// comma-separate; e.g. wedge, round), `--count` scenes from the dataset seed `--seed`.
    #[arg(long = "family", value_delimiter = ',', conflicts_with = "recognizer")]
    pub families: Vec<String>,
    /// How many scenes `--family` draws.
    #[arg(long, default_value_t = 48, value_parser = crate::cli::at_least_one::<u64>)]
    pub count: u64,
    /// Recognize pictures someone else drew, laid out as a dataset (per scene `scene.json`, and
    /// `view_<v>.png` beside `camera_<v>.json`), beside blockworld's own looks of the same
    /// scenes (docs/yardstick.md "The bench"); with `--look photo_varied`, pictures of a
    /// varied-look dataset beside blockworld's varied look in each scene's own draw (its
    /// `look.json` seed; docs/yardstick.md "The varied look, draw for draw").
    #[arg(long, value_name = "DIR", conflicts_with_all = ["recognizer", "families", "make_reference", "from_truth", "golden"])]
    pub pictures: Option<PathBuf>,
    /// What the recognizer is told of the world.
    #[command(flatten)]
    pub world: crate::cli::commands::recognize::WorldArgs,
}

/// Runs `blockworld bench accuracy`.
pub fn run(args: Args) -> anyhow::Result<()> {
    args.world.grid_mm()?;
    if let Some(dir) = &args.pictures {
        return super::pictures::run(&args, dir);
    }
    let suite = if args.families.is_empty() {
        read_suite(&args.suite)?
    } else {
        drawn_suite(&args.families, args.count, args.view.seed)?
    };
    if let Some(dir) = &args.make_reference {
        return write_reference(dir, &suite);
    }
    let views = args.view.corner_views()?;
    let render = args.view.render_options()?;
    let (results, unseen, undecided) = match &args.recognizer {
        Some(dir) => (
            score_suite(&suite, dir, &ScoreOptions::default()),
            Vec::new(),
            Vec::new(),
        ),
        None => run_recognizer(&args, &suite, views.clone(), render)?,
    };
    let families = summarize_by_family(&results);
    print!("{}", family_table(&families));
    let looks = scene_looks(&suite, &render, args.view.seed);
    if !looks.is_empty() {
        print!("{}", factor_table(&results, &looks));
    }
    print_scene_notes(&results, &unseen, &undecided);
    let report = serde_json::json!({
        "suite": if args.families.is_empty() {
            args.suite.display().to_string()
        } else {
            format!("generate --family {} --count {} --seed {}", args.families.join(","), args.count, args.view.seed)
        },
        "recognizer": args.recognizer.as_ref().map_or("blockworld".into(), |d| d.display().to_string()),
        "from_truth": args.from_truth,
        "grid_mm": args.world.grid_mm,
        "views": views.iter().map(|v| v.name()).collect::<Vec<_>>(),
        "noise_sigma": render.noise_sigma,
        "projection": args.view.projection,
        "families": families,
        "scenes": results,
        "looks": looks.iter().map(|d| serde_json::json!({"seed": d.seed, "bins": d.bins})).collect::<Vec<_>>(),
        "undecided": undecided.iter().map(|(id, why)| serde_json::json!({"id": id, "why": why})).collect::<Vec<_>>(),
    });
    write_report(&args.json_out, &report)?;
    if let Some(golden) = &args.golden {
        gate(golden, &results)?;
    }
    Ok(())
}

/// The lines under the tables: the confidently wrong scenes, blocks no view shows, scenes the
/// views do not decide, unexpected passes and failures.
fn print_scene_notes(
    results: &[SceneResult],
    unseen: &[(String, usize)],
    undecided: &[(String, String)],
) {
    let wrong: Vec<&str> = results
        .iter()
        .filter(|r| r.confidently_wrong)
        .map(|r| r.id.as_str())
        .collect();
    println!(
        "confidently wrong (status ok, verdict not exact): {} of {} scenes ({:.1}%){}",
        wrong.len(),
        results.len(),
        100.0 * wrong.len() as f64 / results.len().max(1) as f64,
        if wrong.is_empty() {
            String::new()
        } else {
            format!(": {}", wrong.join(", "))
        }
    );
    let unseen_total: usize = unseen.iter().map(|(_, n)| n).sum();
    if unseen_total > 0 {
        println!(
            "blocks no view shows (counted apart; no picture can recover them): {unseen_total} in {:?}",
            unseen.iter().filter(|(_, n)| *n > 0).map(|(id, _)| id).collect::<Vec<_>>()
        );
    }
    for (id, why) in undecided {
        println!("views do not decide {id} (counted apart; declining it is right): {why}");
    }
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
}

/// What the standing check did (docs/recognizer.md "Reconstructions that must stand"): the
/// answers it declined, what their verdicts would have been, and its cost per settled answer.
fn print_standing_check(runs: &[blockworld::pipeline::SceneRun]) {
    let declined: Vec<&SceneResult> = runs
        .iter()
        .filter_map(|r| r.declined_by_standing.as_ref())
        .collect();
    let settled: Vec<f64> = runs
        .iter()
        .map(|r| r.times.stand_ms)
        .filter(|&ms| ms > 0.0)
        .collect();
    let mean_ms = settled.iter().sum::<f64>() / settled.len().max(1) as f64;
    let max_ms = settled.iter().copied().fold(0.0, f64::max);
    let exact = declined
        .iter()
        .filter(|r| r.verdict == blockworld::score::Verdict::Exact)
        .count();
    let ids: Vec<String> = declined
        .iter()
        .map(|r| format!("{} ({})", r.id, r.verdict.as_str()))
        .collect();
    println!(
        "standing check: {} answers settled (mean {mean_ms:.1} ms, max {max_ms:.1} ms); {} declined, of which {exact} exact and {} confidently wrong before the check{}",
        settled.len(),
        declined.len(),
        declined.len() - exact,
        if ids.is_empty() { String::new() } else { format!(": {}", ids.join(", ")) }
    );
}

/// The suite's results, per scene id how many blocks no view shows, and the scenes the views do
/// not decide with why.
type SuiteOutcome = (
    Vec<SceneResult>,
    Vec<(String, usize)>,
    Vec<(String, String)>,
);

/// Renders, recognizes and scores every suite scene (`pipeline::run_suite`); returns the
/// results, per scene how many blocks no view shows, and the scenes the views do not decide.
fn run_recognizer(
    args: &Args,
    suite: &[(String, Scene)],
    views: Vec<blockworld::camera::CornerView>,
    render: blockworld::render::RenderOptions,
) -> anyhow::Result<SuiteOutcome> {
    let renderer = Renderer::new(args.view.backend()?).context("starting the renderer")?;
    print!("{}", super::machine::banner(Some(&renderer)));
    let opts = PipelineOptions {
        render,
        views,
        recognize: recognize_options(args),
        source: if args.from_truth {
            DrawingSource::Truth
        } else {
            DrawingSource::Pictures(VisionOptions::default())
        },
        ..PipelineOptions::default()
    };
    let runs = if opts.render.look == Look::PhotoVaried {
        // Each scene in its own draw of the look, seeded as `generate` seeds it.
        let seed = args.view.seed;
        suite
            .iter()
            .enumerate()
            .map(|(i, (id, scene))| {
                let mut o = opts.clone();
                o.render.seed = scene_seed(seed, i as u64);
                run_scene(&renderer, id, scene, &o)
            })
            .collect()
    } else {
        run_suite(&renderer, suite, &opts)
    };
    print_standing_check(&runs);
    let unseen = runs
        .iter()
        .map(|r| (r.result.id.clone(), r.unseen_blocks.len()))
        .collect();
    let undecided = runs
        .iter()
        .filter_map(|r| Some((r.result.id.clone(), r.undecided.clone()?)))
        .collect();
    Ok((
        runs.into_iter().map(|r| r.result).collect(),
        unseen,
        undecided,
    ))
}

/// The pipeline's recognizer options, told what `args` says of the world (`--grid-mm`).
pub(super) fn recognize_options(args: &Args) -> blockworld::recognize::RecognizeOptions {
    blockworld::recognize::RecognizeOptions {
        grid_mm: args.world.grid_mm,
        ..PipelineOptions::default().recognize
    }
}

/// The scenes `generate --family F --count N --seed S` would write, drawn and settled in memory
/// (`dataset::draw_stable_scene`, the generator's own path), with their ids.
fn drawn_suite(families: &[String], count: u64, seed: u64) -> anyhow::Result<Vec<(String, Scene)>> {
    let families = parse_families(families)?;
    if count == 0 {
        bail!("--count 0: draw at least one scene");
    }
    (0..count)
        .map(|index| {
            let spec = SceneSpec::new(seed, index, &families);
            let drawn = draw_stable_scene(&spec, &SettleParams::default())
                .with_context(|| format!("drawing scene {} of the suite", spec.id()))?;
            Ok((spec.id(), drawn.scene))
        })
        .collect()
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
        "{} accuracy regression(s) against {}; fix them, or accept on purpose with {}",
        failures.len(),
        golden_path.display(),
        golden.bless
    )
}

/// The per-family table.
pub(super) fn family_table(rows: &[FamilySummary]) -> String {
    let mut t = format!(
        "| {} |\n|{}\n",
        FAMILY_TABLE_HEADINGS.join(" | "),
        "---|".repeat(FAMILY_TABLE_HEADINGS.len())
    );
    for r in rows {
        t.push_str(&format!("| {} |\n", r.cells().join(" | ")));
    }
    t
}

/// Each suite scene's draw of the varied look, in suite order (seeded as `run_recognizer`
/// seeds it); empty unless the look is `photo_varied`.
fn scene_looks(suite: &[(String, Scene)], render: &RenderOptions, seed: u64) -> Vec<LookDraw> {
    suite
        .iter()
        .enumerate()
        .filter_map(|(i, (_, scene))| {
            RenderOptions {
                seed: scene_seed(seed, i as u64),
                ..*render
            }
            .look_draw(scene.blocks.len())
        })
        .collect()
}

/// The per-factor table: for every factor of the varied look and each of its bins, the
/// supported scenes drawn in it and how many came out exact, declined or confidently wrong
/// (docs/varied-look.md "Factors and bins").
pub(crate) fn factor_table(results: &[SceneResult], looks: &[LookDraw]) -> String {
    let mut t = String::from(
        "| factor | bin | supported scenes | exact | declined | confidently wrong |\n|---|---|---|---|---|---|\n",
    );
    for factor in FACTORS {
        let mut bins: Vec<&str> = looks
            .iter()
            .filter_map(|d| d.bins.get(factor).map(String::as_str))
            .collect();
        bins.sort_unstable();
        bins.dedup();
        for bin in bins {
            let rs: Vec<&SceneResult> = results
                .iter()
                .zip(looks)
                .filter(|(r, d)| r.supported && d.bins.get(factor).is_some_and(|b| b == bin))
                .map(|(r, _)| r)
                .collect();
            let n = rs.len();
            let exact = rs.iter().filter(|r| r.verdict == Verdict::Exact).count();
            let declined = rs
                .iter()
                .filter(|r| r.verdict == Verdict::Unsupported)
                .count();
            let wrong = rs.iter().filter(|r| r.confidently_wrong).count();
            t.push_str(&format!(
                "| {factor} | {bin} | {n} | {exact} ({:.0}%) | {declined} | {wrong} |\n",
                100.0 * exact as f64 / n.max(1) as f64
            ));
        }
    }
    t
}

/// Writes a bench's per-scene results as pretty JSON to `path` (its folder made first) and
/// names the file on stdout; `bench accuracy` and `bench accuracy --pictures` share it.
pub(crate) fn write_report(path: &Path, report: &serde_json::Value) -> anyhow::Result<()> {
    if let Some(parent) = path.parent() {
        std::fs::create_dir_all(parent)
            .with_context(|| format!("creating {}", parent.display()))?;
    }
    blockworld::io::write_atomic(path, blockworld::io::pretty_json(report).as_bytes())
        .with_context(|| format!("writing {}", path.display()))?;
    println!("per-scene results: {}", path.display());
    Ok(())
}
