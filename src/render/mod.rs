//! The off-screen renderer (docs/rendering.md "Rendering"): grayscale 45-degree corner views of a scene, rendered with
//! wgpu (Vulkan on lavapipe by default), plus their ground truth: depth, block ids and the exact
//! visible line drawing computed from geometry.
//!
//! The camera is the shared `crate::camera`; the exact line drawing is `crate::linedraw` (pure
//! geometry, shared with the recognizer's check); only `gpu` touches wgpu.

mod gpu;
mod mesh;
pub mod photo;

pub use photo::{Look, PhotoOptions};

use crate::camera::{Camera, CameraOptions, CornerView, Projection, DEPTH_UNITS_PER_MM};

use crate::drawing::LineDrawing;
use crate::geom::DVec3;
use crate::io::echo_number;
use crate::linedraw;
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

/// Everything that decides how a view is rendered. Serializes flat (camera options first) into
/// `dataset.json`, without the per-scene noise seed.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct RenderOptions {
    /// Camera placement, projection and picture size.
    #[serde(flatten)]
    pub camera: CameraOptions,
    /// Multisample count: 1 (exact gray levels) or 4.
    pub msaa: u32,
    /// Standard deviation of Gaussian sensor noise in gray levels; 0 = none.
    pub noise_sigma: f64,
    /// Seed of the noise (the same seed gives the same noise).
    #[serde(skip)]
    pub seed: u64,
    /// Line art (the default) or photo (docs/rendering.md "Photographic look").
    #[serde(skip_serializing_if = "Look::is_line_art")]
    pub look: Look,
    /// 1 (the default), 2 or 4: the written picture is the rendered one averaged 2 x 2 once
    /// or twice, as the thesis did (Ch. VI); its camera describes the written picture.
    #[serde(skip_serializing_if = "is_one")]
    pub downsample: u32,
    /// Light, albedos and sensor of the photo look (ignored by line art; written to
    /// `dataset.json` only when not the defaults).
    #[serde(skip_serializing_if = "PhotoOptions::is_default")]
    pub photo: PhotoOptions,
}

fn is_one(v: &u32) -> bool {
    *v == 1
}

/// Most blocks `render` takes per scene (docs/limits.md "Render"): one view of 10,000 blocks
/// renders with its ground truth in about 40 s at 360 MB (debug build, lavapipe).
pub const MAX_RENDER_BLOCKS: usize = 10_000;

/// Narrowest side, in px, of a picture blockworld writes (after `--downsample`): the vision
/// front end needs a few pixels either side of a line, and a smaller picture shows no block.
pub const MIN_PICTURE_SIDE_PX: u32 = 8;

impl RenderOptions {
    /// Checks the options every renderer can take, whatever its device (the one home of these
    /// bounds; the command line and the dataset writer call it): a written picture (the
    /// rendered one after `downsample`) of at least [`MIN_PICTURE_SIDE_PX`] a side, an
    /// elevation of 1..=89 degrees, a field of view of 1..=170 degrees, a pixel aspect of
    /// 0.1..=10, MSAA 1 or 4 (the only counts lavapipe offers), sensor noise of 0..=128 gray
    /// levels and a framing margin in [0, 0.5). Each error names the one flag at fault and the
    /// values it takes.
    pub fn validate(&self) -> Result<(), RenderError> {
        self.validate_size()?;
        let c = &self.camera;
        let bad = |what: String| Err(RenderError::Options(what));
        if !(1.0..=89.0).contains(&c.elevation_deg) {
            return bad(format!(
                "--elevation {} is out of range; use 1..=89 degrees",
                echo_number(c.elevation_deg)
            ));
        }
        if let Projection::Perspective { fov_y_deg } = c.projection {
            if !(1.0..=170.0).contains(&fov_y_deg) {
                return bad(format!(
                    "--fov {} is out of range; use 1..=170 degrees",
                    echo_number(fov_y_deg)
                ));
            }
        }
        if !(0.1..=10.0).contains(&c.pixel_aspect) {
            return bad(format!(
                "--pixel-aspect {} is out of range; use 0.1..=10",
                echo_number(c.pixel_aspect)
            ));
        }
        if !(0.0..0.5).contains(&c.margin) {
            return bad(format!(
                "framing margin {} is out of range; use [0, 0.5)",
                echo_number(c.margin)
            ));
        }
        if self.msaa != 1 && self.msaa != 4 {
            return bad(format!(
                "--msaa {} is not supported; use 1 or 4 (the counts lavapipe offers)",
                self.msaa
            ));
        }
        if !(0.0..=128.0).contains(&self.noise_sigma) {
            return bad(format!(
                "--noise {} is out of range; use 0..=128 gray levels",
                echo_number(self.noise_sigma)
            ));
        }
        self.photo.validate().map_err(RenderError::Options)
    }

