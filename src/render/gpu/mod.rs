//! The only wgpu code of blockworld: the device (made once), the pipelines of
//! `shaders/scene.wgsl`, cached render targets and the readback of the gray picture, depth and
//! block ids.
//!
//! Several frames (a dataset scene's four corner views) go to the device in ONE submission and
//! come back through ONE wait on the device ([`Gpu::draw_many`]): each frame's passes and copy
//! into its own readback buffer are recorded into one command encoder, so the per-submission
//! cost of lavapipe (waking its rasterizer threads, the fence, the map) is paid once per scene,
//! not once per view (docs/benchmarks.md "Benchmarks").
//!
//! Without MSAA one pass writes the whole pixel into ONE `R32Uint` target when every block id
//! fits 8 bits (at most 255 blocks): depth in the high 16 bits, the gray level, the id
//! ([`PixelLayout::Word`]); larger scenes get two targets, the gray level (`R8Uint`) and depth
//! with a 16-bit id in one word ([`PixelLayout::GrayAndTruth`]). One target instead of the
//! three separate pictures spares lavapipe two color stores per pixel, two clears and two
//! copies (docs/benchmarks.md "Peers"); the readback splits the words while it drops the row
//! padding, so the frames are those of separate targets. With MSAA 4 the gray picture is drawn
//! multisampled (`R8Unorm`, resolving averages) and resolved, and a second single-sampled pass
//! draws the ground truth (`R32Uint`, as in the two-target layout), so depth and ids are never
//! blended.
//!
//! Where the floor fills the picture ([`mesh::floor_fill`]), the pass that writes depth and ids
//! does not draw it: the target starts from the floor's gray level and id 0, and the readback
//! writes the floor's exact depth into the pixels no block covers (docs/rendering.md "Rendering").

pub mod mesh;
pub mod photo;

use super::{Backend, RenderError};
use mesh::{DrawOrder, FloorFill, SeamLines, Vertex};
use std::sync::{Arc, Mutex};

/// The shader source, compiled in so an edited shader triggers a rebuild.
const SCENE_WGSL: &str = include_str!("../../../shaders/scene.wgsl");

/// The single-sampled pass's gray picture: the level as an integer.
const GRAY_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R8Uint;
/// The multisampled gray picture and its resolve target (resolving averages normalized values).
const GRAY_MSAA_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R8Unorm;
/// The ground truth: `depth << 16 | block id` (`truth_of` in `shaders/scene.wgsl`), or the
/// whole pixel `depth << 16 | gray << 8 | block id` (`pixel_of`).
const TRUTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Uint;

/// Largest block id (index + 1) the one-word pixel holds.
const MAX_WORD_BLOCK_ID: u32 = 0xff;

/// How a single-sampled frame's pixels are laid out in its targets.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum PixelLayout {
    /// One `R32Uint` target: `depth << 16 | gray << 8 | id` (ids up to [`MAX_WORD_BLOCK_ID`]).
    Word,
    /// The gray level in its own target and `depth << 16 | id` in the other (any id up to
    /// 65535; also the layout of the multisampled frames' ground truth).
    GrayAndTruth,
}

impl PixelLayout {
    /// The layout for frames drawn with `msaa` samples whose largest block id is `max_id`.
    fn of(msaa: u32, max_id: u32) -> PixelLayout {
        if msaa == 1 && max_id <= MAX_WORD_BLOCK_ID {
            PixelLayout::Word
        } else {
            PixelLayout::GrayAndTruth
        }
    }
}
const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// How many differently sized target sets stay cached.
const MAX_CACHED_TARGETS: usize = 4;

/// Most frames recorded into one submission: the four corner views of a scene.
pub const MAX_FRAMES_PER_SUBMISSION: usize = 4;

/// Readback bytes one submission may hold at most (256 MiB): larger pictures go fewer frames at a
/// time, so four views of a huge picture never need four huge buffers at once.
const MAX_SUBMISSION_READBACK_BYTES: u64 = 256 << 20;

/// Bytes between the frames' uniforms in the uniform buffer: wgpu's
/// `min_uniform_buffer_offset_alignment` on every device (256).
const UNIFORM_STRIDE: u64 = 256;

/// Per-frame shader constants (`Frame` in `shaders/scene.wgsl`).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct FrameUniforms {
    /// World mm to clip space, column-major.
    pub clip_from_world: [f32; 16],
    /// Third row of the world-to-camera matrix (depth = -dot(row, p)).
    pub view_z_row: [f32; 4],
    /// Seam half width in px.
    pub seam_half_width_px: f32,
    /// Seam gray level.
    pub seam_level: f32,
    /// Depth PNG steps per mm.
    pub depth_units_per_mm: f32,
    /// Padding to 16 bytes.
    pub pad: f32,
}

/// One frame to draw: its triangles and its shader constants.
#[derive(Debug, Clone, Copy)]
pub struct FrameRequest<'a> {
    /// Triangle list of the frame (its camera's mesh, [`mesh::scene_vertices`]).
    pub vertices: &'a [Vertex],
    /// The frame's shader constants.
    pub uniforms: FrameUniforms,
    /// The floor computed instead of drawn ([`mesh::floor_fill`]), when it fills the picture:
    /// the pass that writes depth and ids then skips the floor's triangles.
    pub floor: Option<FloorFill>,
}

/// One frame read back, rows top to bottom, tightly packed.
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    /// Gray levels, `w * h`.
    pub gray: Vec<u8>,
    /// Depth in 1/16 mm, `w * h`.
    pub depth: Vec<u16>,
    /// Block index + 1, `w * h`.
    pub ids: Vec<u16>,
}

