//! `blockworld compare [--suite DIR]`: Kanade's model against the modified model on the same
//! exact line drawings (thesis Chapter VI "Comparisons of the Two Models", Figures 6.17 and
//! 6.18), with measured numbers printed beside the thesis's. A thesis number is never printed
//! in place of a measurement; where they differ, the row says so.

use anyhow::Context;
use blockworld::camera::{Camera, CameraOptions, CornerView};
use blockworld::csg::reconstruction;
use blockworld::drawing::LineDrawing;
use blockworld::geom::{median, DVec2, DVec3};
use blockworld::kanade::{
    check_labelling, computer_words, depth_rms_px, is_consistent, label_drawing,
    labelling_from_kinds, orthographic_px_per_mm, recover_shape, surface_connection_graph,
    true_line_ends_px, Catalog, ComputerWords, LabelOptions, LabelReport, LineLabel, ShapeRecovery,
};
use blockworld::linedraw::visible_line_drawing;
use blockworld::recognize::{recognize, ObservedView, RecognizeOptions};
use blockworld::scene::{read_scene, Scene};
use blockworld::score::score_reconstruction;
use std::path::{Path, PathBuf};
use std::time::Instant;

use super::label::combinations_text;

/// Options of `blockworld compare`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Folder holding the thesis's cases: single_cube.json, two_cubes_touching.json and
    /// thesis_sample.json.
    #[arg(long, default_value = "scenes")]
    pub scenes: PathBuf,
    /// Also run both models over every scene of this suite (e.g. scenes/bench), four views each.
    #[arg(long)]
    pub suite: Option<PathBuf>,
    /// Corner view of the thesis's cases.
    #[arg(long, default_value = "ne")]
    pub view: String,
    /// Timed repetitions per scene (the median is printed).
    #[arg(long, default_value_t = 50, value_parser = crate::cli::at_least_one::<usize>)]
    pub repeat: usize,
}

/// The models compared: the trihedral catalog as the thesis's count is made (step 2 only), and
/// Kanade's full model on blocks (steps 2 and 3), then the blocks catalog without step 3.
const MODELS: [Model; 3] = [
    Model {
        catalog: Catalog::HuffmanClowes,
        gradient_check: false,
    },
    Model {
        catalog: Catalog::Blocks,
        gradient_check: true,
    },
    Model {
        catalog: Catalog::Blocks,
        gradient_check: false,
    },
];

/// One thesis case: its file, its name in Figure 6.17, and the thesis's numbers.
struct ThesisCase {
    file: &'static str,
    name: &'static str,
    /// Figure 6.17: line labels, junction labels, six-bit words, % saved.
    words: [usize; 3],
    saved_pct: f64,
}

const CASES: [ThesisCase; 3] = [
    ThesisCase {
        file: "single_cube.json",
        name: "cube",
        words: [9, 22, 7],
        saved_pct: 77.42,
    },
    ThesisCase {
        file: "two_cubes_touching.json",
        name: "two cubes of different size",
        words: [18, 65, 15],
        saved_pct: 81.93,
    },
    ThesisCase {
        file: "thesis_sample.json",
        name: "sample of Fig. 6.13",
        words: [27, 100, 20],
        saved_pct: 84.25,
    },
];

/// Everything measured on one drawing.
struct Measured {
    drawing: LineDrawing,
    report: LabelReport,
    words: ComputerWords,
    truth_found: bool,
    rms_mm: Option<f64>,
    kanade_us: f64,
    six_bit_us: f64,
}

/// The modified model on the scene: the recognizer (Chapters IV-V) on the exact drawings of
/// the four corner views (the thesis takes four views of a complex sample), its time in ms
/// (fastest of 3) and its 3D result scored against the truth (verdict and volume IoU).
fn recognizer_time_ms(scene: &Scene, _drawing: &LineDrawing) -> Option<(f64, String)> {
    let points: Vec<DVec3> = scene.world_vertices();
    let views: Vec<ObservedView> = CornerView::ALL
        .iter()
        .map(|&v| {
            let camera = Camera::frame(&points, v, &CameraOptions::default());
            ObservedView::new(visible_line_drawing(scene, &camera), camera)
        })
        .collect();
    let mut best = f64::INFINITY;
    let mut answer = None;
    for _ in 0..3 {
        let t = Instant::now();
        let r = recognize(&views, &RecognizeOptions::default()).ok()?;
        best = best.min(t.elapsed().as_secs_f64() * 1e3);
        answer = Some(r);
    }
    let recon = reconstruction(&scene.name, &answer?, 0.5);
    let score = score_reconstruction(scene, &recon).ok()?;
    Some((
        best,
        format!("{} (IoU {:.4})", score.verdict.as_str(), score.iou),
    ))
}

