//! `blockworld bench recognize`: milliseconds per scene (all four views) for the modified
//! Kanade recognizer as `blockworld recognize` runs it (with the pictures for its step-6 check,
//! `pipeline::recognize_rendered`), for the recognizer on the drawings alone (the thesis's
//! Chapter VI claim is about the drawings), and for the vision front end plus the recognizer
//! with pictures, median over the accuracy suite and for a 12-block stack, on one core (the
//! recognizer is single-threaded; rendering happens before the clock starts). Also the thesis's memory claim (Chapter VI,
//! Figure 6.17), measured: the bytes of the six-bit vertex table against everything else the
//! recognizer keeps for a scene.

use super::fastest_ms;
use super::machine::banner;
use super::render::bench_scene;
use crate::cli::view_args::ViewArgs;
use anyhow::Context;
use blockworld::geom::median;
use blockworld::pipeline::{observe, recognize_rendered, DrawingSource};
use blockworld::recognize::{recognize, ObservedView, Recognition, RecognizeOptions};
use blockworld::render::Renderer;
use blockworld::scene::{read_scene, Block, Scene};
use blockworld::vision::VisionOptions;
use std::path::PathBuf;

/// Options of `blockworld bench recognize`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// How the views are rendered.
    #[command(flatten)]
    pub view: Box<ViewArgs>,
    /// The suite: a directory of scene files.
    #[arg(long, default_value = "scenes/bench")]
    pub suite: PathBuf,
    /// Timed runs per scene; the fastest counts.
    #[arg(long, default_value_t = 3, value_parser = crate::cli::at_least_one::<usize>)]
    pub repeat: usize,
}

/// One scene's figures.
struct Figures {
    blocks: usize,
    /// The recognizer with the pictures, as `blockworld recognize` runs it.
    recognize_ms: f64,
    /// The recognizer on the drawings alone (no picture check).
    drawings_only_ms: f64,
    vision_ms: f64,
    six_bit_bytes: usize,
    other_bytes: usize,
}

/// The six-bit table is one byte per vertex (six bits used); everything else: the drawings'
/// points, lines and junction classes, and the recognizer's candidate and answer blocks.
fn memory_bytes(views: &[ObservedView], r: &Recognition) -> (usize, usize) {
    let vertices: usize = views.iter().map(|v| v.drawing.points.len()).sum();
    let lines: usize = views.iter().map(|v| v.drawing.lines.len()).sum();
    let drawing = vertices * (std::mem::size_of::<[f64; 2]>() + 1) + lines * 2 * 8;
    let blocks = (r.evidence.pooled_candidates + r.blocks.len()) * std::mem::size_of::<Block>();
    (vertices, drawing + blocks)
}

fn measure(renderer: &Renderer, scene: &Scene, args: &Args) -> anyhow::Result<Figures> {
    let opts = args.view.render_options()?;
    let views = args.view.corner_views()?;
    let rendered = renderer.render_views(scene, &views, &opts)?;
    let source = DrawingSource::Pictures(VisionOptions::default());
    let (vision_ms, observed) = fastest_ms(args.repeat, || {
        observe(&rendered, &source)
            .map(|(v, _)| v)
            .unwrap_or_default()
    });
    let ropts = RecognizeOptions::default();
    let (drawings_only_ms, _) = fastest_ms(args.repeat, || recognize(&observed, &ropts).ok());
    let (recognize_ms, last) = fastest_ms(args.repeat, || {
        recognize_rendered(&rendered, &observed, &source, &ropts).ok()
    });
    let r = last.context("the recognizer refused its input")?;
    let (six_bit_bytes, other_bytes) = memory_bytes(&observed, &r);
    Ok(Figures {
        blocks: scene.blocks.len(),
        recognize_ms,
        drawings_only_ms,
        vision_ms,
        six_bit_bytes,
        other_bytes,
    })
}

/// Runs `blockworld bench recognize`.
pub fn run(args: Args) -> anyhow::Result<()> {
    let renderer = Renderer::new(args.view.backend()?).context("starting the renderer")?;
    print!("{}", banner(Some(&renderer)));
    let mut paths: Vec<PathBuf> = std::fs::read_dir(&args.suite)
        .with_context(|| format!("reading the suite {}", args.suite.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .collect();
    paths.sort();
    let mut suite = Vec::new();
    for p in &paths {
        let scene = read_scene(p)?;
        suite.push(measure(&renderer, &scene, &args)?);
    }
    let twelve = measure(&renderer, &bench_scene(12), &args)?;
    println!(
        "ms per scene ({} views, fastest of {}), one core:",
        args.view.corner_views()?.len(),
        args.repeat
    );
    println!("| scenes | blocks | recognizer, drawings only | recognizer with pictures (as `recognize`) | vision + recognizer with pictures | six-bit table bytes | everything else bytes |");
    println!("|---|---|---|---|---|---|---|");
    let med = |f: &dyn Fn(&Figures) -> f64| {
        let mut values: Vec<f64> = suite.iter().map(f).collect();
        median(&mut values).unwrap_or(f64::NAN)
    };
    println!(
        "| suite median ({} scenes) | {:.0} | {:.2} | {:.2} | {:.2} | {:.0} | {:.0} |",
        suite.len(),
        med(&|f| f.blocks as f64),
        med(&|f| f.drawings_only_ms),
        med(&|f| f.recognize_ms),
        med(&|f| f.recognize_ms + f.vision_ms),
        med(&|f| f.six_bit_bytes as f64),
        med(&|f| f.other_bytes as f64),
    );
    println!(
        "| 12-block stack | {} | {:.2} | {:.2} | {:.2} | {} | {} |",
        twelve.blocks,
        twelve.drawings_only_ms,
        twelve.recognize_ms,
        twelve.recognize_ms + twelve.vision_ms,
        twelve.six_bit_bytes,
        twelve.other_bytes
    );
    Ok(())
}
