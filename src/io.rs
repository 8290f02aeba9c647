//! Atomic file output: every file is written to a temporary name beside its destination and
//! renamed into place, so an interrupted run (kill -9, full disk) never leaves a half-written
//! file under the final name.

use std::io::Write;
use std::path::{Path, PathBuf};

/// Writes `bytes` to `path` through a temporary file in the same directory and a rename.
/// On any error the temporary file is removed and `path` is untouched.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let tmp = temp_path(path);
    let result = (|| {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_data()?;
        drop(f);
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// A temporary name for `path` in the same directory: `.<name>.tmp.<pid>.<random>`. The random
/// part keeps writers apart that share a process id (every Kubernetes pod runs as PID 1, and
/// shards on a shared volume write the same names) or a process (threads).
pub fn temp_path(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let unique: u64 = rand::random();
    path.with_file_name(format!(".{name}.tmp.{}.{unique:016x}", std::process::id()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn writes_and_leaves_no_temporary() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.txt");
        write_atomic(&p, b"hello").unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"hello");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
        let missing = dir.path().join("no/such/dir/a.txt");
        assert!(write_atomic(&missing, b"x").is_err());
    }

    #[test]
    fn temporary_names_differ_within_one_process() {
        let p = Path::new("/x/a.json");
        assert_ne!(temp_path(p), temp_path(p));
        assert_eq!(temp_path(p).parent(), p.parent());
    }
}