/// Runs `blockworld compare`.
pub fn run(args: Args) -> anyhow::Result<()> {
    let view = CornerView::parse(&args.view)
        .with_context(|| format!("--view {:?}: use ne, se, sw or nw", args.view))?;
    println!("{}", machine_line());
    let mut rows = [Vec::new(), Vec::new()];
    for case in &CASES {
        let path = args.scenes.join(case.file);
        let scene = read_scene(&path).with_context(|| format!("reading {}", path.display()))?;
        for (k, model) in MODELS[..2].iter().enumerate() {
            let m = measure(&scene, view, *model, args.repeat)
                .with_context(|| format!("measuring {}", path.display()))?;
            rows[k].push((case, scene.clone(), m));
        }
    }
    print_words_table(&rows[1]);
    print_search_table(&rows[0], MODELS[0]);
    print_search_table(&rows[1], MODELS[1]);
    if let Some(dir) = &args.suite {
        run_suite(dir)?;
    }
    Ok(())
}

fn machine_line() -> String {
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|t| {
            t.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|s| s.trim().to_string())
        })
        .unwrap_or_else(|| "unknown CPU".into());
    let cores = std::thread::available_parallelism().map_or(0, |n| n.get());
    let load = std::fs::read_to_string("/proc/loadavg")
        .map(|l| l.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_else(|_| "unknown".into());
    let profile = if cfg!(debug_assertions) {
        "debug build"
    } else {
        "release build"
    };
    format!("{cpu}, {cores} cores, load average {load}, {profile}; drawings: exact (linedraw), orthographic, 512 x 480")
}

fn camera(scene: &Scene, view: CornerView) -> Camera {
    let pts: Vec<DVec3> = scene.world_vertices();
    Camera::frame(&pts, view, &CameraOptions::default())
}

/// The true labels and the true 3D line ends (x px, y px, depth towards the viewer in px).
fn truth_of(
    scene: &Scene,
    cam: &Camera,
    d: &LineDrawing,
) -> (Option<Vec<LineLabel>>, Vec<Option<[DVec3; 2]>>) {
    let centres: Vec<DVec2> = scene
        .blocks
        .iter()
        .map(|b| cam.picture_from_world(b.center_mm).truncate())
        .collect();
    (labelling_from_kinds(d, &centres), true_line_ends_px(d, cam))
}

/// Kanade's model as run here: a catalog, the outer boundary occluding (Appendix A step 2),
/// and optionally the gradient check of step 3 before the search.
#[derive(Debug, Clone, Copy)]
struct Model {
    catalog: Catalog,
    gradient_check: bool,
}

impl Model {
    fn name(self) -> String {
        if self.gradient_check {
            format!("{} + gradient check", self.catalog.name())
        } else {
            self.catalog.name().to_string()
        }
    }
}

fn options(model: Model) -> LabelOptions {
    LabelOptions {
        catalog: model.catalog,
        gradient_check: model.gradient_check,
        boundary_occluding: true,
        limit: 20,
        node_budget: 200_000,
        ..Default::default()
    }
}

type Chosen = (Vec<Option<LineLabel>>, Option<ShapeRecovery>);

/// Kanade's steps on one drawing: label, then choose the labelling whose gradients break the
/// fewest links (Appendix A step 3; the first on a tie) and recover its shape.
fn kanade(d: &LineDrawing, model: Model) -> anyhow::Result<(LabelReport, Option<Chosen>)> {
    let report = label_drawing(d, &options(model), &mut |_| {})?;
    let mut best: Option<(usize, Chosen)> = None;
    for l in &report.labellings {
        let rec = recover_shape(d, l).ok();
        let bad = rec.as_ref().map_or(usize::MAX, |r| r.inconsistent_links);
        if best.as_ref().is_none_or(|b| bad < b.0) {
            best = Some((bad, (l.clone(), rec)));
        }
    }
    Ok((report, best.map(|b| b.1)))
}

