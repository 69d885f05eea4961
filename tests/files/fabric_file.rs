//! Fabric files: the built-in set, the schema, and rejection of bad files with errors that
//! name the fabric, the thread and the field.

use crate::common;
use clothbake::formats::fabric_toml::{FabricFileError, FabricSet};
use proptest::prelude::*;

const NAMES: [&str; 6] = [
    "linen_plain",
    "silk_crepe_de_chine",
    "polyester_satin_charmeuse",
    "polyester_satin_charmeuse_back",
    "silk_shot",
    "velvet",
];

#[test]
fn builtin_set_holds_the_six_measured_fabrics() {
    let set = FabricSet::builtin();
    let names: Vec<&str> = set.fabrics().iter().map(|f| f.name.as_str()).collect();
    assert_eq!(names, NAMES);
    let satin = set.get("polyester_satin_charmeuse").unwrap();
    assert_eq!(satin.thread1.offsets_deg.len(), 8);
    assert_eq!(
        satin.thread1.albedo_rgb(),
        [0.035, 0.035 * 0.37, 0.035 * 0.3]
    );
    assert_eq!(satin.thread1.gamma_s_deg, 2.5);
    assert_eq!(set.get("velvet").unwrap().thread2.lengths, [0.5, 0.0, 0.5]);
}

/// A valid one-fabric file with `edit` applied to its text.
fn file_with(edit: impl Fn(String) -> String) -> String {
    let base = r#"
[[fabric]]
name = "test"
[fabric.thread1]
eta = 1.5
albedo = [0.5, 0.5, 0.5]
kd = 0.3
gamma_s_deg = 10.0
gamma_v_deg = 20.0
coverage = 0.4
offsets_deg = [-20.0, 20.0]
lengths = [1.0]
[fabric.thread2]
eta = 1.5
albedo = [0.5, 0.5, 0.5]
kd = 0.3
gamma_s_deg = 10.0
gamma_v_deg = 20.0
coverage = 0.4
offsets_deg = [0.0]
"#;
    edit(base.to_string())
}

