//! Instance masks of one view for the vision-tool exports (docs/exports.md "Masks"): the
//! visible mask of each block read from the id picture exactly, the full (amodal) mask from the
//! block's projected silhouette, boxes, areas and COCO's run-length encoding.
//!
//! Masks are in raster order (row 0 at the top of the picture, as PNG stores it); a pixel spans
//! `[c, c + 1) x [r, r + 1)` in raster px, its centre at `(c + 0.5, r + 0.5)`.

use crate::camera::Camera;
use crate::geom::{convex_hull, DVec2};
use crate::scene::Block;

/// Why masks could not be made from an id picture.
#[derive(Debug, thiserror::Error)]
pub enum MaskError {
    /// The id picture's pixel count is not its width times its height.
    #[error("id picture holds {pixels} pixels but is {width_px}x{height_px}; re-render the view")]
    Size {
        /// Pixels held.
        pixels: usize,
        /// Width, px.
        width_px: u32,
        /// Height, px.
        height_px: u32,
    },
    /// A pixel names a block the scene does not have.
    #[error("id picture names block id {id} but the scene has {blocks} blocks; the id picture belongs to another scene: re-render it")]
    UnknownBlock {
        /// The id found (block index + 1).
        id: u16,
        /// Blocks in the scene.
        blocks: usize,
    },
}

/// A binary mask of a picture in raster order.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Mask {
    /// Width, px.
    pub width_px: u32,
    /// Height, px.
    pub height_px: u32,
    /// One flag per pixel, row by row from the top.
    pub pixels: Vec<bool>,
}

impl Mask {
    /// An empty mask.
    pub fn new(width_px: u32, height_px: u32) -> Mask {
        Mask {
            width_px,
            height_px,
            pixels: vec![false; width_px as usize * height_px as usize],
        }
    }

    /// Pixels set.
    pub fn area_px(&self) -> u64 {
        self.pixels.iter().filter(|&&p| p).count() as u64
    }

    /// The tightest box around the set pixels as COCO writes it, `[x, y, width, height]` in
    /// raster px (pixel edges: a single pixel at column c, row r is `[c, r, 1, 1]`); `None`
    /// when no pixel is set.
    pub fn bbox_px(&self) -> Option<[u32; 4]> {
        let w = self.width_px as usize;
        let mut lo = [u32::MAX; 2];
        let mut hi = [0u32; 2];
        for (i, _) in self.pixels.iter().enumerate().filter(|(_, &p)| p) {
            let (c, r) = ((i % w) as u32, (i / w) as u32);
            lo = [lo[0].min(c), lo[1].min(r)];
            hi = [hi[0].max(c), hi[1].max(r)];
        }
        (lo[0] != u32::MAX).then(|| [lo[0], lo[1], hi[0] - lo[0] + 1, hi[1] - lo[1] + 1])
    }

    /// COCO's run lengths (pycocotools `encode`): the picture read column by column (column-major,
    /// top to bottom within a column), alternating runs of unset and set pixels, starting with an
    /// unset run (0 when the first pixel is set).
    pub fn rle_counts(&self) -> Vec<u32> {
        let (w, h) = (self.width_px as usize, self.height_px as usize);
        let mut counts = Vec::new();
        let (mut current, mut run) = (false, 0u32);
        for c in 0..w {
            for r in 0..h {
                let p = self.pixels[r * w + c];
                if p != current {
                    counts.push(run);
                    current = p;
                    run = 0;
                }
                run += 1;
            }
        }
        counts.push(run);
        counts
    }
}

/// The visible mask of every block of a scene of `blocks` blocks from its id picture (`ids` in
/// raster order, block index + 1, 0 = floor or background): mask `k` is exactly the pixels whose
/// id is `k + 1`.
pub fn visible_masks(
    ids: &[u16],
    width_px: u32,
    height_px: u32,
    blocks: usize,
) -> Result<Vec<Mask>, MaskError> {
    if ids.len() != width_px as usize * height_px as usize {
        return Err(MaskError::Size {
            pixels: ids.len(),
            width_px,
            height_px,
        });
    }
    let mut masks = vec![Mask::new(width_px, height_px); blocks];
    for (i, &id) in ids.iter().enumerate() {
        if id == 0 {
            continue;
        }
        let mask = masks
            .get_mut(usize::from(id) - 1)
            .ok_or(MaskError::UnknownBlock { id, blocks })?;
        mask.pixels[i] = true;
    }
    Ok(masks)
}

