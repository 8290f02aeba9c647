//! What a hostile but fair user does to the command line (docs/cli.md "Exit codes and progress output"): full or closed
//! stdout, huge coordinates, loose edges of the file formats, odd encodings. Each test pins one
//! failure that once passed with a panic, `null` in the output or a misleading message.

mod common;
use common::run::blockworld_to_full_stdout;
use common::{blockworld, command, fails_with_2, stderr};

use std::path::{Path, PathBuf};
use std::process::{Output, Stdio};

fn scene(name: &str) -> String {
    common::root()
        .join("scenes")
        .join(name)
        .to_string_lossy()
        .into_owned()
}

fn write(dir: &Path, name: &str, text: &[u8]) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// Regression: every printing command panicked ("failed printing to stdout", exit 101) on a
/// full stdout; it must be an error with exit 2.
#[test]
fn full_stdout_is_an_error_with_exit_2() {
    let two = scene("two_layer.json");
    let err = fails_with_2(&blockworld_to_full_stdout(["score", &two, &two]));
    assert!(err.contains("writing to stdout"), "{err}");
}

/// Regression: a stdout pipe whose reader had gone (`| head -1`) made commands panic; a closed
/// pipe ends the command quietly with exit 0, as Unix tools do.
#[test]
fn closed_stdout_pipe_ends_quietly() {
    let two = scene("two_layer.json");
    for _ in 0..5 {
        let mut child = command()
            .args(["score", &two, &two])
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        drop(child.stdout.take());
        let o = child.wait_with_output().unwrap();
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(0), "stderr: {err}");
        assert!(err.is_empty(), "{err}");
    }
}

/// Regression: without `XDG_RUNTIME_DIR` (batch jobs, cron, containers) a Vulkan render that
/// succeeded printed two `error: XDG_RUNTIME_DIR is invalid` lines.
#[test]
fn headless_render_prints_no_spurious_errors() {
    if common::renderer().is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let o = command()
        .args(["render", &scene("single_cube.json"), "--views", "ne", "-o"])
        .arg(dir.path())
        .env_remove("XDG_RUNTIME_DIR")
        .env_remove("NODEVICE_SELECT")
        .output()
        .unwrap();
    common::ok(&o);
    assert_eq!(stderr(&o), "", "nothing on stderr on success");
}

/// Regression: an OS error was printed twice (`X: Is a directory`, then `caused by: Is a
/// directory`).
#[test]
fn os_errors_are_printed_once() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path().to_string_lossy().into_owned();
    let err = fails_with_2(&blockworld(["score", &d, &d]));
    assert_eq!(err.matches("Is a directory").count(), 1, "{err}");
    assert!(err.contains(&d), "{err}");
}

/// Regression: a UTF-8 byte-order mark gave "expected value at line 1 column 1" and invalid
/// UTF-8 no position; name the BOM, give the byte offset.
#[test]
fn bom_and_invalid_utf8_are_named() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read(scene("two_layer.json")).unwrap();
    let bom = write(
        dir.path(),
        "bom.json",
        &[b"\xEF\xBB\xBF".as_slice(), &text].concat(),
    );
    let err = fails_with_2(&blockworld([
        "export",
        bom.to_str().unwrap(),
        "-o",
        "x.glb",
    ]));
    assert!(
        err.contains("byte-order mark") && err.contains("bom.json"),
        "{err}"
    );
    let mut bad = text.clone();
    bad[20] = 0xFF;
    let bad = write(dir.path(), "bad.json", &bad);
    let err = fails_with_2(&blockworld([
        "export",
        bad.to_str().unwrap(),
        "-o",
        "x.glb",
    ]));
    assert!(
        err.contains("byte offset 20") && err.contains("bad.json"),
        "{err}"
    );
}

