//! Step 1b of the vision front end: edge pixels of faint steps along the block directions
//! (docs/recognizer-pictures.md "Steps read along the block directions").
//!
//! Chapter VI's Sobel operator reads a step from one 3 x 3 window, so a step must stand out of
//! one window's noise: at the third reading's threshold of 40, about 10 gray levels. In dim or
//! flat light two faces of a block, or a face and the floor, differ by less, while the step
//! runs straight along the whole edge: taken along the edge's own picture direction over
//! [`OrientedOptions::half_length_px`] px either side (the median of the changes across, so a
//! strong edge crossing the window does not carry it), the change across it stands out of
//! noise a few times smaller. [`oriented_edge_map`] marks the pixels where, for one of the
//! block directions, that change across the pixel reaches the threshold and is
//! [`STEP_OVER_BESIDE`] times the change [`BESIDE_PX`] either side: a band a few px wide per
//! faint edge, which the line finder of step 2 then fits like the Sobel map's bands. A ramp
//! of shading (a penumbra) changes as much beside it and is not marked.

use super::lines::EdgeDirection;
use crate::geom::{gray_at, median, noise_levels, DVec2};
use image::{GrayImage, Luma};

/// The noise of the median of n samples of Gaussian noise over that of their mean:
/// sqrt(pi / 2).
pub const MEDIAN_NOISE_RATIO: f64 = 1.2533141373155003;

/// Options of [`oriented_edge_map`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OrientedOptions {
    /// The change across is taken over this many px either side along the direction: 5 takes
    /// the median of 11 samples, under half the noise of one, and still fits along the 12 px
    /// edges of a `b7_5` at 256 x 240.
    pub half_length_px: usize,
    /// Smallest change across an edge pixel, gray levels: 4, under the 8 levels between two
    /// faces lit alike in the varied look's dim draws (docs/recognizer-pictures.md "Steps read
    /// along the block directions").
    pub min_step_levels: f64,
    /// The change must also reach this many times its own noise: the picture's noise, times
    /// sqrt 2 for a difference, times [`MEDIAN_NOISE_RATIO`] over the square root of the
    /// samples for their median.
    pub noise_multiple: f64,
}

impl Default for OrientedOptions {
    fn default() -> Self {
        OrientedOptions {
            half_length_px: 5,
            min_step_levels: 4.0,
            noise_multiple: 5.0,
        }
    }
}

impl OrientedOptions {
    /// The threshold on the change across for a picture of noise `noise_levels` (sigma, gray
    /// levels): [`Self::min_step_levels`], or [`Self::noise_multiple`] times the noise of the
    /// median when that is higher.
    pub fn threshold_levels(&self, noise_levels: f64) -> f64 {
        let samples = (2 * self.half_length_px + 1) as f64;
        let median_noise =
            noise_levels * std::f64::consts::SQRT_2 * MEDIAN_NOISE_RATIO / samples.sqrt();
        self.min_step_levels.max(self.noise_multiple * median_noise)
    }
}

/// The change across `c` along `u` (unit, picture px), taken over `half` px either side: the
/// median of `gray(p + n) - gray(p - n)` for `p = c + s u`, `n` the unit normal of `u`, so a
/// strong edge crossing the window at a few samples does not carry it; `None` when a sample
/// falls outside the picture. `changes` is scratch space, reused from pixel to pixel.
fn change_across(
    gray: &GrayImage,
    c: DVec2,
    u: DVec2,
    half: usize,
    changes: &mut Vec<f64>,
) -> Option<f64> {
    let n = u.perp();
    changes.clear();
    for s in -(half as i64)..=half as i64 {
        let p = c + u * s as f64;
        changes.push(gray_at(gray, p + n)? - gray_at(gray, p - n)?);
    }
    median(changes)
}

/// The change across each pixel of `gray` along `dir` ([`change_across`] at the pixel's
/// centre), absolute, row by row as the raster; 0 where the window leaves the picture.
fn changes_along(gray: &GrayImage, dir: &EdgeDirection, half: usize) -> Vec<f64> {
    let (w, h) = gray.dimensions();
    let mut out = vec![0.0; (w * h) as usize];
    let mut changes = Vec::with_capacity(2 * half + 1);
    for row in 0..h {
        let y = f64::from(h - 1 - row) + 0.5;
        for x in 0..w {
            let c = DVec2::new(f64::from(x) + 0.5, y);
            let m = change_across(gray, c, dir.at(c), half, &mut changes).map_or(0.0, f64::abs);
            out[(row * w + x) as usize] = m;
        }
    }
    out
}

/// The value of the raster `map` (w x h, as [`changes_along`]) at picture point `p`, 0
/// outside.
fn map_at(map: &[f64], w: u32, h: u32, p: DVec2) -> f64 {
    let (x, y) = (p.x.floor(), p.y.floor());
    if x < 0.0 || y < 0.0 || x >= f64::from(w) || y >= f64::from(h) {
        return 0.0;
    }
    map[((h - 1 - y as u32) * w + x as u32) as usize]
}

