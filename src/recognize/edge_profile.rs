//! Reading a view's picture across one segment (docs/recognizer.md "Recognizer"): the
//! picture with its noise and scale ([`ViewPicture`]), and what it shows across a line, step
//! or crack ([`EdgeProfile`]), as the thesis's line finder read its edge pixels: across the
//! line. [`super::picture`] asks it where a hypothesis's redraw and a view's drawing differ.

use super::Camera;
use crate::geom::{gray_at, median, noise_levels, DVec2, DVec3};
use image::GrayImage;
/// A view's picture with its noise and scale, read once.
#[derive(Debug, Clone, Copy)]
pub struct ViewPicture<'a> {
    /// The grayscale picture the view's drawing was read from (px, y up as in `geom`).
    pub gray: &'a GrayImage,
    /// The picture's noise sigma, gray levels ([`noise_levels`]).
    pub noise_levels: f64,
    /// Picture px per world mm at the camera's target, along the block axis drawn longest.
    pub px_per_mm: f64,
}

impl<'a> ViewPicture<'a> {
    /// `gray`, taken by `camera`, with its noise and scale measured.
    pub fn new(gray: &'a GrayImage, camera: &Camera) -> ViewPicture<'a> {
        let at = DVec3::from_array(camera.target_mm);
        let centre = camera.picture_from_world(at).truncate();
        let px_per_mm = [DVec3::X, DVec3::Y, DVec3::Z]
            .iter()
            .map(|&axis| {
                camera
                    .picture_from_world(at + axis)
                    .truncate()
                    .distance(centre)
            })
            .filter(|d| d.is_finite())
            .fold(0.0, f64::max);
        ViewPicture {
            gray,
            noise_levels: noise_levels(gray),
            px_per_mm,
        }
    }

    /// `true` when the point tolerance `tol_px` spans at most [`MAX_TOLERANCE_MM`] on the
    /// blocks: only then does reading the picture decide between hypotheses as finely as the
    /// drawings' check (docs/rendering.md "Photographic look": at 128 x 120 the 2 px are 2.7 mm).
    pub fn fine_enough(&self, tol_px: f64) -> bool {
        self.px_per_mm * MAX_TOLERANCE_MM >= tol_px
    }

    /// The smallest change across a line one sample must show, gray levels: at least
    /// [`MIN_STEP_LEVELS`], and [`NOISE_MULTIPLE`] times the picture's noise.
    pub fn min_step_levels(&self) -> f64 {
        MIN_STEP_LEVELS.max(NOISE_MULTIPLE * self.noise_levels)
    }
}

/// The picture is read only when the point tolerance spans at most this on the blocks, mm: an
/// answer the picture lets through is placed to within the tolerance, and a catalog block's
/// half height is 3.75 mm, so a tolerance of more than a millimetre could let an answer off
/// by a visible fraction of a block through (a 512 x 480 corner view of the suite has about
/// 3 px per mm; 128 x 120 has 0.75).
pub const MAX_TOLERANCE_MM: f64 = 1.0;
/// Smallest change across a confirmed edge at one sample, gray levels: a crack between flush
/// tops of equal albedo darkens by about 3 levels in the photographic look (noise about 1).
pub const MIN_STEP_LEVELS: f64 = 2.5;
/// A sample's change must reach this many times the picture's noise (each side is the mean of
/// two pixels, so the change has the noise's sigma; 2.5 sigma is crossed by 0.6% of samples
/// of one sign, and [`MIN_SHARE`] asks for most of them).
pub const NOISE_MULTIPLE: f64 = 2.5;
/// Share of the samples along a line that must show the step (or the crack) to confirm it: a
/// contact shadow can even two faces out over part of an edge.
pub const MIN_SHARE: f64 = 0.5;
/// A drawing line the redraw lacks is tolerated when its median step across is under this,
/// gray levels, and no crack runs along it: Chapter VI's threshold of 80 on the smoothed Sobel
/// magnitude (eq. 2.1; a sharp step of h levels gives 4h) answers to steps of 20 levels and
/// more, so a line this weak was not seen by the thesis's threshold: the front end drew it
/// from soft shading (a cast shadow's boundary within one face) or by the faint-edge step.
pub const WEAK_STEP_LEVELS: f64 = 20.0;
/// Lines shorter than this are fragments, px (no sample fits between their end margins).
pub const FRAGMENT_PX: f64 = 2.0 * END_MARGIN_PX + 3.0;
/// Ends of a line skipped by the samples, px (other edges meet there).
pub const END_MARGIN_PX: f64 = 4.0;
/// The line is looked for this far on either side of where it is drawn, px (the exact drawing
/// is of the sharp solid, the picture of a bevelled one).
pub const SEARCH_PX: f64 = 2.0;
/// How much further apart a contact edge's end may lie in the picture than the point
/// tolerance allows, mm: the photographed crack's half width (0.15 mm, docs/rendering.md "Photographic look": faces that touch draw back 0.15 mm each) plus the bevel beside it (0.05 mm) and as
/// much again for the edge fit pulled into the crack's dark middle.
pub const CRACK_ALLOWANCE_MM: f64 = 0.4;

/// What the picture shows across one segment (see the module doc).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct EdgeProfile {
    /// Samples read (1 px apart, [`END_MARGIN_PX`] clear of the ends).
    pub samples: usize,
    /// Where across the segment the step is strongest, px.
    pub step_offset_px: f64,
    /// Median signed step there (the mean of two pixels on the normal's side minus the mean
    /// of two on the other), gray levels.
    pub step_levels: f64,
    /// Share of samples whose step has the median's sign and reaches the minimum.
    pub step_share: f64,
    /// Share of samples where a narrow line darker than both sides by the minimum runs (a
    /// crack), at the offset where it is highest.
    pub crack_share: f64,
    /// The same at the offsets where the two sides are even (median step under the minimum):
    /// a crack between faces alike, not the dark edge of a shadow's core beside its step.
    pub even_crack_share: f64,
}

