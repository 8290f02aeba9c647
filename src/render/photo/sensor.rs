//! The camera sensor of the photographic look (docs/rendering.md "Photographic look"): what the thesis's
//! COHU 4810 CCD and EPIX digitizer did to the light before the Sobel operator (Ch. VI): optical
//! blur (a Gaussian point spread function), vignetting, shot and read noise, gamma, 8-bit
//! quantization, and the 2 x 2 averaging that took 512 x 480 down to 256 x 240 and 128 x 120.
//!
//! Pure functions on plain buffers, no GPU: the renderer hands over linear radiance in [0, 1]
//! (rows top to bottom) and receives the 8-bit picture.

use crate::io::echo_number;
use image::{GrayImage, Luma};

/// Linear radiance per pixel, 0 = black, 1 = the brightest level the sensor records; rows top to
/// bottom, `width * height` values.
#[derive(Debug, Clone, PartialEq)]
pub struct RadianceImage {
    /// Width in px.
    pub width: u32,
    /// Height in px.
    pub height: u32,
    /// Values, row-major, rows top to bottom.
    pub values: Vec<f32>,
}

impl RadianceImage {
    /// An image of `width * height` pixels all at `value`.
    pub fn filled(width: u32, height: u32, value: f32) -> RadianceImage {
        RadianceImage {
            width,
            height,
            values: vec![value; width as usize * height as usize],
        }
    }

    #[cfg(test)]
    fn at(&self, x: usize, y: usize) -> f32 {
        self.values[y * self.width as usize + x]
    }
}

/// The sensor's parameters (docs/rendering.md "Photographic look"); the defaults give a clean but real
/// camera: a PSF of 0.7 px, 20,000 electrons at full well, 12 electrons of read noise, gamma
/// 1 (the linear setting of machine-vision CCD cameras; 2.2 is the video setting) and a 15%
/// corner falloff.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct SensorModel {
    /// Standard deviation of the Gaussian point spread function, px; 0 = none.
    pub blur_sigma_px: f64,
    /// Electrons collected at radiance 1: shot noise has standard deviation `sqrt(electrons)`,
    /// so a larger well is a cleaner picture; 0 = no shot noise.
    pub full_well_e: f64,
    /// Read noise, electrons (standard deviation), added whatever the light.
    pub read_noise_e: f64,
    /// Display gamma: the recorded level is `radiance^(1/gamma)`; 1 = linear.
    pub gamma: f64,
    /// Share of the light lost in the picture's corners (a `1 - v r^2` falloff, r = 1 at a
    /// corner); 0 = none.
    pub vignetting: f64,
}

impl Default for SensorModel {
    fn default() -> Self {
        SensorModel {
            blur_sigma_px: 0.7,
            full_well_e: 20_000.0,
            read_noise_e: 12.0,
            gamma: 1.0,
            vignetting: 0.15,
        }
    }
}

impl SensorModel {
    /// A sensor that changes nothing but quantization: no blur, noise or vignetting, gamma 1.
    pub const IDEAL: SensorModel = SensorModel {
        blur_sigma_px: 0.0,
        full_well_e: 0.0,
        read_noise_e: 0.0,
        gamma: 1.0,
        vignetting: 0.0,
    };

    /// Checks the parameters: blur 0..=10 px, full well 0 or 100..=1e7 electrons, read noise
    /// 0..=1e4 electrons, gamma 0.2..=5, vignetting 0..=0.9. The error says which is wrong.
    pub fn validate(&self) -> Result<(), String> {
        let checks = [
            ("blur", self.blur_sigma_px, 0.0, 10.0, "0..=10 px"),
            (
                "read-noise",
                self.read_noise_e,
                0.0,
                1e4,
                "0..=10000 electrons",
            ),
            ("gamma", self.gamma, 0.2, 5.0, "0.2..=5"),
            ("vignetting", self.vignetting, 0.0, 0.9, "0..=0.9"),
        ];
        for (what, v, lo, hi, range) in checks {
            if !(lo..=hi).contains(&v) {
                return Err(format!(
                    "--sensor-{what} {} is out of range; use {range}",
                    echo_number(v)
                ));
            }
        }
        let w = self.full_well_e;
        if !(w == 0.0 || (100.0..=1e7).contains(&w)) {
            return Err(format!(
                "--sensor-full-well {} is out of range; use 0 (no shot noise) or 100..=1e7 \
                 electrons",
                echo_number(w)
            ));
        }
        Ok(())
    }

