//! `blockworld demo [-o DIR]`: the main job. Runs the whole pipeline that exists so far on the
//! thesis's block sample (`scenes/thesis_sample.json`, Chapter VI / Appendix B): settles it with
//! rapier3d, renders the four corner views with their ground truth into DIR (default
//! `out/demo`), runs the vision front end on each view (Sobel, least-squares lines, vertices and
//! six-bit codes; `vertices_<view>.json`) and compares it with the exact line drawing, and
//! recognizes the sample from the four pictures (`reconstruction.json`), scores it against the
//! truth, and exports the sample as glTF (`<scene>.glb`).

use crate::cli::view_args::parse_backend;
use anyhow::Context;
use blockworld::camera::CornerView;
use blockworld::csg::reconstruction;
use blockworld::output::encode_png_rgb8;
use blockworld::physics::{settle, SettleParams};
use blockworld::pipeline::{observe, recognize_rendered, PipelineOptions};
use blockworld::render::{RenderOptions, RenderedView, Renderer};
use blockworld::scene::{read_scene, reconstruction_to_json, Reconstruction, Scene};
use blockworld::score::score_reconstruction;
use blockworld::view::{
    draw_sheet, rasterize_sheet, wire_model, HiddenLines, Role, SheetOptions, THESIS_FIGURES,
};
use blockworld::vision::{detect_line_drawing, match_vertices, VisionOptions};
use std::path::{Path, PathBuf};

/// The demo scene, relative to the working directory (the repository root under `make demo`).
const DEMO_SCENE: &str = "scenes/thesis_sample.json";

/// Options of `blockworld demo`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Output directory (created if missing).
    #[arg(
        short,
        long = "output",
        alias = "out",
        value_name = "OUTPUT",
        default_value = "out/demo"
    )]
    pub out: PathBuf,
    /// Graphics backend: vulkan (lavapipe, default) or gl (llvmpipe through EGL).
    #[arg(long, default_value = "vulkan")]
    pub backend: String,
}

/// Runs `blockworld demo`.
pub fn run(args: Args) -> anyhow::Result<()> {
    let backend = parse_backend(&args.backend)?;
    let scene_path = demo_scene_path();
    let scene = read_scene(&scene_path)
        .with_context(|| format!("reading the demo scene {}", scene_path.display()))?;
    outln!(
        "demo: {} ({} blocks) from {}",
        scene.name,
        scene.blocks.len(),
        scene_path.display()
    )?;
    let scene = settled_sample(&scene, &scene_path)?;
    let renderer = Renderer::new(backend).context("starting the renderer")?;
    outln!("renderer: {}", renderer.adapter_info())?;
    let views = renderer
        .render_views(&scene, &CornerView::ALL, &RenderOptions::default())
        .with_context(|| format!("rendering {}", scene_path.display()))?;
    super::render::write_and_list(&args.out, &views)?;
    for v in &views {
        outln!("{}", view_summary(v))?;
    }
    for v in &views {
        outln!("{}", vision_summary(v, &args.out)?)?;
    }
    let recon = recognize_summary(&scene, &views, &args.out)?;
    figures_of(&recon, &args.out)?;
    export_models(&scene, &recon, &args.out, &scene_path)
}

/// The sample settled with the default parameters, after a line saying how it settled; an
/// error when it does not rest stably.
fn settled_sample(scene: &Scene, scene_path: &Path) -> anyhow::Result<Scene> {
    let settled = settle(scene, &SettleParams::default())
        .with_context(|| format!("settling {}", scene_path.display()))?;
    outln!(
        "settle: {} after {} steps (max drift {:.3} mm, max turn {:.3} deg)",
        if settled.report.stable {
            "stable"
        } else {
            "UNSTABLE"
        },
        settled.report.steps,
        settled.report.max_drift_mm,
        settled.report.max_turn_deg
    )?;
    if !settled.report.stable {
        anyhow::bail!(
            "{} does not rest stably: {}",
            scene_path.display(),
            settled
                .report
                .describe_moved(scene, &SettleParams::default())
        );
    }
    Ok(settled.scene)
}

/// Writes the truth and the reconstruction as one glTF, and the truth alone as another.
fn export_models(
    scene: &Scene,
    recon: &Reconstruction,
    out: &Path,
    scene_path: &Path,
) -> anyhow::Result<()> {
    let both = out.join(format!("{}_truth_and_reconstruction.glb", scene.name));
    let glb = blockworld::export::reconstruction_with_truth_to_glb(scene, recon)
        .context("exporting the truth and the reconstruction as one glTF")?;
    blockworld::io::write_atomic(&both, &glb)
        .with_context(|| format!("writing {}", both.display()))?;
    outln!(
        "export: truth and reconstruction as two named scenes -> {} ({} bytes)",
        both.display(),
        glb.len()
    )?;
    let glb_path = out.join(format!("{}.glb", scene.name));
    let glb = blockworld::export::scene_to_glb(scene)
        .with_context(|| format!("exporting {} as glTF", scene_path.display()))?;
    blockworld::io::write_atomic(&glb_path, &glb)
        .with_context(|| format!("writing {}", glb_path.display()))?;
    outln!(
        "export: {} blocks as glTF 2.0 -> {} ({} bytes)",
        scene.blocks.len(),
        glb_path.display(),
        glb.len()
    )?;
    Ok(())
}

