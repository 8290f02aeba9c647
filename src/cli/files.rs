//! Reading the files the stages exchange, with errors that name the file and say how to make a
//! good one: pictures (`view_<v>.png`), cameras (`camera_<v>.json`) and line drawings
//! (`lines_<v>.json`, `vertices_<v>.json`, hand-made drawings).

use anyhow::Context;
use blockworld::camera::{parse_camera_json, Camera, CornerView};
use blockworld::drawing::LineDrawing;
use blockworld::geom::DVec3;
use blockworld::scene::{read_scene_with_progress, Scene, SceneError};
use blockworld::vision::decode_gray;
use image::GrayImage;
use std::path::Path;

/// Reads a PNG as 8-bit gray; warns when it had to convert it.
pub fn read_picture(path: &Path) -> anyhow::Result<GrayImage> {
    let bytes = std::fs::read(path).with_context(|| format!("reading {}", path.display()))?;
    let dec = decode_gray(&bytes).with_context(|| format!("{}", path.display()))?;
    if let Some(from) = &dec.converted_from {
        eprintln!(
            "warning: {}: {from} image converted to 8-bit gray",
            path.display()
        );
    }
    Ok(dec.gray)
}

/// Decodes a 16-bit PNG of a scene folder (`depth_<v>.png`, `ids_<v>.png`) into its width,
/// height and samples.
pub fn read_gray16(path: &Path) -> anyhow::Result<(u32, u32, Vec<u16>)> {
    let bytes = std::fs::read(path).with_context(|| format!("reading {}", path.display()))?;
    let img = image::load_from_memory_with_format(&bytes, image::ImageFormat::Png)
        .with_context(|| format!("{}: not a PNG; re-generate the scene", path.display()))?;
    let image::DynamicImage::ImageLuma16(g) = img else {
        anyhow::bail!(
            "{}: not a 16-bit gray PNG; re-generate the scene",
            path.display()
        );
    };
    Ok((g.width(), g.height(), g.into_raw()))
}

/// Reads and checks a `camera_<view>.json`.
pub fn read_camera(path: &Path) -> anyhow::Result<Camera> {
    let text =
        blockworld::io::read_text(path).with_context(|| format!("reading {}", path.display()))?;
    parse_camera_json(&text).with_context(|| format!("{}", path.display()))
}

/// What a scene folder's `look.json` records that the recognizer may use (docs/varied-look.md
/// "look.json"): the lights of each view and the blocks' edge rounding.
#[derive(Debug, Clone, PartialEq)]
pub struct RecordedLook {
    /// The unit vectors towards each light of each view asked for, in order; a view the file
    /// does not name has no known lights.
    pub towards_lights: Vec<Vec<DVec3>>,
    /// The blocks' edge radius, mm; 0 when the file does not say.
    pub edge_radius_mm: f64,
}

/// Largest edge radius a `look.json` may record, mm: a third of the thinnest block's 7.5 mm
/// height (at half of it no flat face would be left); the varied look draws up to 0.5.
pub const MAX_RECORDED_EDGE_RADIUS_MM: f64 = 2.5;

/// What a scene folder's `look.json` records for `views` ([`RecordedLook`]): `views.<view>[]
/// .towards_light` (the unit vector towards each light) and `edge_radius_mm`. Only those parts
/// of the file are read, so a hand-made `{"edge_radius_mm": 0.2, "views": {"ne":
/// [{"towards_light": [x, y, z]}]}}` serves as well, either part left out.
pub fn read_recorded_look(path: &Path, views: &[CornerView]) -> anyhow::Result<RecordedLook> {
    #[derive(serde::Deserialize)]
    struct Recorded {
        #[serde(default)]
        views: std::collections::BTreeMap<String, Vec<RecordedLight>>,
        #[serde(default)]
        edge_radius_mm: f64,
    }
    #[derive(serde::Deserialize)]
    struct RecordedLight {
        towards_light: [f64; 3],
    }
    let text =
        blockworld::io::read_text(path).with_context(|| format!("reading {}", path.display()))?;
    let recorded: Recorded = serde_json::from_str(&text).with_context(|| {
        format!(
            "{}: not a look.json with \"edge_radius_mm\": r and \"views\": {{\"<view>\": [{{\"towards_light\": [x, y, z]}}]}}; regenerate the scene or remove the file",
            path.display()
        )
    })?;
    let r = recorded.edge_radius_mm;
    anyhow::ensure!(
        (0.0..=MAX_RECORDED_EDGE_RADIUS_MM).contains(&r),
        "{}: edge_radius_mm {r} is not a radius from 0 to {MAX_RECORDED_EDGE_RADIUS_MM} mm; give the blocks' edge radius in mm (0 for sharp edges)",
        path.display()
    );
    let towards_lights = views
        .iter()
        .map(|&view| {
            let lights = recorded
                .views
                .get(view.name())
                .map_or(&[][..], Vec::as_slice);
            lights
                .iter()
                .map(|l| checked_light(path, view, l.towards_light))
                .collect()
        })
        .collect::<anyhow::Result<_>>()?;
    Ok(RecordedLook {
        towards_lights,
        edge_radius_mm: r,
    })
}

