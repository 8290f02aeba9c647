//! docs/cli.md is generated from the clap definitions (`blockworld docs cli`, `make docs`):
//! this fails when the committed page is not what the parser describes, and shows how it
//! fails on a stale page.

mod common;

/// What `blockworld docs cli` prints.
fn generated_page() -> String {
    common::ok(common::blockworld(["docs", "cli"]))
}

/// The first line where `committed` differs from `generated`, for the failure message.
fn first_difference(committed: &str, generated: &str) -> Option<(usize, String, String)> {
    let (mut a, mut b) = (committed.lines(), generated.lines());
    for n in 1.. {
        match (a.next(), b.next()) {
            (None, None) => return None,
            (x, y) if x == y => continue,
            (x, y) => {
                let show = |l: Option<&str>| l.unwrap_or("<end of page>").to_string();
                return Some((n, show(x), show(y)));
            }
        }
    }
    None
}

/// Why a committed page is out of date, or None when it is the generated one.
fn stale(committed: &str, generated: &str) -> Option<String> {
    first_difference(committed, generated).map(|(line, was, now)| {
        format!(
            "docs/cli.md is out of date at line {line}:\n  page: {was}\n  now:  {now}\n\
             run `make docs` (blockworld docs cli > docs/cli.md) and commit the page"
        )
    })
}

#[test]
fn cli_page_is_generated_from_the_current_definitions() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let committed = std::fs::read_to_string(root.join("docs/cli.md")).expect("docs/cli.md");
    let generated = generated_page();
    if let Some(why) = stale(&committed, &generated) {
        panic!("{why}");
    }
    // Every visible command has its section, and the page is not trivially empty.
    for command in [
        "render",
        "generate",
        "recognize",
        "export-dataset",
        "completions",
    ] {
        assert!(
            generated.contains(&format!("\n## blockworld {command}\n")),
            "no section for {command}"
        );
    }
    assert!(
        !generated.contains("## blockworld docs"),
        "the hidden generator is listed"
    );
}

#[test]
fn a_stale_page_is_caught() {
    let generated = generated_page();
    // A flag renamed in the parser but not on the page, and a page missing its last command.
    let renamed = generated.replacen("--output", "--out-dir", 1);
    let why = stale(&renamed, &generated).expect("a renamed flag is caught");
    assert!(
        why.contains("--out-dir") && why.contains("make docs"),
        "{why}"
    );
    let cut = &generated[..generated.rfind("\n## ").unwrap()];
    assert!(
        stale(cut, &generated).is_some(),
        "a missing section is caught"
    );
    assert!(stale(&generated, &generated).is_none());
}
