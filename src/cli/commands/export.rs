//! `blockworld export SCENE.json -o OUT.glb|OUT.gltf`: the scene as a glTF 2.0 model (thesis
//! Ch. VI "Display the Final Sample": look at the block sample from any viewpoint).

use anyhow::{bail, Context};
use blockworld::export::{scene_to_glb, scene_to_gltf_json};
use blockworld::io::write_atomic;
use blockworld::scene::read_scene;
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
    let form = form_of(&args.output)?;
    let scene = read_scene(&args.scene)?;
    let out = &args.output;
    let context = || format!("exporting {} to {}", args.scene.display(), out.display());
    match form {
        Form::Glb => {
            let glb = scene_to_glb(&scene).with_context(context)?;
            write_atomic(out, &glb).with_context(|| format!("writing {}", out.display()))?;
            outln!(
                "{}: {} blocks -> {} ({} bytes)",
                args.scene.display(),
                scene.blocks.len(),
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
            let (text, bin) = scene_to_gltf_json(&scene, &bin_name).with_context(context)?;
            write_atomic(&bin_path, &bin)
                .with_context(|| format!("writing {}", bin_path.display()))?;
            write_atomic(out, text.as_bytes())
                .with_context(|| format!("writing {}", out.display()))?;
            outln!(
                "{}: {} blocks -> {} + {} ({} + {} bytes)",
                args.scene.display(),
                scene.blocks.len(),
                out.display(),
                bin_path.display(),
                text.len(),
                bin.len()
            )?;
        }
    }
    Ok(())
}
