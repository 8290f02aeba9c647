//! Writing rendered views to a directory, the layout `blockworld render` and every dataset
//! scene share: `view_<v>.png`, `depth_<v>.png`, `ids_<v>.png`, `lines_<v>.json`,
//! `camera_<v>.json`, each written atomically.
//!
//! Formats (docs/rendering.md "Views and ground truth"):
//! * `view_<v>.png`: 8-bit grayscale picture.
//! * `depth_<v>.png`: 16-bit grayscale, depth along the optical axis in
//!   1 / [`DEPTH_UNITS_PER_MM`] mm steps, 0 = nothing seen.
//! * `ids_<v>.png`: 16-bit grayscale, block index + 1, 0 = floor or background.
//! * `lines_<v>.json`: [`crate::drawing::LineDrawing::to_json`].
//! * `camera_<v>.json`: the serde [`crate::camera::Camera`] plus `depth_units_per_mm` and
//!   `picture`, the picture-coordinate convention in words.

use crate::camera::camera_json;
use crate::io::{write_atomic_with, FileSync};
use crate::render::RenderedView;
use sha2::{Digest, Sha256};
use std::path::Path;

/// A file written: its name inside the directory and the sha256 of its bytes (hex).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct WrittenFile {
    /// File name inside the output directory.
    pub name: String,
    /// Lower-case hex sha256 of the bytes written.
    pub sha256: String,
}

/// Writes every view's files into `dir` (which must exist), atomically, in a fixed order:
/// per view `view`, `depth`, `ids`, `lines`, `camera`.
pub fn write_rendered_views(
    dir: &Path,
    views: &[RenderedView],
) -> std::io::Result<Vec<WrittenFile>> {
    write_rendered_views_with(dir, views, FileSync::EveryFile)
}

/// [`write_rendered_views`] with the files' sync chosen by `sync` (datasets, whose resume
/// re-hashes every file, skip the per-file sync by default).
pub fn write_rendered_views_with(
    dir: &Path,
    views: &[RenderedView],
    sync: FileSync,
) -> std::io::Result<Vec<WrittenFile>> {
    write_rendered_views_prefixed(dir, "", views, sync)
}

/// [`write_rendered_views_with`] with `prefix` before every file name (`f0003_` writes
/// `f0003_view_ne.png`, ...): the rendered frames of a trajectory
/// (docs/stability.md "Rendered frames"). The returned names carry the prefix.
pub fn write_rendered_views_prefixed(
    dir: &Path,
    prefix: &str,
    views: &[RenderedView],
    sync: FileSync,
) -> std::io::Result<Vec<WrittenFile>> {
    let mut written = Vec::with_capacity(views.len() * 5);
    for v in views {
        let name = v.camera.view.name();
        let files = [
            (
                format!("{prefix}view_{name}.png"),
                encode_png_gray8(&v.gray)?,
            ),
            (
                format!("{prefix}depth_{name}.png"),
                encode_png_depth(&v.depth)?,
            ),
            (format!("{prefix}ids_{name}.png"), encode_png_ids(&v.ids)?),
            (
                format!("{prefix}lines_{name}.json"),
                v.lines.to_json().into_bytes(),
            ),
            (
                format!("{prefix}camera_{name}.json"),
                camera_json(&v.camera).into_bytes(),
            ),
        ];
        for (file, bytes) in files {
            write_atomic_with(&dir.join(&file), &bytes, sync)?;
            written.push(WrittenFile {
                name: file,
                sha256: hex::encode(Sha256::digest(&bytes)),
            });
        }
    }
    Ok(written)
}

/// PNG bytes of an 8-bit gray picture (`view_<v>.png`): fast compression, the adaptive filter
/// (each row filtered the way that makes it smallest; a rendered picture has shading, seams and
/// optional noise, and no single filter fits every one of them).
pub fn encode_png_gray8(img: &image::GrayImage) -> std::io::Result<Vec<u8>> {
    encode_png(
        img.as_raw(),
        [img.width(), img.height()],
        png::ColorType::Grayscale,
        png::BitDepth::Eight,
        png::Filter::Adaptive,
    )
}

/// PNG bytes of an 8-bit RGB image (the viewer's pictures): fast compression, adaptive filter.
pub fn encode_png_rgb8(img: &image::RgbImage) -> std::io::Result<Vec<u8>> {
    encode_png(
        img.as_raw(),
        [img.width(), img.height()],
        png::ColorType::Rgb,
        png::BitDepth::Eight,
        png::Filter::Adaptive,
    )
}

/// PNG bytes of a picture of flat regions (`blockworld report`'s depth and id pictures): fast
/// compression and the Up filter on every row, which predicts a flat region exactly and costs
/// one fifth of the adaptive choice's filtering.
pub fn encode_png_flat(img: &image::DynamicImage) -> std::io::Result<Vec<u8>> {
    let (color, samples) = match img {
        image::DynamicImage::ImageLuma8(g) => (png::ColorType::Grayscale, g.as_raw()),
        image::DynamicImage::ImageRgb8(c) => (png::ColorType::Rgb, c.as_raw()),
        _ => {
            return Err(std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                "encode_png_flat takes 8-bit gray or RGB",
            ))
        }
    };
    encode_png(
        samples,
        [img.width(), img.height()],
        color,
        png::BitDepth::Eight,
        png::Filter::Up,
    )
}

