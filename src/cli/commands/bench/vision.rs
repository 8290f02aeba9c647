//! `blockworld bench vision`: the vision front end (docs/vision.md "Vision front end") measured against exact ground
//! truth. Renders the accuracy-suite scenes (`scenes/bench/*.json`, else `scenes/*.json`) in the
//! four corner views with the real renderer (or reads already rendered views with `--from`),
//! runs Sobel + smoothing + threshold, lines and vertices on one core, matches the vertices to
//! the `lines` points within 2 px, and prints per family and overall: vertex precision and
//! recall, six-bit code accuracy of matched vertices, line angle error, and ms per view per step.

use crate::cli::files::{read_camera, read_drawing, read_picture};
use anyhow::{bail, Context};
use blockworld::camera::{Camera, CornerView};
use blockworld::drawing::{EdgeAxis, LineDrawing};
use blockworld::render::{Backend, Look, RenderOptions, Renderer};
use blockworld::vision::{
    detect_with_directions, edge_directions, line_angle_errors_deg, match_vertices_with_tolerances,
    Detection, EdgeDirection, MatchTolerances, VertexMatch, VisionOptions,
};
use image::GrayImage;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Options of `blockworld bench vision`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Gaussian sensor noise of the renders, standard deviation in gray levels.
    #[arg(long, default_value_t = 0.0)]
    pub noise: f64,
    /// Seed of the noise.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Folder of scene files (default scenes/bench if it exists, else scenes).
    #[arg(long)]
    pub suite: Option<PathBuf>,
    /// Read rendered views (view_<v>.png, camera_<v>.json, lines_<v>.json, searched
    /// recursively; the family is the folder name) instead of rendering.
    #[arg(long, conflicts_with = "suite")]
    pub from: Option<PathBuf>,
    /// Render with a perspective camera of this vertical field of view, degrees (default:
    /// orthographic, the target setting of docs/vision.md "Vision front end").
    #[arg(long)]
    pub perspective: Option<f64>,
    /// Matching distance, px.
    #[arg(long, default_value_t = 2.0)]
    pub match_px: f64,
    /// Repeat each view's steps this many times and keep the fastest (timing only).
    #[arg(long, default_value_t = 3, value_parser = crate::cli::at_least_one::<u32>)]
    pub repeat: u32,
    /// Instead of the suite: the front end's time per megapixel on pictures as dense in edges
    /// as it accepts, from 512 px up to --max-side (docs/vision.md "Vision front end").
    #[arg(long)]
    pub scaling: bool,
    /// Largest side of --scaling, px.
    #[arg(long, default_value_t = 4096)]
    pub max_side: u32,
    /// Picture look of the renders: lineart (default) or photo (docs/rendering.md "Photographic look").
    #[arg(long, default_value = "lineart")]
    pub look: String,
    /// Average the renders 2x2 once (2) or twice (4), as the thesis did.
    #[arg(long, default_value_t = 1)]
    pub downsample: u32,
    /// Photo look: largest turn of the key light per scene, degrees.
    #[arg(long, default_value_t = 0.0)]
    pub light_jitter: f64,
}

/// One view to measure.
struct Sample {
    family: String,
    /// `false` for scenes marked `expect.supported: false` (Ch. VII cases).
    supported: bool,
    gray: GrayImage,
    camera: Camera,
    truth: LineDrawing,
}

/// Sums over the views of a family.
#[derive(Default)]
struct Tally {
    views: usize,
    truth: usize,
    found: usize,
    matched: usize,
    codes_equal: usize,
    angles: Vec<f64>,
    distances_px: Vec<f64>,
    ms: [f64; 3],
}

impl Tally {
    /// Adds one view: its vertex match, line angle errors and ms per step.
    fn add(&mut self, m: &VertexMatch, angles: &[f64], ms: [f64; 3]) {
        self.views += 1;
        self.truth += m.truth;
        self.found += m.found;
        self.matched += m.pairs.len();
        self.codes_equal += m.codes_equal;
        self.angles.extend(angles);
        self.distances_px.extend(&m.distances_px);
        for (a, b) in self.ms.iter_mut().zip(ms) {
            *a += b;
        }
    }
}

