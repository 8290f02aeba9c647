//! The whole method on a scene, in memory, as the thesis's flow chart runs it (Figure 5.3):
//! the corner views rendered with their ground truth → the line drawings (the vision front end
//! on the pictures, or the exact drawings, to tell recognition errors from vision errors) →
//! the modified Kanade recognizer → its CSG reconstruction → its score against the truth.
//!
//! The one home of suite running: `bench accuracy` and the accuracy gate
//! (`tests/accuracy_gate.rs`) call [`run_scene`] and [`run_suite`]; `demo` and `bench
//! recognize`, which keep the rendered views for their own output, call [`observe`] and
//! [`recognize_rendered`], the same two steps [`run_scene`] takes, so every caller runs the
//! recognizer as `blockworld recognize` does (with the pictures for step 6 when the drawings
//! were read from them; a decline for what a missed line causes reads the pictures again
//! fainter, [`read_again_fainter`], module `reread`), and every answer must stand
//! ([`recognize_standing`], module `stand`). Each stage's time is counted where the stage is called
//! ([`StageTimes`]), so benches print what the stages measured instead of re-running their
//! steps. No file I/O.

mod reread;
mod stand;

pub use reread::{read_again_fainter, Reading, FAINTER_THRESHOLDS, READ_AGAIN_AFTER};
pub use stand::{check_answer_stands, recognize_standing, Standing};

use crate::camera::CornerView;
use crate::csg::reconstruction;
use crate::physics::SettleParams;
use crate::recognize::{
    equally_good_alternative, recognize_in_pictures, ObservedView, Recognition, RecognizeError,
    RecognizeOptions,
};
use crate::render::{RenderOptions, RenderedView, Renderer};
use crate::scene::{Reconstruction, Scene};
use crate::score::{score_suite_scene, NoReconstruction, SceneResult, ScoreOptions};
use crate::vision::{detect_line_drawing, VisionOptions};
use serde::Serialize;
use std::time::Instant;

/// Where the recognizer's line drawings come from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum DrawingSource {
    /// The vision front end on the rendered pictures (the method as the thesis ran it).
    Pictures(VisionOptions),
    /// The exact visible line drawings of the ground truth (`--from-truth`).
    Truth,
}

/// How a scene is run through the pipeline.
#[derive(Debug, Clone, PartialEq)]
pub struct PipelineOptions {
    /// How the views are rendered.
    pub render: RenderOptions,
    /// Which corner views (the thesis: two opposite ones for simple samples, four otherwise).
    pub views: Vec<CornerView>,
    /// Pictures through vision, or the exact drawings.
    pub source: DrawingSource,
    /// The recognizer's tolerances and limits. The default has no time budget, only the node
    /// budget (docs/limits.md "Recognizer"), so that an accuracy figure is the same on every
    /// machine and under any load.
    pub recognize: RecognizeOptions,
    /// The scorer's tolerances and bars.
    pub score: ScoreOptions,
    /// Block bottoms within this height share a layer of the CSG, mm; default 0.5.
    pub layer_tol_mm: f64,
}

impl Default for PipelineOptions {
    fn default() -> Self {
        PipelineOptions {
            render: RenderOptions::default(),
            views: CornerView::ALL.to_vec(),
            source: DrawingSource::Pictures(VisionOptions::default()),
            recognize: RecognizeOptions {
                time_budget_s: f64::INFINITY,
                ..RecognizeOptions::default()
            },
            score: ScoreOptions::default(),
            layer_tol_mm: 0.5,
        }
    }
}

/// Milliseconds spent in each stage for one scene (all views together).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct StageTimes {
    /// Rendering the pictures and their ground truth.
    pub render_ms: f64,
    /// The vision front end (0 with exact drawings).
    pub vision_ms: f64,
    /// The recognizer and its CSG (the standing check included).
    pub recognize_ms: f64,
    /// The standing check alone (settling an `ok` answer; 0 for a decline).
    pub stand_ms: f64,
    /// Scoring against the truth.
    pub score_ms: f64,
}

