//! The command line as users script it: `clothbake fabrics` and `clothbake eval`.

use crate::common::*;
use clothbake::model::{Integration, Patch, ResonantNodes};
use std::io::Write;
use std::process::{Command, Output, Stdio};

/// Runs the binary with `stdin` on its standard input.
pub(crate) fn clothbake(args: &[&str], stdin: &str) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_clothbake"))
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn clothbake");
    let mut input = child.stdin.take().unwrap();
    let text = stdin.to_string();
    let writer = std::thread::spawn(move || {
        let _ = input.write_all(text.as_bytes());
    });
    let output = child.wait_with_output().unwrap();
    writer.join().unwrap();
    output
}

fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

fn parse_f(line: &str) -> [f64; 3] {
    let v: serde_json::Value = serde_json::from_str(line).unwrap();
    let f = v["f"].as_array().unwrap();
    [0, 1, 2].map(|i| f[i].as_f64().unwrap())
}

#[test]
fn fabrics_lists_the_builtin_set() {
    let out = clothbake(&["fabrics"], "");
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    for fabric in builtin() {
        assert!(text.contains(&fabric.name), "{text}");
    }
}

#[test]
fn eval_matches_the_library_and_normalises_directions() {
    let input = "{\"wi\":[0,0,2],\"wo\":[0.3,0.2,0.9]}\n{\"wi\":[1e-3,-2e-3,4e-3],\"wo\":[-3,1,2]}\n{\"wi\":[1,0,-1],\"wo\":[0,0,1]}\r\n";
    for (args, integration) in [
        (vec!["eval", "--fabric", "silk_shot"], Integration::Direct),
        (
            vec!["eval", "--fabric", "silk_shot", "--samples", "8"],
            Integration::Paper(8),
        ),
        (
            vec!["eval", "--fabric", "silk_shot", "--integration", "paper"],
            Integration::Paper(32),
        ),
        (
            vec!["eval", "--fabric", "silk_shot", "--integration", "resonant"],
            Integration::Resonant(ResonantNodes::DEFAULT),
        ),
        (
            vec![
                "eval",
                "--fabric",
                "silk_shot",
                "--integration",
                "resonant",
                "--surface-nodes",
                "9",
                "--base-nodes",
                "4",
            ],
            Integration::Resonant(ResonantNodes {
                surface: 9,
                base: 4,
                ..ResonantNodes::DEFAULT
            }),
        ),
    ] {
        let out = clothbake(&args, input);
        assert!(out.status.success(), "{}", stderr(&out));
        let lines: Vec<&str> = std::str::from_utf8(&out.stdout).unwrap().lines().collect();
        assert_eq!(lines.len(), 3);
        let patch = Patch::new(&fabric("silk_shot"), integration);
        let pairs = [
            ([0., 0., 2.], [0.3, 0.2, 0.9]),
            ([1e-3, -2e-3, 4e-3], [-3., 1., 2.]),
            ([1., 0., -1.], [0., 0., 1.]),
        ];
        for (line, (wi, wo)) in lines.iter().zip(pairs) {
            let expected = patch.eval(
                glam::DVec3::from(wi).normalize(),
                glam::DVec3::from(wo).normalize(),
            );
            let got = parse_f(line);
            for c in 0..3 {
                assert!(
                    (got[c] - expected[c]).abs() <= 1e-15 * expected[c].abs(),
                    "{line} vs {expected}"
                );
            }
        }
        assert_eq!(parse_f(lines[2]), [0.0; 3], "below the horizon");
    }
}

