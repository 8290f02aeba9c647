//! `blockworld export SCENE.json -o OUT.glb|OUT.gltf`: the scene as a glTF 2.0 model (thesis
//! Ch. VI "Display the Final Sample": look at the block sample from any viewpoint).

use anyhow::{bail, Context};
use blockworld::export::{reconstruction_with_truth_to_gltf, scene_to_gltf, GltfFiles};
use blockworld::io::write_atomic;
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
    /// gltf (by the output's extension), or thesis: the two data files of Appendix B,
    /// OUTPUT_vertices.txt and OUTPUT_connections.txt, in block units (Chapter VI).
    #[arg(long, default_value = "gltf")]
    pub format: String,
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
    let inputs: Vec<&Path> = inputs.iter().map(PathBuf::as_path).collect();
    match args.format.to_ascii_lowercase().as_str() {
        "gltf" => {}
        "thesis" => return run_thesis(&args, &inputs),
        other => bail!("--format: unknown format {other:?}; the formats are gltf and thesis"),
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
        let scene = match super::view::thesis_pair(&args.scene) {
            Some(_) => {
                super::view::read_model(&args.scene, blockworld::export::Truncation::Strict)?
            }
            None => crate::cli::files::read_scene_shown(&args.scene)?,
        };
        return Ok((scene_to_gltf(&scene)?, scene.blocks.len()));
    };
    let truth = read_scene(truth_path)
        .with_context(|| format!("reading the truth scene {}", truth_path.display()))?;
    let recon = read_reconstruction(&args.scene)
        .with_context(|| format!("reading the reconstruction {}", args.scene.display()))?;
    let files = reconstruction_with_truth_to_gltf(&truth, &recon)?;
    Ok((files, truth.blocks.len() + recon.blocks.len()))
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
