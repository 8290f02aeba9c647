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

mod device;
mod passes;
pub mod photo;
mod pipelines;
mod readback;
mod targets;

pub use device::adapter_summary;

use super::mesh;
use super::{Backend, RenderError};
use mesh::{DrawOrder, FloorFill, Vertex};
use passes::{draw_runs, encode_readback, FramePasses};
use pipelines::Pipelines;
use std::borrow::Cow;
use std::sync::{Arc, Mutex};
use targets::{ReadbackLayout, Targets};

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
/// The depth buffer of every pass, the photographic look's included.
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

impl Gpu {
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
        let (layout, ordered) = in_draw_order(requests, msaa);
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
        ordered: &[OrderedMesh<'_>],
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
}

/// A frame's vertices in their drawing order, and that order.
type OrderedMesh<'a> = (Cow<'a, [Vertex]>, DrawOrder);

/// The pixel layout of a submission's frames and each frame's vertices in its drawing order:
/// nearer blocks first where the one-word pixel has the pipelines for it.
fn in_draw_order<'a>(
    requests: &[FrameRequest<'a>],
    msaa: u32,
) -> (PixelLayout, Vec<OrderedMesh<'a>>) {
    let max_id = requests
        .iter()
        .flat_map(|r| r.vertices.iter().map(|v| v.block_id))
        .max()
        .unwrap_or(0);
    let layout = PixelLayout::of(msaa, max_id);
    let ordered = requests
        .iter()
        .map(|r| {
            let order = match layout {
                PixelLayout::Word => mesh::nearer_first_order(r.vertices, r.uniforms.view_z_row),
                PixelLayout::GrayAndTruth => DrawOrder::Ascending,
            };
            (mesh::in_draw_order(r.vertices, order), order)
        })
        .collect();
    (layout, ordered)
}

/// Frames per submission for pictures of `readback_bytes` each: all four views unless that
/// would hold more than [`MAX_SUBMISSION_READBACK_BYTES`] of readback, never fewer than one.
fn frames_per_submission(readback_bytes: u64) -> usize {
    let fit = MAX_SUBMISSION_READBACK_BYTES / readback_bytes.max(1);
    (fit as usize).clamp(1, MAX_FRAMES_PER_SUBMISSION)
}

#[cfg(test)]
mod tests {
    use super::*;
    use targets::ReadbackLayout;

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

    #[test]
    fn one_word_pixels_only_single_sampled_with_ids_of_8_bits() {
        assert_eq!(PixelLayout::of(1, 0), PixelLayout::Word);
        assert_eq!(PixelLayout::of(1, 255), PixelLayout::Word);
        assert_eq!(PixelLayout::of(1, 256), PixelLayout::GrayAndTruth);
        assert_eq!(PixelLayout::of(4, 1), PixelLayout::GrayAndTruth);
    }
}
