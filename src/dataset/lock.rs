//! The dataset lock (docs/datasets.md "Settling", concurrent writers): two runs writing the
//! same scenes into one folder would delete each other's temporary files, so a writer takes
//! `flock` locks first. A whole-dataset run holds `.lock` exclusively; a shard run holds `.lock`
//! shared plus `.lock.shard-I-of-N` exclusively, so the shards of one dataset written by
//! separate processes (Slurm, Kubernetes) run side by side while the same shard, or a whole run
//! beside a shard run, is refused. Each holder writes "pid P on host H" into the file it holds
//! exclusively, and a refused writer names it. A finished run removes its lock files (the last
//! shard out removes `.lock`), so a dataset's files are the same whoever wrote it; one left by a
//! killed run holds no lock (the kernel drops it with the process) and the next run reuses it.

use super::{DatasetError, Shard};
use std::fs::{File, OpenOptions};
use std::io::Write;
use std::path::{Path, PathBuf};

/// Held locks; dropping it removes the lock files it may remove and releases them.
#[derive(Debug)]
pub struct DatasetLock {
    /// (file, path, held exclusively), `.lock` first.
    held: Vec<(File, PathBuf, bool)>,
}

impl Drop for DatasetLock {
    fn drop(&mut self) {
        while let Some((file, path, exclusive)) = self.held.pop() {
            // A shared holder removes `.lock` only when it is the last one (it can turn its
            // lock exclusive); a writer that opened the file meanwhile sees it unlinked and
            // retries on a fresh file.
            if exclusive || try_flock(&file, true).is_ok() {
                let _ = std::fs::remove_file(&path);
            }
        }
    }
}

/// Takes the locks for writing `shard` of the dataset in `dir` (which must exist), or returns
/// [`DatasetError::Locked`] naming the run that holds them.
pub fn lock_dataset(dir: &Path, shard: Shard) -> Result<DatasetLock, DatasetError> {
    let main = dir.join(".lock");
    if shard.is_whole() {
        let file = acquire(&main, true, || holders(dir))?;
        write_holder(&file);
        return Ok(DatasetLock {
            held: vec![(file, main, true)],
        });
    }
    let main_file = acquire(&main, false, || read_holder(&main))?;
    let mut lock = DatasetLock {
        held: vec![(main_file, main, false)],
    };
    let own = dir.join(format!(".lock.shard-{}-of-{}", shard.index, shard.count));
    let own_file = acquire(&own, true, || read_holder(&own))?;
    write_holder(&own_file);
    lock.held.push((own_file, own, true));
    Ok(lock)
}

/// Opens and locks `path`, retrying when the file was removed under us by a finishing run
/// (then the lock we got is on a stale file) or a run is just leaving.
fn acquire(
    path: &Path,
    exclusive: bool,
    holder: impl FnOnce() -> String,
) -> Result<File, DatasetError> {
    const ATTEMPTS: u32 = 5;
    for attempt in 1..=ATTEMPTS {
        let file = open(path)?;
        match try_flock(&file, exclusive) {
            Ok(()) if is_current(&file, path) => return Ok(file),
            Ok(()) => continue,
            Err(Busy::Held) if attempt < ATTEMPTS => {
                std::thread::sleep(std::time::Duration::from_millis(20));
            }
            Err(Busy::Held) => {
                return Err(DatasetError::Locked {
                    path: path.to_path_buf(),
                    holder: holder(),
                })
            }
            Err(Busy::Io(source)) => {
                return Err(DatasetError::Io {
                    path: path.to_path_buf(),
                    source,
                })
            }
        }
    }
    Err(DatasetError::Locked {
        path: path.to_path_buf(),
        holder: "runs starting and finishing at the same moment; try again".to_string(),
    })
}

/// Why a lock was not taken.
enum Busy {
    /// Another open file holds a conflicting lock.
    Held,
    /// flock(2) failed otherwise.
    Io(std::io::Error),
}

/// `flock(2)` without blocking: exclusive or shared. On Linux it also works across the hosts
/// of an NFS share (emulated with byte-range locks), as a Slurm cluster's datasets need.
fn try_flock(file: &File, exclusive: bool) -> Result<(), Busy> {
    use std::os::unix::io::AsRawFd;
    let op = if exclusive {
        libc::LOCK_EX
    } else {
        libc::LOCK_SH
    };
    // SAFETY: flock only reads the descriptor number, which `file` keeps open for the call.
    let rc = unsafe { libc::flock(file.as_raw_fd(), op | libc::LOCK_NB) };
    if rc == 0 {
        return Ok(());
    }
    let e = std::io::Error::last_os_error();
    match e.raw_os_error() {
        Some(libc::EWOULDBLOCK) => Err(Busy::Held),
        _ => Err(Busy::Io(e)),
    }
}

/// Whether `file` is still the file at `path` (not removed by a run that finished).
fn is_current(file: &File, path: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (file.metadata(), std::fs::metadata(path)) {
        (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
        _ => false,
    }
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

/// "pid P on host H" (every Kubernetes pod is PID 1, so the host tells pods apart).
fn this_run() -> String {
    let host = std::fs::read_to_string("/proc/sys/kernel/hostname").unwrap_or_default();
    format!("pid {} on host {}", std::process::id(), host.trim())
}

/// Best effort: the record only names the holder in a refusal (a full disk must not stop a
/// run that could resume).
fn write_holder(mut file: &File) {
    let _ = file.set_len(0);
    let _ = file.write_all(this_run().as_bytes());
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
        .filter(|p| File::open(p).is_ok_and(|f| try_flock(&f, true).is_err()))
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
        drop(lock_dataset(dir.path(), Shard::WHOLE).unwrap());
        let left: Vec<_> = std::fs::read_dir(dir.path()).unwrap().flatten().collect();
        assert!(left.is_empty(), "lock files removed when done: {left:?}");
    }
}
