//! The GPU half of the photographic look (docs/rendering.md "Photographic look"): the pipelines of
//! `shaders/photo.wgsl`, a key-light shadow map pass and the radiance pass (linear radiance in
//! an `R32Float` target, read back for the sensor model of `render::photo::sensor`).
//!
//! The radiance pass draws the triangles that need no shadow test first and those that do
//! last, nearer blocks before farther ones and the floor at the end
//! (`render::photo::mesh::PhotoMesh`), with depth test Less and depth writes: lavapipe tests
//! depth before it runs the fragment shader, so the soft shadow test runs almost only on the
//! surface that shows, without a depth pre-pass (which cost a second pass over every
//! triangle). A pixel shows the nearest surface either way.
//!
//! Created on first use, so line-art rendering never builds them.

use super::super::photo::mesh::{PhotoMesh, PhotoVertex};
use super::super::RenderError;
use super::pipelines::uniform_layout_entry;
use super::{Gpu, DEPTH_FORMAT};
use std::sync::Mutex;

/// The shader source, compiled in so an edited shader triggers a rebuild.
const PHOTO_WGSL: &str = include_str!("../../../shaders/photo.wgsl");

const RADIANCE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;

/// Side of the square shadow map, texels: on a scene framed in 512 px, about two texels per
/// picture pixel. 1024 gave pictures within a few levels of these (a quarter of a percent of
/// the pixels differ by more than 4) at one and a half times the cost: the filter's taps
/// spread over four times the memory.
pub const SHADOW_MAP_PX: u32 = 512;

/// Shader constants of one photo view (`Photo` in `shaders/photo.wgsl`).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct PhotoUniforms {
    /// World mm to the picture's clip space, column-major.
    pub clip_from_world: [f32; 16],
    /// World mm to the shadow camera's clip space, column-major.
    pub light_clip_from_world: [f32; 16],
    /// Unit vector towards the light (xyz) and diffuse intensity (w).
    pub towards_light: [f32; 4],
    /// Ambient, depth bias (mm), receiver normal offset (mm), shadow map texel (mm).
    pub params: [f32; 4],
    /// Tan of the light's angular radius, shadow depth range (mm), blocker search radius
    /// (mm), largest penumbra radius (mm).
    pub soft: [f32; 4],
    /// World normal to shadow clip-space plane normal (inverse transpose of the linear part of
    /// `light_clip_from_world`), column-major.
    pub light_clip_normal: [f32; 16],
    /// Smallest penumbra radius (mm), the specular highlight's weight (0: matte, no
    /// highlight), its Blinn-Phong exponent, then unused.
    pub soft_min: [f32; 4],
    /// The eye: its position, world mm, with w = 1 (perspective), or the unit direction
    /// towards it with w = 0 (orthographic); read only for the highlight.
    pub eye: [f32; 4],
}

/// Pipelines, shadow map and cached targets of the photo look; one per renderer.
pub struct PhotoPass {
    shadow: wgpu::RenderPipeline,
    radiance: wgpu::RenderPipeline,
    unshadowed: wgpu::RenderPipeline,
    unshadowed_behind: wgpu::RenderPipeline,
    uniforms: wgpu::Buffer,
    shadow_bind_group: wgpu::BindGroup,
    photo_bind_group: wgpu::BindGroup,
    shadow_view: wgpu::TextureView,
    vertices: Option<wgpu::Buffer>,
    targets: Option<RadianceTargets>,
}

/// The photo pass, built on first use (`Renderer` holds one).
#[derive(Default)]
pub struct PhotoSlot(Mutex<Option<PhotoPass>>);

struct RadianceTargets {
    size: [u32; 2],
    radiance: wgpu::Texture,
    radiance_view: wgpu::TextureView,
    depth_view: wgpu::TextureView,
    readback: wgpu::Buffer,
    row_bytes: u32,
}

/// A photo view submitted to the GPU and not yet read back ([`Gpu::submit_photo`]): holds the
/// photo pass (so no other view reuses its targets meanwhile) until [`PendingPhoto::read`].
pub struct PendingPhoto<'a> {
    gpu: &'a Gpu,
    pass: std::sync::MutexGuard<'a, Option<PhotoPass>>,
}

impl PendingPhoto<'_> {
    /// Waits for the view and reads its radiance back as `w * h` f32 rows top to bottom.
    pub fn read(self) -> Result<Vec<f32>, RenderError> {
        let t = self
            .pass
            .as_ref()
            .and_then(|p| p.targets.as_ref())
            .ok_or_else(|| RenderError::Gpu("photo targets missing after submission".into()))?;
        self.gpu.read_radiance(t)
    }
}

