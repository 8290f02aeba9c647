//! `blockworld bench accuracy --pictures DIR`: the recognizer on pictures someone else drew
//! (docs/yardstick.md). DIR is laid out as a dataset: per scene a folder with `scene.json` (the
//! truth), and per view `view_<v>.png` beside the `camera_<v>.json` it was drawn through, as
//! `bench/blender/render_dataset.py` writes it. Every scene is recognized from those pictures
//! alone, by `blockworld recognize`'s own reading of a folder (vision front end, the modified
//! Kanade recognizer with its picture-aware check, the fainter readings, the standing check) and
//! scored; in the same run blockworld draws the same scenes through the same cameras in its
//! line art and its photo look, so the figures stand side by side on the same scenes.

use super::accuracy::Args;
use crate::cli::commands::recognize::recognize_folder;
use crate::cli::files::read_camera;
use anyhow::{bail, Context};
use blockworld::camera::{Camera, CornerView};
use blockworld::csg::reconstruction;
use blockworld::pipeline::{run_scene, run_suite, DrawingSource, PipelineOptions};
use blockworld::render::{Look, RenderOptions, Renderer};
use blockworld::scene::{read_scene, Scene};
use blockworld::score::{
    score_suite_scene, summarize_by_family, NoReconstruction, SceneResult, ScoreOptions, Verdict,
};
use blockworld::vision::VisionOptions;
use glam::DVec3;
use std::path::{Path, PathBuf};

/// Largest difference between a camera file's matrix entry and blockworld's own camera for the
/// same scene and view: the files are written with 17 significant digits, so the two agree far
/// closer than this when the view options match.
const CAMERA_TOL: f64 = 1e-9;

/// One scene of the pictures' folder: its id, truth and the folder holding its views.
struct PictureScene {
    id: String,
    truth: Scene,
    folder: PathBuf,
}

/// One way of drawing the scenes and its results.
struct Source {
    name: String,
    results: Vec<SceneResult>,
}

/// Runs `bench accuracy --pictures DIR` (see the module doc).
pub fn run(args: &Args, dir: &Path) -> anyhow::Result<()> {
    let views = args.view.corner_views()?;
    if views.is_empty() {
        bail!("--views: no view given; name one or more of ne, se, sw, nw");
    }
    let render = args.view.render_options()?;
    let varied = render.look == Look::PhotoVaried;
    let scenes = read_picture_scenes(dir, &views)?;
    for s in &scenes {
        if varied {
            look_seed(s)?;
        } else {
            check_cameras(s, &views, &render)?;
        }
    }
    let name = dir.display().to_string();
    let recognize = super::accuracy::recognize_options(args);
    let pictured = crate::cli::progress::with_progress(
        "bench accuracy --pictures",
        "scenes",
        scenes.len() as u64,
        |p| {
            let mut out = Vec::new();
            for (k, s) in scenes.iter().enumerate() {
                out.push(recognize_pictures(s, &views, &recognize));
                p(k as u64 + 1, scenes.len() as u64);
            }
            out
        },
    );
    let renderer = Renderer::new(args.view.backend()?).context("starting the renderer")?;
    print!("{}", super::machine::banner(Some(&renderer)));
    let suite: Vec<(String, Scene)> = scenes
        .iter()
        .map(|s| (s.id.clone(), s.truth.clone()))
        .collect();
    let mut sources = vec![Source {
        name,
        results: pictured,
    }];
    let own_looks: &[(Look, &str)] = if varied {
        &[(Look::PhotoVaried, "blockworld varied photo look")]
    } else {
        &[
            (Look::LineArt, "blockworld line art"),
            (Look::Photo, "blockworld photo look"),
        ]
    };
    for &(look, label) in own_looks {
        let opts = PipelineOptions {
            render: RenderOptions { look, ..render },
            views: views.clone(),
            source: DrawingSource::Pictures(VisionOptions::default()),
            recognize: super::accuracy::recognize_options(args),
            ..PipelineOptions::default()
        };
        let runs = if varied {
            own_varied_runs(&renderer, &scenes, &opts)?
        } else {
            run_suite(&renderer, &suite, &opts)
        };
        sources.push(Source {
            name: label.to_string(),
            results: runs.into_iter().map(|r| r.result).collect(),
        });
    }
    print!("{}", side_by_side(&sources));
    if varied {
        print!("{}", factor_tables(&scenes, &render, &sources)?);
    }
    print!(
        "{}",
        super::accuracy::family_table(&summarize_by_family(&sources[0].results))
    );
    write_report(args, dir, &views, &sources)
}

