//! `clothbake bake` and `clothbake check` as users run them: manifests, scenes, budgets,
//! bad arguments, and an interrupted bake leaving the previous table intact.

use crate::common::*;

use clothbake::formats::table_exr::read_table;
use clothbake::table::wgsl::lookup_wgsl;

use std::process::{Command, Output};
use std::time::Duration;

/// Runs the `clothbake` binary with `args` and no input.
pub(crate) fn clothbake(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_clothbake"))
        .args(args)
        .output()
        .expect("spawn clothbake")
}

#[test]
fn unchanged_fabrics_are_not_baked_again_and_changed_ones_are() {
    let dir = temp_dir("manifest");
    let out = path_str(&dir);
    let args = [
        "bake",
        "--fabric",
        "velvet",
        "--layout",
        "grid4d",
        "--resolution",
        "4",
        "--out",
        out,
    ];
    let first = clothbake(&args);
    assert!(first.status.success(), "{}", output_text(&first));
    assert!(output_text(&first).contains("baked in"));
    let second = clothbake(&args);
    assert!(
        output_text(&second).contains("up to date"),
        "{}",
        output_text(&second)
    );
    // A changed fabric (here through a fabric file) is baked again.
    let fabrics = dir.join("fabrics.toml");
    std::fs::write(
        &fabrics,
        clothbake::formats::fabric_toml::BUILTIN_FABRICS_TOML.replace("kd = 0.1", "kd = 0.2"),
    )
    .unwrap();
    let mut changed = args.to_vec();
    changed.extend(["--fabrics", path_str(&fabrics)]);
    let third = clothbake(&changed);
    assert!(
        output_text(&third).contains("baked in"),
        "{}",
        output_text(&third)
    );
    assert_eq!(
        read_table(&dir.join("velvet.exr"))
            .unwrap()
            .table
            .fabric
            .thread1
            .kd,
        0.2
    );
    let check = clothbake(&["check", path_str(&dir.join("velvet.exr")), "--pairs", "200"]);
    assert!(
        check.status.success() && output_text(&check).contains("baked in"),
        "{}",
        output_text(&check)
    );
}

#[test]
fn scene_bakes_only_its_fabrics_and_error_budget_picks_a_resolution() {
    let dir = temp_dir("scene");
    let scene = dir.join("scene.toml");
    std::fs::write(
        &scene,
        "fabrics = [\"silk_shot\"]\nlayout = \"grid4d\"\n[budget]\nmax_error = 0.5\n",
    )
    .unwrap();
    let out = clothbake(&["bake", "--scene", path_str(&scene), "--out", path_str(&dir)]);
    assert!(out.status.success(), "{}", output_text(&out));
    assert!(
        output_text(&out).contains("chosen for the error budget"),
        "{}",
        output_text(&out)
    );
    let names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(
        names.contains(&"silk_shot.exr".to_string())
            && !names.iter().any(|n| n.starts_with("velvet")),
        "{names:?}"
    );
    // Every rung tried before the chosen one missed the budget, the chosen one met it.
    let tried: Vec<(u32, f64)> = output_text(&out)
        .lines()
        .filter_map(|l| {
            let rest = l.strip_prefix("silk_shot: grid4d at resolution ")?;
            let (resolution, errors) = rest.split_once(": relative RMS ")?;
            let worst = errors
                .split(['%', ','])
                .filter_map(|x| x.trim().split(' ').next()?.parse::<f64>().ok())
                .fold(0.0, f64::max);
            Some((resolution.parse().ok()?, worst / 100.0))
        })
        .collect();
    let chosen = read_table(&dir.join("silk_shot.exr"))
        .unwrap()
        .table
        .resolution;
    let (last, earlier) = tried
        .split_last()
        .expect("the tried resolutions are reported");
    assert_eq!(last.0, chosen);
    assert!(
        last.1 <= 0.5 && earlier.iter().all(|(_, e)| *e > 0.5),
        "{tried:?}"
    );
}