#[test]
fn bad_lines_stop_with_the_line_number_after_earlier_output() {
    let good = "{\"wi\":[0,0,1],\"wo\":[0,0.5,1]}\n";
    for (bad, expected) in [
        ("{\"wi\":[0,0,0],\"wo\":[0,0,1]}", "wi is the zero vector"),
        ("{\"wi\":[0,0,1],\"wo\":[0,0,1e999]}", "line 3"),
        ("{\"wi\":[0,0,1]}", "missing field `wo`"),
        ("{\"wi\":[0,0,1],\"wo\":[0,1]}", "line 3"),
        ("not json", "line 3"),
        ("", "line 3"),
        (
            "{\"wi\":[0,0,1],\"wo\":[0,0,1],\"extra\":1}",
            "unknown field `extra`",
        ),
    ] {
        let input = format!("{good}{good}{bad}\n{good}");
        let out = clothbake(
            &["eval", "--fabric", "linen_plain", "--samples", "4"],
            &input,
        );
        assert!(!out.status.success(), "{bad:?} accepted");
        let message = stderr(&out);
        assert!(
            message.contains("input line 3") && message.contains(expected),
            "{bad:?}: {message}"
        );
        assert_eq!(
            String::from_utf8(out.stdout).unwrap().lines().count(),
            2,
            "{bad:?}: earlier lines lost"
        );
    }
}

#[test]
fn bad_arguments_and_fabric_files_exit_non_zero() {
    let out = clothbake(&["eval", "--fabric", "tweed"], "");
    assert!(!out.status.success());
    assert!(stderr(&out).contains("no fabric named 'tweed'") && stderr(&out).contains("velvet"));
    let out = clothbake(&["eval", "--fabric", "velvet", "--samples", "0"], "");
    assert!(!out.status.success());
    // Options that do not belong to the chosen rule, and node counts out of range.
    for (args, expected) in [
        (
            vec!["--integration", "direct", "--samples", "8"],
            "--samples applies to paper mode",
        ),
        (
            vec!["--integration", "resonant", "--samples", "8"],
            "--samples applies to paper mode",
        ),
        (vec!["--base-nodes", "3"], "apply to --integration resonant"),
        (
            vec!["--integration", "paper", "--surface-nodes", "3"],
            "apply to --integration resonant",
        ),
        (
            vec!["--integration", "resonant", "--volume-nodes", "0"],
            "--volume-nodes",
        ),
        (
            vec!["--integration", "resonant", "--surface-nodes", "17"],
            "must be in 1..=16",
        ),
        (vec!["--integration", "midpoint"], "--integration"),
    ] {
        let mut all = vec!["eval", "--fabric", "velvet"];
        all.extend(args.iter().copied());
        let out = clothbake(&all, "");
        assert!(!out.status.success(), "{args:?} accepted");
        assert!(
            stderr(&out).contains(expected),
            "{args:?}: {}",
            stderr(&out)
        );
    }
    let dir = temp_dir("cli");
    let path = dir.join("bad.toml");
    let text =
        clothbake::formats::fabric_toml::BUILTIN_FABRICS_TOML.replacen("kd = 0.3", "kd = 3.0", 1);
    std::fs::write(&path, text).unwrap();
    for args in [vec!["fabrics"], vec!["eval", "--fabric", "linen_plain"]] {
        let mut args = args.clone();
        args.extend(["--fabrics", path.to_str().unwrap()]);
        let out = clothbake(&args, "");
        assert!(!out.status.success());
        assert!(
            stderr(&out).contains("fabric 'linen_plain', thread 1, field 'kd'"),
            "{}",
            stderr(&out)
        );
    }
    let out = clothbake(
        &[
            "fabrics",
            "--fabrics",
            dir.join("none.toml").to_str().unwrap(),
        ],
        "",
    );
    assert!(!out.status.success() && stderr(&out).contains("cannot read fabric file"));
}

#[test]
fn eval_streams_many_lines_in_order() {
    // 200,000 lines (40 chunks) through paper mode N = 1; the output keeps input order.
    let count = 200_000;
    let mut input = String::with_capacity(count * 48);
    for i in 0..count {
        let z = 0.05 + 0.9 * (i as f64 / count as f64);
        input.push_str(&format!("{{\"wi\":[0.1,0.2,{z}],\"wo\":[-0.2,0.1,0.7]}}\n"));
    }
    let out = clothbake(&["eval", "--fabric", "velvet", "--samples", "1"], &input);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = String::from_utf8(out.stdout).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), count);
    let patch = Patch::new(&fabric("velvet"), Integration::Paper(1));
    for i in [0, 1, 4095, 4096, 77_777, count - 1] {
        let z = 0.05 + 0.9 * (i as f64 / count as f64);
        let unit = |v| clothbake::formats::json_lines::unit_direction(v, "w").unwrap();
        let expected = patch.eval(unit([0.1, 0.2, z]), unit([-0.2, 0.1, 0.7]));
        assert_eq!(parse_f(lines[i]), expected.to_array(), "line {}", i + 1);
    }
}