/// Regression: a block at x = 1e308 mm passed validation; `export` wrote a node translation
/// of `null` and `render` a camera full of `null`. Now exit 2 naming the block, nothing written.
#[test]
fn huge_coordinates_are_refused_naming_the_block() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(scene("two_layer.json")).unwrap();
    let far = text.replacen("[0, 22.5, 0]", "[1e308, 22.5, 0]", 1);
    assert_ne!(far, text, "the fixture has the block to move");
    let far = write(dir.path(), "far.json", far.as_bytes());
    let glb = dir.path().join("far.glb");
    let err = fails_with_2(&blockworld([
        "export",
        far.to_str().unwrap(),
        "-o",
        glb.to_str().unwrap(),
    ]));
    assert!(
        err.contains("block 1") && err.contains("outside the world"),
        "{err}"
    );
    assert!(!glb.exists());
    let out = dir.path().join("settled.json");
    let err = fails_with_2(&blockworld([
        "settle",
        far.to_str().unwrap(),
        "--allow-drift",
        "-o",
        out.to_str().unwrap(),
    ]));
    assert!(err.contains("block 1"), "{err}");
    assert!(!out.exists());
}

/// Regression: `--views ""` exited 0 writing nothing, and `--views ne,ne` wrote every file
/// twice.
#[test]
fn render_views_must_be_given_once_each() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let one = scene("single_cube.json");
    for (views, says) in [("", "no view given"), ("ne,ne", "ne is given twice")] {
        let o = blockworld([
            "render",
            &one,
            "--views",
            views,
            "-o",
            out.to_str().unwrap(),
        ]);
        let err = fails_with_2(&o);
        assert!(err.contains(says), "{err}");
        assert!(!out.exists(), "nothing written for --views {views:?}");
    }
}

/// Regression: `edges -o e.jpg` wrote PNG bytes under a `.jpg` name.
#[test]
fn edges_refuses_a_non_png_output_name() {
    let dir = tempfile::tempdir().unwrap();
    let pic = dir.path().join("v.png");
    image::GrayImage::from_fn(16, 16, |x, _| image::Luma([if x < 8 { 20 } else { 200 }]))
        .save(&pic)
        .unwrap();
    let jpg = dir.path().join("e.jpg");
    let err = fails_with_2(&blockworld([
        "edges",
        pic.to_str().unwrap(),
        "-o",
        jpg.to_str().unwrap(),
    ]));
    assert!(err.contains("e.jpg") && err.contains(".png"), "{err}");
    assert!(!jpg.exists());
    let png = dir.path().join("e.png");
    let o = blockworld(["edges", pic.to_str().unwrap(), "-o", png.to_str().unwrap()]);
    common::ok(&o);
    assert!(png.exists());
}

fn generate(dir: &Path, extra: &[&str]) -> Output {
    let mut args = vec![
        "generate", "--views", "", "--family", "single", "--jobs", "1",
    ];
    args.extend_from_slice(extra);
    args.extend_from_slice(&["-o", dir.to_str().unwrap()]);
    blockworld(&args)
}

/// Regression: every `generate` error said "fix the cause, e.g. free disk space", also for
/// `--count 0`, options differing from the existing dataset and a concurrent writer; and
/// `--jobs 1000000` hung spawning threads.
#[test]
fn generate_errors_carry_their_own_fix() {
    let dir = tempfile::tempdir().unwrap();
    let ds = dir.path().join("ds");
    let err = fails_with_2(&generate(&ds, &["--count", "0"]));
    assert!(err.contains("--count must be at least 1"), "{err}");
    assert!(!err.contains("disk space"), "{err}");
    let o = generate(&ds, &["--count", "2", "--seed", "1"]);
    common::ok(&o);
    let err = fails_with_2(&generate(&ds, &["--count", "2", "--seed", "2"]));
    assert!(
        err.contains("other options") && err.contains("seed"),
        "{err}"
    );
    assert!(!err.contains("disk space"), "{err}");
    let many = [
        "generate", "--views", "", "--count", "2", "--jobs", "1000000", "-o",
    ];
    let err = fails_with_2(&blockworld([&many[..], &[ds.to_str().unwrap()]].concat()));
    assert!(err.contains("--jobs 1000000: at most 1024"), "{err}");
    let file = write(dir.path(), "a_file", b"");
    let err = fails_with_2(&generate(&file, &["--count", "2"]));
    assert!(err.contains("give a directory"), "{err}");
    assert!(!err.contains("disk space"), "{err}");
}

