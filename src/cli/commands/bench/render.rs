//! `blockworld bench render`: ms per view for scenes of 1, 10 and 50 blocks at 512 x 480
//! (docs/rendering.md "Rendering" target: at most 2 ms per view for 10 blocks on a 2-core machine with lavapipe).
//! Columns: render + readback (pixels only) one view per submission, the same with the four
//! corner views in one submission (`Renderer::render_views_pixels`, as `generate` renders; time
//! per view), the one-view render plus the exact line drawing (`Renderer::render`), render +
//! readback + PNG encoding of the three images, and the photo look's render + readback (docs/rendering.md
//! "Photographic look"; a quarter of the iterations) with its ratio to line art's.
//! `--photo-only` times the photo look alone (after four untimed views), so a profiler such as
//! callgrind counts nothing else; `--photo-parts` times the photo look part by part (its mesh,
//! its radiance without shadows, with the ground truth, with the shadows, then the whole view);
//! `--blocks` picks the scene sizes.

use anyhow::Context;
use blockworld::camera::CornerView;
use blockworld::output::{encode_png_depth, encode_png_gray8, encode_png_ids};
use blockworld::render::{Backend, RenderOptions, Renderer};
use blockworld::scene::{b15_layers, Scene};
use std::time::{Duration, Instant};

/// Options of `blockworld bench render`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Timed renders per scene (spread over the four views, at least 4), after 32 untimed
    /// warm-up renders.
    #[arg(long, default_value_t = 200)]
    pub iterations: usize,
    /// Graphics backend: vulkan (lavapipe, default) or gl (llvmpipe through EGL).
    #[arg(long, default_value = "vulkan")]
    pub backend: String,
    /// Multisample count, 1 or 4.
    #[arg(long, default_value_t = 1)]
    pub msaa: u32,
    /// Scene sizes, blocks (comma-separated, each 1 to 1000; `b15_layers` stacks of Baustein 15).
    #[arg(long, value_delimiter = ',', default_values_t = [1, 10, 50])]
    pub blocks: Vec<usize>,
    /// Time only the photo look: four untimed views, then a quarter of `--iterations` timed
    /// (for profiling it alone, e.g. `valgrind --tool=callgrind`).
    #[arg(long, conflicts_with = "photo_parts")]
    pub photo_only: bool,
    /// Time the photo look part by part against line art (docs/rendering.md "Photographic look"): the
    /// render mesh alone (CPU), the radiance without shadows or sensor, that plus the
    /// ground-truth draw, plus the shadows, and the whole view; a quarter of `--iterations`
    /// each.
    #[arg(long)]
    pub photo_parts: bool,
}

/// The largest `--blocks` entry (docs/limits.md "Benchmarks").
pub const MAX_BLOCKS: usize = 1000;

/// `n` Baustein 15 in layers of a 3 x 3 square, touching (so every view shows seams).
pub fn bench_scene(n: usize) -> Scene {
    b15_layers(n, 3, format!("bench_{n}"))
}

/// Runs `blockworld bench render`.
pub fn run(args: Args) -> anyhow::Result<()> {
    let backend = match args.backend.to_ascii_lowercase().as_str() {
        "vulkan" | "vk" => Backend::Vulkan,
        "gl" | "gles" => Backend::Gl,
        other => anyhow::bail!("--backend: unknown backend {other:?}; use vulkan or gl"),
    };
    let opts = RenderOptions {
        msaa: args.msaa,
        ..Default::default()
    };
    if args.iterations < 4 {
        anyhow::bail!(
            "--iterations {}: give at least 4 timed renders per scene, one per view",
            args.iterations
        );
    }
    let iterations = args.iterations;
    super::check_block_counts(
        "blocks",
        &args.blocks,
        MAX_BLOCKS,
        "each size is rendered --iterations times",
    )?;
    let start = Instant::now();
    let renderer = Renderer::new(backend).context("starting the renderer")?;
    let setup = start.elapsed();
    outln!("{}", super::machine::banner(Some(&renderer)).trim_end())?;
    outln!(
        "device setup (instance + adapter + device + pipelines): {:.1} ms",
        ms(setup)
    )?;
    outln!(
        "{} x {}, msaa {}, {iterations} timed renders per scene over the four views (each cell: median / mean wall ms / CPU ms per view)",
        opts.camera.size_px[0], opts.camera.size_px[1], opts.msaa
    )?;
    let photo = RenderOptions {
        look: blockworld::render::Look::Photo,
        ..opts
    };
    print_table_header(&args)?;
    for &n in &args.blocks {
        let scene = bench_scene(n);
        scene
            .validate(&scene.name)
            .context("the benchmark scene is invalid")?;
        if args.photo_only {
            let photo_pixels = time_photo(&renderer, &scene, &photo, iterations)?;
            outln!("| {n} | {} |", photo_pixels.show())?;
            continue;
        }
        if args.photo_parts {
            outln!(
                "{}",
                photo_parts_row(&renderer, &scene, &opts, &photo, iterations)?
            )?;
            continue;
        }
        outln!(
            "{}",
            line_art_row(n, &renderer, &scene, &opts, &photo, iterations)?
        )?;
    }
    Ok(())
}