/// The pipelines of one pass, one per [`SeamLines`] variant of the shader.
struct SeamPipelines {
    none: wgpu::RenderPipeline,
    four: wgpu::RenderPipeline,
    eight: wgpu::RenderPipeline,
}

/// A pass's pipeline for each [`SeamLines`] variant.
type PipelineOf<'a> = [&'a wgpu::RenderPipeline; 3];

impl SeamPipelines {
    fn by_variant(&self) -> PipelineOf<'_> {
        [&self.none, &self.four, &self.eight]
    }
}

/// The index of `lines` in a [`PipelineOf`].
fn variant_index(lines: SeamLines) -> usize {
    match lines {
        SeamLines::None => 0,
        SeamLines::Four => 1,
        SeamLines::Eight => 2,
    }
}

struct Pipelines {
    /// Single-sampled gray, depth and ids in one word ([`PixelLayout::Word`]).
    word: SeamPipelines,
    /// The same keeping fragments as near as what is drawn, for blocks drawn in
    /// [`DrawOrder::Descending`].
    word_as_near: SeamPipelines,
    /// Single-sampled gray + depth and ids ([`PixelLayout::GrayAndTruth`]).
    all: SeamPipelines,
    /// Gray only, 4 samples.
    gray_msaa4: SeamPipelines,
    /// Depth + ids, single-sampled.
    truth: wgpu::RenderPipeline,
}

/// Bytes per row of each readback region (the gray picture, then the packed ground truth),
/// padded to `COPY_BYTES_PER_ROW_ALIGNMENT`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct ReadbackLayout {
    gray_row: u32,
    truth_row: u32,
    height: u32,
}

impl ReadbackLayout {
    fn new([w, h]: [u32; 2]) -> ReadbackLayout {
        let align = wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
        ReadbackLayout {
            gray_row: w.div_ceil(align) * align,
            truth_row: (4 * w).div_ceil(align) * align,
            height: h,
        }
    }
    fn truth_offset(&self) -> u64 {
        self.gray_row as u64 * self.height as u64
    }
    fn total(&self) -> u64 {
        self.truth_offset() + self.truth_row as u64 * self.height as u64
    }
}

/// Render targets and the readback buffer for one (size, msaa).
struct Targets {
    size: [u32; 2],
    msaa: u32,
    /// The gray picture ([`GRAY_FORMAT`], or the resolve target in [`GRAY_MSAA_FORMAT`]).
    gray: wgpu::Texture,
    gray_view: wgpu::TextureView,
    /// Depth and block ids packed ([`TRUTH_FORMAT`]).
    truth: wgpu::Texture,
    truth_view: wgpu::TextureView,
    depth_buffer_view: wgpu::TextureView,
    /// Multisampled gray and depth buffer (MSAA 4 only).
    msaa_views: Option<(wgpu::TextureView, wgpu::TextureView)>,
    /// One readback buffer per frame of a submission, created as submissions need them.
    readbacks: Vec<wgpu::Buffer>,
    layout: ReadbackLayout,
}

/// Mutable state behind the lock: the growable vertex buffer and cached targets.
#[derive(Default)]
struct State {
    vertices: Option<wgpu::Buffer>,
    targets: Vec<Targets>,
}

/// The device with its pipelines; all rendering goes through [`Gpu::draw`].
pub struct Gpu {
    device: wgpu::Device,
    queue: wgpu::Queue,
    info: wgpu::AdapterInfo,
    pipelines: Pipelines,
    uniforms: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
    max_texture_px: u32,
    max_buffer_bytes: u64,
    /// Errors wgpu reported outside any error scope (instead of panicking).
    uncaptured: Arc<Mutex<Vec<String>>>,
    state: Mutex<State>,
}

/// The adapter `backend` offers (lavapipe on this project's machines), and the backend's name
/// for errors: what [`Gpu::new`] builds its device on.
fn request_adapter(backend: Backend) -> Result<(wgpu::Adapter, &'static str), RenderError> {
    let (backends, name) = match backend {
        Backend::Vulkan => (wgpu::Backends::VULKAN, "Vulkan"),
        Backend::Gl => (wgpu::Backends::GL, "GL"),
    };
    let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
    desc.backends = backends;
    desc.flags = wgpu::InstanceFlags::empty();
    let instance = wgpu::Instance::new(desc);
    let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
        power_preference: wgpu::PowerPreference::HighPerformance,
        force_fallback_adapter: false,
        ..Default::default()
    }))
    .map_err(|e| RenderError::NoAdapter {
        backend: name,
        detail: e.to_string(),
    })?;
    Ok((adapter, name))
}

/// "name (backend, device type, driver)" of an adapter.
fn describe(info: &wgpu::AdapterInfo) -> String {
    format!(
        "{} ({:?}, {:?}, driver {} {})",
        info.name, info.backend, info.device_type, info.driver, info.driver_info
    )
}

/// [`Gpu::adapter_info`] of the adapter `backend` offers, without creating a device (tens of
/// milliseconds instead of a device and its pipelines): for benchmark tables of stages that
/// do not render, which still name the rasterizer of the machine they ran on (docs/benchmarks.md
/// "Benchmarks").
pub fn adapter_summary(backend: Backend) -> Result<String, RenderError> {
    request_adapter(backend).map(|(adapter, _)| describe(&adapter.get_info()))
}

