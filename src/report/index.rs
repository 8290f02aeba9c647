//! The index: the accuracy table of the run, the filters and the thumbnail grid, which
//! `report.js` draws page by page from `scenes.js` (one array per scene), so the index of
//! 10,000 scenes stays one small page and a short script.

use super::{
    escape_html, Outcome, RunInfo, SceneSummary, SiteFile, PAGE_SIZE, REPORT_JS, STYLE_CSS,
};
use crate::score::{summarize_by_family, SceneResult, Verdict, FAMILY_TABLE_HEADINGS};
use std::fmt::Write as _;

/// The site's shared files: `index.html`, `scenes.js`, `style.css` and `report.js`.
pub fn index_files(run: &RunInfo, scenes: &[SceneSummary]) -> Vec<SiteFile> {
    let file = |path: &str, text: String| SiteFile {
        path: path.into(),
        bytes: text.into_bytes(),
    };
    vec![
        file("index.html", index_html(run, scenes)),
        file("scenes.js", scenes_script(scenes)),
        file("style.css", STYLE_CSS.into()),
        file("report.js", REPORT_JS.into()),
    ]
}

/// `scenes.js`: `window.BLOCKWORLD_SCENES`, one array per scene: id, family, blocks,
/// supported (1 or 0), outcome class, decline kind, label, volume IoU (null when not
/// recognized), the thumbnail's view and its picture's width and height in px.
pub fn scenes_script(scenes: &[SceneSummary]) -> String {
    let mut s = format!(
        "// blockworld report: {} scenes (id, family, blocks, supported, outcome, kind, label, IoU, thumbnail view, its width and height px)\nwindow.BLOCKWORLD_PAGE_SIZE = {PAGE_SIZE};\nwindow.BLOCKWORLD_SCENES = [\n",
        scenes.len()
    );
    for sc in scenes {
        let iou = sc
            .result
            .as_ref()
            .map_or("null".to_string(), |r| format!("{:.4}", r.iou));
        let _ = writeln!(
            s,
            "[{},{},{},{},\"{}\",{},{},{iou},{},{},{}],",
            json_str(&sc.id),
            json_str(&sc.family),
            sc.blocks,
            u8::from(sc.supported),
            sc.outcome.class(),
            json_str(sc.outcome.detail()),
            json_str(&sc.outcome.label()),
            json_str(&sc.thumbnail_view),
            sc.thumbnail_px[0],
            sc.thumbnail_px[1]
        );
    }
    s.push_str("];\n");
    s
}

fn json_str(s: &str) -> String {
    serde_json::to_string(s).expect("a string serializes")
}

fn index_html(run: &RunInfo, scenes: &[SceneSummary]) -> String {
    let results: Vec<SceneResult> = scenes.iter().filter_map(|s| s.result.clone()).collect();
    let mut h = String::new();
    let title = format!("blockworld report: {}", run.dataset);
    let _ = write!(
        h,
        "<!doctype html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>{t}</title>\n<link rel=\"stylesheet\" href=\"style.css\">\n</head>\n<body class=\"index\">\n<h1>{t}</h1>\n",
        t = escape_html(&title)
    );
    h.push_str(&run_line(run, scenes.len()));
    if results.is_empty() {
        h.push_str("<p>No recognitions: build with <code>--recognitions DIR</code> (the folder <code>blockworld recognize-dataset</code> writes) for verdicts and the accuracy table.</p>\n");
    } else {
        h.push_str(&headline(&results));
        h.push_str(&accuracy_table(&results));
    }
    h.push_str(&filters(scenes));
    h.push_str("<p id=\"count\"></p>\n<nav class=\"pager\" id=\"pager-top\"></nav>\n<div id=\"grid\" class=\"grid\"></div>\n<nav class=\"pager\" id=\"pager-bottom\"></nav>\n");
    h.push_str("<noscript><p>The grid needs JavaScript; every scene's page is <code>&lt;id&gt;/index.html</code>.</p></noscript>\n");
    h.push_str("<script src=\"scenes.js\"></script>\n<script src=\"report.js\"></script>\n</body>\n</html>\n");
    h
}