    /// The size part of [`RenderOptions::validate`]: `--downsample` 1, 2 or 4, and the written
    /// picture at least [`MIN_PICTURE_SIDE_PX`] a side.
    fn validate_size(&self) -> Result<(), RenderError> {
        let [w, h] = self.camera.size_px;
        let d = self.downsample;
        if ![1, 2, 4].contains(&d) {
            return Err(RenderError::Options(format!(
                "--downsample {d} is not supported; use 1, 2 or 4"
            )));
        }
        let min = MIN_PICTURE_SIDE_PX;
        if w / d < min || h / d < min {
            return Err(RenderError::Options(format!(
                "--size {w}x{h} with --downsample {d} writes a {}x{} px picture, below the \
                 {min} px a side blockworld writes; use a --size of at least {}x{} or a smaller \
                 --downsample",
                w / d,
                h / d,
                min * d,
                min * d
            )));
        }
        Ok(())
    }
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            camera: CameraOptions::default(),
            msaa: 1,
            noise_sigma: 0.0,
            seed: 0,
            look: Look::LineArt,
            downsample: 1,
            photo: PhotoOptions::default(),
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
    /// Unit vectors from the scene towards each light that lit the picture (world frame), as
    /// the look records them: the varied look's lights in this view (`look.json`,
    /// docs/varied-look.md "look.json"); empty for looks that record none.
    pub towards_lights: Vec<DVec3>,
    /// Radius of the blocks' rounded edges, mm, as the look records it (`look.json`
    /// `edge_radius_mm`, the varied look); 0 for looks that record none.
    pub edge_radius_mm: f64,
}

/// Rendering errors; each says what to do.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// No adapter for the requested backend.
    #[error(
        "no usable {backend} graphics adapter: {detail}. {}",
        no_adapter_hint(backend)
    )]
    NoAdapter {
        /// "Vulkan" or "GL".
        backend: &'static str,
        /// What wgpu said.
        detail: String,
    },
    /// The device could not be created, or a GPU operation failed.
    #[error("GPU error: {0}")]
    Gpu(String),
    /// Options that cannot be rendered (size, MSAA count); the text names the flag at fault.
    #[error("{0}")]
    Options(String),
}

/// What to install or try when `backend` ("Vulkan" or "GL") has no adapter (docs/rendering.md
/// "Rendering"): the other backend is suggested, never the one that just failed.
fn no_adapter_hint(backend: &str) -> &'static str {
    if backend == "GL" {
        "Install Mesa's EGL and GL drivers (llvmpipe): `apt-get install -y libegl1 libegl-mesa0 \
         libgl1-mesa-dri`, or use the default `--backend vulkan` (lavapipe)"
    } else {
        "Install lavapipe (Mesa's CPU Vulkan driver): `apt-get install -y mesa-vulkan-drivers \
         libvulkan1`, or try `--backend gl` (Mesa llvmpipe through EGL)"
    }
}

/// Gray level of the background (where neither the floor nor a block is seen).
pub const BACKGROUND_LEVEL: u8 = 20;

/// Gray level of the seam drawn along every block face edge, so that touching blocks stay
/// distinguishable (docs/rendering.md "Rendering"; real Fischer-Technik blocks show a dark gap there).
pub const SEAM_LEVEL: u8 = 35;

/// Half width of the seam in px: a fragment whose pixel centre lies closer than this to the
/// projected line of an edge of its own face is seam. An edge shared by two visible faces (a
/// convex edge, a crack between touching blocks) gets a band about 1.1 px wide centred on the
/// exact line (1 or 2 pixels across). A silhouette edge of a block (its other face turns away)
/// has no neighbour to draw the far half, and what lies behind may be a face of the same gray
/// level, so on its block's side the nearest pixel in each row or column is seam too: without
/// it, 25 of the accuracy suite's 256 views showed an occluding line with no intensity edge at
/// all (`tests/render_vs_truth.rs`). Slightly more than 0.5 so that a line exactly between two
/// pixel centres (common with symmetric framing) marks both of them instead of neither.
pub const SEAM_HALF_WIDTH_PX: f64 = 0.55;