impl Gpu {
    /// Submits the photo look of one view: the shadow map from the key light, then linear
    /// radiance of the mesh into a `size` px target (its shadowed triangles with the soft
    /// shadow test, the rest without). Returns without waiting, so the caller can submit the
    /// view's ground truth meanwhile and wait once for both ([`PendingPhoto::read`]).
    pub fn submit_photo<'a>(
        &'a self,
        slot: &'a PhotoSlot,
        mesh: &PhotoMesh,
        uniforms: &PhotoUniforms,
        size: [u32; 2],
    ) -> Result<PendingPhoto<'a>, RenderError> {
        let mut guard = slot
            .0
            .lock()
            .map_err(|_| RenderError::Gpu("photo state poisoned by an earlier panic".into()))?;
        let scope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let oom = self.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        if guard.is_none() {
            *guard = Some(self.create_photo_pass());
        }
        let pass = guard.as_mut().expect("just created");
        let bytes: &[u8] = bytemuck::cast_slice(&mesh.vertices);
        self.photo_buffers(pass, bytes.len() as u64, size);
        let vbuf = pass.vertices.as_ref().expect("just created");
        self.queue.write_buffer(vbuf, 0, bytes);
        self.queue
            .write_buffer(&pass.uniforms, 0, bytemuck::bytes_of(uniforms));
        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
        encode_photo_passes(&mut encoder, pass, mesh);
        self.queue.submit([encoder.finish()]);
        let oom_error = pollster::block_on(oom.pop());
        let validation_error = pollster::block_on(scope.pop());
        if let Some(e) = validation_error.or(oom_error) {
            return Err(RenderError::Gpu(e.to_string()));
        }
        Ok(PendingPhoto {
            gpu: self,
            pass: guard,
        })
    }

    /// Grows the vertex buffer to hold `vertex_bytes` and (re)creates the targets for `size`.
    fn photo_buffers(&self, pass: &mut PhotoPass, vertex_bytes: u64, size: [u32; 2]) {
        if pass
            .vertices
            .as_ref()
            .is_none_or(|b| b.size() < vertex_bytes)
        {
            pass.vertices = Some(self.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("photo vertices"),
                size: vertex_bytes.next_power_of_two().max(64 * 1024),
                usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }));
        }
        if pass.targets.as_ref().is_none_or(|t| t.size != size) {
            pass.targets = Some(self.create_radiance_targets(size));
        }
    }

    fn create_radiance_targets(&self, size: [u32; 2]) -> RadianceTargets {
        let texture = |label, format, usage| {
            super::targets::texture_2d(&self.device, label, size, format, 1, usage)
        };
        let radiance = texture(
            "radiance",
            RADIANCE_FORMAT,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        );
        let depth = texture(
            "photo depth buffer",
            DEPTH_FORMAT,
            wgpu::TextureUsages::RENDER_ATTACHMENT,
        );
        let align = wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
        let row_bytes = (4 * size[0]).div_ceil(align) * align;
        let readback = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("radiance readback"),
            size: row_bytes as u64 * size[1] as u64,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        RadianceTargets {
            size,
            radiance_view: radiance.create_view(&Default::default()),
            depth_view: depth.create_view(&Default::default()),
            radiance,
            readback,
            row_bytes,
        }
    }

    /// Maps the radiance readback, waits, and unpads the rows into f32 values.
    fn read_radiance(&self, t: &RadianceTargets) -> Result<Vec<f32>, RenderError> {
        let (tx, rx) = std::sync::mpsc::channel();
        t.readback.map_async(wgpu::MapMode::Read, .., move |r| {
            let _ = tx.send(r);
        });
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| RenderError::Gpu(format!("waiting for the GPU: {e}")))?;
        rx.recv()
            .map_err(|_| RenderError::Gpu("readback callback never ran".into()))?
            .map_err(|e| RenderError::Gpu(format!("mapping the radiance readback: {e}")))?;
        let values = {
            let bytes = t
                .readback
                .get_mapped_range(..)
                .map_err(|e| RenderError::Gpu(format!("reading the radiance readback: {e}")))?;
            let [w, h] = t.size.map(|v| v as usize);
            let mut out = Vec::with_capacity(w * h);
            for r in 0..h {
                let row = &bytes[r * t.row_bytes as usize..][..4 * w];
                match bytemuck::try_cast_slice::<u8, f32>(row) {
                    Ok(values) => out.extend_from_slice(values),
                    Err(_) => out.extend(
                        row.chunks_exact(4)
                            .map(|c| f32::from_ne_bytes([c[0], c[1], c[2], c[3]])),
                    ),
                }
            }
            out
        };
        t.readback.unmap();
        Ok(values)
    }

    fn create_photo_pass(&self) -> PhotoPass {
        let device = &self.device;
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("photo.wgsl"),
            source: wgpu::ShaderSource::Wgsl(PHOTO_WGSL.into()),
        });
        let uniforms = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("photo uniforms"),
            size: std::mem::size_of::<PhotoUniforms>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let (shadow_view, sampler) = shadow_map(device);
        let (shadow_bgl, photo_bgl) = bind_group_layouts(device);
        let shadow_bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("photo shadow"),
            layout: &shadow_bgl,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: uniforms.as_entire_binding(),
            }],
        });
        let photo_bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("photo"),
            layout: &photo_bgl,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: uniforms.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::TextureView(&shadow_view),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: wgpu::BindingResource::Sampler(&sampler),
                },
            ],
        });
        PhotoPass {
            shadow: photo_pipeline(device, &module, &shadow_bgl, PhotoStage::Shadow, false),
            radiance: photo_pipeline(
                device,
                &module,
                &photo_bgl,
                PhotoStage::Radiance("fs_photo"),
                false,
            ),
            unshadowed: photo_pipeline(
                device,
                &module,
                &photo_bgl,
                PhotoStage::Radiance("fs_photo_unshadowed"),
                false,
            ),
            unshadowed_behind: photo_pipeline(
                device,
                &module,
                &photo_bgl,
                PhotoStage::Radiance("fs_photo_unshadowed"),
                true,
            ),
            uniforms,
            shadow_bind_group,
            photo_bind_group,
            shadow_view,
            vertices: None,
            targets: None,
        }
    }
}