impl Gpu {
    /// Creates instance, adapter, device and pipelines on `backend`.
    pub fn new(backend: Backend) -> Result<Gpu, RenderError> {
        let (adapter, name) = request_adapter(backend)?;
        let info = adapter.get_info();
        let limits = adapter.limits();
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("blockworld"),
            required_features: wgpu::Features::empty(),
            required_limits: wgpu::Limits::downlevel_webgl2_defaults().using_resolution(limits),
            experimental_features: wgpu::ExperimentalFeatures::disabled(),
            memory_hints: wgpu::MemoryHints::Performance,
            trace: wgpu::Trace::Off,
        }))
        .map_err(|e| RenderError::Gpu(format!("cannot create a {name} device: {e}")))?;
        let uncaptured = Arc::new(Mutex::new(Vec::new()));
        let sink = Arc::clone(&uncaptured);
        device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
            tracing::error!("wgpu: {e}");
            if let Ok(mut v) = sink.lock() {
                v.push(e.to_string());
            }
        }));
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let (pipelines, uniforms, bind_group) = create_pipelines(&device);
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(RenderError::Gpu(format!("creating pipelines: {e}")));
        }
        Ok(Gpu {
            max_texture_px: device.limits().max_texture_dimension_2d,
            max_buffer_bytes: device.limits().max_buffer_size,
            device,
            queue,
            info,
            pipelines,
            uniforms,
            bind_group,
            uncaptured,
            state: Mutex::new(State::default()),
        })
    }

    /// "name (backend, device type, driver)", for logs and benchmark tables.
    pub fn adapter_info(&self) -> String {
        describe(&self.info)
    }

    /// Largest picture side the device accepts, px.
    pub fn max_texture_px(&self) -> u32 {
        self.max_texture_px
    }

    /// Whether a `size` picture's readback buffer (gray, depth and ids, rows padded) fits the
    /// device's `max_buffer_size`; otherwise the largest square side that fits, px.
    pub fn readback_fits(&self, size: [u32; 2]) -> Result<(), u32> {
        if ReadbackLayout::new(size).total() <= self.max_buffer_bytes {
            return Ok(());
        }
        let (mut lo, mut hi) = (1u32, self.max_texture_px);
        while lo < hi {
            let mid = lo + (hi - lo).div_ceil(2);
            if ReadbackLayout::new([mid, mid]).total() <= self.max_buffer_bytes {
                lo = mid;
            } else {
                hi = mid - 1;
            }
        }
        Err(lo)
    }

    /// Draws every request into `size` px targets with `msaa` samples and reads them back, in
    /// order: up to [`MAX_FRAMES_PER_SUBMISSION`] frames per submission and per wait.
    pub fn draw_many(
        &self,
        requests: &[FrameRequest<'_>],
        size: [u32; 2],
        msaa: u32,
    ) -> Result<Vec<Frame>, RenderError> {
        let per_submission = frames_per_submission(ReadbackLayout::new(size).total());
        let mut frames = Vec::with_capacity(requests.len());
        for chunk in requests.chunks(per_submission) {
            frames.extend(self.draw_submission(chunk, size, msaa)?);
        }
        Ok(frames)
    }

    /// One submission: every frame's passes and readback copy in one command buffer, then one
    /// wait for all of them.
    fn draw_submission(
        &self,
        requests: &[FrameRequest<'_>],
        size: [u32; 2],
        msaa: u32,
    ) -> Result<Vec<Frame>, RenderError> {
        let mut state = self
            .state
            .lock()
            .map_err(|_| RenderError::Gpu("renderer state poisoned by an earlier panic".into()))?;
        let state = &mut *state;
        let started = std::time::Instant::now();
        let scope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let oom = self.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let max_id = requests
            .iter()
            .flat_map(|r| r.vertices.iter().map(|v| v.block_id))
            .max()
            .unwrap_or(0);
        let layout = PixelLayout::of(msaa, max_id);
        // Nearer blocks first where the one-word pixel has the pipelines for it.
        let ordered: Vec<(std::borrow::Cow<'_, [Vertex]>, DrawOrder)> = requests
            .iter()
            .map(|r| {
                let order = match layout {
                    PixelLayout::Word => {
                        mesh::nearer_first_order(r.vertices, r.uniforms.view_z_row)
                    }
                    PixelLayout::GrayAndTruth => DrawOrder::Ascending,
                };
                (mesh::in_draw_order(r.vertices, order), order)
            })
            .collect();
        let firsts = self.upload(&mut state.vertices, requests, &ordered);
        let vbuf = state.vertices.as_ref().expect("uploaded");
        let targets = self.targets(&mut state.targets, size, msaa);
        self.ensure_readbacks(targets, requests.len());
        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
        for (i, ((vertices, order), first)) in ordered.iter().zip(firsts).enumerate() {
            let uniform_offset = (i as u64 * UNIFORM_STRIDE) as u32;
            let runs = draw_runs(vertices, *order, first);
            let floor = requests[i].floor.as_ref();
            let frame = FramePasses {
                runs: &runs,
                uniform_offset,
                floor,
            };
            self.encode_passes(&mut encoder, targets, layout, vbuf, &frame);
            encode_readback(&mut encoder, targets, layout, &targets.readbacks[i]);
        }
        self.queue.submit([encoder.finish()]);
        let submitted = started.elapsed();
        let floors: Vec<Option<FloorFill>> = requests.iter().map(|r| r.floor).collect();
        let result = self.read_back(targets, layout, &floors);
        tracing::debug!(
            frames = requests.len(),
            submit_ms = submitted.as_secs_f64() * 1e3,
            total_ms = started.elapsed().as_secs_f64() * 1e3,
            "gpu draw + readback"
        );
        let oom_error = pollster::block_on(oom.pop());
        let validation_error = pollster::block_on(scope.pop());
        if let Some(e) = validation_error.or(oom_error) {
            return Err(RenderError::Gpu(e.to_string()));
        }
        if let Some(e) = self.uncaptured.lock().ok().and_then(|mut v| v.pop()) {
            return Err(RenderError::Gpu(e));
        }
        result
    }

    /// Writes every request's vertices (`ordered`, in their drawing order) one after another
    /// into the vertex buffer and its uniforms at `i * UNIFORM_STRIDE`; returns each frame's
    /// first vertex.
    fn upload(
        &self,
        slot: &mut Option<wgpu::Buffer>,
        requests: &[FrameRequest<'_>],
        ordered: &[(std::borrow::Cow<'_, [Vertex]>, DrawOrder)],
    ) -> Vec<u32> {
        let total_bytes: u64 = ordered
            .iter()
            .map(|(v, _)| std::mem::size_of_val(&**v) as u64)
            .sum();
        let vbuf = self.vertex_buffer(slot, total_bytes);
        let (mut byte_offset, mut first) = (0u64, 0u32);
        let mut firsts = Vec::with_capacity(requests.len());
        for (i, (r, (vertices, _))) in requests.iter().zip(ordered).enumerate() {
            let bytes: &[u8] = bytemuck::cast_slice(vertices);
            self.queue.write_buffer(vbuf, byte_offset, bytes);
            self.queue.write_buffer(
                &self.uniforms,
                i as u64 * UNIFORM_STRIDE,
                bytemuck::bytes_of(&r.uniforms),
            );
            firsts.push(first);
            byte_offset += bytes.len() as u64;
            first += vertices.len() as u32;
        }
        firsts
    }

    /// Creates readback buffers until `targets` has one per frame of the submission.
    fn ensure_readbacks(&self, targets: &mut Targets, frames: usize) {
        while targets.readbacks.len() < frames {
            targets
                .readbacks
                .push(self.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("readback"),
                    size: targets.layout.total(),
                    usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                }));
        }
    }

    /// The vertex buffer, grown (to a power of two) only when the scene does not fit.
    fn vertex_buffer<'a>(
        &self,
        slot: &'a mut Option<wgpu::Buffer>,
        bytes: u64,
    ) -> &'a wgpu::Buffer {
        let fits = slot.as_ref().is_some_and(|b| b.size() >= bytes);
        if !fits {
            *slot = Some(self.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("scene vertices"),
                size: bytes.next_power_of_two().max(64 * 1024),
                usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }));
        }
        slot.as_ref().expect("just created")
    }

    /// The cached targets for (size, msaa), created on first use.
    fn targets<'a>(
        &self,
        cache: &'a mut Vec<Targets>,
        size: [u32; 2],
        msaa: u32,
    ) -> &'a mut Targets {
        let found = cache.iter().position(|t| t.size == size && t.msaa == msaa);
        let index = match found {
            Some(i) => i,
            None => {
                if cache.len() >= MAX_CACHED_TARGETS {
                    cache.remove(0);
                }
                cache.push(self.create_targets(size, msaa));
                cache.len() - 1
            }
        };
        &mut cache[index]
    }

    fn create_targets(&self, size: [u32; 2], msaa: u32) -> Targets {
        let texture = |label, format, samples, usage| {
            let t = self.device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d {
                    width: size[0],
                    height: size[1],
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: samples,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            });
            let v = t.create_view(&wgpu::TextureViewDescriptor::default());
            (t, v)
        };
        let readable = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC;
        let attachment = wgpu::TextureUsages::RENDER_ATTACHMENT;
        let gray_format = if msaa > 1 {
            GRAY_MSAA_FORMAT
        } else {
            GRAY_FORMAT
        };
        let (gray, gray_view) = texture("gray", gray_format, 1, readable);
        let (truth, truth_view) = texture("depth and ids", TRUTH_FORMAT, 1, readable);
        let (_, depth_buffer_view) = texture("depth buffer", DEPTH_FORMAT, 1, attachment);
        let msaa_views = (msaa > 1).then(|| {
            let (_, c) = texture("gray msaa", GRAY_MSAA_FORMAT, msaa, attachment);
            let (_, d) = texture("depth buffer msaa", DEPTH_FORMAT, msaa, attachment);
            (c, d)
        });
        let layout = ReadbackLayout::new(size);
        Targets {
            size,
            msaa,
            gray,
            gray_view,
            truth,
            truth_view,
            depth_buffer_view,
            msaa_views,
            readbacks: Vec::new(),
            layout,
        }
    }

    /// Records the frame's passes: each run of triangles (`runs`, vertex ranges in drawing
    /// order) drawn with the pipeline of its [`SeamLines`] variant, keeping fragments as near
    /// as what is drawn where the run says so ([`draw_runs`]; one-word pixels only).
    fn encode_passes(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        t: &Targets,
        layout: PixelLayout,
        vbuf: &wgpu::Buffer,
        frame: &FramePasses<'_>,
    ) {
        // The background level: an integer in the integer target, normalized in the
        // multisampled one. A single-sampled pass whose floor is computed starts from the
        // floor's level instead, which every pixel no block covers then keeps; the
        // multisampled picture still draws the floor (its samples are resolved together).
        let background = f64::from(super::BACKGROUND_LEVEL);
        let single_sampled_level = frame.floor.map_or(background, |f| f64::from(f.gray_level));
        let clear_gray = wgpu::Color {
            r: if t.msaa_views.is_some() {
                background / 255.0
            } else {
                single_sampled_level
            },
            g: 0.0,
            b: 0.0,
            a: 1.0,
        };
        let gray_target = |view, resolve| wgpu::RenderPassColorAttachment {
            view,
            depth_slice: None,
            resolve_target: resolve,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Clear(clear_gray),
                store: wgpu::StoreOp::Store,
            },
        };
        let truth_target = |view, clear| wgpu::RenderPassColorAttachment {
            view,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Clear(clear),
                store: wgpu::StoreOp::Store,
            },
        };
        // Depth 0, id 0 and, in the one-word pixel, the background (or floor) level at bits
        // 8..15.
        let clear_word = wgpu::Color {
            r: single_sampled_level * 256.0,
            ..wgpu::Color::TRANSPARENT
        };
        let uniform_offset = frame.uniform_offset;
        let all_runs = frame.runs;
        let truth_runs: Vec<DrawRun> = all_runs
            .iter()
            .filter(|r| frame.floor.is_none() || !r.floor)
            .cloned()
            .collect();
        let mut pass = |pipelines: [PipelineOf<'_>; 2],
                        colors: &[Option<wgpu::RenderPassColorAttachment>],
                        depth_buffer: &wgpu::TextureView,
                        runs: &[DrawRun]| {
            let mut rp = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: None,
                color_attachments: colors,
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: depth_buffer,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Discard,
                    }),
                    stencil_ops: None,
                }),
                ..Default::default()
            });
            rp.set_bind_group(0, &self.bind_group, &[uniform_offset]);
            rp.set_vertex_buffer(0, vbuf.slice(..));
            for run in runs {
                rp.set_pipeline(pipelines[usize::from(run.as_near)][variant_index(run.lines)]);
                rp.draw(run.vertices.clone(), 0..1);
            }
        };
        match &t.msaa_views {
            None if layout == PixelLayout::Word => pass(
                [
                    self.pipelines.word.by_variant(),
                    self.pipelines.word_as_near.by_variant(),
                ],
                &[Some(truth_target(&t.truth_view, clear_word))],
                &t.depth_buffer_view,
                &truth_runs,
            ),
            None => pass(
                [self.pipelines.all.by_variant(); 2],
                &[
                    Some(gray_target(&t.gray_view, None)),
                    Some(truth_target(&t.truth_view, wgpu::Color::TRANSPARENT)),
                ],
                &t.depth_buffer_view,
                &truth_runs,
            ),
            Some((color, depth_buffer)) => {
                pass(
                    [self.pipelines.gray_msaa4.by_variant(); 2],
                    &[Some(gray_target(color, Some(&t.gray_view)))],
                    depth_buffer,
                    all_runs,
                );
                pass(
                    [[&self.pipelines.truth; 3]; 2],
                    &[Some(truth_target(&t.truth_view, wgpu::Color::TRANSPARENT))],
                    &t.depth_buffer_view,
                    &truth_runs,
                );
            }
        }
    }

    /// Maps the readback buffers of `floors.len()` frames, waits once, and unpads their rows,
    /// writing each computed floor's depth ([`FloorFill`]).
    fn read_back(
        &self,
        t: &Targets,
        layout: PixelLayout,
        floors: &[Option<FloorFill>],
    ) -> Result<Vec<Frame>, RenderError> {
        let frames = floors.len();
        let buffers = &t.readbacks[..frames];
        let (tx, rx) = std::sync::mpsc::channel();
        for buffer in buffers {
            let tx = tx.clone();
            buffer.map_async(wgpu::MapMode::Read, .., move |r| {
                let _ = tx.send(r);
            });
        }
        drop(tx);
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| RenderError::Gpu(format!("waiting for the GPU: {e}")))?;
        for _ in buffers {
            rx.recv()
                .map_err(|_| RenderError::Gpu("readback callback never ran".into()))?
                .map_err(|e| RenderError::Gpu(format!("mapping the readback buffer: {e}")))?;
        }
        let mut out = Vec::with_capacity(frames);
        for (buffer, floor) in buffers.iter().zip(floors) {
            let frame = {
                let bytes = buffer
                    .get_mapped_range(..)
                    .map_err(|e| RenderError::Gpu(format!("reading the readback buffer: {e}")))?;
                unpad(PackedFrame {
                    bytes: &bytes,
                    size: t.size,
                    rows: &t.layout,
                    pixels: layout,
                    floor: floor.as_ref(),
                })
            };
            buffer.unmap();
            out.push(frame);
        }
        Ok(out)
    }
}