/// Both models on one scene's view: Kanade's labelling, SCG and gradients timed together; the
/// six-bit side timed as the coding of every vertex (`LineDrawing::finalize`, Chapter IV).
fn measure(
    scene: &Scene,
    view: CornerView,
    model: Model,
    repeat: usize,
) -> anyhow::Result<Measured> {
    let catalog = model.catalog;
    let cam = camera(scene, view);
    let drawing = visible_line_drawing(scene, &cam);
    let (truth, truth_ends) = truth_of(scene, &cam, &drawing);
    let mut times = Vec::with_capacity(repeat);
    let mut result = None;
    for _ in 0..repeat {
        let t = Instant::now();
        result = Some(kanade(&drawing, model)?);
        times.push(t.elapsed().as_secs_f64() * 1e6);
    }
    let (report, chosen) = result.context("no run")?;
    let kanade_us = median(&mut times).unwrap_or(f64::NAN);
    let mut times = Vec::with_capacity(repeat);
    for _ in 0..repeat {
        let mut d = drawing.clone();
        let t = Instant::now();
        d.finalize();
        times.push(t.elapsed().as_secs_f64() * 1e6);
    }
    let six_bit_us = median(&mut times).unwrap_or(f64::NAN);
    let labels = chosen.as_ref().map(|c| c.0.clone());
    let scg = surface_connection_graph(&drawing, labels.as_deref().unwrap_or(&[]))?;
    let words = computer_words(&drawing, &scg);
    let truth_found = match &truth {
        Some(t) => is_consistent(&check_labelling(&drawing, t, catalog, true)?),
        None => false,
    };
    let rms_mm = chosen
        .as_ref()
        .and_then(|c| c.1.as_ref())
        .and_then(|rec| depth_rms_px(rec, &truth_ends))
        .map(|(px, _)| px / orthographic_px_per_mm(&cam));
    Ok(Measured {
        drawing,
        report,
        words,
        truth_found,
        rms_mm,
        kanade_us,
        six_bit_us,
    })
}

/// A measured number with the thesis's beside it when they differ.
fn vs(measured: String, thesis: String) -> String {
    if measured == thesis {
        format!("{measured} (= thesis)")
    } else {
        format!("{measured} (thesis: {thesis}; differs)")
    }
}

fn print_words_table(rows: &[(&ThesisCase, Scene, Measured)]) {
    println!("\nFigure 6.17, computer words (the labelling Kanade's model settles on: blocks catalog, gradient check; rules in docs/kanade.md \"Kanade's model\"):\n");
    let mut head = "| words |".to_string();
    let mut sep = "|---|".to_string();
    for (c, _, _) in rows {
        head += &format!(" {} |", c.name);
        sep += "---|";
    }
    println!("{head}\n{sep}");
    let names = [
        "line labels",
        "junction labels + 5 per SCG link",
        "six-bit codes (one per vertex)",
    ];
    for (k, name) in names.iter().enumerate() {
        let mut line = format!("| {name} |");
        for (c, _, m) in rows {
            let got = [
                m.words.line_labels,
                m.words.junction_labels,
                m.words.six_bit,
            ][k];
            line += &format!(" {} |", vs(got.to_string(), c.words[k].to_string()));
        }
        println!("{line}");
    }
    let mut line = "| memory saved by six-bit coding |".to_string();
    for (c, _, m) in rows {
        line += &format!(
            " {} |",
            vs(
                format!("{:.2}%", 100.0 * m.words.saved()),
                format!("{:.2}%", c.saved_pct)
            )
        );
    }
    println!("{line}");
    let mut line = "| SCG links (surface pairs) |".to_string();
    for (_, _, m) in rows {
        line += &format!(" {} |", m.words.scg_links);
    }
    println!("{line}");
}

fn print_search_table(rows: &[(&ThesisCase, Scene, Measured)], model: Model) {
    println!("\nFigure 6.18, labels searched, time and accuracy ({}, outer boundary occluding; median of the timed runs):\n", model.name());
    println!("| scene | Kanade: combinations after the initial constraint | after Waltz filtering | search nodes | consistent labellings | true labelling among them | six-bit: line look-ups (vertices x 6) | Kanade µs (label + SCG + gradients) | six-bit coding µs | recognizer ms | Kanade 3D RMS mm (up to depth) | modified model 3D |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    for (c, scene, m) in rows {
        let combos = combinations_text(&m.report.stats.combinations_before);
        let combos = if c.name == "cube" {
            vs(combos, "1,216".into())
        } else {
            combos
        };
        let lookups = 6 * m.words.six_bit;
        let lookups = if c.name == "cube" {
            vs(lookups.to_string(), "42".into())
        } else {
            lookups.to_string()
        };
        let (rec, rec_3d) = recognizer_time_ms(scene, &m.drawing).map_or(
            ("declined the input".to_string(), "none".to_string()),
            |(t, s)| (format!("{t:.3}"), s),
        );
        let count = if m.report.count.exact {
            m.report.count.value.to_string()
        } else {
            format!("≥ {}", m.report.count.value)
        };
        println!(
            "| {} | {combos} | {} | {} | {count} | {} | {lookups} | {:.1} | {:.1} | {rec} | {} | {rec_3d} |",
            c.name,
            combinations_text(&m.report.stats.combinations_after),
            m.report.stats.nodes,
            if m.truth_found { "yes" } else { "no" },
            m.kanade_us,
            m.six_bit_us,
            m.rms_mm.map_or("none".into(), |r| format!("{r:.2e}")),
        );
    }
}