impl EdgeProfile {
    /// `true` when the picture shows an edge along the segment (step or crack on at least
    /// [`MIN_SHARE`] of the samples).
    pub fn confirms(&self) -> bool {
        self.samples > 0 && self.step_share.max(self.crack_share) >= MIN_SHARE
    }

    /// `true` when the picture shows no block edge along the segment: too short to read, or
    /// no crack between even sides and a median step under [`WEAK_STEP_LEVELS`] (a shadow's
    /// boundary within one face, a penumbra's ramp).
    pub fn is_weak(&self) -> bool {
        self.samples == 0
            || (self.even_crack_share < MIN_SHARE && self.step_levels.abs() < WEAK_STEP_LEVELS)
    }
}

/// The points a segment from `a` along unit `u`, `len` px long, is read at: 1 px apart,
/// [`END_MARGIN_PX`] clear of its ends (other edges meet there).
fn sample_centres(a: DVec2, u: DVec2, len: f64) -> Vec<DVec2> {
    (0..)
        .map(|k| END_MARGIN_PX + f64::from(k))
        .take_while(|&t| t <= len - END_MARGIN_PX)
        .map(|t| a + u * t)
        .collect()
}

/// The offsets across a segment where the line is looked for, px: every 0.5 px within
/// [`SEARCH_PX`] of where it is drawn.
fn search_offsets() -> impl Iterator<Item = f64> {
    let steps = (4.0 * SEARCH_PX) as i32;
    (0..=steps).map(|k| f64::from(k) * 0.5 - SEARCH_PX)
}

/// Reads the picture across segment `a`-`b` (see [`EdgeProfile`]).
pub fn edge_profile(picture: &ViewPicture, a: DVec2, b: DVec2) -> EdgeProfile {
    let len = a.distance(b);
    if len.is_nan() || len < FRAGMENT_PX {
        return EdgeProfile::default();
    }
    let u = (b - a) / len;
    let n = u.perp();
    let min_step = picture.min_step_levels();
    let at = |c: DVec2, d: f64| gray_at(picture.gray, c + n * d);
    let centres = sample_centres(a, u, len);
    let mut best = EdgeProfile::default();
    for o in search_offsets() {
        let mut step = Vec::with_capacity(centres.len());
        let mut crack = Vec::with_capacity(centres.len());
        for &c in &centres {
            let side = |s: f64| Some((at(c, o + s * 1.5)? + at(c, o + s * 2.5)?) / 2.0);
            let (Some(plus), Some(minus)) = (side(1.0), side(-1.0)) else {
                continue;
            };
            step.push(plus - minus);
            let centre = [-0.5, 0.0, 0.5]
                .iter()
                .filter_map(|&d| at(c, o + d))
                .fold(f64::INFINITY, f64::min);
            crack.push(plus.min(minus) - centre);
        }
        if step.is_empty() {
            continue;
        }
        let m = median(&mut step.clone()).unwrap_or(0.0);
        let sign = if m < 0.0 { -1.0 } else { 1.0 };
        let share = |v: &[f64], f: &dyn Fn(f64) -> bool| {
            v.iter().filter(|&&x| f(x)).count() as f64 / v.len() as f64
        };
        let step_share = share(&step, &|s| s * sign >= min_step);
        let crack_share = share(&crack, &|d| d >= min_step);
        let better = (step_share, m.abs()) > (best.step_share, best.step_levels.abs());
        if better || best.samples == 0 {
            best.samples = step.len();
            best.step_offset_px = o;
            best.step_levels = m;
            best.step_share = step_share;
        }
        best.crack_share = best.crack_share.max(crack_share);
        if m.abs() < min_step {
            best.even_crack_share = best.even_crack_share.max(crack_share);
        }
    }
    best
}

