//! How the dataset writer keeps its picture buffers: each scene allocates and frees about 5 MB
//! of pictures (four views of gray, depth and ids at 512 x 480). glibc's allocator hands blocks
//! of that size back to the kernel when they are freed (`mmap` threshold and heap trimming), so
//! every scene faulted in fresh zeroed pages again. Measured with `perf stat` on `bench
//! generate` (docs/benchmarks.md "Benchmarks"): 60,000-141,000 page faults per 100 scenes, about 11,700
//! with the heap kept, and the median CPU time of four runs 8% lower. The output does not
//! change.

/// Largest block glibc still serves from the heap instead of a fresh `mmap` (32 MiB, glibc's
/// own upper bound for this threshold): bigger pictures (above 2,900 x 2,900 px) keep mapping.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
const MMAP_THRESHOLD_BYTES: libc::c_int = 32 << 20;

/// Free bytes at the heap's top before glibc returns them to the kernel (256 MiB): the
/// scene-sized churn stays in the heap.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
const TRIM_THRESHOLD_BYTES: libc::c_int = 256 << 20;

/// Keeps freed picture buffers in the heap for the rest of the process (glibc on Linux; a no-op
/// elsewhere). Called by [`super::generate_dataset`] and once at the start of the `blockworld`
/// binary: every command handles pictures (the vision front end allocates and frees about 1 MB
/// per view, which glibc otherwise trims and faults in again, about 0.1 ms per view); returns
/// whether both settings took.
pub fn keep_freed_pictures_in_heap() -> bool {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    {
        static DONE: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
        *DONE.get_or_init(|| {
            // SAFETY: mallopt only changes glibc's allocation thresholds, under glibc's own arena
            // lock (safe beside other threads), with values glibc documents as valid.
            let mmap = unsafe { libc::mallopt(libc::M_MMAP_THRESHOLD, MMAP_THRESHOLD_BYTES) };
            let trim = unsafe { libc::mallopt(libc::M_TRIM_THRESHOLD, TRIM_THRESHOLD_BYTES) };
            mmap == 1 && trim == 1
        })
    }
    #[cfg(not(all(target_os = "linux", target_env = "gnu")))]
    {
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    #[test]
    fn glibc_accepts_the_thresholds_and_allocation_still_works() {
        assert!(keep_freed_pictures_in_heap());
        assert!(keep_freed_pictures_in_heap(), "a second call is harmless");
        let pictures: Vec<Vec<u16>> = (0..8).map(|i| vec![i as u16; 512 * 480]).collect();
        assert_eq!(pictures[7][512 * 480 - 1], 7);
    }
}
