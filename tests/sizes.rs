//! Room sizes as a test (style guide: small functions, files under about 800 lines): no source
//! file under `src/` over 1,000 lines and no function over 80. The function scanner blanks
//! comments, strings and character literals, then matches each `fn`'s body braces.

mod common;

use common::rust_files;
use std::path::{Path, PathBuf};

/// The longest function allowed, in lines from its `fn` line to its closing brace.
const MAX_FUNCTION_LINES: usize = 80;
/// The longest source file allowed, in lines.
const MAX_FILE_LINES: usize = 1000;

/// The length in bytes of a string literal (plain or raw) starting at `i`, if one starts there.
fn string_len(b: &[u8], i: usize) -> Option<usize> {
    let ident_before = i > 0 && (b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_');
    if b[i] == b'r' && !ident_before {
        let hashes = b[i + 1..].iter().take_while(|&&c| c == b'#').count();
        if b.get(i + 1 + hashes) == Some(&b'"') {
            let close: Vec<u8> = std::iter::once(b'"')
                .chain(std::iter::repeat_n(b'#', hashes))
                .collect();
            let start = i + 2 + hashes;
            let end = b[start..]
                .windows(close.len())
                .position(|w| w == close.as_slice())
                .map_or(b.len(), |p| start + p + close.len());
            return Some(end - i);
        }
    }
    if b[i] != b'"' {
        return None;
    }
    let mut j = i + 1;
    while j < b.len() && b[j] != b'"' {
        j += if b[j] == b'\\' { 2 } else { 1 };
    }
    Some((j + 1).min(b.len()) - i)
}

/// The length of a character literal at `i` (`'x'`, `'\n'`, `'\u{..}'`), not a lifetime.
fn char_len(b: &[u8], i: usize) -> Option<usize> {
    if b[i] != b'\'' {
        return None;
    }
    let rest = &b[i + 1..];
    let body = if rest.first() == Some(&b'\\') {
        rest.iter().position(|&c| c == b'\'')?
    } else {
        let ch = std::str::from_utf8(&rest[..rest.len().min(4)])
            .ok()
            .or_else(|| std::str::from_utf8(&rest[..1]).ok())?;
        ch.chars().next()?.len_utf8()
    };
    (rest.get(body) == Some(&b'\'')).then_some(body + 2)
}

/// `text` with comments, strings and character literals replaced by spaces (newlines kept).
fn blank(text: &str) -> Vec<u8> {
    let b = text.as_bytes();
    let mut out = b.to_vec();
    let mut i = 0;
    let wipe = |out: &mut Vec<u8>, from: usize, to: usize| {
        for c in &mut out[from..to] {
            if *c != b'\n' {
                *c = b' ';
            }
        }
    };
    while i < b.len() {
        let len = if b[i..].starts_with(b"//") {
            b[i..]
                .iter()
                .position(|&c| c == b'\n')
                .unwrap_or(b.len() - i)
        } else if b[i..].starts_with(b"/*") {
            b[i + 2..]
                .windows(2)
                .position(|w| w == b"*/")
                .map_or(b.len() - i, |p| p + 4)
        } else if let Some(n) = string_len(b, i).or_else(|| char_len(b, i)) {
            n
        } else {
            i += 1;
            continue;
        };
        wipe(&mut out, i, (i + len).min(b.len()));
        i += len;
    }
    out
}

/// Each function with a body in `text`: its name, first line (1-based) and length in lines.
fn functions(text: &str) -> Vec<(String, usize, usize)> {
    let b = blank(text);
    let line_of = |at: usize| b[..at].iter().filter(|&&c| c == b'\n').count() + 1;
    let mut found = Vec::new();
    let mut i = 0;
    while let Some(p) = b[i..].windows(3).position(|w| w == b"fn ") {
        let at = i + p;
        i = at + 3;
        if at > 0 && (b[at - 1].is_ascii_alphanumeric() || b[at - 1] == b'_') {
            continue;
        }
        let name: String = b[at + 3..]
            .iter()
            .take_while(|c| c.is_ascii_alphanumeric() || **c == b'_')
            .map(|&c| c as char)
            .collect();
        let Some(open) = body_start(&b, at + 3) else {
            continue;
        };
        let Some(close) = matching_brace(&b, open) else {
            continue;
        };
        found.push((name, line_of(at), line_of(close) - line_of(at) + 1));
    }
    found
}

/// The `{` opening the body of the function whose signature starts at `from`; `None` for a
/// declaration without a body (it ends with `;` first).
fn body_start(b: &[u8], from: usize) -> Option<usize> {
    let mut depth = 0i32;
    for (k, &c) in b.iter().enumerate().skip(from) {
        match c {
            b'(' | b'[' => depth += 1,
            b')' | b']' => depth -= 1,
            b'{' if depth == 0 => return Some(k),
            b';' if depth == 0 => return None,
            _ => {}
        }
    }
    None
}

/// The `}` that closes the `{` at `open`.
fn matching_brace(b: &[u8], open: usize) -> Option<usize> {
    let mut depth = 0usize;
    for (k, &c) in b.iter().enumerate().skip(open) {
        match c {
            b'{' => depth += 1,
            b'}' => {
                depth -= 1;
                if depth == 0 {
                    return Some(k);
                }
            }
            _ => {}
        }
    }
    None
}

fn sources() -> Vec<(PathBuf, String)> {
    let mut files = Vec::new();
    rust_files(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("src"),
        &mut files,
    );
    files.sort();
    assert!(files.len() > 50, "src/ has {} .rs files", files.len());
    files
        .into_iter()
        .map(|p| {
            let text = std::fs::read_to_string(&p).unwrap();
            (p, text)
        })
        .collect()
}

#[test]
fn no_function_in_src_is_longer_than_eighty_lines() {
    let mut long = Vec::new();
    for (path, text) in sources() {
        for (name, line, lines) in functions(&text) {
            if lines > MAX_FUNCTION_LINES {
                long.push(format!("{}:{line} {name} {lines}", path.display()));
            }
        }
    }
    assert!(
        long.is_empty(),
        "functions over {MAX_FUNCTION_LINES} lines: {long:#?}"
    );
}

#[test]
fn no_file_in_src_is_longer_than_a_thousand_lines() {
    let long: Vec<String> = sources()
        .into_iter()
        .filter(|(_, text)| text.lines().count() > MAX_FILE_LINES)
        .map(|(p, text)| format!("{} {}", p.display(), text.lines().count()))
        .collect();
    assert!(
        long.is_empty(),
        "files over {MAX_FILE_LINES} lines: {long:#?}"
    );
}

#[test]
fn the_scanner_measures_bodies_and_skips_braces_in_text() {
    let body: String = (0..90).map(|k| format!("    let x{k} = {k};\n")).collect();
    let text = format!(
        "/// doc with fn fake() {{\ntrait T {{ fn decl(&self); }}\nfn long() {{\n{body}}}\n\
         fn short(s: &str) -> char {{\n    let _ = \"}} {{ fn inner() {{\";\n    let _: &'static str = r#\"}}\"#;\n    '{{'\n}}\n"
    );
    let found = functions(&text);
    let names: Vec<&str> = found.iter().map(|(n, _, _)| n.as_str()).collect();
    assert_eq!(names, ["long", "short"]);
    assert_eq!(found[0], ("long".to_string(), 3, 92));
    assert_eq!(found[1], ("short".to_string(), 95, 5));
}
