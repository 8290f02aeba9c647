//! Atomic file output: every file is written to a temporary name beside its destination and
//! renamed into place, so an interrupted run (kill -9, full disk) never leaves a half-written
//! file under the final name.

use std::io::Write;
use std::path::{Path, PathBuf};

/// Pretty JSON with a final newline: the one layout of every JSON file blockworld writes (scene,
/// reconstruction, drawing and camera files, `dataset.json`), so the same value always gives
/// the same bytes. Values of plain data always serialize; a failure here is a bug.
pub fn pretty_json<T: serde::Serialize + ?Sized>(value: &T) -> String {
    let mut s = serde_json::to_string_pretty(value).expect("plain data serializes to JSON");
    s.push('\n');
    s
}

/// Writes `bytes` to `path` through a temporary file in the same directory and a rename, with
/// the data on disk before the rename (`fdatasync`). On any error the temporary file is removed
/// and `path` is untouched.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    write_atomic_with(path, bytes, FileSync::EveryFile)
}

/// When a file's data is forced to disk (docs/datasets.md "Settling", durability).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FileSync {
    /// `fdatasync` before the rename: the file survives a power loss once written.
    #[default]
    EveryFile,
    /// Rename only: the file survives a killed process (the page cache keeps it), not a power
    /// loss; for outputs whose resume re-hashes every file against its manifest, which finds
    /// and redoes what a power loss damaged (`generate`'s scenes and their done markers, docs/datasets.md
    /// "Settling"; `export-dataset`'s pictures and part files, docs/wireframe.md "Wireframe datasets"), where a sync per file makes the disk the bottleneck.
    Verified,
}

/// What an output path names before anything is written to it (docs/limits.md "Outputs").
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OutputTarget {
    /// Nothing yet, or a regular file: written to a temporary name and renamed into place.
    File,
    /// A character device or a FIFO (`/dev/null`, `/dev/stdout`, a named pipe): written
    /// through, never renamed over, so `-o /dev/null` discards the output.
    Stream,
}

/// Checks that `path` may take an output file: a regular file or nothing is replaced
/// atomically, a character device or FIFO is written through, and a directory, block device
/// or socket is refused with an `InvalidInput` error saying why. Every file blockworld writes
/// goes through this check (in [`write_atomic_with`]).
pub fn check_output_path(path: &Path) -> std::io::Result<OutputTarget> {
    let refuse = |what: &str| {
        Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            format!("is {what}, not a file; give a file name"),
        ))
    };
    let Ok(meta) = std::fs::metadata(path) else {
        return Ok(OutputTarget::File);
    };
    let kind = meta.file_type();
    if kind.is_file() {
        return Ok(OutputTarget::File);
    }
    if kind.is_dir() {
        return refuse("a directory");
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if kind.is_char_device() || kind.is_fifo() {
            return Ok(OutputTarget::Stream);
        }
        if kind.is_block_device() {
            return refuse("a block device");
        }
    }
    refuse("a socket or other special file")
}