/// The table's header for the chosen mode (`--photo-only`, `--photo-parts` or the default).
fn print_table_header(args: &Args) -> anyhow::Result<()> {
    if args.photo_only {
        outln!("| blocks | photo look: render + readback |")?;
        outln!("|---|---|")?;
    } else if args.photo_parts {
        outln!("| blocks | line art: render + readback | photo mesh (CPU; triangles) | radiance without shadows or sensor | + ground truth | + shadows | the photo view (+ sensor and mesh) | mesh + radiance + ground truth / line art | photo / line art |")?;
        outln!("|---|---|---|---|---|---|---|---|---|")?;
    } else {
        outln!("| blocks | render + readback | four views per submission | + line drawing | render + readback + 3 PNG encodes | photo look: render + readback | photo / line art |")?;
        outln!("|---|---|---|---|---|---|---|")?;
    }
    Ok(())
}

/// The default table's row of one scene: 32 untimed warm-up views, then the line-art columns,
/// the PNG encodes and the photo look, each `iterations` times.
fn line_art_row(
    n: usize,
    renderer: &Renderer,
    scene: &Scene,
    opts: &RenderOptions,
    photo: &RenderOptions,
    iterations: usize,
) -> anyhow::Result<String> {
    for k in 0..32 {
        renderer.render_pixels(scene, CornerView::ALL[k % 4], opts)?;
    }
    let pixels = time_views(iterations, |view| {
        renderer.render_pixels(scene, view, opts).map(|_| ())
    })?;
    let four = time_four_views(iterations, || {
        renderer
            .render_views_pixels(scene, &CornerView::ALL, opts)
            .map(|_| ())
    })?;
    let full = time_views(iterations, |view| {
        renderer.render(scene, view, opts).map(|_| ())
    })?;
    let mut encode_error = None;
    let png = time_views(iterations, |view| {
        let v = renderer.render_pixels(scene, view, opts)?;
        let encoded = encode_png_gray8(&v.gray)
            .and_then(|_| encode_png_depth(&v.depth))
            .and_then(|_| encode_png_ids(&v.ids));
        if let Err(e) = encoded {
            encode_error = Some(e);
        }
        Ok(())
    })?;
    if let Some(e) = encode_error {
        return Err(e).context("encoding PNGs");
    }
    let photo_pixels = time_photo(renderer, scene, photo, iterations)?;
    Ok(format!(
        "| {n} | {} | {} | {} | {} | {} | {:.1} x |",
        pixels.show(),
        four.show(),
        full.show(),
        png.show(),
        photo_pixels.show(),
        ms(photo_pixels.median) / ms(pixels.median).max(1e-9)
    ))
}

/// The photo look's column: four untimed views, then a quarter of `iterations` (at least
/// four) timed.
fn time_photo(
    renderer: &Renderer,
    scene: &Scene,
    photo: &RenderOptions,
    iterations: usize,
) -> anyhow::Result<Timing> {
    time_warm(iterations.div_ceil(4).max(4), |view| {
        renderer.render_pixels(scene, view, photo).map(|_| ())
    })
}

/// One row of `--photo-parts`: line art's view, then the photo look's parts, each timed over
/// a quarter of `iterations` (at least four) after four untimed views; the mesh and setups of
/// the four views are built before the parts that take them are timed.
fn photo_parts_row(
    renderer: &Renderer,
    scene: &Scene,
    line_art: &RenderOptions,
    photo: &RenderOptions,
    iterations: usize,
) -> anyhow::Result<String> {
    use blockworld::render::photo::{PhotoParts, PhotoSetup};
    let quarter = iterations.div_ceil(4).max(4);
    let line = time_warm(quarter, |view| {
        renderer.render_pixels(scene, view, line_art).map(|_| ())
    })?;
    let setups = CornerView::ALL.map(|v| PhotoSetup::new(scene, v, photo));
    let bare = setups.clone().map(|s| s.without_shadows());
    let mesh = time_warm(quarter, |view| {
        std::hint::black_box(PhotoSetup::new(scene, view, photo));
        Ok(())
    })?;
    let part = |setups: &[PhotoSetup; 4], truth: bool| {
        let parts = PhotoParts {
            sensor: false,
            truth,
        };
        time_warm(quarter, |view| {
            renderer
                .render_photo_parts(scene, view, photo, &setups[view.index()], parts)
                .map(|_| ())
        })
    };
    let radiance = part(&bare, false)?;
    let truth = part(&bare, true)?;
    let shadows = part(&setups, true)?;
    let whole = time_photo(renderer, scene, photo, iterations)?;
    let triangles = setups.iter().map(PhotoSetup::triangles).sum::<usize>() / 4;
    let per_line = |t: Duration| ms(t) / ms(line.median).max(1e-9);
    Ok(format!(
        "| {} | {} | {} ({triangles}) | {} | {} | {} | {} | {:.1} x | {:.1} x |",
        scene.blocks.len(),
        line.show(),
        mesh.show(),
        radiance.show(),
        truth.show(),
        shadows.show(),
        whole.show(),
        per_line(mesh.median + truth.median),
        per_line(whole.median),
    ))
}

