//! `blockworld bench peers --python VENV/bin/python --peers-dir DIR [--rounds 5]`: blockworld's
//! generate, render and vision beside the peers that do the same work, interleaved over rounds
//! in one run, and the ratio of the medians (docs/benchmarks.md "Benchmarks": only ratios measured in one run
//! on one machine compare; absolute figures on shared machines do not).
//!
//! The peers are Python programs outside blockworld: a Kubric-style dataset pipeline (PyBullet,
//! TinyRenderer, Pillow) and OpenCV's vision path, each printing one line `RESULT {json}`, from
//! `--peers-dir`; and Blender 4.2 Workbench through `bench/peers/blender_workbench.py`, which is
//! compiled into the binary and written to a scratch folder. Settling is not compared: the peer
//! folder has no PyBullet settle script (`bench settle`-style figures stay in docs/benchmarks.md
//! "Benchmarks").

use super::machine::banner;
use super::vision::fastest_steps;
use crate::cli::commands::generate::{checked_options, renderer_for, renderers_for};
use crate::cli::files::{read_camera, read_picture};
use crate::cli::view_args::ViewArgs;
use anyhow::{bail, Context};
use blockworld::camera::CornerView;
use blockworld::dataset::{generate_dataset, Shard};
use blockworld::render::{RenderOptions, Renderer};
use blockworld::vision::{edge_directions, VisionOptions};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

/// The Blender Workbench peer script (our own code, docs/benchmarks.md "Benchmarks").
const BLENDER_SCRIPT: &str = include_str!("../../../../bench/peers/blender_workbench.py");

/// The peer scripts `--peers-dir` must hold.
const PEER_SCRIPTS: [&str; 3] = ["kubric_style_bench.py", "opencv_bench.py", "layout.py"];

/// The Python modules the peers import.
const PEER_MODULES: &str = "pybullet, PIL, numpy, cv2, bpy";

/// How to make a Python environment that runs every peer.
const INSTALL_HINT: &str = "run `make peers` (a venv in target/peers-venv from \
                            bench/peers/requirements.txt), or pass --python with such a venv's python";

/// Blocks of the render comparison (the 10-block row of `bench render`).
const RENDER_BLOCKS: usize = 10;

/// Scenes whose views the vision comparison reads (four views each).
const VISION_SCENES: usize = 8;

/// Runs of the vision front end per view, both sides (the OpenCV script's `--repeat`).
const VISION_REPEAT: usize = 3;

/// Untimed runs of the vision front end on the first view before the timed ones (the OpenCV
/// script's fixed warm-up).
const VISION_WARMUP: usize = 3;

/// Options of `blockworld bench peers`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Python with the packages of bench/peers/requirements.txt (`make peers` builds this
    /// one).
    #[arg(long, default_value = "target/peers-venv/bin/python")]
    pub python: PathBuf,
    /// Folder of the peer scripts (kubric_style_bench.py, opencv_bench.py, layout.py).
    #[arg(long, default_value = "bench/peers")]
    pub peers_dir: PathBuf,
    /// Rounds; each runs every measurement once, blockworld and peer one after the other.
    #[arg(long, default_value_t = 5, value_parser = crate::cli::at_least_one::<usize>)]
    pub rounds: usize,
    /// Scenes per dataset run (blockworld's and the Kubric-style pipeline's).
    #[arg(long, default_value_t = 100, value_parser = crate::cli::at_least_one::<u64>)]
    pub count: u64,
    /// Workers of both dataset pipelines.
    #[arg(long, default_value_t = 2)]
    pub jobs: usize,
    /// Timed views per render run (blockworld's and Blender's).
    #[arg(long, default_value_t = 40)]
    pub render_views: usize,
    /// Seconds of untimed renders before each side's timed renders (blockworld's and
    /// Blender's alike, at least their fixed warm-up counts), so both are timed in their
    /// steady state: one process rendering the 10-block view without pause read 1.01, 0.91
    /// and 0.86 ms per view in its first three seconds and 0.83-0.87 after (docs/benchmarks.md "Peers").
    #[arg(long, default_value_t = 2.0)]
    pub render_warmup_s: f64,
    /// blockworld's view options (defaults: the four corner views, 512 x 480, orthographic).
    #[command(flatten)]
    pub view: ViewArgs,
}

