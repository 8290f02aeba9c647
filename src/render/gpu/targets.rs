//! Render targets cached per (size, msaa), the growable vertex buffer, and the layout of the
//! readback buffers the targets are copied into.

use super::{Gpu, DEPTH_FORMAT, GRAY_FORMAT, GRAY_MSAA_FORMAT, MAX_CACHED_TARGETS, TRUTH_FORMAT};

/// Bytes per row of each readback region (the gray picture, then the packed ground truth),
/// padded to `COPY_BYTES_PER_ROW_ALIGNMENT`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct ReadbackLayout {
    pub(super) gray_row: u32,
    pub(super) truth_row: u32,
    pub(super) height: u32,
}

impl ReadbackLayout {
    pub(super) fn new([w, h]: [u32; 2]) -> ReadbackLayout {
        let align = wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
        ReadbackLayout {
            gray_row: w.div_ceil(align) * align,
            truth_row: (4 * w).div_ceil(align) * align,
            height: h,
        }
    }
    pub(super) fn truth_offset(&self) -> u64 {
        self.gray_row as u64 * self.height as u64
    }
    pub(super) fn total(&self) -> u64 {
        self.truth_offset() + self.truth_row as u64 * self.height as u64
    }
}

/// Render targets and the readback buffer for one (size, msaa).
pub(super) struct Targets {
    pub(super) size: [u32; 2],
    pub(super) msaa: u32,
    /// The gray picture ([`GRAY_FORMAT`], or the resolve target in [`GRAY_MSAA_FORMAT`]).
    pub(super) gray: wgpu::Texture,
    pub(super) gray_view: wgpu::TextureView,
    /// Depth and block ids packed ([`TRUTH_FORMAT`]).
    pub(super) truth: wgpu::Texture,
    pub(super) truth_view: wgpu::TextureView,
    pub(super) depth_buffer_view: wgpu::TextureView,
    /// Multisampled gray and depth buffer (MSAA 4 only).
    pub(super) msaa_views: Option<(wgpu::TextureView, wgpu::TextureView)>,
    /// One readback buffer per frame of a submission, created as submissions need them.
    pub(super) readbacks: Vec<wgpu::Buffer>,
    pub(super) layout: ReadbackLayout,
}

impl Gpu {
    /// Creates readback buffers until `targets` has one per frame of the submission.
    pub(super) fn ensure_readbacks(&self, targets: &mut Targets, frames: usize) {
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
    pub(super) fn vertex_buffer<'a>(
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
    pub(super) fn targets<'a>(
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

    /// The targets of a `size` px picture with `msaa` samples, and no readback buffer yet.
    fn create_targets(&self, size: [u32; 2], msaa: u32) -> Targets {
        let texture = |label, format, samples, usage| {
            let t = texture_2d(&self.device, label, size, format, samples, usage);
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
}

/// A 2D texture of `size_px` with one mip level: the one descriptor of every render target,
/// depth buffer and shadow map of the GPU stage.
pub(super) fn texture_2d(
    device: &wgpu::Device,
    label: &str,
    size_px: [u32; 2],
    format: wgpu::TextureFormat,
    sample_count: u32,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: size_px[0],
            height: size_px[1],
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
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
}
