//! A sheet into pixels: faces filled through a per-pixel depth buffer, lines by Bresenham,
//! labels in the bitmap font. Everything is integer or exactly repeatable floating point, so
//! the same sheet gives the same bytes (the goldens of Figures 6.7-6.12 are exact).

use super::font::{text_pixels, text_width_px, GLYPH_H};
use super::panel::{Panel, PictureFace, Role, Sheet};
use crate::geom::{newell_vector, DVec2, DVec3};
use image::{Rgb, RgbImage};

/// Sheet background (white, like the thesis's printed figures).
const BACKGROUND: Rgb<u8> = Rgb([255, 255, 255]);
/// Label text and viewport borders.
const INK: Rgb<u8> = Rgb([0, 0, 0]);
/// Viewport borders on a sheet of several.
const BORDER: Rgb<u8> = Rgb([160, 160, 160]);

/// The line colour of a role: black for a plain model, blue for the truth and red for the
/// reconstruction of an overlay.
pub fn role_colour(role: Role) -> [u8; 3] {
    match role {
        Role::Model => [0, 0, 0],
        Role::Truth => [30, 90, 220],
        Role::Reconstruction => [220, 40, 40],
    }
}

/// The full-intensity fill colour of a role's shaded faces.
fn fill_colour(role: Role) -> [f64; 3] {
    match role {
        Role::Model => [235.0, 235.0, 235.0],
        Role::Truth => [170.0, 200.0, 255.0],
        Role::Reconstruction => [255.0, 185.0, 185.0],
    }
}

/// Draws a sheet into an RGB image (row 0 at the top; picture y up is flipped here).
pub fn rasterize_sheet(sheet: &Sheet) -> RgbImage {
    let mut img = RgbImage::from_pixel(sheet.width_px, sheet.height_px, BACKGROUND);
    for panel in &sheet.panels {
        let bounds = raster_bounds(panel, sheet.height_px);
        fill_faces(&mut img, panel, bounds);
        for line in &panel.lines {
            let c = Rgb(role_colour(line.role));
            draw_line(&mut img, bounds, sheet.height_px, (line.a_px, line.b_px), c);
        }
        draw_label(&mut img, panel, bounds);
        if sheet.panels.len() > 1 {
            draw_border(&mut img, bounds);
        }
    }
    img
}

/// A panel's raster pixel range: columns x0..x1 and rows r0..r1 (exclusive ends).
#[derive(Debug, Clone, Copy)]
struct RasterBounds {
    x0: u32,
    x1: u32,
    r0: u32,
    r1: u32,
}

fn raster_bounds(panel: &Panel, sheet_h: u32) -> RasterBounds {
    let r = &panel.rect_px;
    let top = f64::from(sheet_h) - (r.y0_px + r.height_px);
    RasterBounds {
        x0: r.x0_px as u32,
        x1: (r.x0_px + r.width_px) as u32,
        r0: top as u32,
        r1: (top + r.height_px) as u32,
    }
}

/// The raster pixel (column, row) holding picture point `p`, clamped into `b`.
fn raster_of(p: DVec2, b: RasterBounds, sheet_h: u32) -> (i64, i64) {
    let col = (p.x.floor() as i64).clamp(i64::from(b.x0), i64::from(b.x1) - 1);
    let row =
        ((f64::from(sheet_h) - p.y).floor() as i64).clamp(i64::from(b.r0), i64::from(b.r1) - 1);
    (col, row)
}

/// Bresenham's line between the pixels holding the two picture points.
fn draw_line(
    img: &mut RgbImage,
    b: RasterBounds,
    sheet_h: u32,
    (p, q): (DVec2, DVec2),
    c: Rgb<u8>,
) {
    let (mut x, mut y) = raster_of(p, b, sheet_h);
    let (x1, y1) = raster_of(q, b, sheet_h);
    let (dx, dy) = ((x1 - x).abs(), -(y1 - y).abs());
    let (sx, sy) = ((x1 - x).signum(), (y1 - y).signum());
    let mut err = dx + dy;
    loop {
        img.put_pixel(x as u32, y as u32, c);
        if x == x1 && y == y1 {
            break;
        }
        let e2 = 2 * err;
        if e2 >= dy {
            err += dy;
            x += sx;
        }
        if e2 <= dx {
            err += dx;
            y += sy;
        }
    }
}

/// Fills the panel's faces, nearest first per pixel: the depth of a pixel's ray (x/z, y/z, 1)
/// where it meets each face's plane, compared exactly per pixel centre.
fn fill_faces(img: &mut RgbImage, panel: &Panel, b: RasterBounds) {
    if panel.faces.is_empty() {
        return;
    }
    let (w, h) = ((b.x1 - b.x0) as usize, (b.r1 - b.r0) as usize);
    let mut depth = vec![f64::INFINITY; w * h];
    let (centre, half) = panel.window();
    let sheet_h = f64::from(img.height());
    for face in &panel.faces {
        let Some(plane) = plane_of(&face.canonical) else {
            continue;
        };
        let poly: Vec<DVec2> = face
            .canonical
            .iter()
            .map(|p| panel.picture_px(*p))
            .collect();
        let colour = shade(face);
        for row in b.r0..b.r1 {
            for col in b.x0..b.x1 {
                let p = DVec2::new(f64::from(col) + 0.5, sheet_h - f64::from(row) - 0.5);
                if !inside_convex(&poly, p) {
                    continue;
                }
                let s = (p - centre) / half;
                let ray = DVec3::new(s.x, s.y, 1.0);
                let z = plane.1 / plane.0.dot(ray);
                let k = (row - b.r0) as usize * w + (col - b.x0) as usize;
                if z > 0.0 && z < depth[k] {
                    depth[k] = z;
                    img.put_pixel(col, row, colour);
                }
            }
        }
    }
}

