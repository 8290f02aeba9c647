//! A sheet as SVG text: the same picture lines and labels as the raster, as vector strokes.
//! Shaded faces need the raster's depth buffer, so a shaded sheet is drawn as lines only here
//! (the CLI refuses `--shade` with an `.svg` output).

use super::font::GLYPH_H;
use super::panel::Sheet;
use super::raster::role_colour;
use std::fmt::Write;

/// The sheet as a standalone SVG document (y flipped: SVG's y grows downward). Coordinates are
/// printed with three decimals, so the same sheet gives the same text.
pub fn sheet_to_svg(sheet: &Sheet) -> String {
    let (w, h) = (sheet.width_px, sheet.height_px);
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}">"#
    );
    let _ = writeln!(s, r#"<rect width="{w}" height="{h}" fill="white"/>"#);
    let fh = f64::from(h);
    for panel in &sheet.panels {
        let r = &panel.rect_px;
        if sheet.panels.len() > 1 {
            let _ = writeln!(
                s,
                r##"<rect x="{:.3}" y="{:.3}" width="{:.3}" height="{:.3}" fill="none" stroke="#a0a0a0"/>"##,
                r.x0_px,
                fh - r.y0_px - r.height_px,
                r.width_px,
                r.height_px
            );
        }
        for line in &panel.lines {
            let [cr, cg, cb] = role_colour(line.role);
            let _ = writeln!(
                s,
                r#"<line x1="{:.3}" y1="{:.3}" x2="{:.3}" y2="{:.3}" stroke="rgb({cr},{cg},{cb})" stroke-width="1"/>"#,
                line.a_px.x,
                fh - line.a_px.y,
                line.b_px.x,
                fh - line.b_px.y
            );
        }
        let size = f64::from(GLYPH_H) * 1.5;
        for (k, text) in panel.label.iter().enumerate() {
            let _ = writeln!(
                s,
                r#"<text x="{:.3}" y="{:.3}" font-family="monospace" font-size="{size:.1}" text-anchor="end">{}</text>"#,
                r.x0_px + r.width_px - 4.0,
                fh - r.y0_px - r.height_px + 4.0 + (k as f64 + 1.0) * size * 1.2,
                escape(text)
            );
        }
    }
    s.push_str("</svg>\n");
    s
}

/// `text` with XML's special characters escaped.
fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::{DVec2, DVec3};
    use crate::view::panel::{Panel, PictureLine, PixelRect, Role};
    use crate::view::ViewParams;

    #[test]
    fn lines_are_flipped_to_svg_y_down_and_coloured_by_role() {
        let sheet = Sheet {
            width_px: 100,
            height_px: 50,
            panels: vec![Panel {
                rect_px: PixelRect {
                    x0_px: 0.0,
                    y0_px: 0.0,
                    width_px: 100.0,
                    height_px: 50.0,
                },
                params: ViewParams {
                    from_mm: DVec3::ZERO,
                    at_mm: DVec3::Z,
                    up: DVec3::Y,
                    view_angle_deg: 60.0,
                },
                lines: vec![PictureLine {
                    a_px: DVec2::new(10.0, 0.0),
                    b_px: DVec2::new(20.0, 50.0),
                    role: Role::Reconstruction,
                }],
                faces: Vec::new(),
                clipped_lines: 0,
                rejected_lines: 0,
                label: vec!["AT <0>".to_string()],
            }],
        };
        let svg = sheet_to_svg(&sheet);
        assert!(svg
            .contains(r#"x1="10.000" y1="50.000" x2="20.000" y2="0.000" stroke="rgb(220,40,40)""#));
        assert!(svg.contains("AT &lt;0&gt;"));
        assert!(svg.trim_end().ends_with("</svg>"));
    }
}
