//! `blockworld report`: a static web site of a dataset and of the recognizer's answers on it
//! (docs/report.md). Plain data in, text and bytes out: an index with the accuracy table and a
//! thumbnail grid of every scene (filtered by family and by outcome, paged in the browser), and
//! per scene a page with its views and overlays that a click shows or hides: the exact line
//! drawing coloured by kind, the vertices with their six-bit codes (Chapter IV) and junctions,
//! the vision front end's lines beside the truth's, the block ids and depth, and the
//! recognizer's answer drawn over each view with the observed lines it leaves unexplained (the
//! check of step 6, as `recognize --debug-dir` draws it), its CSG tree (Figure 4.6) and score.
//! The site uses no server and no network: plain HTML, one style sheet and one small script,
//! opened from the file system. Reading the dataset and writing the site is the caller's.

mod index;
mod overlay;
mod page;
mod pictures;

pub use index::{index_files, scenes_script};
pub use page::scene_page;
pub use pictures::{depth_picture, ids_picture};

use crate::drawing::LineDrawing;
use crate::recognize::decline_kind;
use crate::scene::{ReconStatus, Reconstruction};
use crate::score::{SceneResult, Verdict};

/// Scenes per index page: 100 thumbnails, a few windows' worth, so the first page of a
/// 10,000-scene index shows from the file system in well under a second (docs/report.md
/// "Speed").
pub const PAGE_SIZE: usize = 100;

/// The style sheet every page links (`style.css` at the site's root).
pub const STYLE_CSS: &str = include_str!("site/style.css");

/// The script every page loads (`report.js` at the site's root): the index's filters and pages,
/// a scene page's overlay toggles.
pub const REPORT_JS: &str = include_str!("site/report.js");

/// One file of the site: its path relative to the site's root (`/`-separated) and its bytes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SiteFile {
    /// Path under the site's root, e.g. `s000042/index.html`.
    pub path: String,
    /// The file's bytes.
    pub bytes: Vec<u8>,
}

/// What the index says about the run as a whole.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RunInfo {
    /// The dataset, as named on the command line.
    pub dataset: String,
    /// The recognitions folder, when one was given.
    pub recognitions: Option<String>,
    /// The views of the recognitions (empty without).
    pub views: Vec<String>,
}

/// How one scene came out, as the index filters it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Outcome {
    /// No recognition was given for the scene.
    NotRecognized,
    /// Answered and exact.
    Exact,
    /// Declined (`unsupported`), with the kind of decline (`recognize::DECLINE_KINDS`).
    Declined(String),
    /// Answered `ok` but not exact: the worst outcome.
    ConfidentlyWrong,
    /// Anything else (no reconstruction, a scoring error): the verdict's name.
    Other(String),
}

impl Outcome {
    /// The outcome of `result` for the answer `recon`.
    pub fn of(result: &SceneResult, recon: Option<&Reconstruction>) -> Outcome {
        if result.confidently_wrong {
            return Outcome::ConfidentlyWrong;
        }
        if let Some(r) = recon.filter(|r| r.status == ReconStatus::Unsupported) {
            return Outcome::Declined(decline_kind(r.reason.as_deref().unwrap_or("")).into());
        }
        match result.verdict {
            Verdict::Exact => Outcome::Exact,
            v => Outcome::Other(v.as_str().into()),
        }
    }

    /// The filter value: `exact`, `declined`, `wrong`, `other` or `none`.
    pub fn class(&self) -> &'static str {
        match self {
            Outcome::NotRecognized => "none",
            Outcome::Exact => "exact",
            Outcome::Declined(_) => "declined",
            Outcome::ConfidentlyWrong => "wrong",
            Outcome::Other(_) => "other",
        }
    }

    /// The words shown on a thumbnail and a scene page.
    pub fn label(&self) -> String {
        match self {
            Outcome::NotRecognized => "not recognized".into(),
            Outcome::Exact => "exact".into(),
            Outcome::Declined(kind) => format!("declined: {kind}"),
            Outcome::ConfidentlyWrong => "confidently wrong".into(),
            Outcome::Other(v) => v.clone(),
        }
    }

    /// The decline kind, empty for other outcomes.
    pub fn detail(&self) -> &str {
        match self {
            Outcome::Declined(kind) | Outcome::Other(kind) => kind,
            _ => "",
        }
    }
}

/// One scene as the index lists it.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneSummary {
    /// Scene id, also its folder in the site.
    pub id: String,
    /// Its family.
    pub family: String,
    /// Blocks in the truth.
    pub blocks: usize,
    /// `expect.supported` of the truth.
    pub supported: bool,
    /// The view whose picture is the thumbnail (`ne`).
    pub thumbnail_view: String,
    /// The thumbnail picture's width and height, px; `[0, 0]` when the scene has no view.
    /// The grid sizes each thumbnail from it before the picture loads, so the browser fetches
    /// only the pictures in or near the window.
    pub thumbnail_px: [u32; 2],
    /// How the recognizer did.
    pub outcome: Outcome,
    /// The score, when recognized.
    pub result: Option<SceneResult>,
}

/// One view of a scene page.
#[derive(Debug, Clone, PartialEq)]
pub struct ReportView {
    /// The view's name (`ne`); its pictures are `view_<v>.png`, `depth_<v>.png`, `ids_<v>.png`
    /// in the scene's folder.
    pub name: String,
    /// Picture width and height, px.
    pub size_px: [u32; 2],
    /// The exact visible line drawing (`lines_<v>.json`).
    pub truth: LineDrawing,
    /// What the recognizer saw and answered in this view, when recognized.
    pub seen: Option<SeenView>,
}

/// A view as the recognizer saw it and its answer drawn in it (the file `<id>.views.json` of
/// `recognize-dataset`).
#[derive(Debug, Clone, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub struct SeenView {
    /// The view's name.
    pub view: String,
    /// The vision front end's drawing (or the exact one with `--from-truth`).
    pub observed: LineDrawing,
    /// The answer's own exact drawing in the view's camera (the blocks the search chose, also
    /// when it declined).
    pub answer: LineDrawing,
    /// Lines of `observed` no line of `answer` explains.
    pub unexplained_lines: Vec<usize>,
    /// Lines of `answer` along no line of `observed`.
    pub extra_lines: Vec<usize>,
}

/// Everything a scene page shows.
#[derive(Debug, Clone, PartialEq)]
pub struct ReportScene {
    /// The index's line of the scene.
    pub summary: SceneSummary,
    /// `expect.reason` of the truth, for a known failure case.
    pub expected_reason: Option<String>,
    /// The views, in the dataset's order.
    pub views: Vec<ReportView>,
    /// The recognizer's answer, when recognized.
    pub recon: Option<Reconstruction>,
    /// Files of the scene's folder in the site that the page links (`scene.json`,
    /// `scene.glb`).
    pub files: Vec<String>,
    /// The previous and next scene ids, for the page's links.
    pub neighbours: [Option<String>; 2],
}

/// `text` with `&`, `<`, `>` and `"` escaped for HTML text and attribute values.
pub fn escape_html(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            c => out.push(c),
        }
    }
    out
}

#[cfg(test)]
mod tests;