/// The plane (n, d: n·p = d) of a canonical polygon, `None` when degenerate or through the eye.
fn plane_of(poly: &[DVec3]) -> Option<(DVec3, f64)> {
    let n = newell_vector(poly);
    let d = n.dot(*poly.first()?);
    (n.length() > 0.0 && d != 0.0).then_some((n, d))
}

/// `true` when `p` lies inside (or on) the convex polygon, whichever way it winds.
fn inside_convex(poly: &[DVec2], p: DVec2) -> bool {
    let (mut pos, mut neg) = (false, false);
    for (i, a) in poly.iter().enumerate() {
        let e = poly[(i + 1) % poly.len()] - *a;
        let c = e.perp_dot(p - *a);
        pos |= c > 0.0;
        neg |= c < 0.0;
    }
    !(pos && neg)
}

fn shade(face: &PictureFace) -> Rgb<u8> {
    let f = fill_colour(face.role);
    Rgb(f.map(|c| (c * face.intensity).round().clamp(0.0, 255.0) as u8))
}

/// The label, right-aligned in the panel's top right-hand corner; font pixels twice as large
/// on panels of 400 px and more.
fn draw_label(img: &mut RgbImage, panel: &Panel, b: RasterBounds) {
    let scale = if b.x1 - b.x0 >= 400 { 2 } else { 1 };
    let margin = 4 * scale;
    for (k, text) in panel.label.iter().enumerate() {
        let width = text_width_px(text, scale);
        let Some(left) = (b.x1 - margin).checked_sub(width) else {
            continue;
        };
        let top = b.r0 + margin + k as u32 * (GLYPH_H + 2) * scale;
        for (dx, dy) in text_pixels(text, scale) {
            let (x, y) = (left + dx, top + dy);
            if x >= b.x0 && x < b.x1 && y < b.r1 {
                img.put_pixel(x, y, INK);
            }
        }
    }
}

fn draw_border(img: &mut RgbImage, b: RasterBounds) {
    for x in b.x0..b.x1 {
        img.put_pixel(x, b.r0, BORDER);
        img.put_pixel(x, b.r1 - 1, BORDER);
    }
    for y in b.r0..b.r1 {
        img.put_pixel(b.x0, y, BORDER);
        img.put_pixel(b.x1 - 1, y, BORDER);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::view::panel::PixelRect;
    use crate::view::{PictureLine, ViewParams};

    fn panel(lines: Vec<PictureLine>, faces: Vec<PictureFace>) -> Sheet {
        Sheet {
            width_px: 64,
            height_px: 64,
            panels: vec![Panel {
                rect_px: PixelRect {
                    x0_px: 0.0,
                    y0_px: 0.0,
                    width_px: 64.0,
                    height_px: 64.0,
                },
                params: ViewParams {
                    from_mm: DVec3::ZERO,
                    at_mm: DVec3::Z,
                    up: DVec3::Y,
                    view_angle_deg: 60.0,
                },
                lines,
                faces,
                clipped_lines: 0,
                rejected_lines: 0,
                label: Vec::new(),
            }],
        }
    }

    #[test]
    fn a_horizontal_line_sets_one_row_in_picture_y_up() {
        let line = PictureLine {
            a_px: DVec2::new(10.5, 5.5),
            b_px: DVec2::new(20.5, 5.5),
            role: Role::Model,
        };
        let img = rasterize_sheet(&panel(vec![line], Vec::new()));
        // Picture y 5.5 is raster row 64 - 6 = 58.
        let dark: Vec<(u32, u32)> = img
            .enumerate_pixels()
            .filter(|p| p.2 .0 != [255, 255, 255])
            .map(|p| (p.0, p.1))
            .collect();
        assert_eq!(dark.len(), 11);
        assert!(dark.iter().all(|&(x, y)| y == 58 && (10..=20).contains(&x)));
    }

    #[test]
    fn a_line_past_the_panel_is_clamped_to_its_edge() {
        let line = PictureLine {
            a_px: DVec2::new(-10.0, 70.0),
            b_px: DVec2::new(80.0, -20.0),
            role: Role::Truth,
        };
        let img = rasterize_sheet(&panel(vec![line], Vec::new()));
        assert_eq!(img.get_pixel(0, 0).0, role_colour(Role::Truth));
        assert_eq!(img.get_pixel(63, 63).0, role_colour(Role::Truth));
    }

    #[test]
    fn the_nearer_face_wins_the_depth_test_in_either_order() {
        // Two squares covering the window centre, at depth 0.5 (bright) and 0.8 (dark).
        let square = |z: f64, intensity: f64| PictureFace {
            canonical: [(-0.2, -0.2), (0.2, -0.2), (0.2, 0.2), (-0.2, 0.2)]
                .iter()
                .map(|&(x, y)| DVec3::new(x * z, y * z, z))
                .collect(),
            intensity,
            role: Role::Model,
        };
        for faces in [
            vec![square(0.5, 1.0), square(0.8, 0.5)],
            vec![square(0.8, 0.5), square(0.5, 1.0)],
        ] {
            let img = rasterize_sheet(&panel(Vec::new(), faces));
            assert_eq!(img.get_pixel(32, 32).0, [235, 235, 235]);
            assert_eq!(img.get_pixel(2, 2).0, [255, 255, 255]);
        }
    }
}