/// What one frame's passes draw: its runs, where its uniforms sit, and its computed floor.
struct FramePasses<'a> {
    runs: &'a [DrawRun],
    uniform_offset: u32,
    floor: Option<&'a FloorFill>,
}

/// A run of consecutive triangles drawn with one pipeline.
#[derive(Debug, Clone, PartialEq, Eq)]
struct DrawRun {
    /// Vertex range in the vertex buffer.
    vertices: std::ops::Range<u32>,
    /// The seam-line variant of its faces.
    lines: SeamLines,
    /// Whether fragments as near as what is drawn are kept (`LessEqual`): the blocks of a
    /// [`DrawOrder::Descending`] mesh, never the floor.
    as_near: bool,
    /// Whether the run is the floor's (skipped where the floor is computed, [`FloorFill`]).
    floor: bool,
}

/// The runs of a frame whose mesh (`vertices`, in drawing `order`) starts at vertex `first`:
/// the blocks' runs ([`mesh::seam_line_runs`]), then the floor's, which always keeps only
/// nearer fragments.
fn draw_runs(vertices: &[Vertex], order: DrawOrder, first: u32) -> Vec<DrawRun> {
    let blocks = mesh::block_vertex_count(vertices);
    let parts = [
        (
            0,
            &vertices[..blocks],
            order == DrawOrder::Descending,
            false,
        ),
        (blocks, &vertices[blocks..], false, true),
    ];
    let mut runs = Vec::new();
    for (start, part, as_near, floor) in parts {
        let offset = first + start as u32;
        runs.extend(
            mesh::seam_line_runs(part)
                .into_iter()
                .map(|(r, lines)| DrawRun {
                    vertices: r.start + offset..r.end + offset,
                    lines,
                    as_near,
                    floor,
                }),
        );
    }
    runs
}

