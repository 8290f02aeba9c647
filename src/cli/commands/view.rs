//! `blockworld view MODEL -o OUT.png|OUT.svg [options]`: the thesis's viewer (Chapter II
//! eq. 2.2-2.8, Chapter VI "Display the Final Sample", Figures 6.7-6.12). Its options mirror
//! the thesis's menu: r (MODEL: a scene, a reconstruction or the Appendix B data files),
//! f `--from`, a `--at`, u `--up`, z `--view-angle`, m `--move-from`, d `--world`; and, as
//! Chapter VII recommends, `--viewports`, `--hidden-lines remove`, `--shade` and `--overlay`.

use anyhow::{bail, Context};
use blockworld::export::{parse_thesis_files, thesis_model_to_scene, Truncation};
use blockworld::geom::DVec3;
use blockworld::io::write_atomic;
use blockworld::output::encode_png_rgb8;
use blockworld::scene::{read_reconstruction, Scene};
use blockworld::view::{
    draw_sheet, rasterize_sheet, sheet_to_svg, wire_model, HiddenLines, Role, SheetOptions,
    ViewParams, WireModel,
};
use std::path::{Path, PathBuf};

/// Options of `blockworld view`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The model (menu r): a scene or reconstruction file (.json), or the Appendix B data files
    /// as PREFIX, PREFIX_vertices.txt or PREFIX_connections.txt.
    pub model: PathBuf,
    /// Output picture: .png (raster) or .svg (vector).
    #[arg(short, long)]
    pub output: PathBuf,
    /// The From point (menu f), world mm: x,y,z. Default: from the south-east corner above,
    /// far enough to see the whole model.
    #[arg(long, allow_hyphen_values = true)]
    pub from: Option<String>,
    /// The At point (menu a), world mm: x,y,z. Default: the centre of the model's bounds.
    #[arg(long, allow_hyphen_values = true)]
    pub at: Option<String>,
    /// The Up direction (menu u): x,y,z (Figures 6.7-6.10 use 1,0,0  0,0,1  0,1,0  2,1,3).
    #[arg(long, default_value = "0,1,0", allow_hyphen_values = true)]
    pub up: String,
    /// The view angle in degrees (menu z; eq. 2.6): smaller magnifies.
    #[arg(long, default_value_t = 60.0)]
    pub view_angle: f64,
    /// Move From toward At by this many mm (menu m, the arrow keys); negative moves away.
    #[arg(long, allow_hyphen_values = true)]
    pub move_from: Option<f64>,
    /// Print the world coordinates of every vertex (menu d).
    #[arg(long)]
    pub world: bool,
    /// Viewports on the sheet, each From turned 360/N degrees further about At (Chapter VII).
    #[arg(long, default_value_t = 1)]
    pub viewports: u32,
    /// show (the thesis's wireframe) or remove (Chapter VII hidden-line removal).
    #[arg(long, default_value = "show")]
    pub hidden_lines: String,
    /// Fill faces with flat shading (Chapter VII); removes hidden lines; .png only; at most
    /// 250 blocks (MODEL and --overlay together) times --viewports.
    #[arg(long)]
    pub shade: bool,
    /// A truth scene to draw under MODEL: truth in blue, MODEL (the reconstruction) in red.
    #[arg(long)]
    pub overlay: Option<PathBuf>,
    /// Sheet size in pixels, WxH.
    #[arg(long, default_value = "512x512")]
    pub size: String,
    /// Read Appendix B data files as a printed fragment (fewer vertices than declared).
    #[arg(long)]
    pub fragment: bool,
}