/// The numbers of a JSON array field `name` of one output line.
fn json_array(line: &str, name: &str) -> Option<Vec<f64>> {
    let value: serde_json::Value = serde_json::from_str(line).unwrap();
    value[name]
        .as_array()
        .map(|a| a.iter().map(|x| x.as_f64().unwrap()).collect())
}

#[test]
fn sample_agrees_with_eval_pdf_and_f() {
    // Draws for a few wo (one below the horizon: rejected), then each drawn pair through
    // `eval --pdf`: the same density, and weight·pdf = F (both the direct evaluation).
    let requests = [
        ([0.0, 0.0, 1.0], [0.3, 0.6, 0.95]),
        ([0.4, -0.2, 0.5], [0.71, 0.12, 0.44]),
        ([0.9, 0.1, 0.05], [0.05, 0.9, 0.03]),
        ([0.2, 0.3, 0.7], [0.999, 0.001, 0.5]),
        ([0.2, 0.3, -0.7], [0.5, 0.5, 0.5]),
    ];
    let input: String = requests
        .iter()
        .map(|(wo, u)| format!("{{\"wo\":{wo:?},\"u\":{u:?}}}\n"))
        .collect();
    let out = clothbake(&["sample", "--fabric", "silk_shot"], &input);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = String::from_utf8(out.stdout).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), requests.len());
    assert_eq!(
        lines[4], r#"{"wi":null,"pdf":0.0,"weight":[0.0,0.0,0.0]}"#,
        "a wo below the horizon is rejected"
    );
    let mut pairs = String::new();
    let mut drawn = Vec::new();
    for (line, (wo, _)) in lines[..4].iter().zip(&requests) {
        let wi = json_array(line, "wi").expect("an accepted draw");
        let value: serde_json::Value = serde_json::from_str(line).unwrap();
        let pdf = value["pdf"].as_f64().unwrap();
        let weight = json_array(line, "weight").unwrap();
        pairs.push_str(&format!("{{\"wi\":{wi:?},\"wo\":{wo:?}}}\n"));
        drawn.push((pdf, weight));
    }
    let out = clothbake(&["eval", "--fabric", "silk_shot", "--pdf"], &pairs);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = String::from_utf8(out.stdout).unwrap();
    for (line, (pdf, weight)) in text.lines().zip(&drawn) {
        let value: serde_json::Value = serde_json::from_str(line).unwrap();
        let eval_pdf = value["pdf"].as_f64().unwrap();
        let f = parse_f(line);
        // Both print shortest round-trip decimals of the same f64 computation; `eval` gets
        // wi back through that decimal form, so allow a few ulps.
        assert!(
            (eval_pdf - pdf).abs() <= 1e-12 * pdf,
            "pdf {eval_pdf} vs {pdf}"
        );
        for c in 0..3 {
            assert!(
                (weight[c] * pdf - f[c]).abs() <= 1e-12 * f[c].abs().max(1e-300),
                "weight·pdf {} vs F {}",
                weight[c] * pdf,
                f[c]
            );
        }
    }
}

#[test]
fn sample_rejects_bad_lines_and_albedo_prints_the_curve() {
    for (line, message) in [
        (
            r#"{"wo":[0,0,1],"u":[0.5,1.0,0.5]}"#,
            "u[1] = 1 is not in [0, 1)",
        ),
        (
            r#"{"wo":[0,0,1],"u":[-0.1,0.5,0.5]}"#,
            "u[0] = -0.1 is not in [0, 1)",
        ),
        (
            r#"{"wo":[0,0,0],"u":[0.1,0.5,0.5]}"#,
            "wo is the zero vector",
        ),
        (r#"{"wo":[0,0,1]}"#, "missing field `u`"),
    ] {
        let out = clothbake(&["sample", "--fabric", "linen_plain"], &format!("{line}\n"));
        assert!(!out.status.success(), "{line} accepted");
        assert!(
            stderr(&out).contains("input line 1") && stderr(&out).contains(message),
            "{line}: {}",
            stderr(&out)
        );
    }
    let out = clothbake(&["albedo", "--fabric", "velvet", "--samples", "64"], "");
    assert!(out.status.success(), "{}", stderr(&out));
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.starts_with("velvet: directional albedo"), "{text}");
    assert_eq!(
        text.lines()
            .filter(|l| l
                .split_whitespace()
                .next()
                .is_some_and(|t| t.ends_with('°')))
            .count(),
        clothbake::sampling::ALBEDO_ELEVATIONS_DEG.len(),
        "{text}"
    );
    assert!(text.contains("maximum:"), "{text}");
}