pub use gpu::adapter_summary;
pub use mesh::{
    face_gray_level, floor_fill, FloorFill, AMBIENT, BLOCK_ALBEDO, FLOOR_ALBEDO,
    LIGHT_IN_CAMERA_FRAME,
};

/// The renderer: one wgpu device, created once and reused for any number of scenes; `Sync`, so
/// worker threads can share it (rendering itself is serialised on one queue).
pub struct Renderer {
    gpu: gpu::Gpu,
    photo: gpu::photo::PhotoSlot,
}

impl Renderer {
    /// Creates the device on `backend` (instance, adapter, device and pipelines, once).
    pub fn new(backend: Backend) -> Result<Renderer, RenderError> {
        Ok(Renderer {
            gpu: gpu::Gpu::new(backend)?,
            photo: Default::default(),
        })
    }

    /// Renders one corner view of `scene` with its ground truth, including the exact visible
    /// line drawing ([`linedraw::visible_line_drawing`]).
    pub fn render(
        &self,
        scene: &Scene,
        view: CornerView,
        opts: &RenderOptions,
    ) -> Result<RenderedView, RenderError> {
        self.render_with_progress(scene, view, opts, &|_, _| {})
    }

    /// [`Renderer::render`] reporting the exact line drawing's progress as `(done, total)`
    /// ([`linedraw::visible_line_drawing_with_progress`]): on scenes of thousands of blocks the
    /// drawing takes seconds, the pixels do not.
    pub fn render_with_progress(
        &self,
        scene: &Scene,
        view: CornerView,
        opts: &RenderOptions,
        progress: &(dyn Fn(u64, u64) + Sync),
    ) -> Result<RenderedView, RenderError> {
        let mut rendered = self.render_pixels(scene, view, opts)?;
        rendered.lines = linedraw::visible_line_drawing_with_progress(
            scene,
            &rendered.camera,
            &linedraw::TruthTolerances::default(),
            progress,
        );
        Ok(rendered)
    }

    /// Renders the pixels of one view (gray picture, depth, ids) and leaves `lines` empty: for
    /// benchmarks and callers that compute their own drawing.
    pub fn render_pixels(
        &self,
        scene: &Scene,
        view: CornerView,
        opts: &RenderOptions,
    ) -> Result<RenderedView, RenderError> {
        let mut views = self.render_views_pixels(scene, &[view], opts)?;
        views
            .pop()
            .ok_or_else(|| RenderError::Gpu("the renderer returned no view".into()))
    }

    /// The pixels of the given views, `lines` empty: all views drawn in one GPU submission and
    /// read back after one wait (docs/benchmarks.md "Benchmarks": the per-submission cost of lavapipe is paid
    /// once per scene). The pixels are those of [`Renderer::render_pixels`] view by view.
    pub fn render_views_pixels(
        &self,
        scene: &Scene,
        views: &[CornerView],
        opts: &RenderOptions,
    ) -> Result<Vec<RenderedView>, RenderError> {
        self.check_options(opts)?;
        if opts.look != Look::LineArt || opts.downsample > 1 {
            return views
                .iter()
                .map(|&view| self.render_pixels_through_sensor(scene, view, opts))
                .collect();
        }
        self.render_views_pixels_framed(scene, views, opts, &scene.world_vertices())
    }

