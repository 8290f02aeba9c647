//! Step 1 of the vision front end: the Sobel edge magnitude (Chapter II, eq. 2.1 with the
//! Figure 2.7 kernels), 3x3 mean smoothing and a threshold (Chapter VI, "The Effect of the Sobel
//! Operator"), giving a binary edge map.
//!
//! Readings (docs/thesis-readings.md "Thesis readings"): eq. 2.1b prints `- f(m-1,n+1)`; the Figure 2.7
//! kernel and symmetry say `+`, which is what is computed here. The border is handled by
//! repeating the edge pixel, which reproduces the thesis's 3x11 worked example exactly.
//!
//! Cost: each step is one pass over the image with a few integer operations per pixel and one
//! output allocation per image (no per-pixel allocation).

use image::{GrayImage, ImageBuffer, Luma};

/// A 16-bit single-channel image: Sobel magnitudes (0..=1443) and their smoothed values.
pub type MagnitudeImage = ImageBuffer<Luma<u16>, Vec<u16>>;

/// Which 3x3 window the smoothing averages (Chapter VI).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SmoothWindow {
    /// Rows `i-1..=i+1`, columns `j-1..=j+1`: the window centred on the pixel. The default,
    /// because it does not move edges.
    #[default]
    Centred,
    /// Rows `i-1..=i+1`, columns `j-2..=j`: the window that reproduces the thesis's smoothed
    /// 3x11 table value for value (its edges sit one column right of the centred result).
    Trailing,
}

/// Options of the edge detector (Chapter II, VI).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct EdgeOptions {
    /// A smoothed magnitude strictly above this is an edge pixel. Default 80, the value the
    /// thesis used for its Figures 6.5 and 6.6 (Ch. VI); its worked 3x11 example uses 60.
    pub threshold: u16,
    /// Hysteresis (docs/rendering.md "Photographic look"): a smoothed magnitude above this, but not above
    /// `threshold`, is an edge pixel too when it is 8-connected through such pixels to one above
    /// `threshold`. In a camera picture an edge between two faces of nearly equal shading (a lit
    /// bevel between them, 5-10 gray levels of step) gives 40-50, below the thesis's 80, while
    /// its ends meet strong edges. Raised to [`WEAK_OVER_MEDIAN`] times the picture's median
    /// magnitude (the noise on its faces) when that is higher, so sensor noise does not grow
    /// along edges; equal to `threshold` (or above) turns hysteresis off. Default 80, off:
    /// at 40 or 30 on the photo-look accuracy suite it also kept the soft shadows' edges near
    /// contacts and made fewer views match their exact drawings (docs/rendering.md "Photographic look");
    /// the faint edges are read between found vertices instead (`add_faint_edges`).
    pub weak_threshold: u16,
    /// Which 3x3 window smooths the magnitude; default [`SmoothWindow::Centred`].
    pub window: SmoothWindow,
}

impl Default for EdgeOptions {
    fn default() -> Self {
        EdgeOptions {
            threshold: 80,
            weak_threshold: 80,
            window: SmoothWindow::Centred,
        }
    }
}

/// Clamped neighbour indices `(i-1, i, i+1)` of `i` in `0..n` (edge pixel repeated).
#[inline]
fn around(i: usize, n: usize) -> (usize, usize, usize) {
    (i.saturating_sub(1), i, (i + 1).min(n - 1))
}

/// The Sobel edge magnitude `sqrt(dx^2 + dy^2)` of eq. 2.1, with the symmetric kernels of
/// Figure 2.7 (eq. 2.1b's sign typo is not followed), rounded to the nearest integer. Border
/// pixels repeat the edge pixel. A step of `d` gray levels gives `4 d` on both sides of it (the
/// thesis's 100 -> 50 step gives 200, Ch. VI).
pub fn sobel_magnitude(image: &GrayImage) -> MagnitudeImage {
    let (w, h) = image.dimensions();
    let (wu, hu) = (w as usize, h as usize);
    let mut out = vec![0u16; wu * hu];
    if wu == 0 || hu == 0 {
        return MagnitudeImage::from_raw(w, h, out).unwrap_or_default();
    }
    for (y, row) in out.chunks_exact_mut(wu).enumerate() {
        sobel_row(image.as_raw(), wu, hu, y, row);
    }
    MagnitudeImage::from_raw(w, h, out).unwrap_or_default()
}