fn error_of(text: &str) -> String {
    match FabricSet::parse(text, "test.toml") {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn valid_minimal_file_parses_with_defaults() {
    let set = FabricSet::parse(&file_with(|s| s), "test.toml").unwrap();
    let f = &set.fabrics()[0];
    assert_eq!(f.options, clothbake::model::ModelOptions::default());
    assert_eq!(f.thread1.albedo_scale, 1.0);
}

#[test]
fn bad_fields_are_named_with_fabric_and_thread() {
    let cases: &[(&str, &str, &str)] = &[
        (
            "eta = 1.5\nalbedo = [0.5, 0.5, 0.5]\nkd = 0.3\ngamma_s_deg = 10.0\ngamma_v_deg = 20.0\ncoverage = 0.4\noffsets_deg = [-20.0",
            "eta = 0.9\nalbedo = [0.5, 0.5, 0.5]\nkd = 0.3\ngamma_s_deg = 10.0\ngamma_v_deg = 20.0\ncoverage = 0.4\noffsets_deg = [-20.0",
            "fabric 'test', thread 1, field 'eta'",
        ),
        (
            "kd = 0.3\ngamma_s_deg = 10.0\ngamma_v_deg = 20.0\ncoverage = 0.4\noffsets_deg = [0.0]",
            "kd = 1.3\ngamma_s_deg = 10.0\ngamma_v_deg = 20.0\ncoverage = 0.4\noffsets_deg = [0.0]",
            "thread 2, field 'kd'",
        ),
        (
            "gamma_s_deg = 10.0\ngamma_v_deg = 20.0\ncoverage = 0.4\noffsets_deg = [0.0]",
            "gamma_s_deg = 0.0\ngamma_v_deg = 20.0\ncoverage = 0.4\noffsets_deg = [0.0]",
            "thread 2, field 'gamma_s_deg'",
        ),
        (
            "coverage = 0.4\noffsets_deg = [0.0]",
            "coverage = 0.7\noffsets_deg = [0.0]",
            "field 'coverage': thread1.coverage + thread2.coverage",
        ),
        (
            "offsets_deg = [-20.0, 20.0]",
            "offsets_deg = [-20.0, 95.0]",
            "thread 1, field 'offsets_deg'",
        ),
        (
            "offsets_deg = [0.0]",
            "offsets_deg = []",
            "thread 2, field 'offsets_deg': needs at least one",
        ),
        (
            "lengths = [1.0]",
            "lengths = [1.0, 2.0]",
            "thread 1, field 'lengths'",
        ),
        (
            "lengths = [1.0]",
            "lengths = [-1.0]",
            "thread 1, field 'lengths'",
        ),
        ("name = \"test\"", "name = \"../evil\"", "field 'name'"),
        (
            "albedo = [0.5, 0.5, 0.5]\nkd = 0.3\ngamma_s_deg = 10.0\ngamma_v_deg = 20.0\ncoverage = 0.4\noffsets_deg = [0.0]",
            "albedo = [0.5, -0.5, 0.5]\nkd = 0.3\ngamma_s_deg = 10.0\ngamma_v_deg = 20.0\ncoverage = 0.4\noffsets_deg = [0.0]",
            "thread 2, field 'albedo'",
        ),
        (
            "kd = 0.3\ngamma_s_deg = 10.0\ngamma_v_deg = 20.0\ncoverage = 0.4\noffsets_deg = [-20",
            "kd = nan\ngamma_s_deg = 10.0\ngamma_v_deg = 20.0\ncoverage = 0.4\noffsets_deg = [-20",
            "thread 1, field 'kd': must be a finite number",
        ),
    ];
    for (from, to, expected) in cases {
        let text = file_with(|s| s.replacen(from, to, 1));
        assert_ne!(text, file_with(|s| s), "edit {from:?} did not apply");
        let message = error_of(&text);
        assert!(
            message.contains(expected),
            "expected {expected:?} in {message:?}"
        );
    }
}

#[test]
fn all_zero_lengths_and_bad_options_are_rejected() {
    let text = file_with(|s| {
        s.replacen(
            "offsets_deg = [-20.0, 20.0]\nlengths = [1.0]",
            "offsets_deg = [-20.0, 0.0, 20.0]\nlengths = [0.0, 0.0]",
            1,
        )
    });
    assert!(error_of(&text).contains("are all zero"));
    let text = file_with(|s| {
        s.replacen(
            "name = \"test\"",
            "name = \"test\"\noptions = { sigma_u_deg = -3.0 }",
            1,
        )
    });
    assert!(error_of(&text).contains("options.sigma_u_deg"));
    let text = file_with(|s| {
        s.replacen(
            "name = \"test\"",
            "name = \"test\"\noptions = { gaussian_width = \"wide\" }",
            1,
        )
    });
    assert!(error_of(&text).contains("gaussian_width"));
    // A single segment ignores its length, even 0.
    let text = file_with(|s| s.replacen("lengths = [1.0]", "lengths = [0.0]", 1));
    FabricSet::parse(&text, "test.toml").unwrap();
}

#[test]
fn unknown_keys_missing_fields_duplicates_and_empty_files_are_rejected() {
    let message = error_of(&file_with(|s| {
        s.replacen("kd = 0.3", "kd = 0.3\nroughness = 2.0", 1)
    }));
    assert!(message.contains("roughness"), "{message}");
    let message = error_of(&file_with(|s| s.replacen("coverage = 0.4\n", "", 1)));
    assert!(message.contains("coverage"), "{message}");
    let twice = file_with(|s| format!("{s}{s}"));
    assert!(matches!(
        FabricSet::parse(&twice, "t"),
        Err(FabricFileError::Duplicate { .. })
    ));
    assert!(matches!(
        FabricSet::parse("", "t"),
        Err(FabricFileError::Empty { .. })
    ));
    assert!(matches!(
        FabricSet::parse("[[fabric]", "t"),
        Err(FabricFileError::Parse { .. })
    ));
}

#[test]
fn oversized_and_missing_files_are_rejected_before_reading() {
    let dir = common::temp_dir("fabric");
    let big = dir.join("big.toml");
    let file = std::fs::File::create(&big).unwrap();
    file.set_len(clothbake::formats::fabric_toml::MAX_FABRIC_FILE_BYTES + 1)
        .unwrap();
    assert!(matches!(
        FabricSet::load(&big),
        Err(FabricFileError::TooLarge { .. })
    ));
    assert!(matches!(
        FabricSet::load(&dir.join("missing.toml")),
        Err(FabricFileError::Io { .. })
    ));
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    /// Random damage to a valid file (cut, byte changes, inserted text) gives an error or a
    /// valid set, never a panic; whatever parses also validates.
    #[test]
    fn damaged_files_never_panic(
        cut in 0usize..600,
        flips in proptest::collection::vec((0usize..600, any::<u8>()), 0..6),
        insert in "[ -~\n]{0,12}",
        at in 0usize..600,
    ) {
        let mut bytes = file_with(|s| s).into_bytes();
        for (pos, byte) in flips {
            let len = bytes.len();
            bytes[pos % len] = byte;
        }
        let mut text = String::from_utf8_lossy(&bytes).into_owned();
        let at = text.char_indices().map(|(i, _)| i).nth(at % text.chars().count()).unwrap_or(0);
        text.insert_str(at, &insert);
        let cut = text.char_indices().map(|(i, _)| i).nth(cut % text.chars().count()).unwrap_or(0);
        let text = if cut > 300 { text[..cut].to_string() } else { text };
        if let Ok(set) = FabricSet::parse(&text, "fuzz") {
            for f in set.fabrics() {
                prop_assert!(f.validate().is_ok());
            }
        }
    }

    /// Out-of-range values of every numeric field of thread 2 are rejected, naming it.
    #[test]
    fn out_of_range_numbers_are_rejected(
        field in prop::sample::select(vec!["eta", "kd", "gamma_s_deg", "gamma_v_deg", "coverage", "albedo_scale"]),
        value in prop_oneof![-1e6..-1e-9f64, 1.0001f64..1e6, Just(f64::INFINITY), Just(f64::NAN)],
    ) {
        // Only these fields accept values above 1 (coverage then breaks a1 + a2 ≤ 1).
        let valid_anyway = matches!(field, "eta" | "gamma_s_deg" | "gamma_v_deg" | "albedo_scale")
            && value.is_finite() && value > 1.0;
        let literal = if value.is_nan() { "nan".to_string() } else if value.is_infinite() { "inf".to_string() } else { format!("{value:?}") };
        let text = file_with(|s| {
            let (head, thread2) = s.split_once("[fabric.thread2]\n").unwrap();
            let kept: Vec<&str> = thread2.lines().filter(|l| !l.starts_with(&format!("{field} ="))).collect();
            format!("{head}[fabric.thread2]\n{field} = {literal}\n{}\n", kept.join("\n"))
        });
        match FabricSet::parse(&text, "fuzz") {
            Ok(_) => prop_assert!(valid_anyway, "accepted {field} = {value}"),
            Err(e) => {
                let message = e.to_string();
                prop_assert!(message.contains(field) && message.contains("thread 2"), "{message}");
            }
        }
    }
}