/// Recognizes the sample from the four pictures (vision, then the modified Kanade recognizer),
/// writes `reconstruction.json`, scores it against the truth and prints the verdict.
fn recognize_summary(
    scene: &Scene,
    views: &[RenderedView],
    out: &Path,
) -> anyhow::Result<Reconstruction> {
    let opts = PipelineOptions::default();
    let (observed, _) = observe(views, &opts.source).context("vision on the demo views")?;
    let recognition = recognize_rendered(views, &observed, &opts.source, &opts.recognize)
        .context("recognizing the demo views")?;
    let recon = reconstruction(&scene.name, &recognition, opts.layer_tol_mm);
    let path = out.join("reconstruction.json");
    blockworld::io::write_atomic(&path, reconstruction_to_json(&recon).as_bytes())
        .with_context(|| format!("writing {}", path.display()))?;
    let score = score_reconstruction(scene, &recon).context("scoring the reconstruction")?;
    outln!(
        "recognize: {} -> {} blocks, status {} -> {}; against the truth: {} (IoU {:.4}, {} of {} blocks matched){}",
        views.len(),
        recon.blocks.len(),
        if recon.is_ok() { "ok" } else { "unsupported" },
        path.display(),
        score.verdict.as_str(),
        score.iou,
        score.matched_blocks,
        score.truth_blocks,
        recon
            .reason
            .as_deref()
            .map_or(String::new(), |r| format!("; reason: {r}"))
    )?;
    Ok(recon)
}

/// Draws the reconstruction as the thesis displays its final sample (Figures 6.7-6.12,
/// `view::THESIS_FIGURES`), one PNG per figure.
fn figures_of(recon: &Reconstruction, out: &Path) -> anyhow::Result<()> {
    let model = wire_model(&recon.to_scene(), Role::Model);
    let opts = SheetOptions {
        size_px: [400, 400],
        hidden_lines: HiddenLines::Show,
        ..SheetOptions::default()
    };
    for fig in &THESIS_FIGURES {
        let sheet = draw_sheet(std::slice::from_ref(&model), &fig.params()?, &opts)?;
        let png = encode_png_rgb8(&rasterize_sheet(&sheet))?;
        let path = out.join(format!("{}.png", fig.name));
        blockworld::io::write_atomic(&path, &png)
            .with_context(|| format!("writing {}", path.display()))?;
    }
    outln!(
        "view: the reconstruction as the thesis shows its sample (Figures 6.7-6.12) -> {}/fig6_*.png",
        out.display()
    )?;
    Ok(())
}

/// Runs the vision front end on one view, writes `vertices_<view>.json` (a line drawing in the
/// `lines_<view>.json` format) and compares it with the exact drawing (vertices within 2 px).
fn vision_summary(v: &RenderedView, out: &Path) -> anyhow::Result<String> {
    let name = v.camera.view.name();
    let det = detect_line_drawing(&v.gray, &v.camera, &VisionOptions::default())
        .with_context(|| format!("vision on view {name}"))?;
    let path = out.join(format!("vertices_{name}.json"));
    blockworld::io::write_atomic(&path, det.drawing.to_json().as_bytes())
        .with_context(|| format!("writing {}", path.display()))?;
    let m = match_vertices(&det.drawing, &v.lines);
    Ok(format!(
        "vision {name}: {} vertices, {} lines -> {}; against the exact drawing: precision {:.3}, \
         recall {:.3}, six-bit code accuracy {:.3}",
        det.drawing.points.len(),
        det.drawing.lines.len(),
        path.display(),
        m.precision(),
        m.recall(),
        m.code_accuracy()
    ))
}

/// `scenes/thesis_sample.json` from the working directory, else from the source tree this binary
/// was built from.
fn demo_scene_path() -> PathBuf {
    let local = Path::new(DEMO_SCENE);
    if local.exists() {
        return local.to_path_buf();
    }
    Path::new(env!("CARGO_MANIFEST_DIR")).join(DEMO_SCENE)
}

/// One line per view: the drawing's size by line kind and the gray levels in the picture.
pub fn view_summary(v: &RenderedView) -> String {
    let [boundary, convex, concave, crack] = v.lines.kind_counts();
    let mut seen = [false; 256];
    for p in v.gray.as_raw() {
        seen[*p as usize] = true;
    }
    let levels: Vec<String> = (0..256)
        .filter(|l| seen[*l])
        .map(|l| l.to_string())
        .collect();
    format!(
        "view {}: {} points, {} lines (boundary {boundary}, convex {convex}, concave {concave}, \
         crack {crack}); gray levels {}: {}",
        v.camera.view.name(),
        v.lines.points.len(),
        v.lines.lines.len(),
        levels.len(),
        levels.join(" ")
    )
}