/// Row `y` of [`sobel_magnitude`] of the `wu` x `hu` picture `src` into `row`.
#[inline(always)]
fn sobel_row(src: &[u8], wu: usize, hu: usize, y: usize, row: &mut [u16]) {
    let (ya, _, yb) = around(y, hu);
    let (ra, r, rb) = (
        &src[ya * wu..][..wu],
        &src[y * wu..][..wu],
        &src[yb * wu..][..wu],
    );
    // Border columns repeat the edge pixel.
    for x in [0, wu - 1] {
        let (xa, _, xb) = around(x, wu);
        row[x] = sobel_at(
            [ra[xa], ra[x], ra[xb]],
            [r[xa], r[xb]],
            [rb[xa], rb[x], rb[xb]],
        );
    }
    if wu >= 3 {
        sobel_interior(ra, r, rb, &mut row[1..wu - 1]);
    }
}

/// Step 1 in one pass: the binary edge map of `image`, the same as
/// [`threshold_hysteresis`] of [`smooth_3x3`] of [`sobel_magnitude`] (Chapter II eq. 2.1,
/// Chapter VI), computed row by row with three rows of magnitudes and their horizontal sums
/// held, so neither the magnitude nor the smoothed image is stored: the picture is read once and
/// the map written once. With hysteresis on (`weak_threshold < threshold`), which needs the
/// whole smoothed image, the three steps run one after the other.
pub fn edge_map(image: &GrayImage, opts: &EdgeOptions) -> GrayImage {
    if opts.weak_threshold < opts.threshold {
        return detect_edges(image, opts).1;
    }
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has AVX2, checked just above.
        return unsafe { edge_map_avx2(image, opts) };
    }
    edge_map_rows(image, opts)
}

/// [`edge_map_rows`] compiled for AVX2 (sixteen 16-bit lanes instead of eight): the same
/// integer and `f32` operations, so the same map, in about half the instructions. Chosen at
/// run time, as OpenCV does, since the binary is built for baseline x86-64.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn edge_map_avx2(image: &GrayImage, opts: &EdgeOptions) -> GrayImage {
    edge_map_rows(image, opts)
}

/// The one-pass [`edge_map`] without hysteresis.
#[inline(always)]
fn edge_map_rows(image: &GrayImage, opts: &EdgeOptions) -> GrayImage {
    let (w, h) = image.dimensions();
    let (wu, hu) = (w as usize, h as usize);
    let mut out = vec![0u8; wu * hu];
    if wu == 0 || hu == 0 {
        return GrayImage::from_raw(w, h, out).unwrap_or_default();
    }
    let (mut magnitude, mut sums) = (vec![0u16; wu], vec![0u16; 3 * wu]);
    let mut held = [usize::MAX; 3];
    // `(s + 4) / 9 > t` (the rounded mean of [`smooth_3x3`] above the threshold) is `s >= 9 t + 5`.
    let least_sum = 9 * u32::from(opts.threshold) + 5;
    for y in 0..hu {
        let (ya, _, yb) = around(y, hu);
        for r in [ya, y, yb] {
            if held[r % 3] != r {
                sobel_row(image.as_raw(), wu, hu, r, &mut magnitude);
                horizontal_sums(&magnitude, &mut sums[r % 3 * wu..][..wu], opts.window);
                held[r % 3] = r;
            }
        }
        let (a, m, b) = (
            &sums[ya % 3 * wu..][..wu],
            &sums[y % 3 * wu..][..wu],
            &sums[yb % 3 * wu..][..wu],
        );
        let row = &mut out[y * wu..][..wu];
        for (((o, &a), &m), &b) in row.iter_mut().zip(a).zip(m).zip(b) {
            *o = u8::from(u32::from(a) + u32::from(m) + u32::from(b) >= least_sum);
        }
    }
    GrayImage::from_raw(w, h, out).unwrap_or_default()
}