    /// Records `radiance` as an 8-bit picture: blur, vignetting, shot and read noise (seeded by
    /// `seed`, the same seed gives the same picture), gamma, quantization. The picture is cut
    /// into bands of [`BAND_ROWS`] rows, exposed on rayon's threads (within the caller's pool,
    /// so `--jobs 1` stays on one thread); each band blurs its own rows plus the kernel's
    /// radius of neighbours, so it stays in the cache, and every pixel gets the same IEEE
    /// operations in the same order as [`gaussian_blur`], [`apply_vignetting`],
    /// [`add_shot_and_read_noise`] and [`quantize`] one after another (a unit test holds them to
    /// the same bytes), whatever the bands or threads.
    pub fn expose(&self, radiance: &RadianceImage, seed: u64) -> GrayImage {
        use rayon::prelude::*;
        let exposure = Exposure::new(self, radiance, seed);
        let mut out = vec![0u8; radiance.values.len()];
        let band_px = (radiance.width as usize * BAND_ROWS).max(1);
        out.par_chunks_mut(band_px)
            .enumerate()
            .for_each(|(b, band)| exposure.band(b * BAND_ROWS, band));
        GrayImage::from_raw(radiance.width, radiance.height, out).expect("one level per pixel")
    }
}

/// Rows of one band of [`SensorModel::expose`]: 32 rows of 512 px blurred with a 7-tap kernel
/// are 38 rows of f32, 78 KB, within a core's L2 cache.
pub const BAND_ROWS: usize = 32;

/// What [`SensorModel::expose`] computes once per picture and every band reads.
struct Exposure<'a> {
    radiance: &'a RadianceImage,
    kernel: Vec<f32>,
    vignette: Vignette,
    noise: PixelNoise,
    levels: QuantizationLevels,
}

impl<'a> Exposure<'a> {
    fn new(sensor: &SensorModel, radiance: &'a RadianceImage, seed: u64) -> Exposure<'a> {
        Exposure {
            radiance,
            kernel: gaussian_kernel(sensor.blur_sigma_px),
            vignette: Vignette::new(radiance.width, radiance.height, sensor.vignetting),
            noise: PixelNoise::new(sensor.full_well_e, sensor.read_noise_e, seed),
            levels: QuantizationLevels::new(sensor.gamma),
        }
    }

    /// Exposes the rows from `y0` into `out` (whole rows), with the widest vector arithmetic
    /// the CPU has: the loops are compiled for baseline x86-64, AVX2 and AVX-512 (chosen at
    /// run time), the same IEEE operations on each pixel, so the same bytes.
    fn band(&self, y0: usize, out: &mut [u8]) {
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("avx512f")
                && std::arch::is_x86_feature_detected!("avx512dq")
                && std::arch::is_x86_feature_detected!("avx512vl")
                && std::arch::is_x86_feature_detected!("avx512bw")
            {
                // SAFETY: the CPU has these features, checked just above.
                return unsafe { self.band_avx512(y0, out) };
            }
            if std::arch::is_x86_feature_detected!("avx2") {
                // SAFETY: the CPU has AVX2, checked just above.
                return unsafe { self.band_avx2(y0, out) };
            }
        }
        self.band_pixels(y0, out)
    }

    /// [`Exposure::band_pixels`] compiled with AVX-512 (64-bit multiplies in vectors for the
    /// noise's hash).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f,avx512dq,avx512vl,avx512bw")]
    unsafe fn band_avx512(&self, y0: usize, out: &mut [u8]) {
        self.band_pixels(y0, out)
    }