/// PNG bytes of a depth map (`depth_<v>.png`, 16-bit): the Paeth filter on every row. Depth
/// is planar per face, so Paeth predicts it as well as the adaptive choice (on the 400 depth
/// maps of `generate --count 100`: 0.2% larger files) at about half the encoding time (docs/benchmarks.md
/// "Benchmarks").
pub fn encode_png_depth(img: &crate::render::Gray16Image) -> std::io::Result<Vec<u8>> {
    encode_png_gray16_with(img, png::Filter::Paeth)
}

/// PNG bytes of an id map (`ids_<v>.png`, 16-bit): the Up filter on every row. Ids are flat
/// regions whose rows mostly repeat the row above, which Up turns into zeros (on the 400 id maps
/// of `generate --count 100`: 2.6% larger files than the adaptive choice) at under half the
/// encoding time (docs/benchmarks.md "Benchmarks").
pub fn encode_png_ids(img: &crate::render::Gray16Image) -> std::io::Result<Vec<u8>> {
    encode_png_gray16_with(img, png::Filter::Up)
}

/// PNG bytes of any other 16-bit gray image (the smoothed edge magnitude of `blockworld
/// edges`): fast compression, adaptive filter.
pub fn encode_png_gray16(img: &crate::render::Gray16Image) -> std::io::Result<Vec<u8>> {
    encode_png_gray16_with(img, png::Filter::Adaptive)
}

/// PNG bytes of a 16-bit gray image with `filter`: its samples in PNG's big-endian order (one
/// vectorized pass; `image`'s encoder reorders them byte by byte), then encoded.
fn encode_png_gray16_with(
    img: &crate::render::Gray16Image,
    filter: png::Filter,
) -> std::io::Result<Vec<u8>> {
    let big_endian: Vec<u16> = img.as_raw().iter().map(|v| v.to_be()).collect();
    encode_png(
        bytemuck::cast_slice(&big_endian),
        [img.width(), img.height()],
        png::ColorType::Grayscale,
        png::BitDepth::Sixteen,
        filter,
    )
}

/// PNG bytes of `samples` (rows of `size_px[0]` pixels, 16-bit samples big-endian) with the
/// `png` crate's fast compression (fdeflate) and the given row filter.
fn encode_png(
    samples: &[u8],
    size_px: [u32; 2],
    color: png::ColorType,
    depth: png::BitDepth,
    filter: png::Filter,
) -> std::io::Result<Vec<u8>> {
    let mut out = Vec::with_capacity(samples.len() / 8);
    let mut encoder = png::Encoder::new(&mut out, size_px[0], size_px[1]);
    encoder.set_color(color);
    encoder.set_depth(depth);
    // The compression sets a default filter of its own: the filter goes second.
    encoder.set_compression(png::Compression::Fast);
    encoder.set_filter(filter);
    let mut writer = encoder.write_header().map_err(std::io::Error::other)?;
    writer
        .write_image_data(samples)
        .map_err(std::io::Error::other)?;
    writer.finish().map_err(std::io::Error::other)?;
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::{parse_camera_json, Camera, CameraOptions, CornerView};
    use crate::drawing::LineDrawing;
    use crate::render::Gray16Image;
    use image::{GrayImage, Luma};

    fn view() -> RenderedView {
        let camera = Camera::frame(
            &[glam::DVec3::ZERO, glam::DVec3::ONE * 15.0],
            CornerView::Se,
            &CameraOptions {
                size_px: [7, 5],
                ..Default::default()
            },
        );
        let mut depth = Gray16Image::new(7, 5);
        depth.put_pixel(1, 2, Luma([40_000]));
        let mut ids = Gray16Image::new(7, 5);
        ids.put_pixel(6, 4, Luma([3]));
        RenderedView {
            camera,
            gray: GrayImage::from_fn(7, 5, |x, y| Luma([(x * 30 + y) as u8])),
            depth,
            ids,
            lines: LineDrawing::default(),
            towards_lights: Vec::new(),
            edge_radius_mm: 0.0,
        }
    }

    #[test]
    fn writes_five_files_per_view_that_decode_to_the_same_pixels() {
        let dir = tempfile::tempdir().unwrap();
        let v = view();
        let written = write_rendered_views(dir.path(), std::slice::from_ref(&v)).unwrap();
        let names: Vec<&str> = written.iter().map(|w| w.name.as_str()).collect();
        assert_eq!(
            names,
            [
                "view_se.png",
                "depth_se.png",
                "ids_se.png",
                "lines_se.json",
                "camera_se.json"
            ]
        );
        for w in &written {
            let bytes = std::fs::read(dir.path().join(&w.name)).unwrap();
            assert_eq!(hex::encode(Sha256::digest(&bytes)), w.sha256);
        }
        let gray = image::open(dir.path().join("view_se.png")).unwrap();
        assert_eq!(gray.color(), image::ColorType::L8);
        assert_eq!(gray.into_luma8(), v.gray);
        let depth = image::open(dir.path().join("depth_se.png")).unwrap();
        assert_eq!(depth.color(), image::ColorType::L16);
        assert_eq!(depth.into_luma16(), v.depth);
        let ids = image::open(dir.path().join("ids_se.png"))
            .unwrap()
            .into_luma16();
        assert_eq!(ids, v.ids);
        let cam: serde_json::Value =
            serde_json::from_slice(&std::fs::read(dir.path().join("camera_se.json")).unwrap())
                .unwrap();
        assert_eq!(cam["depth_units_per_mm"], 16.0);
        assert_eq!(cam["view"], "se");
        assert!(cam["picture"].as_str().unwrap().contains("y up"));
        let back = parse_camera_json(&cam.to_string()).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(back, v.camera);
        // Nothing else (no temporaries) in the directory.
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 5);
    }
}
