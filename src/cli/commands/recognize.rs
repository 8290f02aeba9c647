//! `blockworld recognize DIR -o RECON.json [--views ne,se,sw,nw] [--from-truth]`: the modified
//! Kanade recognizer (thesis Chapters IV-V) on a directory as `render` writes it, per view
//! `view_<v>.png` + `camera_<v>.json` (or the exact `lines_<v>.json` with `--from-truth`), and
//! the lights a `look.json` beside them records.
//! An answer must stand (`pipeline::recognize_standing`: settled with rapier, declined when a
//! block would move). Writes a reconstruction file: the scene-file blocks plus `status`, `reason` and the CSG tree
//! (Figure 4.6).

use crate::cli::files::{read_camera, read_drawing, read_picture, read_recorded_look};
use crate::cli::progress::with_progress;
use anyhow::Context;
use blockworld::camera::CornerView;
use blockworld::csg::reconstruction;
use blockworld::pipeline::answer_of_pictures;
use blockworld::recognize::{
    recognize_with_progress, ObservedView, Recognition, RecognizeOptions, SearchProgress,
};
use blockworld::render::photo::varied::LOOK_FILE;
use blockworld::scene::reconstruction_to_json;
use blockworld::vision::{
    detect_line_drawing, detect_line_drawing_with_progress, VisionOptions, VISION_STEPS,
};
use std::path::{Path, PathBuf};

/// Options of `blockworld recognize`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Directory with `camera_<v>.json` and `view_<v>.png` (or `lines_<v>.json`) per view; a
    /// `look.json` beside them gives the lights that lit each view (its
    /// `views.<v>[].towards_light`), so that the edges of the shadows an answer casts are
    /// told from block edges, and the blocks' edge radius (`edge_radius_mm`), so that their
    /// rounded outlines place them (docs/recognizer-pictures.md "Known lights", "Known edge
    /// rounding").
    pub dir: PathBuf,
    /// The reconstruction file to write.
    #[arg(short, long)]
    pub output: PathBuf,
    /// The views and where their drawings come from.
    #[command(flatten)]
    pub source: SourceArgs,
    /// Also write the thesis's intermediate files here: the six-bit analysis of every vertex
    /// (Figure A.6), the parallelogram search results, the layer table, and one overlay PNG per
    /// view with the answer's drawing over the picture.
    #[arg(long, value_name = "D")]
    pub debug_dir: Option<PathBuf>,
    /// Stop the search for blocks after this many nodes (candidates weighed) and answer
    /// `unsupported`, naming the budget; the suites' scenes need far fewer.
    #[arg(long, default_value_t = RecognizeOptions::default().node_budget)]
    pub node_budget: u64,
    /// Stop the search for blocks after this many seconds (more than 0, at most 1000000) and
    /// answer `unsupported`, naming the budget (the node budget, the same on every machine,
    /// usually ends it first).
    #[arg(long, default_value_t = RecognizeOptions::default().time_budget_s)]
    pub time_budget_s: f64,
    /// What the recognizer is told of the world.
    #[command(flatten)]
    pub world: WorldArgs,
    /// The recording holds the reconstruction beside the truth when the folder has a
    /// `scene.json` (a dataset's scene folder does), the views the recognizer read, and the
    /// drawings it recognized from.
    #[command(flatten)]
    pub rrd: crate::cli::rrd::RrdArgs,
}

/// The search's progress on stderr, at most once a second once it has run for one: a search
/// that takes seconds shows it is alive and how much of its budget it has spent.
fn search_progress() -> impl Fn(SearchProgress) {
    let last = std::cell::Cell::new(std::time::Instant::now());
    move |p: SearchProgress| {
        if last.get().elapsed().as_secs_f64() >= 1.0 {
            eprintln!(
                "recognize: search, {} of {} nodes, {:.1} of {} s",
                p.nodes, p.node_budget, p.elapsed_s, p.time_budget_s
            );
            last.set(std::time::Instant::now());
        }
    }
}

/// Which views the recognizer reads and where their drawings come from (`recognize` and
/// `recognize-dataset`).
#[derive(Debug, clap::Args)]
pub struct SourceArgs {
    /// Comma-separated corner views to use (any subset, e.g. `ne,sw`).
    #[arg(long, value_delimiter = ',', default_value = "ne,se,sw,nw")]
    pub views: Vec<String>,
    /// Read the exact line drawings `lines_<v>.json` instead of running the vision front end
    /// on `view_<v>.png`.
    #[arg(long)]
    pub from_truth: bool,
}