/// Runs `blockworld view`.
pub fn run(args: Args) -> anyhow::Result<()> {
    let svg = output_is_svg(&args.output)?;
    if svg && args.shade {
        bail!(
            "--shade needs a .png output (shading uses a depth buffer); drop --shade or write .png"
        );
    }
    let mut inputs = model_files(&args.model);
    inputs.extend(args.overlay.iter().flat_map(|o| model_files(o)));
    let inputs: Vec<&Path> = inputs.iter().map(PathBuf::as_path).collect();
    crate::cli::files::check_output(&args.output, &inputs)?;
    let truncation = if args.fragment {
        Truncation::AllowFragment
    } else {
        Truncation::Strict
    };
    let model = read_named_model("the model", &args.model, truncation)?;
    let truth = match &args.overlay {
        Some(path) => Some(read_named_model("the --overlay file", path, truncation)?),
        None => None,
    };
    let (models, scenes) = match &truth {
        Some(t) => (
            vec![
                wire_model(t, Role::Truth),
                wire_model(&model, Role::Reconstruction),
            ],
            vec![t, &model],
        ),
        None => (vec![wire_model(&model, Role::Model)], vec![&model]),
    };
    if args.world {
        out!("{}", world_table(&models))?;
    }
    check_shaded_work(&args, &scenes)?;
    let params = view_params(&args, &scenes)?;
    let opts = sheet_options(&args)?;
    let sheet = draw_sheet(&models, &params, &opts).context("drawing the view")?;
    let bytes = if svg {
        sheet_to_svg(&sheet).into_bytes()
    } else {
        encode_png_rgb8(&rasterize_sheet(&sheet)).context("encoding the view PNG")?
    };
    write_atomic(&args.output, &bytes)
        .with_context(|| format!("writing {}", args.output.display()))?;
    let p = &sheet.panels[0];
    outln!(
        "{}: {} blocks, {} viewport(s); first: {} lines drawn, {} clipped, {} outside -> {}",
        args.model.display(),
        model.blocks.len(),
        sheet.panels.len(),
        p.lines.len(),
        p.clipped_lines,
        p.rejected_lines,
        args.output.display()
    )?;
    Ok(())
}

/// Most blocks times viewports `--shade` fills (docs/limits.md "Viewer"): shading costs time
/// in proportion to both (1,000 blocks in one 512 x 512 viewport: 85 s in a debug build, about
/// 11 s in a release build), while the wireframe draws 5,000 blocks in 0.14 s.
pub const MAX_SHADED_BLOCK_VIEWS: usize = 250;

/// Refuses `--shade` beyond [`MAX_SHADED_BLOCK_VIEWS`], before any drawing, naming the model
/// file and the fix.
fn check_shaded_work(args: &Args, scenes: &[&Scene]) -> anyhow::Result<()> {
    let blocks: usize = scenes.iter().map(|s| s.blocks.len()).sum();
    let work = blocks.saturating_mul(args.viewports.max(1) as usize);
    if args.shade && work > MAX_SHADED_BLOCK_VIEWS {
        bail!(
            "{}: --shade of {blocks} blocks in {} viewport(s) fills {work} block views, more than the {MAX_SHADED_BLOCK_VIEWS} it takes; drop --shade (the wireframe draws any number of blocks quickly), or view fewer blocks or viewports",
            args.model.display(),
            args.viewports.max(1)
        );
    }
    Ok(())
}

fn output_is_svg(path: &Path) -> anyhow::Result<bool> {
    match path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .as_deref()
    {
        Some("png") => Ok(false),
        Some("svg") => Ok(true),
        _ => bail!("{}: unknown output type; use .png or .svg", path.display()),
    }
}

/// The two Appendix B files named by `path` (PREFIX, PREFIX_vertices.txt or
/// PREFIX_connections.txt), if it names them.
pub fn thesis_pair(path: &Path) -> Option<(PathBuf, PathBuf)> {
    let s = path.to_string_lossy();
    let prefix = if let Some(p) = s.strip_suffix("_vertices.txt") {
        p.to_string()
    } else if let Some(p) = s.strip_suffix("_connections.txt") {
        p.to_string()
    } else if !path.exists() && Path::new(&format!("{s}_vertices.txt")).exists() {
        s.to_string()
    } else {
        return None;
    };
    Some((
        PathBuf::from(format!("{prefix}_vertices.txt")),
        PathBuf::from(format!("{prefix}_connections.txt")),
    ))
}

/// The files a model argument names: the two Appendix B files, or the one scene file.
pub fn model_files(path: &Path) -> Vec<PathBuf> {
    match thesis_pair(path) {
        Some((v, c)) => vec![v, c],
        None => vec![path.to_path_buf()],
    }
}