/// Regression: two `generate` runs into one folder deleted each other's temporary files; the
/// second is refused naming the first's pid, and nothing of the first is disturbed.
#[test]
fn a_second_generate_into_the_same_folder_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let ds = dir.path().join("ds");
    let mut first = command()
        .args([
            "generate", "--views", "", "--family", "single", "--jobs", "1",
        ])
        .args(["--count", "18446744073709551615", "-o"])
        .arg(&ds)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    wait_for(&ds.join("s000000").join("done.json"));
    let err = fails_with_2(&generate(&ds, &["--count", "18446744073709551615"]));
    assert!(err.contains(&format!("pid {}", first.id())), "{err}");
    assert!(!err.contains("disk space"), "{err}");
    assert_eq!(first.try_wait().unwrap(), None, "the first run goes on");
    first.kill().unwrap();
    first.wait().unwrap();
}

/// Regression: `generate --count 18446744073709551615` panicked and `--count 1000000000000`
/// aborted allocating every scene up front. Generation streams: the run starts writing scenes
/// at once and its memory stays small.
#[test]
fn generate_streams_whatever_the_count() {
    for count in ["18446744073709551615", "1000000000000"] {
        let dir = tempfile::tempdir().unwrap();
        let ds = dir.path().join("ds");
        let mut run = command()
            .args([
                "generate", "--views", "", "--family", "single", "--jobs", "1",
            ])
            .args(["--count", count, "-o"])
            .arg(&ds)
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        wait_for(&ds.join("s000002").join("done.json"));
        let status = std::fs::read_to_string(format!("/proc/{}/status", run.id())).unwrap();
        let rss_kib: u64 = status
            .lines()
            .find_map(|l| l.strip_prefix("VmRSS:"))
            .and_then(|v| v.split_whitespace().next()?.parse().ok())
            .unwrap();
        assert!(
            rss_kib < 300 * 1024,
            "--count {count}: {rss_kib} KiB resident"
        );
        assert_eq!(
            run.try_wait().unwrap(),
            None,
            "--count {count} still running"
        );
        run.kill().unwrap();
        run.wait().unwrap();
    }
}