/// Eq. 2.1 on the interior pixels of one row (`out[i]` is pixel `i + 1`): the rows above, at and
/// below as slices of equal length, indexed so the compiler drops the bounds checks and works
/// on several pixels at once (the same values as [`sobel_at`], pixel by pixel).
#[inline(always)]
fn sobel_interior(above: &[u8], at: &[u8], below: &[u8], out: &mut [u16]) {
    let n = out.len();
    let (a0, a1, a2) = (&above[..n], &above[1..n + 1], &above[2..n + 2]);
    let (m0, m2) = (&at[..n], &at[2..n + 2]);
    let (b0, b1, b2) = (&below[..n], &below[1..n + 1], &below[2..n + 2]);
    for i in 0..n {
        out[i] = sobel_at([a0[i], a1[i], a2[i]], [m0[i], m2[i]], [b0[i], b1[i], b2[i]]);
    }
}

/// Eq. 2.1 on one 3x3 neighbourhood: the row above, the left and right neighbours, the row
/// below (the centre pixel has weight 0 in both kernels).
#[inline(always)]
fn sobel_at(above: [u8; 3], sides: [u8; 2], below: [u8; 3]) -> u16 {
    // In i16 (|dx|, |dy| <= 4 * 255) and squared in f32, exact (dx^2 + dy^2 < 2^24): the
    // compiler then works on eight pixels at a time, four for the square root.
    let v = |x: u8| i16::from(x);
    // dx: right column minus left column (Figure 2.7, left kernel).
    let dx = (v(above[2]) + 2 * v(sides[1]) + v(below[2]))
        - (v(above[0]) + 2 * v(sides[0]) + v(below[0]));
    // dy: top row minus bottom row (Figure 2.7, right kernel).
    let dy = (v(above[0]) + 2 * v(above[1]) + v(above[2]))
        - (v(below[0]) + 2 * v(below[1]) + v(below[2]));
    let (dx, dy) = (f32::from(dx), f32::from(dy));
    // `+ 0.5` then truncation rounds half up (the value is never negative) without a libm call.
    truncate_to_u16((dx * dx + dy * dy).sqrt() + 0.5)
}

/// `v as u16` for `0 <= v < 2^16` (a Sobel magnitude plus one half), in float and integer
/// operations the compiler runs four pixels at a time: Rust's saturating `as` conversion is
/// done one value at a time. Adding 2^23 rounds `v` to the nearest integer (ties to even) in
/// the low mantissa bits; one is taken off when that rounded up. Checked equal to `as u16` for
/// every magnitude of eq. 2.1 (unit test).
#[inline(always)]
fn truncate_to_u16(v: f32) -> u16 {
    const TWO_23: f32 = 8_388_608.0;
    let nearest = (v + TWO_23).to_bits().wrapping_sub(TWO_23.to_bits()) as i32;
    (nearest - i32::from(nearest as f32 > v)) as u16
}

/// The 3x3 mean of `magnitude` (Chapter VI: "replacing the value of every pixel with the average
/// of the 3x3 pixels of its neighborhood"), rounded to the nearest integer, edge pixels repeated.
/// [`SmoothWindow::Trailing`] reproduces the thesis's table; [`SmoothWindow::Centred`] (default)
/// does not shift edges.
pub fn smooth_3x3(magnitude: &MagnitudeImage, window: SmoothWindow) -> MagnitudeImage {
    let (w, h) = magnitude.dimensions();
    let (wu, hu) = (w as usize, h as usize);
    let mut out = vec![0u16; wu * hu];
    if wu == 0 || hu == 0 {
        return MagnitudeImage::from_raw(w, h, out).unwrap_or_default();
    }
    let src = magnitude.as_raw();
    // The horizontal 3-sums of the three rows in use, row `r` in slot `r % 3` (three rows of
    // scratch instead of a second image).
    let mut ring = vec![0u16; 3 * wu];
    let mut held = [usize::MAX; 3];
    for y in 0..hu {
        let (ya, _, yb) = around(y, hu);
        for r in [ya, y, yb] {
            if held[r % 3] != r {
                horizontal_sums(&src[r * wu..][..wu], &mut ring[r % 3 * wu..][..wu], window);
                held[r % 3] = r;
            }
        }
        let (a, m, b) = (
            &ring[ya % 3 * wu..][..wu],
            &ring[y % 3 * wu..][..wu],
            &ring[yb % 3 * wu..][..wu],
        );
        // Vertical 3-sums, rounded mean.
        let row = &mut out[y * wu..][..wu];
        for (((o, &a), &m), &b) in row.iter_mut().zip(a).zip(m).zip(b) {
            *o = ((u32::from(a) + u32::from(m) + u32::from(b) + 4) / 9) as u16;
        }
    }
    MagnitudeImage::from_raw(w, h, out).unwrap_or_default()
}