    /// [`Exposure::band_pixels`] compiled with AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn band_avx2(&self, y0: usize, out: &mut [u8]) {
        self.band_pixels(y0, out)
    }

    /// The body of [`Exposure::band`], inlined into each compiled variant: the horizontal blur
    /// of the band's rows and the kernel's radius around them ([`blur_row`]), then per output
    /// row the vertical blur ([`blur_column_row`]) and the fused vignetting, noise and
    /// quantization.
    #[inline(always)]
    fn band_pixels(&self, y0: usize, out: &mut [u8]) {
        let (w, h) = (self.radiance.width as usize, self.radiance.height as usize);
        if w == 0 {
            return;
        }
        let rows = out.len() / w;
        let r = self.kernel.len() / 2;
        let (lo, hi) = (y0.saturating_sub(r), (y0 + rows + r).min(h));
        let source = |y: usize| &self.radiance.values[y * w..][..w];
        let mut light = vec![0.0f32; w];
        let blurred: Vec<f32> = if r == 0 {
            Vec::new()
        } else {
            let mut blurred = vec![0.0f32; (hi - lo) * w];
            let mut padded = vec![0.0f32; w + 2 * r];
            for (y, dst) in (lo..hi).zip(blurred.chunks_exact_mut(w)) {
                blur_row(source(y), dst, &mut padded, &self.kernel);
            }
            blurred
        };
        for (dy, out_row) in out.chunks_exact_mut(w).enumerate() {
            let y = y0 + dy;
            let row: &[f32] = if r == 0 {
                source(y)
            } else {
                light.fill(0.0);
                blur_column_row(&mut light, y, h, &self.kernel, |sy| {
                    &blurred[(sy - lo) * w..][..w]
                });
                &light
            };
            self.expose_row(row, out_row, y);
        }
    }

    /// Vignetting, noise and quantization of blurred row `y`.
    #[inline(always)]
    fn expose_row(&self, row: &[f32], out_row: &mut [u8], y: usize) {
        let first = y * row.len();
        if self.levels.thresholds.is_none() && self.noise.on {
            expose_linear_row(row, out_row, &self.vignette, y, &self.noise, first);
            return;
        }
        for (x, (value, level)) in row.iter().zip(out_row.iter_mut()).enumerate() {
            let kept = value * self.vignette.gain(x, y);
            *level = self.levels.level(self.noise.record(kept, first + x));
        }
    }
}

/// One row of [`SensorModel::expose`] in its usual setting, gamma 1 with noise: the same
/// operations per pixel as the general loop (vignetting gain, [`PixelNoise::record`], then
/// [`QuantizationLevels::level`]'s rounding), written without a branch per pixel so the compiler
/// turns it into vector arithmetic. Row `y` starts at pixel index `first`.
#[inline(always)]
fn expose_linear_row(
    row: &[f32],
    out: &mut [u8],
    vignette: &Vignette,
    y: usize,
    noise: &PixelNoise,
    first: usize,
) {
    let (v, dy_sq) = (vignette.v, vignette.dy_sq[y]);
    for (x, ((value, level), dx_sq)) in row.iter().zip(out).zip(&vignette.dx_sq).enumerate() {
        let kept = value * (1.0 - v * (dx_sq + dy_sq));
        let recorded = noise.record_noisy(kept, first + x);
        // In 0.5..=255.5 (or NaN, which both casts make 0): truncating through i32 is the
        // same as through u8, and vectorizes.
        *level = (255.0 * recorded.clamp(0.0, 1.0) + 0.5) as i32 as u8;
    }
}

/// The normalised 1-D Gaussian kernel of standard deviation `sigma_px`, radius `ceil(3 sigma)`;
/// `[1]` for sigma 0.
pub fn gaussian_kernel(sigma_px: f64) -> Vec<f32> {
    if sigma_px <= 0.0 {
        return vec![1.0];
    }
    let radius = (3.0 * sigma_px).ceil() as i64;
    let raw: Vec<f64> = (-radius..=radius)
        .map(|i| (-(i * i) as f64 / (2.0 * sigma_px * sigma_px)).exp())
        .collect();
    let sum: f64 = raw.iter().sum();
    raw.iter().map(|w| (w / sum) as f32).collect()
}

/// Optical blur: the separable Gaussian point spread function of `sigma_px`; the border
/// repeats the edge pixel, so a uniform picture stays uniform and light is conserved inside.
/// Each pass adds the kernel's weighted, shifted rows in the kernel's order (whole rows at a
/// time, which the compiler turns into vector arithmetic).
pub fn gaussian_blur(img: &RadianceImage, sigma_px: f64) -> RadianceImage {
    let kernel = gaussian_kernel(sigma_px);
    if kernel.len() == 1 || img.values.is_empty() {
        return img.clone();
    }
    blur_columns(&blur_rows(img, &kernel), &kernel)
}

