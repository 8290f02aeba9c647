//! `blockworld edges VIEW.png [-o OUT.png] [--threshold N] [--magnitude MAG.png]`: the thesis's
//! edge detection (Sobel eq. 2.1 with 3x3 smoothing and a threshold, Ch. II and VI) written as a
//! binary PNG (0 and 255).

use crate::cli::files::read_picture;
use anyhow::Context;
use blockworld::output::{encode_png_gray16, encode_png_gray8};
use blockworld::vision::{smooth_3x3, sobel_magnitude, threshold, EdgeOptions, SmoothWindow};
use image::GrayImage;
use std::path::{Path, PathBuf};

/// Options of `blockworld edges`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The grayscale view (PNG); colour images are converted to gray with a warning.
    pub view: PathBuf,
    /// Where to write the binary edge map (PNG, 0/255); default `<VIEW>_edges.png`.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Smoothed Sobel magnitude above this is an edge (the thesis used 80, Ch. VI).
    #[arg(long, default_value_t = EdgeOptions::default().threshold)]
    pub threshold: u16,
    /// Smooth with the thesis's trailing 3x3 window (reproduces its Ch. VI table) instead of the
    /// centred one.
    #[arg(long)]
    pub trailing_window: bool,
    /// Also write the smoothed magnitude here (16-bit PNG).
    #[arg(long)]
    pub magnitude: Option<PathBuf>,
}

/// Runs `blockworld edges`.
pub fn run(args: Args) -> anyhow::Result<()> {
    for p in args.output.iter().chain(&args.magnitude) {
        require_png_name(p)?;
    }
    let out = args
        .output
        .clone()
        .unwrap_or_else(|| sibling(&args.view, "_edges.png"));
    for p in std::iter::once(&out).chain(&args.magnitude) {
        crate::cli::files::check_output(p, &[&args.view])?;
    }
    let gray = read_picture(&args.view)?;
    let window = if args.trailing_window {
        SmoothWindow::Trailing
    } else {
        SmoothWindow::Centred
    };
    let smoothed = smooth_3x3(&sobel_magnitude(&gray), window);
    let mut edges = threshold(&smoothed, args.threshold);
    let count = edges.as_raw().iter().filter(|v| **v != 0).count();
    edges.iter_mut().for_each(|v| *v *= 255);
    write_png_gray8(&out, &edges)?;
    if let Some(m) = &args.magnitude {
        let bytes = encode_png_gray16(&smoothed).context("encoding the magnitude PNG")?;
        blockworld::io::write_atomic(m, &bytes)
            .with_context(|| format!("writing {}", m.display()))?;
    }
    outln!(
        "{}: {count} edge pixels (threshold {}) -> {}",
        args.view.display(),
        args.threshold,
        out.display()
    )?;
    Ok(())
}

/// Both outputs are PNG bytes, so their names must say `.png` (an `e.jpg` holding PNG bytes
/// misleads every viewer that trusts the extension).
fn require_png_name(path: &Path) -> anyhow::Result<()> {
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    if ext.as_deref() != Some("png") {
        anyhow::bail!(
            "{}: edges writes PNG pictures; give the output a .png name",
            path.display()
        );
    }
    Ok(())
}

/// `dir/name.png` -> `dir/name<suffix>`.
fn sibling(p: &Path, suffix: &str) -> PathBuf {
    let stem = p
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    p.with_file_name(format!("{stem}{suffix}"))
}

/// Writes an 8-bit gray PNG atomically.
fn write_png_gray8(path: &Path, img: &GrayImage) -> anyhow::Result<()> {
    let bytes = encode_png_gray8(img).context("encoding the edge PNG")?;
    blockworld::io::write_atomic(path, &bytes)
        .with_context(|| format!("writing {}", path.display()))
}