/// `towards_light`, a light `path` records for `view`, as a unit vector; an error naming the
/// file unless it points above the horizon.
fn checked_light(path: &Path, view: CornerView, towards_light: [f64; 3]) -> anyhow::Result<DVec3> {
    let d = DVec3::from_array(towards_light);
    let unit = d.is_finite() && d.length() > 1e-9 && d.y > 0.0;
    anyhow::ensure!(
        unit,
        "{}: views.{}: towards_light {:?} is not a direction above the horizon; give a nonzero [x, y, z] with y > 0 (y up)",
        path.display(),
        view.name(),
        towards_light
    );
    Ok(d.normalize())
}

/// Reads and checks a line drawing.
pub fn read_drawing(path: &Path) -> anyhow::Result<LineDrawing> {
    let text =
        blockworld::io::read_text(path).with_context(|| format!("reading {}", path.display()))?;
    LineDrawing::from_json(&text).with_context(|| format!("{}", path.display()))
}

/// Reads and validates a scene file, showing the validation's progress (block pairs tested;
/// docs/cli.md "Exit codes and progress output"). The error is the library's, naming the file.
pub fn read_scene_shown(path: &Path) -> Result<Scene, SceneError> {
    crate::cli::progress::with_progress("validate", "block pairs", 0, |p| {
        read_scene_with_progress(path, p)
    })
}

/// The one output-path check of every command that writes a file, run before any work
/// (docs/limits.md "Outputs"): a directory where a file is meant is refused, a device node or
/// FIFO is written through (`blockworld::io::check_output_path`), and an output that is one of
/// the command's `inputs` (the same file, by device and inode) is refused, since writing it
/// would replace the input the command reads.
pub fn check_output(output: &Path, inputs: &[&Path]) -> anyhow::Result<()> {
    use std::os::unix::fs::MetadataExt;
    let target = blockworld::io::check_output_path(output)
        .with_context(|| format!("output {}", output.display()))?;
    if target == blockworld::io::OutputTarget::Stream {
        return Ok(());
    }
    let Ok(out) = std::fs::metadata(output) else {
        return Ok(());
    };
    for input in inputs {
        let same =
            std::fs::metadata(input).is_ok_and(|m| (m.dev(), m.ino()) == (out.dev(), out.ino()));
        if same {
            anyhow::bail!(
                "output {} is the input {}: writing it would replace what is read; give another \
                 output name",
                output.display(),
                input.display()
            );
        }
    }
    Ok(())
}

/// A folder written whole or not at all (docs/report.md "Output"): the files go into a
/// temporary folder beside `dest`, which [`StagedFolder::publish`] renames into place; dropped
/// unpublished (an error), the temporary folder is removed and `dest` is untouched.
pub struct StagedFolder {
    /// The temporary folder being written.
    pub tmp: std::path::PathBuf,
    dest: std::path::PathBuf,
    published: bool,
}

impl StagedFolder {
    /// Checks that `dest` may be replaced, before any work: it is absent, an empty folder, or
    /// a folder holding `marker` (an earlier output of the same command); then makes the
    /// temporary folder.
    pub fn new(dest: &Path, marker: &str, what: &str) -> anyhow::Result<StagedFolder> {
        if dest.exists() {
            let empty = std::fs::read_dir(dest)
                .with_context(|| {
                    format!(
                        "{}: not a folder; give a folder for the {what}",
                        dest.display()
                    )
                })?
                .next()
                .is_none();
            if !empty && !dest.join(marker).is_file() {
                anyhow::bail!(
                    "{}: holds files but no {marker}, so it is not an earlier {what}; give a new or empty folder",
                    dest.display()
                );
            }
        }
        let name = dest
            .file_name()
            .with_context(|| format!("{}: give a folder name", dest.display()))?;
        let tmp = dest.with_file_name(format!(
            ".{}.tmp-{}",
            name.to_string_lossy(),
            std::process::id()
        ));
        if tmp.exists() {
            std::fs::remove_dir_all(&tmp).with_context(|| format!("removing {}", tmp.display()))?;
        }
        std::fs::create_dir_all(&tmp).with_context(|| format!("creating {}", tmp.display()))?;
        Ok(StagedFolder {
            tmp,
            dest: dest.to_path_buf(),
            published: false,
        })
    }

    /// Writes `bytes` to `relative` in the temporary folder, making its folder first.
    pub fn write(&self, relative: &str, bytes: &[u8]) -> anyhow::Result<()> {
        let path = self.tmp.join(relative);
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent)
                .with_context(|| format!("creating {}", parent.display()))?;
        }
        std::fs::write(&path, bytes).with_context(|| format!("writing {}", path.display()))
    }

    /// Renames the finished folder to `dest`, replacing what `new` accepted there.
    pub fn publish(mut self) -> anyhow::Result<()> {
        let old = self.tmp.with_extension("old");
        if self.dest.exists() {
            std::fs::rename(&self.dest, &old)
                .with_context(|| format!("moving the earlier {} aside", self.dest.display()))?;
        }
        if let Err(e) = std::fs::rename(&self.tmp, &self.dest) {
            if old.exists() {
                let _ = std::fs::rename(&old, &self.dest);
            }
            return Err(e).with_context(|| {
                format!("renaming {} to {}", self.tmp.display(), self.dest.display())
            });
        }
        self.published = true;
        if old.exists() {
            std::fs::remove_dir_all(&old).with_context(|| format!("removing {}", old.display()))?;
        }
        Ok(())
    }
}

impl Drop for StagedFolder {
    fn drop(&mut self) {
        if !self.published {
            let _ = std::fs::remove_dir_all(&self.tmp);
        }
    }
}
