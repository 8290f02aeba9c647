//! References that cannot rot: every `README "..."` or `docs/<page>.md "..."` citation in the
//! sources, tests, Makefile, README.md and docs/ names a page that exists and headings that exist
//! on it, and every `docs/<page>.md` a file mentions or a Markdown link points at exists.
//!
//! A citation is a page followed by one or more quoted headings, `"A", "B"`; a quote may be
//! escaped (`\"A\"`, inside a Rust string) and may be broken over comment lines. A heading
//! matches with or without a trailing parenthesis (`Wireframe datasets (HAWP, L-CNN, LETR)`
//! answers to `"Wireframe datasets"`).

use std::path::{Path, PathBuf};

/// The folders and files scanned, relative to the repository root.
const SCANNED: [&str; 5] = ["src", "tests", "Makefile", "README.md", "docs"];

/// This checker, whose own tests cite pages that do not exist on purpose.
const CHECKER: &str = "tests/references.rs";

/// Folders whose files are data, not text that cites (fuzz corpora, fixtures).
const SKIPPED_DIRS: [&str; 4] = ["fixtures", "corpus", "seeds", "artifacts"];

/// One dangling reference: where it is and what is wrong.
#[derive(Debug, PartialEq)]
struct Dangling {
    file: String,
    line: usize,
    problem: String,
}

/// The headings of a Markdown text (lines starting with `#` outside code fences), each also
/// without a trailing parenthesis.
fn headings(markdown: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut fenced = false;
    for line in markdown.lines() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            continue;
        }
        if fenced || !line.starts_with('#') {
            continue;
        }
        let text = line.trim_start_matches('#').trim().to_string();
        if let Some(open) = text.rfind(" (") {
            if text.ends_with(')') {
                out.push(text[..open].trim().to_string());
            }
        }
        out.push(text);
    }
    out
}

/// Skips whitespace and comment-line prefixes (`//!`, `///`, `//`, `#`) after a line break.
fn skip_gap(s: &str) -> &str {
    let mut rest = s;
    loop {
        let trimmed = rest.trim_start_matches([' ', '\t']);
        if let Some(after) = trimmed.strip_prefix('\n') {
            let after = after.trim_start_matches([' ', '\t']);
            let after = after
                .strip_prefix("//!")
                .or_else(|| after.strip_prefix("///"))
                .or_else(|| after.strip_prefix("//"))
                .or_else(|| after.strip_prefix('#'))
                .unwrap_or(after);
            rest = after;
        } else {
            return trimmed;
        }
    }
}

/// The quoted names right after a citation's page: `"A", "B"` (quotes may be escaped, names may
/// be broken over comment lines). Empty when no quote follows.
fn quoted_names(after_page: &str) -> Vec<String> {
    let mut names = Vec::new();
    // A citation puts a space or a line break between the page and its first heading; a quote
    // right after the page (`"docs/cli.md"`) closes a string instead.
    if !after_page.starts_with([' ', '\n']) {
        return Vec::new();
    }
    let mut rest = skip_gap(after_page);
    loop {
        let body = match rest.strip_prefix("\\\"").or_else(|| rest.strip_prefix('"')) {
            Some(body) => body,
            None => return names,
        };
        let Some(end) = body.find('"') else {
            return names;
        };
        let raw = body[..end].trim_end_matches('\\');
        let joined = raw
            .split('\n')
            .enumerate()
            .map(|(i, l)| {
                if i == 0 {
                    return l.trim();
                }
                let l = l.trim_start();
                l.strip_prefix("//!")
                    .or_else(|| l.strip_prefix("///"))
                    .or_else(|| l.strip_prefix("//"))
                    .or_else(|| l.strip_prefix('#'))
                    .unwrap_or(l)
                    .trim()
            })
            .collect::<Vec<_>>()
            .join(" ");
        names.push(joined.trim().to_string());
        rest = &body[end + 1..];
        let after_comma = skip_gap(rest);
        match after_comma.strip_prefix(',') {
            Some(next) => rest = skip_gap(next),
            None => return names,
        }
    }
}

