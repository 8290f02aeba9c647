//! The dataset lock (README "Settling and datasets", concurrent writers): two runs writing the
//! same scenes into one folder would delete each other's temporary files, so a writer takes
//! `flock` locks first. A whole-dataset run holds `.lock` exclusively; a shard run holds `.lock`
//! shared plus `.lock.shard-I-of-N` exclusively, so the shards of one dataset written by
//! separate processes (Slurm, Kubernetes) run side by side while the same shard, or a whole run
//! beside a shard run, is refused. Each holder writes "pid P on host H" into the file it holds
//! exclusively, and a refused writer names it. The kernel drops a lock when its process dies
//! (kill -9 included), so nothing stale is ever left to clean up.

use super::{DatasetError, Shard};
use std::fs::{File, OpenOptions, TryLockError};
use std::io::Write;
use std::path::{Path, PathBuf};

/// Held locks; dropping it releases them.
#[derive(Debug)]
pub struct DatasetLock {
    _files: Vec<File>,
}

/// Takes the locks for writing `shard` of the dataset in `dir` (which must exist), or returns
/// [`DatasetError::Locked`] naming the run that holds them.
pub fn lock_dataset(dir: &Path, shard: Shard) -> Result<DatasetLock, DatasetError> {
    let main = dir.join(".lock");
    let main_file = open(&main)?;
    if shard.is_whole() {
        try_lock(&main_file, true, &main, || holders(dir))?;
        write_holder(&main_file, &main)?;
        return Ok(DatasetLock {
            _files: vec![main_file],
        });
    }
    try_lock(&main_file, false, &main, || read_holder(&main))?;
    let own = dir.join(format!(".lock.shard-{}-of-{}", shard.index, shard.count));
    let own_file = open(&own)?;
    try_lock(&own_file, true, &own, || read_holder(&own))?;
    write_holder(&own_file, &own)?;
    Ok(DatasetLock {
        _files: vec![main_file, own_file],
    })
}

fn open(path: &Path) -> Result<File, DatasetError> {
    OpenOptions::new()
        .read(true)
        .write(true)
        .create(true)
        .truncate(false)
        .open(path)
        .map_err(|source| DatasetError::Io {
            path: path.to_path_buf(),
            source,
        })
}

fn try_lock(
    file: &File,
    exclusive: bool,
    path: &Path,
    holder: impl FnOnce() -> String,
) -> Result<(), DatasetError> {
    let result = if exclusive {
        file.try_lock()
    } else {
        file.try_lock_shared()
    };
    match result {
        Ok(()) => Ok(()),
        Err(TryLockError::WouldBlock) => Err(DatasetError::Locked {
            path: path.to_path_buf(),
            holder: holder(),
        }),
        Err(TryLockError::Error(source)) => Err(DatasetError::Io {
            path: path.to_path_buf(),
            source,
        }),
    }
}

/// "pid P on host H" (every Kubernetes pod is PID 1, so the host tells pods apart).
fn this_run() -> String {
    let host = std::fs::read_to_string("/proc/sys/kernel/hostname").unwrap_or_default();
    format!("pid {} on host {}", std::process::id(), host.trim())
}

fn write_holder(mut file: &File, path: &Path) -> Result<(), DatasetError> {
    let io = |source| DatasetError::Io {
        path: path.to_path_buf(),
        source,
    };
    file.set_len(0).map_err(io)?;
    file.write_all(this_run().as_bytes()).map_err(io)
}

fn read_holder(path: &Path) -> String {
    match std::fs::read_to_string(path) {
        Ok(s) if !s.trim().is_empty() => s.trim().to_string(),
        _ => "a run that has not written its pid yet".to_string(),
    }
}

/// Who holds the whole-dataset lock: the whole run's own record, else the shard runs'.
fn holders(dir: &Path) -> String {
    let mut shard_files: Vec<PathBuf> = std::fs::read_dir(dir)
        .map(|d| d.flatten().map(|e| e.path()).collect())
        .unwrap_or_default();
    shard_files.retain(|p| {
        p.file_name()
            .is_some_and(|n| n.to_string_lossy().starts_with(".lock.shard-"))
    });
    shard_files.sort();
    let held: Vec<String> = shard_files
        .iter()
        .filter(|p| File::open(p).is_ok_and(|f| f.try_lock().is_err()))
        .map(|p| read_holder(p))
        .collect();
    if held.is_empty() {
        read_holder(&dir.join(".lock"))
    } else {
        format!("shard runs: {}", held.join(", "))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Regression: two runs into one folder deleted each other's temporary files; the second
    /// writer is refused naming the first's pid, while different shards share the folder.
    #[test]
    fn a_second_writer_is_refused_and_shards_coexist() {
        let dir = tempfile::tempdir().unwrap();
        let whole = lock_dataset(dir.path(), Shard::WHOLE).unwrap();
        let err = lock_dataset(dir.path(), Shard::WHOLE)
            .unwrap_err()
            .to_string();
        assert!(
            err.contains(&format!("pid {}", std::process::id())),
            "{err}"
        );
        assert!(lock_dataset(dir.path(), Shard::new(0, 2).unwrap()).is_err());
        drop(whole);
        let s0 = lock_dataset(dir.path(), Shard::new(0, 2).unwrap()).unwrap();
        let s1 = lock_dataset(dir.path(), Shard::new(1, 2).unwrap()).unwrap();
        let again = lock_dataset(dir.path(), Shard::new(1, 2).unwrap()).unwrap_err();
        assert!(again.to_string().contains("pid"), "{again}");
        let err = lock_dataset(dir.path(), Shard::WHOLE)
            .unwrap_err()
            .to_string();
        assert!(err.contains("shard runs"), "{err}");
        drop((s0, s1));
        lock_dataset(dir.path(), Shard::WHOLE).unwrap();
    }
}
