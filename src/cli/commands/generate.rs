//! `blockworld generate --count N --seed S -o DATASET [--family F ...] [--jobs J]
//! [--shard I/N | --shards N] [view options]` (docs/datasets.md "Settling").
//!
//! `--seed` is the dataset seed (shared with the view options, where it seeds sensor noise:
//! here each scene's noise seed is its own scene seed). `--shards N` takes the shard index from
//! `SLURM_ARRAY_TASK_ID` (the array index is the shard index) or Kubernetes' `JOB_COMPLETION_INDEX`.

use crate::cli::progress::with_progress;
use crate::cli::view_args::ViewArgs;
use anyhow::{bail, Context};
use blockworld::dataset::{
    generate_dataset, DatasetError, DatasetOptions, Family, GenerateSummary, SceneFileEncoder,
    Shard, StabilityOptions, TrajectoryFrames, DEFAULT_FRAME_EVERY,
};
use blockworld::export::scene_to_glb;
use blockworld::io::FileSync;
use blockworld::physics::SettleParams;
use blockworld::render::Renderer;
use blockworld::scene::{Scene, SceneError};
use std::path::PathBuf;
use std::time::Instant;

/// Options of `blockworld generate`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Number of scenes in the whole dataset (all shards together).
    #[arg(long)]
    pub count: u64,
    /// Output dataset directory (created; re-running the same command resumes).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Families to cycle through (repeat or comma-separate); default all. One of: single, row,
    /// l_shape, two_layer, three_layer, tower, staircase, separated, random_stack,
    /// upper_larger, yaw; and, only when named, the Chapter VII parts: wedge, round.
    #[arg(long = "family", value_delimiter = ',')]
    pub families: Vec<String>,
    /// Worker threads (default: all cores). The dataset's bytes do not depend on it.
    #[arg(long, default_value_t = 0)]
    pub jobs: usize,
    /// Write only shard I of N (0-based): scenes with index % N == I.
    #[arg(long, conflicts_with = "shards")]
    pub shard: Option<String>,
    /// Write shard I of N, I taken from SLURM_ARRAY_TASK_ID or JOB_COMPLETION_INDEX.
    #[arg(long)]
    pub shards: Option<u64>,
    /// Also write each settled scene as binary glTF, `scene.glb`, listed in the manifest.
    #[arg(long)]
    pub gltf: bool,
    /// Keep the draws that do not stand and label every scene in `meta.stability`: stable,
    /// the first block to move and when, the cause, the largest displacement
    /// (docs/stability.md). Unstable draws are made by shifting or tilting a block.
    #[arg(long)]
    pub keep_unstable: bool,
    /// With --keep-unstable: the share of scenes drawn to stand, 0 to 1 (each scene's seed
    /// decides which).
    #[arg(long, requires = "keep_unstable", default_value_t = 0.5)]
    pub stable_fraction: f64,
    /// With --keep-unstable: record every block's pose at 30 Hz until rest or 4 s,
    /// `trajectory.bin`; with --gltf also the fall as an animated glTF, `fall.glb`.
    #[arg(long, requires = "keep_unstable")]
    pub trajectory: bool,
    /// With --trajectory: draw these views (comma separated: ne, se, sw, nw) at every
    /// --trajectory-every-th frame of each trajectory and at its last, with the cameras of the
    /// scene's still views and the same ground truth (depth, ids, exact lines, camera), into
    /// frames/f<frame>_<file>, listed in the manifest. Line art only. At most 128 pictures
    /// (frames x views) per scene; a trajectory has at most 122 frames (docs/limits.md
    /// "Stability frames").
    #[arg(long, requires = "trajectory", value_delimiter = ',')]
    pub trajectory_views: Vec<String>,
    /// With --trajectory-views: draw every Nth frame, 1 = all [default: 4].
    #[arg(long, requires = "trajectory_views")]
    pub trajectory_every: Option<u32>,
    /// Force every file to disk before it is renamed into place (default: none but the
    /// manifest; a resume re-hashes every file, which finds what a power loss damaged).
    #[arg(long)]
    pub fsync: bool,
    /// How views are rendered; `--views ""` writes scene.json only. `--seed` is the dataset seed.
    #[command(flatten)]
    pub view: ViewArgs,
}

/// Resolves the families named on the command line (all when none).
pub fn parse_families(names: &[String]) -> anyhow::Result<Vec<Family>> {
    let names: Vec<&str> = names
        .iter()
        .map(|s| s.trim())
        .filter(|s| !s.is_empty())
        .collect();
    if names.is_empty() {
        return Ok(Family::ALL.to_vec());
    }
    names
        .iter()
        .map(|n| {
            Family::parse(n).with_context(|| {
                let known: Vec<&str> = Family::ALL
                    .iter()
                    .chain(&Family::CHAPTER_VII)
                    .map(|f| f.name())
                    .collect();
                format!(
                    "--family: unknown family {n:?}; known: {}",
                    known.join(", ")
                )
            })
        })
        .collect()
}