    /// [`Renderer::render_views_pixels`] in line art with each camera framed on `frame_mm`
    /// instead of the scene's own vertices: the frames of a fall drawn from one fixed camera
    /// (docs/stability.md "A fall in pictures"). Other looks are refused.
    pub fn render_views_pixels_framed(
        &self,
        scene: &Scene,
        views: &[CornerView],
        opts: &RenderOptions,
        frame_mm: &[DVec3],
    ) -> Result<Vec<RenderedView>, RenderError> {
        self.check_options(opts)?;
        if opts.look != Look::LineArt || opts.downsample > 1 {
            return Err(RenderError::Options(
                "a camera framed on given points draws line art only; drop --look and --downsample"
                    .into(),
            ));
        }
        let points = frame_mm;
        let cameras: Vec<Camera> = views
            .iter()
            .map(|v| Camera::frame(points, *v, &opts.camera))
            .collect();
        let meshes = cameras
            .iter()
            .map(|c| view_mesh(scene, c))
            .collect::<Result<Vec<_>, _>>()?;
        let requests: Vec<gpu::FrameRequest<'_>> = cameras
            .iter()
            .zip(&meshes)
            .map(|(c, m)| gpu::FrameRequest {
                vertices: m,
                uniforms: frame_uniforms(c),
                floor: mesh::floor_fill(scene, c),
            })
            .collect();
        let frames = self
            .gpu
            .draw_many(&requests, opts.camera.size_px, opts.msaa)?;
        cameras
            .into_iter()
            .zip(frames)
            .map(|(camera, frame)| rendered_view(camera, frame, opts))
            .collect()
    }

    /// Renders the given views of `scene` (usually [`CornerView::ALL`]) with their exact line
    /// drawings; the pixels of all views come from one submission
    /// ([`Renderer::render_views_pixels`]).
    pub fn render_views(
        &self,
        scene: &Scene,
        views: &[CornerView],
        opts: &RenderOptions,
    ) -> Result<Vec<RenderedView>, RenderError> {
        let rendered = self.render_views_pixels(scene, views, opts)?;
        Ok(with_exact_lines(scene, rendered))
    }

    /// [`Renderer::render_views_pixels_framed`] with each view's exact line drawing: the frames
    /// of a fall seen by the cameras of the scene at rest-start, each with its whole ground
    /// truth (`generate --trajectory-views`, docs/stability.md "Rendered frames").
    pub fn render_views_framed(
        &self,
        scene: &Scene,
        views: &[CornerView],
        opts: &RenderOptions,
        frame_mm: &[DVec3],
    ) -> Result<Vec<RenderedView>, RenderError> {
        let rendered = self.render_views_pixels_framed(scene, views, opts, frame_mm)?;
        Ok(with_exact_lines(scene, rendered))
    }

    /// Adapter name and backend, for logs and benchmark tables.
    pub fn adapter_info(&self) -> String {
        self.gpu.adapter_info()
    }

    /// Checks options against this device's limits before anything is rendered: each side at
    /// most the largest texture, and the readback of gray, depth and ids (5 bytes per pixel)
    /// within the largest buffer; the error says which sizes work.
    pub fn check_options(&self, opts: &RenderOptions) -> Result<(), RenderError> {
        opts.validate()?;
        let [w, h] = opts.camera.size_px;
        let max = self.gpu.max_texture_px();
        if w > max || h > max {
            return Err(RenderError::Options(format!(
                "picture size {w}x{h} px: each side must be 1..={max} on this device"
            )));
        }
        if let Err(side) = self.gpu.readback_fits([w, h]) {
            return Err(RenderError::Options(format!(
                "picture size {w}x{h} px is too large for this device: its largest buffer \
                 cannot hold the picture with its depth and ids (5 bytes per pixel); use at \
                 most about {} Mpx, e.g. {side}x{side}",
                (side as u64 * side as u64) / 1_000_000
            )));
        }
        Ok(())
    }
}

/// The views with their `lines` set to the exact visible line drawing of `scene` in each
/// view's camera.
fn with_exact_lines(scene: &Scene, mut rendered: Vec<RenderedView>) -> Vec<RenderedView> {
    for v in &mut rendered {
        v.lines = linedraw::visible_line_drawing_with_progress(
            scene,
            &v.camera,
            &linedraw::TruthTolerances::default(),
            &|_, _| {},
        );
    }
    rendered
}

/// The triangles of `scene` seen by `camera`; a face the renderer cannot draw is an options
/// error naming it.
fn view_mesh(scene: &Scene, camera: &Camera) -> Result<Vec<mesh::Vertex>, RenderError> {
    mesh::scene_vertices(scene, camera).map_err(|e| {
        RenderError::Options(format!(
            "block {} face {} has {} edges; the renderer draws faces of at most {} edges",
            e.block,
            e.face,
            e.edges,
            mesh::MAX_FACE_EDGES
        ))
    })
}