/// One suite drawing's outcome for one catalog.
#[derive(Default, Clone)]
struct SuiteRow {
    supported: bool,
    count: u128,
    exact: bool,
    truth_found: bool,
    chosen_is_truth: bool,
    uncatalogued: bool,
    rms_mm: Option<f64>,
    ms: f64,
}

fn suite_row(scene: &Scene, view: CornerView, model: Model) -> anyhow::Result<SuiteRow> {
    let catalog = model.catalog;
    let cam = camera(scene, view);
    let d = visible_line_drawing(scene, &cam);
    let (truth, ends) = truth_of(scene, &cam, &d);
    let t = Instant::now();
    let (report, chosen) = kanade(&d, model)?;
    let ms = t.elapsed().as_secs_f64() * 1e3;
    let truth_found = match &truth {
        Some(t) => is_consistent(&check_labelling(&d, t, catalog, true)?),
        None => false,
    };
    let chosen_is_truth = match (&truth, &chosen) {
        (Some(t), Some((l, _))) => t.iter().zip(l).all(|(a, b)| b.is_none_or(|b| b == *a)),
        _ => false,
    };
    let rms_mm = chosen
        .as_ref()
        .and_then(|c| c.1.as_ref())
        .and_then(|rec| depth_rms_px(rec, &ends))
        .map(|(px, _)| px / orthographic_px_per_mm(&cam));
    Ok(SuiteRow {
        supported: scene.expect.as_ref().is_none_or(|e| e.supported),
        count: report.count.value,
        exact: report.count.exact,
        truth_found,
        chosen_is_truth,
        uncatalogued: !report.uncatalogued.is_empty(),
        rms_mm,
        ms,
    })
}

fn run_suite(dir: &Path) -> anyhow::Result<()> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .with_context(|| format!("reading the suite folder {}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .collect();
    files.sort();
    let views = [
        CornerView::Ne,
        CornerView::Se,
        CornerView::Sw,
        CornerView::Nw,
    ];
    println!("\nSuite {} ({} scenes x 4 views, exact drawings; outer boundary occluding; counts capped at 200,000 search nodes):\n", dir.display(), files.len());
    println!("| catalog | drawings | true labelling among the consistent ones | exactly one labelling | none | labellings: median / max (exact counts) | count only a lower bound | drawings with junctions outside the catalog | chosen labelling = truth | Kanade 3D RMS mm: median / max (drawings) | ms per drawing |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    for model in MODELS {
        let mut rows = Vec::new();
        for f in &files {
            let scene = read_scene(f).with_context(|| format!("reading {}", f.display()))?;
            for view in views {
                rows.push(suite_row(&scene, view, model)?);
            }
        }
        print_suite_line(
            &format!("{} (supported scenes)", model.name()),
            rows.iter().filter(|r| r.supported),
        );
        print_suite_line(&format!("{} (all scenes)", model.name()), rows.iter());
    }
    Ok(())
}

fn pct(n: usize, of: usize) -> String {
    format!("{:.1}%", 100.0 * n as f64 / of.max(1) as f64)
}

fn print_suite_line<'a>(name: &str, rows: impl Iterator<Item = &'a SuiteRow>) {
    let rows: Vec<&SuiteRow> = rows.collect();
    let n = rows.len();
    let share = |f: &dyn Fn(&SuiteRow) -> bool| pct(rows.iter().filter(|r| f(r)).count(), n);
    let mut counts: Vec<u128> = rows.iter().filter(|r| r.exact).map(|r| r.count).collect();
    counts.sort_unstable();
    let mut rms: Vec<f64> = rows.iter().filter_map(|r| r.rms_mm).collect();
    rms.sort_by(f64::total_cmp);
    let ms = rows.iter().map(|r| r.ms).sum::<f64>() / n.max(1) as f64;
    println!(
        "| {name} | {n} | {} | {} | {} | {} / {} | {} | {} | {} | {} | {ms:.2} |",
        share(&|r| r.truth_found),
        share(&|r| r.exact && r.count == 1),
        share(&|r| r.exact && r.count == 0),
        counts
            .get(counts.len() / 2)
            .map_or("-".into(), |c| c.to_string()),
        counts.last().map_or("-".into(), |c| c.to_string()),
        share(&|r| !r.exact),
        share(&|r| r.uncatalogued),
        share(&|r| r.chosen_is_truth),
        match (rms.get(rms.len() / 2), rms.last()) {
            (Some(m), Some(x)) => format!("{m:.2} / {x:.2} ({})", rms.len()),
            _ => "-".into(),
        },
    );
}
