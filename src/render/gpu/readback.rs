//! The readback: one wait for a submission's frames, then each frame's padded rows unpacked into
//! the gray picture, depth and block ids.

use super::mesh::FloorFill;
use super::targets::{ReadbackLayout, Targets};
use super::{Frame, Gpu, PixelLayout, RenderError, MAX_WORD_BLOCK_ID};

impl Gpu {
    /// Maps the readback buffers of `floors.len()` frames, waits once, and unpads their rows,
    /// writing each computed floor's depth ([`FloorFill`]).
    pub(super) fn read_back(
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::mesh;

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
}