/// Frames per submission for pictures of `readback_bytes` each: all four views unless that
/// would hold more than [`MAX_SUBMISSION_READBACK_BYTES`] of readback, never fewer than one.
fn frames_per_submission(readback_bytes: u64) -> usize {
    let fit = MAX_SUBMISSION_READBACK_BYTES / readback_bytes.max(1);
    (fit as usize).clamp(1, MAX_FRAMES_PER_SUBMISSION)
}

/// Copies the frame's targets into `readback` (the gray region stays unused in the one-word
/// layout), rows padded to 256 bytes.
fn encode_readback(
    encoder: &mut wgpu::CommandEncoder,
    t: &Targets,
    layout: PixelLayout,
    readback: &wgpu::Buffer,
) {
    let l = &t.layout;
    let extent = wgpu::Extent3d {
        width: t.size[0],
        height: t.size[1],
        depth_or_array_layers: 1,
    };
    let gray = (layout == PixelLayout::GrayAndTruth).then_some((&t.gray, 0, l.gray_row));
    let truth = Some((&t.truth, l.truth_offset(), l.truth_row));
    for (texture, offset, row) in [gray, truth].into_iter().flatten() {
        encoder.copy_texture_to_buffer(
            texture.as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer: readback,
                layout: wgpu::TexelCopyBufferLayout {
                    offset,
                    bytes_per_row: Some(row),
                    rows_per_image: Some(t.size[1]),
                },
            },
            extent,
        );
    }
}

