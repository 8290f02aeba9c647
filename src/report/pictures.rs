//! The depth and id pictures made visible: the 16-bit `depth_<v>.png` and `ids_<v>.png` hold
//! 1/16 mm steps and block index + 1, which a browser shows as black (it keeps the high byte).

use image::{GrayImage, RgbImage};

/// Twelve colours that tell neighbouring blocks apart (block index modulo 12).
const ID_COLOURS: [[u8; 3]; 12] = [
    [230, 25, 75],
    [60, 180, 75],
    [255, 225, 25],
    [0, 130, 200],
    [245, 130, 48],
    [145, 30, 180],
    [70, 240, 240],
    [240, 50, 230],
    [210, 245, 60],
    [250, 190, 212],
    [0, 128, 128],
    [170, 110, 40],
];

/// The id picture `ids` (`width` x `height`, row-major, block index + 1, 0 = none) in colour:
/// block `i` in `ID_COLOURS[i % 12]`, nothing black. `None` when the sizes disagree.
pub fn ids_picture(width: u32, height: u32, ids: &[u16]) -> Option<RgbImage> {
    if ids.len() != (width as usize) * (height as usize) {
        return None;
    }
    let rgb: Vec<u8> = ids
        .iter()
        .flat_map(|&id| match id {
            0 => [0, 0, 0],
            id => ID_COLOURS[usize::from(id - 1) % ID_COLOURS.len()],
        })
        .collect();
    RgbImage::from_raw(width, height, rgb)
}

/// The depth picture `depth` (1/16 mm steps, 0 = nothing) in gray: the nearest depth white,
/// the farthest 40, nothing black. `None` when the sizes disagree.
pub fn depth_picture(width: u32, height: u32, depth: &[u16]) -> Option<GrayImage> {
    if depth.len() != (width as usize) * (height as usize) {
        return None;
    }
    let seen = depth.iter().copied().filter(|&d| d > 0);
    let (lo, hi) = seen.fold((u16::MAX, 0), |(lo, hi), d| (lo.min(d), hi.max(d)));
    let span = u32::from(hi.saturating_sub(lo)).max(1);
    let gray: Vec<u8> = depth
        .iter()
        .map(|&d| match d {
            0 => 0,
            // 255 - 215 (d - lo) / span, rounded to the nearest level in integers.
            d => (255 - (215 * u32::from(d - lo) + span / 2) / span) as u8,
        })
        .collect();
    GrayImage::from_raw(width, height, gray)
}