/// One scene through the pipeline.
#[derive(Debug, Clone)]
pub struct SceneRun {
    /// The score and verdict.
    pub result: SceneResult,
    /// The recognizer's answer (`None` when the input could not be made, e.g. a render error).
    pub reconstruction: Option<Reconstruction>,
    /// Indices of truth blocks that no view shows at all (no pixel in any `ids` picture): no
    /// picture can recover them, so they are counted apart.
    pub unseen_blocks: Vec<usize>,
    /// Why the views cannot decide the scene, when they cannot ([`undecided_by_views`]): then
    /// declining is the right answer, and the scene is counted apart.
    pub undecided: Option<String>,
    /// The score the recognizer's `ok` answer would have had when the standing check declined
    /// it (`None` when the check changed nothing): how `bench accuracy` measures the check.
    pub declined_by_standing: Option<SceneResult>,
    /// Time per stage.
    pub times: StageTimes,
}

fn ms_since(t: Instant) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}

/// Blocks (indices) that no rendered view shows: their id (index + 1) is in no `ids` picture.
pub fn unseen_blocks(scene: &Scene, views: &[RenderedView]) -> Vec<usize> {
    let mut seen = vec![false; scene.blocks.len()];
    for v in views {
        for &id in v.ids.as_raw() {
            if let Some(s) = (id as usize).checked_sub(1).and_then(|i| seen.get_mut(i)) {
                *s = true;
            }
        }
    }
    (0..seen.len()).filter(|&i| !seen[i]).collect()
}

/// Why the exact drawings `truth_views` of `scene` cannot decide it, if they cannot: a block
/// with no line in any view, or another set of catalog blocks (one block split in two, or two
/// merged: a crack hidden in every view) that draws every view as the truth does. No picture
/// taken from these views can then tell the scene from the alternative (docs/recognizer.md "Recognizer",
/// counted apart like blocks no view shows).
pub fn undecided_by_views(
    scene: &Scene,
    truth_views: &[ObservedView],
    tol_px: f64,
) -> Option<String> {
    let mut drawn = vec![false; scene.blocks.len()];
    for e in truth_views.iter().flat_map(|v| &v.drawing.edges) {
        if let Some(d) = drawn.get_mut(e.block) {
            *d = true;
        }
    }
    if let Some(i) = drawn.iter().position(|d| !d) {
        return Some(format!("block {i} has no line in any view"));
    }
    equally_good_alternative(&scene.blocks, truth_views, tol_px)
}

/// The observed views of rendered pictures: each view's drawing from `source`, its camera and
/// the lights recorded with it.
/// Returns the views and the milliseconds spent in vision.
pub fn observe(
    rendered: &[RenderedView],
    source: &DrawingSource,
) -> Result<(Vec<ObservedView>, f64), crate::vision::VisionError> {
    let t = Instant::now();
    let views = rendered
        .iter()
        .map(|v| {
            let drawing = match source {
                DrawingSource::Truth => v.lines.clone(),
                DrawingSource::Pictures(o) => detect_line_drawing(&v.gray, &v.camera, o)?.drawing,
            };
            Ok(ObservedView {
                drawing,
                camera: v.camera,
                towards_lights: v.towards_lights.clone(),
                edge_radius_mm: v.edge_radius_mm,
            })
        })
        .collect::<Result<Vec<_>, _>>()?;
    let vision_ms = match source {
        DrawingSource::Truth => 0.0,
        DrawingSource::Pictures(_) => ms_since(t),
    };
    Ok((views, vision_ms))
}

/// Recognizes `views`, observed from `rendered` through `source` ([`observe`]), as `blockworld
/// recognize` does: when the drawings were read from the pictures, step 6 reads the pictures
/// too (`recognize_in_pictures`); exact drawings are recognized from the drawings alone. The
/// answer must stand ([`recognize_standing`]).
pub fn recognize_rendered(
    rendered: &[RenderedView],
    views: &[ObservedView],
    source: &DrawingSource,
    opts: &RecognizeOptions,
) -> Result<Recognition, RecognizeError> {
    recognize_rendered_standing(rendered, views, source, opts).map(|s| s.recognition)
}

/// [`recognize_rendered`] with what the standing check did ([`Standing`]).
pub fn recognize_rendered_standing(
    rendered: &[RenderedView],
    views: &[ObservedView],
    source: &DrawingSource,
    opts: &RecognizeOptions,
) -> Result<Standing, RecognizeError> {
    let DrawingSource::Pictures(vision) = source else {
        return recognize_standing(views, &[], opts);
    };
    let pictures: Vec<&image::GrayImage> = rendered.iter().map(|v| &v.gray).collect();
    let first = recognize_in_pictures(views, &pictures, opts)?;
    Ok(answer_of_pictures(first, &pictures, views, vision, opts).0)
}