/// The block's whole silhouette in `camera`'s picture, as if nothing hid it: its catalog
/// vertices projected through the camera (picture px, y up, turned into raster px), their convex
/// hull, and every pixel whose centre the hull covers by the rasterizer's rule
/// ([`covers_pixel_centre`]). Pixels outside the picture are cut off.
pub fn silhouette_mask(block: &Block, camera: &Camera) -> Mask {
    let [w, h] = camera.size_px;
    polygon_mask(&silhouette_hull_px(block, camera), w, h)
}

/// The block's whole silhouette in `camera`'s picture as a convex polygon in raster px (y down
/// from the top edge): the convex hull of its catalog vertices projected through the camera.
pub fn silhouette_hull_px(block: &Block, camera: &Camera) -> Vec<DVec2> {
    let h = f64::from(camera.size_px[1]);
    let raster: Vec<DVec2> = block
        .world_vertices()
        .into_iter()
        .map(|p| {
            let q = camera.picture_from_world(p);
            DVec2::new(q.x, h - q.y)
        })
        .collect();
    convex_hull(&raster)
}

/// The mask of a convex polygon given in raster px (any winding): the pixels whose centres it
/// covers by [`covers_pixel_centre`].
pub fn polygon_mask(polygon: &[DVec2], width_px: u32, height_px: u32) -> Mask {
    let mut mask = Mask::new(width_px, height_px);
    if polygon.len() < 3 {
        return mask;
    }
    let mut hull = polygon.to_vec();
    // Clockwise on the screen (y down), the winding the top-left rule is stated for.
    if signed_area(&hull) < 0.0 {
        hull.reverse();
    }
    let lo = hull
        .iter()
        .fold(DVec2::splat(f64::INFINITY), |a, p| a.min(*p));
    let hi = hull
        .iter()
        .fold(DVec2::splat(f64::NEG_INFINITY), |a, p| a.max(*p));
    let span = |lo: f64, hi: f64, n: u32| {
        let first = (lo - 0.5).floor().max(0.0) as u32;
        let last = ((hi - 0.5).ceil().max(-1.0) as i64).min(i64::from(n) - 1);
        (first, last)
    };
    let (c0, c1) = span(lo.x, hi.x, width_px);
    let (r0, r1) = span(lo.y, hi.y, height_px);
    for r in i64::from(r0)..=r1 {
        for c in i64::from(c0)..=c1 {
            let centre = DVec2::new(c as f64 + 0.5, r as f64 + 0.5);
            if covers_pixel_centre(&hull, centre) {
                mask.pixels[r as usize * width_px as usize + c as usize] = true;
            }
        }
    }
    mask
}

/// Twice the signed area in raster px (positive when clockwise on the screen, y down).
fn signed_area(polygon: &[DVec2]) -> f64 {
    (0..polygon.len())
        .map(|k| polygon[k].perp_dot(polygon[(k + 1) % polygon.len()]))
        .sum()
}

/// Whether a convex polygon, clockwise on the screen (raster px, y down), covers point `p` by
/// the rasterization rule of Direct3D and Vulkan (the renderer's): strictly inside every edge,
/// or exactly on a top edge (horizontal, the polygon below it) or a left edge (going up the
/// screen), so a pixel centre on an edge shared by two polygons belongs to one of them.
pub fn covers_pixel_centre(polygon: &[DVec2], p: DVec2) -> bool {
    (0..polygon.len()).all(|k| {
        let (a, b) = (polygon[k], polygon[(k + 1) % polygon.len()]);
        let e = b - a;
        let side = e.perp_dot(p - a);
        let top = e.y == 0.0 && e.x > 0.0;
        let left = e.y < 0.0;
        side > 0.0 || (side == 0.0 && (top || left))
    })
}

