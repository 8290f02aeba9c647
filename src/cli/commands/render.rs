//! `blockworld render SCENE.json -o DIR`: the four corner views of a scene and their ground
//! truth (docs/rendering.md "Rendering"), written with [`blockworld::output::write_rendered_views`].

use crate::cli::progress::with_progress;
use crate::cli::view_args::ViewArgs;
use anyhow::Context;
use blockworld::output::write_rendered_views;
use blockworld::render::{RenderedView, Renderer};

use std::path::{Path, PathBuf};

/// Options of `blockworld render`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The scene file (JSON, see docs/formats.md "Scene files").
    pub scene: PathBuf,
    /// Output directory (created if missing).
    #[arg(short, long = "output", alias = "out", value_name = "OUTPUT")]
    pub out: PathBuf,
    #[command(flatten)]
    pub view: ViewArgs,
    #[command(flatten)]
    pub rrd: crate::cli::rrd::RrdArgs,
}

/// Runs `blockworld render`.
pub fn run(args: Args) -> anyhow::Result<()> {
    args.rrd.check(&[&args.scene])?;
    let views = args.view.some_corner_views()?;
    let opts = args.view.render_options()?;
    let backend = args.view.backend()?;
    let scene = crate::cli::files::read_scene_shown(&args.scene)
        .with_context(|| format!("reading scene {}", args.scene.display()))?;
    let max = blockworld::render::MAX_RENDER_BLOCKS;
    crate::cli::check_block_count(&args.scene, scene.blocks.len(), max, "render", "Render")?;
    let renderer = Renderer::new(backend).context("starting the renderer")?;
    renderer.check_options(&opts).context("--size")?;
    // Each view's line drawing counts the scene's edges twice (hidden lines, then their kinds);
    // every view has the same count, so the whole is the views times one view's total.
    let n = views.len() as u64;
    let rendered = with_progress("render", "edge steps", 0, |progress| {
        let mut done = Vec::with_capacity(views.len());
        for v in &views {
            let k = done.len() as u64;
            let view_progress = |d: u64, t: u64| progress(k * t + d, n * t);
            done.push(renderer.render_with_progress(&scene, *v, &opts, &view_progress)?);
        }
        Ok::<_, blockworld::render::RenderError>(done)
    })
    .with_context(|| format!("rendering {}", args.scene.display()))?;
    write_and_list(&args.out, &rendered)?;
    #[cfg(feature = "rrd")]
    if let Some(path) = &args.rrd.rrd {
        write_recording(path, &scene, &rendered)?;
    }
    if let Some(draw) = opts.look_draw(scene.blocks.len()) {
        let path = args.out.join(blockworld::render::photo::varied::LOOK_FILE);
        let text = draw.to_json();
        blockworld::io::write_atomic(&path, text.as_bytes())
            .with_context(|| format!("writing {}", path.display()))?;
        outln!(
            "wrote {}  sha256 {}",
            path.display(),
            blockworld::dataset::sha256_hex(text.as_bytes())
        )?;
    }
    Ok(())
}

/// Creates `out`, writes every view's files into it and prints each file with its sha256
/// (shared by `render` and `demo`).
pub fn write_and_list(out: &Path, views: &[RenderedView]) -> anyhow::Result<()> {
    std::fs::create_dir_all(out)
        .with_context(|| format!("creating output directory {}", out.display()))?;
    let written = write_rendered_views(out, views)
        .with_context(|| format!("writing views into {}", out.display()))?;
    for f in &written {
        outln!("wrote {}  sha256 {}", out.join(&f.name).display(), f.sha256)?;
    }
    Ok(())
}

/// The recording of `render --rrd`: the scene's blocks and every rendered view.
#[cfg(feature = "rrd")]
fn write_recording(
    path: &Path,
    scene: &blockworld::scene::Scene,
    rendered: &[RenderedView],
) -> anyhow::Result<()> {
    use blockworld::export::rrd::{Picture, RecordingData, ViewData};
    let views = rendered
        .iter()
        .map(|v| ViewData {
            camera: &v.camera,
            picture: Some(Picture {
                size_px: [v.gray.width(), v.gray.height()],
                pixels: v.gray.as_raw(),
            }),
            depth: Some(Picture {
                size_px: [v.depth.width(), v.depth.height()],
                pixels: v.depth.as_raw(),
            }),
            ids: Some(Picture {
                size_px: [v.ids.width(), v.ids.height()],
                pixels: v.ids.as_raw(),
            }),
            lines: Some(&v.lines),
        })
        .collect();
    let data = RecordingData {
        name: &scene.name,
        truth: Some(scene),
        recognized: None,
        views,
        fall: None,
    };
    crate::cli::rrd::write_recording(path, &data)
}