/// The horizontal 3-sums of one row of magnitudes `r` into `dst` (at most 3 * 1443, fits u16),
/// over the columns `window` names, edge pixels repeated.
#[inline(always)]
fn horizontal_sums(r: &[u16], dst: &mut [u16], window: SmoothWindow) {
    let wu = r.len();
    let at = |i: usize| r[i];
    for x in [0, 1, wu - 1] {
        if x < wu {
            let (a, b, c) = match window {
                SmoothWindow::Centred => around(x, wu),
                SmoothWindow::Trailing => (x.saturating_sub(2), x.saturating_sub(1), x),
            };
            dst[x] = at(a) + at(b) + at(c);
        }
    }
    if wu >= 3 {
        let body = r.windows(3).map(|t| t[0] + t[1] + t[2]);
        match window {
            // Centred: column x sums x-1..=x+1, for x in 1..w-1.
            SmoothWindow::Centred => dst[1..wu - 1]
                .iter_mut()
                .zip(body)
                .for_each(|(d, v)| *d = v),
            // Trailing: column x sums x-2..=x, for x in 2..w.
            SmoothWindow::Trailing => dst[2..].iter_mut().zip(body).for_each(|(d, v)| *d = v),
        }
    }
}

/// The binary edge map (Chapter II "Threshold"): 1 where `smoothed > threshold`, else 0.
pub fn threshold(smoothed: &MagnitudeImage, threshold: u16) -> GrayImage {
    let (w, h) = smoothed.dimensions();
    let out = smoothed
        .as_raw()
        .iter()
        .map(|&v| u8::from(v > threshold))
        .collect();
    GrayImage::from_raw(w, h, out).unwrap_or_default()
}

/// The weak threshold is at least this many times the picture's median smoothed magnitude
/// ([`EdgeOptions::weak_threshold`]): most pixels lie on flat faces, so the median is their
/// noise (about 2 on a photo-look picture, about 25 with `--noise 8`).
pub const WEAK_OVER_MEDIAN: u16 = 2;

/// The median of a magnitude image (0 for an empty one), by a histogram of its values.
fn median_magnitude(smoothed: &MagnitudeImage) -> u16 {
    let raw = smoothed.as_raw();
    let mut counts = vec![0usize; usize::from(u16::MAX) + 1];
    for &v in raw {
        counts[usize::from(v)] += 1;
    }
    let half = raw.len() / 2;
    let mut seen = 0;
    for (v, &c) in counts.iter().enumerate() {
        seen += c;
        if seen > half {
            return v as u16;
        }
    }
    0
}

/// The binary edge map with hysteresis (see [`EdgeOptions::weak_threshold`]): 1 where
/// `smoothed > strong`, and where `smoothed > weak` (raised to [`WEAK_OVER_MEDIAN`] times the
/// median) on a pixel 8-connected through such pixels to one above `strong`; else 0. With
/// `weak >= strong` it is [`threshold`].
pub fn threshold_hysteresis(smoothed: &MagnitudeImage, strong: u16, weak: u16) -> GrayImage {
    let mut out = threshold(smoothed, strong);
    if weak >= strong {
        return out;
    }
    let weak = weak.max(median_magnitude(smoothed).saturating_mul(WEAK_OVER_MEDIAN));
    if weak >= strong {
        return out;
    }
    let (w, h) = smoothed.dimensions();
    let (wu, hu) = (w as usize, h as usize);
    let mag = smoothed.as_raw();
    let edge = out.as_mut();
    let mut stack: Vec<usize> = (0..edge.len()).filter(|&i| edge[i] == 1).collect();
    while let Some(i) = stack.pop() {
        let (x, y) = (i % wu, i / wu);
        for ny in y.saturating_sub(1)..=(y + 1).min(hu - 1) {
            for nx in x.saturating_sub(1)..=(x + 1).min(wu - 1) {
                let j = ny * wu + nx;
                if edge[j] == 0 && mag[j] > weak {
                    edge[j] = 1;
                    stack.push(j);
                }
            }
        }
    }
    out
}