/// The medians' rows: what both sides did and the figures of every round.
#[derive(Debug, Default)]
struct Rounds {
    bw_scenes_per_s: Vec<f64>,
    peer_scenes_per_s: Vec<f64>,
    bw_ms_per_view: Vec<f64>,
    bw_ms_per_view_four: Vec<f64>,
    blender_ms_per_view: Vec<f64>,
    bw_vision_ms: Vec<f64>,
    opencv_ms: Vec<f64>,
}

/// Runs `blockworld bench peers`.
pub fn run(args: Args) -> anyhow::Result<()> {
    let w = args.render_warmup_s;
    crate::cli::check_number("--render-warmup-s", w, w >= 0.0, "use 0 s or more")?;
    check_peers(&args.python, &args.peers_dir, &python_imports)?;
    let renderer = renderer_for(&args.view)?.context("bench peers needs views to render")?;
    let scratch = std::env::temp_dir().join(format!("blockworld-peers-{}", std::process::id()));
    std::fs::create_dir_all(&scratch).with_context(|| format!("creating {}", scratch.display()))?;
    let result = run_rounds(&args, &renderer, &scratch);
    let _ = std::fs::remove_dir_all(&scratch);
    let rounds = result?;
    outln!("{}", banner(Some(&renderer)).trim_end())?;
    print_table(&args, &rounds)
}

/// Every round: blockworld's dataset run then the Kubric-style one, blockworld's renders then
/// Blender's, blockworld's vision then OpenCV's on the same views.
fn run_rounds(args: &Args, renderer: &Renderer, scratch: &Path) -> anyhow::Result<Rounds> {
    let blender = scratch.join("blender_workbench.py");
    std::fs::write(&blender, BLENDER_SCRIPT)
        .with_context(|| format!("writing {}", blender.display()))?;
    let peer = |script: &Path, extra: &[String]| run_peer(&args.python, script, extra);
    let mut r = Rounds::default();
    for round in 1..=args.rounds {
        eprintln!("bench peers: round {round} of {}", args.rounds);
        let dataset = scratch.join("blockworld-dataset");
        let _ = std::fs::remove_dir_all(&dataset);
        r.bw_scenes_per_s.push(blockworld_generate(args, &dataset)?);
        let out = scratch.join("kubric-out").display().to_string();
        let kubric = args.peers_dir.join("kubric_style_bench.py");
        let k = peer(
            &kubric,
            &strings(&[
                "--count",
                &args.count.to_string(),
                "--jobs",
                &args.jobs.to_string(),
                "--out",
                &out,
            ]),
        )?;
        r.peer_scenes_per_s.push(number(&k, "scenes_per_s")?);
        let (one, four) = blockworld_render(renderer, args.render_views, args.render_warmup_s)?;
        r.bw_ms_per_view.push(one);
        r.bw_ms_per_view_four.push(four);
        let out = scratch.join("blender-out").display().to_string();
        let blocks = RENDER_BLOCKS.to_string();
        let b = peer(
            &blender,
            &strings(&[
                "--blocks",
                &blocks,
                "--views",
                &args.render_views.to_string(),
                "--warmup-seconds",
                &args.render_warmup_s.to_string(),
                "--out",
                &out,
            ]),
        )?;
        r.blender_ms_per_view
            .push(number(&b, "ms_per_view_median")?);
        let views = collect_views(&dataset, &scratch.join("views"))?;
        r.bw_vision_ms.push(blockworld_vision(&views)?);
        let opencv = args.peers_dir.join("opencv_bench.py");
        let dir = scratch.join("views").display().to_string();
        let repeat = VISION_REPEAT.to_string();
        let opencv_args = ["--views-dir", &dir, "--threads", "1", "--repeat", &repeat];
        let o = peer(&opencv, &strings(&opencv_args))?;
        r.opencv_ms.push(number(&o, "ms_per_view_total_mean")?);
    }
    Ok(r)
}

