//! The crate's architecture as a test (style guide §3): data flows one way through the stages,
//! and each external crate lives in one stage. Scans `use crate::...` / `crate::...` paths in
//! each module's source files.

mod common;

use common::rust_files;
use std::collections::BTreeSet;
use std::path::Path;

/// Stage -> the crate modules it may use. A stage not listed here fails the test, so a new
/// stage must declare its place in the flow.
const ALLOWED: &[(&str, &[&str])] = &[
    ("geom", &[]),
    ("io", &[]),
    ("camera", &["geom", "io"]),
    ("drawing", &["geom", "io"]),
    ("scene", &["geom", "io"]),
    ("physics", &["scene", "geom"]),
    ("linedraw", &["scene", "drawing", "camera", "geom"]),
    (
        "render",
        &["scene", "drawing", "linedraw", "camera", "geom", "io"],
    ),
    ("output", &["render", "drawing", "camera", "io", "geom"]),
    ("vision", &["drawing", "camera", "geom"]),
    ("score", &["scene", "drawing", "geom"]),
    (
        "dataset",
        &[
            "scene", "physics", "render", "output", "drawing", "camera", "io", "geom", "export",
            "vision",
        ],
    ),
    (
        "recognize",
        &["drawing", "linedraw", "scene", "camera", "geom"],
    ),
    ("csg", &["recognize", "scene", "camera", "geom"]),
    ("kanade", &["drawing", "camera", "geom"]),
    (
        "view",
        &["scene", "drawing", "linedraw", "camera", "geom", "io"],
    ),
    ("export", &["scene", "drawing", "camera", "geom", "io"]),
    (
        "pipeline",
        &[
            "scene",
            "render",
            "vision",
            "recognize",
            "csg",
            "score",
            "physics",
            "drawing",
            "camera",
            "geom",
        ],
    ),
    (
        "report",
        &["scene", "drawing", "recognize", "score", "geom"],
    ),
    ("cli", &["*"]),
];

/// Stages that must not depend on the renderer (docs/architecture.md "Stages"): what feeds it, and
/// `vision`, which reads any picture with its camera, rendered or photographed.
const BELOW_RENDER: &[&str] = &[
    "geom", "io", "camera", "drawing", "scene", "physics", "vision",
];

/// Stages after the renderer in the flow that still must not import it: they need the exact
/// line drawing (`linedraw`, pure geometry) or the scene, never the GPU code or its pictures.
const NOT_RENDER_CLIENTS: &[&str] = &["recognize", "kanade", "view", "score", "report"];

/// External crate -> the only stages (path prefixes under src/) that may name it.
const EXTERNAL_HOMES: &[(&str, &[&str])] = &[
    ("wgpu", &["render/gpu"]),
    ("rapier3d", &["physics"]),
    ("parry3d", &["score"]),
    ("clap", &["cli"]),
    ("anyhow", &["cli"]),
    ("gltf", &["export"]),
    ("rerun", &["export/rrd"]),
    ("indicatif", &["cli"]),
    (
        "libc",
        &["dataset/lock", "dataset/memory", "dataset/placement"],
    ),
    ("png", &["output"]),
];

fn crate_modules_used(text: &str) -> BTreeSet<String> {
    let mut used = BTreeSet::new();
    for (i, _) in text.match_indices("crate::") {
        let rest = &text[i + "crate::".len()..];
        let name: String = rest
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect();
        if !name.is_empty() {
            used.insert(name);
        }
    }
    // `use crate::{a, b::c}` groups.
    for (i, _) in text.match_indices("crate::{") {
        let rest = &text[i + "crate::{".len()..];
        let group = &rest[..rest.find('}').unwrap_or(0)];
        for item in group.split(',') {
            let name: String = item
                .trim()
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect();
            if !name.is_empty() {
                used.insert(name);
            }
        }
    }
    used
}

fn stage_of(src: &Path, file: &Path) -> String {
    let rel = file.strip_prefix(src).unwrap();
    let first = rel
        .components()
        .next()
        .unwrap()
        .as_os_str()
        .to_string_lossy();
    first.trim_end_matches(".rs").to_string()
}

#[test]
fn stages_import_only_upstream() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let mut violations = Vec::new();
    for f in &files {
        let stage = stage_of(&src, f);
        if stage == "lib" || stage == "main" {
            continue;
        }
        let Some((_, allowed)) = ALLOWED.iter().find(|(s, _)| *s == stage) else {
            violations.push(format!(
                "{}: stage {stage:?} is not in ALLOWED",
                f.display()
            ));
            continue;
        };
        if allowed.contains(&"*") {
            continue;
        }
        let text = std::fs::read_to_string(f).unwrap();
        for used in crate_modules_used(&text) {
            if used != stage && !allowed.contains(&used.as_str()) {
                violations.push(format!("{}: {stage} uses crate::{used}", f.display()));
            }
        }
    }
    assert!(
        violations.is_empty(),
        "layering violations:\n{}",
        violations.join("\n")
    );
}

#[test]
fn no_stage_below_render_imports_render() {
    for (stage, allowed) in ALLOWED {
        if BELOW_RENDER.contains(stage) {
            assert!(
                !allowed.contains(&"render") && !allowed.contains(&"*"),
                "{stage} comes before render in the flow but may import it"
            );
        }
    }
}

#[test]
fn the_line_drawing_stages_do_not_import_the_renderer() {
    for stage in NOT_RENDER_CLIENTS {
        let Some((_, allowed)) = ALLOWED.iter().find(|(s, _)| s == stage) else {
            panic!("{stage} is not in ALLOWED");
        };
        assert!(
            !allowed.contains(&"render") && !allowed.contains(&"*"),
            "{stage} may import render: it needs only the exact line drawing (crate::linedraw)"
        );
    }
    let allowed_linedraw = ALLOWED.iter().find(|(s, _)| *s == "linedraw").unwrap().1;
    assert!(
        !allowed_linedraw.contains(&"render"),
        "linedraw is pure geometry and must not import render"
    );
}

#[test]
fn external_crates_live_in_one_stage() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let mut violations = Vec::new();
    for f in &files {
        let rel = f.strip_prefix(&src).unwrap().to_string_lossy().to_string();
        let text = std::fs::read_to_string(f).unwrap();
        for (krate, homes) in EXTERNAL_HOMES {
            let named =
                text.contains(&format!("{krate}::")) || text.contains(&format!("use {krate}"));
            if named && !homes.iter().any(|h| rel.starts_with(h)) {
                violations.push(format!("{rel} names {krate} (allowed only in {homes:?})"));
            }
        }
    }
    assert!(violations.is_empty(), "{}", violations.join("\n"));
}

#[test]
fn the_command_line_belongs_to_the_binary() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let lib = std::fs::read_to_string(root.join("lib.rs")).unwrap();
    assert!(
        !lib.contains("mod cli"),
        "src/lib.rs declares the cli: the library must not carry clap, anyhow or indicatif"
    );
    let main = std::fs::read_to_string(root.join("main.rs")).unwrap();
    assert!(
        main.contains("mod cli;"),
        "src/main.rs must declare the cli"
    );
}

#[test]
fn the_scanner_sees_groups_and_paths() {
    let used = crate_modules_used(
        "use crate::{geom::DVec3, scene::Scene};\nlet x = crate::io::write_atomic;",
    );
    assert_eq!(
        used.into_iter().collect::<Vec<_>>(),
        vec!["geom".to_string(), "io".to_string(), "scene".to_string()]
    );
}
