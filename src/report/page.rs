//! A scene's page: its views with the overlay toggles, the recognizer's answer and score, the
//! CSG tree and blocks, the truth beside the reconstruction, and links to its files.

use super::overlay::{drawing_svg, view_svg, OVERLAYS};
use super::{escape_html, Outcome, ReportScene, ReportView};
use crate::scene::{CsgNode, Reconstruction};
use crate::score::SceneResult;
use std::fmt::Write as _;

/// The page `<id>/index.html` of `scene` (its pictures beside it in the same folder).
pub fn scene_page(scene: &ReportScene) -> String {
    let s = &scene.summary;
    let mut h = format!(
        "<!doctype html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>{id}: blockworld report</title>\n<link rel=\"stylesheet\" href=\"../style.css\">\n</head>\n<body class=\"scene show-{first}\">\n",
        id = escape_html(&s.id),
        first = if scene.recon.is_some() { "answer" } else { "truth" }
    );
    h.push_str(&nav(scene));
    let _ = writeln!(
        h,
        "<h1>{} <span class=\"badge o-{}\">{}</span></h1>",
        escape_html(&s.id),
        s.outcome.class(),
        escape_html(&s.outcome.label())
    );
    h.push_str(&facts(scene));
    h.push_str(&toggles(scene));
    h.push_str("<div class=\"views\">\n");
    for v in &scene.views {
        h.push_str(&view_figure(v));
    }
    h.push_str("</div>\n");
    if let (Some(recon), Some(result)) = (&scene.recon, &s.result) {
        h.push_str(&answer_section(recon, result));
    }
    h.push_str(&side_by_side(scene));
    h.push_str(&files_section(scene));
    h.push_str("<script src=\"../report.js\"></script>\n</body>\n</html>\n");
    h
}

fn nav(scene: &ReportScene) -> String {
    let link = |id: &Option<String>, label: &str| match id {
        Some(id) => format!(
            " · <a href=\"../{0}/index.html\" rel=\"{label}\">{label}: {0}</a>",
            escape_html(id)
        ),
        None => String::new(),
    };
    format!(
        "<nav><a href=\"../index.html\">index</a>{}{}</nav>\n",
        link(&scene.neighbours[0], "prev"),
        link(&scene.neighbours[1], "next")
    )
}

fn facts(scene: &ReportScene) -> String {
    let s = &scene.summary;
    let expected = match &scene.expected_reason {
        Some(r) if !s.supported => format!("a known failure case: {}", escape_html(r)),
        _ if !s.supported => "a known failure case".into(),
        _ => "supported by the method".into(),
    };
    format!(
        "<p class=\"facts\">family <b>{}</b>, {} block{}, {expected}.</p>\n",
        escape_html(&s.family),
        s.blocks,
        if s.blocks == 1 { "" } else { "s" }
    )
}

fn toggles(scene: &ReportScene) -> String {
    let recognized = scene.recon.is_some();
    let mut t = String::from("<fieldset class=\"toggles\"><legend>overlays</legend>\n");
    for (name, label) in OVERLAYS {
        let needs_answer = matches!(name, "vision" | "answer");
        if needs_answer && !recognized {
            continue;
        }
        let on = name == if recognized { "answer" } else { "truth" };
        let _ = writeln!(
            t,
            "<label><input type=\"checkbox\" data-overlay=\"{name}\"{}> {label}</label>",
            if on { " checked" } else { "" }
        );
    }
    t.push_str("</fieldset>\n<p class=\"legend\"><span class=\"k-boundary\">boundary</span> <span class=\"k-convex\">convex</span> <span class=\"k-concave\">concave</span> <span class=\"k-crack\">crack</span> · <span class=\"vision\">vision</span> · <span class=\"a-drawn\">answer</span> <span class=\"a-extra\">answer, not seen</span> <span class=\"a-unexplained\">seen, unexplained</span></p>\n");
    t
}

fn view_figure(v: &ReportView) -> String {
    let n = escape_html(&v.name);
    let [w, h] = v.size_px;
    format!(
        "<figure class=\"view\" id=\"view-{n}\"><div class=\"stack\" style=\"width:{w}px;height:{h}px\"><img src=\"view_{n}.png\" width=\"{w}\" height=\"{h}\" alt=\"view {n}\"><img class=\"ov ov-ids\" src=\"ids_{n}.png\" width=\"{w}\" height=\"{h}\" alt=\"block ids {n}\"><img class=\"ov ov-depth\" src=\"depth_{n}.png\" width=\"{w}\" height=\"{h}\" alt=\"depth {n}\">{}</div><figcaption>{n}: {} exact lines{}</figcaption></figure>\n",
        view_svg(v),
        v.truth.lines.len(),
        v.seen.as_ref().map_or(String::new(), |s| format!(
            ", {} seen ({} unexplained), {} in the answer ({} not seen)",
            s.observed.lines.len(),
            s.unexplained_lines.len(),
            s.answer.lines.len(),
            s.extra_lines.len()
        ))
    )
}