fn strings(items: &[&str]) -> Vec<String> {
    items.iter().map(|s| s.to_string()).collect()
}

/// scenes/s of `generate` (default families, the view options given) into `dir`, through
/// `generate`'s renderers (one device per worker), made before the clock starts and dropped
/// after the run, so the render comparison that follows runs beside no other device.
fn blockworld_generate(args: &Args, dir: &Path) -> anyhow::Result<f64> {
    let renderers = renderers_for(&args.view, args.jobs)?;
    let opts = checked_options(args.count, &[], &args.view, args.jobs, Shard::WHOLE)?;
    let started = Instant::now();
    let s = generate_dataset(dir, &opts, &renderers, &|_, _| {})
        .with_context(|| format!("generating {}", dir.display()))?;
    Ok(s.generated as f64 / started.elapsed().as_secs_f64().max(1e-9))
}

/// Median ms per view of `views` renders (render + readback) of the 10-block stack of `bench
/// render`: one view per submission, and the four corner views per submission; after at least
/// 8 untimed renders and `warmup_s` seconds of them.
fn blockworld_render(
    renderer: &Renderer,
    views: usize,
    warmup_s: f64,
) -> anyhow::Result<(f64, f64)> {
    let scene = super::render::bench_scene(RENDER_BLOCKS);
    let opts = RenderOptions::default();
    let warmup = Instant::now();
    let mut k = 0;
    while k < 8 || warmup.elapsed().as_secs_f64() < warmup_s {
        renderer.render_pixels(&scene, CornerView::ALL[k % 4], &opts)?;
        k += 1;
    }
    let mut one = Vec::with_capacity(views);
    for k in 0..views.max(1) {
        let t = Instant::now();
        renderer.render_pixels(&scene, CornerView::ALL[k % 4], &opts)?;
        one.push(t.elapsed().as_secs_f64() * 1e3);
    }
    let mut four = Vec::new();
    for _ in 0..views.max(4) / 4 {
        let t = Instant::now();
        renderer.render_views_pixels(&scene, &CornerView::ALL, &opts)?;
        four.push(t.elapsed().as_secs_f64() * 1e3 / 4.0);
    }
    Ok((median(&mut one), median(&mut four)))
}

/// Copies the pictures and cameras of the first scenes of `dataset` into `views/<scene>/`
/// (emptied first; OpenCV's script reads every `view_*.png` below it): the same pictures for
/// blockworld's vision and OpenCV's. Returns the (picture, camera) pairs.
fn collect_views(dataset: &Path, views: &Path) -> anyhow::Result<Vec<(PathBuf, PathBuf)>> {
    let _ = std::fs::remove_dir_all(views);
    let mut pairs = Vec::new();
    for index in 0..VISION_SCENES as u64 {
        let id = blockworld::dataset::scene_id(index);
        let to = views.join(&id);
        std::fs::create_dir_all(&to).with_context(|| format!("creating {}", to.display()))?;
        for v in CornerView::ALL {
            let files = [
                format!("view_{}.png", v.name()),
                format!("camera_{}.json", v.name()),
            ];
            for f in &files {
                let src = dataset.join(&id).join(f);
                std::fs::copy(&src, to.join(f))
                    .with_context(|| format!("copying {}", src.display()))?;
            }
            pairs.push((to.join(&files[0]), to.join(&files[1])));
        }
    }
    Ok(pairs)
}

