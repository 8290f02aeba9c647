//! `blockworld render SCENE.json -o DIR`: the four corner views of a scene and their ground
//! truth (issue #2), written with [`crate::output::write_rendered_views`].

use crate::cli::view_args::ViewArgs;
use crate::output::write_rendered_views;
use crate::render::Renderer;
use crate::scene::read_scene;
use anyhow::Context;
use std::path::PathBuf;

/// Options of `blockworld render`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The scene file (JSON, see README "Scene files").
    pub scene: PathBuf,
    /// Output directory (created if missing).
    #[arg(short, long)]
    pub out: PathBuf,
    #[command(flatten)]
    pub view: ViewArgs,
}

/// Runs `blockworld render`.
pub fn run(args: Args) -> anyhow::Result<()> {
    let views = args.view.corner_views()?;
    let opts = args.view.render_options()?;
    let backend = args.view.backend()?;
    let scene = read_scene(&args.scene)
        .with_context(|| format!("reading scene {}", args.scene.display()))?;
    let renderer = Renderer::new(backend).context("starting the renderer")?;
    let rendered = renderer
        .render_views(&scene, &views, &opts)
        .with_context(|| format!("rendering {}", args.scene.display()))?;
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating output directory {}", args.out.display()))?;
    let written = write_rendered_views(&args.out, &rendered)
        .with_context(|| format!("writing views into {}", args.out.display()))?;
    for f in &written {
        println!(
            "wrote {}  sha256 {}",
            args.out.join(&f.name).display(),
            f.sha256
        );
    }
    Ok(())
}
