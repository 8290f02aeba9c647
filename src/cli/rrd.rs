//! `--rrd FILE` of `render` and `recognize` (docs/rerun.md): the flag, its early checks, and the
//! atomic write of the recording `blockworld::export::rrd` encodes. Without the `rrd` feature
//! the flag is refused before any work.

use std::path::{Path, PathBuf};

/// The `--rrd` flag.
#[derive(Debug, Clone, clap::Args)]
pub struct RrdArgs {
    /// Also write a Rerun recording (.rrd) of the scene, its cameras, pictures, depth, ids and
    /// line drawings (docs/rerun.md); needs a build with `--features rrd`.
    #[arg(long, value_name = "FILE")]
    pub rrd: Option<PathBuf>,
}

/// What a build without the feature says to `--rrd`.
pub const NO_RRD_FEATURE: &str =
    "built without the rrd feature; build with `cargo build --features rrd`";

impl RrdArgs {
    /// Refuses `--rrd` in a build without the feature, and an output path that cannot be
    /// written or is one of `inputs`; run before any work.
    pub fn check(&self, inputs: &[&Path]) -> anyhow::Result<()> {
        let Some(path) = &self.rrd else {
            return Ok(());
        };
        if !cfg!(feature = "rrd") {
            anyhow::bail!("--rrd {}: {NO_RRD_FEATURE}", path.display());
        }
        crate::cli::files::check_output(path, inputs)
    }
}

/// Encodes `data` and writes it to `path` atomically, printing the file and its sha256.
#[cfg(feature = "rrd")]
pub fn write_recording(
    path: &Path,
    data: &blockworld::export::rrd::RecordingData,
) -> anyhow::Result<()> {
    use anyhow::Context;
    let bytes = blockworld::export::rrd::recording_to_rrd(data)
        .with_context(|| format!("making the Rerun recording {}", path.display()))?;
    blockworld::io::write_atomic(path, &bytes)
        .with_context(|| format!("writing {}", path.display()))?;
    outln!(
        "wrote {}  sha256 {}",
        path.display(),
        blockworld::dataset::sha256_hex(&bytes)
    )?;
    Ok(())
}

/// One view's files as `recognize --rrd` records them: its picture, depth and ids when the
/// folder has them.
#[cfg(feature = "rrd")]
struct ViewFiles {
    picture: Option<image::GrayImage>,
    depth: Option<(u32, u32, Vec<u16>)>,
    ids: Option<(u32, u32, Vec<u16>)>,
}

#[cfg(feature = "rrd")]
fn read_view_files(dir: &Path, view: &str) -> anyhow::Result<ViewFiles> {
    use crate::cli::files::{read_gray16, read_picture};
    let picture = dir.join(format!("view_{view}.png"));
    let depth = dir.join(format!("depth_{view}.png"));
    let ids = dir.join(format!("ids_{view}.png"));
    Ok(ViewFiles {
        picture: picture
            .exists()
            .then(|| read_picture(&picture))
            .transpose()?,
        depth: depth.exists().then(|| read_gray16(&depth)).transpose()?,
        ids: ids.exists().then(|| read_gray16(&ids)).transpose()?,
    })
}

/// The recording of `recognize --rrd`: the reconstruction's blocks (when it is an answer), the
/// truth from `dir/scene.json` (when there), and each observed view with the drawing the
/// recognizer read and the folder's pictures.
#[cfg(feature = "rrd")]
pub fn write_recognize_recording(
    path: &Path,
    dir: &Path,
    observed: &[blockworld::recognize::ObservedView],
    recon: &blockworld::scene::Reconstruction,
) -> anyhow::Result<()> {
    use anyhow::Context;
    use blockworld::export::rrd::{Picture, RecordingData, ViewData};
    let scene_path = dir.join("scene.json");
    let truth = scene_path
        .exists()
        .then(|| blockworld::scene::read_scene(&scene_path))
        .transpose()
        .with_context(|| format!("reading the truth {}", scene_path.display()))?;
    let recognized = recon.is_ok().then(|| recon.to_scene());
    let files = observed
        .iter()
        .map(|o| read_view_files(dir, o.camera.view.name()))
        .collect::<anyhow::Result<Vec<_>>>()?;
    fn sixteen(p: &(u32, u32, Vec<u16>)) -> Picture<'_, u16> {
        Picture {
            size_px: [p.0, p.1],
            pixels: p.2.as_slice(),
        }
    }
    let views = observed
        .iter()
        .zip(&files)
        .map(|(o, f)| ViewData {
            camera: &o.camera,
            picture: f.picture.as_ref().map(|g| Picture {
                size_px: [g.width(), g.height()],
                pixels: g.as_raw().as_slice(),
            }),
            depth: f.depth.as_ref().map(sixteen),
            ids: f.ids.as_ref().map(sixteen),
            lines: Some(&o.drawing),
        })
        .collect();
    let data = RecordingData {
        name: &recon.name,
        truth: truth.as_ref(),
        recognized: recognized.as_ref(),
        views,
        fall: None,
    };
    write_recording(path, &data)
}