/// Waits up to a minute for `path` to appear (a scene finished by a background run).
fn wait_for(path: &Path) {
    let start = std::time::Instant::now();
    while !path.exists() {
        assert!(
            start.elapsed().as_secs() < 60,
            "{} did not appear",
            path.display()
        );
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
}

/// Regression: `--size` accepted pictures the device cannot read back (over about 52 Mpx), and
/// the render failed after start-up with wgpu's raw validation error; the check now runs
/// against the adapter's limits first and says which sizes work.
#[test]
fn oversized_pictures_are_refused_before_rendering() {
    if common::renderer().is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = blockworld([
        "render",
        &scene("single_cube.json"),
        "--views",
        "ne",
        "--size",
        "8192x8192",
        "-o",
        out.to_str().unwrap(),
    ]);
    let err = fails_with_2(&o);
    assert!(err.contains("8192x8192") && err.contains("Mpx"), "{err}");
    assert!(!err.to_lowercase().contains("validation"), "{err}");
    assert!(!out.exists());
}

/// Regression: `vertices` on noise was superlinear (8192 x 8192 took 263 s and 2.7 GB); a
/// picture with far more edge pixels than a block scene is refused, saying the cap, while a
/// rendered 2048 x 2048 view of the thesis sample is not.
#[test]
fn noise_pictures_are_refused_with_the_edge_cap() {
    use blockworld::camera::{Camera, CameraOptions, CornerView};
    use blockworld::vision::{detect_line_drawing, VisionError, VisionOptions};
    use rand::{Rng, SeedableRng};
    let side = 2048;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
    let noise = image::GrayImage::from_fn(side, side, |_, _| image::Luma([rng.random()]));
    let corners = [glam::DVec3::ZERO, glam::DVec3::splat(15.0)];
    let opts = CameraOptions {
        size_px: [side, side],
        ..Default::default()
    };
    let camera = Camera::frame(&corners, CornerView::Ne, &opts);
    let start = std::time::Instant::now();
    let err = detect_line_drawing(&noise, &camera, &VisionOptions::default()).unwrap_err();
    println!("refused in {:.2} s: {err}", start.elapsed().as_secs_f64());
    assert!(
        matches!(
            err,
            VisionError::TooManyEdges {
                cap_px: 819_200,
                ..
            }
        ),
        "{err}"
    );
    assert!(err.to_string().contains("819200"), "{err}");
    let Some(renderer) = common::renderer() else {
        return;
    };
    let scene = blockworld::scene::read_scene(Path::new(&scene("thesis_sample.json"))).unwrap();
    let mut ropts = blockworld::render::RenderOptions::default();
    ropts.camera.size_px = [side, side];
    for view in renderer
        .render_views(&scene, &CornerView::ALL, &ropts)
        .unwrap()
    {
        let det = detect_line_drawing(&view.gray, &view.camera, &VisionOptions::default());
        assert!(det.is_ok(), "{:?}", det.err());
    }
}

/// Regression: commands that still print with `println!` (here `bench accuracy`) panicked on a
/// full stdout (exit 101); the binary's panic hook turns that into exit 2 with the error.
#[test]
fn println_on_a_full_stdout_still_exits_2() {
    let dir = tempfile::tempdir().unwrap();
    let json = dir.path().join("a.json");
    let err = fails_with_2(&blockworld_to_full_stdout([
        "bench",
        "accuracy",
        "--recognizer",
        &common::root()
            .join("golden/recon_reference")
            .to_string_lossy(),
        "--suite",
        &scene("bench"),
        "--json-out",
        json.to_str().unwrap(),
    ]));
    assert!(err.contains("writing to stdout"), "{err}");
}

/// Regression: an endless input (`/dev/zero` as the scene) was read until memory ran out; text
/// inputs stop at 128 MiB with an error naming the file.
#[test]
fn endless_inputs_stop_at_the_size_cap() {
    let dir = tempfile::tempdir().unwrap();
    let glb = dir.path().join("z.glb");
    let err = fails_with_2(&blockworld([
        "export",
        "/dev/zero",
        "-o",
        glb.to_str().unwrap(),
    ]));
    assert!(
        err.contains("/dev/zero") && err.contains("128 MiB"),
        "{err}"
    );
    assert!(!glb.exists());
}

/// Long work logs its progress when stderr is not a terminal: `render` counts the scene's
/// validated block pairs and the line drawing's edge steps, `vertices` the vision steps, each up to 100% (the quiet first second
/// is set to 0 so a small scene shows it).
#[test]
fn render_and_vertices_log_progress_lines_when_not_on_a_terminal() {
    if common::renderer().is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let run = |args: &[&str]| {
        command()
            .args(args)
            .env("BLOCKWORLD_PROGRESS_AFTER_MS", "0")
            .output()
            .unwrap()
    };
    let o = run(&[
        "render",
        &scene("two_layer.json"),
        "-o",
        &out.to_string_lossy(),
        "--views",
        "ne,sw",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let lines: Vec<String> = stderr(&o)
        .lines()
        .filter(|l| l.starts_with("render: "))
        .map(String::from)
        .collect();
    assert!(lines.len() >= 10, "a line per twentieth: {lines:?}");
    assert!(lines.last().unwrap().contains("(100%)"), "{lines:?}");
    assert!(
        stderr(&o)
            .lines()
            .any(|l| l.starts_with("validate: ") && l.contains("block pairs (100%)")),
        "the scene's validation shows its progress too: {}",
        stderr(&o)
    );
    let o = run(&[
        "vertices",
        &out.join("view_ne.png").to_string_lossy(),
        "--camera",
        &out.join("camera_ne.json").to_string_lossy(),
        "-o",
        &dir.path().join("v.json").to_string_lossy(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("vertices: 3/3 steps (100%)"),
        "{}",
        stderr(&o)
    );
    // Without the knob, quick work stays silent.
    let o = blockworld([
        "vertices",
        &out.join("view_ne.png").to_string_lossy(),
        "--camera",
        &out.join("camera_ne.json").to_string_lossy(),
    ]);
    assert!(!stderr(&o).contains("steps"), "{}", stderr(&o));
}

/// Row 12a of docs/limits.md's render bounds: `--downsample 4` of an 8x8 render writes a 2x2
/// picture; it is refused before rendering, naming both flags and the smallest size that works.
/// Row 11b/d: an out-of-range render option names only its own flag and echoes the number short.
#[test]
fn render_options_name_their_own_flag_and_keep_pictures_at_least_8_px() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("r");
    let o = out.to_string_lossy().into_owned();
    let one = scene("single_cube.json");
    let args = ["render", &one, "--views", "ne", "-o", &o];
    let err = fails_with_2(&blockworld(args.iter().chain(&[
        "--downsample",
        "4",
        "--size",
        "8x8",
    ])));
    assert!(err.contains("2x2 px") && err.contains("32x32"), "{err}");
    assert!(!out.exists(), "nothing written");
    let err = fails_with_2(&blockworld(args.iter().chain(&["--elevation", "1e300"])));
    assert!(err.contains("--elevation 1e300 is out of range"), "{err}");
    assert!(!err.contains("--fov") && err.len() < 200, "{err}");
}

/// Regression: a blank picture (or a drawing with no lines) was answered `ok` with 0 blocks;
/// an answer without blocks explains nothing, so it declines.
#[test]
fn recognize_declines_views_that_show_no_block() {
    let dir = tempfile::tempdir().unwrap();
    let fixture = common::root().join("tests/fixtures/vision/single_cube");
    std::fs::copy(
        fixture.join("camera_ne.json"),
        dir.path().join("camera_ne.json"),
    )
    .unwrap();
    image::GrayImage::from_pixel(512, 480, image::Luma([255]))
        .save(dir.path().join("view_ne.png"))
        .unwrap();
    write(
        dir.path(),
        "lines_ne.json",
        br#"{"points": [], "lines": []}"#,
    );
    let d = dir.path().to_string_lossy().into_owned();
    let recon = dir.path().join("recon.json");
    for extra in [None, Some("--from-truth")] {
        let mut args = vec!["recognize", &d, "--views", "ne", "-o"];
        args.push(recon.to_str().unwrap());
        args.extend(extra);
        let out = common::ok(blockworld(&args));
        assert!(
            out.contains("0 blocks") && out.contains("no block found"),
            "{out}"
        );
        let text = std::fs::read_to_string(&recon).unwrap();
        assert!(text.contains("\"unsupported\""), "{text}");
    }
}

/// Regression: `compare --repeat 0` and `bench recognize --repeat 0` ran once as if given 1;
/// every count of timed runs (and the benchmarks' scene counts) takes at least 1, and 0 is
/// refused before any work, naming the flag.
#[test]
fn counts_of_runs_refuse_zero_naming_the_flag() {
    for args in [
        &["compare", "--repeat", "0"][..],
        &["bench", "recognize", "--repeat", "0"],
        &["bench", "settle", "--repeat", "0"],
        &["bench", "vision", "--repeat", "0"],
        &["bench", "peers", "--rounds", "0"],
        &["bench", "generate", "--count", "0"],
        &["bench", "accuracy", "--count", "0"],
    ] {
        let err = fails_with_2(&blockworld(args));
        let flag = args[args.len() - 2];
        assert!(
            err.contains(flag) && err.contains("give at least 1"),
            "{args:?}: {err}"
        );
    }
}

/// Regression: `view --from 1e300,1e300,1e300` overflowed computing the viewing axes and was
/// reported as "--up is zero or along the line of sight"; the coordinate is refused by its
/// option and number, and an Up of any length counts by its direction alone.
#[test]
fn view_names_an_overflowing_eye_point_not_up() {
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("v.png");
    let two = scene("two_layer.json");
    let view = |extra: &[&str]| {
        let mut args = vec!["view", &two, "-o", png.to_str().unwrap()];
        args.extend_from_slice(extra);
        blockworld(&args)
    };
    for (option, point) in [("--from", "1e300,1e300,1e300"), ("--at", "1e300,0,0")] {
        let err = fails_with_2(&view(&[option, point]));
        assert!(
            err.contains(&format!("{option} coordinate 1e300 mm is out of range"))
                && err.contains("1000000 mm")
                && !err.contains("--up"),
            "{err}"
        );
        assert!(!png.exists());
    }
    common::ok(view(&["--up", "0,1e300,0"]));
    assert!(png.exists());
}

/// Regression: `view PREFIX` with a bad Appendix B file opened its error with "the model" only,
/// and `view --overlay /nonexistent` did not say the overlay file was missing.
#[test]
fn view_names_the_model_file_and_a_missing_overlay() {
    let dir = tempfile::tempdir().unwrap();
    let prefix = dir.path().join("bad");
    write(dir.path(), "bad_vertices.txt", b"garbage\n");
    write(dir.path(), "bad_connections.txt", b"0\n");
    let png = dir.path().join("v.png");
    let p = prefix.to_string_lossy().into_owned();
    let err = fails_with_2(&blockworld(["view", &p, "-o", png.to_str().unwrap()]));
    assert!(
        err.contains(&format!("reading the model {p}")) && err.contains("bad_vertices.txt"),
        "{err}"
    );
    let two = scene("two_layer.json");
    let args = ["view", &two, "--overlay", "/nonexistent", "-o"];
    let err = fails_with_2(&blockworld(args.iter().chain(&[png.to_str().unwrap()])));
    assert!(
        err.contains("the --overlay file /nonexistent is missing"),
        "{err}"
    );
    assert!(!png.exists());
}

/// Appendix B files are read through one reader: a non-UTF-8 byte in either file is reported by
/// `view`, `export` and `score` with its byte offset and the file's name.
#[test]
fn non_utf8_appendix_b_files_name_the_byte_offset_and_file() {
    let dir = tempfile::tempdir().unwrap();
    let prefix = dir.path().join("tl").to_string_lossy().into_owned();
    let o = blockworld([
        "export",
        &scene("two_layer.json"),
        "--format",
        "thesis",
        "-o",
        &prefix,
    ]);
    common::ok(&o);
    let png = dir.path().join("v.png").to_string_lossy().into_owned();
    let glb = dir.path().join("x.glb").to_string_lossy().into_owned();
    let commands: [&[&str]; 3] = [
        &["view", &prefix, "-o", &png],
        &["export", &prefix, "-o", &glb],
        &["score", &prefix, &prefix],
    ];
    common::ok(blockworld(commands[2]));
    for file in ["tl_vertices.txt", "tl_connections.txt"] {
        let path = dir.path().join(file);
        let good = std::fs::read(&path).unwrap();
        let mut bad = good.clone();
        bad[50] = 0xFF;
        std::fs::write(&path, &bad).unwrap();
        for args in commands {
            let err = fails_with_2(&blockworld(args));
            assert!(
                err.contains("byte offset 50") && err.contains(file),
                "{args:?}: {err}"
            );
        }
        std::fs::write(&path, &good).unwrap();
    }
    assert!(!Path::new(&png).exists() && !Path::new(&glb).exists());
}

/// Regression: out-of-range numbers outside the render options were echoed with 300 digits
/// (`--view-angle 1e300`, `--split`, `--stable-fraction`, `--perspective`, settle's
/// tolerances), and negative budgets and tolerances were taken; each is refused before any
/// work, naming its flag, the number echoed short.
#[test]
fn out_of_range_numbers_are_echoed_short_naming_the_flag() {
    let dir = tempfile::tempdir().unwrap();
    let out = |name: &str| dir.path().join(name).to_string_lossy().into_owned();
    let two = scene("two_layer.json");
    let fixture = common::root().join("tests/fixtures/vision/single_cube");
    let view_png = fixture.join("view_ne.png").to_string_lossy().into_owned();
    let camera = fixture
        .join("camera_ne.json")
        .to_string_lossy()
        .into_owned();
    let lines = fixture.join("lines_ne.json").to_string_lossy().into_owned();
    let fix = fixture.to_string_lossy().into_owned();
    let (v, s, r, g) = (out("v.png"), out("s.json"), out("r.json"), out("g"));
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (
            vec!["view", &two, "-o", &v, "--view-angle", "1e300"],
            "--view-angle 1e300",
        ),
        (
            vec!["view", &two, "-o", &v, "--move-from", "1e300"],
            "--move-from 1e300",
        ),
        (
            vec!["settle", &two, "-o", &s, "--drift-tol-mm=-1e300"],
            "--drift-tol-mm -1e300",
        ),
        (
            vec!["settle", &two, "-o", &s, "--turn-tol-deg=-1"],
            "--turn-tol-deg -1 ",
        ),
        (
            vec!["recognize", &fix, "-o", &r, "--time-budget-s=-1e300"],
            "--time-budget-s -1e300",
        ),
        (
            vec!["label", &lines, "--time-budget-s", "0"],
            "--time-budget-s 0 ",
        ),
        (
            vec![
                "generate",
                "--count",
                "1",
                "--keep-unstable",
                "--stable-fraction",
                "1e300",
                "-o",
                &g,
            ],
            "--stable-fraction 1e300",
        ),
        (
            vec!["vertices", &view_png, "--camera", &camera, "--max-gap=-1"],
            "--max-gap -1 ",
        ),
        (
            vec!["bench", "vision", "--perspective", "1e300"],
            "--perspective 1e300",
        ),
        (
            vec!["bench", "vision", "--match-px=-1e300"],
            "--match-px -1e300",
        ),
    ];
    for (args, says) in cases {
        let err = fails_with_2(&blockworld(&args));
        assert!(err.contains(says) && err.len() < 400, "{args:?}: {err}");
    }
    for f in ["v.png", "s.json", "r.json", "g"] {
        assert!(!dir.path().join(f).exists(), "{f} written");
    }
}

/// Regression: an Appendix B pair holding one cube twice (coincident cubes) was read as two
/// blocks; it is refused by `view`, `export` and `score`, naming both blocks.
#[test]
fn coincident_cubes_in_appendix_b_files_are_refused_naming_both() {
    let dir = tempfile::tempdir().unwrap();
    let good = dir.path().join("tc").to_string_lossy().into_owned();
    let two = scene("two_cubes_touching.json");
    common::ok(blockworld([
        "export", &two, "--format", "thesis", "-o", &good,
    ]));
    let text = std::fs::read_to_string(format!("{good}_vertices.txt")).unwrap();
    let mut lines: Vec<&str> = text.lines().collect();
    let (count_line, _) = lines
        .iter()
        .enumerate()
        .find(|(_, l)| l.trim() == "16")
        .unwrap();
    let first: Vec<&str> = lines[count_line + 1..count_line + 9].to_vec();
    lines.splice(count_line + 9..count_line + 17, first);
    let bad = dir.path().join("cc").to_string_lossy().into_owned();
    std::fs::write(format!("{bad}_vertices.txt"), lines.join("\n")).unwrap();
    std::fs::copy(
        format!("{good}_connections.txt"),
        format!("{bad}_connections.txt"),
    )
    .unwrap();
    common::ok(blockworld(["score", &good, &good]));
    let png = dir.path().join("v.png").to_string_lossy().into_owned();
    let glb = dir.path().join("x.glb").to_string_lossy().into_owned();
    let commands: [&[&str]; 3] = [
        &["view", &bad, "-o", &png],
        &["export", &bad, "-o", &glb],
        &["score", &good, &bad],
    ];
    for args in commands {
        let err = fails_with_2(&blockworld(args));
        assert!(
            err.contains("block 1 (faces from 1) and block 2 (faces from 7) overlap by 15.000 mm")
                && err.contains("cc_connections.txt"),
            "{args:?}: {err}"
        );
    }
    assert!(!Path::new(&png).exists() && !Path::new(&glb).exists());
}
