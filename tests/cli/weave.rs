//! `clothbake weave` as users run it: drawdowns of named weaves and WIF files, a woven fabric
//! that `eval`, `bake` and `check` take unchanged, and bad drafts and knobs refused.

use crate::common::*;

use crate::bake::clothbake;
use clothbake::formats::fabric_toml::FabricSet;

#[test]
fn drawdowns_of_named_weaves() {
    for (weave, drawdown) in [
        ("plain", "#.\n.#\n"),
        ("twill:2/2:s", "##..\n#..#\n..##\n.##.\n"),
        ("sateen:5", "#....\n..#..\n....#\n.#...\n...#.\n"),
    ] {
        let out = clothbake(&["weave", weave, "--drawdown"]);
        assert!(out.status.success(), "{}", output_text(&out));
        assert_eq!(String::from_utf8_lossy(&out.stdout), drawdown, "{weave}");
    }
}

#[test]
fn a_woven_fabric_evaluates_bakes_and_checks() {
    let dir = temp_dir("weave");
    let fabric_file = dir.join("denim.toml");
    let out = clothbake(&[
        "weave",
        "twill:3/1",
        "--yarn",
        "fibre=cotton,crimp=30,legs=0.2",
        "--warp",
        "colour=#203050",
        "--weft",
        "colour=#e0e0d8,cover=0.8",
        "--name",
        "denim",
        "--out",
        path_str(&fabric_file),
    ]);
    let text = output_text(&out);
    assert!(out.status.success(), "{text}");
    // One line per family with its coverage and curve.
    let warp = text
        .lines()
        .find(|l| l.starts_with("thread 1 (warp)"))
        .unwrap();
    assert!(
        warp.contains("face 0.7500") && warp.contains("floats 4×3"),
        "{warp}"
    );
    let set = FabricSet::load(&fabric_file).unwrap();
    let denim = set.require("denim").unwrap();
    assert_eq!(denim.thread1.eta, 1.55);
    // The weft's cover of 0.8 leaves the warp's strip uncovered a fifth of the time.
    assert!((denim.thread1.coverage - (0.2 + 0.8 * 0.75)).abs() < 1e-12);
    let tables = dir.join("tables");
    let bake = clothbake(&[
        "bake",
        "--fabrics",
        path_str(&fabric_file),
        "--fabric",
        "denim",
        "--out",
        path_str(&tables),
    ]);
    assert!(bake.status.success(), "{}", output_text(&bake));
    let check = clothbake(&[
        "check",
        path_str(&tables.join("denim.exr")),
        "--pairs",
        "300",
    ]);
    assert!(check.status.success(), "{}", output_text(&check));
}

#[test]
fn bad_drafts_and_knobs_are_refused_with_the_reason() {
    let dir = temp_dir("weave-bad");
    let out_file = dir.join("x.toml");
    let out = path_str(&out_file);
    for (args, needle) in [
        (
            vec!["weave", "satin:6", "--out", out],
            "no regular satin of 6 ends",
        ),
        (vec!["weave", "twill:2", "--out", out], "N/M"),
        (
            vec!["weave", "plain", "--yarn", "crimp=100", "--out", out],
            "--yarn: yarn knob 'crimp'",
        ),
        (
            vec!["weave", "plain", "--weft", "fibre=hemp", "--out", out],
            "unknown fibre",
        ),
        (vec!["weave", "missing.wif", "--drawdown"], "missing.wif"),
        (vec!["weave", "plain"], "--out"),
    ] {
        let result = clothbake(&args);
        let text = output_text(&result);
        assert!(!result.status.success(), "{args:?} succeeded: {text}");
        assert!(text.contains(needle), "{args:?}: {text}");
        assert!(!text.contains("panicked"), "{args:?}: {text}");
    }
    assert!(!out_file.exists());
    // An unwritable path fails and leaves nothing behind.
    let blocked = dir.join("no-such-dir").join("x.toml");
    let result = clothbake(&["weave", "plain", "--out", path_str(&blocked)]);
    assert!(!result.status.success() && output_text(&result).contains("cannot write"));
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
}