/// The horizontal pass of [`gaussian_blur`], row by row ([`blur_row`]).
fn blur_rows(img: &RadianceImage, kernel: &[f32]) -> RadianceImage {
    let (w, r) = (img.width as usize, kernel.len() / 2);
    let mut out = RadianceImage::filled(img.width, img.height, 0.0);
    let mut padded = vec![0.0f32; w + 2 * r];
    for (src, dst) in img
        .values
        .chunks_exact(w)
        .zip(out.values.chunks_exact_mut(w))
    {
        blur_row(src, dst, &mut padded, kernel);
    }
    out
}

/// One row of the horizontal blur: `src` padded with its edge pixels (in `padded`, of
/// `src.len() + kernel.len() - 1` values), then `dst[x] = sum_k kernel[k] * padded[x + k]`
/// added in the kernel's order onto `dst`'s zeros.
#[inline(always)]
fn blur_row(src: &[f32], dst: &mut [f32], padded: &mut [f32], kernel: &[f32]) {
    let (w, r) = (src.len(), kernel.len() / 2);
    padded[..r].fill(src[0]);
    padded[r..r + w].copy_from_slice(src);
    padded[r + w..].fill(src[w - 1]);
    for (k, weight) in kernel.iter().enumerate() {
        for (d, s) in dst.iter_mut().zip(&padded[k..k + w]) {
            *d += weight * s;
        }
    }
}

/// The vertical pass of [`gaussian_blur`], row by row ([`blur_column_row`]).
fn blur_columns(img: &RadianceImage, kernel: &[f32]) -> RadianceImage {
    let (w, h) = (img.width as usize, img.height as usize);
    let mut out = RadianceImage::filled(img.width, img.height, 0.0);
    for (y, dst) in out.values.chunks_exact_mut(w).enumerate() {
        blur_column_row(dst, y, h, kernel, |sy| &img.values[sy * w..][..w]);
    }
    out
}

/// Row `y` of the vertical blur of a picture `h` rows tall, added onto `dst`'s zeros: the
/// weighted sum, in the kernel's order, of the rows `y - r ..= y + r` clamped to the picture,
/// row `sy` read as `row(sy)`.
#[inline(always)]
fn blur_column_row<'r>(
    dst: &mut [f32],
    y: usize,
    h: usize,
    kernel: &[f32],
    row: impl Fn(usize) -> &'r [f32],
) {
    let r = kernel.len() / 2;
    for (k, weight) in kernel.iter().enumerate() {
        let sy = (y + k).saturating_sub(r).min(h - 1);
        for (d, s) in dst.iter_mut().zip(row(sy)) {
            *d += weight * s;
        }
    }
}

/// The share of light each pixel keeps under vignetting, `1 - v r^2`, from per-column and
/// per-row parts of `r^2` (`r`: distance from the picture centre over the half diagonal).
struct Vignette {
    v: f32,
    dx_sq: Vec<f32>,
    dy_sq: Vec<f32>,
}

impl Vignette {
    fn new(width: u32, height: u32, v: f64) -> Vignette {
        let (w, h) = (f64::from(width), f64::from(height));
        let half_diagonal_sq = ((w * w + h * h) / 4.0).max(f64::MIN_POSITIVE);
        let parts = |n: u32, size: f64| -> Vec<f32> {
            (0..n)
                .map(|i| {
                    let d = f64::from(i) + 0.5 - size / 2.0;
                    (d * d / half_diagonal_sq) as f32
                })
                .collect()
        };
        Vignette {
            v: v.max(0.0) as f32,
            dx_sq: parts(width, w),
            dy_sq: parts(height, h),
        }
    }

    /// Share kept at pixel (x, y); exactly 1 when `v` is 0.
    #[inline(always)]
    fn gain(&self, x: usize, y: usize) -> f32 {
        1.0 - self.v * (self.dx_sq[x] + self.dy_sq[y])
    }
}