/// The binary map (0/1) of `gray`'s edge pixels of faint steps along `directions` (module
/// doc): a pixel is marked when, for one direction, the change across it reaches `opts`'s
/// threshold for the picture's noise and at least [`STEP_OVER_BESIDE`] times the change
/// across the pixels [`BESIDE_PX`] either side: a step changes within a px or two, while a
/// ramp (a penumbra, shading across a face) changes as much beside it, and so does the flank
/// of a strong edge's blur.
pub fn oriented_edge_map(
    gray: &GrayImage,
    directions: &[EdgeDirection],
    opts: &OrientedOptions,
) -> GrayImage {
    let (w, h) = gray.dimensions();
    let threshold = opts.threshold_levels(noise_levels(gray));
    let mut out = GrayImage::new(w, h);
    for dir in directions {
        let map = changes_along(gray, dir, opts.half_length_px);
        for row in 0..h {
            let y = f64::from(h - 1 - row) + 0.5;
            for x in 0..w {
                let m = map[(row * w + x) as usize];
                if m < threshold {
                    continue;
                }
                let c = DVec2::new(f64::from(x) + 0.5, y);
                let n = dir.at(c).perp() * BESIDE_PX;
                let beside = map_at(&map, w, h, c + n).max(map_at(&map, w, h, c - n));
                if m >= STEP_OVER_BESIDE * beside {
                    out.put_pixel(x, row, Luma([1]));
                }
            }
        }
    }
    out
}

/// How far either side of a pixel the change across is compared, px: past a sensor-blurred
/// step's own change (sigma about 1 px).
pub const BESIDE_PX: f64 = 3.0;
/// A marked pixel's change across is at least this many times that [`BESIDE_PX`] either side.
pub const STEP_OVER_BESIDE: f64 = 3.0;

/// `edges` with every pixel marked in `more` marked too (both 0/1 maps of one size).
pub(super) fn union_of_edge_maps(edges: &mut GrayImage, more: &GrayImage) {
    for (e, m) in edges.as_mut().iter_mut().zip(more.as_raw()) {
        *e = (*e).max(*m);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    /// A 60 x 60 picture: a face of 100 left of column 30 and of `100 - step` right of it, with
    /// uniform noise of +-`noise` levels (seeded).
    fn faces(step: f64, noise: f64) -> GrayImage {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        GrayImage::from_fn(60, 60, |x, _| {
            let level = if x < 30 { 100.0 } else { 100.0 - step };
            let e = if noise > 0.0 {
                rng.random_range(-noise..noise)
            } else {
                0.0
            };
            Luma([(level + e).round() as u8])
        })
    }

    fn vertical() -> Vec<EdgeDirection> {
        vec![EdgeDirection::Parallel(DVec2::Y)]
    }

    fn marked_columns(map: &GrayImage) -> Vec<u32> {
        let mut cols: Vec<u32> = map
            .enumerate_pixels()
            .filter(|(_, _, p)| p.0[0] != 0)
            .map(|(x, _, _)| x)
            .collect();
        cols.sort_unstable();
        cols.dedup();
        cols
    }

    #[test]
    fn a_faint_step_in_noise_is_marked_along_its_direction_and_nowhere_else() {
        // 6 levels of step under noise of +-4 levels (sigma 2.3): one window's Sobel does not
        // tell it from the noise, the average along the edge does.
        let pic = faces(6.0, 4.0);
        let map = oriented_edge_map(&pic, &vertical(), &OrientedOptions::default());
        let cols = marked_columns(&map);
        assert!(
            cols.iter().all(|&c| (28..=31).contains(&c)),
            "marked away from the step: {cols:?}"
        );
        let on_edge = map
            .enumerate_pixels()
            .filter(|(_, _, p)| p.0[0] != 0)
            .count();
        assert!(on_edge >= 40, "only {on_edge} px of the 60 px edge marked");
    }

    #[test]
    fn noise_alone_and_a_step_across_the_direction_are_not_marked() {
        let map = oriented_edge_map(&faces(0.0, 4.0), &vertical(), &OrientedOptions::default());
        assert!(marked_columns(&map).is_empty(), "noise marked");
        // The same step read along the horizontal: the averaging runs across the step.
        let across = [EdgeDirection::Parallel(DVec2::X)];
        let map = oriented_edge_map(&faces(6.0, 4.0), &across, &OrientedOptions::default());
        assert!(
            marked_columns(&map).is_empty(),
            "a step across the direction marked"
        );
    }

    #[test]
    fn a_step_under_the_smallest_change_is_not_marked() {
        let map = oriented_edge_map(&faces(3.0, 0.0), &vertical(), &OrientedOptions::default());
        assert!(marked_columns(&map).is_empty());
        let map = oriented_edge_map(&faces(5.0, 0.0), &vertical(), &OrientedOptions::default());
        assert_eq!(marked_columns(&map), vec![29, 30]);
    }

    /// Shading falling 3 levels per px across 16 px (a penumbra): 6 levels over 2 px, above
    /// the threshold, but as much beside every pixel as across it: not marked; a step of the
    /// same 6 levels is.
    #[test]
    fn a_ramp_of_shading_is_not_marked_and_a_step_as_strong_is() {
        let ramp = GrayImage::from_fn(60, 60, |x, _| {
            let x = f64::from(x).clamp(22.0, 38.0);
            Luma([(148.0 - 3.0 * (x - 22.0)).round() as u8])
        });
        let map = oriented_edge_map(&ramp, &vertical(), &OrientedOptions::default());
        assert!(
            marked_columns(&map).is_empty(),
            "{:?}",
            marked_columns(&map)
        );
        let map = oriented_edge_map(&faces(6.0, 0.0), &vertical(), &OrientedOptions::default());
        assert_eq!(marked_columns(&map), vec![29, 30]);
    }

    #[test]
    fn the_threshold_rises_with_the_noise() {
        let o = OrientedOptions::default();
        assert_eq!(o.threshold_levels(1.0), 4.0);
        let t = o.threshold_levels(6.0);
        assert!(
            (t - 5.0 * 6.0 * 2f64.sqrt() * MEDIAN_NOISE_RATIO / 11f64.sqrt()).abs() < 1e-9,
            "{t}"
        );
    }
}