/// What the recognizer is told of the world the pictures show (`recognize`,
/// `recognize-dataset`, `bench accuracy`).
#[derive(Debug, Clone, Copy, clap::Args)]
pub struct WorldArgs {
    /// The blocks stand on a grid of this pitch, mm: every block's least x and z a multiple
    /// of it in the cameras' world frame (7.5: the Fischer-Technik grid on which `generate`'s
    /// supported families put every block). Each block is then put on its nearest grid place
    /// (docs/recognizer-pictures.md "Blocks on a known grid"). More than 4, at most 1000.
    #[arg(long, value_name = "MM")]
    pub grid_mm: Option<f64>,
}

impl WorldArgs {
    /// The grid's pitch, checked: more than four times `recognize::GRID_SNAP_MM` (the
    /// nearest grid place is never in doubt) and at most 1000 mm; exit 2 naming the flag.
    pub fn grid_mm(&self) -> anyhow::Result<Option<f64>> {
        if let Some(mm) = self.grid_mm {
            let ok = mm > 4.0 * blockworld::recognize::GRID_SNAP_MM && mm <= 1000.0;
            let takes = "give the grid's pitch in mm, more than 4 and at most 1000 (7.5 for the Fischer-Technik grid)";
            crate::cli::check_number("--grid-mm", mm, ok, takes)?;
        }
        Ok(self.grid_mm)
    }
}

/// Reads one view of `dir`: its camera and its drawing (exact, or from the picture, which is
/// then returned too for step 6's picture-aware check); `shown` shows the vision front end's
/// progress (one scene), or not (a dataset's scenes in parallel).
pub(super) fn read_view(
    dir: &Path,
    view: CornerView,
    from_truth: bool,
    shown: bool,
) -> anyhow::Result<(ObservedView, Option<image::GrayImage>)> {
    let v = view.name();
    let camera_path = dir.join(format!("camera_{v}.json"));
    if !camera_path.exists() {
        anyhow::bail!(
            "{}: missing; every view needs its camera (render the directory with `blockworld render`, or drop {v} from --views)",
            camera_path.display()
        );
    }
    let camera = read_camera(&camera_path)?;
    if camera.view != view {
        anyhow::bail!(
            "{}: holds the {} view, not {v}; re-render the directory",
            camera_path.display(),
            camera.view.name()
        );
    }
    if from_truth {
        let drawing = read_drawing(&dir.join(format!("lines_{v}.json")))?;
        return Ok((ObservedView::new(drawing, camera), None));
    }
    let picture = dir.join(format!("view_{v}.png"));
    let gray = read_picture(&picture)?;
    let opts = VisionOptions::default();
    let drawing = if shown {
        with_progress(&format!("vision {v}"), "steps", VISION_STEPS, |p| {
            detect_line_drawing_with_progress(&gray, &camera, &opts, p)
        })
    } else {
        detect_line_drawing(&gray, &camera, &opts)
    }
    .with_context(|| format!("{} (camera {})", picture.display(), camera_path.display()))?
    .drawing;
    Ok((ObservedView::new(drawing, camera), Some(gray)))
}

/// Refuses a missing input folder, and an output that would overwrite one of the inputs of
/// `views`.
fn check_paths(args: &Args, views: &[CornerView]) -> anyhow::Result<()> {
    let inputs: Vec<PathBuf> = views
        .iter()
        .flat_map(|v| {
            let v = v.name();
            ["camera_{v}.json", "lines_{v}.json", "view_{v}.png"]
                .map(|f| args.dir.join(f.replace("{v}", v)))
        })
        .chain([args.dir.join(LOOK_FILE)])
        .collect();
    let inputs: Vec<&Path> = inputs.iter().map(PathBuf::as_path).collect();
    if !args.dir.is_dir() {
        anyhow::bail!(
            "{}: no such folder; give the folder `blockworld render` wrote (camera_<v>.json with view_<v>.png or lines_<v>.json per view)",
            args.dir.display()
        );
    }
    crate::cli::files::check_output(&args.output, &inputs)
}