/// Step 1 of the front end in one call: Sobel, smoothing, threshold. Returns the smoothed
/// magnitude and the binary edge map (values 0 and 1).
pub fn detect_edges(image: &GrayImage, opts: &EdgeOptions) -> (MagnitudeImage, GrayImage) {
    let smoothed = smooth_3x3(&sobel_magnitude(image), opts.window);
    let edges = threshold_hysteresis(&smoothed, opts.threshold, opts.weak_threshold);
    (smoothed, edges)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The thesis's 3x11 ideal image (Ch. VI): three identical rows.
    fn ideal_3x11() -> GrayImage {
        let row = [100u8, 100, 100, 50, 50, 50, 50, 100, 100, 100, 100];
        GrayImage::from_fn(11, 3, |x, _| Luma([row[x as usize]]))
    }

    fn rows<P: image::Primitive>(img: &ImageBuffer<Luma<P>, Vec<P>>) -> Vec<Vec<P>> {
        img.as_raw()
            .chunks(img.width() as usize)
            .map(|r| r.to_vec())
            .collect()
    }

    #[test]
    fn chapter_vi_3x11_example_value_for_value() {
        let sobel = sobel_magnitude(&ideal_3x11());
        let want_sobel = vec![0u16, 0, 200, 200, 0, 0, 200, 200, 0, 0, 0];
        assert_eq!(rows(&sobel), vec![want_sobel; 3]);

        let trailing = smooth_3x3(&sobel, SmoothWindow::Trailing);
        let want_smooth = vec![0u16, 0, 67, 133, 133, 67, 67, 133, 133, 67, 0];
        assert_eq!(rows(&trailing), vec![want_smooth.clone(); 3]);

        // The centred window gives the same numbers one column to the left.
        let centred = smooth_3x3(&sobel, SmoothWindow::Centred);
        let mut shifted = want_smooth[1..].to_vec();
        shifted.push(0);
        assert_eq!(rows(&centred), vec![shifted; 3]);

        let binary = threshold(&trailing, 60);
        let want_binary = vec![0u8, 0, 1, 1, 1, 1, 1, 1, 1, 1, 0];
        assert_eq!(rows(&binary), vec![want_binary; 3]);
    }

    /// The one-pass edge map is the three steps' map pixel for pixel: noisy pictures of odd
    /// sizes (one row, one column, two), both windows, thresholds around the values met; and it
    /// is not trivially so: the thesis's 3x11 example at threshold 60 has edges.
    #[test]
    fn one_pass_edge_map_equals_sobel_smoothing_and_threshold() {
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        for (w, h) in [(1, 1), (1, 7), (9, 1), (2, 2), (3, 3), (17, 11), (64, 40)] {
            let img = GrayImage::from_fn(w, h, |_, _| {
                let v = next();
                // Mostly flat with steps and speckle, as block pictures are.
                Luma([if v % 5 == 0 {
                    (v >> 8) as u8
                } else {
                    100 + (v % 3) as u8 * 40
                }])
            });
            for window in [SmoothWindow::Centred, SmoothWindow::Trailing] {
                for t in [0u16, 30, 60, 80, 200, 1443] {
                    let opts = EdgeOptions {
                        threshold: t,
                        weak_threshold: t,
                        window,
                    };
                    let steps = threshold(&smooth_3x3(&sobel_magnitude(&img), window), t);
                    assert_eq!(edge_map(&img, &opts), steps, "{w}x{h} {window:?} {t}");
                }
            }
        }
        let opts = EdgeOptions {
            threshold: 60,
            weak_threshold: 60,
            window: SmoothWindow::Trailing,
        };
        let map = edge_map(&ideal_3x11(), &opts);
        assert_eq!(rows(&map)[1], vec![0u8, 0, 1, 1, 1, 1, 1, 1, 1, 1, 0]);
    }

    #[test]
    fn vertical_step_uses_the_dy_kernel_and_constant_image_has_no_edges() {
        // A horizontal edge: top rows 10, bottom rows 60 -> dy magnitude 4 * 50 = 200.
        let img = GrayImage::from_fn(5, 6, |_, y| Luma([if y < 3 { 10 } else { 60 }]));
        let m = sobel_magnitude(&img);
        assert_eq!(m.get_pixel(2, 2).0[0], 200);
        assert_eq!(m.get_pixel(2, 3).0[0], 200);
        assert_eq!(m.get_pixel(2, 0).0[0], 0);
        let flat = GrayImage::from_pixel(7, 4, Luma([123]));
        let (_, e) = detect_edges(&flat, &EdgeOptions::default());
        assert!(e.as_raw().iter().all(|&v| v == 0));
        // A diagonal step: the magnitude is the Euclidean norm of both kernels.
        let diag = GrayImage::from_fn(3, 3, |x, y| Luma([if x + y < 2 { 0 } else { 100 }]));
        // Right column 100, 100, 100; left column 0, 0, 100; top row 0, 0, 100; bottom 100s.
        let dx = 400 - 100;
        let dy = 100 - 400;
        let want = ((dx * dx + dy * dy) as f64).sqrt().round() as u16;
        assert_eq!(sobel_magnitude(&diag).get_pixel(1, 1).0[0], want);
    }

    #[test]
    fn the_vectorised_truncation_equals_as_u16_for_every_sobel_magnitude() {
        // dx and dy of eq. 2.1 lie in -1020..=1020, so dx^2 + dy^2 <= 2 * 1020^2.
        for s in 0..=2 * 1020 * 1020 {
            let v = (s as f32).sqrt() + 0.5;
            assert_eq!(truncate_to_u16(v), v as u16, "dx^2 + dy^2 = {s}");
        }
        // It can fail: a value just below an integer must not round up.
        assert_eq!(truncate_to_u16(2.999), 2);
        assert_eq!(truncate_to_u16(3.0), 3);
    }

    #[test]
    fn a_faint_edge_joined_to_a_strong_one_is_kept_and_a_lone_one_is_not() {
        // A strong vertical step (50 levels) whose lower half fades to 18 levels, and a lone
        // 18-level step elsewhere: Sobel 4 d = 72 on the two columns of a faint step, 48 after
        // the 3x3 mean (strong: 133).
        let img = GrayImage::from_fn(40, 30, |x, y| {
            let d = if y < 15 { 50 } else { 18 };
            let left = if x < 10 { 100 } else { 100 + d };
            let lone = if x >= 30 && y >= 20 { 18 } else { 0 };
            Luma([(left + lone) as u8])
        });
        let smoothed = smooth_3x3(&sobel_magnitude(&img), SmoothWindow::Centred);
        let plain = threshold(&smoothed, 80);
        let hyst = threshold_hysteresis(&smoothed, 80, 40);
        let at = |e: &GrayImage, x, y| e.get_pixel(x, y).0[0];
        // The faint continuation of the strong step: only with hysteresis.
        assert_eq!((at(&plain, 9, 25), at(&hyst, 9, 25)), (0, 1));
        // The lone faint step is not connected to anything strong: never.
        assert_eq!((at(&plain, 30, 25), at(&hyst, 30, 25)), (0, 0));
        // With the weak threshold at the strong one, it is the plain threshold.
        assert_eq!(threshold_hysteresis(&smoothed, 80, 80), plain);
    }

    #[test]
    fn noise_raises_the_weak_threshold_to_twice_the_median() {
        // Half the pixels at 30, half at 60: median 60 (above half), weak 120 > strong 80, so
        // hysteresis is off and the result is the plain threshold.
        let m = MagnitudeImage::from_fn(10, 10, |x, _| Luma([if x < 5 { 30 } else { 60 }]));
        assert_eq!(median_magnitude(&m), 60);
        assert_eq!(threshold_hysteresis(&m, 80, 20), threshold(&m, 80));
        // Mostly flat (median 0): the weak threshold stays 20 and the 30s joined to the strong
        // column are kept.
        let quiet = MagnitudeImage::from_fn(10, 10, |x, _| {
            Luma([match x {
                0 => 100,
                1..=3 => 30,
                _ => 0,
            }])
        });
        let kept = threshold_hysteresis(&quiet, 80, 20);
        assert_eq!(kept.as_raw().iter().filter(|&&v| v == 1).count(), 40);
    }

    #[test]
    fn empty_and_one_pixel_images_do_not_panic() {
        for (w, h) in [(0, 0), (1, 1), (1, 5), (5, 1), (0, 3)] {
            let img = GrayImage::new(w, h);
            let (s, e) = detect_edges(&img, &EdgeOptions::default());
            assert_eq!(s.dimensions(), (w, h));
            assert_eq!(e.dimensions(), (w, h));
        }
    }
}