/// Mean over the views of the vision front end's time on one thread, ms: each step's fastest
/// of [`VISION_REPEAT`] runs ([`fastest_steps`], the stage's own counters), summed, after
/// [`VISION_WARMUP`] untimed runs on the first view, with every picture read before: the
/// statistic and the warm-up of the OpenCV peer script (and the statistic of `bench vision`).
fn blockworld_vision(views: &[(PathBuf, PathBuf)]) -> anyhow::Result<f64> {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build()?;
    let opts = VisionOptions::default();
    let mut inputs = Vec::with_capacity(views.len());
    for (picture, camera) in views {
        let dirs = edge_directions(
            &read_camera(camera)?,
            &blockworld::drawing::EdgeAxis::BLOCK_AXES,
        );
        inputs.push((read_picture(picture)?, dirs));
    }
    if let Some((gray, dirs)) = inputs.first() {
        pool.install(|| fastest_steps(gray, dirs, &opts, VISION_WARMUP));
    }
    let total: f64 = inputs
        .iter()
        .map(|(gray, dirs)| {
            let (_, fastest) = pool.install(|| fastest_steps(gray, dirs, &opts, VISION_REPEAT));
            fastest.iter().sum::<f64>()
        })
        .sum();
    Ok(total / views.len().max(1) as f64)
}

/// Checks that `python` runs every peer: the interpreter exists, `peers_dir` holds the peer
/// scripts, and `imports_ok(python)` says the modules import. The error names what is missing
/// and how to install it (exit 2).
fn check_peers(
    python: &Path,
    peers_dir: &Path,
    imports_ok: &dyn Fn(&Path) -> Result<(), String>,
) -> anyhow::Result<()> {
    if !python.is_file() {
        bail!(
            "--python {}: no such interpreter; make one with {INSTALL_HINT}",
            python.display()
        );
    }
    let missing: Vec<&str> = PEER_SCRIPTS
        .into_iter()
        .filter(|s| !peers_dir.join(s).is_file())
        .collect();
    if !missing.is_empty() {
        bail!(
            "--peers-dir {}: missing {}; give the folder of the peer scripts",
            peers_dir.display(),
            missing.join(", ")
        );
    }
    imports_ok(python).map_err(|detail| {
        anyhow::anyhow!(
            "--python {} cannot import {PEER_MODULES} ({detail}); install them with {INSTALL_HINT}",
            python.display()
        )
    })
}

/// Whether `python` imports every peer module; the error is Python's last line.
fn python_imports(python: &Path) -> Result<(), String> {
    let out = Command::new(python)
        .args(["-c", &format!("import {PEER_MODULES}")])
        .output()
        .map_err(|e| e.to_string())?;
    if out.status.success() {
        return Ok(());
    }
    let stderr = String::from_utf8_lossy(&out.stderr);
    Err(stderr.lines().last().unwrap_or("no output").to_string())
}

/// Runs one peer script and returns its `RESULT` object.
fn run_peer(python: &Path, script: &Path, extra: &[String]) -> anyhow::Result<serde_json::Value> {
    let out = Command::new(python)
        .arg(script)
        .args(extra)
        .output()
        .with_context(|| format!("running {} {}", python.display(), script.display()))?;
    let stdout = String::from_utf8_lossy(&out.stdout);
    if !out.status.success() {
        let stderr = String::from_utf8_lossy(&out.stderr);
        let tail: Vec<&str> = stderr.lines().rev().take(5).collect();
        bail!(
            "{} failed ({}): {}",
            script.display(),
            out.status,
            tail.into_iter().rev().collect::<Vec<_>>().join(" | ")
        );
    }
    parse_result_line(&stdout).with_context(|| format!("output of {}", script.display()))
}

/// The JSON object of the last line `RESULT {json}` of a peer's output.
fn parse_result_line(stdout: &str) -> anyhow::Result<serde_json::Value> {
    let line = stdout
        .lines()
        .rev()
        .find_map(|l| l.trim().strip_prefix("RESULT "))
        .context("no line `RESULT {json}`")?;
    let value: serde_json::Value =
        serde_json::from_str(line).context("the RESULT line is not JSON")?;
    if !value.is_object() {
        bail!("the RESULT line holds {value}, not a JSON object");
    }
    Ok(value)
}