/// One view from its camera and the frame read back: the gray picture with the view's sensor
/// noise, depth and ids; `lines` empty.
fn rendered_view(
    camera: Camera,
    frame: gpu::Frame,
    opts: &RenderOptions,
) -> Result<RenderedView, RenderError> {
    let [w, h] = opts.camera.size_px;
    let mut gray = GrayImage::from_raw(w, h, frame.gray)
        .ok_or_else(|| RenderError::Gpu("gray readback has the wrong size".into()))?;
    add_sensor_noise(
        &mut gray,
        opts.noise_sigma,
        noise_seed(opts.seed, camera.view),
    );
    let depth = Gray16Image::from_raw(w, h, frame.depth)
        .ok_or_else(|| RenderError::Gpu("depth readback has the wrong size".into()))?;
    let ids = Gray16Image::from_raw(w, h, frame.ids)
        .ok_or_else(|| RenderError::Gpu("ids readback has the wrong size".into()))?;
    Ok(RenderedView {
        camera,
        gray,
        depth,
        ids,
        lines: LineDrawing::default(),
        towards_lights: Vec::new(),
        edge_radius_mm: 0.0,
    })
}

/// The noise seed of one view: the options' seed mixed with the view, so the four views get
/// different but reproducible noise.
fn noise_seed(seed: u64, view: CornerView) -> u64 {
    let v = view.index() as u64;
    seed ^ (v + 1).wrapping_mul(0x9E37_79B9_7F4A_7C15)
}

/// The shader constants of one view: the camera's matrices in f32.
fn frame_uniforms(camera: &Camera) -> gpu::FrameUniforms {
    let clip = camera.clip_from_world().as_mat4().to_cols_array();
    let z_row = camera.view_matrix().row(2).as_vec4().to_array();
    gpu::FrameUniforms {
        clip_from_world: clip,
        view_z_row: z_row,
        seam_half_width_px: SEAM_HALF_WIDTH_PX as f32,
        seam_level: f32::from(SEAM_LEVEL),
        depth_units_per_mm: DEPTH_UNITS_PER_MM as f32,
        pad: 0.0,
    }
}

/// Adds Gaussian sensor noise of standard deviation `sigma_levels` (the thesis's CCD camera,
/// Ch. VI) to every pixel, rounded and clamped to 0..=255; deterministic in `seed`.
pub fn add_sensor_noise(gray: &mut GrayImage, sigma_levels: f64, seed: u64) {
    use rand::SeedableRng;
    use rand_distr::Distribution;
    if sigma_levels <= 0.0 {
        return;
    }
    let Ok(normal) = rand_distr::Normal::new(0.0, sigma_levels) else {
        return;
    };
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    for p in gray.pixels_mut() {
        let v = f64::from(p.0[0]) + normal.sample(&mut rng);
        p.0[0] = v.round().clamp(0.0, 255.0) as u8;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Regression: after `--backend gl` failed, the hint suggested `--backend gl` and named the
    /// Vulkan packages.
    #[test]
    fn no_adapter_hint_suggests_the_other_backend() {
        let gl = RenderError::NoAdapter {
            backend: "GL",
            detail: "none".into(),
        }
        .to_string();
        assert!(
            gl.contains("--backend vulkan") && !gl.contains("--backend gl"),
            "{gl}"
        );
        assert!(!gl.contains("mesa-vulkan-drivers"), "{gl}");
        let vk = RenderError::NoAdapter {
            backend: "Vulkan",
            detail: "none".into(),
        }
        .to_string();
        assert!(
            vk.contains("--backend gl") && vk.contains("mesa-vulkan-drivers"),
            "{vk}"
        );
    }

    #[test]
    fn noise_is_deterministic_per_seed_and_view() {
        let base = GrayImage::from_pixel(16, 16, Luma([100]));
        let noisy = |seed, view| {
            let mut g = base.clone();
            add_sensor_noise(&mut g, 5.0, noise_seed(seed, view));
            g
        };
        assert_eq!(noisy(1, CornerView::Ne), noisy(1, CornerView::Ne));
        assert_ne!(noisy(1, CornerView::Ne), noisy(2, CornerView::Ne));
        assert_ne!(noisy(1, CornerView::Ne), noisy(1, CornerView::Se));
        assert_ne!(noisy(1, CornerView::Ne), base);
        let mut clean = base.clone();
        add_sensor_noise(&mut clean, 0.0, 7);
        assert_eq!(clean, base);
    }
}