#[cfg(feature = "runtime")]
#[test]
fn bad_environments_are_refused_by_name() {
    // Untrusted environment files: missing, truncated, and an unknown kind; and a sample
    // count out of range. Each exits non-zero before any rendering, naming what is wrong.
    let dir = temp_dir("cli-env");
    let truncated = dir.join("truncated.hdr");
    std::fs::write(
        &truncated,
        b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 64 +X 128\n\x02\x02",
    )
    .unwrap();
    let unknown = dir.join("sky.png");
    std::fs::write(&unknown, b"not an image").unwrap();
    let missing = dir.join("missing.exr");
    for (path, expected) in [
        (&truncated, "truncated.hdr"),
        (&unknown, "sky.png"),
        (&missing, "missing.exr"),
    ] {
        let out = clothbake(
            &[
                "render",
                "--out",
                dir.join("frame.png").to_str().unwrap(),
                "--env",
                path.to_str().unwrap(),
            ],
            "",
        );
        assert!(!out.status.success(), "{} accepted", path.display());
        assert!(stderr(&out).contains(expected), "{}", stderr(&out));
        assert!(!dir.join("frame.png").exists());
    }
    let out = clothbake(&["render", "--out", "x.png", "--env-samples", "0"], "");
    assert!(
        !out.status.success() && stderr(&out).contains("--env-samples"),
        "{}",
        stderr(&out)
    );
}

/// `--evaluator` spells every rule the older options select, with the same values, and a bad
/// spelling is refused by name.
#[test]
fn evaluator_spellings_match_the_older_options() {
    let input = "{\"wi\":[0.2,0.1,0.9],\"wo\":[-0.3,0.2,0.8]}\n{\"wi\":[0.7,0,0.3],\"wo\":[-0.6,0.1,0.5]}\n";
    for (spelling, older) in [
        ("direct", vec![]),
        ("paper:8", vec!["--samples", "8"]),
        ("paper", vec!["--integration", "paper"]),
        (
            "resonant:3/2/2",
            vec![
                "--integration",
                "resonant",
                "--surface-nodes",
                "3",
                "--volume-nodes",
                "2",
                "--base-nodes",
                "2",
            ],
        ),
    ] {
        let run = |extra: &[&str]| {
            let mut args = vec!["eval", "--fabric", "polyester_satin_charmeuse"];
            args.extend_from_slice(extra);
            let out = clothbake(&args, input);
            assert!(out.status.success(), "{args:?}: {}", stderr(&out));
            String::from_utf8(out.stdout).unwrap()
        };
        let new = run(&["--evaluator", spelling]);
        assert_eq!(new, run(&older), "--evaluator {spelling} against {older:?}");
        assert_eq!(new.lines().count(), 2);
    }
    for (spelling, expected) in [
        ("nearest", "unknown evaluator 'nearest'"),
        ("paper:0", "paper[:N]"),
        ("resonant:6/5", "resonant[:S/V/B]"),
        ("table:missing.exr", "missing.exr"),
    ] {
        let out = clothbake(
            &["eval", "--fabric", "velvet", "--evaluator", spelling],
            input,
        );
        assert!(!out.status.success(), "{spelling} accepted");
        assert!(
            stderr(&out).contains(expected),
            "{spelling}: {}",
            stderr(&out)
        );
    }
    // The new spelling and the older options are one choice: both at once is an error.
    let out = clothbake(
        &[
            "eval",
            "--fabric",
            "velvet",
            "--evaluator",
            "direct",
            "--samples",
            "4",
        ],
        input,
    );
    assert!(!out.status.success());
}
