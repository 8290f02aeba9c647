//! `blockworld export SCENE.json -o OUT.glb|OUT.gltf`: the scene as a glTF 2.0 model (thesis
//! Ch. VI "Display the Final Sample": look at the block sample from any viewpoint); with
//! `--trajectory`, its fall as an animation; `--format rrd`, the same as a Rerun recording
//! (docs/rerun.md "Falls"); `--format thesis`, the Appendix B files.

use anyhow::{bail, Context};
use blockworld::export::{
    reconstruction_with_truth_to_gltf, scene_fall_to_gltf, scene_to_gltf, GltfFiles,
};
use blockworld::io::write_atomic;
use blockworld::physics::Trajectory;
use blockworld::scene::{read_reconstruction, read_scene};
use std::path::{Path, PathBuf};

/// Options of `blockworld export`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The scene (or reconstruction) file to export.
    pub scene: PathBuf,
    /// Output: `.glb` writes one binary glTF file; `.gltf` writes the JSON and its buffer as
    /// `<stem>.bin` beside it.
    #[arg(short, long)]
    pub output: PathBuf,
    /// gltf (by the output's extension); thesis: the two data files of Appendix B,
    /// OUTPUT_vertices.txt and OUTPUT_connections.txt, in block units (Chapter VI); or rrd: a
    /// Rerun recording of the blocks and the floor (docs/rerun.md; needs `--features rrd`).
    #[arg(long, default_value = "gltf")]
    pub format: String,
    /// A stability dataset's `trajectory.bin` of SCENE (docs/stability.md "Trajectories"):
    /// the fall as a glTF animation `fall` (.glb or .gltf), or with `--format rrd` the truth's
    /// poses on the Rerun timeline `fall` (s). At most 64 MiB.
    #[arg(long, value_name = "FILE")]
    pub trajectory: Option<PathBuf>,
    /// With a glTF output: the truth scene to put beside SCENE, which is then read as a
    /// reconstruction; the file holds node groups `truth` and `reconstruction`, scenes
    /// `overlay`, `truth` and `reconstruction`, a material per role, and the block types and
    /// CSG tree in `extras`.
    #[arg(long)]
    pub truth: Option<PathBuf>,
}

/// The two glTF forms, chosen by the output's extension.
enum Form {
    Glb,
    GltfWithBin,
}

fn form_of(path: &Path) -> anyhow::Result<Form> {
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    match ext.as_deref() {
        Some("glb") => Ok(Form::Glb),
        Some("gltf") => Ok(Form::GltfWithBin),
        other => bail!(
            "{}: unknown output extension {}; use .glb (one binary file) or .gltf (JSON plus a .bin beside it)",
            path.display(),
            other.map_or("(none)".to_string(), |e| format!("\".{e}\""))
        ),
    }
}

/// Runs `blockworld export`: reads and validates the scene, builds the glTF and writes it
/// atomically (for `.gltf`, the `.bin` first so the JSON never points at a missing file).
pub fn run(args: Args) -> anyhow::Result<()> {
    let mut inputs = super::view::model_files(&args.scene);
    inputs.extend(args.truth.iter().cloned());
    inputs.extend(args.trajectory.iter().cloned());
    let inputs: Vec<&Path> = inputs.iter().map(PathBuf::as_path).collect();
    if args.trajectory.is_some() && args.truth.is_some() {
        bail!("--trajectory with --truth: a fall is of one scene; leave out --truth");
    }
    match args.format.to_ascii_lowercase().as_str() {
        "gltf" => {}
        "thesis" if args.trajectory.is_some() => {
            bail!("--trajectory: the Appendix B files hold no motion; use --format gltf or rrd")
        }
        "thesis" => return run_thesis(&args, &inputs),
        "rrd" => return run_rrd(&args, &inputs),
        other => {
            bail!("--format: unknown format {other:?}; the formats are gltf, thesis and rrd")
        }
    }
    let form = form_of(&args.output)?;
    let out = &args.output;
    crate::cli::files::check_output(out, &inputs)?;
    if let Form::GltfWithBin = form {
        crate::cli::files::check_output(&out.with_extension("bin"), &inputs)?;
    }
    let context = || format!("exporting {} to {}", args.scene.display(), out.display());
    let (files, blocks) = gltf_files(&args).with_context(context)?;
    match form {
        Form::Glb => {
            let glb = files.to_glb().with_context(context)?;
            write_atomic(out, &glb).with_context(|| format!("writing {}", out.display()))?;
            outln!(
                "{}: {} blocks -> {} ({} bytes)",
                args.scene.display(),
                blocks,
                out.display(),
                glb.len()
            )?;
        }
        Form::GltfWithBin => {
            let bin_path = out.with_extension("bin");
            let bin_name = bin_path
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .with_context(|| format!("{}: no file name", out.display()))?;
            let text = files.to_gltf_json(&bin_name).with_context(context)?;
            let bin = &files.bin;
            write_atomic(&bin_path, bin)
                .with_context(|| format!("writing {}", bin_path.display()))?;
            write_atomic(out, text.as_bytes())
                .with_context(|| format!("writing {}", out.display()))?;
            outln!(
                "{}: {} blocks -> {} + {} ({} + {} bytes)",
                args.scene.display(),
                blocks,
                out.display(),
                bin_path.display(),
                text.len(),
                bin.len()
            )?;
        }
    }
    Ok(())
}

