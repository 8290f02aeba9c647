//! Where a dataset's scene folders go on disk (docs/datasets.md "Settling", file system).
//!
//! `generate` creates 22 files per scene (four views of five files, `scene.json`, `done.json`).
//! On ext4 without a journal (this project's machines), creating a file skips, one by one,
//! every inode of its block group that was freed in the last minute or so (`recently_deleted`
//! in the kernel's inode allocator), looking each one up in the buffer cache. A folder that
//! shares its block group with freshly deleted files (a dataset written where the previous one
//! was just removed, or a `/tmp` that other programs empty) paid that scan for every file:
//! `perf` put a quarter to a half of `generate`'s CPU time in it. Marking the dataset folder
//! as the top of unrelated folder trees (ext4's `T` attribute, `chattr +T`) makes ext4's
//! folder allocator (Orlov) place each scene folder in a block group of its own choosing, one
//! with few folders and free inodes above average, rather than beside its parent; the scene's
//! files follow their folder. It changes where inodes go, never what the files hold.

use std::path::Path;

/// ext4's "top of directory hierarchies" inode flag, `FS_TOPDIR_FL` of `linux/fs.h`.
#[cfg(target_os = "linux")]
const TOPDIR_FLAG: libc::c_int = 0x0002_0000;

/// Marks the folder `dir` as the top of unrelated folder trees (ext4's `T` attribute), so the
/// file system spreads the scene folders created in it over its block groups. Returns whether
/// the folder now carries the flag: `false` where the file system has no such flag (tmpfs, XFS,
/// network file systems answer the request with an error) or on other systems, which is
/// harmless: the dataset is the same either way.
pub fn spread_scene_folders(dir: &Path) -> bool {
    #[cfg(target_os = "linux")]
    {
        use std::os::fd::AsRawFd;
        let Ok(folder) = std::fs::File::open(dir) else {
            return false;
        };
        if !folder.metadata().is_ok_and(|m| m.is_dir()) {
            return false;
        }
        let Some(mut flags) = inode_flags(&folder) else {
            return false;
        };
        if flags & TOPDIR_FLAG != 0 {
            return true;
        }
        flags |= TOPDIR_FLAG;
        // SAFETY: FS_IOC_SETFLAGS reads one int through a pointer to a live local; the file is
        // open for the call's whole duration.
        let fd = folder.as_raw_fd();
        unsafe { libc::ioctl(fd, libc::FS_IOC_SETFLAGS, &flags as *const libc::c_int) == 0 }
    }
    #[cfg(not(target_os = "linux"))]
    {
        let _ = dir;
        false
    }
}

/// The inode flags of an open file (what `lsattr` shows), `None` where the file system has
/// none to give.
#[cfg(target_os = "linux")]
fn inode_flags(file: &std::fs::File) -> Option<libc::c_int> {
    use std::os::fd::AsRawFd;
    let mut flags: libc::c_int = 0;
    // SAFETY: FS_IOC_GETFLAGS writes one int (the kernel's `put_user(flags, (int *)arg)`)
    // through a pointer to a live local; the file is open for the call's whole duration.
    let ok = unsafe {
        libc::ioctl(
            file.as_raw_fd(),
            libc::FS_IOC_GETFLAGS,
            &mut flags as *mut libc::c_int,
        )
    } == 0;
    ok.then_some(flags)
}

/// Whether `dir` carries ext4's top-of-hierarchies flag (what `lsattr -d` shows as `T`).
#[cfg(all(test, target_os = "linux"))]
fn has_topdir_flag(dir: &Path) -> bool {
    std::fs::File::open(dir)
        .ok()
        .and_then(|folder| inode_flags(&folder))
        .is_some_and(|flags| flags & TOPDIR_FLAG != 0)
}

#[cfg(all(test, target_os = "linux"))]
mod tests {
    use super::*;

    /// Whether `dir` is on ext4 (ext2 and ext3 share the magic number and the flag).
    fn is_ext4(dir: &Path) -> bool {
        use std::os::unix::ffi::OsStrExt;
        const EXT4_SUPER_MAGIC: i64 = 0xEF53;
        let path = std::ffi::CString::new(dir.as_os_str().as_bytes()).unwrap();
        // SAFETY: statfs fills the zeroed struct through a pointer to a live local; the path
        // is a NUL-terminated C string that outlives the call.
        let mut fs: libc::statfs = unsafe { std::mem::zeroed() };
        let ok = unsafe { libc::statfs(path.as_ptr(), &mut fs) } == 0;
        ok && fs.f_type as i64 == EXT4_SUPER_MAGIC
    }

    /// Where the file system takes the flag (ext4, as on this project's machines) the folder
    /// carries it afterwards and a second call is harmless; elsewhere nothing is claimed. A
    /// file or a missing path is refused without a panic.
    #[test]
    fn the_flag_is_set_where_the_file_system_has_it_and_files_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let folder = dir.path().join("dataset");
        std::fs::create_dir(&folder).unwrap();
        assert!(!has_topdir_flag(&folder), "a new folder has no T attribute");
        let spread = spread_scene_folders(&folder);
        if is_ext4(&folder) {
            assert!(spread, "ext4 takes the T attribute");
        }
        if spread {
            assert!(has_topdir_flag(&folder));
            assert!(spread_scene_folders(&folder));
            // Folders made inside it are still ordinary folders holding ordinary files.
            std::fs::create_dir(folder.join("s000000")).unwrap();
            std::fs::write(folder.join("s000000/scene.json"), b"{}").unwrap();
            assert_eq!(
                std::fs::read(folder.join("s000000/scene.json")).unwrap(),
                b"{}"
            );
        } else {
            assert!(!has_topdir_flag(&folder));
        }
        let file = dir.path().join("file");
        std::fs::write(&file, b"x").unwrap();
        assert!(!spread_scene_folders(&file));
        assert!(!spread_scene_folders(&dir.path().join("missing")));
    }
}