/// Shard from `--shard I/N`, or `--shards N` with the index from the array job's environment.
fn resolve_shard(args: &Args) -> anyhow::Result<Shard> {
    if let Some(s) = &args.shard {
        return Ok(Shard::parse(s)?);
    }
    let Some(n) = args.shards else {
        return Ok(Shard::WHOLE);
    };
    let env_u64 = |name: &str| -> anyhow::Result<Option<u64>> {
        match std::env::var(name) {
            Ok(v) => v
                .trim()
                .parse::<u64>()
                .map(Some)
                .with_context(|| format!("{name}={v:?} is not a whole number")),
            Err(_) => Ok(None),
        }
    };
    // The array index is the shard index (submit with --array=0-<N-1>); the task count is not
    // checked, since a failed task resubmitted alone (--array=<i>) sees a count of 1.
    let index = if let Some(id) = env_u64("SLURM_ARRAY_TASK_ID")? {
        id
    } else if let Some(i) = env_u64("JOB_COMPLETION_INDEX")? {
        i
    } else {
        bail!("--shards {n} needs SLURM_ARRAY_TASK_ID (Slurm array job) or JOB_COMPLETION_INDEX (Kubernetes Indexed Job); use --shard I/{n} elsewhere");
    };
    Ok(Shard::new(index, n)?)
}

/// The dataset options of a command line.
pub fn dataset_options(args: &Args) -> anyhow::Result<DatasetOptions> {
    let shard = resolve_shard(args)?;
    let opts = checked_options(args.count, &args.families, &args.view, args.jobs, shard)?;
    Ok(DatasetOptions {
        scene_file: args.gltf.then_some(SceneFileEncoder {
            name: "scene.glb",
            encode: encode_glb,
        }),
        file_sync: if args.fsync {
            FileSync::EveryFile
        } else {
            FileSync::Verified
        },
        stability: stability_options(args)?,
        ..opts
    })
}

/// The stability options of `--keep-unstable`, `--stable-fraction` and `--trajectory`.
fn stability_options(args: &Args) -> anyhow::Result<Option<StabilityOptions>> {
    if !args.keep_unstable {
        return Ok(None);
    }
    let f = args.stable_fraction;
    if !(0.0..=1.0).contains(&f) {
        bail!(
            "--stable-fraction {}: give a share from 0 to 1 (0.5 draws half the scenes to stand)",
            blockworld::io::echo_number(f)
        );
    }
    Ok(Some(StabilityOptions {
        stable_fraction: f,
        trajectory: args.trajectory,
        fall_gltf: args.trajectory && args.gltf,
        frames: trajectory_frames(args)?,
    }))
}

/// The frames of `--trajectory-views` and `--trajectory-every`, when views are named.
fn trajectory_frames(args: &Args) -> anyhow::Result<Option<TrajectoryFrames>> {
    let named: Vec<String> = args
        .trajectory_views
        .iter()
        .filter(|v| !v.trim().is_empty())
        .cloned()
        .collect();
    if named.is_empty() && args.trajectory_views.is_empty() {
        return Ok(None);
    }
    let views = crate::cli::view_args::parse_corner_views_of("--trajectory-views", &named)?;
    Ok(Some(TrajectoryFrames {
        views,
        every: args.trajectory_every.unwrap_or(DEFAULT_FRAME_EVERY),
    }))
}

/// The settled scene as binary glTF (`generate --gltf`), for the dataset's `scene.glb`.
fn encode_glb(scene: &Scene) -> Result<Vec<u8>, String> {
    scene_to_glb(scene).map_err(|e| e.to_string())
}

/// Dataset options from checked command-line values (shared with `bench generate`);
/// `view.seed` is the dataset seed.
pub fn checked_options(
    count: u64,
    families: &[String],
    view: &ViewArgs,
    jobs: usize,
    shard: Shard,
) -> anyhow::Result<DatasetOptions> {
    Ok(DatasetOptions {
        count,
        seed: view.seed,
        families: parse_families(families)?,
        views: view.corner_views()?,
        render: view.render_options()?,
        settle: SettleParams::default(),
        shard,
        jobs,
        scene_file: None,
        file_sync: FileSync::Verified,
        stability: None,
    })
}

/// Renderers for a dataset run on `jobs` worker threads (0 = one per core): one device per
/// worker, at most [`MAX_RENDERERS`], so workers render side by side instead of waiting for one
/// device (docs/benchmarks.md "Benchmarks"); none when no views are asked for.
pub fn renderers_for(args: &ViewArgs, jobs: usize) -> anyhow::Result<Vec<Renderer>> {
    if args.corner_views()?.is_empty() {
        return Ok(Vec::new());
    }
    open_renderers(args, jobs)
}