/// The scene folders of `dir` that hold `scene.json`, sorted by id, each checked to hold every
/// view's picture and camera.
fn read_picture_scenes(dir: &Path, views: &[CornerView]) -> anyhow::Result<Vec<PictureScene>> {
    let entries = std::fs::read_dir(dir).with_context(|| {
        format!(
            "--pictures {}: not a folder; give the output of bench/blender/render_dataset.py",
            dir.display()
        )
    })?;
    let mut folders: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.join("scene.json").is_file())
        .collect();
    folders.sort();
    if folders.is_empty() {
        bail!(
            "--pictures {}: no scene folders with scene.json; lay it out as a dataset (docs/yardstick.md \"The bench\")",
            dir.display()
        );
    }
    folders
        .into_iter()
        .map(|folder| {
            for v in views {
                for file in [format!("view_{}.png", v.name()), format!("camera_{}.json", v.name())] {
                    if !folder.join(&file).is_file() {
                        bail!(
                            "{}: missing; every scene needs each view's picture and camera (finish the render, or drop {} from --views)",
                            folder.join(file).display(),
                            v.name()
                        );
                    }
                }
            }
            let id = folder.file_name().unwrap_or_default().to_string_lossy().into_owned();
            let truth = read_scene(&folder.join("scene.json"))?;
            Ok(PictureScene { id, truth, folder })
        })
        .collect()
}

/// The seed of scene `s`'s draw of the varied look, read from its `look.json`
/// (docs/varied-look.md "look.json"), which `bench/blender/render_dataset.py` copies beside the
/// pictures; an error naming the file when it is missing or has no seed.
fn look_seed(s: &PictureScene) -> anyhow::Result<u64> {
    let path = s.folder.join("look.json");
    let text = std::fs::read_to_string(&path).with_context(|| {
        format!(
            "{}: missing; --look photo_varied scores pictures of a varied-look dataset (generate --look photo_varied, then render_dataset.py, which copies look.json)",
            path.display()
        )
    })?;
    let look: serde_json::Value = serde_json::from_str(&text)
        .with_context(|| format!("{}: not JSON; regenerate the dataset", path.display()))?;
    look.get("seed")
        .and_then(serde_json::Value::as_u64)
        .with_context(|| {
            format!(
                "{}: no integer \"seed\"; regenerate the dataset with generate --look photo_varied",
                path.display()
            )
        })
}

/// The per-factor table of every source (docs/varied-look.md "Accuracy per factor"), the
/// scenes binned by their draws (each re-drawn from its `look.json` seed).
fn factor_tables(
    scenes: &[PictureScene],
    render: &RenderOptions,
    sources: &[Source],
) -> anyhow::Result<String> {
    let mut looks = Vec::new();
    for s in scenes {
        let seed = look_seed(s)?;
        let opts = RenderOptions { seed, ..*render };
        looks.extend(opts.look_draw(s.truth.blocks.len()));
    }
    Ok(sources
        .iter()
        .map(|src| {
            format!(
                "{}:\n{}",
                src.name,
                super::accuracy::factor_table(&src.results, &looks)
            )
        })
        .collect())
}

/// blockworld's own varied look of each scene, in the draw its `look.json` seeds, through the
/// pipeline (the cameras are the draw's, as the pictures' are).
fn own_varied_runs(
    renderer: &Renderer,
    scenes: &[PictureScene],
    opts: &PipelineOptions,
) -> anyhow::Result<Vec<blockworld::pipeline::SceneRun>> {
    scenes
        .iter()
        .map(|s| {
            let mut o = opts.clone();
            o.render.seed = look_seed(s)?;
            Ok(run_scene(renderer, &s.id, &s.truth, &o))
        })
        .collect()
}

