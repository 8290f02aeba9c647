//! `blockworld bench scale`: how each stage's cost grows with the number of blocks (1, 10,
//! 100, 1,000, ...): scene validation, settling (rapier3d), the pictures of one view (render and
//! readback), the exact line drawing of that view (hidden-line removal), and scoring the scene
//! against itself (parry3d volume overlap). Beside the times, the growth exponent between
//! consecutive sizes: `log(t2 / t1) / log(n2 / n1)`, 1 for linear, 2 for quadratic.

use super::fastest_ms;
use super::machine::banner;
use anyhow::Context;
use blockworld::camera::CornerView;
use blockworld::linedraw::visible_line_drawing;
use blockworld::physics::{settle, SettleParams};
use blockworld::render::{Backend, RenderOptions, Renderer};
use blockworld::scene::b15_layers;
use blockworld::scene::{Reconstruction, Scene};
use blockworld::score::score_reconstruction;

/// Options of `blockworld bench scale`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Block counts, comma separated, each 1 to 10000.
    #[arg(long, value_delimiter = ',', default_value = "1,10,100,1000")]
    pub blocks: Vec<usize>,
    /// Skip settling (rapier) for counts above this (its cost dominates first).
    #[arg(long, default_value_t = 1000)]
    pub settle_max: usize,
}

/// The largest `--blocks` entry (docs/limits.md "Benchmarks"): the stack, its pictures and its
/// line drawing are held in memory and every stage runs once per entry; `render`'s bound,
/// [`blockworld::render::MAX_RENDER_BLOCKS`].
pub const MAX_BLOCKS: usize = blockworld::render::MAX_RENDER_BLOCKS;

/// `n` Baustein 15 in a cube-like stack: layers of k x k, k the cube root of `n` rounded up.
pub fn grid_stack(n: usize) -> Scene {
    let k = (1..).find(|k| k * k * k >= n).unwrap_or(1);
    b15_layers(n, k, format!("grid_{n}"))
}

/// One row: ms per stage (`None` = skipped).
struct Row {
    blocks: usize,
    ms: [Option<f64>; 5],
}

fn measure(renderer: &Renderer, n: usize, args: &Args) -> anyhow::Result<Row> {
    let scene = grid_stack(n);
    let (validate, ok) = fastest_ms(1, || scene.validate(&scene.name));
    ok.context("the grid stack is valid")?;
    let settle_ms = if n <= args.settle_max {
        let (ms, settled) = fastest_ms(1, || settle(&scene, &SettleParams::default()));
        settled.context("settling the grid stack")?;
        Some(ms)
    } else {
        None
    };
    let opts = RenderOptions::default();
    let (pixels, rendered) =
        fastest_ms(1, || renderer.render_pixels(&scene, CornerView::Ne, &opts));
    let rendered = rendered.context("rendering the grid stack")?;
    let (drawing, _) = fastest_ms(1, || visible_line_drawing(&scene, &rendered.camera));
    let recon = Reconstruction::ok(scene.name.clone(), scene.blocks.clone());
    let (score, s) = fastest_ms(1, || score_reconstruction(&scene, &recon));
    s.context("scoring the grid stack against itself")?;
    Ok(Row {
        blocks: n,
        ms: [
            Some(validate),
            settle_ms,
            Some(pixels),
            Some(drawing),
            Some(score),
        ],
    })
}

fn cell(v: Option<f64>) -> String {
    v.map_or("—".to_string(), |ms| format!("{ms:.1}"))
}

/// The growth exponent of `t` from `a` to `b` blocks.
fn exponent(a: (usize, Option<f64>), b: (usize, Option<f64>)) -> String {
    match (a.1, b.1) {
        (Some(ta), Some(tb)) if ta > 0.0 && tb > 0.0 && b.0 > a.0 => {
            format!("{:.2}", (tb / ta).ln() / (b.0 as f64 / a.0 as f64).ln())
        }
        _ => "—".to_string(),
    }
}

/// Runs `blockworld bench scale`.
pub fn run(args: Args) -> anyhow::Result<()> {
    super::check_block_counts(
        "blocks",
        &args.blocks,
        MAX_BLOCKS,
        "each stack is built, settled, rendered, drawn and scored in memory",
    )?;
    let renderer = Renderer::new(Backend::Vulkan).context("starting the renderer")?;
    outln!("{}", banner(Some(&renderer)).trim_end())?;
    outln!("ms per stage for a cube-like stack of n b15 (one view, 512 x 480, one run each); growth exponent to the row above in brackets")?;
    outln!("| blocks | validate | settle | pixels (render + readback) | exact line drawing | score (IoU against itself) |")?;
    outln!("|---|---|---|---|---|---|")?;
    // One untimed render first: the device's first frame compiles its pipelines.
    renderer
        .render_pixels(&grid_stack(1), CornerView::Ne, &RenderOptions::default())
        .context("warming up the renderer")?;
    let mut last: Option<Row> = None;
    for &n in &args.blocks {
        let row = measure(&renderer, n, &args)?;
        let cols: Vec<String> = (0..5)
            .map(|s| {
                let growth = last.as_ref().map_or(String::new(), |l| {
                    format!(
                        " ({})",
                        exponent((l.blocks, l.ms[s]), (row.blocks, row.ms[s]))
                    )
                });
                format!("{}{growth}", cell(row.ms[s]))
            })
            .collect();
        outln!("| {n} | {} |", cols.join(" | "))?;
        last = Some(row);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_stacks_are_valid_and_have_the_asked_count() {
        for n in [1, 10, 27, 28] {
            let s = grid_stack(n);
            assert_eq!(s.blocks.len(), n);
            s.validate("grid").unwrap();
        }
        assert_eq!(exponent((10, Some(1.0)), (100, Some(100.0))), "2.00");
        assert_eq!(exponent((10, Some(1.0)), (100, None)), "—");
    }
}
