//! `blockworld generate` and `blockworld merge` end to end (docs/datasets.md "Settling"): every family
//! yields scenes; the same seed gives the same bytes whatever `--jobs`; shards merge into the
//! unsharded dataset; a run killed midway resumes to a byte-identical dataset. Scale-out on the
//! real engines: a Slurm array job (`scripts/slurm_generate.sh`, one task killed with SIGKILL and
//! resubmitted) and the Kubernetes Indexed Job manifest validated offline; both skip loudly
//! without a cluster or validator, and fail instead in CI (`CI` or `BLOCKWORLD_REQUIRE_SLURM`,
//! `BLOCKWORLD_REQUIRE_K8S_VALIDATE`, which `make test` sets).
//!
//! Most tests use `--views ""` (scene.json only) so they run without a GPU; the `_rendered`
//! variants render the four views and skip loudly when no adapter (or no renderer yet) exists,
//! unless `BLOCKWORLD_REQUIRE_GPU` is set.

mod common;
use common::{assert_same_tree, blockworld, command, fails_with_2, ok, renderer_available, tree};

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

fn generate(dir: &Path, count: u32, extra: &[&str]) -> String {
    let count = count.to_string();
    let mut args = vec![
        "generate",
        "--count",
        &count,
        "--seed",
        "7",
        "-o",
        dir.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    ok(blockworld(&args))
}

fn manifest(dir: &Path) -> Vec<serde_json::Value> {
    std::fs::read_to_string(dir.join("manifest.jsonl"))
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

#[test]
fn every_family_yields_stable_scenes_with_its_expectation() {
    let tmp = tempfile::tempdir().unwrap();
    let ds = tmp.path().join("ds");
    generate(&ds, 22, &["--views", ""]);
    let lines = manifest(&ds);
    assert_eq!(lines.len(), 22);
    let mut families = BTreeMap::new();
    for (i, l) in lines.iter().enumerate() {
        assert_eq!(l["id"], format!("s{i:06}"), "scene-id order");
        *families
            .entry(l["family"].as_str().unwrap().to_string())
            .or_insert(0) += 1;
        let scene =
            blockworld::scene::read_scene(&ds.join(l["id"].as_str().unwrap()).join("scene.json"))
                .unwrap();
        assert_eq!(scene.blocks.len() as u64, l["blocks"].as_u64().unwrap());
        let meta = scene.meta.as_ref().unwrap();
        assert_eq!(meta["settle"]["stable"], true, "{}", l["id"]);
        assert_eq!(meta["seed"], l["seed"]);
        let unsupported = ["upper_larger", "yaw"].contains(&l["family"].as_str().unwrap());
        assert_eq!(l["supported"], !unsupported, "{l}");
        assert_eq!(scene.is_supported(), !unsupported);
        if unsupported {
            assert!(l["reason"].as_str().unwrap().contains("Ch. VII"), "{l}");
        }
    }
    assert_eq!(families.len(), 11, "{families:?}");
    assert!(families.values().all(|&n| n == 2));
    let options: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(ds.join("dataset.json")).unwrap()).unwrap();
    assert_eq!(options["count"], 22);
    assert_eq!(options["seed"], 7);
}

#[test]
fn the_same_seed_gives_the_same_bytes_whatever_jobs() {
    let tmp = tempfile::tempdir().unwrap();
    let (a, b) = (tmp.path().join("a"), tmp.path().join("b"));
    generate(&a, 16, &["--views", "", "--jobs", "1"]);
    generate(&b, 16, &["--views", "", "--jobs", "2"]);
    assert_same_tree(&a, &b);
    // A different seed gives a different dataset.
    let c = tmp.path().join("c");
    ok(blockworld([
        "generate",
        "--count",
        "16",
        "--seed",
        "8",
        "-o",
        c.to_str().unwrap(),
        "--views",
        "",
    ]));
    assert_ne!(
        std::fs::read(a.join("manifest.jsonl")).unwrap(),
        std::fs::read(c.join("manifest.jsonl")).unwrap()
    );
}

#[test]
fn shards_merge_into_the_unsharded_dataset() {
    let tmp = tempfile::tempdir().unwrap();
    let (whole, sharded) = (tmp.path().join("whole"), tmp.path().join("sharded"));
    generate(&whole, 14, &["--views", ""]);
    for i in 0..3 {
        generate(&sharded, 14, &["--views", "", "--shard", &format!("{i}/3")]);
    }
    // Before every shard is merged, merge refuses with the missing shard named.
    let shard2 = sharded.join("manifest.shard-2-of-3.jsonl");
    let kept = std::fs::read(&shard2).unwrap();
    std::fs::remove_file(&shard2).unwrap();
    let err = fails_with_2(&blockworld(["merge", sharded.to_str().unwrap()]));
    assert!(err.contains("shard 2 of 3 is missing"), "{err}");
    std::fs::write(&shard2, &kept).unwrap();

    ok(blockworld(["merge", sharded.to_str().unwrap()]));
    for i in 0..3 {
        std::fs::remove_file(sharded.join(format!("manifest.shard-{i}-of-3.jsonl"))).unwrap();
    }
    assert_same_tree(&whole, &sharded);
}

#[test]
fn merge_refuses_doubled_scenes_and_damaged_files() {
    let tmp = tempfile::tempdir().unwrap();
    let ds = tmp.path().join("ds");
    for i in 0..2 {
        generate(&ds, 6, &["--views", "", "--shard", &format!("{i}/2")]);
    }
    let s0 = ds.join("manifest.shard-0-of-2.jsonl");
    let good = std::fs::read_to_string(&s0).unwrap();
    let first = good.lines().next().unwrap().to_string();
    std::fs::write(&s0, format!("{good}{first}\n")).unwrap();
    let err = fails_with_2(&blockworld(["merge", ds.to_str().unwrap()]));
    assert!(err.contains("listed twice"), "{err}");
    std::fs::write(&s0, &good).unwrap();

    let scene = ds.join("s000001").join("scene.json");
    let bytes = std::fs::read(&scene).unwrap();
    std::fs::write(&scene, b"{}").unwrap();
    let err = fails_with_2(&blockworld(["merge", ds.to_str().unwrap()]));
    assert!(err.contains("sha256 differs"), "{err}");
    std::fs::write(&scene, bytes).unwrap();
    ok(blockworld(["merge", ds.to_str().unwrap()]));
}

#[test]
fn shards_from_the_array_job_environment() {
    let tmp = tempfile::tempdir().unwrap();
    let ds = tmp.path().join("ds");
    let run = |var: &str, value: &str| {
        command()
            .args([
                "generate", "--count", "5", "--seed", "7", "--views", "", "--shards", "2", "-o",
            ])
            .arg(&ds)
            .env(var, value)
            .output()
            .unwrap()
    };
    ok(run("SLURM_ARRAY_TASK_ID", "0"));
    ok(run("JOB_COMPLETION_INDEX", "1"));
    assert!(ds.join("manifest.shard-0-of-2.jsonl").exists());
    assert!(ds.join("manifest.shard-1-of-2.jsonl").exists());
    // Index 2 of 2 is out of range, from either variable.
    for var in ["JOB_COMPLETION_INDEX", "SLURM_ARRAY_TASK_ID"] {
        let err = fails_with_2(&run(var, "2"));
        assert!(err.contains("shard 2/2"), "{var}: {err}");
    }
    // A task resubmitted alone (sbatch --array=1) sees a count of 1 and a minimum of 1: its
    // index is still the shard.
    let resubmitted = command()
        .args([
            "generate", "--count", "5", "--seed", "7", "--views", "", "--shards", "2", "-o",
        ])
        .arg(&ds)
        .env("SLURM_ARRAY_TASK_ID", "1")
        .env("SLURM_ARRAY_TASK_COUNT", "1")
        .env("SLURM_ARRAY_TASK_MIN", "1")
        .output()
        .unwrap();
    assert!(
        ok(resubmitted).contains("(shard 1/2)"),
        "the resubmitted task resumes shard 1"
    );
    ok(blockworld(["merge", ds.to_str().unwrap()]));
    assert_eq!(manifest(&ds).len(), 5);
}

/// Regression: `merge` panicked (remainder by zero) on a stray `manifest.shard-0-of-0.jsonl`,
/// and allocated per scene the count that `dataset.json` claims (10^12 aborted, 2^64-1
/// overflowed) before checking anything. Both now end in an error that names the file.
#[test]
fn merge_names_stray_shards_and_distrusts_a_huge_count() {
    let tmp = tempfile::tempdir().unwrap();
    let ds = tmp.path().join("ds");
    generate(&ds, 3, &["--views", "", "--shard", "0/2"]);
    generate(&ds, 3, &["--views", "", "--shard", "1/2"]);
    let stray = ds.join("manifest.shard-0-of-0.jsonl");
    std::fs::write(&stray, "{}\n").unwrap();
    let out = blockworld(["merge", ds.to_str().unwrap()]);
    let err = common::fails_with_2(&out);
    assert!(
        err.contains("manifest.shard-0-of-0.jsonl") && !err.contains("panicked"),
        "{err}"
    );
    std::fs::remove_file(&stray).unwrap();
    let path = ds.join("dataset.json");
    let original = std::fs::read_to_string(&path).unwrap();
    for claim in ["1000000000000", "18446744073709551615", "-1"] {
        let mut v: serde_json::Value = serde_json::from_str(&original).unwrap();
        v["count"] = serde_json::from_str(claim).unwrap();
        std::fs::write(&path, v.to_string()).unwrap();
        let started = std::time::Instant::now();
        let out = blockworld(["merge", ds.to_str().unwrap()]);
        assert_eq!(out.status.code(), Some(2), "count {claim}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.contains("dataset.json") || err.contains("missing"),
            "{err}"
        );
        assert!(!err.contains("panicked"), "{err}");
        // Not a timing target: a guard that the merge did not walk 10^12 slots.
        assert!(
            started.elapsed().as_secs() < 60,
            "count {claim} took too long"
        );
    }
    std::fs::write(&path, original).unwrap();
    ok(blockworld(["merge", ds.to_str().unwrap()]));
}

#[test]
fn a_run_killed_midway_resumes_to_the_same_bytes() {
    let tmp = tempfile::tempdir().unwrap();
    let (killed, clean) = (tmp.path().join("killed"), tmp.path().join("clean"));
    let args = |dir: &Path| {
        vec![
            "generate".to_string(),
            "--count".into(),
            "250".into(),
            "--seed".into(),
            "7".into(),
            "--views".into(),
            "".into(),
            "--jobs".into(),
            "1".into(),
            "-o".into(),
            dir.to_str().unwrap().into(),
        ]
    };
    let mut child = command()
        .args(args(&killed))
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let done = |dir: &Path| {
        std::fs::read_dir(dir)
            .map(|r| {
                r.flatten()
                    .filter(|e| e.path().join("done.json").exists())
                    .count()
            })
            .unwrap_or(0)
    };
    while done(&killed) < 20 {
        assert!(
            child.try_wait().unwrap().is_none(),
            "finished before the kill"
        );
        std::thread::sleep(std::time::Duration::from_millis(2));
    }
    child.kill().unwrap(); // SIGKILL
    child.wait().unwrap();
    assert!(
        !killed.join("manifest.jsonl").exists(),
        "killed before the end"
    );
    let partial = done(&killed);
    assert!(partial < 250);
    // Damage one finished scene as a full disk would: it must be redone too.
    std::fs::write(killed.join("s000003").join("scene.json"), b"").unwrap();

    let out = ok(blockworld(args(&killed)));
    let kept = partial as u64 - 1;
    assert!(
        out.contains(&format!("{kept} kept from an earlier run")),
        "{out} (partial {partial})"
    );
    ok(blockworld(args(&clean)));
    assert_same_tree(&killed, &clean);
}

/// A tmpfs mounted for one test, unmounted on drop (also when the test fails).
struct TinyDisk(PathBuf);

impl TinyDisk {
    /// Mounts a tmpfs of `size` (e.g. "96k") at `dir`; `None` where mounting is not permitted
    /// (not root, or no mount in this sandbox).
    fn mount(dir: &Path, size: &str) -> Option<TinyDisk> {
        std::fs::create_dir_all(dir).unwrap();
        let status = Command::new("mount")
            .args(["-t", "tmpfs", "-o", &format!("size={size}"), "tmpfs"])
            .arg(dir)
            .stderr(std::process::Stdio::null())
            .status()
            .ok()?;
        status.success().then(|| TinyDisk(dir.to_path_buf()))
    }

    fn resize(&self, size: &str) {
        let status = Command::new("mount")
            .args(["-o", &format!("remount,size={size}")])
            .arg(&self.0)
            .status()
            .unwrap();
        assert!(status.success(), "remount {}", self.0.display());
    }
}

impl Drop for TinyDisk {
    fn drop(&mut self) {
        let _ = Command::new("umount").arg(&self.0).status();
    }
}

/// Nothing lost: a full disk stops the run with an error that names the file, leaves
/// no half-written file under a final name and no temporary file, and the same command, re-run
/// once there is space, resumes to the bytes of an uninterrupted run.
#[test]
fn a_full_disk_stops_cleanly_and_the_rerun_resumes_to_the_same_bytes() {
    let tmp = tempfile::tempdir().unwrap();
    let Some(disk) = TinyDisk::mount(&tmp.path().join("tiny"), "96k") else {
        eprintln!(
            "SKIPPED: cannot mount a tmpfs here (needs root); the full-disk case is untested"
        );
        return;
    };
    let (full, clean) = (disk.0.join("ds"), tmp.path().join("clean"));
    let args = |dir: &Path| {
        [
            "generate", "--count", "40", "--seed", "7", "--views", "", "--jobs", "1", "-o",
        ]
        .iter()
        .map(|s| s.to_string())
        .chain([dir.to_str().unwrap().to_string()])
        .collect::<Vec<_>>()
    };
    let run = |dir: &Path| blockworld(args(dir));
    let stderr = fails_with_2(&run(&full));
    assert!(
        stderr.contains("No space left on device")
            && stderr.contains(full.to_str().unwrap())
            && stderr.contains("free disk space, then re-run the same command"),
        "{stderr}"
    );
    let files = tree(&full);
    assert!(
        files.len() > 2,
        "some scenes were written before the disk filled"
    );
    for (name, bytes) in &files {
        let name = name.to_string_lossy();
        assert!(
            !name.contains(".tmp."),
            "temporary file left behind: {name}"
        );
        if name.ends_with(".json") && !name.ends_with("manifest.jsonl") {
            serde_json::from_slice::<serde_json::Value>(bytes)
                .unwrap_or_else(|e| panic!("{name} is half-written: {e}"));
        }
    }
    disk.resize("16m");
    ok(run(&full));
    ok(run(&clean));
    assert_same_tree(&full, &clean);
}

#[test]
fn other_options_in_the_same_directory_are_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let ds = tmp.path().join("ds");
    generate(&ds, 3, &["--views", ""]);
    let err = fails_with_2(&blockworld([
        "generate",
        "--count",
        "3",
        "--seed",
        "9",
        "--views",
        "",
        "-o",
        ds.to_str().unwrap(),
    ]));
    assert!(err.contains("other options"), "{err}");
}