#[test]
fn bad_arguments_and_scene_files_exit_non_zero_with_a_message() {
    let dir = temp_dir("badbake");
    let out = path_str(&dir);
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, "fabrics = []\n").unwrap();
    let wrong = dir.join("wrong.toml");
    std::fs::write(&wrong, "fabrics = [\"velvet\"]\ncamera = 3\n").unwrap();
    for (args, expected) in [
        (
            vec!["bake", "--fabric", "tweed", "--out", out],
            "no fabric named 'tweed'",
        ),
        (
            vec!["bake", "--layout", "spiral", "--out", out],
            "unknown layout 'spiral'",
        ),
        (
            vec![
                "bake",
                "--fabric",
                "velvet",
                "--resolution",
                "1",
                "--out",
                out,
            ],
            "outside 2..=",
        ),
        (
            vec!["bake", "--fabric", "velvet", "--max-error=-1", "--out", out],
            "--max-error must be a positive number",
        ),
        (
            vec!["bake", "--scene", path_str(&scene), "--out", out],
            "names no fabric",
        ),
        (
            vec!["bake", "--scene", path_str(&wrong), "--out", out],
            "camera",
        ),
        (
            vec!["check", path_str(&dir.join("missing.exr"))],
            "missing.exr",
        ),
    ] {
        let result = clothbake(&args);
        assert!(!result.status.success(), "{args:?} succeeded");
        assert!(
            output_text(&result).contains(expected),
            "{args:?}: {}",
            output_text(&result)
        );
    }
}

/// Kill bakes at several moments, including while the table is being written: the table
/// that was there before always loads, and no partial file takes its name.
#[test]
fn interrupted_bake_leaves_the_previous_table_loadable() {
    let dir = temp_dir("interrupt");
    let out = path_str(&dir);
    let table = dir.join("polyester_satin_charmeuse.exr");
    let first = clothbake(&[
        "bake",
        "--fabric",
        "polyester_satin_charmeuse",
        "--layout",
        "grid4d",
        "--resolution",
        "6",
        "--out",
        out,
    ]);
    assert!(first.status.success(), "{}", output_text(&first));
    let before = std::fs::read(&table).unwrap();
    let mut kills = 0;
    // A grid4d bake at resolution 12 takes about a second on two cores; the delays span its
    // computation, its write, and its completion.
    let delays = [
        50, 200, 400, 600, 800, 900, 1000, 1100, 1200, 1300, 1500, 1800, 2500, 4000,
    ];
    for delay_ms in delays {
        let mut child = Command::new(env!("CARGO_BIN_EXE_clothbake"))
            .args([
                "bake",
                "--fabric",
                "polyester_satin_charmeuse",
                "--force",
                "--layout",
                "grid4d",
                "--resolution",
                "12",
                "--out",
                out,
            ])
            .stdout(std::process::Stdio::null())
            .spawn()
            .unwrap();
        std::thread::sleep(Duration::from_millis(delay_ms));
        if child.try_wait().unwrap().is_none() {
            child.kill().unwrap();
            kills += 1;
        }
        child.wait().unwrap();
        let file =
            read_table(&table).unwrap_or_else(|e| panic!("after a kill at {delay_ms} ms: {e}"));
        // Either the old table, untouched, or a complete new one.
        let now = std::fs::read(&table).unwrap();
        assert!(
            now == before || file.table.resolution == 12,
            "at {delay_ms} ms"
        );
    }
    println!(
        "{kills} of {} bakes killed before they finished",
        delays.len()
    );
    // The next bake clears the temporaries the killed ones left behind.
    let last = clothbake(&[
        "bake",
        "--fabric",
        "polyester_satin_charmeuse",
        "--force",
        "--layout",
        "grid4d",
        "--resolution",
        "4",
        "--out",
        out,
    ]);
    assert!(last.status.success(), "{}", output_text(&last));
    let stray: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".tmp"))
        .collect();
    assert!(stray.is_empty(), "{stray:?}");
    assert!(
        kills >= 2,
        "bakes finished too fast to be interrupted: {kills} killed"
    );
}

/// `clothbake wgsl` prints exactly the shader the runtime uses for the table, and refuses a
/// file that is not a table.
#[test]
fn wgsl_prints_the_specialised_lookup_of_a_table() {
    let dir = temp_dir("wgsl");
    let out = path_str(&dir);
    let bake = clothbake(&[
        "bake",
        "--fabric",
        "velvet",
        "--layout",
        "split_frame",
        "--resolution",
        "8",
        "--out",
        out,
    ]);
    assert!(bake.status.success(), "{}", output_text(&bake));
    let table = dir.join("velvet.exr");
    let baked = read_table(&table).unwrap().table;
    let printed = clothbake(&["wgsl", path_str(&table)]);
    assert!(printed.status.success(), "{}", output_text(&printed));
    let expected = lookup_wgsl(&baked);
    assert_eq!(String::from_utf8_lossy(&printed.stdout), expected);
    assert!(expected.contains("fn cloth_brdf("));

    let not_a_table = dir.join("scene.toml");
    std::fs::write(&not_a_table, "fabrics = []\n").unwrap();
    let refused = clothbake(&["wgsl", path_str(&not_a_table)]);
    assert!(!refused.status.success());
    assert!(
        output_text(&refused).contains("scene.toml"),
        "{}",
        output_text(&refused)
    );
    assert!(refused.stdout.is_empty());
}