/// [`renderers_for`] whatever `--views` says (`--trajectory-views` draws with `--views ""`).
fn open_renderers(args: &ViewArgs, jobs: usize) -> anyhow::Result<Vec<Renderer>> {
    let workers = if jobs == 0 {
        std::thread::available_parallelism().map_or(1, |n| n.get())
    } else {
        jobs
    };
    let mut renderers = vec![open_renderer(args)?];
    while renderers.len() < workers.clamp(1, MAX_RENDERERS) {
        // A device that will not open a second time (an exclusive GPU) leaves the workers
        // sharing the ones there are.
        match open_renderer(args) {
            Ok(r) => renderers.push(r),
            Err(e) => {
                tracing::info!("rendering through {} device(s): {e:#}", renderers.len());
                break;
            }
        }
    }
    Ok(renderers)
}

/// Most renderers (devices) a dataset run creates: each lavapipe device starts its own
/// rasterizer threads, one per core.
pub const MAX_RENDERERS: usize = 4;

/// Creates the renderer when views are asked for.
pub fn renderer_for(args: &ViewArgs) -> anyhow::Result<Option<Renderer>> {
    if args.corner_views()?.is_empty() {
        return Ok(None);
    }
    open_renderer(args).map(Some)
}

/// A renderer on the backend of `args`, checked against its picture size.
fn open_renderer(args: &ViewArgs) -> anyhow::Result<Renderer> {
    let r = Renderer::new(args.backend()?)
        .context("creating the renderer (pass --views \"\" to write scene.json only)")?;
    r.check_options(&args.render_options()?).context("--size")?;
    Ok(r)
}

/// Runs `blockworld generate`.
pub fn run(args: Args) -> anyhow::Result<()> {
    let opts = dataset_options(&args)?;
    let frames = opts.stability.as_ref().is_some_and(|s| s.frames.is_some());
    let renderers = if opts.views.is_empty() && frames {
        open_renderers(&args.view, args.jobs)?
    } else {
        renderers_for(&args.view, args.jobs)?
    };
    let total = opts.shard.len(opts.count);
    let started = Instant::now();
    let summary = with_progress("generate", "scenes", total, |progress| {
        generate_dataset(&args.output, &opts, &renderers, progress)
    })
    .map_err(|e| with_fix(e, &args.output))?;
    report(&summary, &opts, started.elapsed().as_secs_f64())
}

/// The error with a fix that fits it: an interrupted write is fixed by its cause (free disk
/// space, a writable folder, a directory as `-o`) and resumed by re-running the same command;
/// bad options, a dataset written with other options and a concurrent writer carry their own
/// fix in their message.
fn with_fix(e: DatasetError, out: &std::path::Path) -> anyhow::Error {
    let io_kind = match &e {
        DatasetError::Io { source, .. } => Some(source.kind()),
        DatasetError::Scene(SceneError::Io { source, .. }) => Some(source.kind()),
        _ => None,
    };
    let what = format!("generating {}", out.display());
    let Some(kind) = io_kind else {
        return anyhow::Error::new(e).context(what);
    };
    use std::io::ErrorKind as K;
    let fix = match kind {
        K::StorageFull | K::QuotaExceeded => "free disk space",
        K::PermissionDenied | K::ReadOnlyFilesystem => "make the folder writable",
        K::AlreadyExists | K::NotADirectory => "give a directory (new or this dataset's) as -o",
        _ => "fix the cause above",
    };
    anyhow::Error::new(e).context(format!(
        "{what} ({fix}, then re-run the same command: finished scenes are kept)"
    ))
}

fn report(s: &GenerateSummary, opts: &DatasetOptions, secs: f64) -> anyhow::Result<()> {
    let shard = if opts.shard.is_whole() {
        String::new()
    } else {
        format!(" (shard {}/{})", opts.shard.index, opts.shard.count)
    };
    outln!(
        "{} scenes{shard}: {} generated, {} kept from an earlier run; redrew {} unstable and {} unplaceable draws; {:.2} s ({:.1} scenes/s); manifest {}",
        s.scenes,
        s.generated,
        s.resumed,
        s.unstable_draws,
        s.unplaceable_draws,
        secs,
        s.generated as f64 / secs.max(1e-9),
        s.manifest.display()
    )?;
    if opts.stability.is_some() {
        outln!(
            "stability: {} of {} scenes do not stand; redrew {} perturbed draws that stood",
            s.unstable_scenes,
            s.scenes,
            s.stood_draws
        )?;
    }
    Ok(())
}