/// The positive number `key` of a RESULT object.
fn number(result: &serde_json::Value, key: &str) -> anyhow::Result<f64> {
    result[key]
        .as_f64()
        .filter(|v| v.is_finite() && *v > 0.0)
        .with_context(|| format!("RESULT has no positive number {key:?}: {result}"))
}

/// [`blockworld::geom::median`] of measured times; NaN when there are none.
fn median(values: &mut [f64]) -> f64 {
    blockworld::geom::median(values).unwrap_or(f64::NAN)
}

/// The table of medians, `same work | blockworld | peer | ratio | target`, and every round's
/// figures.
fn print_table(args: &Args, r: &Rounds) -> anyhow::Result<()> {
    let m = |v: &Vec<f64>| median(&mut v.clone());
    let (bw_gen, peer_gen) = (m(&r.bw_scenes_per_s), m(&r.peer_scenes_per_s));
    let (bw_one, bw_four, blender) = (
        m(&r.bw_ms_per_view),
        m(&r.bw_ms_per_view_four),
        m(&r.blender_ms_per_view),
    );
    let (bw_vis, cv) = (m(&r.bw_vision_ms), m(&r.opencv_ms));
    outln!(
        "medians of {} interleaved rounds (blockworld, then the peer, in each round)",
        r.bw_scenes_per_s.len()
    )?;
    outln!("| same work | blockworld | peer | ratio | target |")?;
    outln!("|---|---|---|---|---|")?;
    outln!(
        "| dataset, {} scenes, {} workers, four views with ground truth (scenes/s) | {bw_gen:.1} | Kubric-style (PyBullet + TinyRenderer + Pillow) {peer_gen:.2} | {:.1}x | 10x |",
        args.count, args.jobs, bw_gen / peer_gen
    )?;
    outln!(
        "| render, {RENDER_BLOCKS} blocks, ms per view (render + readback), one view per submission | {bw_one:.2} | Blender 4.2 Workbench, AA off, with its PNG write {blender:.1} | {:.1}x | 30x |",
        blender / bw_one
    )?;
    outln!(
        "| the same, four views per submission (as `generate` renders) | {bw_four:.2} | Blender 4.2 Workbench {blender:.1} | {:.1}x | 30x |",
        blender / bw_four
    )?;
    outln!(
        "| vision, ms per view, 1 thread, {} views of the dataset | {bw_vis:.2} | OpenCV Sobel + blur + threshold + HoughLinesP {cv:.2} | {:.1}x | 5x |",
        VISION_SCENES * 4,
        cv / bw_vis
    )?;
    print_rounds(args, r)
}