/// One frame's bytes as read back, and what is needed to unpack them ([`unpad`]).
#[derive(Clone, Copy)]
struct PackedFrame<'a> {
    /// The mapped readback buffer.
    bytes: &'a [u8],
    /// Picture width and height, px.
    size: [u32; 2],
    /// Where the targets' rows sit in `bytes`.
    rows: &'a ReadbackLayout,
    /// How the pixels are packed.
    pixels: PixelLayout,
    /// The computed floor, if any ([`FloorFill`]).
    floor: Option<&'a FloorFill>,
}

/// Drops the row padding and splits the packed words into gray, depth (high 16 bits) and ids in
/// the same pass: tight `w * h` images, rows top to bottom; a computed floor's depth
/// ([`FloorFill`]) goes into every pixel no block covers. The loops are compiled twice, for
/// baseline x86-64 and for AVX2 (chosen at run time when the CPU has it): the same results,
/// twice the lanes.
fn unpad(packed: PackedFrame<'_>) -> Frame {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has AVX2, checked just above.
        return unsafe { unpad_avx2(packed) };
    }
    unpad_rows(packed)
}

/// [`unpad_rows`] compiled with AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn unpad_avx2(packed: PackedFrame<'_>) -> Frame {
    unpad_rows(packed)
}

/// The body of [`unpad`], inlined into each compiled variant.
#[inline(always)]
fn unpad_rows(packed: PackedFrame<'_>) -> Frame {
    let PackedFrame {
        bytes,
        size: [w, h],
        rows: l,
        pixels: layout,
        floor,
    } = packed;
    let (w, h) = (w as usize, h as usize);
    let mut frame = Frame {
        gray: Vec::with_capacity(w * h),
        depth: Vec::with_capacity(w * h),
        ids: Vec::with_capacity(w * h),
    };
    let columns: Vec<f64> = match floor {
        Some(_) => (0..w).map(|c| c as f64).collect(),
        None => Vec::new(),
    };
    if layout == PixelLayout::GrayAndTruth {
        for r in 0..h {
            let start = r * l.gray_row as usize;
            frame.gray.extend_from_slice(&bytes[start..start + w]);
        }
    }
    for r in 0..h {
        let start = l.truth_offset() as usize + r * l.truth_row as usize;
        let row = &bytes[start..start + 4 * w];
        match bytemuck::try_cast_slice::<u8, u32>(row) {
            Ok(words) => split_words(words.iter().copied(), layout, &mut frame),
            Err(_) => split_words(
                row.chunks_exact(4)
                    .map(|c| u32::from_ne_bytes([c[0], c[1], c[2], c[3]])),
                layout,
                &mut frame,
            ),
        }
        if let Some(floor) = floor {
            let start = r * w;
            fill_floor_row(
                &mut frame.depth[start..],
                &frame.ids[start..],
                floor,
                r,
                &columns,
            );
        }
    }
    frame
}

/// Writes the computed floor's depth ([`FloorFill`]) into the pixels of raster row `row` that
/// no block covers (id 0): the floor fills the picture, so those are the floor's. `columns`
/// holds the column numbers 0, 1, .. as f64.
#[inline(always)]
fn fill_floor_row(depth: &mut [u16], ids: &[u16], floor: &FloorFill, row: usize, columns: &[f64]) {
    let row_start = floor.row_start(row);
    for ((d, &id), &column) in depth.iter_mut().zip(ids).zip(columns) {
        let floor_units = floor.depth_units_in_row(row_start, column);
        // All ones where no block is (id 0): a select without a branch, so the loop vectorizes.
        let floor_mask = u16::from(id == 0).wrapping_neg();
        *d = (floor_units & floor_mask) | (*d & !floor_mask);
    }
}