fn answer_section(recon: &Reconstruction, r: &SceneResult) -> String {
    let mut h = String::from("<h2>Answer</h2>\n<table class=\"score\">\n");
    let mut row = |k: &str, v: String| {
        let _ = writeln!(h, "<tr><th>{k}</th><td>{v}</td></tr>");
    };
    row("status", format!("{:?}", recon.status).to_lowercase());
    if let Some(reason) = &recon.reason {
        row("reason", escape_html(reason));
    }
    row("verdict", r.verdict.as_str().into());
    row("volume IoU", format!("{:.4}", r.iou));
    row(
        "blocks",
        format!(
            "{} truth, {} answer, {} matched at 3D IoU ≥ 0.5; F1 {:.3}",
            r.truth_blocks, r.recon_blocks, r.detected_blocks, r.f1
        ),
    );
    row(
        "mean centre error",
        r.mean_center_error_mm
            .map_or("-".into(), |e| format!("{e:.3} mm")),
    );
    row(
        "layers",
        if r.layers_right { "right" } else { "wrong" }.into(),
    );
    if let Some(note) = &r.note {
        row("note", escape_html(note));
    }
    h.push_str("</table>\n");
    h.push_str(&blocks_and_tree(recon));
    h
}

fn blocks_and_tree(recon: &Reconstruction) -> String {
    let mut h = String::new();
    if let Some(tree) = &recon.csg {
        h.push_str("<h2>Layers and CSG tree</h2>\n<pre class=\"csg\">");
        csg_lines(tree, recon, 0, &mut h);
        h.push_str("</pre>\n");
    }
    if !recon.blocks.is_empty() {
        h.push_str("<table class=\"blocks\"><thead><tr><th>block</th><th>type</th><th>centre, mm</th></tr></thead><tbody>\n");
        for (i, b) in recon.blocks.iter().enumerate() {
            let c = b.center_mm;
            let _ = writeln!(
                h,
                "<tr><td>{i}</td><td>{}</td><td>{:.2}, {:.2}, {:.2}</td></tr>",
                escape_html(b.block_type.id),
                c.x,
                c.y,
                c.z
            );
        }
        h.push_str("</tbody></table>\n");
    }
    h
}

fn csg_lines(node: &CsgNode, recon: &Reconstruction, depth: usize, out: &mut String) {
    let pad = "  ".repeat(depth);
    let (name, children): (String, Vec<&CsgNode>) = match node {
        CsgNode::Block(i) => {
            let ty = recon.blocks.get(*i).map_or("?", |b| b.block_type.id);
            (format!("block {i} ({ty})"), Vec::new())
        }
        CsgNode::Union(c) => ("union".into(), c.iter().collect()),
        CsgNode::Intersection(c) => ("intersection".into(), c.iter().collect()),
        CsgNode::Difference(p) => ("difference".into(), p.iter().collect()),
    };
    let _ = writeln!(out, "{pad}{}", escape_html(&name));
    for c in children {
        csg_lines(c, recon, depth + 1, out);
    }
}

/// The first view's exact drawing beside the answer's drawing in the same camera.
fn side_by_side(scene: &ReportScene) -> String {
    let Some(v) = scene.views.first() else {
        return String::new();
    };
    let mut h = format!(
        "<h2>Truth and reconstruction</h2>\n<div class=\"pair\"><figure>{}<figcaption>truth, view {}</figcaption></figure>",
        drawing_svg(&v.truth, v.size_px, "truth-lines"),
        escape_html(&v.name)
    );
    match &v.seen {
        Some(seen) => {
            let _ = write!(
                h,
                "<figure>{}<figcaption>the answer's blocks{}</figcaption></figure>",
                drawing_svg(&seen.answer, v.size_px, "answer-lines"),
                if matches!(scene.summary.outcome, Outcome::Declined(_)) {
                    " (chosen by the search, then declined)"
                } else {
                    ""
                }
            );
        }
        None => h.push_str("<p>No recognition of this scene.</p>"),
    }
    h.push_str("</div>\n");
    h
}

fn files_section(scene: &ReportScene) -> String {
    let mut h = String::from("<h2>Files</h2>\n<ul class=\"files\">\n");
    for f in &scene.files {
        let what = if f.ends_with(".glb") {
            "glTF 2.0 model of the scene"
        } else if f == "recon.json" {
            "the reconstruction file (the answer)"
        } else {
            "the scene file (truth)"
        };
        let _ = writeln!(
            h,
            "<li><a href=\"{0}\">{0}</a>: {what}</li>",
            escape_html(f)
        );
    }
    if !scene.files.iter().any(|f| f.ends_with(".glb")) {
        h.push_str("<li>no glTF model: generate the dataset with <code>--gltf</code></li>\n");
    }
    h.push_str("</ul>\n");
    h
}