/// Vignetting: each pixel keeps `1 - v r^2` of its light, `r` its distance from the picture
/// centre over the half diagonal (1 at the corners).
pub fn apply_vignetting(img: &mut RadianceImage, v: f64) {
    let vignette = Vignette::new(img.width, img.height, v);
    let w = img.width as usize;
    for (i, value) in img.values.iter_mut().enumerate() {
        *value *= vignette.gain(i % w, i / w);
    }
}

/// Shot and read noise of one exposure, as radiance: pixel `i` gets `z_i * sqrt(s / well +
/// (read / well)^2)` added to its clamped radiance `s`, `z_i` a standard normal deviate drawn
/// from the seed and the pixel's index alone ([`standard_normal`]), so any pixel's noise can
/// be made in any order.
struct PixelNoise {
    key: u64,
    shot_per_radiance: f32,
    read_sq: f32,
    on: bool,
}

impl PixelNoise {
    fn new(full_well_e: f64, read_noise_e: f64, seed: u64) -> PixelNoise {
        let well = if full_well_e > 0.0 {
            full_well_e
        } else {
            20_000.0
        };
        PixelNoise {
            key: mix64(seed ^ 0x5E_4503),
            shot_per_radiance: if full_well_e > 0.0 {
                (1.0 / well) as f32
            } else {
                0.0
            },
            read_sq: ((read_noise_e / well) * (read_noise_e / well)) as f32,
            on: full_well_e > 0.0 || read_noise_e > 0.0,
        }
    }

    /// The recorded radiance of pixel `i` receiving `radiance`.
    #[inline(always)]
    fn record(&self, radiance: f32, i: usize) -> f32 {
        if !self.on {
            return radiance;
        }
        self.record_noisy(radiance, i)
    }

    /// [`PixelNoise::record`] when the noise is on.
    #[inline(always)]
    fn record_noisy(&self, radiance: f32, i: usize) -> f32 {
        let s = radiance.max(0.0);
        let sigma = (self.shot_per_radiance * s + self.read_sq).sqrt();
        s + sigma * standard_normal(self.key, i as u64)
    }
}