/// Fails unless every camera file is the camera blockworld frames for the scene with the view
/// options given: only then are blockworld's own looks drawn through the same cameras.
fn check_cameras(
    s: &PictureScene,
    views: &[CornerView],
    render: &RenderOptions,
) -> anyhow::Result<()> {
    let points: Vec<DVec3> = s.truth.world_vertices();
    for &v in views {
        let path = s.folder.join(format!("camera_{}.json", v.name()));
        let file = read_camera(&path)?;
        let ours = Camera::frame(&points, v, &render.camera);
        let differs = file
            .view_from_world
            .iter()
            .chain(&file.clip_from_view)
            .zip(ours.view_from_world.iter().chain(&ours.clip_from_view))
            .any(|(a, b)| (a - b).abs() > CAMERA_TOL * a.abs().max(1.0));
        if differs || file.size_px != ours.size_px {
            bail!(
                "{}: not the camera blockworld frames for this scene with these view options; pass the options the dataset was generated with (its dataset.json \"render\": --projection, --fov, --size, --elevation, --pixel-aspect)",
                path.display()
            );
        }
    }
    Ok(())
}

/// Recognizes one scene from its pictures with `blockworld recognize`'s own reading of a folder
/// (the fainter readings and the standing check included: `recognize::recognize_folder`) and
/// scores it; an unreadable file or a vision or recognizer error is a `failed` result with the
/// reason.
fn recognize_pictures(
    s: &PictureScene,
    views: &[CornerView],
    recognize: &blockworld::recognize::RecognizeOptions,
) -> SceneResult {
    let opts = PipelineOptions::default();
    let answer = recognize_folder(&s.folder, views, false, false, recognize)
        .map(|(_, r)| reconstruction(&s.truth.name, &r, opts.layer_tol_mm))
        .map_err(|e| NoReconstruction(format!("{e:#}")));
    score_suite_scene(
        &s.id,
        &s.truth,
        answer.as_ref().map_err(Clone::clone),
        &ScoreOptions::default(),
    )
}

/// Exact, declined and confidently wrong of each source over the supported scenes, and over
/// all scenes.
fn side_by_side(sources: &[Source]) -> String {
    let mut t = String::from(
        "| pictures | supported scenes | exact | declined | confidently wrong | other | all scenes exact |\n|---|---|---|---|---|---|---|\n",
    );
    for s in sources {
        let supported: Vec<&SceneResult> = s.results.iter().filter(|r| r.supported).collect();
        let n = supported.len();
        let count = |f: &dyn Fn(&SceneResult) -> bool| supported.iter().filter(|r| f(r)).count();
        let exact = count(&|r| r.verdict == Verdict::Exact);
        let declined = count(&|r| r.verdict == Verdict::Unsupported);
        let wrong = count(&|r| r.confidently_wrong);
        let all_exact = s
            .results
            .iter()
            .filter(|r| r.verdict == Verdict::Exact)
            .count();
        t.push_str(&format!(
            "| {} | {n} | {exact} ({}) | {declined} ({}) | {wrong} ({}) | {} | {all_exact} of {} |\n",
            s.name,
            percent(exact, n),
            percent(declined, n),
            percent(wrong, n),
            n - exact - declined - wrong,
            s.results.len()
        ));
    }
    t
}

fn percent(part: usize, whole: usize) -> String {
    format!("{:.0}%", 100.0 * part as f64 / whole.max(1) as f64)
}