/// The key light's shadow map ([`SHADOW_MAP_PX`] square, depth) and its comparison sampler.
fn shadow_map(device: &wgpu::Device) -> (wgpu::TextureView, wgpu::Sampler) {
    let shadow_map = super::targets::texture_2d(
        device,
        "shadow map",
        [SHADOW_MAP_PX; 2],
        DEPTH_FORMAT,
        1,
        wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
    );
    let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("shadow sampler"),
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        compare: Some(wgpu::CompareFunction::LessEqual),
        ..Default::default()
    });
    (shadow_map.create_view(&Default::default()), sampler)
}

/// The shadow pass's layout (the uniforms) and the radiance pass's (uniforms, shadow map,
/// comparison sampler).
fn bind_group_layouts(device: &wgpu::Device) -> (wgpu::BindGroupLayout, wgpu::BindGroupLayout) {
    let uniform = uniform_layout_entry(false);
    let shadow = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("photo shadow"),
        entries: &[uniform],
    });
    let photo = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("photo"),
        entries: &[
            uniform,
            wgpu::BindGroupLayoutEntry {
                binding: 1,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Depth,
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                count: None,
            },
            wgpu::BindGroupLayoutEntry {
                binding: 2,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Comparison),
                count: None,
            },
        ],
    });
    (shadow, photo)
}

