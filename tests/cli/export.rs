//! `clothbake export`: every target writes a file its engine's own validator accepts (the
//! Khronos glTF-Validator, MaterialX's Python package, the JSON's parameters by the model's
//! names), a fabric from a weave draft exports as a built-in one does, and bad input is
//! refused with no file left behind.
//!
//! The validators are installed by scripts/setup.sh (tools/export-check/README.md); a missing
//! one fails the test with the command to install it rather than skipping.
#![cfg_attr(not(feature = "runtime"), allow(dead_code, unused_imports))]

use crate::bake::clothbake;
use crate::common::*;
use clothbake::export::TARGETS;
use std::path::{Path, PathBuf};
use std::process::Command;

fn repository() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Runs an outside validator, failing with how to install it if it cannot start.
fn validate(program: &Path, script: &str, file: &Path) -> String {
    let out = Command::new(program)
        .arg(repository().join("tools/export-check").join(script))
        .arg(file)
        .output()
        .unwrap_or_else(|e| {
            panic!(
                "cannot run {} ({e}); run scripts/setup.sh, which installs it",
                program.display()
            )
        });
    let text = output_text(&out);
    assert!(
        out.status.success(),
        "{script} refuses {}: {text}",
        file.display()
    );
    text
}

/// Exports `fabric` to `target` and checks what it prints and the file it writes.
fn export(dir: &Path, fabric: &str, fabrics: Option<&Path>, target: &str) -> PathBuf {
    let file = dir.join(format!("{fabric}-{target}.out"));
    let mut args = vec!["export", fabric, "--to", target, "--out", path_str(&file)];
    if let Some(fabrics) = fabrics {
        args.extend(["--fabrics", path_str(fabrics)]);
    }
    let out = clothbake(&args);
    let text = output_text(&out);
    assert!(out.status.success(), "{text}");
    for line in [
        "relative RMS of F",
        "directional albedo",
        "drape image",
        "wrote",
    ] {
        assert!(text.contains(line), "{target}: no '{line}' in {text}");
    }
    file
}

// With the runtime only: scripts/test.sh runs this binary again without it, and the export's
// files are the same either way (only the printed drape-image line differs).
#[cfg(feature = "runtime")]
#[test]
fn every_target_exports_a_file_its_engine_accepts_and_a_woven_fabric_exports_too() {
    let dir = temp_dir("export");
    let woven = dir.join("woven.toml");
    let out = clothbake(&[
        "weave",
        "twill:2/1",
        "--yarn",
        "fibre=wool",
        "--name",
        "twill_wool",
        "--out",
        path_str(&woven),
    ]);
    assert!(out.status.success(), "{}", output_text(&out));
    for (k, target) in TARGETS.iter().enumerate() {
        // Built-in fabrics for half the targets, the woven one for the others.
        let file = if k % 2 == 0 {
            export(&dir, "silk_crepe_de_chine", None, target.name)
        } else {
            export(&dir, "twill_wool", Some(&woven), target.name)
        };
        let text = std::fs::read_to_string(&file).unwrap();
        match target.extension {
            "gltf" => {
                let report = validate(Path::new("node"), "validate-gltf.mjs", &file);
                assert!(report.contains("0 errors"), "{report}");
                let asset: serde_json::Value = serde_json::from_str(&text).unwrap();
                let material = &asset["materials"][0];
                assert!(material["extensions"]["KHR_materials_sheen"].is_object());
                assert!(
                    material["extras"]["clothbake"]["loss"]["uniform"]["relative_rms"].is_f64()
                );
            }
            "mtlx" => {
                let python = repository().join(".venv/bin/python");
                let report = validate(&python, "validate-mtlx.py", &file);
                assert!(report.contains("VALID"), "{report}");
            }
            _ => {
                // The engine's inputs by the model's names, a colour as one array.
                let json: serde_json::Value = serde_json::from_str(&text).unwrap();
                let parameters = json["parameters"].as_object().unwrap();
                for p in target.model.parameters {
                    let key = p.name.rsplit_once('.').map_or(p.name, |(colour, _)| colour);
                    assert!(parameters.contains_key(key), "{}: no {key}", target.name);
                }
                assert!(json["clothbake"]["loss"]["highlight"]["relative_rms"].is_f64());
            }
        }
    }
}

#[test]
fn export_refuses_an_unknown_fabric_a_damaged_file_and_an_unwritable_path_and_leaves_no_file() {
    let dir = temp_dir("export-bad");
    let out_file = dir.join("out.gltf");
    let damaged = dir.join("damaged.toml");
    std::fs::write(&damaged, "[[fabric]]\nname = \"x\"\neta = \"glass\"\n").unwrap();
    let not_a_directory = dir.join("file.txt");
    std::fs::write(&not_a_directory, "").unwrap();
    let below_a_file = not_a_directory.join("out.gltf");
    let out = path_str(&out_file);
    for (args, expected) in [
        (
            vec!["export", "burlap", "--to", "gltf", "--out", out],
            "burlap",
        ),
        (
            vec![
                "export",
                "x",
                "--fabrics",
                path_str(&damaged),
                "--to",
                "gltf",
                "--out",
                out,
            ],
            "damaged.toml",
        ),
        (
            vec!["export", "velvet", "--to", "maya", "--out", out],
            "maya",
        ),
        (
            vec![
                "export",
                "velvet",
                "--to",
                "gltf",
                "--out",
                path_str(&below_a_file),
            ],
            "file.txt",
        ),
    ] {
        let output = clothbake(&args);
        let text = output_text(&output);
        assert!(!output.status.success(), "{args:?}: {text}");
        assert!(text.contains(expected), "{args:?}: {text}");
        assert!(!text.contains("panicked"), "{text}");
        assert!(
            !out_file.exists() && !below_a_file.exists(),
            "{args:?} left a file"
        );
    }
    // Nothing but the inputs in the directory: no temporary file left either.
    let mut names: Vec<String> = std::fs::read_dir(&*dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names, ["damaged.toml", "file.txt"]);
}

#[test]
fn export_help_lists_every_registered_target() {
    let output = clothbake(&["export", "--help"]);
    let text = output_text(&output);
    assert!(output.status.success(), "{text}");
    for target in TARGETS {
        let row = format!(
            "{:<10} .{:<5} {}",
            target.name, target.extension, target.model.title
        );
        assert!(text.contains(&row), "--help lacks {row:?}: {text}");
    }
}
