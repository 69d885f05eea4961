//! Sample files as untrusted input: every error names the file, the line and the field.

use clothbake::fit::samples::{MAX_SAMPLE_FILE_BYTES, SampleError};
use clothbake::fit::solve::FitOptions;
use clothbake::fit::{LikeFabric, Parametrisation, fit, load_samples, parse_samples};
use clothbake::formats::fabric_toml::FabricSet;

const GOOD: &str = r#"{"wi":[0,0,1],"wo":[0.3,0.2,0.9],"f":[0.1,0.2,0.3]}"#;

fn error_of(bad: &str) -> String {
    let text = format!("# header\n{GOOD}\n\n{bad}\n{GOOD}\n");
    parse_samples(text.as_bytes(), "m.jsonl")
        .unwrap_err()
        .to_string()
}

#[test]
fn errors_name_the_line_and_the_field() {
    for (bad, field) in [
        // NaN and infinities are not JSON; serde_json rejects them, and 1e999 overflows.
        (r#"{"wi":[0,0,1],"wo":[0,0,1],"f":[NaN,0,0]}"#, "(line)"),
        (
            r#"{"wi":[0,0,1],"wo":[0,0,1],"f":[Infinity,0,0]}"#,
            "(line)",
        ),
        (r#"{"wi":[0,0,1e999],"wo":[0,0,1],"f":[0,0,0]}"#, "(line)"),
        (r#"{"wi":[0,0,1],"wo":[0,0,1],"f":[0,-1e-3,0]}"#, "'f'"),
        (r#"{"wi":[0,0,1],"wo":[0.5,0.5,-0.1],"f":[0,0,0]}"#, "'wo'"),
        (r#"{"wi":[1,0,0],"wo":[0,0,1],"f":[0,0,0]}"#, "'wi'"),
        (r#"{"wi":[0,0,0],"wo":[0,0,1],"f":[0,0,0]}"#, "'wi'"),
        (
            r#"{"wi":[0,0,1],"wo":[0,0,1],"f":[0,0,0],"weight":0}"#,
            "'weight'",
        ),
        (
            r#"{"wi":[0,0,1],"wo":[0,0,1],"f":[0,0,0],"rgb":[1,1,1]}"#,
            "'rgb'",
        ),
    ] {
        let message = error_of(bad);
        assert!(message.contains("m.jsonl, line 4"), "{bad}: {message}");
        assert!(message.contains(field), "{bad}: {message}");
    }
}

#[test]
fn a_file_over_the_limit_is_refused_before_it_is_read() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("huge.jsonl");
    // Sparse: the size is what is checked, nothing is written.
    std::fs::File::create(&path)
        .unwrap()
        .set_len(MAX_SAMPLE_FILE_BYTES + 1)
        .unwrap();
    let error = load_samples(&path).unwrap_err();
    assert!(matches!(error, SampleError::TooLarge { .. }), "{error}");
    assert!(error.to_string().contains("huge.jsonl"), "{error}");
    let missing = load_samples(&dir.path().join("none.jsonl")).unwrap_err();
    assert!(matches!(missing, SampleError::Io { .. }), "{missing}");
}

#[test]
fn fewer_samples_than_parameters_is_an_error() {
    let fabric = FabricSet::builtin().get("linen_plain").unwrap().clone();
    let like = LikeFabric::new(&fabric, None);
    let n = like.parameters().len();
    let text = vec![GOOD; n].join("\n");
    let samples = parse_samples(text.as_bytes(), "few.jsonl").unwrap();
    // Every 5th held out leaves fewer than n to fit.
    let error = fit(&like, &samples, &FitOptions::default(), &|_| {}).unwrap_err();
    let message = error.to_string();
    assert!(
        message.contains("few.jsonl") && message.contains("fewer than"),
        "{message}"
    );
}

#[test]
fn rows_are_checked_as_lines_are() {
    use clothbake::fit::Samples;
    let good = ([0.0, 0.0, 1.0], [0.3, 0.2, 0.9], [0.1, 0.2, 0.3], None);
    let samples = Samples::from_rows(&[good, good], "arrays").unwrap();
    assert_eq!(samples.samples.len(), 2);
    assert_eq!(samples.sha256.len(), 64);
    let below = ([0.0, 0.0, 1.0], [0.3, 0.2, -0.9], [0.1, 0.2, 0.3], None);
    let error = Samples::from_rows(&[good, good, below], "arrays").unwrap_err();
    let text = error.to_string();
    assert!(text.contains("line 3") && text.contains("'wo'"), "{text}");
    let weightless = ([0.0, 0.0, 1.0], [0.3, 0.2, 0.9], [0.1, 0.2, 0.3], Some(0.0));
    assert!(
        Samples::from_rows(&[weightless], "arrays")
            .unwrap_err()
            .to_string()
            .contains("'weight'")
    );
    assert!(matches!(
        Samples::from_rows(&[], "arrays"),
        Err(SampleError::Empty { .. })
    ));
}

/// 1,000 damaged sample files (lines deleted, duplicated, cut, bytes flipped, numbers made
/// huge, negative, NaN or text, keys renamed) either load or are refused with the line and
/// field named; none panics.
#[test]
fn damaged_sample_files_load_or_name_the_line_and_never_panic() {
    use rand::{Rng, SeedableRng};
    let lines: Vec<String> = (0..12)
        .map(|i| {
            let t = i as f64 / 12.0;
            format!(
                r#"{{"wi":[{:.3},0.1,0.8],"wo":[-0.2,{:.3},0.7],"f":[{:.4},0.2,0.05],"weight":1.5}}"#,
                t - 0.5,
                0.4 - t,
                0.1 + t
            )
        })
        .collect();
    let replacements = ["1e999", "-3", "NaN", "\"x\"", "0", "[]", "null", "1e308"];
    let mut rng = rand_pcg::Pcg64::seed_from_u64(0x46_dead);
    let (mut loaded, mut refused, mut panics) = (0, 0, 0);
    for _ in 0..1000 {
        let mut file: Vec<String> = lines.clone();
        for _ in 0..rng.random_range(1..4) {
            let k = rng.random_range(0..file.len().max(1));
            match rng.random_range(0..7) {
                0 if !file.is_empty() => {
                    file.remove(k);
                }
                1 if !file.is_empty() => {
                    let line = file[k].clone();
                    file.insert(k, line);
                }
                2 if !file.is_empty() => {
                    let cut = rng.random_range(0..=file[k].len());
                    file[k].truncate(cut);
                }
                3 if !file.is_empty() => {
                    let numbers: Vec<usize> = file[k]
                        .match_indices(|c: char| c.is_ascii_digit())
                        .map(|(i, _)| i)
                        .collect();
                    if let Some(&at) = numbers.get(rng.random_range(0..numbers.len().max(1))) {
                        let with = replacements[rng.random_range(0..replacements.len())];
                        file[k].replace_range(at..at + 1, with);
                    }
                }
                4 if !file.is_empty() => {
                    let key = ["\"wi\"", "\"wo\"", "\"f\"", "\"weight\""][rng.random_range(0..4)];
                    file[k] = file[k].replacen(key, "\"w\"", 1);
                }
                5 => file.insert(k.min(file.len()), "# comment".into()),
                _ => {}
            }
        }
        let mut bytes = file.join("\n").into_bytes();
        if rng.random_bool(0.2) && !bytes.is_empty() {
            let at = rng.random_range(0..bytes.len());
            bytes[at] ^= 1 << rng.random_range(0..8);
        }
        match std::panic::catch_unwind(|| parse_samples(&bytes, "damaged.jsonl")) {
            Err(_) => panics += 1,
            Ok(Ok(_)) => loaded += 1,
            Ok(Err(error)) => {
                let text = error.to_string();
                assert!(
                    text.contains("damaged.jsonl")
                        && (text.contains("line ") || text.contains("no samples")),
                    "{text}"
                );
                refused += 1;
            }
        }
    }
    assert_eq!(panics, 0);
    assert!(
        loaded >= 50 && refused >= 300,
        "{loaded} loaded, {refused} refused"
    );
}