#[test]
fn rendered_datasets_are_identical_whatever_jobs_and_list_every_view() {
    if !renderer_available() {
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let (a, b) = (tmp.path().join("a"), tmp.path().join("b"));
    generate(&a, 4, &["--jobs", "1", "--size", "128x120"]);
    generate(&b, 4, &["--jobs", "2", "--size", "128x120"]);
    assert_same_tree(&a, &b);
    for l in manifest(&a) {
        let files = l["files"].as_object().unwrap();
        for v in ["ne", "se", "sw", "nw"] {
            for f in ["view", "depth", "ids"] {
                assert!(files.contains_key(&format!("{f}_{v}.png")), "{l}");
            }
            for f in ["lines", "camera"] {
                assert!(files.contains_key(&format!("{f}_{v}.json")), "{l}");
            }
        }
    }
}

#[test]
fn rendered_shards_merge_and_resume() {
    if !renderer_available() {
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let (whole, sharded) = (tmp.path().join("whole"), tmp.path().join("sharded"));
    generate(&whole, 4, &["--size", "128x120"]);
    for i in 0..2 {
        generate(
            &sharded,
            4,
            &["--size", "128x120", "--shard", &format!("{i}/2")],
        );
    }
    std::fs::remove_file(sharded.join("s000002").join("view_se.png")).unwrap();
    let out = generate(&sharded, 4, &["--size", "128x120", "--shard", "0/2"]);
    assert!(out.contains("1 generated"), "{out}");
    ok(blockworld(["merge", sharded.to_str().unwrap()]));
    for i in 0..2 {
        std::fs::remove_file(sharded.join(format!("manifest.shard-{i}-of-2.jsonl"))).unwrap();
    }
    assert_same_tree(&whole, &sharded);
}

/// Whether a scale-out check must run rather than skip: in CI (`CI` set) or when `var` is set
/// (`make test` sets it).
fn required(var: &str) -> bool {
    std::env::var_os("CI").is_some() || std::env::var_os(var).is_some()
}

/// A Slurm cluster answering `sinfo`, or a loud skip (`false`); no cluster is a failure in CI or
/// with `BLOCKWORLD_REQUIRE_SLURM` set. `scripts/slurm_local.sh up` starts one on the local machine.
fn slurm_available() -> bool {
    let up = Command::new("sinfo")
        .arg("-h")
        .output()
        .is_ok_and(|o| o.status.success() && !o.stdout.is_empty());
    if !up && required("BLOCKWORLD_REQUIRE_SLURM") {
        panic!("no Slurm cluster answers sinfo, and CI or BLOCKWORLD_REQUIRE_SLURM requires one: run scripts/slurm_local.sh up (docs/datasets.md \"Settling\")");
    }
    if !up {
        eprintln!("SKIPPED: no Slurm cluster (sinfo failed); scripts/slurm_local.sh up starts one, docs/datasets.md \"Settling\"");
    }
    up
}

/// Submits `scripts/slurm_generate.sh` as the array `array` (one CPU per task, logs
/// `task-<index>.log` in `logs`) writing `count` scenes of seed 7 in `shards` shards; the job id.
fn sbatch_generate(array: &str, logs: &Path, ds: &Path, count: u32, extra: &[&str]) -> String {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("scripts/slurm_generate.sh");
    let out = Command::new("sbatch")
        .args(["--parsable", "--cpus-per-task=1"])
        .arg(format!("--array={array}"))
        .arg(format!("--output={}/task-%a.log", logs.display()))
        .arg(&script)
        .arg(ds)
        .args([&count.to_string(), "7", "4"])
        .args(extra)
        .env("BLOCKWORLD", common::run::BIN)
        .output()
        .unwrap();
    let id = ok(out).trim().to_string();
    assert!(
        id.parse::<u64>().is_ok(),
        "sbatch --parsable printed {id:?}"
    );
    id
}

/// Waits until no task of job `id` is pending or running (`squeue`); then `scontrol show job`
/// of `task` (`<id>_<task>`: its state and exit code, kept by slurmctld for minutes).
fn wait_for_job(id: &str, task: u32) -> String {
    let started = std::time::Instant::now();
    loop {
        let out = ok(Command::new("squeue")
            .args(["-h", "-j", id])
            .output()
            .unwrap());
        if out.trim().is_empty() {
            break;
        }
        // A guard against a cluster that never runs the job, not a timing target.
        assert!(
            started.elapsed().as_secs() < 600,
            "job {id} still queued after 10 min:\n{out}"
        );
        std::thread::sleep(std::time::Duration::from_millis(100));
    }
    let show = Command::new("scontrol")
        .args(["-o", "show", "job", &format!("{id}_{task}")])
        .output()
        .unwrap();
    String::from_utf8_lossy(&show.stdout).into_owned()
}

fn task_log(logs: &Path, task: u32) -> String {
    std::fs::read_to_string(logs.join(format!("task-{task}.log"))).unwrap_or_default()
}

/// Finished scenes (a `done.json`) of shard `index` of 4 in `ds`.
fn done_in_shard(ds: &Path, index: u64) -> usize {
    std::fs::read_dir(ds)
        .map(|r| {
            r.flatten()
                .filter(|e| {
                    let name = e.file_name().to_string_lossy().into_owned();
                    name.strip_prefix('s')
                        .and_then(|n| n.parse::<u64>().ok())
                        .is_some_and(|n| n % 4 == index)
                        && e.path().join("done.json").exists()
                })
                .count()
        })
        .unwrap_or(0)
}

fn remove_shard_manifests(ds: &Path) {
    for i in 0..4 {
        std::fs::remove_file(ds.join(format!("manifest.shard-{i}-of-4.jsonl"))).unwrap();
    }
}

/// A real Slurm array of 4 tasks of `scripts/slurm_generate.sh` (rendered at 128x120 when a
/// renderer exists) writes 4 shards that `merge` joins into the bytes of one unsharded run; a
/// damaged shard makes `merge` refuse (so the comparison can fail).
#[test]
fn a_slurm_array_of_four_tasks_merges_to_the_bytes_of_one_run() {
    if !slurm_available() {
        return;
    }
    let views: &[&str] = if renderer_available() {
        &["--size", "128x120"]
    } else {
        &["--views", ""]
    };
    let tmp = tempfile::tempdir().unwrap();
    let (whole, sharded) = (tmp.path().join("whole"), tmp.path().join("sharded"));
    generate(&whole, 8, views);
    let id = sbatch_generate("0-3", tmp.path(), &sharded, 8, views);
    wait_for_job(&id, 0);
    for i in 0..4 {
        let log = task_log(tmp.path(), i);
        assert!(
            log.contains(&format!("2 scenes (shard {i}/4): 2 generated")),
            "task {i}:\n{log}"
        );
    }
    let scene = sharded.join("s000002").join("scene.json");
    let bytes = std::fs::read(&scene).unwrap();
    std::fs::write(&scene, b"{}").unwrap();
    let out = blockworld(["merge", sharded.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2), "merge took a damaged shard");
    assert!(String::from_utf8_lossy(&out.stderr).contains("sha256 differs"));
    std::fs::write(&scene, bytes).unwrap();

    ok(blockworld(["merge", sharded.to_str().unwrap()]));
    remove_shard_manifests(&sharded);
    assert_same_tree(&whole, &sharded);
}

/// SIGKILL one task of a real Slurm array mid-run (`scancel --batch --signal=KILL`); its shard
/// is unfinished, the resubmitted task (`sbatch --array=1`) redoes only the missing scenes, and
/// the merged dataset is the bytes of one unsharded run. The scenes are rendered in the photo
/// look so that a task's 60 scenes take seconds (scenes without pictures take about a
/// millisecond each, faster than `scancel` reaches the task).
#[test]
fn a_slurm_task_killed_mid_run_resumes_when_resubmitted() {
    if !slurm_available() {
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let (whole, sharded) = (tmp.path().join("whole"), tmp.path().join("sharded"));
    let opts = ["--look", "photo"];
    let id = sbatch_generate("0-3", tmp.path(), &sharded, 240, &opts);
    let shard1 = sharded.join("manifest.shard-1-of-4.jsonl");
    for polls in 0.. {
        if done_in_shard(&sharded, 1) >= 2 {
            break;
        }
        assert!(!shard1.exists(), "task 1 finished before the kill");
        if polls % 50 == 49 {
            let queued = ok(Command::new("squeue")
                .args(["-h", "-j", &format!("{id}_1")])
                .output()
                .unwrap());
            let log = task_log(tmp.path(), 1);
            assert!(!queued.trim().is_empty(), "task 1 ended early:\n{log}");
        }
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    ok(Command::new("scancel")
        .args(["--batch", "--signal=KILL", &format!("{id}_1")])
        .output()
        .unwrap());
    let state = wait_for_job(&id, 1);
    assert!(
        state.contains("ExitCode=0:9"),
        "not killed by SIGKILL: {state}"
    );
    assert!(!shard1.exists(), "task 1 finished before the kill");
    let kept = done_in_shard(&sharded, 1);
    assert!((2..60).contains(&kept), "{kept} of 60 scenes done");

    let again = tmp.path().join("again");
    std::fs::create_dir(&again).unwrap();
    let id = sbatch_generate("1", &again, &sharded, 240, &opts);
    wait_for_job(&id, 1);
    let log = task_log(&again, 1);
    let resumed = format!(
        "60 scenes (shard 1/4): {} generated, {kept} kept from an earlier run",
        60 - kept
    );
    assert!(log.contains(&resumed), "{log}");
    ok(blockworld(["merge", sharded.to_str().unwrap()]));
    remove_shard_manifests(&sharded);
    generate(&whole, 240, &opts);
    assert_same_tree(&whole, &sharded);
}

/// `--fsync` (every file forced to disk) changes when bytes reach the disk, never which bytes:
/// the dataset equals the default run's, which syncs no scene file (only the manifest).
#[test]
fn fsync_every_file_writes_the_same_dataset_as_the_default() {
    let tmp = tempfile::tempdir().unwrap();
    let (synced, verified) = (tmp.path().join("synced"), tmp.path().join("verified"));
    generate(&synced, 3, &["--size", "128x120", "--fsync"]);
    generate(&verified, 3, &["--size", "128x120"]);
    assert_same_tree(&synced, &verified);
}

/// What a power loss can leave of files renamed into place without a sync (the default for
/// every scene file, `done.json` included): an empty file, or one of the right length holding
/// zeros. A resume parses each scene's done marker and re-hashes the files it lists, so it
/// redoes exactly the scenes so damaged, and the dataset equals an uninterrupted run's.
#[test]
fn a_resume_redoes_scenes_whose_unsynced_files_a_power_loss_damaged() {
    let tmp = tempfile::tempdir().unwrap();
    let (damaged, clean) = (tmp.path().join("damaged"), tmp.path().join("clean"));
    let opts = ["--views", ""];
    generate(&damaged, 6, &opts);
    let zeroed = |path: &Path| {
        let len = std::fs::metadata(path).unwrap().len() as usize;
        std::fs::write(path, vec![0u8; len]).unwrap();
    };
    std::fs::write(damaged.join("s000001/done.json"), b"").unwrap();
    zeroed(&damaged.join("s000002/done.json"));
    zeroed(&damaged.join("s000004/scene.json"));
    std::fs::remove_file(damaged.join("manifest.jsonl")).unwrap();
    let out = generate(&damaged, 6, &opts);
    assert!(
        out.contains("6 scenes: 3 generated, 3 kept from an earlier run"),
        "{out}"
    );
    generate(&clean, 6, &opts);
    assert_same_tree(&damaged, &clean);
}

/// `scripts/slurm_generate.sh` refuses an array index that is not a shard, before it writes
/// anything (an array of 0-4 for 4 shards would otherwise write a fifth shard).
#[test]
fn the_slurm_script_refuses_an_index_outside_its_shards() {
    let tmp = tempfile::tempdir().unwrap();
    let ds = tmp.path().join("ds");
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("scripts/slurm_generate.sh");
    let run = |task: &str| {
        Command::new("bash")
            .arg(&script)
            .arg(&ds)
            .args(["8", "7", "4", "--views", ""])
            .env("SLURM_ARRAY_TASK_ID", task)
            .env("BLOCKWORLD", common::run::BIN)
            .output()
            .unwrap()
    };
    let out = run("4");
    let err = common::fails_with_2(&out);
    assert!(err.contains("--array=0-3"), "{err}");
    assert!(!ds.exists(), "wrote before refusing");
    let out = ok(run("3"));
    assert!(out.contains("2 scenes (shard 3/4): 2 generated"), "{out}");
}

/// The offline validator of Kubernetes manifests: `make setup` installs PyPI's
/// `kubernetes-validate` into target/kubernetes-validate; `None` is a loud skip, a failure in CI
/// or with `BLOCKWORLD_REQUIRE_K8S_VALIDATE` set.
fn kubernetes_validate() -> Option<PathBuf> {
    let installed = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("target/kubernetes-validate/bin/kubernetes-validate");
    if installed.exists() {
        return Some(installed);
    }
    if required("BLOCKWORLD_REQUIRE_K8S_VALIDATE") {
        panic!("{} is missing: run make setup", installed.display());
    }
    eprintln!(
        "SKIPPED: no {} (make setup installs it)",
        installed.display()
    );
    None
}

/// `scripts/k8s_generate_job.yaml` is a valid Kubernetes 1.37 Indexed Job (strict schema, no
/// cluster needed) whose completions equal its `--shards`; a misspelt field or a wrong type fails.
#[test]
fn the_kubernetes_indexed_job_validates_and_a_broken_one_does_not() {
    let Some(validator) = kubernetes_validate() else {
        return;
    };
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scripts/k8s_generate_job.yaml");
    let job = std::fs::read_to_string(&path).unwrap();
    assert!(job.contains("completionMode: Indexed"));
    assert!(job.contains("completions: 8") && job.contains("--shards=8"));
    let validate = |file: &Path| {
        Command::new(&validator)
            .args(["-k", "1.37.0", "--strict"])
            .arg(file)
            .output()
            .unwrap()
    };
    let out = ok(validate(&path));
    assert!(out.contains("passed"), "{out}");

    let tmp = tempfile::tempdir().unwrap();
    for (from, to, says) in [
        (
            "completions: 8",
            "completion: 8",
            "'completion' was unexpected",
        ),
        (
            "parallelism: 8",
            "parallelism: eight",
            "is not of type 'integer'",
        ),
    ] {
        let broken = tmp.path().join("broken.yaml");
        std::fs::write(&broken, job.replace(from, to)).unwrap();
        let out = validate(&broken);
        let text = String::from_utf8_lossy(&out.stdout).into_owned()
            + &String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success() && text.contains(says), "{to}: {text}");
    }
}