/// The page a citation starting at `at` names: `README.md` or `docs/<page>.md`, and the text
/// after it.
fn cited_page(text: &str, at: usize) -> Option<(String, usize)> {
    let s = &text[at..];
    if s.starts_with("README") {
        let len = if s.starts_with("README.md") { 9 } else { 6 };
        return Some(("README.md".to_string(), at + len));
    }
    let name_len = s[5..].find(".md")?;
    let name = &s[5..5 + name_len];
    let ok = !name.is_empty()
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_' || c == '/');
    ok.then(|| (format!("docs/{name}.md"), at + 5 + name_len + 3))
}

/// Every dangling reference in one file's text. `page_text` reads a page by its path relative
/// to the repository root (None when it does not exist).
fn dangling_in(
    file: &str,
    text: &str,
    page_text: &dyn Fn(&str) -> Option<String>,
) -> Vec<Dangling> {
    let mut out = Vec::new();
    let starts = text
        .match_indices("README")
        .chain(text.match_indices("docs/"))
        .map(|(i, _)| i);
    for at in starts {
        // `golden/README.md`, `scenes/bench/README.md`: another folder's README, not a citation.
        let before = text[..at].chars().last();
        if matches!(before, Some(c) if c == '/' || c.is_ascii_alphanumeric() || c == '_') {
            continue;
        }
        let Some((page, after)) = cited_page(text, at) else {
            continue;
        };
        let line = text[..at].matches('\n').count() + 1;
        let names = quoted_names(&text[after..]);
        let is_readme = page == "README.md";
        if is_readme && names.is_empty() {
            continue; // "README.md" named as a file, not cited
        }
        let Some(markdown) = page_text(&page) else {
            out.push(Dangling {
                file: file.to_string(),
                line,
                problem: format!("{page} does not exist"),
            });
            continue;
        };
        let known = headings(&markdown);
        for name in names {
            if !known.contains(&name) {
                out.push(Dangling {
                    file: file.to_string(),
                    line,
                    problem: format!("{page} has no heading \"{name}\""),
                });
            }
        }
    }
    out.extend(dangling_links(file, text, page_text));
    out
}

/// Markdown links to `.md` files (`](docs/x.md)`, `](x.md#...)`) that point at no file; relative
/// to the linking file's folder.
fn dangling_links(
    file: &str,
    text: &str,
    page_text: &dyn Fn(&str) -> Option<String>,
) -> Vec<Dangling> {
    if !file.ends_with(".md") {
        return Vec::new();
    }
    let folder = Path::new(file).parent().unwrap_or(Path::new(""));
    let mut out = Vec::new();
    for (at, _) in text.match_indices("](") {
        let target = &text[at + 2..];
        let Some(end) = target.find(')') else {
            continue;
        };
        let target = target[..end].split('#').next().unwrap_or("");
        if !target.ends_with(".md") || target.contains("://") {
            continue;
        }
        let path = normalize(&folder.join(target));
        if page_text(&path).is_none() {
            out.push(Dangling {
                file: file.to_string(),
                line: text[..at].matches('\n').count() + 1,
                problem: format!("link to {path}, which does not exist"),
            });
        }
    }
    out
}

/// `docs/../README.md` -> `README.md`.
fn normalize(path: &Path) -> String {
    let mut parts: Vec<String> = Vec::new();
    for c in path.components() {
        match c {
            std::path::Component::ParentDir => {
                parts.pop();
            }
            std::path::Component::Normal(s) => parts.push(s.to_string_lossy().into_owned()),
            _ => {}
        }
    }
    parts.join("/")
}