/// Runs `blockworld bench vision`.
pub fn run(args: Args) -> anyhow::Result<()> {
    let m = args.match_px;
    crate::cli::check_number("--match-px", m, m > 0.0, "use a positive distance in px")?;
    if args.scaling {
        return super::vision_scaling::run(args.max_side, args.repeat);
    }
    let samples = match &args.from {
        Some(dir) => read_views(dir)?,
        None => render_suite(&args)?,
    };
    if samples.is_empty() {
        bail!("no views to measure");
    }
    let opts = VisionOptions::default();
    let tol = MatchTolerances {
        distance_px: args.match_px,
        ..Default::default()
    };
    let mut families: BTreeMap<String, Tally> = BTreeMap::new();
    let mut all = Tally::default();
    let mut supported = Tally::default();
    for s in &samples {
        let (drawing, lines, ms) = timed_steps(s, &opts, args.repeat);
        let m = match_vertices_with_tolerances(&drawing, &s.truth, &tol);
        let angles = line_angle_errors_deg(&lines, &s.truth, &tol);
        let mut tallies = vec![families.entry(s.family.clone()).or_default(), &mut all];
        if s.supported {
            tallies.push(&mut supported);
        }
        for t in tallies {
            t.add(&m, &angles, ms);
        }
    }
    print_header(&args, all.views)?;
    for (name, t) in &families {
        print_row(name, t)?;
    }
    print_row("ALL", &all)?;
    if supported.views != all.views {
        print_row("ALL supported", &supported)?;
    }
    outln!(
        "(vtx_px: mean distance of matched vertices, px; ms per view per step, fastest of --repeat; angle error in degrees over fitted lines with a true counterpart)"
    )?;
    Ok(())
}

/// The machine banner, the run's settings over `views` views and the table's column names.
fn print_header(args: &Args, views: usize) -> anyhow::Result<()> {
    outln!("{}", super::machine::banner(None).trim_end())?;
    outln!(
        "vision front end vs ground truth: {} views, {}, noise sigma {}, match within {} px, one core",
        views,
        match args.perspective {
            Some(f) => format!("perspective {f} deg"),
            None => "orthographic".to_string(),
        },
        args.noise,
        args.match_px
    )?;
    outln!(
        "{:<22} {:>5} {:>6} {:>6} {:>6} {:>6} {:>6} {:>7} {:>8} {:>8} {:>6} {:>6} {:>6} {:>6}",
        "family",
        "views",
        "truth",
        "found",
        "prec",
        "recall",
        "code",
        "vtx_px",
        "ang_mean",
        "ang_max",
        "edges",
        "lines",
        "verts",
        "total"
    )?;
    Ok(())
}

fn print_row(name: &str, t: &Tally) -> anyhow::Result<()> {
    let r = |a: usize, b: usize| if b == 0 { 1.0 } else { a as f64 / b as f64 };
    let mean = t.angles.iter().sum::<f64>() / t.angles.len().max(1) as f64;
    let max = t.angles.iter().cloned().fold(0.0, f64::max);
    let v = t.views.max(1) as f64;
    let ms: Vec<f64> = t.ms.iter().map(|x| x / v).collect();
    outln!(
        "{:<22} {:>5} {:>6} {:>6} {:>6.3} {:>6.3} {:>6.3} {:>7.3} {:>8.3} {:>8.3} {:>6.3} {:>6.3} {:>6.3} {:>6.3}",
        name,
        t.views,
        t.truth,
        t.found,
        r(t.matched, t.found),
        r(t.matched, t.truth),
        r(t.codes_equal, t.matched),
        t.distances_px.iter().sum::<f64>() / t.distances_px.len().max(1) as f64,
        mean,
        max,
        ms[0],
        ms[1],
        ms[2],
        ms.iter().sum::<f64>()
    )
}

/// Runs the front end `repeat` times; per step the fastest of the stage's own counters.
fn timed_steps(
    s: &Sample,
    opts: &VisionOptions,
    repeat: u32,
) -> (LineDrawing, Vec<blockworld::vision::FittedLine>, [f64; 3]) {
    let dirs = edge_directions(&s.camera, &blockworld::drawing::EdgeAxis::BLOCK_AXES);
    let (det, best) = fastest_steps(&s.gray, &dirs, opts, repeat as usize);
    (det.drawing, det.lines, best)
}

/// Runs the front end on `gray` `repeat` times (at least once): the last detection and, per
/// step, the fastest of the stage's own counters, ms. The statistic of `bench vision`, of `bench
/// peers` and of the OpenCV peer script (docs/benchmarks.md "Peers").
pub(super) fn fastest_steps(
    gray: &GrayImage,
    dirs: &[(EdgeAxis, EdgeDirection)],
    opts: &VisionOptions,
    repeat: usize,
) -> (Detection, [f64; 3]) {
    let mut det = detect_with_directions(gray, dirs, opts);
    let mut best = det.timings.steps_ms();
    for _ in 1..repeat {
        det = detect_with_directions(gray, dirs, opts);
        for (b, m) in best.iter_mut().zip(det.timings.steps_ms()) {
            *b = b.min(m);
        }
    }
    (det, best)
}

