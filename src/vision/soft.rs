//! Step 2a of the vision front end: lines along soft shading are dropped (docs/rendering.md "Photographic look").
//!
//! The Sobel operator (eq. 2.1) answers to any change of brightness, and Chapter VI's threshold
//! to any change strong enough. In a camera picture a block's soft shadow on a neighbour is such
//! a change: its penumbra darkens the face over tens of pixels, and near a contact its
//! boundary can run along a block axis and be fitted as a line. A block's edge is a step (two
//! faces meet; the sensor's blur spreads it over a pixel or two) or a thin line (a bevel's
//! highlight, a crack, line art's ink). [`drop_soft_edges`] reads the picture across each line:
//! the largest change over 2 px near the line against the change from 7 px on one side to 7 px
//! on the other. A step or a thin line changes by most of its contrast within 2 px
//! ([`STEP_SHARPNESS_MIN`] or more); a penumbra's ramp does not.

use super::lines::{gray_at, FittedLine};
use image::GrayImage;

/// A line is kept when its sharpness (the median over its samples of the largest 2 px change
/// near it over the change across 14 px) is at least this. A linear ramp wider than 14 px gives
/// 1/7; a step blurred by the sensor (sigma 0.7 px) about 0.9.
pub const STEP_SHARPNESS_MIN: f64 = 0.4;
/// Changes across a line smaller than this, gray levels, are not read as a ramp (a sample on a
/// thin line between faces of equal brightness).
const FLAT_ACROSS_LEVELS: f64 = 6.0;
/// Samples are taken every this many px along the line, away from its ends.
const SAMPLE_STEP_PX: f64 = 2.0;
/// Ends of a line skipped by the samples, as a share of its length (junctions).
const END_SHARE: f64 = 0.2;

/// The sharpness of `l` in `gray` (see the module doc); `None` when no sample lies in the
/// picture.
pub fn step_sharpness(gray: &GrayImage, l: &FittedLine) -> Option<f64> {
    let n = l.direction.perp();
    let len = l.length_px();
    let mut ratios: Vec<f64> = Vec::new();
    let mut t = END_SHARE * len;
    while t <= (1.0 - END_SHARE) * len {
        let c = l.from_px + (l.to_px - l.from_px) * (t / len.max(1e-9));
        let at = |d: f64| gray_at(gray, c + n * d);
        let across = match (at(-7.0), at(7.0)) {
            (Some(a), Some(b)) => (b - a).abs(),
            _ => {
                t += SAMPLE_STEP_PX;
                continue;
            }
        };
        if across < FLAT_ACROSS_LEVELS {
            ratios.push(1.0);
            t += SAMPLE_STEP_PX;
            continue;
        }
        // The levels at -3..=3 px across, each read once; the largest change over 2 px.
        let level: [Option<f64>; 7] = std::array::from_fn(|j| at(j as f64 - 3.0));
        let near = level
            .windows(3)
            .filter_map(|w| Some((w[2]? - w[0]?).abs()))
            .fold(0.0, f64::max);
        ratios.push(near / across);
        t += SAMPLE_STEP_PX;
    }
    if ratios.is_empty() {
        return None;
    }
    ratios.sort_by(f64::total_cmp);
    Some(ratios[ratios.len() / 2])
}

/// `lines` without those along soft shading: sharpness below [`STEP_SHARPNESS_MIN`]. Lines
/// too short to sample are kept.
pub fn drop_soft_edges(gray: &GrayImage, lines: &[FittedLine]) -> Vec<FittedLine> {
    lines
        .iter()
        .filter(|l| step_sharpness(gray, l).is_none_or(|s| s >= STEP_SHARPNESS_MIN))
        .copied()
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::drawing::EdgeAxis;
    use crate::geom::DVec2;
    use image::Luma;

    fn vertical_line(x: f64) -> FittedLine {
        FittedLine {
            axis: EdgeAxis::BLOCK_AXES[0],
            centroid_px: DVec2::new(x, 30.0),
            direction: DVec2::Y,
            from_px: DVec2::new(x, 10.0),
            to_px: DVec2::new(x, 50.0),
            support: 40,
            rms_px: 0.3,
        }
    }

    /// A 60 x 60 picture whose brightness depends on x only.
    fn picture(f: impl Fn(f64) -> f64) -> GrayImage {
        GrayImage::from_fn(60, 60, |x, _| Luma([f(x as f64 + 0.5).round() as u8]))
    }

    #[test]
    fn a_step_and_a_thin_line_are_sharp_a_penumbra_is_not() {
        let line = vertical_line(30.0);
        let step = picture(|x| if x < 30.0 { 80.0 } else { 150.0 });
        let ink = picture(|x| if (x - 30.0).abs() < 1.0 { 20.0 } else { 120.0 });
        // A shadow's penumbra: 150 down to 80 over 30 px.
        let ramp = picture(|x| (150.0 - 70.0 * (x - 15.0) / 30.0).clamp(80.0, 150.0));
        assert!(step_sharpness(&step, &line).unwrap() > 0.9);
        assert!(step_sharpness(&ink, &line).unwrap() >= 1.0);
        assert!(step_sharpness(&ramp, &line).unwrap() < STEP_SHARPNESS_MIN);
        assert_eq!(drop_soft_edges(&step, &[line]).len(), 1);
        assert_eq!(drop_soft_edges(&ramp, &[line]).len(), 0);
    }
}