/// One row of packed words split onto the ends of the frame's pictures, each picture in its own
/// pass so each vectorizes: `depth << 16 | id` ([`PixelLayout::GrayAndTruth`], gray read
/// separately) or `depth << 16 | gray << 8 | id` ([`PixelLayout::Word`]).
#[inline(always)]
fn split_words(words: impl Iterator<Item = u32> + Clone, layout: PixelLayout, frame: &mut Frame) {
    frame.depth.extend(words.clone().map(|v| (v >> 16) as u16));
    match layout {
        PixelLayout::GrayAndTruth => frame.ids.extend(words.map(|v| v as u16)),
        PixelLayout::Word => {
            frame.gray.extend(words.clone().map(|v| (v >> 8) as u8));
            frame
                .ids
                .extend(words.map(|v| (v & MAX_WORD_BLOCK_ID) as u16));
        }
    }
}

fn create_pipelines(device: &wgpu::Device) -> (Pipelines, wgpu::Buffer, wgpu::BindGroup) {
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("scene.wgsl"),
        source: wgpu::ShaderSource::Wgsl(SCENE_WGSL.into()),
    });
    let uniforms = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("frame uniforms"),
        size: UNIFORM_STRIDE * MAX_FRAMES_PER_SUBMISSION as u64,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let bgl = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("frame"),
        entries: &[wgpu::BindGroupLayoutEntry {
            binding: 0,
            visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: true,
                min_binding_size: None,
            },
            count: None,
        }],
    });
    let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("frame"),
        layout: &bgl,
        entries: &[wgpu::BindGroupEntry {
            binding: 0,
            resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                buffer: &uniforms,
                offset: 0,
                size: std::num::NonZeroU64::new(std::mem::size_of::<FrameUniforms>() as u64),
            }),
        }],
    });
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("scene"),
        bind_group_layouts: &[Some(&bgl)],
        immediate_size: 0,
    });
    let target = |format| {
        Some(wgpu::ColorTargetState {
            format,
            blend: None,
            write_mask: wgpu::ColorWrites::ALL,
        })
    };
    let (gray, gray_msaa, truth) = (
        target(GRAY_FORMAT),
        target(GRAY_MSAA_FORMAT),
        target(TRUTH_FORMAT),
    );
    let make = |entries: [&str; 2],
                targets: &[Option<wgpu::ColorTargetState>],
                samples: u32,
                compare: wgpu::CompareFunction| {
        create_pipeline(device, &module, &layout, entries, targets, samples, compare)
    };
    let variants = |fragment: &str,
                    targets: &[Option<wgpu::ColorTargetState>],
                    samples: u32,
                    compare: wgpu::CompareFunction| SeamPipelines {
        none: make(
            ["vs_no_lines", &format!("{fragment}_no_lines")],
            targets,
            samples,
            compare,
        ),
        four: make(
            ["vs_four_lines", &format!("{fragment}_four_lines")],
            targets,
            samples,
            compare,
        ),
        eight: make(["vs_main", fragment], targets, samples, compare),
    };
    use wgpu::CompareFunction::{Less, LessEqual};
    let word = std::slice::from_ref(&truth);
    let pipelines = Pipelines {
        word: variants("fs_pixel", word, 1, Less),
        word_as_near: variants("fs_pixel", word, 1, LessEqual),
        all: variants("fs_all", &[gray, truth.clone()], 1, Less),
        gray_msaa4: variants("fs_gray", &[gray_msaa], 4, Less),
        truth: make(["vs_main", "fs_truth"], &[truth], 1, Less),
    };
    (pipelines, uniforms, bind_group)
}