/// The glTF document of the scene, or of the reconstruction beside its `--truth`, and the
/// number of blocks in it.
fn gltf_files(args: &Args) -> anyhow::Result<(GltfFiles, usize)> {
    let Some(truth_path) = &args.truth else {
        let scene = read_model(&args.scene)?;
        let files = match read_trajectory(args)? {
            Some(t) => scene_fall_to_gltf(&scene, &t.times_s, &t.frames)?,
            None => scene_to_gltf(&scene)?,
        };
        return Ok((files, scene.blocks.len()));
    };
    let truth = read_scene(truth_path)
        .with_context(|| format!("reading the truth scene {}", truth_path.display()))?;
    let recon = read_reconstruction(&args.scene)
        .with_context(|| format!("reading the reconstruction {}", args.scene.display()))?;
    let files = reconstruction_with_truth_to_gltf(&truth, &recon)?;
    Ok((files, truth.blocks.len() + recon.blocks.len()))
}

/// SCENE, a scene file or a pair of Appendix B files.
fn read_model(path: &Path) -> anyhow::Result<blockworld::scene::Scene> {
    Ok(match super::view::thesis_pair(path) {
        Some(_) => super::view::read_model(path, blockworld::export::Truncation::Strict)?,
        None => crate::cli::files::read_scene_shown(path)?,
    })
}

/// Largest `--trajectory` read, bytes: 122 frames of 2,000 blocks (the settle bound,
/// docs/limits.md) take 6.5 MiB.
const MAX_TRAJECTORY_BYTES: u64 = 64 << 20;

/// The `--trajectory` file, read and checked, when given.
fn read_trajectory(args: &Args) -> anyhow::Result<Option<Trajectory>> {
    let Some(path) = &args.trajectory else {
        return Ok(None);
    };
    let why =
        "more than any trajectory of a scene generate settles; give the scene's trajectory.bin";
    let bytes = blockworld::io::read_bytes_at_most(path, MAX_TRAJECTORY_BYTES, why)
        .with_context(|| format!("reading the trajectory {}", path.display()))?;
    let t = Trajectory::from_bytes(&bytes).with_context(|| format!("{}", path.display()))?;
    Ok(Some(t))
}

/// `--format rrd`: a Rerun recording of the scene (or of the reconstruction beside its
/// `--truth`) and, with `--trajectory`, the truth's fall on the timeline `fall`.
#[cfg(feature = "rrd")]
fn run_rrd(args: &Args, inputs: &[&Path]) -> anyhow::Result<()> {
    use blockworld::export::rrd::{Fall, RecordingData};
    crate::cli::files::check_output(&args.output, inputs)?;
    let (truth, recon) = match &args.truth {
        Some(t) => {
            let truth = read_scene(t)
                .with_context(|| format!("reading the truth scene {}", t.display()))?;
            let recon = read_reconstruction(&args.scene)
                .with_context(|| format!("reading the reconstruction {}", args.scene.display()))?;
            (truth, Some(recon.to_scene()))
        }
        None => (read_model(&args.scene)?, None),
    };
    let trajectory = read_trajectory(args)?;
    let data = RecordingData {
        name: &truth.name,
        truth: Some(&truth),
        recognized: recon.as_ref(),
        views: Vec::new(),
        fall: trajectory.as_ref().map(|t| Fall {
            times_s: &t.times_s,
            frames: &t.frames,
        }),
    };
    crate::cli::rrd::write_recording(&args.output, &data)
}

/// `--format rrd` in a build without the feature: refused before any work.
#[cfg(not(feature = "rrd"))]
fn run_rrd(args: &Args, _inputs: &[&Path]) -> anyhow::Result<()> {
    bail!(
        "--format rrd {}: {}",
        args.output.display(),
        crate::cli::rrd::NO_RRD_FEATURE
    )
}

/// `--format thesis`: the Appendix B data files, vertices first so a reader that finds the
/// connections file finds its vertices too.
fn run_thesis(args: &Args, inputs: &[&Path]) -> anyhow::Result<()> {
    let prefix = args.output.display().to_string();
    let paths =
        ["_vertices.txt", "_connections.txt"].map(|s| PathBuf::from(format!("{prefix}{s}")));
    for p in &paths {
        crate::cli::files::check_output(p, inputs)?;
    }
    let scene = super::view::read_model(&args.scene, blockworld::export::Truncation::Strict)?;
    let files = blockworld::export::scene_to_thesis_files(&scene).with_context(|| {
        format!(
            "exporting {} as Appendix B data files",
            args.scene.display()
        )
    })?;
    for (path, text) in paths.iter().zip([&files.vertices, &files.connections]) {
        write_atomic(path, text.as_bytes())
            .with_context(|| format!("writing {}", path.display()))?;
    }
    outln!(
        "{}: {} blocks -> {prefix}_vertices.txt, {prefix}_connections.txt (block units of {} mm)",
        args.scene.display(),
        scene.blocks.len(),
        blockworld::export::THESIS_UNIT_MM
    )?;
    Ok(())
}
