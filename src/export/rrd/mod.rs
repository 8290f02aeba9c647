//! Rerun recordings (`.rrd`) of a scene, its corner views and a reconstruction (docs/rerun.md):
//! the world in metres (blocks as flat-shaded meshes, the floor), each corner camera with its
//! picture, depth, instance ids and exact line drawing, and the recognizer's blocks beside the
//! truth, and a fall (a stability dataset's trajectory) on the timeline [`FALL_TIMELINE`]. The
//! one home of the `rerun` crate; built only with the `rrd` feature.
//!
//! Plain data in, bytes out: [`recording_to_rrd`] returns the encoded recording and `cli` writes
//! it. Entity tree, units and the orthographic cameras: docs/rerun.md "Entity tree".

mod entities;

use crate::camera::Camera;
use crate::drawing::LineDrawing;
use crate::geom::{DQuat, DVec3};
use crate::scene::Scene;

pub use entities::{
    pinhole_intrinsics_px, view_entity, BLOCKS_RECOGNIZED, BLOCKS_TRUTH, DEPTH_METER, FLOOR,
};

/// Why a recording could not be made.
#[derive(Debug, thiserror::Error)]
pub enum RrdError {
    /// A block type whose faces cannot be made into a mesh, or a fall whose keyframes do not
    /// fit the truth's blocks.
    #[error(transparent)]
    Mesh(#[from] super::ExportError),
    /// A picture whose pixel count does not match its size.
    #[error("view {view}: the {what} picture has {got} pixels, its size {size_px:?} needs {want}; render the view again")]
    PictureSize {
        /// The corner view's name.
        view: &'static str,
        /// Which picture (`picture`, `depth`, `ids`).
        what: &'static str,
        /// Its width and height in px.
        size_px: [u32; 2],
        /// Pixels it has.
        got: usize,
        /// Pixels its size needs.
        want: usize,
    },
    /// The Rerun SDK refused to start or to encode the recording.
    #[error("Rerun SDK: {0}")]
    Sdk(String),
}

/// One picture as rows top to bottom, each left to right (PNG order).
#[derive(Debug, Clone, Copy)]
pub struct Picture<'a, T> {
    /// Width and height in px.
    pub size_px: [u32; 2],
    /// `width * height` pixels.
    pub pixels: &'a [T],
}

/// One corner view as `blockworld render` writes it; the pictures are optional (a folder
/// `recognize` reads may hold only the picture, or only the exact drawing).
#[derive(Debug, Clone, Copy)]
pub struct ViewData<'a> {
    /// The camera (`camera_<v>.json`).
    pub camera: &'a Camera,
    /// 8-bit grey picture (`view_<v>.png`).
    pub picture: Option<Picture<'a, u8>>,
    /// Depth along the optical axis, `DEPTH_UNITS_PER_MM` steps per mm (`depth_<v>.png`).
    pub depth: Option<Picture<'a, u16>>,
    /// Block index + 1 per pixel, 0 = floor or background (`ids_<v>.png`).
    pub ids: Option<Picture<'a, u16>>,
    /// A line drawing in picture px (`lines_<v>.json`, or the vision front end's).
    pub lines: Option<&'a LineDrawing>,
}

/// What one recording holds.
#[derive(Debug, Clone)]
pub struct RecordingData<'a> {
    /// The recording's name: its recording id is `blockworld/<name>`.
    pub name: &'a str,
    /// The scene's blocks (`world/truth/blocks`), when known.
    pub truth: Option<&'a Scene>,
    /// The recognizer's blocks (`world/recognized/blocks`), when there is an answer.
    pub recognized: Option<&'a Scene>,
    /// The corner views.
    pub views: Vec<ViewData<'a>>,
    /// The truth's fall, when there is one: its blocks' poses are then logged at every frame
    /// on the timeline [`FALL_TIMELINE`] instead of once.
    pub fall: Option<Fall<'a>>,
}

/// The timeline of a fall, seconds from the start of the simulation.
pub const FALL_TIMELINE: &str = "fall";

/// A fall as the physics records it (`trajectory.bin`, docs/stability.md "Trajectories"):
/// `frames[k][i]` is block `i`'s centre (mm) and rotation at `times_s[k]`.
#[derive(Debug, Clone, Copy)]
pub struct Fall<'a> {
    /// Time of each frame, s, strictly increasing.
    pub times_s: &'a [f64],
    /// Per frame, one pose per block of the truth.
    pub frames: &'a [Vec<(DVec3, DQuat)>],
}

/// Encodes `data` as a Rerun recording (`.rrd` bytes), every entity static (no timeline) but
/// the truth's block poses of a fall.
pub fn recording_to_rrd(data: &RecordingData) -> Result<Vec<u8>, RrdError> {
    let sdk = |e: &dyn std::fmt::Display| RrdError::Sdk(e.to_string());
    let (rec, storage) = rerun::RecordingStreamBuilder::new("blockworld")
        .recording_id(format!("blockworld/{}", data.name))
        .enabled(true)
        .memory()
        .map_err(|e| sdk(&e))?;
    entities::log_world(&rec, data).map_err(|e| match e {
        entities::LogError::Rrd(e) => e,
        entities::LogError::Stream(e) => sdk(&e),
    })?;
    for view in &data.views {
        entities::log_view(&rec, view).map_err(|e| match e {
            entities::LogError::Rrd(e) => e,
            entities::LogError::Stream(e) => sdk(&e),
        })?;
    }
    rec.flush_blocking().map_err(|e| sdk(&e))?;
    storage.drain_as_bytes().map_err(|e| sdk(&e))
}

#[cfg(test)]
mod tests;