fn create_pipeline(
    device: &wgpu::Device,
    module: &wgpu::ShaderModule,
    layout: &wgpu::PipelineLayout,
    [vertex_entry, fragment_entry]: [&str; 2],
    targets: &[Option<wgpu::ColorTargetState>],
    samples: u32,
    depth_compare: wgpu::CompareFunction,
) -> wgpu::RenderPipeline {
    let attributes = wgpu::vertex_attr_array![
        0 => Float32x3,
        1 => Float32x4,
        2 => Float32x4,
        3 => Float32x4,
        4 => Float32x4,
        5 => Float32x4,
        6 => Float32x4,
        7 => Uint32x2,
    ];
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(fragment_entry),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some(vertex_entry),
            compilation_options: Default::default(),
            buffers: &[Some(wgpu::VertexBufferLayout {
                array_stride: std::mem::size_of::<Vertex>() as u64,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &attributes,
            })],
        },
        primitive: wgpu::PrimitiveState {
            topology: wgpu::PrimitiveTopology::TriangleList,
            front_face: wgpu::FrontFace::Ccw,
            cull_mode: Some(wgpu::Face::Back),
            ..Default::default()
        },
        depth_stencil: Some(wgpu::DepthStencilState {
            format: DEPTH_FORMAT,
            depth_write_enabled: Some(true),
            depth_compare: Some(depth_compare),
            stencil: Default::default(),
            bias: Default::default(),
        }),
        multisample: wgpu::MultisampleState {
            count: samples,
            ..Default::default()
        },
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some(fragment_entry),
            compilation_options: Default::default(),
            targets,
        }),
        multiview_mask: None,
        cache: None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn readback_rows_are_padded_to_256_bytes() {
        let l = ReadbackLayout::new([500, 3]);
        assert_eq!((l.gray_row, l.truth_row), (512, 2048));
        assert_eq!(l.truth_offset(), 512 * 3);
        assert_eq!(l.total(), 512 * 3 + 2048 * 3);
        let l = ReadbackLayout::new([512, 480]);
        assert_eq!((l.gray_row, l.truth_row), (512, 2048));
        assert_eq!(l.total(), 5 * 512 * 480, "5 bytes per pixel, no padding");
    }

    #[test]
    fn four_views_share_a_submission_unless_their_readback_is_huge() {
        let small = ReadbackLayout::new([512, 480]).total();
        assert_eq!(frames_per_submission(small), MAX_FRAMES_PER_SUBMISSION);
        let huge = ReadbackLayout::new([8192, 8192]).total();
        assert_eq!(frames_per_submission(huge), 1);
        let big = ReadbackLayout::new([4096, 4096]).total();
        assert_eq!(
            frames_per_submission(big),
            3,
            "80 MiB each: three fit in 256 MiB"
        );
        assert_eq!(frames_per_submission(u64::MAX), 1);
    }

    fn packed<'a>(
        bytes: &'a [u8],
        size: [u32; 2],
        rows: &'a ReadbackLayout,
        pixels: PixelLayout,
        floor: Option<&'a FloorFill>,
    ) -> PackedFrame<'a> {
        PackedFrame {
            bytes,
            size,
            rows,
            pixels,
            floor,
        }
    }

    #[test]
    fn unpad_drops_padding_and_splits_depth_from_ids() {
        let l = ReadbackLayout::new([3, 2]);
        let mut bytes = vec![0u8; l.total() as usize];
        bytes[..3].copy_from_slice(&[1, 2, 3]);
        bytes[256..259].copy_from_slice(&[4, 5, 6]);
        let t = l.truth_offset() as usize;
        let word = |depth: u32, id: u32| ((depth << 16) | id).to_ne_bytes();
        bytes[t..t + 4].copy_from_slice(&word(7, 0));
        bytes[t + 8..t + 12].copy_from_slice(&word(65535, 65535));
        // The second row starts after the padding (256 bytes), not after three words.
        bytes[t + 256..t + 260].copy_from_slice(&word(1, 2));
        bytes[t + 12..t + 16].copy_from_slice(&word(9, 9));
        let f = unpad(packed(&bytes, [3, 2], &l, PixelLayout::GrayAndTruth, None));
        assert_eq!(f.gray, vec![1, 2, 3, 4, 5, 6]);
        assert_eq!(f.depth, vec![7, 0, 65535, 1, 0, 0]);
        assert_eq!(f.ids, vec![0, 0, 65535, 2, 0, 0]);
    }

    #[test]
    fn unpad_splits_the_one_word_pixel_into_gray_depth_and_ids() {
        let l = ReadbackLayout::new([2, 2]);
        let mut bytes = vec![0u8; l.total() as usize];
        // The gray region is not read in this layout.
        bytes[..2].copy_from_slice(&[99, 99]);
        let t = l.truth_offset() as usize;
        let word =
            |depth: u32, gray: u32, id: u32| ((depth << 16) | (gray << 8) | id).to_ne_bytes();
        bytes[t..t + 4].copy_from_slice(&word(0, 20, 0));
        bytes[t + 4..t + 8].copy_from_slice(&word(65535, 255, 255));
        bytes[t + 256..t + 260].copy_from_slice(&word(300, 35, 7));
        bytes[t + 260..t + 264].copy_from_slice(&word(1, 210, 1));
        let f = unpad(packed(&bytes, [2, 2], &l, PixelLayout::Word, None));
        assert_eq!(f.gray, vec![20, 255, 35, 210]);
        assert_eq!(f.depth, vec![0, 65535, 300, 1]);
        assert_eq!(f.ids, vec![0, 255, 7, 1]);
    }

    #[test]
    fn unpad_writes_the_computed_floor_only_where_no_block_is_in_both_compiled_variants() {
        use crate::camera::{Camera, CameraOptions, CornerView};
        let scene = crate::scene::b15_layers(1, 1, "cube".into());
        let opts = CameraOptions {
            size_px: [37, 5],
            ..Default::default()
        };
        let camera = Camera::frame(&scene.blocks[0].world_vertices(), CornerView::Se, &opts);
        let fill = mesh::floor_fill(&scene, &camera).expect("the floor fills a corner view");
        let l = ReadbackLayout::new([37, 5]);
        let mut bytes = vec![0u8; l.total() as usize];
        let t = l.truth_offset() as usize;
        // Every third pixel is block 1 at depth 4321 and gray 210; the rest are bare.
        for r in 0..5 {
            for c in (0..37).step_by(3) {
                let at = t + r * l.truth_row as usize + 4 * c;
                let word: u32 = (4321 << 16) | (210 << 8) | 1;
                bytes[at..at + 4].copy_from_slice(&word.to_ne_bytes());
            }
        }
        let f = unpad(packed(&bytes, [37, 5], &l, PixelLayout::Word, Some(&fill)));
        for r in 0..5 {
            for c in 0..37 {
                let i = r * 37 + c;
                if c % 3 == 0 {
                    assert_eq!((f.depth[i], f.ids[i], f.gray[i]), (4321, 1, 210));
                } else {
                    assert_eq!(f.depth[i], fill.depth_units(c, r), "({c}, {r})");
                    assert_eq!(f.ids[i], 0);
                }
            }
        }
        // The baseline loops (what a CPU without AVX2 runs) give the same frame.
        let baseline = unpad_rows(packed(&bytes, [37, 5], &l, PixelLayout::Word, Some(&fill)));
        assert_eq!(baseline, f);
        // A worse input: without the floor, the bare pixels keep depth 0.
        let bare = unpad(packed(&bytes, [37, 5], &l, PixelLayout::Word, None));
        assert_ne!(bare, f);
        assert_eq!(bare.depth[1], 0);
    }

    #[test]
    fn one_word_pixels_only_single_sampled_with_ids_of_8_bits() {
        assert_eq!(PixelLayout::of(1, 0), PixelLayout::Word);
        assert_eq!(PixelLayout::of(1, 255), PixelLayout::Word);
        assert_eq!(PixelLayout::of(1, 256), PixelLayout::GrayAndTruth);
        assert_eq!(PixelLayout::of(4, 1), PixelLayout::GrayAndTruth);
    }
}
