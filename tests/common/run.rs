//! The one runner of the `blockworld` binary built for these tests, and the checks of its
//! output that many tests share.

use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The binary built for these tests; for scripts that take it in `BLOCKWORLD`.
pub const BIN: &str = env!("CARGO_BIN_EXE_blockworld");

/// The variables through which a Slurm array job or a Kubernetes Indexed Job hands a task its
/// shard (docs/datasets.md); a test run inside such a job must not pass them on.
pub const SCALE_OUT_VARIABLES: [&str; 5] = [
    "SLURM_ARRAY_TASK_ID",
    "SLURM_ARRAY_TASK_COUNT",
    "SLURM_ARRAY_TASK_MIN",
    "SLURM_ARRAY_TASK_MAX",
    "JOB_COMPLETION_INDEX",
];

/// The binary as a command without arguments, for tests that need raw control (stdin, stdout,
/// `spawn`, extra variables, another working directory). The scale-out variables are removed
/// and `XDG_RUNTIME_DIR` is set, so a run inside a batch job or a container behaves as one at a
/// desktop.
pub fn command() -> Command {
    let mut c = Command::new(BIN);
    for v in SCALE_OUT_VARIABLES {
        c.env_remove(v);
    }
    c.env("XDG_RUNTIME_DIR", runtime_dir());
    c
}

/// Runs the binary with `args` (see [`command`]) and returns its output.
pub fn blockworld<I, S>(args: I) -> Output
where
    I: IntoIterator<Item = S>,
    S: AsRef<OsStr>,
{
    command()
        .args(args)
        .output()
        .expect("runs the blockworld binary")
}

/// Runs `blockworld export-dataset DATASET --format FORMAT -o OUT` and then `extra` flags.
pub fn export_dataset(dataset: &Path, format: &str, out: &Path, extra: &[&str]) -> Output {
    let (dataset, out) = (dataset.to_str().unwrap(), out.to_str().unwrap());
    let args = ["export-dataset", dataset, "--format", format, "-o", out];
    blockworld(args.iter().chain(extra))
}

/// The inherited `XDG_RUNTIME_DIR` when it is a directory, else a private one under cargo's
/// temporary folder for integration tests (mode 0700, as the XDG Base Directory
/// specification asks of it).
fn runtime_dir() -> PathBuf {
    if let Some(d) = std::env::var_os("XDG_RUNTIME_DIR").map(PathBuf::from) {
        if d.is_dir() {
            return d;
        }
    }
    let d = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("xdg-runtime");
    std::fs::create_dir_all(&d).expect("creates the runtime directory");
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(&d, std::fs::Permissions::from_mode(0o700))
        .expect("makes the runtime directory private");
    d
}

/// What the run printed on stderr.
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Asserts the run succeeded (printing both streams when not) and returns its stdout.
pub fn ok(o: impl std::borrow::Borrow<Output>) -> String {
    let o = o.borrow();
    assert!(
        o.status.success(),
        "stdout: {}\nstderr: {}",
        String::from_utf8_lossy(&o.stdout),
        stderr(o)
    );
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// Asserts exit code 2 with a message and no panic (the bad-input contract) and returns stderr.
pub fn fails_with_2(o: &Output) -> String {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(2), "stderr: {err}");
    assert!(!err.contains("panicked"), "{err}");
    err
}

/// Runs the binary with `args` and its stdout on `/dev/full`, where every write fails with
/// "No space left on device".
pub fn blockworld_to_full_stdout<I, S>(args: I) -> Output
where
    I: IntoIterator<Item = S>,
    S: AsRef<OsStr>,
{
    let full = std::fs::OpenOptions::new()
        .write(true)
        .open("/dev/full")
        .expect("/dev/full exists on Linux");
    command()
        .args(args)
        .stdout(full)
        .output()
        .expect("runs the blockworld binary")
}

/// Runs the binary with `args`, killing it after `limit_s` seconds; the output, and whether
/// it ended by itself in time.
pub fn blockworld_within<S: AsRef<OsStr>>(
    args: &[S],
    limit_s: u64,
) -> (std::process::Output, bool) {
    use std::process::Stdio;
    let mut child = command()
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let started = std::time::Instant::now();
    let mut in_time = true;
    while child.try_wait().unwrap().is_none() {
        if started.elapsed().as_secs() >= limit_s {
            child.kill().unwrap();
            in_time = false;
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    (child.wait_with_output().unwrap(), in_time)
}

/// `f` of every index in `0..count`, on `threads` threads (index `i` on thread `i % threads`),
/// in index order: for tests that run the binary many times.
pub fn map_on_threads<T: Send>(
    count: usize,
    threads: usize,
    f: impl Fn(usize) -> T + Sync,
) -> Vec<T> {
    let f = &f;
    let mut out: Vec<(usize, T)> = std::thread::scope(|s| {
        let workers: Vec<_> = (0..threads)
            .map(|t| {
                s.spawn(move || {
                    (t..count)
                        .step_by(threads)
                        .map(|i| (i, f(i)))
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        workers
            .into_iter()
            .flat_map(|w| w.join().unwrap())
            .collect()
    });
    out.sort_by_key(|(i, _)| *i);
    out.into_iter().map(|(_, t)| t).collect()
}
