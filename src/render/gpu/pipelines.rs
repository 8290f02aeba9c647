//! The render pipelines of `shaders/scene.wgsl`, one per pass and [`SeamLines`] variant, and the
//! frame uniforms' bind group layout, which the photographic look's passes share
//! ([`uniform_layout_entry`]).

use super::mesh::{SeamLines, Vertex};
use super::{
    FrameUniforms, DEPTH_FORMAT, GRAY_FORMAT, GRAY_MSAA_FORMAT, MAX_FRAMES_PER_SUBMISSION,
};
use super::{TRUTH_FORMAT, UNIFORM_STRIDE};

/// The shader source, compiled in so an edited shader triggers a rebuild.
const SCENE_WGSL: &str = include_str!("../../../shaders/scene.wgsl");

/// The pipelines of one pass, one per [`SeamLines`] variant of the shader.
pub(super) struct SeamPipelines {
    pub(super) none: wgpu::RenderPipeline,
    pub(super) four: wgpu::RenderPipeline,
    pub(super) eight: wgpu::RenderPipeline,
}

/// A pass's pipeline for each [`SeamLines`] variant.
pub(super) type PipelineOf<'a> = [&'a wgpu::RenderPipeline; 3];

impl SeamPipelines {
    pub(super) fn by_variant(&self) -> PipelineOf<'_> {
        [&self.none, &self.four, &self.eight]
    }
}

/// The index of `lines` in a [`PipelineOf`].
pub(super) fn variant_index(lines: SeamLines) -> usize {
    match lines {
        SeamLines::None => 0,
        SeamLines::Four => 1,
        SeamLines::Eight => 2,
    }
}

/// Every pipeline of `shaders/scene.wgsl`, made once per device.
pub(super) struct Pipelines {
    /// Single-sampled gray, depth and ids in one word ([`PixelLayout::Word`]).
    pub(super) word: SeamPipelines,
    /// The same keeping fragments as near as what is drawn, for blocks drawn in
    /// [`DrawOrder::Descending`].
    pub(super) word_as_near: SeamPipelines,
    /// Single-sampled gray + depth and ids ([`PixelLayout::GrayAndTruth`]).
    pub(super) all: SeamPipelines,
    /// Gray only, 4 samples.
    pub(super) gray_msaa4: SeamPipelines,
    /// Depth + ids, single-sampled.
    pub(super) truth: wgpu::RenderPipeline,
}

/// Binding 0 of a bind group layout: a uniform buffer both shader stages read, at a dynamic
/// offset (several frames' uniforms in one buffer, [`UNIFORM_STRIDE`] apart) or not (one view's
/// uniforms, `gpu::photo`).
pub(super) fn uniform_layout_entry(has_dynamic_offset: bool) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding: 0,
        visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset,
            min_binding_size: None,
        },
        count: None,
    }
}

/// The pipelines, the frames' uniform buffer and its bind group.
/// The frames' bind group layout and its bind group: one frame's [`FrameUniforms`] of
/// `uniforms` at a dynamic offset.
fn frame_bind_group(
    device: &wgpu::Device,
    uniforms: &wgpu::Buffer,
) -> (wgpu::BindGroupLayout, wgpu::BindGroup) {
    let bgl = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("frame"),
        entries: &[uniform_layout_entry(true)],
    });
    let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("frame"),
        layout: &bgl,
        entries: &[wgpu::BindGroupEntry {
            binding: 0,
            resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                buffer: uniforms,
                offset: 0,
                size: std::num::NonZeroU64::new(std::mem::size_of::<FrameUniforms>() as u64),
            }),
        }],
    });
    (bgl, bind_group)
}

pub(super) fn create_pipelines(
    device: &wgpu::Device,
) -> (Pipelines, wgpu::Buffer, wgpu::BindGroup) {
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
    let (bgl, bind_group) = frame_bind_group(device, &uniforms);
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