/// Every text file under the scanned paths, relative to `root`.
fn scanned_files(root: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack: Vec<PathBuf> = SCANNED.iter().map(|s| root.join(s)).collect();
    while let Some(path) = stack.pop() {
        if path.is_dir() {
            let skip = path
                .file_name()
                .is_some_and(|n| SKIPPED_DIRS.iter().any(|d| n == *d));
            if skip {
                continue;
            }
            for entry in std::fs::read_dir(&path).unwrap() {
                stack.push(entry.unwrap().path());
            }
        } else if path.is_file() {
            out.push(path);
        }
    }
    out.sort();
    out
}

#[test]
fn every_cited_page_and_heading_exists() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let read_page = |page: &str| std::fs::read_to_string(root.join(page)).ok();
    let mut dangling = Vec::new();
    let mut citations = 0;
    for path in scanned_files(root) {
        let Ok(text) = std::fs::read_to_string(&path) else {
            continue; // pictures and other binary files cite nothing
        };
        let rel = path
            .strip_prefix(root)
            .unwrap()
            .to_string_lossy()
            .into_owned();
        if rel == CHECKER {
            continue;
        }
        citations += text.matches("docs/").count();
        dangling.extend(dangling_in(&rel, &text, &read_page));
    }
    assert!(
        citations > 100,
        "the scan found only {citations} mentions of docs/"
    );
    let report: Vec<String> = dangling
        .iter()
        .map(|d| format!("{}:{}: {}", d.file, d.line, d.problem))
        .collect();
    assert!(
        report.is_empty(),
        "dangling references:\n{}",
        report.join("\n")
    );
}

/// The pages the unit tests below cite against.
fn fake_pages(page: &str) -> Option<String> {
    match page {
        "docs/formats.md" => Some("# File formats\n\n## Scene files\n\n```sh\n# not a heading\n```\n## Wireframe datasets (HAWP, L-CNN, LETR)\n".into()),
        "README.md" => Some("# blockworld\n\n## Install\n".into()),
        _ => None,
    }
}

#[test]
fn a_dangling_page_or_heading_is_found() {
    let text = "see docs/formats.md \"Scene files\", docs/formats.md \"Wireframe datasets\", \
                README \"Install\" and docs/formats.md \"Scene files\", \"Wireframe datasets\"";
    assert_eq!(dangling_in("a.rs", text, &fake_pages), vec![]);
    let bad = "x\n(docs/formats.md \"No such part\")\ndocs/missing.md \"Scene files\"\n\
               README \"not a heading\"; docs/formats.md \"Scene files\", \"# not a heading\"";
    let mut found: Vec<String> = dangling_in("b.rs", bad, &fake_pages)
        .into_iter()
        .map(|d| format!("{}: {}", d.line, d.problem))
        .collect();
    found.sort();
    assert_eq!(
        found,
        vec![
            "2: docs/formats.md has no heading \"No such part\"".to_string(),
            "3: docs/missing.md does not exist".to_string(),
            "4: README.md has no heading \"not a heading\"".to_string(),
            "4: docs/formats.md has no heading \"# not a heading\"".to_string(),
        ]
    );
}

#[test]
fn citations_broken_over_comment_lines_and_escaped_quotes_are_read() {
    let broken =
        "//! the block (docs/formats.md\n//! \"Scene files\", \"Wireframe\n//! datasets\")";
    assert_eq!(dangling_in("c.rs", broken, &fake_pages), vec![]);
    let escaped = r#"bail!("see docs/formats.md \"Scene file\" for the format")"#;
    assert_eq!(dangling_in("d.rs", escaped, &fake_pages).len(), 1);
    let other_readme = "scenes/bench/README.md \"Anything\" and golden/README.md";
    assert_eq!(dangling_in("e.rs", other_readme, &fake_pages), vec![]);
    let link = "[formats](formats.md#scene-files), [gone](limits.md)";
    let found = dangling_in("docs/index.md", link, &fake_pages);
    assert_eq!(found.len(), 1, "{found:?}");
    assert!(found[0].problem.contains("docs/limits.md"), "{found:?}");
}