/// How far either side of a segment [`flat_across`] reads, px: a band from 1 px to this,
/// wide enough that a blurred step (the varied look blurs by up to 1.5 px) cannot hide in it.
pub const FLAT_BAND_PX: f64 = 5.0;

/// `true` when the picture shows nothing across segment `a`-`b`: at every offset within
/// [`SEARCH_PX`] of it, the median difference between the bands either side (1 px to
/// [`FLAT_BAND_PX`]) is under the picture's smallest step ([`ViewPicture::min_step_levels`]),
/// and no sign of difference reaches it on [`MIN_SHARE`] of the samples. A face and the floor
/// beside it lit to the same gray show this: the edge between them is in the scene but not
/// in the picture (docs/recognizer-pictures.md "Outlines against a floor of the same gray").
/// A segment too short to read is not flat.
pub fn flat_across(picture: &ViewPicture, a: DVec2, b: DVec2) -> bool {
    let len = a.distance(b);
    if len.is_nan() || len < FRAGMENT_PX {
        return false;
    }
    let u = (b - a) / len;
    let n = u.perp();
    let min_step = picture.min_step_levels();
    let band = |c: DVec2, o: f64, s: f64| {
        let v: Vec<f64> = (1..=FLAT_BAND_PX as i32)
            .filter_map(|d| gray_at(picture.gray, c + n * (o + s * f64::from(d))))
            .collect();
        (v.len() == FLAT_BAND_PX as usize).then(|| v.iter().sum::<f64>() / v.len() as f64)
    };
    let centres = sample_centres(a, u, len);
    search_offsets().all(|o| {
        let mut diff: Vec<f64> = centres
            .iter()
            .filter_map(|&c| Some(band(c, o, 1.0)? - band(c, o, -1.0)?))
            .collect();
        if diff.len() * 2 < centres.len() || diff.is_empty() {
            return false;
        }
        let share = |sign: f64| {
            diff.iter().filter(|&&d| d * sign >= min_step).count() as f64 / diff.len() as f64
        };
        let (up, down) = (share(1.0), share(-1.0));
        let m = median(&mut diff).unwrap_or(f64::INFINITY);
        m.abs() < min_step && up < MIN_SHARE && down < MIN_SHARE
    })
}

/// `true` when the picture shows no step along the walk from `from` in unit direction `dir`
/// for `len_px`: at every px the mean of a strip 5 px wide (across the walk) and 3 px long
/// ahead differs from the one behind by less than the picture's smallest step
/// ([`ViewPicture::min_step_levels`]). A face seen whole is one gray from edge to edge; a
/// face another block covers in part is not. A walk too short to read (under 6 px) or leaving
/// the picture is not uniform.
pub fn uniform_along(picture: &ViewPicture, from: DVec2, dir: DVec2, len_px: f64) -> bool {
    if len_px.is_nan() || len_px < 6.0 {
        return false;
    }
    let across = dir.perp();
    let strip = |t: f64, ahead: f64| {
        let mut sum = 0.0;
        for s in 1..=3 {
            for w in -2..=2 {
                let q = from + dir * (t + ahead * f64::from(s)) + across * f64::from(w);
                sum += gray_at(picture.gray, q)?;
            }
        }
        Some(sum / 15.0)
    };
    let min_step = picture.min_step_levels();
    (3..=(len_px - 3.0) as i32).all(|t| {
        let t = f64::from(t);
        match (strip(t, 1.0), strip(t, -1.0)) {
            (Some(ahead), Some(behind)) => (ahead - behind).abs() < min_step,
            _ => false,
        }
    })
}