/// Writes every source's per-scene results to `--json-out`.
fn write_report(
    args: &Args,
    dir: &Path,
    views: &[CornerView],
    sources: &[Source],
) -> anyhow::Result<()> {
    let report = serde_json::json!({
        "pictures": dir.display().to_string(),
        "views": views.iter().map(|v| v.name()).collect::<Vec<_>>(),
        "sources": sources.iter().map(|s| serde_json::json!({
            "name": s.name,
            "families": summarize_by_family(&s.results),
            "scenes": s.results,
        })).collect::<Vec<_>>(),
    });
    super::accuracy::write_report(&args.json_out, &report)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cli::commands::recognize::read_view;
    use blockworld::camera::{camera_json, Projection};
    use blockworld::geom::{distance_to_segment_px, DVec2};
    use blockworld::recognize::{draw_hypothesis, recognize_in_pictures, ObservedView};
    use blockworld::scene::{write_scene, Block, ReconStatus};
    use image::GrayImage;

    /// The folder `s000000` of `root` holding the scene file of one block of type `block_type`
    /// on the floor at the origin.
    fn one_block_folder(root: &Path, block_type: &str) -> (PathBuf, Scene) {
        let folder = root.join("s000000");
        std::fs::create_dir_all(&folder).unwrap();
        let block = Block::new(block_type, DVec3::new(0.0, 7.5, 0.0), 0.0);
        let scene = Scene::new("s000000", vec![block]);
        write_scene(&folder.join("scene.json"), &scene).unwrap();
        (folder, scene)
    }

    /// A one-block scene folder with the ne camera framed by `projection` (no picture yet).
    fn scene_folder(root: &Path, projection: Projection) -> (PathBuf, Scene) {
        let (folder, scene) = one_block_folder(root, "b30");
        let mut render = RenderOptions::default();
        render.camera.projection = projection;
        let points: Vec<DVec3> = scene.world_vertices();
        let camera = Camera::frame(&points, CornerView::Ne, &render.camera);
        std::fs::write(folder.join("camera_ne.json"), camera_json(&camera)).unwrap();
        (folder, scene)
    }

    /// A folder of the four corner views of one `b15` cube, its edges inked `ink` on a floor of
    /// gray 150 (a line 1.6 px wide), each beside its camera; returns the folder's root.
    fn faint_cube_folder(root: &Path, ink: u8) -> PathBuf {
        let (folder, scene) = one_block_folder(root, "b15");
        let render = RenderOptions::default();
        for view in CornerView::ALL {
            let camera = Camera::frame(&scene.world_vertices(), view, &render.camera);
            let d = draw_hypothesis(&scene.blocks, &camera);
            let [w, h] = camera.size_px;
            let picture = GrayImage::from_fn(w, h, |x, r| {
                let p = DVec2::new(f64::from(x) + 0.5, f64::from(h - r) - 0.5);
                let inked = d
                    .lines
                    .iter()
                    .any(|&[i, j]| distance_to_segment_px(p, d.points[i], d.points[j]) <= 0.8);
                image::Luma([if inked { ink } else { 150 }])
            });
            let name = view.name();
            picture
                .save(folder.join(format!("view_{name}.png")))
                .unwrap();
            let camera_file = folder.join(format!("camera_{name}.json"));
            std::fs::write(camera_file, camera_json(&camera)).unwrap();
        }
        root.to_path_buf()
    }

    /// Someone else's pictures are recognized as `blockworld recognize` recognizes them: edges
    /// 16 gray levels from the floor, under Chapter VI's threshold once smoothed, are answered
    /// by a fainter reading (the first reading alone declines them); edges 2 levels from the
    /// floor are declined, never answered wrong.
    #[test]
    fn faint_pictures_are_read_again_fainter_as_recognize_reads_them() {
        for (ink, verdict) in [(134, Verdict::Exact), (148, Verdict::Unsupported)] {
            let dir = tempfile::tempdir().unwrap();
            let root = faint_cube_folder(dir.path(), ink);
            let scenes = read_picture_scenes(&root, &CornerView::ALL).unwrap();
            let read = |v| read_view(&scenes[0].folder, v, false, false).unwrap();
            let (observed, pictures): (Vec<ObservedView>, Vec<Option<GrayImage>>) =
                CornerView::ALL.into_iter().map(read).unzip();
            let pictures: Vec<&GrayImage> = pictures.iter().flatten().collect();
            let opts = PipelineOptions::default().recognize;
            let first = recognize_in_pictures(&observed, &pictures, &opts).unwrap();
            assert_eq!(first.status, ReconStatus::Unsupported, "ink {ink}");
            let r = recognize_pictures(&scenes[0], &CornerView::ALL, &opts);
            assert_eq!(r.verdict, verdict, "ink {ink}: {r:?}");
            assert!(!r.confidently_wrong, "ink {ink}");
        }
    }

    #[test]
    fn a_missing_picture_is_named_with_the_fix() {
        let dir = tempfile::tempdir().unwrap();
        let (folder, _) = scene_folder(dir.path(), Projection::Orthographic);
        let e = read_picture_scenes(dir.path(), &[CornerView::Ne])
            .err()
            .unwrap()
            .to_string();
        assert!(
            e.contains("view_ne.png: missing") && e.contains("--views"),
            "{e}"
        );
        image::GrayImage::new(4, 4)
            .save(folder.join("view_ne.png"))
            .unwrap();
        let scenes = read_picture_scenes(dir.path(), &[CornerView::Ne]).unwrap();
        assert_eq!(scenes.len(), 1);
        assert_eq!(scenes[0].id, "s000000");
    }

    #[test]
    fn cameras_of_other_view_options_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let (folder, truth) = scene_folder(dir.path(), Projection::Perspective { fov_y_deg: 30.0 });
        let s = PictureScene {
            id: "s000000".into(),
            truth,
            folder,
        };
        let orthographic = RenderOptions::default();
        let e = check_cameras(&s, &[CornerView::Ne], &orthographic)
            .err()
            .unwrap()
            .to_string();
        assert!(
            e.contains("camera_ne.json") && e.contains("--projection"),
            "{e}"
        );
        let mut perspective = RenderOptions::default();
        perspective.camera.projection = Projection::Perspective { fov_y_deg: 30.0 };
        check_cameras(&s, &[CornerView::Ne], &perspective).unwrap();
    }

    #[test]
    fn side_by_side_counts_supported_scenes_only() {
        let result = |id: &str, supported: bool, verdict: Verdict, wrong: bool| SceneResult {
            id: id.into(),
            family: "row".into(),
            supported,
            verdict,
            iou: 0.0,
            f1: 0.0,
            truth_blocks: 0,
            recon_blocks: 0,
            detected_blocks: 0,
            mean_center_error_mm: None,
            layers_right: false,
            flagged: false,
            unexpected_pass: false,
            confidently_wrong: wrong,
            note: None,
        };
        let source = Source {
            name: "p".into(),
            results: vec![
                result("a", true, Verdict::Exact, false),
                result("b", true, Verdict::Unsupported, false),
                result("c", true, Verdict::Partial, true),
                result("d", false, Verdict::Exact, false),
            ],
        };
        let t = side_by_side(&[source]);
        assert!(
            t.contains("| p | 3 | 1 (33%) | 1 (33%) | 1 (33%) | 0 | 2 of 4 |"),
            "{t}"
        );
    }

    /// A varied-look picture folder must carry the scene's look.json with its seed: a missing
    /// file and one without a seed are named with the fix; a seed beyond i64 is read whole.
    #[test]
    fn a_varied_scene_needs_its_look_json_seed() {
        let dir = tempfile::tempdir().unwrap();
        let (folder, truth) = scene_folder(dir.path(), Projection::Orthographic);
        let s = PictureScene {
            id: "s000000".into(),
            truth,
            folder: folder.clone(),
        };
        let e = format!("{:#}", look_seed(&s).unwrap_err());
        assert!(
            e.contains("look.json: missing") && e.contains("render_dataset.py"),
            "{e}"
        );
        std::fs::write(
            folder.join("look.json"),
            r#"{"format": "blockworld-look/1"}"#,
        )
        .unwrap();
        let e = format!("{:#}", look_seed(&s).unwrap_err());
        assert!(e.contains("no integer \"seed\""), "{e}");
        let seed = r#"{"format": "blockworld-look/1", "seed": 13606263358458041519}"#;
        std::fs::write(folder.join("look.json"), seed).unwrap();
        assert_eq!(look_seed(&s).unwrap(), 13_606_263_358_458_041_519);
    }
}