fn run_line(run: &RunInfo, count: usize) -> String {
    let mut p = format!(
        "<p class=\"run\">{count} scenes of <code>{}</code>",
        escape_html(&run.dataset)
    );
    if let Some(r) = &run.recognitions {
        let _ = write!(
            p,
            "; recognitions <code>{}</code> ({} views: {})",
            escape_html(r),
            run.views.len(),
            escape_html(&run.views.join(", "))
        );
    }
    p.push_str(".</p>\n");
    p
}

/// The three figures that matter: supported scenes exact, confidently wrong, failure cases
/// declined.
fn headline(results: &[SceneResult]) -> String {
    let supported: Vec<&SceneResult> = results.iter().filter(|r| r.supported).collect();
    let exact = supported
        .iter()
        .filter(|r| r.verdict == Verdict::Exact)
        .count();
    let wrong = results.iter().filter(|r| r.confidently_wrong).count();
    let failures = results.len() - supported.len();
    let flagged = results.iter().filter(|r| !r.supported && r.flagged).count();
    format!(
        "<p class=\"headline\">supported scenes exact <b>{exact} / {}</b>; confidently wrong <b id=\"wrong-total\">{wrong}</b>; failure cases declined <b>{flagged} / {failures}</b></p>\n",
        supported.len()
    )
}

fn accuracy_table(results: &[SceneResult]) -> String {
    let mut t = String::from("<table class=\"accuracy\">\n<thead><tr>");
    for h in FAMILY_TABLE_HEADINGS {
        let _ = write!(t, "<th>{}</th>", escape_html(h));
    }
    t.push_str("</tr></thead>\n<tbody>\n");
    for r in summarize_by_family(results) {
        t.push_str(if r.family == "all" {
            "<tr class=\"all\">"
        } else {
            "<tr>"
        });
        for cell in r.cells() {
            let _ = write!(t, "<td>{}</td>", escape_html(&cell));
        }
        t.push_str("</tr>\n");
    }
    t.push_str("</tbody>\n</table>\n");
    t
}

/// The family and outcome selects, with only the values some scene has.
fn filters(scenes: &[SceneSummary]) -> String {
    let mut families: Vec<&str> = scenes.iter().map(|s| s.family.as_str()).collect();
    families.sort_unstable();
    families.dedup();
    let mut kinds: Vec<&str> = scenes
        .iter()
        .filter(|s| matches!(s.outcome, Outcome::Declined(_)))
        .map(|s| s.outcome.detail())
        .collect();
    kinds.sort_unstable();
    kinds.dedup();
    let has = |class: &str| scenes.iter().any(|s| s.outcome.class() == class);
    let mut f = String::from("<form id=\"filters\" class=\"filters\">\n<label>family <select id=\"family\">\n<option value=\"\">all</option>\n");
    for fam in families {
        let _ = writeln!(f, "<option value=\"{0}\">{0}</option>", escape_html(fam));
    }
    f.push_str("</select></label>\n<label>outcome <select id=\"outcome\">\n<option value=\"\">all</option>\n");
    let mut option = |value: String, label: String| {
        let _ = writeln!(
            f,
            "<option value=\"{}\">{}</option>",
            escape_html(&value),
            escape_html(&label)
        );
    };
    if has("exact") {
        option("exact".into(), "exact".into());
    }
    if has("declined") {
        option("declined".into(), "declined (any reason)".into());
    }
    for k in kinds {
        option(format!("declined:{k}"), format!("declined: {k}"));
    }
    for (class, label) in [
        ("wrong", "confidently wrong"),
        ("other", "other verdicts"),
        ("none", "not recognized"),
    ] {
        if has(class) {
            option(class.into(), label.into());
        }
    }
    f.push_str("</select></label>\n</form>\n");
    f
}