/// The splitmix64 finalizer (Steele, Lea and Flood 2014): a bijective mix of 64 bits whose
/// outputs for consecutive inputs look independent.
#[inline(always)]
fn mix64(z: u64) -> u64 {
    let z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    let z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// A standard normal deviate for counter `i` under `key`: one 64-bit hash cut into four 16-bit
/// uniforms whose sum (Irwin-Hall, four terms) is centred and scaled to unit variance. Its
/// tails stop at 3.46 standard deviations, far beyond what an 8-bit level of this sensor's
/// noise can tell apart, at a tenth of the cost of an exact Gaussian.
#[inline(always)]
fn standard_normal(key: u64, i: u64) -> f32 {
    let h = mix64(key.wrapping_add(i.wrapping_mul(0x9E37_79B9_7F4A_7C15)));
    let sum = (h & 0xFFFF) + ((h >> 16) & 0xFFFF) + ((h >> 32) & 0xFFFF) + (h >> 48);
    // Each uniform is (u + 0.5) / 65536: mean 1/2, variance 1/12. The sum is below 2^18, so
    // converting it through i32 is exact (and vectorizes, where u64 to f32 does not).
    ((sum as i32 as f32 + 2.0) * (1.0 / 65_536.0) - 2.0) * 3.0f32.sqrt()
}

/// Shot noise (standard deviation `sqrt(signal electrons)`) plus read noise (`read_noise_e`),
/// as radiance, deterministic in `seed` and each pixel's index. No shot noise when
/// `full_well_e` is 0; read noise is then `read_noise_e` over a nominal well of 20,000
/// electrons.
pub fn add_shot_and_read_noise(
    img: &mut RadianceImage,
    full_well_e: f64,
    read_noise_e: f64,
    seed: u64,
) {
    let noise = PixelNoise::new(full_well_e, read_noise_e, seed);
    for (i, value) in img.values.iter_mut().enumerate() {
        *value = noise.record(*value, i);
    }
}

/// Gamma and 8-bit quantization of one radiance: gamma 1 rounds `255 * clamp(radiance, 0, 1)`
/// directly; another gamma counts the level thresholds `((k - 1/2) / 255)^gamma`, k = 1..=255,
/// the radiance reaches (the same rounding of `255 * radiance^(1/gamma)` without a power per
/// pixel).
struct QuantizationLevels {
    thresholds: Option<Vec<f32>>,
}

impl QuantizationLevels {
    fn new(gamma: f64) -> QuantizationLevels {
        QuantizationLevels {
            thresholds: (gamma != 1.0).then(|| {
                (1..=255)
                    .map(|k| ((f64::from(k) - 0.5) / 255.0).powf(gamma) as f32)
                    .collect()
            }),
        }
    }

    #[inline(always)]
    fn level(&self, radiance: f32) -> u8 {
        match &self.thresholds {
            None => (255.0 * radiance.clamp(0.0, 1.0) + 0.5) as u8,
            Some(t) => t.partition_point(|threshold| radiance >= *threshold) as u8,
        }
    }
}

/// Gamma and 8-bit quantization: level `round(255 * clamp(radiance, 0, 1)^(1/gamma))`, halves
/// rounded up.
pub fn quantize(img: &RadianceImage, gamma: f64) -> GrayImage {
    let levels = QuantizationLevels::new(gamma);
    let values = img.values.iter().map(|v| levels.level(*v)).collect();
    GrayImage::from_raw(img.width, img.height, values).expect("one level per pixel")
}

/// One 2 x 2 averaging step of the thesis (Ch. VI: 512 x 480 to 256 x 240 to 128 x 120): each
/// output pixel is the rounded mean of its four input pixels (an odd last row or column is
/// dropped).
pub fn average_2x2(img: &GrayImage) -> GrayImage {
    let (w, h) = (img.width() / 2, img.height() / 2);
    GrayImage::from_fn(w, h, |x, y| {
        let sum: u32 = [(0, 0), (1, 0), (0, 1), (1, 1)]
            .iter()
            .map(|(dx, dy)| u32::from(img.get_pixel(2 * x + dx, 2 * y + dy).0[0]))
            .sum();
        Luma([((sum + 2) / 4) as u8])
    })
}

/// `--downsample factor` (1, 2 or 4): [`average_2x2`] applied once per halving, as the thesis
/// did, so 4 is two rounded steps, not one 4 x 4 mean.
pub fn downsample(img: &GrayImage, factor: u32) -> GrayImage {
    let mut out = img.clone();
    let mut f = factor;
    while f >= 2 {
        out = average_2x2(&out);
        f /= 2;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_4x4_picture_averages_to_2x2_then_1x1_with_rounding() {
        let img = GrayImage::from_raw(
            4,
            4,
            vec![
                0, 2, 10, 10, //
                4, 4, 10, 11, //
                100, 100, 255, 255, //
                100, 101, 255, 254,
            ],
        )
        .unwrap();
        let half = downsample(&img, 2);
        // (0+2+4+4)/4 = 2.5 -> 3; (10+10+10+11)/4 = 10.25 -> 10; 401/4 -> 100; 1019/4 -> 255.
        assert_eq!(half.into_raw(), vec![3, 10, 100, 255]);
        // Two rounded steps: (3+10+100+255)/4 = 92.
        assert_eq!(downsample(&img, 4).into_raw(), vec![92]);
        assert_eq!(downsample(&img, 1), img);
    }

    #[test]
    fn the_blur_of_an_impulse_sums_to_one_and_is_symmetric() {
        let mut img = RadianceImage::filled(15, 15, 0.0);
        img.values[7 * 15 + 7] = 1.0;
        let blurred = gaussian_blur(&img, 1.2);
        let sum: f32 = blurred.values.iter().sum();
        assert!((sum - 1.0).abs() < 1e-5, "{sum}");
        assert!(blurred.at(7, 7) < 0.2 && blurred.at(7, 7) > 0.05);
        assert!((blurred.at(6, 7) - blurred.at(8, 7)).abs() < 1e-7);
        assert!((blurred.at(7, 5) - blurred.at(5, 7)).abs() < 1e-7);
        assert_eq!(gaussian_kernel(0.0), vec![1.0]);
        assert_eq!(gaussian_blur(&img, 0.0), img);
    }

    #[test]
    fn noise_is_deterministic_per_seed_and_grows_with_light() {
        let sensor = SensorModel {
            blur_sigma_px: 0.0,
            vignetting: 0.0,
            gamma: 1.0,
            ..SensorModel::default()
        };
        let gray = RadianceImage::filled(32, 32, 0.5);
        let a = sensor.expose(&gray, 1);
        assert_eq!(a, sensor.expose(&gray, 1));
        assert_ne!(a, sensor.expose(&gray, 2));
        let spread = |img: &GrayImage| {
            let v: Vec<f64> = img.pixels().map(|p| f64::from(p.0[0])).collect();
            let mean = v.iter().sum::<f64>() / v.len() as f64;
            (v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / v.len() as f64).sqrt()
        };
        // At half light: sqrt(10,000 + 144) e- over 20,000 e- is 0.504% = 1.28 levels.
        let s = spread(&a);
        assert!((1.0..1.6).contains(&s), "{s}");
        let dark = sensor.expose(&RadianceImage::filled(32, 32, 0.05), 1);
        assert!(spread(&dark) < s * 0.6);
        assert_eq!(
            SensorModel::IDEAL.expose(&gray, 1),
            GrayImage::from_pixel(32, 32, Luma([128]))
        );
    }

    #[test]
    fn gamma_vignetting_and_quantization_are_exact() {
        let img = RadianceImage {
            width: 3,
            height: 1,
            values: vec![0.25, 1.5, -0.1],
        };
        // 255 * 0.25^(1/2) = 127.5 -> 128; clamped above and below.
        assert_eq!(quantize(&img, 2.0).into_raw(), vec![128, 255, 0]);
        let mut flat = RadianceImage::filled(4, 4, 1.0);
        apply_vignetting(&mut flat, 0.5);
        // Corner pixel centre (0.5, 0.5): r^2 = (1.5^2 + 1.5^2) / 8 = 0.5625.
        assert!((flat.at(0, 0) - (1.0 - 0.5 * 0.5625)).abs() < 1e-6);
        assert!(flat.at(1, 1) > flat.at(0, 0));
        assert_eq!(flat.at(0, 0), flat.at(3, 3));
    }

    /// The steps one after another on a picture with edges, dark and over-bright parts.
    fn exposed_step_by_step(
        sensor: &SensorModel,
        radiance: &RadianceImage,
        seed: u64,
    ) -> GrayImage {
        let mut light = gaussian_blur(radiance, sensor.blur_sigma_px);
        apply_vignetting(&mut light, sensor.vignetting);
        add_shot_and_read_noise(&mut light, sensor.full_well_e, sensor.read_noise_e, seed);
        quantize(&light, sensor.gamma)
    }

    fn test_scene(w: u32, h: u32) -> RadianceImage {
        let mut img = RadianceImage::filled(w, h, 0.0);
        for (i, v) in img.values.iter_mut().enumerate() {
            let (x, y) = (i as u32 % w, i as u32 / w);
            *v = if x < w / 3 {
                0.05
            } else if y < h / 2 {
                0.6
            } else {
                1.2
            };
        }
        img
    }

    /// [`SensorModel::expose`] one band after another on this thread, each exposed by `band`
    /// (one of [`Exposure`]'s compiled variants).
    fn exposed_band_by_band(
        sensor: &SensorModel,
        radiance: &RadianceImage,
        seed: u64,
        band: impl Fn(&Exposure, usize, &mut [u8]),
    ) -> GrayImage {
        let exposure = Exposure::new(sensor, radiance, seed);
        let w = radiance.width as usize;
        let mut out = vec![0u8; radiance.values.len()];
        for (b, rows) in out.chunks_mut(w * BAND_ROWS).enumerate() {
            band(&exposure, b * BAND_ROWS, rows);
        }
        GrayImage::from_raw(radiance.width, radiance.height, out).unwrap()
    }

    #[test]
    fn the_fused_exposure_equals_the_steps_one_after_another() {
        // Taller than two bands, with a bright stripe across the border between the first two
        // (each band blurs the rows beyond its border itself).
        let mut img = test_scene(37, 23 + 2 * BAND_ROWS as u32);
        for x in 0..37 {
            img.values[(BAND_ROWS - 1) * 37 + x] = 0.95;
        }
        for sensor in [
            SensorModel::default(),
            SensorModel {
                gamma: 2.2,
                vignetting: 0.4,
                blur_sigma_px: 1.5,
                ..SensorModel::default()
            },
            SensorModel {
                full_well_e: 0.0,
                ..SensorModel::default()
            },
            SensorModel::IDEAL,
        ] {
            assert_eq!(
                sensor.expose(&img, 9),
                exposed_step_by_step(&sensor, &img, 9)
            );
            // The baseline loops (what a CPU without AVX2 runs) give the same bytes.
            let baseline = |e: &Exposure, y0, rows: &mut [u8]| e.band_pixels(y0, rows);
            assert_eq!(
                sensor.expose(&img, 9),
                exposed_band_by_band(&sensor, &img, 9, baseline)
            );
            #[cfg(target_arch = "x86_64")]
            if std::arch::is_x86_feature_detected!("avx2") {
                // SAFETY: the CPU has AVX2, checked just above.
                let avx2 = |e: &Exposure, y0, rows: &mut [u8]| unsafe { e.band_avx2(y0, rows) };
                assert_eq!(
                    sensor.expose(&img, 9),
                    exposed_band_by_band(&sensor, &img, 9, avx2)
                );
            }
        }
        // The comparison can fail: another seed's noise differs.
        let sensor = SensorModel::default();
        assert_ne!(
            sensor.expose(&img, 9),
            exposed_step_by_step(&sensor, &img, 10)
        );
    }

    #[test]
    fn the_separable_blur_matches_the_two_dimensional_sum_with_repeated_borders() {
        let img = test_scene(11, 9);
        let kernel = gaussian_kernel(0.9);
        let r = (kernel.len() / 2) as i64;
        let blurred = gaussian_blur(&img, 0.9);
        let at = |x: i64, y: i64| img.at(x.clamp(0, 10) as usize, y.clamp(0, 8) as usize);
        for y in 0..9i64 {
            for x in 0..11i64 {
                let mut want = 0.0f64;
                for (j, wy) in kernel.iter().enumerate() {
                    for (i, wx) in kernel.iter().enumerate() {
                        let (dx, dy) = (i as i64 - r, j as i64 - r);
                        want += f64::from(*wx * *wy) * f64::from(at(x + dx, y + dy));
                    }
                }
                let got = f64::from(blurred.at(x as usize, y as usize));
                assert!((got - want).abs() < 1e-5, "({x}, {y}): {got} vs {want}");
            }
        }
    }

    #[test]
    fn per_pixel_normal_deviates_have_unit_variance_and_no_pattern() {
        let n = 200_000u64;
        let z: Vec<f64> = (0..n)
            .map(|i| f64::from(standard_normal(mix64(5), i)))
            .collect();
        let mean = z.iter().sum::<f64>() / n as f64;
        let var = z.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n as f64;
        assert!(
            mean.abs() < 0.01 && (var - 1.0).abs() < 0.02,
            "{mean} {var}"
        );
        // Neighbours are uncorrelated, and about a third of the deviates lie beyond one sigma
        // (31.7% for a Gaussian, 33% for this sum, 42% for one uniform).
        let lag1 = z.windows(2).map(|p| p[0] * p[1]).sum::<f64>() / n as f64;
        assert!(lag1.abs() < 0.01, "{lag1}");
        let beyond = z.iter().filter(|v| v.abs() > 1.0).count() as f64 / n as f64;
        assert!((0.31..0.34).contains(&beyond), "{beyond}");
        assert!(z.iter().all(|v| v.abs() <= 3.47));
        // The share check can fail: one uniform scaled to unit variance puts 42% beyond.
        let uniform = (0..n)
            .filter(|&i| {
                let u = (mix64(i) >> 40) as f64 / (1u64 << 24) as f64;
                ((u - 0.5) * 12f64.sqrt()).abs() > 1.0
            })
            .count() as f64
            / n as f64;
        assert!(!(0.31..0.34).contains(&uniform), "{uniform}");
    }

    #[test]
    fn out_of_range_parameters_are_named() {
        assert!(SensorModel::default().validate().is_ok());
        let bad = SensorModel {
            gamma: 0.0,
            ..SensorModel::default()
        };
        assert!(bad.validate().unwrap_err().contains("--sensor-gamma"));
        let bad = SensorModel {
            full_well_e: 5.0,
            ..SensorModel::default()
        };
        assert!(bad.validate().unwrap_err().contains("--sensor-full-well"));
    }
}
