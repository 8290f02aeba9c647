//! The camera sensor of the photographic look (README "Photographic look"): what the thesis's
//! COHU 4810 CCD and EPIX digitizer did to the light before the Sobel operator (Ch. VI): optical
//! blur (a Gaussian point spread function), vignetting, shot and read noise, gamma, 8-bit
//! quantization, and the 2 x 2 averaging that took 512 x 480 down to 256 x 240 and 128 x 120.
//!
//! Pure functions on plain buffers, no GPU: the renderer hands over linear radiance in [0, 1]
//! (rows top to bottom) and receives the 8-bit picture.

use image::{GrayImage, Luma};
use rand::SeedableRng;
use rand_distr::Distribution;

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

    fn at(&self, x: usize, y: usize) -> f32 {
        self.values[y * self.width as usize + x]
    }
}

/// The sensor's parameters (README "Photographic look"); the defaults give a clean but real
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
                "read noise",
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
                return Err(format!("sensor {what} {v} is out of range; use {range}"));
            }
        }
        let w = self.full_well_e;
        if !(w == 0.0 || (100.0..=1e7).contains(&w)) {
            return Err(format!(
                "sensor full well {w} electrons is out of range; use 0 (no shot noise) or 100..=1e7"
            ));
        }
        Ok(())
    }

    /// Records `radiance` as an 8-bit picture: blur, vignetting, shot and read noise (seeded by
    /// `seed`, the same seed gives the same picture), gamma, quantization.
    pub fn expose(&self, radiance: &RadianceImage, seed: u64) -> GrayImage {
        let mut light = gaussian_blur(radiance, self.blur_sigma_px);
        apply_vignetting(&mut light, self.vignetting);
        add_shot_and_read_noise(&mut light, self.full_well_e, self.read_noise_e, seed);
        quantize(&light, self.gamma)
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
pub fn gaussian_blur(img: &RadianceImage, sigma_px: f64) -> RadianceImage {
    let kernel = gaussian_kernel(sigma_px);
    if kernel.len() == 1 {
        return img.clone();
    }
    let rows = convolve_1d(img, &kernel, true);
    convolve_1d(&rows, &kernel, false)
}

fn convolve_1d(img: &RadianceImage, kernel: &[f32], along_x: bool) -> RadianceImage {
    let (w, h) = (img.width as usize, img.height as usize);
    let r = (kernel.len() / 2) as i64;
    let mut out = RadianceImage::filled(img.width, img.height, 0.0);
    for y in 0..h {
        for x in 0..w {
            let mut acc = 0.0f32;
            for (k, weight) in kernel.iter().enumerate() {
                let d = k as i64 - r;
                let (sx, sy) = if along_x {
                    ((x as i64 + d).clamp(0, w as i64 - 1) as usize, y)
                } else {
                    (x, (y as i64 + d).clamp(0, h as i64 - 1) as usize)
                };
                acc += weight * img.at(sx, sy);
            }
            out.values[y * w + x] = acc;
        }
    }
    out
}

/// Vignetting: each pixel keeps `1 - v r^2` of its light, `r` its distance from the picture
/// centre over the half diagonal (1 at the corners).
pub fn apply_vignetting(img: &mut RadianceImage, v: f64) {
    if v <= 0.0 {
        return;
    }
    let (w, h) = (img.width as f64, img.height as f64);
    let half_diagonal_sq = (w * w + h * h) / 4.0;
    let width = img.width as usize;
    for (i, value) in img.values.iter_mut().enumerate() {
        let dx = (i % width) as f64 + 0.5 - w / 2.0;
        let dy = (i / width) as f64 + 0.5 - h / 2.0;
        let r_sq = (dx * dx + dy * dy) / half_diagonal_sq;
        *value *= (1.0 - v * r_sq) as f32;
    }
}

/// Shot noise (standard deviation `sqrt(signal electrons)`) plus read noise (`read_noise_e`),
/// as radiance: Gaussian, deterministic in `seed`. No shot noise when `full_well_e` is 0; read
/// noise is then `read_noise_e` over a nominal well of 20,000 electrons.
pub fn add_shot_and_read_noise(
    img: &mut RadianceImage,
    full_well_e: f64,
    read_noise_e: f64,
    seed: u64,
) {
    if full_well_e <= 0.0 && read_noise_e <= 0.0 {
        return;
    }
    let well = if full_well_e > 0.0 {
        full_well_e
    } else {
        20_000.0
    };
    let shot = if full_well_e > 0.0 { 1.0 } else { 0.0 };
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let unit = rand_distr::StandardNormal;
    for value in img.values.iter_mut() {
        let electrons = f64::from(*value).max(0.0) * well;
        let sigma_e = (shot * electrons + read_noise_e * read_noise_e).sqrt();
        let z: f64 = unit.sample(&mut rng);
        *value = ((electrons + sigma_e * z) / well) as f32;
    }
}

/// Gamma and 8-bit quantization: level `round(255 * clamp(radiance, 0, 1)^(1/gamma))`.
pub fn quantize(img: &RadianceImage, gamma: f64) -> GrayImage {
    let mut out = GrayImage::new(img.width, img.height);
    for (p, value) in out.pixels_mut().zip(&img.values) {
        let linear = f64::from(*value).clamp(0.0, 1.0);
        p.0[0] = (255.0 * linear.powf(1.0 / gamma)).round() as u8;
    }
    out
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

    #[test]
    fn out_of_range_parameters_are_named() {
        assert!(SensorModel::default().validate().is_ok());
        let bad = SensorModel {
            gamma: 0.0,
            ..SensorModel::default()
        };
        assert!(bad.validate().unwrap_err().contains("gamma"));
        let bad = SensorModel {
            full_well_e: 5.0,
            ..SensorModel::default()
        };
        assert!(bad.validate().unwrap_err().contains("full well"));
    }
}
