//! `clothbake view` as a user or a script runs it: under Xvfb (an X server without a display;
//! wgpu then presents through Mesa's lavapipe on machines without a GPU) it opens its window,
//! draws `--frames N` frames and exits 0; without tables or without a display it fails with
//! a message that says what is missing.

use crate::common::*;

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// A hung X server or driver must fail the test rather than hold CI until its global timeout.
/// A run takes a few seconds on two cores (device, shader compilation, 30 frames on
/// lavapipe); this is a hang guard, not a speed check.
const HANG_GUARD: Duration = Duration::from_secs(300);

/// The clothbake binary with `args`, without any Wayland display (so that winit takes the
/// X11 display it is given, or none) and with the Vulkan loader's runtime directory set.
pub(crate) fn clothbake_command(program: &str, args: &[&str]) -> Command {
    let mut command = Command::new(program);
    command
        .args(args)
        .env_remove("WAYLAND_DISPLAY")
        .env_remove("WAYLAND_SOCKET")
        .env(
            "XDG_RUNTIME_DIR",
            std::env::var_os("XDG_RUNTIME_DIR").unwrap_or_else(|| "/tmp".into()),
        )
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    command
}

/// Runs `command` to completion, killing it after [`HANG_GUARD`].
pub(crate) fn run(mut command: Command) -> Output {
    let mut child = command.spawn().unwrap_or_else(|e| {
        if e.kind() == std::io::ErrorKind::NotFound {
            panic!(
                "{:?} not found: run scripts/setup.sh to install Xvfb (xvfb-run), which the \
                 window test needs",
                command.get_program()
            );
        }
        panic!("cannot start {:?}: {e}", command.get_program());
    });
    // Drain the pipes on threads so a chatty child cannot block on a full pipe.
    let mut stdout = child.stdout.take().unwrap();
    let mut stderr = child.stderr.take().unwrap();
    let out = std::thread::spawn(move || {
        let mut v = Vec::new();
        std::io::Read::read_to_end(&mut stdout, &mut v).ok();
        v
    });
    let err = std::thread::spawn(move || {
        let mut v = Vec::new();
        std::io::Read::read_to_end(&mut stderr, &mut v).ok();
        v
    });
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if start.elapsed() > HANG_GUARD {
            let _ = child.kill();
            let _ = child.wait();
            panic!(
                "{:?} still running after {HANG_GUARD:?}: killed",
                command.get_args().collect::<Vec<_>>()
            );
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    Output {
        status,
        stdout: out.join().unwrap(),
        stderr: err.join().unwrap(),
    }
}

fn clothbake(args: &[&str]) -> Output {
    run(clothbake_command(env!("CARGO_BIN_EXE_clothbake"), args))
}

/// Bakes velvet and linen_plain at a small thread_frame resolution (a fraction of a second)
/// into `dir` and writes a scene naming both on a coarse drape, lit by the studio
/// environment at 4 samples per pixel, so that frames are cheap on a CPU rasteriser.
fn bake_small_tables(dir: &Path) -> PathBuf {
    let bake = clothbake(&[
        "bake",
        "--fabric",
        "velvet",
        "linen_plain",
        "--layout",
        "thread_frame",
        "--resolution",
        "8",
        "--out",
        path_str(dir),
    ]);
    assert!(bake.status.success(), "{}", output_text(&bake));
    let scene = dir.join("scene.toml");
    std::fs::write(
        &scene,
        "fabrics = [\"velvet\", \"linen_plain\"]\n[mesh]\nkind = \"drape\"\nresolution = 48\n\
         [environment]\nsamples = 4\n",
    )
    .unwrap();
    scene
}

/// The number after "drew " in the viewer's summary line.
fn frames_drawn(output: &str) -> Option<u64> {
    let rest = &output[output.find("drew ")? + "drew ".len()..];
    rest.split_whitespace().next()?.parse().ok()
}

/// `clothbake view ARGS` under xvfb-run, not yet started. xvfb-run's default screen is
/// 640×480 at 8 bits per pixel, which Vulkan drivers may not present to; it asks for 24-bit
/// colour and room for the viewer's windows (1024×768, and the editor's 1280×800).
pub(crate) fn view_command(args: &[&str]) -> Command {
    let mut all = vec![
        "-a",
        "-s",
        "-screen 0 1280x1024x24",
        env!("CARGO_BIN_EXE_clothbake"),
        "view",
    ];
    all.extend(args);
    clothbake_command("xvfb-run", &all)
}

/// `clothbake view` of `scene` with the tables in `dir` under xvfb-run, drawing `frames`
/// frames, with `more` arguments.
fn view_under_xvfb(scene: &Path, dir: &Path, frames: &str, more: &[&str]) -> Output {
    let mut args = vec![
        "--scene",
        path_str(scene),
        "--tables",
        path_str(dir),
        "--frames",
        frames,
    ];
    args.extend(more);
    run(view_command(&args))
}

#[test]
fn view_draws_the_requested_frames_under_xvfb() {
    let dir = temp_dir("frames");
    let scene = bake_small_tables(&dir);
    let output = view_under_xvfb(&scene, &dir, "30", &[]);
    let all = output_text(&output);
    println!("{all}");
    assert!(output.status.success(), "view failed: {all}");
    let adapter = all
        .lines()
        .find(|l| l.contains("adapter "))
        .unwrap_or_else(|| panic!("no adapter line: {all}"));
    eprintln!("adapter line: {adapter}");
    let frames = frames_drawn(&all).unwrap_or_else(|| panic!("no frame count: {all}"));
    assert!(frames >= 30, "drew {frames} frames: {all}");
    assert!(all.contains("median frame time"), "{all}");
    assert!(all.contains("keys:"), "no key list: {all}");
}

#[test]
fn view_without_tables_or_display_fails_with_a_clear_message() {
    let dir = temp_dir("errors");
    let missing = dir.join("no-such-dir");
    for (args, expected) in [
        (
            vec!["view", "--tables", path_str(&missing), "--frames", "1"],
            "does not exist",
        ),
        // An empty directory: no table for the first fabric.
        (
            vec![
                "view",
                "--tables",
                path_str(&dir),
                "--fabric",
                "velvet",
                "--frames",
                "1",
            ],
            "clothbake bake --fabric velvet",
        ),
    ] {
        let output = clothbake(&args);
        assert!(!output.status.success(), "{args:?} succeeded");
        let all = output_text(&output);
        assert!(all.contains(expected), "{args:?}: {all}");
        assert!(!all.contains("panicked"), "{args:?}: {all}");
    }
    // Tables present but no display at all: an error naming the display, not a panic.
    let scene = bake_small_tables(&dir);
    let mut command = clothbake_command(
        env!("CARGO_BIN_EXE_clothbake"),
        &[
            "view",
            "--scene",
            path_str(&scene),
            "--tables",
            path_str(&dir),
            "--frames",
            "1",
        ],
    );
    command.env_remove("DISPLAY");
    let output = run(command);
    let all = output_text(&output);
    assert!(!output.status.success(), "view without a display succeeded");
    assert!(all.contains("cannot open a window"), "{all}");
    assert!(!all.contains("panicked"), "{all}");
}

#[test]
fn view_shows_the_evaluators_it_is_given_and_refuses_one_without_a_gpu_form() {
    let dir = temp_dir("evaluators");
    let scene = bake_small_tables(&dir);
    let view = |evaluators: &[&str]| {
        let more: Vec<&str> = evaluators
            .iter()
            .flat_map(|spelling| ["--evaluator", spelling])
            .collect();
        let output = view_under_xvfb(&scene, &dir, "3", &more);
        (output.status.success(), output_text(&output))
    };
    // The first of the list is shown at start, through its GPU form.
    let (ok, all) = view(&["paper:8", "constant"]);
    println!("{all}");
    assert!(ok, "view failed: {all}");
    assert!(all.contains("velvet, paper:8 (paper N=8)"), "{all}");
    assert_eq!(frames_drawn(&all), Some(3), "{all}");
    // The converged rule has no shader: refused with the evaluators that have one.
    let (ok, all) = view(&["direct"]);
    assert!(!ok, "view --evaluator direct succeeded: {all}");
    assert!(all.contains("has no GPU form"), "{all}");
    assert!(!all.contains("panicked"), "{all}");
    // A spelling that does not parse is refused before any window opens.
    let output = clothbake(&["view", "--evaluator", "nearest", "--frames", "1"]);
    let all = output_text(&output);
    assert!(
        !output.status.success() && all.contains("unknown evaluator 'nearest'"),
        "{all}"
    );
}