/// Every round's figures behind the medians of [`print_table`], and each round's ratios.
fn print_rounds(args: &Args, r: &Rounds) -> anyhow::Result<()> {
    let show = |v: &Vec<f64>| {
        v.iter()
            .map(|x| format!("{x:.2}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    outln!(
        "rounds: blockworld scenes/s {}; Kubric-style {}",
        show(&r.bw_scenes_per_s),
        show(&r.peer_scenes_per_s)
    )?;
    outln!(
        "rounds: blockworld ms/view {} (four per submission {}); Blender {}",
        show(&r.bw_ms_per_view),
        show(&r.bw_ms_per_view_four),
        show(&r.blender_ms_per_view)
    )?;
    outln!(
        "render rows: each side timed {} views after at least {:.1} s of untimed renders (`--render-warmup-s`)",
        args.render_views, args.render_warmup_s
    )?;
    let one = round_ratios(&r.blender_ms_per_view, &r.bw_ms_per_view);
    let four = round_ratios(&r.blender_ms_per_view, &r.bw_ms_per_view_four);
    outln!(
        "render ratio of each round (both sides measured back to back, so a slower phase of the machine slows both): one view per submission {} (median {:.1}x); four views per submission {} (median {:.1}x)",
        show_ratios(&one),
        median(&mut one.clone()),
        show_ratios(&four),
        median(&mut four.clone())
    )?;
    outln!(
        "rounds: blockworld vision ms/view {}; OpenCV {}",
        show(&r.bw_vision_ms),
        show(&r.opencv_ms)
    )?;
    let vision = round_ratios(&r.opencv_ms, &r.bw_vision_ms);
    outln!(
        "vision rows: each side warmed up by {VISION_WARMUP} untimed runs, then each step timed {VISION_REPEAT} times per view, the fastest of each step summed, the mean over the views; ratio of each round {} (median {:.1}x)",
        show_ratios(&vision),
        median(&mut vision.clone())
    )?;
    outln!("settle against PyBullet: `blockworld bench settle --pybullet PYTHON` (the peer stack in both, same run)")
}

/// `peer[i] / ours[i]` for each round.
fn round_ratios(peer: &[f64], ours: &[f64]) -> Vec<f64> {
    peer.iter().zip(ours).map(|(p, o)| p / o).collect()
}

fn show_ratios(ratios: &[f64]) -> String {
    ratios
        .iter()
        .map(|x| format!("{x:.1}x"))
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn result_parser_takes_the_last_result_object() {
        let out = "Fra:1 Mem:12M\nRESULT {\"scenes_per_s\": 1.0}\nnoise\nRESULT {\"scenes_per_s\": 4.56}\n";
        let v = parse_result_line(out).unwrap();
        assert_eq!(number(&v, "scenes_per_s").unwrap(), 4.56);
        assert!(number(&v, "ms_per_view_median").is_err());
    }

    #[test]
    fn result_parser_refuses_missing_or_broken_lines() {
        assert!(parse_result_line("Saved: view_ne.png\n").is_err());
        assert!(parse_result_line("RESULT {not json\n").is_err());
        assert!(parse_result_line("RESULT [1, 2]\n").is_err());
        let zero = parse_result_line("RESULT {\"scenes_per_s\": 0}").unwrap();
        assert!(
            number(&zero, "scenes_per_s").is_err(),
            "a zero rate is no result"
        );
    }

    #[test]
    fn missing_peers_are_named_with_the_install_command() {
        let dir = tempfile::tempdir().unwrap();
        let python = dir.path().join("python");
        let ok = |_: &Path| Ok(());
        let e = check_peers(&python, dir.path(), &ok)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("no such interpreter") && e.contains("make peers"),
            "{e}"
        );
        std::fs::write(&python, "").unwrap();
        std::fs::write(dir.path().join("layout.py"), "").unwrap();
        let e = check_peers(&python, dir.path(), &ok)
            .unwrap_err()
            .to_string();
        assert!(e.contains("kubric_style_bench.py, opencv_bench.py"), "{e}");
        for s in PEER_SCRIPTS {
            std::fs::write(dir.path().join(s), "").unwrap();
        }
        check_peers(&python, dir.path(), &ok).unwrap();
        let no_bpy = |_: &Path| Err("ModuleNotFoundError: No module named 'bpy'".to_string());
        let e = check_peers(&python, dir.path(), &no_bpy)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("No module named 'bpy'") && e.contains("requirements.txt"),
            "{e}"
        );
    }

    #[test]
    fn render_ratios_pair_the_sides_of_each_round() {
        let r = round_ratios(&[40.0, 50.0, 44.0], &[1.0, 2.0, 1.1]);
        assert_eq!(r.len(), 3);
        assert!((r[0] - 40.0).abs() < 1e-12 && (r[1] - 25.0).abs() < 1e-12);
        assert!((r[2] - 40.0).abs() < 1e-9);
        assert_eq!(show_ratios(&r), "40.0x, 25.0x, 40.0x");
    }

    #[test]
    fn median_of_odd_and_even_counts_is_a_measured_time() {
        assert_eq!(median(&mut [5.0, 1.0, 3.0]), 3.0);
        assert_eq!(median(&mut [4.0, 1.0, 3.0, 2.0]), 3.0);
        assert!(median(&mut []).is_nan());
    }
}