/// The passes of one photo view, in their order.
#[derive(Debug, Clone, Copy)]
enum PhotoStage {
    /// Depth from the key light only, front faces culled so a lit face compares against its
    /// own block's far side, never itself.
    Shadow,
    /// Radiance with this fragment entry point (`vs_photo`, back faces culled), where nothing
    /// nearer was drawn before.
    Radiance(&'static str),
}

/// Depth bias of the whole faces drawn behind their shadowed part
/// (`render::photo::mesh::PhotoMesh`): 16 steps of the depth format at the triangle's depth
/// plus a twentieth of a pixel's depth change, far more than the part's own rounding
/// (vertices snap to 1/256 px) and far less than the 0.05 mm bevel between two faces.
const BEHIND_BIAS: wgpu::DepthBiasState = wgpu::DepthBiasState {
    constant: 16,
    slope_scale: 0.05,
    clamp: 0.0,
};

/// The pipeline of one [`PhotoStage`]; `behind`: with [`BEHIND_BIAS`].
fn photo_pipeline(
    device: &wgpu::Device,
    module: &wgpu::ShaderModule,
    bgl: &wgpu::BindGroupLayout,
    stage: PhotoStage,
    behind: bool,
) -> wgpu::RenderPipeline {
    let fragment = match stage {
        PhotoStage::Radiance(entry) => Some(entry),
        PhotoStage::Shadow => None,
    };
    let from_light = matches!(stage, PhotoStage::Shadow);
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("photo"),
        bind_group_layouts: &[Some(bgl)],
        immediate_size: 0,
    });
    let attributes = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32, 2 => Float32x3];
    let targets = [Some(wgpu::ColorTargetState {
        format: RADIANCE_FORMAT,
        blend: None,
        write_mask: wgpu::ColorWrites::ALL,
    })];
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(match stage {
            PhotoStage::Shadow => "photo shadow map",
            PhotoStage::Radiance(entry) => entry,
        }),
        layout: Some(&layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some(if from_light { "vs_shadow" } else { "vs_photo" }),
            compilation_options: Default::default(),
            buffers: &[Some(wgpu::VertexBufferLayout {
                array_stride: std::mem::size_of::<PhotoVertex>() as u64,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &attributes,
            })],
        },
        primitive: wgpu::PrimitiveState {
            topology: wgpu::PrimitiveTopology::TriangleList,
            front_face: wgpu::FrontFace::Ccw,
            cull_mode: Some(if from_light {
                wgpu::Face::Front
            } else {
                wgpu::Face::Back
            }),
            ..Default::default()
        },
        depth_stencil: Some(wgpu::DepthStencilState {
            format: DEPTH_FORMAT,
            depth_write_enabled: Some(true),
            depth_compare: Some(wgpu::CompareFunction::Less),
            stencil: Default::default(),
            bias: if behind {
                BEHIND_BIAS
            } else {
                Default::default()
            },
        }),
        multisample: Default::default(),
        fragment: fragment.map(|entry| wgpu::FragmentState {
            module,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            targets: &targets,
        }),
        multiview_mask: None,
        cache: None,
    })
}

/// The shadow pass (the mesh's casters), the radiance pass (the mesh's triangles without the
/// shadow test first, the whole faces `behind` their shadowed parts with [`BEHIND_BIAS`], then
/// the shadowed triangles with the test, so that nearly every shadowed fragment hidden by a
/// nearer surface fails the depth test before it is shaded) and the copy of the radiance into
/// the readback buffer.
fn encode_photo_passes(encoder: &mut wgpu::CommandEncoder, pass: &PhotoPass, mesh: &PhotoMesh) {
    let range = |r: &std::ops::Range<usize>| r.start as u32..r.end as u32;
    let t = pass.targets.as_ref().expect("created before encoding");
    let vbuf = pass.vertices.as_ref().expect("created before encoding");
    let depth = |view| {
        Some(wgpu::RenderPassDepthStencilAttachment {
            view,
            depth_ops: Some(wgpu::Operations {
                load: wgpu::LoadOp::Clear(1.0),
                store: wgpu::StoreOp::Store,
            }),
            stencil_ops: None,
        })
    };
    {
        let mut rp = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("shadow map"),
            color_attachments: &[],
            depth_stencil_attachment: depth(&pass.shadow_view),
            ..Default::default()
        });
        rp.set_pipeline(&pass.shadow);
        rp.set_bind_group(0, &pass.shadow_bind_group, &[]);
        rp.set_vertex_buffer(0, vbuf.slice(..));
        rp.draw(range(&mesh.casters), 0..1);
    }
    {
        let colors = [Some(wgpu::RenderPassColorAttachment {
            view: &t.radiance_view,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                store: wgpu::StoreOp::Store,
            },
        })];
        let mut rp = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("radiance"),
            color_attachments: &colors,
            depth_stencil_attachment: depth(&t.depth_view),
            ..Default::default()
        });
        rp.set_bind_group(0, &pass.photo_bind_group, &[]);
        rp.set_vertex_buffer(0, vbuf.slice(..));
        rp.set_pipeline(&pass.unshadowed);
        rp.draw(range(&mesh.unshadowed), 0..1);
        rp.set_pipeline(&pass.unshadowed_behind);
        rp.draw(range(&mesh.behind), 0..1);
        rp.set_pipeline(&pass.radiance);
        rp.draw(range(&mesh.shadowed), 0..1);
    }
    encoder.copy_texture_to_buffer(
        t.radiance.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &t.readback,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(t.row_bytes),
                rows_per_image: Some(t.size[1]),
            },
        },
        wgpu::Extent3d {
            width: t.size[0],
            height: t.size[1],
            depth_or_array_layers: 1,
        },
    );
}