/// Reads a model (menu r): the Appendix B data files (in mm, the thesis's frame) or a scene or
/// reconstruction file (not checked for overlaps: reconstructions may overlap).
pub fn read_model(path: &Path, truncation: Truncation) -> anyhow::Result<Scene> {
    let Some((vp, cp)) = thesis_pair(path) else {
        return read_reconstruction(path)
            .map(|r| r.to_scene())
            .with_context(|| format!("reading {}", path.display()));
    };
    let read = |p: &Path| {
        blockworld::io::read_text(p).with_context(|| {
            format!("reading {} (Appendix B data files come in pairs: PREFIX_vertices.txt and PREFIX_connections.txt)", p.display())
        })
    };
    let (v, c) = (read(&vp)?, read(&cp)?);
    let names = (vp.display().to_string(), cp.display().to_string());
    let model = parse_thesis_files(&v, &c, (&names.0, &names.1), truncation)?;
    let name = vp
        .file_stem()
        .map(|s| {
            s.to_string_lossy()
                .trim_end_matches("_vertices")
                .to_string()
        })
        .unwrap_or_default();
    Ok(thesis_model_to_scene(&model, &name, &names.1, truncation)?)
}

/// [`read_model`] of the `role` ("the model", "the --overlay file"): a missing file is named as
/// missing, and any other error opens with the role and the path.
fn read_named_model(role: &str, path: &Path, truncation: Truncation) -> anyhow::Result<Scene> {
    if thesis_pair(path).is_none() && !path.exists() {
        bail!(
            "{role} {} is missing: no such file, nor an Appendix B pair {0}_vertices.txt and {0}_connections.txt; give a scene or reconstruction file, or the PREFIX of an Appendix B pair",
            path.display()
        );
    }
    read_model(path, truncation).with_context(|| format!("reading {role} {}", path.display()))
}

/// The menu's d: every vertex of every block in world mm.
fn world_table(models: &[WireModel]) -> String {
    let mut t = String::new();
    for m in models {
        t.push_str(&format!(
            "# {:?}: {} vertices, world mm\n",
            m.role,
            m.vertices_mm.len()
        ));
        for (k, v) in m.vertices_mm.iter().enumerate() {
            // Rounded to the printed 0.1 µm first, so rounding noise never prints as -0.0000.
            let v = (*v * 1e4).round() / 1e4 + DVec3::ZERO;
            t.push_str(&format!(
                "{:>4} {:>10.4} {:>10.4} {:>10.4}\n",
                k + 1,
                v.x,
                v.y,
                v.z
            ));
        }
    }
    t
}

/// Parses "x,y,z".
fn parse_point(option: &str, text: &str) -> anyhow::Result<DVec3> {
    let v: Vec<f64> = text
        .split(',')
        .map(|t| t.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .ok()
        .filter(|v: &Vec<f64>| v.len() == 3 && v.iter().all(|x| x.is_finite()))
        .with_context(|| format!("{option}: expected three finite numbers x,y,z, got {text:?}"))?;
    Ok(DVec3::new(v[0], v[1], v[2]))
}

fn view_params(args: &Args, scenes: &[&Scene]) -> anyhow::Result<ViewParams> {
    let framing = ViewParams::framing(scenes, args.view_angle)?;
    let at_mm = match &args.at {
        Some(t) => parse_point("--at", t)?,
        None => framing.at_mm,
    };
    let from_mm = match &args.from {
        Some(t) => parse_point("--from", t)?,
        None => at_mm + (framing.from_mm - framing.at_mm),
    };
    let params = ViewParams {
        from_mm,
        at_mm,
        up: parse_point("--up", &args.up)?,
        view_angle_deg: args.view_angle,
    };
    Ok(match args.move_from {
        Some(d) => params.move_from(d)?,
        None => params,
    })
}

fn sheet_options(args: &Args) -> anyhow::Result<SheetOptions> {
    let (w, h) = args
        .size
        .split_once(['x', 'X'])
        .and_then(|(w, h)| Some((w.trim().parse::<u32>().ok()?, h.trim().parse::<u32>().ok()?)))
        .filter(|&(w, h)| (32..=8192).contains(&w) && (32..=8192).contains(&h))
        .with_context(|| {
            format!(
                "--size: expected WxH with each side 32..=8192, got {:?}",
                args.size
            )
        })?;
    let hidden_lines = match args.hidden_lines.to_ascii_lowercase().as_str() {
        "show" => HiddenLines::Show,
        "remove" => HiddenLines::Remove,
        other => bail!("--hidden-lines: unknown value {other:?}; use show or remove"),
    };
    Ok(SheetOptions {
        size_px: [w, h],
        viewports: args.viewports,
        hidden_lines,
        shade: args.shade,
        ..SheetOptions::default()
    })
}