/// [`write_atomic`] with the sync chosen by `sync`. A character device or FIFO is written
/// through and a directory refused ([`check_output_path`]).
pub fn write_atomic_with(path: &Path, bytes: &[u8], sync: FileSync) -> std::io::Result<()> {
    if check_output_path(path)? == OutputTarget::Stream {
        let mut f = std::fs::OpenOptions::new().write(true).open(path)?;
        return f.write_all(bytes).and_then(|()| f.flush());
    }
    let tmp = temp_path(path);
    let result = (|| {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        if sync == FileSync::EveryFile {
            f.sync_data()?;
        }
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

/// Longest echo of a number in a message, in characters, before [`echo_number`] switches to
/// scientific form.
pub const MAX_ECHO_CHARS: usize = 20;

/// `value` as a message echoes it: as written by `{}` when that is at most [`MAX_ECHO_CHARS`]
/// characters (`95`, `0.25`), else in scientific form (`1e300`, `-1.5e-300`), so an
/// out-of-range number never fills the terminal with its hundreds of digits.
pub fn echo_number(value: f64) -> String {
    let plain = value.to_string();
    if plain.len() <= MAX_ECHO_CHARS {
        plain
    } else {
        format!("{value:e}")
    }
}

/// Reads a UTF-8 text file (scene, camera, drawing) with errors a user can act on: a leading
/// byte-order mark is named as such (JSON forbids it; many Windows editors add it) and invalid
/// UTF-8 gives the byte offset of the first bad byte. Both are `InvalidData` errors.
pub fn read_text(path: &Path) -> std::io::Result<String> {
    let why = "more than any scene, camera or drawing file (a million blocks take about 60 MiB); \
               give the right file";
    read_text_at_most(path, MAX_TEXT_BYTES, why)
}

/// [`read_text`] of a file of at most `max_bytes`: a larger regular file is refused before it
/// is read, an endless one (`/dev/zero`) once `max_bytes` are read; the error says the bound
/// and `why` (why no right file is larger, and the fix).
pub fn read_text_at_most(path: &Path, max_bytes: u64, why: &str) -> std::io::Result<String> {
    text_from_bytes(read_bytes_at_most(path, max_bytes, why)?)
}

/// The bytes of a file of at most `max_bytes` (a trajectory, a picture): the bound of
/// [`read_text_at_most`] without its text checks.
pub fn read_bytes_at_most(path: &Path, max_bytes: u64, why: &str) -> std::io::Result<Vec<u8>> {
    use std::io::Read;
    let file = std::fs::File::open(path)?;
    let too_large = || {
        std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!("is larger than {} MiB, {why}", max_bytes >> 20),
        )
    };
    if file.metadata()?.len() > max_bytes {
        return Err(too_large());
    }
    let mut bytes = Vec::new();
    file.take(max_bytes + 1).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > max_bytes {
        return Err(too_large());
    }
    Ok(bytes)
}

/// Largest text input read, bytes (128 MiB): reading stops there, so `/dev/zero` or an endless
/// pipe given as a scene is an error, not an exhausted memory.
pub const MAX_TEXT_BYTES: u64 = 128 << 20;

/// The checks of [`read_text`] on bytes already read.
pub fn text_from_bytes(bytes: Vec<u8>) -> std::io::Result<String> {
    const BOM: &[u8] = b"\xEF\xBB\xBF";
    let invalid = |m: String| std::io::Error::new(std::io::ErrorKind::InvalidData, m);
    if bytes.starts_with(BOM) {
        return Err(invalid(
            "starts with a UTF-8 byte-order mark (BOM, bytes EF BB BF), which JSON does not allow; \
             save the file as UTF-8 without BOM"
                .to_string(),
        ));
    }
    String::from_utf8(bytes).map_err(|e| {
        let at = e.utf8_error().valid_up_to();
        let byte = e.as_bytes()[at];
        invalid(format!(
            "is not UTF-8: byte 0x{byte:02X} at byte offset {at} is invalid; save the file as UTF-8"
        ))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn echoed_numbers_are_short_whatever_their_size() {
        assert_eq!(echo_number(95.0), "95");
        assert_eq!(echo_number(-0.25), "-0.25");
        assert_eq!(echo_number(1e300), "1e300");
        assert_eq!(echo_number(-1.5e-300), "-1.5e-300");
        assert!(echo_number(f64::MAX).len() <= 2 * MAX_ECHO_CHARS);
    }

    #[test]
    fn both_syncs_write_the_same_bytes_and_leave_no_temporary_file() {
        let dir = tempfile::tempdir().unwrap();
        for (name, sync) in [
            ("a.txt", FileSync::EveryFile),
            ("b.txt", FileSync::Verified),
        ] {
            write_atomic_with(&dir.path().join(name), b"scene", sync).unwrap();
        }
        let names: Vec<String> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        assert_eq!(names.len(), 2, "{names:?}");
        for n in ["a.txt", "b.txt"] {
            assert_eq!(std::fs::read(dir.path().join(n)).unwrap(), b"scene");
        }
        let missing = dir.path().join("no/such/dir/c.txt");
        assert!(write_atomic_with(&missing, b"x", FileSync::Verified).is_err());
    }

    #[test]
    fn bom_and_invalid_utf8_are_named_with_the_offset() {
        let bom = text_from_bytes(b"\xEF\xBB\xBF{}".to_vec())
            .unwrap_err()
            .to_string();
        assert!(bom.contains("byte-order mark"), "{bom}");
        let bad = text_from_bytes(b"{\"a\": \xFF}".to_vec())
            .unwrap_err()
            .to_string();
        assert!(bad.contains("0xFF at byte offset 6"), "{bad}");
        assert_eq!(text_from_bytes(b"{}".to_vec()).unwrap(), "{}");
    }

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
    fn a_fifo_is_written_through_and_a_directory_refused() {
        // A rename over a FIFO or device node (`-o /dev/null`) would replace it by a regular
        // file; the bytes must go through it instead.
        use std::os::unix::fs::FileTypeExt;
        let null = Path::new("/dev/null");
        assert_eq!(check_output_path(null).unwrap(), OutputTarget::Stream);
        let dir = tempfile::tempdir().unwrap();
        let fifo = dir.path().join("pipe");
        let made = std::process::Command::new("mkfifo").arg(&fifo).status();
        assert!(made.unwrap().success());
        let reader = {
            let fifo = fifo.clone();
            std::thread::spawn(move || std::fs::read(fifo).unwrap())
        };
        write_atomic(&fifo, b"through").unwrap();
        assert!(std::fs::metadata(&fifo).unwrap().file_type().is_fifo());
        assert_eq!(reader.join().unwrap(), b"through");
        let err = write_atomic(dir.path(), b"x").unwrap_err().to_string();
        assert!(err.contains("is a directory"), "{err}");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
        let new = dir.path().join("new.json");
        assert_eq!(check_output_path(&new).unwrap(), OutputTarget::File);
    }

    #[test]
    fn temporary_names_differ_within_one_process() {
        let p = Path::new("/x/a.json");
        assert_ne!(temp_path(p), temp_path(p));
        assert_eq!(temp_path(p).parent(), p.parent());
    }
}
