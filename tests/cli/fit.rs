//! `clothbake fit` end to end: a sample file in, a fabric file out that loads; errors exit
//! non-zero and leave no file.

use crate::bake::clothbake;
use clothbake::fit::samples::{synthetic_samples, write_samples};
use clothbake::fit::{LikeFabric, Parametrisation, perturbed};
use clothbake::formats::fabric_toml::FabricSet;
use clothbake::measure::direction_sets::uniform_pairs;
use std::path::Path;

fn write_sample_file(path: &Path) {
    let fabric = FabricSet::builtin().get("velvet").unwrap().clone();
    let like = LikeFabric::new(&fabric, Some(1.46));
    let moved = like.fabric(&perturbed(&like, 0.1, 5));
    let samples = synthetic_samples(&moved, &uniform_pairs(150, 9), 0.03, 10);
    let mut text = b"# velvet moved by 10%, 3% noise\n".to_vec();
    write_samples(&samples, &mut text).unwrap();
    std::fs::write(path, text).unwrap();
}

#[test]
fn fit_writes_a_fabric_file_that_loads() {
    let dir = tempfile::tempdir().unwrap();
    let samples = dir.path().join("velvet.jsonl");
    write_sample_file(&samples);
    let out = dir.path().join("fitted.toml");
    let s = samples.to_str().unwrap();
    let o = out.to_str().unwrap();
    let output = clothbake(&[
        "fit",
        s,
        "--like",
        "velvet",
        "--fibre",
        "linen",
        "--name",
        "velvet_fit",
        "--out",
        o,
    ]);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&output.stderr)
    );
    assert!(stdout.contains("held out"), "{stdout}");
    let set = FabricSet::load(&out).unwrap();
    let fitted = set.require("velvet_fit").unwrap();
    assert_eq!(fitted.thread1.eta, 1.46);
    let text = std::fs::read_to_string(&out).unwrap();
    let hash = clothbake::formats::table_exr::hex(&{
        use sha2::Digest;
        sha2::Sha256::digest(std::fs::read(&samples).unwrap())
    });
    assert!(text.starts_with("# Fitted by clothbake fit"), "{text}");
    assert!(text.contains(&hash), "{text}");
    assert!(
        text.contains("150 samples: 120 fitted, 30 held out"),
        "{text}"
    );
}

#[test]
fn errors_exit_non_zero_and_write_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let good = dir.path().join("good.jsonl");
    write_sample_file(&good);
    let bad = dir.path().join("bad.jsonl");
    std::fs::write(
        &bad,
        "{\"wi\":[0,0,1],\"wo\":[0,0,1],\"f\":[0.1,0.1,0.1]}\n{\"wi\":[0,0,1],\"wo\":[0,0,-1],\"f\":[0.1,0.1,0.1]}\n",
    )
    .unwrap();
    let out = dir.path().join("out.toml");
    let o = out.to_str().unwrap();
    let (g, b) = (good.to_str().unwrap(), bad.to_str().unwrap());
    for (args, expected) in [
        (vec!["fit", b, "--like", "velvet", "--out", o], "line 2"),
        (vec!["fit", g, "--like", "no_such", "--out", o], "no_such"),
        (
            vec![
                "fit",
                g,
                "--like",
                "velvet",
                "--fibre",
                "unobtainium",
                "--out",
                o,
            ],
            "unobtainium",
        ),
        (
            vec!["fit", g, "--weave", "satin:6", "--out", o],
            "no regular satin",
        ),
        (
            vec![
                "fit", g, "--weave", "plain", "--warp", "crimp=-1", "--out", o,
            ],
            "--warp",
        ),
        (
            vec![
                "fit", g, "--like", "velvet", "--name", "bad name", "--out", o,
            ],
            "name",
        ),
        (vec!["fit", g, "--out", o], "--like"),
    ] {
        let output = clothbake(&args);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(!output.status.success(), "{args:?}");
        assert!(stderr.contains(expected), "{args:?}: {stderr}");
        assert!(!out.exists(), "{args:?} left a file");
    }
}

/// `fit --weave`: the yarn knobs of a plain weave fitted to samples of a plain weave of other
/// knobs; the fitted fabric keeps the weave's form of curve and reproduces the held-out samples to the noise.
#[test]
fn fit_from_a_weave_draft() {
    use clothbake::weave::{NamedWeave, Weave};
    let dir = tempfile::tempdir().unwrap();
    let mut weave = Weave::new("plain".parse::<NamedWeave>().unwrap().draft());
    weave
        .warp
        .set_all("fibre=linen,crimp=35,kd=0.5,colour=#80a0ff")
        .unwrap();
    weave
        .weft
        .set_all("fibre=linen,crimp=20,gamma_s=8,cover=0.7")
        .unwrap();
    let truth = weave.fabric("truth").unwrap();
    let samples = synthetic_samples(&truth, &uniform_pairs(300, 21), 0.01, 22);
    let path = dir.path().join("plain.jsonl");
    let mut text = Vec::new();
    write_samples(&samples, &mut text).unwrap();
    std::fs::write(&path, text).unwrap();
    let out = dir.path().join("fitted.toml");
    let output = clothbake(&[
        "fit",
        path.to_str().unwrap(),
        "--weave",
        "plain",
        "--fibre",
        "linen",
        "--out",
        out.to_str().unwrap(),
    ]);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let set = FabricSet::load(&out).unwrap();
    let fitted = set.require("plain").unwrap();
    assert_eq!(fitted.thread1.eta, 1.46);
    // The weave's form of curve: symmetric, from −crimp to +crimp.
    let offsets = &fitted.thread1.offsets_deg;
    assert!(
        offsets.len() <= 8 && offsets[0] == -offsets[offsets.len() - 1],
        "{offsets:?}"
    );
    assert!(fitted.thread1.coverage + fitted.thread2.coverage <= 1.0);
    // 1% noise: the held-out relative RMS sits at the noise, well under 2%.
    let held_out: f64 = stdout
        .split("relative RMS ")
        .nth(1)
        .and_then(|rest| rest.split(", ").nth(1))
        .and_then(|held| held.split('%').next())
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("no held-out figure in {stdout}"));
    assert!(held_out < 2.0, "{stdout}");
}