/// COCO's compressed run-length string (pycocotools `rleToString`, the `counts` string of an RLE
/// with `size`): each count, minus the count two before it from the third on, in 5-bit groups
/// from the least significant, `0x20` marking that more follow, offset by 48 into printable
/// ASCII.
pub fn rle_string(counts: &[u32]) -> String {
    let mut out = String::new();
    for (i, &count) in counts.iter().enumerate() {
        let mut x = i64::from(count);
        if i > 2 {
            x -= i64::from(counts[i - 2]);
        }
        loop {
            let mut c = x & 0x1f;
            x >>= 5;
            let more = if c & 0x10 != 0 { x != -1 } else { x != 0 };
            if more {
                c |= 0x20;
            }
            out.push(char::from((c + 48) as u8));
            if !more {
                break;
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mask_of(rows: &[&str]) -> Mask {
        let mut m = Mask::new(rows[0].len() as u32, rows.len() as u32);
        for (r, row) in rows.iter().enumerate() {
            for (c, ch) in row.chars().enumerate() {
                m.pixels[r * rows[0].len() + c] = ch == '#';
            }
        }
        m
    }

    #[test]
    fn run_lengths_read_columns_top_to_bottom_starting_unset() {
        let m = mask_of(&["#..", "##.", "..."]);
        // Columns: [#, #, .], [., #, .], [., ., .] -> 0 unset, 2 set, 2 unset, 1 set, 4 unset.
        assert_eq!(m.rle_counts(), [0, 2, 2, 1, 4]);
        assert_eq!(m.bbox_px(), Some([0, 0, 2, 2]));
        assert_eq!(m.area_px(), 3);
        assert_eq!(Mask::new(2, 2).rle_counts(), [4]);
        assert_eq!(Mask::new(2, 2).bbox_px(), None);
    }

    #[test]
    fn rle_strings_match_pycocotools() {
        // pycocotools 2.0.11: `mask.encode` of the 3x3 mask above gives b"022O2", and
        // `frPyObjects({"size": [1, 49], "counts": [5, 40, 3, 1]}, 1, 49)` b"5X13iN" (a count
        // needing two 5-bit groups, and a difference below zero needing two).
        assert_eq!(rle_string(&[0, 2, 2, 1, 4]), "022O2");
        assert_eq!(rle_string(&[5, 40, 3, 1]), "5X13iN");
    }

    #[test]
    fn visible_masks_are_the_id_pixels_and_foreign_ids_are_refused() {
        let ids = [0, 1, 2, 2, 0, 1];
        let m = visible_masks(&ids, 3, 2, 2).unwrap();
        assert_eq!(m[0].pixels, [false, true, false, false, false, true]);
        assert_eq!(m[1].pixels, [false, false, true, true, false, false]);
        assert!(matches!(
            visible_masks(&ids, 3, 2, 1),
            Err(MaskError::UnknownBlock { id: 2, blocks: 1 })
        ));
        assert!(matches!(
            visible_masks(&ids, 2, 2, 2),
            Err(MaskError::Size { .. })
        ));
    }

    #[test]
    fn pixel_centres_on_shared_edges_belong_to_one_polygon() {
        // Rectangles sharing the line x = 1.5 (and y = 1.5) through pixel centres: without the
        // top-left rule both would claim the centres on it, or neither.
        let rect = |x0: f64, y0: f64, x1: f64, y1: f64| {
            vec![
                DVec2::new(x0, y0),
                DVec2::new(x1, y0),
                DVec2::new(x1, y1),
                DVec2::new(x0, y1),
            ]
        };
        let pairs = [
            (rect(0.5, 0.5, 1.5, 2.5), rect(1.5, 0.5, 2.5, 2.5)),
            (rect(0.5, 0.5, 2.5, 1.5), rect(0.5, 1.5, 2.5, 2.5)),
        ];
        for (a, b) in pairs {
            let (a, b) = (polygon_mask(&a, 4, 4), polygon_mask(&b, 4, 4));
            let both = a.pixels.iter().zip(&b.pixels).filter(|(p, q)| **p && **q);
            assert_eq!(both.count(), 0);
            assert_eq!((a.area_px(), b.area_px()), (2, 2));
            // Together they cover exactly the centres (0.5 | 1.5, 0.5 | 1.5).
            assert_eq!(
                (0..16)
                    .filter(|&i| a.pixels[i] || b.pixels[i])
                    .collect::<Vec<_>>(),
                [0, 1, 4, 5]
            );
        }
        let square = rect(0.5, 0.5, 2.5, 2.5);
        let reversed: Vec<DVec2> = square.iter().rev().copied().collect();
        assert_eq!(polygon_mask(&reversed, 4, 4), polygon_mask(&square, 4, 4));
    }
}