/// The answer `blockworld recognize` gives for the views `read` from `pictures` (one per
/// view, in the same order) with `vision`, given `first`, the recognizer's answer on them: read again fainter when it declines for what a missed line causes
/// ([`read_again_fainter`]), then held to standing ([`check_answer_stands`]); with the views
/// of the fainter reading that answered (`None`: the first reading's stand). The one home of
/// these two steps, so that `recognize`, `recognize-dataset`, the benches and the gate score
/// the same answer for the same pictures.
pub fn answer_of_pictures(
    first: Recognition,
    pictures: &[&image::GrayImage],
    read: &[ObservedView],
    vision: &VisionOptions,
    opts: &RecognizeOptions,
) -> (Standing, Option<Vec<ObservedView>>) {
    let reading = read_again_fainter(first, pictures, read, vision, opts);
    let standing = check_answer_stands(reading.recognition, &SettleParams::default());
    (standing, reading.views)
}

/// Renders `scene`, recognizes it and scores the answer against it (see the module doc).
/// Failures to render, to see or to recognize become a `failed` result with the reason.
pub fn run_scene(renderer: &Renderer, id: &str, scene: &Scene, opts: &PipelineOptions) -> SceneRun {
    let mut times = StageTimes::default();
    let t = Instant::now();
    let rendered = renderer.render_views(scene, &opts.views, &opts.render);
    times.render_ms = ms_since(t);
    let mut declined_answer = None;
    let answer = rendered
        .as_ref()
        .map_err(|e| NoReconstruction(format!("rendering: {e}")))
        .and_then(|r| {
            let (views, vision_ms) =
                observe(r, &opts.source).map_err(|e| NoReconstruction(format!("vision: {e}")))?;
            times.vision_ms = vision_ms;
            let t = Instant::now();
            let standing = recognize_rendered_standing(r, &views, &opts.source, &opts.recognize)
                .map_err(|e| NoReconstruction(format!("recognizer: {e}")))?;
            let recon = reconstruction(&scene.name, &standing.recognition, opts.layer_tol_mm);
            times.recognize_ms = ms_since(t);
            times.stand_ms = standing.check_ms;
            declined_answer = standing.declined_answer;
            Ok(recon)
        });
    let unseen = rendered
        .as_ref()
        .map(|r| unseen_blocks(scene, r))
        .unwrap_or_default();
    let undecided = rendered.as_ref().ok().and_then(|r| {
        let (truth, _) = observe(r, &DrawingSource::Truth).ok()?;
        undecided_by_views(scene, &truth, opts.recognize.tol_px)
    });
    let t = Instant::now();
    let result = score_suite_scene(
        id,
        scene,
        answer.as_ref().map_err(Clone::clone),
        &opts.score,
    );
    times.score_ms = ms_since(t);
    let declined_by_standing = declined_answer.map(|r| {
        let recon = reconstruction(&scene.name, &r, opts.layer_tol_mm);
        score_suite_scene(id, scene, Ok(&recon), &opts.score)
    });
    SceneRun {
        result,
        reconstruction: answer.ok(),
        unseen_blocks: unseen,
        undecided,
        declined_by_standing,
        times,
    }
}

/// Runs every `(id, scene)` of a suite through [`run_scene`], in order.
pub fn run_suite(
    renderer: &Renderer,
    suite: &[(String, Scene)],
    opts: &PipelineOptions,
) -> Vec<SceneRun> {
    suite
        .iter()
        .map(|(id, scene)| run_scene(renderer, id, scene, opts))
        .collect()
}

/// A run is *confidently wrong* when the recognizer answered `ok` but the answer is not exact:
/// the worst outcome a recognizer can give (docs/recognizer.md "Recognizer").
pub fn is_confidently_wrong(run: &SceneRun) -> bool {
    run.reconstruction.as_ref().is_some_and(|r| r.is_ok())
        && run.result.verdict != crate::score::Verdict::Exact
}
