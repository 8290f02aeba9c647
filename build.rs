//! Build script: stamps the git commit into `blockworld --version` (`BLOCKWORLD_COMMIT`), or
//! "unknown" when the source is not a git checkout (a crate tarball, `cargo install` from a
//! copy).

use std::process::Command;

fn main() {
    let commit = Command::new("git")
        .args(["rev-parse", "--short", "HEAD"])
        .output()
        .ok()
        .filter(|o| o.status.success())
        .and_then(|o| String::from_utf8(o.stdout).ok())
        .map(|s| s.trim().to_string())
        .filter(|s| !s.is_empty())
        .unwrap_or_else(|| "unknown".to_string());
    println!("cargo:rustc-env=BLOCKWORLD_COMMIT={commit}");
    // Rebuild when HEAD moves (a commit, a checkout); the paths are relative to the package.
    for path in git_paths() {
        println!("cargo:rerun-if-changed={path}");
    }
}

/// The files whose change means another commit: HEAD and the ref it points at.
fn git_paths() -> Vec<String> {
    let git_dir = Command::new("git")
        .args(["rev-parse", "--git-dir"])
        .output()
        .ok()
        .filter(|o| o.status.success())
        .and_then(|o| String::from_utf8(o.stdout).ok())
        .map(|s| s.trim().to_string());
    let Some(git_dir) = git_dir else {
        return Vec::new();
    };
    let mut paths = vec![format!("{git_dir}/HEAD")];
    if let Ok(head) = std::fs::read_to_string(format!("{git_dir}/HEAD")) {
        if let Some(reference) = head.trim().strip_prefix("ref: ") {
            let common = Command::new("git")
                .args(["rev-parse", "--git-common-dir"])
                .output()
                .ok()
                .and_then(|o| String::from_utf8(o.stdout).ok())
                .map(|s| s.trim().to_string())
                .unwrap_or_else(|| git_dir.clone());
            paths.push(format!("{common}/{reference}"));
        }
    }
    paths
}