/// `observed`, the views of the folder `dir`, with what its `look.json` records: each view's
/// lights and the blocks' edge rounding (`files::read_recorded_look`;
/// docs/recognizer-pictures.md "Known lights" and "Known edge rounding"); unchanged when the
/// folder has none.
fn with_recorded_look(
    dir: &Path,
    mut observed: Vec<ObservedView>,
) -> anyhow::Result<Vec<ObservedView>> {
    let path = dir.join(LOOK_FILE);
    if path.exists() {
        let views: Vec<CornerView> = observed.iter().map(|v| v.camera.view).collect();
        let look = read_recorded_look(&path, &views)?;
        for (v, l) in observed.iter_mut().zip(look.towards_lights) {
            v.towards_lights = l;
            v.edge_radius_mm = look.edge_radius_mm;
        }
    }
    Ok(observed)
}

/// Reads `views` of the folder `dir` ([`read_view`]) and recognizes them (the search's progress
/// on stderr when `shown`), read again fainter when it declines for a missed line and checked
/// to stand (`pipeline::answer_of_pictures`); returns the views that gave the answer and
/// the answer.
pub(super) fn recognize_folder(
    dir: &Path,
    views: &[CornerView],
    from_truth: bool,
    shown: bool,
    opts: &RecognizeOptions,
) -> anyhow::Result<(Vec<ObservedView>, Recognition)> {
    let (observed, pictures): (Vec<ObservedView>, Vec<Option<image::GrayImage>>) = views
        .iter()
        .map(|&v| read_view(dir, v, from_truth, shown))
        .collect::<anyhow::Result<Vec<_>>>()?
        .into_iter()
        .unzip();
    let observed = with_recorded_look(dir, observed)?;
    let pictures: Vec<&image::GrayImage> = pictures.iter().flatten().collect();
    let quiet = |_: SearchProgress| {};
    let shown_progress = search_progress();
    let progress: &dyn Fn(SearchProgress) = if shown { &shown_progress } else { &quiet };
    let recognition = recognize_with_progress(&observed, &pictures, opts, progress)
        .with_context(|| format!("recognizing {}", dir.display()))?;
    let vision = VisionOptions::default();
    let (standing, read) = answer_of_pictures(recognition, &pictures, &observed, &vision, opts);
    Ok((read.unwrap_or(observed), standing.recognition))
}

/// Runs `blockworld recognize`.
pub fn run(args: Args) -> anyhow::Result<()> {
    let views = crate::cli::view_args::parse_corner_views(&args.source.views)?;
    let budget_s = args.time_budget_s;
    let takes = "use a positive number of seconds, at most 1000000";
    let ok = budget_s > 0.0 && budget_s <= 1e6;
    crate::cli::check_number("--time-budget-s", budget_s, ok, takes)?;
    check_paths(&args, &views)?;
    args.rrd.check(&[&args.output])?;
    let opts = RecognizeOptions {
        node_budget: args.node_budget,
        time_budget_s: args.time_budget_s,
        grid_mm: args.world.grid_mm()?,
        ..RecognizeOptions::default()
    };
    let (observed, recognition) =
        recognize_folder(&args.dir, &views, args.source.from_truth, true, &opts)?;
    if let Some(debug) = &args.debug_dir {
        super::recognize_debug::write_debug_files(
            &args.dir,
            debug,
            &observed,
            &recognition,
            &opts,
        )?;
    }
    let name = args
        .dir
        .file_name()
        .map_or("recognized".into(), |n| n.to_string_lossy().into_owned());
    let recon = reconstruction(&name, &recognition, 0.5);
    blockworld::io::write_atomic(&args.output, reconstruction_to_json(&recon).as_bytes())
        .with_context(|| format!("writing {}", args.output.display()))?;
    #[cfg(feature = "rrd")]
    if let Some(path) = &args.rrd.rrd {
        crate::cli::rrd::write_recognize_recording(path, &args.dir, &observed, &recon)?;
    }
    outln!(
        "{}: {} blocks in {} layers -> {}{}",
        args.dir.display(),
        recognition.blocks.len(),
        recognition.layers.len(),
        args.output.display(),
        recognition
            .reason
            .as_deref()
            .map_or(String::new(), |r| format!(" (unsupported: {r})"))
    )?;
    Ok(())
}