/// [`time_views`] after four untimed calls (one per corner view).
fn time_warm(
    iterations: usize,
    mut f: impl FnMut(CornerView) -> Result<(), blockworld::render::RenderError>,
) -> anyhow::Result<Timing> {
    for view in CornerView::ALL {
        f(view)?;
    }
    time_views(iterations, f)
}

/// Median and mean wall time per view, and the process's CPU time per view (all threads,
/// lavapipe's rasterizer threads included).
struct Timing {
    median: Duration,
    mean: Duration,
    cpu: Option<Duration>,
}

impl Timing {
    /// The timing of `times` (one per call, at least one), with the process's CPU time since
    /// `cpu_start` shared over the `views` rendered.
    fn of(mut times: Vec<Duration>, cpu_start: Option<Duration>, views: usize) -> Timing {
        let cpu = process_cpu_time()
            .zip(cpu_start)
            .map(|(end, start)| end.saturating_sub(start) / views as u32);
        let mean = times.iter().sum::<Duration>() / times.len() as u32;
        times.sort();
        Timing {
            median: times[times.len() / 2],
            mean,
            cpu,
        }
    }

    fn show(&self) -> String {
        let cpu = self
            .cpu
            .map(|c| format!("{:.2}", ms(c)))
            .unwrap_or_else(|| "?".into());
        format!("{:.3} / {:.3} / {cpu}", ms(self.median), ms(self.mean))
    }
}

/// User + system CPU time of this process so far, from `/proc/self/stat` (Linux; clock ticks of
/// 10 ms, the kernel's USER_HZ = 100 on Linux).
fn process_cpu_time() -> Option<Duration> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // Fields after the command name in parentheses; utime and stime are fields 14 and 15.
    let rest = &stat[stat.rfind(')')? + 2..];
    let fields: Vec<&str> = rest.split_whitespace().collect();
    let ticks: u64 = fields.get(11)?.parse::<u64>().ok()? + fields.get(12)?.parse::<u64>().ok()?;
    Some(Duration::from_millis(ticks * 10))
}

fn time_views(
    iterations: usize,
    mut f: impl FnMut(CornerView) -> Result<(), blockworld::render::RenderError>,
) -> anyhow::Result<Timing> {
    let mut times = Vec::with_capacity(iterations);
    let cpu_start = process_cpu_time();
    for k in 0..iterations {
        let t = Instant::now();
        f(CornerView::ALL[k % 4])?;
        times.push(t.elapsed());
    }
    Ok(Timing::of(times, cpu_start, iterations))
}

/// [`time_views`] for a call that renders all four corner views at once: `iterations` views
/// (rounded up to whole calls), each call's time divided by four.
fn time_four_views(
    iterations: usize,
    mut f: impl FnMut() -> Result<(), blockworld::render::RenderError>,
) -> anyhow::Result<Timing> {
    let views = CornerView::ALL.len();
    let mut times = Vec::with_capacity(iterations.div_ceil(views));
    let cpu_start = process_cpu_time();
    for _ in 0..iterations.div_ceil(views) {
        let t = Instant::now();
        f()?;
        times.push(t.elapsed() / views as u32);
    }
    let rendered = times.len() * views;
    Ok(Timing::of(times, cpu_start, rendered))
}

fn ms(d: Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bench_scenes_are_valid_stacks_of_the_asked_size() {
        for n in [1, 10, 50] {
            let s = bench_scene(n);
            assert_eq!(s.blocks.len(), n);
            s.validate("bench").unwrap();
        }
        let top = bench_scene(50).bounds_mm().unwrap().1;
        assert_eq!(top.y, 6.0 * 15.0, "50 blocks make 6 layers");
    }
}