fn render_suite(args: &Args) -> anyhow::Result<Vec<Sample>> {
    let dir = match &args.suite {
        Some(d) => d.clone(),
        None if Path::new("scenes/bench").is_dir() => PathBuf::from("scenes/bench"),
        None => PathBuf::from("scenes"),
    };
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .with_context(|| format!("reading the suite folder {}", dir.display()))?
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .collect();
    files.sort();
    if files.is_empty() {
        bail!(
            "{}: no scene files (*.json); pass --suite DIR or --from DIR",
            dir.display()
        );
    }
    let renderer = Renderer::new(Backend::Vulkan).context("creating the renderer (bench vision renders the suite; or pass --from DIR with rendered views)")?;
    let mut opts = RenderOptions {
        noise_sigma: args.noise,
        seed: args.seed,
        look: Look::parse(&args.look)
            .with_context(|| format!("--look: unknown {:?}; use lineart or photo", args.look))?,
        downsample: args.downsample,
        ..Default::default()
    };
    opts.photo.light_jitter_deg = args.light_jitter;
    if let Some(fov_y_deg) = args.perspective {
        if !(1.0..=170.0).contains(&fov_y_deg) {
            bail!(
                "--perspective {} is out of range; use 1..=170 degrees",
                blockworld::io::echo_number(fov_y_deg)
            );
        }
        opts.camera.projection = blockworld::camera::Projection::Perspective { fov_y_deg };
    }
    let mut out = Vec::new();
    for f in files {
        let scene = blockworld::scene::read_scene(&f)?;
        let family = scene
            .meta
            .as_ref()
            .and_then(|m| m.get("family"))
            .and_then(|v| v.as_str())
            .map(str::to_string)
            .unwrap_or_else(|| scene.name.clone());
        for v in renderer
            .render_views(&scene, &CornerView::ALL, &opts)
            .with_context(|| format!("rendering {}", f.display()))?
        {
            out.push(Sample {
                family: family.clone(),
                supported: scene.expect.as_ref().is_none_or(|e| e.supported),
                gray: v.gray,
                camera: v.camera,
                truth: v.lines,
            });
        }
    }
    Ok(out)
}

fn read_views(dir: &Path) -> anyhow::Result<Vec<Sample>> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        let mut entries: Vec<PathBuf> = std::fs::read_dir(&d)
            .with_context(|| format!("reading {}", d.display()))?
            .flatten()
            .map(|e| e.path())
            .collect();
        entries.sort();
        for p in entries {
            if p.is_dir() {
                stack.push(p);
                continue;
            }
            let name = p
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            let Some(view) = name
                .strip_prefix("view_")
                .and_then(|n| n.strip_suffix(".png"))
            else {
                continue;
            };
            let camera = read_camera(&d.join(format!("camera_{view}.json")))?;
            let lines_path = d.join(format!("lines_{view}.json"));
            let truth = read_drawing(&lines_path)?;
            let family = d
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            out.push(Sample {
                family,
                supported: true,
                gray: read_picture(&p)?,
                camera,
                truth,
            });
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use blockworld::vision::isometric_edge_directions;

    /// A light square on a dark ground: edges and lines for the front end to find.
    fn square() -> GrayImage {
        GrayImage::from_fn(96, 80, |x, y| {
            let inside = (30..66).contains(&x) && (20..60).contains(&y);
            image::Luma([if inside { 200 } else { 40 }])
        })
    }

    /// The timed runs detect what one untimed run detects, and each step's figure is the
    /// fastest of real timings (finite, not negative), also when asked for no repeat at all.
    #[test]
    fn fastest_steps_time_the_same_detection_per_step() {
        let (gray, dirs) = (square(), isometric_edge_directions());
        let opts = VisionOptions::default();
        let once = detect_with_directions(&gray, &dirs, &opts);
        assert!(!once.lines.is_empty(), "the square gives lines");
        for repeat in [0, 1, 3] {
            let (det, best) = fastest_steps(&gray, &dirs, &opts, repeat);
            assert_eq!(det.lines, once.lines, "repeat {repeat}");
            assert!(
                best.iter().all(|ms| ms.is_finite() && *ms >= 0.0),
                "{best:?}"
            );
        }
    }
}
