//! The passes of one frame recorded into the submission's command encoder: each run of
//! triangles with the pipeline of its seam-line variant, then the copy into the readback buffer.

use super::mesh::{self, DrawOrder, FloorFill, SeamLines, Vertex};
use super::pipelines::{variant_index, PipelineOf};
use super::targets::Targets;
use super::{Gpu, PixelLayout};

impl Gpu {
    /// Records the frame's passes: each run of triangles (`runs`, vertex ranges in drawing
    /// order) drawn with the pipeline of its [`SeamLines`] variant, keeping fragments as near
    /// as what is drawn where the run says so ([`draw_runs`]; one-word pixels only).
    pub(super) fn encode_passes(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        t: &Targets,
        layout: PixelLayout,
        vbuf: &wgpu::Buffer,
        frame: &FramePasses<'_>,
    ) {
        let clear = ClearColors::of(t, frame.floor);
        let truth_runs: Vec<DrawRun> = frame
            .runs
            .iter()
            .filter(|r| frame.floor.is_none() || !r.floor)
            .cloned()
            .collect();
        let p = &self.pipelines;
        let mut pass = |pipelines, colors: &[_], depth_buffer, runs| {
            let pass = Pass {
                pipelines,
                colors,
                depth_buffer,
                runs,
            };
            self.encode_pass(encoder, vbuf, frame.uniform_offset, pass);
        };
        let truth_cleared = color_attachment(&t.truth_view, None, wgpu::Color::TRANSPARENT);
        match &t.msaa_views {
            None if layout == PixelLayout::Word => pass(
                [p.word.by_variant(), p.word_as_near.by_variant()],
                &[color_attachment(&t.truth_view, None, clear.word)],
                &t.depth_buffer_view,
                &truth_runs,
            ),
            None => pass(
                [p.all.by_variant(); 2],
                &[
                    color_attachment(&t.gray_view, None, clear.gray),
                    truth_cleared,
                ],
                &t.depth_buffer_view,
                &truth_runs,
            ),
            Some((color, depth_buffer)) => {
                pass(
                    [p.gray_msaa4.by_variant(); 2],
                    &[color_attachment(color, Some(&t.gray_view), clear.gray)],
                    depth_buffer,
                    frame.runs,
                );
                pass(
                    [[&p.truth; 3]; 2],
                    &[truth_cleared],
                    &t.depth_buffer_view,
                    &truth_runs,
                );
            }
        }
    }

    /// Records one render pass: the depth buffer cleared, the frame's uniforms bound, and each
    /// run drawn with its pipeline.
    fn encode_pass(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        vbuf: &wgpu::Buffer,
        uniform_offset: u32,
        pass: Pass<'_, '_>,
    ) {
        let mut rp = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: None,
            color_attachments: pass.colors,
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: pass.depth_buffer,
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
        for run in pass.runs {
            rp.set_pipeline(pass.pipelines[usize::from(run.as_near)][variant_index(run.lines)]);
            rp.draw(run.vertices.clone(), 0..1);
        }
    }
}

/// One render pass: its pipelines (by whether the run keeps fragments as near as what is drawn,
/// then by [`SeamLines`] variant), color targets, depth buffer and runs.
struct Pass<'a, 'v> {
    pipelines: [PipelineOf<'a>; 2],
    colors: &'a [Option<wgpu::RenderPassColorAttachment<'v>>],
    depth_buffer: &'a wgpu::TextureView,
    runs: &'a [DrawRun],
}

/// The values the gray and the one-word targets start from.
struct ClearColors {
    /// The gray target: the background level, an integer in the integer target and normalized
    /// in the multisampled one.
    gray: wgpu::Color,
    /// The one-word target: depth 0, id 0 and the gray level at bits 8..15.
    word: wgpu::Color,
}

impl ClearColors {
    /// A single-sampled pass whose floor is computed starts from the floor's level instead of
    /// the background's, which every pixel no block covers then keeps; the multisampled
    /// picture still draws the floor (its samples are resolved together).
    fn of(t: &Targets, floor: Option<&FloorFill>) -> ClearColors {
        let background = f64::from(crate::render::BACKGROUND_LEVEL);
        let single_sampled_level = floor.map_or(background, |f| f64::from(f.gray_level));
        let gray_level = if t.msaa_views.is_some() {
            background / 255.0
        } else {
            single_sampled_level
        };
        ClearColors {
            gray: wgpu::Color {
                r: gray_level,
                g: 0.0,
                b: 0.0,
                a: 1.0,
            },
            word: wgpu::Color {
                r: single_sampled_level * 256.0,
                ..wgpu::Color::TRANSPARENT
            },
        }
    }
}

/// A color target cleared to `clear` and stored, resolved into `resolve` if multisampled.
fn color_attachment<'v>(
    view: &'v wgpu::TextureView,
    resolve: Option<&'v wgpu::TextureView>,
    clear: wgpu::Color,
) -> Option<wgpu::RenderPassColorAttachment<'v>> {
    Some(wgpu::RenderPassColorAttachment {
        view,
        depth_slice: None,
        resolve_target: resolve,
        ops: wgpu::Operations {
            load: wgpu::LoadOp::Clear(clear),
            store: wgpu::StoreOp::Store,
        },
    })
}

/// What one frame's passes draw: its runs, where its uniforms sit, and its computed floor.
pub(super) struct FramePasses<'a> {
    pub(super) runs: &'a [DrawRun],
    pub(super) uniform_offset: u32,
    pub(super) floor: Option<&'a FloorFill>,
}

/// A run of consecutive triangles drawn with one pipeline.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) struct DrawRun {
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
pub(super) fn draw_runs(vertices: &[Vertex], order: DrawOrder, first: u32) -> Vec<DrawRun> {
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

/// Copies the frame's targets into `readback` (the gray region stays unused in the one-word
/// layout), rows padded to 256 bytes.
pub(super) fn encode_readback(
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
