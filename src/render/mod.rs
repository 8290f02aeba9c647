//! The off-screen renderer (issue #2): grayscale 45-degree corner views of a scene, rendered with
//! wgpu (Vulkan on lavapipe by default), plus their ground truth: depth, block ids and the exact
//! visible line drawing computed from geometry.
//!
//! `camera` is pure math shared with `vision`; `truth` is pure geometry; only `gpu` touches wgpu.

pub mod camera;
pub mod truth;

pub use camera::{Camera, CameraOptions, CornerView, Projection};

use crate::drawing::LineDrawing;
use crate::scene::Scene;
use image::{GrayImage, ImageBuffer, Luma};

/// A 16-bit single-channel image (depth and block ids).
pub type Gray16Image = ImageBuffer<Luma<u16>, Vec<u16>>;

/// Which wgpu backend renders.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Backend {
    /// Vulkan (lavapipe on a machine without a GPU). The default.
    #[default]
    Vulkan,
    /// OpenGL ES through EGL (Mesa llvmpipe).
    Gl,
}

/// Everything that decides how a view is rendered.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RenderOptions {
    /// Camera placement, projection and picture size.
    pub camera: CameraOptions,
    /// Multisample count: 1 (exact gray levels) or 4.
    pub msaa: u32,
    /// Standard deviation of Gaussian sensor noise in gray levels; 0 = none.
    pub noise_sigma: f64,
    /// Seed of the noise (the same seed gives the same noise).
    pub seed: u64,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            camera: CameraOptions::default(),
            msaa: 1,
            noise_sigma: 0.0,
            seed: 0,
        }
    }
}

/// One rendered corner view with its ground truth.
#[derive(Debug, Clone)]
pub struct RenderedView {
    /// The camera that took it (written as `camera_<view>.json`).
    pub camera: Camera,
    /// 8-bit grayscale picture (`view_<view>.png`).
    pub gray: GrayImage,
    /// Depth along the optical axis, `depth_units_per_mm` steps per mm, 0 = nothing
    /// (`depth_<view>.png`).
    pub depth: Gray16Image,
    /// Block index + 1 per pixel, 0 = background or floor (`ids_<view>.png`).
    pub ids: Gray16Image,
    /// The exact visible line drawing (`lines_<view>.json`).
    pub lines: LineDrawing,
}

/// Depth PNG scale: steps per millimetre (1/16 mm resolution, up to 4095.9 mm).
pub const DEPTH_UNITS_PER_MM: f64 = 16.0;

/// Rendering errors; each says what to do.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// No adapter for the requested backend.
    #[error("no usable {backend} graphics adapter: {detail}. Install lavapipe (Mesa's CPU Vulkan driver): `apt-get install -y mesa-vulkan-drivers libvulkan1`, or try `--backend gl` (Mesa llvmpipe through EGL)")]
    NoAdapter {
        /// "Vulkan" or "GL".
        backend: &'static str,
        /// What wgpu said.
        detail: String,
    },
    /// The device could not be created, or a GPU operation failed.
    #[error("GPU error: {0}")]
    Gpu(String),
    /// Options that cannot be rendered (size, MSAA count).
    #[error("invalid render options: {0}")]
    Options(String),
    /// Not built yet.
    #[error("the renderer is not implemented yet")]
    Unimplemented,
}

/// The renderer: one wgpu device, created once and reused for any number of scenes; `Sync`, so
/// worker threads can share it.
pub struct Renderer {
    _private: (),
}

impl Renderer {
    /// Creates the device on `backend`.
    pub fn new(_backend: Backend) -> Result<Renderer, RenderError> {
        Err(RenderError::Unimplemented)
    }

    /// Renders one corner view of `scene` with its ground truth.
    pub fn render(
        &self,
        _scene: &Scene,
        _view: CornerView,
        _opts: &RenderOptions,
    ) -> Result<RenderedView, RenderError> {
        Err(RenderError::Unimplemented)
    }

    /// Renders the given views of `scene` (usually [`CornerView::ALL`]).
    pub fn render_views(
        &self,
        scene: &Scene,
        views: &[CornerView],
        opts: &RenderOptions,
    ) -> Result<Vec<RenderedView>, RenderError> {
        views.iter().map(|v| self.render(scene, *v, opts)).collect()
    }

    /// Adapter name and backend, for logs and benchmark tables.
    pub fn adapter_info(&self) -> String {
        String::new()
    }
}
