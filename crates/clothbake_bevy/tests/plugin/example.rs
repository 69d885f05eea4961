//! The `drape` example as a user runs it: under Xvfb (an X server without a display; Bevy's
//! wgpu presents through Mesa's lavapipe where there is no GPU) it opens its window, loads the
//! six tables, draws the frames asked for and exits 0.

use crate::common::{bake_tables, scratch};

use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// A hung X server or driver must fail the test, not hold CI: a run takes seconds.
const HANG_GUARD: Duration = Duration::from_secs(300);

#[test]
fn drape_example_draws_frames_under_xvfb_and_exits() {
    let dir = scratch("example");
    // The example shows the built-in scene's fabrics.
    let fabrics = clothbake::scene::Scene::builtin().fabrics;
    bake_tables(
        &dir,
        &fabrics.iter().map(String::as_str).collect::<Vec<_>>(),
    );
    // target/release/deps/plugin-HASH → target/release/examples/drape (cargo test builds the
    // examples of the package it tests).
    let exe = std::env::current_exe().unwrap();
    let example = exe
        .parent()
        .and_then(|deps| deps.parent())
        .map(|profile| profile.join("examples").join("drape"))
        .expect("target directory");
    assert!(example.exists(), "{} not built", example.display());
    let screenshot = dir.join("drape.png");
    let _ = std::fs::remove_file(&screenshot);
    let mut child = Command::new("xvfb-run")
        .args(["-a", "-s", "-screen 0 1280x1024x24"])
        .arg(&example)
        .args(["--frames", "2", "--tables"])
        .arg(&dir)
        .arg("--screenshot")
        .arg(&screenshot)
        .env_remove("WAYLAND_DISPLAY")
        .env_remove("WAYLAND_SOCKET")
        .env(
            "XDG_RUNTIME_DIR",
            std::env::var_os("XDG_RUNTIME_DIR").unwrap_or_else(|| "/tmp".into()),
        )
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap_or_else(|e| panic!("cannot start xvfb-run ({e}): run scripts/setup.sh"));
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > HANG_GUARD {
            let _ = child.kill();
            panic!("drape still running after {HANG_GUARD:?}: killed");
        }
        std::thread::sleep(Duration::from_millis(100));
    }
    let output = child.wait_with_output().unwrap();
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
    println!("{text}");
    assert!(output.status.success(), "drape failed: {text}");
    assert!(text.contains("drape: drew"), "no frame count: {text}");
    assert!(!text.contains("ERROR"), "Bevy logged an error: {text}");
    // The screenshot shows cloth: a good share of its pixels differ from the clear colour.
    let bytes = std::fs::read(&screenshot).expect("screenshot written");
    let decoder = png::Decoder::new(std::io::Cursor::new(bytes));
    let mut reader = decoder.read_info().expect("PNG");
    let mut pixels = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut pixels).expect("PNG frame");
    let channels = info.color_type.samples();
    let lit = pixels
        .chunks_exact(channels)
        .filter(|p| p[..3].iter().any(|&c| c > 40))
        .count();
    let share = lit as f64 / (info.width * info.height) as f64;
    println!(
        "drape screenshot: {}×{}, {:.1}% lit",
        info.width,
        info.height,
        100.0 * share
    );
    assert!(
        share > 0.05,
        "the screenshot shows almost no cloth ({share})"
    );
}
