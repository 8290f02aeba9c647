//! The SVG drawn over a view's picture: one group per overlay, shown or hidden by the page's
//! toggles (the class `ov-<name>`). Picture coordinates are px with y up from the bottom-left
//! corner (`geom`); SVG's y runs down, so y becomes `height - y`.

use super::{escape_html, ReportView};
use crate::drawing::{LineDrawing, LineKind};
use std::fmt::Write as _;

/// The overlays of a scene page, in toggle order: (class suffix, label).
pub const OVERLAYS: [(&str, &str); 6] = [
    ("truth", "exact lines by kind"),
    ("codes", "vertices: six-bit code, junction"),
    ("vision", "vision lines"),
    ("answer", "answer: explained / unexplained"),
    ("ids", "block ids"),
    ("depth", "depth"),
];

/// `M x y L x y ...` for `lines` of `d` (indices), in a picture `height_px` high.
fn path_of(d: &LineDrawing, lines: impl Iterator<Item = usize>, height_px: f64) -> String {
    let mut p = String::new();
    for k in lines {
        let Some(&[a, b]) = d.lines.get(k) else {
            continue;
        };
        let (Some(pa), Some(pb)) = (d.points.get(a), d.points.get(b)) else {
            continue;
        };
        let _ = write!(
            p,
            "M{:.1} {:.1}L{:.1} {:.1}",
            pa.x,
            height_px - pa.y,
            pb.x,
            height_px - pb.y
        );
    }
    p
}

fn path_element(class: &str, d: String) -> String {
    if d.is_empty() {
        return String::new();
    }
    format!("<path class=\"{class}\" d=\"{d}\"/>")
}

fn kind_name(kind: LineKind) -> &'static str {
    match kind {
        LineKind::Boundary => "boundary",
        LineKind::Convex => "convex",
        LineKind::Concave => "concave",
        LineKind::Crack => "crack",
    }
}

/// The exact drawing's lines, one path per kind (`k-boundary`, ...); lines of unknown kind as
/// `k-line`.
fn truth_group(d: &LineDrawing, h: f64) -> String {
    let mut g = String::from("<g class=\"ov ov-truth\">");
    for kind in [
        LineKind::Boundary,
        LineKind::Convex,
        LineKind::Concave,
        LineKind::Crack,
    ] {
        let lines = (0..d.lines.len()).filter(|&k| d.kinds.get(k) == Some(&kind));
        g.push_str(&path_element(
            &format!("k-{}", kind_name(kind)),
            path_of(d, lines, h),
        ));
    }
    let unknown = (0..d.lines.len()).filter(|&k| d.kinds.get(k).is_none());
    g.push_str(&path_element("k-line", path_of(d, unknown, h)));
    g.push_str("</g>");
    g
}

/// Every vertex of the exact drawing with its six-bit code and junction.
fn codes_group(d: &LineDrawing, h: f64) -> String {
    let mut g = String::from("<g class=\"ov ov-codes\">");
    for (i, p) in d.points.iter().enumerate() {
        let code = d.codes.get(i).map_or(0, |c| c.0);
        let junction = d
            .junctions
            .get(i)
            .and_then(|j| serde_json::to_value(j).ok())
            .and_then(|v| v.as_str().map(str::to_string))
            .unwrap_or_default();
        let (x, y) = (p.x, h - p.y);
        let _ = write!(
            g,
            "<circle cx=\"{x:.1}\" cy=\"{y:.1}\" r=\"3\"/><text x=\"{:.1}\" y=\"{:.1}\">{code} {}</text>",
            x + 4.0,
            y - 4.0,
            escape_html(&junction)
        );
    }
    g.push_str("</g>");
    g
}

/// The SVG over one view's picture with every overlay group (the picture layers `ids` and
/// `depth` are images of the page, not part of it).
pub(super) fn view_svg(view: &ReportView) -> String {
    let [w, h] = view.size_px;
    let hf = f64::from(h);
    let mut s = format!(
        "<svg class=\"overlay\" xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 {w} {h}\" width=\"{w}\" height=\"{h}\">"
    );
    s.push_str(&truth_group(&view.truth, hf));
    s.push_str(&codes_group(&view.truth, hf));
    if let Some(seen) = &view.seen {
        let o = &seen.observed;
        s.push_str("<g class=\"ov ov-vision\">");
        s.push_str(&path_element("vision", path_of(o, 0..o.lines.len(), hf)));
        s.push_str("</g><g class=\"ov ov-answer\">");
        let a = &seen.answer;
        let drawn = (0..a.lines.len()).filter(|k| !seen.extra_lines.contains(k));
        s.push_str(&path_element("a-drawn", path_of(a, drawn, hf)));
        s.push_str(&path_element(
            "a-extra",
            path_of(a, seen.extra_lines.iter().copied(), hf),
        ));
        let unexplained = seen.unexplained_lines.iter().copied();
        s.push_str(&path_element("a-unexplained", path_of(o, unexplained, hf)));
        s.push_str("</g>");
    }
    s.push_str("</svg>");
    s
}

/// A drawing alone on white, `class` naming its colour (`truth-lines`, `answer-lines`): the
/// truth and the reconstruction side by side.
pub(super) fn drawing_svg(d: &LineDrawing, size_px: [u32; 2], class: &str) -> String {
    let [w, h] = size_px;
    format!(
        "<svg class=\"drawing\" xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 {w} {h}\" width=\"{w}\" height=\"{h}\">{}</svg>",
        path_element(class, path_of(d, 0..d.lines.len(), f64::from(h)))
    )
}
