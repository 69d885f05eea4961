use super::*;
use crate::editor::fields::{FIELDS, FieldKind, value_text};
use crate::formats::draft_source::load_draft;
use crate::formats::fabric_toml::FabricSet;
use crate::model::Fabric;
use std::collections::BTreeMap;

fn builtins() -> Vec<String> {
    FabricSet::builtin()
        .fabrics()
        .iter()
        .map(|f| f.name.clone())
        .collect()
}

/// The fabric as its file writes it, leaf by leaf: `thread1.coverage` → its TOML value.
fn leaves(fabric: &Fabric) -> BTreeMap<String, toml::Value> {
    fn walk(prefix: &str, value: toml::Value, out: &mut BTreeMap<String, toml::Value>) {
        match value {
            toml::Value::Table(table) => {
                for (key, value) in table {
                    let path = if prefix.is_empty() {
                        key
                    } else {
                        format!("{prefix}.{key}")
                    };
                    walk(&path, value, out);
                }
            }
            leaf => {
                out.insert(prefix.to_string(), leaf);
            }
        }
    }
    let mut out = BTreeMap::new();
    walk("", toml::Value::try_from(fabric).unwrap(), &mut out);
    out
}

fn toml_of(value: &EditValue) -> toml::Value {
    match value {
        EditValue::Number(v) => toml::Value::Float(*v),
        EditValue::Vector(v) => toml::Value::Array(v.iter().map(|&x| x.into()).collect()),
        EditValue::Choice(t) | EditValue::Text(t) => toml::Value::String(t.clone()),
    }
}

/// Values to try on a field holding `value`: each number moved by one ulp towards 0, or
/// away from it (one of which stays within any range); the other choices.
fn candidates(spec: &FieldSpec, value: &EditValue) -> Vec<EditValue> {
    let nudged = |v: f64| {
        if v > 0.0 {
            [v.next_down(), v.next_up()]
        } else {
            [v.next_up(), v.next_down()]
        }
    };
    match (spec.kind(), value) {
        (FieldKind::Choice(choices), _) => choices
            .iter()
            .map(|c| EditValue::Choice(c.to_string()))
            .collect(),
        (FieldKind::Text, _) => vec![EditValue::Text("renamed-1".into())],
        (_, EditValue::Number(v)) => nudged(*v).map(EditValue::Number).to_vec(),
        (_, EditValue::Vector(v)) => (0..2)
            .map(|k| EditValue::Vector(v.iter().map(|&x| nudged(x)[k]).collect()))
            .collect(),
        _ => panic!("{}: {value:?}", spec.path),
    }
}

#[test]
fn every_field_sets_exactly_its_place_in_the_fabric_file_on_every_builtin() {
    for name in builtins() {
        let mut session = EditSession::builtin(&name).unwrap();
        assert_eq!(session.fields().count(), 22, "no knobs without a weave");
        for spec in session.fields() {
            let before = session.fabric().clone();
            let value = session.value(spec.path).unwrap();
            assert_eq!(
                toml_of(&value),
                leaves(&before)[spec.path],
                "{name} {}",
                spec.path
            );
            let mut accepted = 0;
            for candidate in candidates(spec, &value) {
                let revision = session.revision();
                if session
                    .apply(&Edit::new(spec.path, candidate.clone()))
                    .is_err()
                {
                    assert_eq!(session.fabric(), &before);
                    continue;
                }
                accepted += 1;
                assert_eq!(
                    session.value(spec.path).unwrap(),
                    candidate,
                    "{name} {}",
                    spec.path
                );
                // Only this field's place in the file changed, to exactly the value set.
                let (old, new) = (leaves(&before), leaves(session.fabric()));
                let changed: Vec<&String> = new.keys().filter(|k| old[*k] != new[*k]).collect();
                if candidate != value {
                    assert_eq!(changed, [spec.path], "{name}");
                    assert_eq!(session.revision(), revision + 1);
                }
                assert_eq!(new[spec.path], toml_of(&candidate));
                // Its text reads back to the same value.
                let text = session.text(spec.path).unwrap();
                assert_eq!(spec.parse_text(&text).unwrap(), candidate, "{text}");
                while session.undo() {}
                assert_eq!(session.fabric(), &before);
            }
            assert!(accepted > 0, "{name} {}: nothing accepted", spec.path);
        }
    }
}

#[test]
fn the_registry_covers_every_key_of_the_fabric_file_once() {
    let fabric = EditSession::builtin("velvet").unwrap().fabric().clone();
    let file: Vec<String> = leaves(&fabric).into_keys().collect();
    let mut registry: Vec<&str> = FIELDS
        .iter()
        .filter(|f| !f.is_knob())
        .map(|f| f.path)
        .collect();
    registry.sort();
    assert_eq!(registry, file);
    let mut paths: Vec<&str> = FIELDS.iter().map(|f| f.path).collect();
    paths.dedup();
    assert_eq!(paths.len(), FIELDS.len());
}

#[test]
fn bad_values_are_refused_beside_the_field_and_change_nothing() {
    let mut session = EditSession::builtin("polyester_satin_charmeuse").unwrap();
    session.apply_text("thread1.kd", "0.5").unwrap();
    let (fabric, revision) = (session.fabric().clone(), session.revision());
    let free = 1.0 - fabric.thread2.coverage;
    let over = (free + 0.01).to_string();
    let mut lengths = fabric.thread1.lengths.clone();
    lengths[0] = -1.0;
    let negative = value_text(&EditValue::Vector(lengths));
    let cases: &[(&str, &str, &str)] = &[
        ("thread1.coverage", "nan", "finite"),
        ("thread1.coverage", "inf", "finite"),
        ("thread1.coverage", "1e999", "finite"),
        ("thread1.coverage", "", "no value"),
        ("thread1.coverage", "abc", "not a number"),
        ("thread1.coverage", "1.5", "within [0, 1]"),
        (
            "thread1.coverage",
            &over,
            "thread1.coverage + thread2.coverage",
        ),
        (
            "thread2.coverage",
            "0.99",
            "thread1.coverage + thread2.coverage",
        ),
        ("thread1.gamma_s_deg", "-1", "> 0"),
        ("thread2.gamma_v_deg", "0", "> 0"),
        ("thread1.eta", "0.9", "at least 1"),
        ("thread1.albedo", "0.1 0.2", "takes 3 numbers"),
        ("thread1.albedo", "0.1 nan 0.2", "finite"),
        ("thread1.albedo", "0.1 -0.2 0.2", "≥ 0"),
        (
            "thread1.lengths",
            "1 2 3 4 5 6 7 8 9",
            "one length per segment",
        ),
        ("thread1.offsets_deg", "", "at least one control point"),
        ("thread1.offsets_deg", "0 x", "not a number"),
        ("thread1.lengths", &negative, "≥ 0"),
        ("thread1.offsets_deg", "0 95", "within [-90, 90]"),
        ("options.sigma_u_deg", "0", "(0, 180]"),
        ("options.gaussian_width", "wide", "not one of"),
        ("name", "a name", "may hold only"),
    ];
    for &(field, text, needle) in cases {
        let error = session.apply_text(field, text).unwrap_err();
        assert_eq!(error.field(), field);
        assert!(
            error.message().contains(needle),
            "{field} {text:?}: {error}"
        );
        assert_eq!(session.error(field), Some(error.message().as_str()));
        assert_eq!(session.fabric(), &fabric, "{field} {text:?}");
        assert_eq!(session.revision(), revision);
    }
    // Widget values too.
    for value in [f64::NAN, f64::INFINITY, -0.5] {
        let edit = Edit::new("thread1.coverage", EditValue::Number(value));
        assert!(session.apply(&edit).is_err());
    }
    let wrong = Edit::new("thread1.kd", EditValue::Choice("std_dev".into()));
    assert!(
        session
            .apply(&wrong)
            .unwrap_err()
            .message()
            .contains("kind")
    );
    assert_eq!(session.fabric(), &fabric);
    // One step of history: the good edit before.
    assert!(session.undo() && !session.can_undo());
    assert!(session.redo());
    // A good edit of the field clears its error and no other.
    session.apply_text("thread1.coverage", "0.5").unwrap();
    assert_eq!(session.error("thread1.coverage"), None);
    assert!(session.error("thread1.albedo").is_some());
    let unknown = session.apply_text("thread1.covrage", "0.5").unwrap_err();
    assert!(
        unknown
            .to_string()
            .contains("did you mean 'thread1.coverage'"),
        "{unknown}"
    );
    let knob = session.apply_text("warp.crimp", "30").unwrap_err();
    assert!(matches!(knob, EditError::NotAWeave { .. }), "{knob}");
}

#[test]
fn undo_and_redo_restore_the_exact_fabrics() {
    let mut session = EditSession::builtin("silk_shot").unwrap();
    let mut history = vec![session.fabric().clone()];
    let mut revisions = vec![session.revision()];
    for (field, text) in [
        ("thread1.gamma_s_deg", "7.25"),
        ("thread2.albedo", "0.1, 0.2, 0.30000000000000004"),
        ("thread1.offsets_deg", "-30 0 30"),
        ("options.tangent_sampling", "control_points"),
    ] {
        session.apply_text(field, text).unwrap();
        history.push(session.fabric().clone());
        revisions.push(session.revision());
    }
    // Offsets of another count of points resized the lengths.
    assert_eq!(session.fabric().thread1.lengths.len(), 2);
    assert!(revisions.windows(2).all(|w| w[1] > w[0]));
    for expected in history.iter().rev().skip(1) {
        let revision = session.revision();
        assert!(session.undo());
        assert_eq!(session.fabric(), expected);
        assert!(session.revision() > revision);
    }
    assert!(!session.undo());
    for expected in &history[1..] {
        assert!(session.redo());
        assert_eq!(session.fabric(), expected);
    }
    assert!(!session.redo());
    // A new edit after an undo drops the redo steps.
    session.undo();
    session.apply_text("thread1.kd", "0.125").unwrap();
    assert!(!session.can_redo());
    // The same value again is no step.
    let revision = session.revision();
    session.apply_text("thread1.kd", "0.125").unwrap();
    assert_eq!(session.revision(), revision);
}

#[test]
fn a_dragged_slider_is_one_undo_step() {
    let mut session = EditSession::builtin("velvet").unwrap();
    let start = session.fabric().clone();
    for v in [10.0, 11.0, 12.0] {
        let edit = Edit::new("thread1.gamma_s_deg", EditValue::Number(v));
        session.apply_coalesced(&edit).unwrap();
    }
    session.end_gesture();
    let edit = Edit::new("thread1.gamma_s_deg", EditValue::Number(13.0));
    session.apply_coalesced(&edit).unwrap();
    assert_eq!(session.fabric().thread1.gamma_s_deg, 13.0);
    assert!(session.undo());
    assert_eq!(session.fabric().thread1.gamma_s_deg, 12.0);
    assert!(session.undo());
    assert_eq!(session.fabric(), &start);
    assert!(!session.can_undo());
}

#[test]
fn saving_writes_a_file_that_reads_back_to_the_same_fabric() {
    let scratch = tempfile::tempdir().unwrap();
    let mut session = EditSession::builtin("linen_plain").unwrap();
    assert!(!session.is_dirty());
    for (field, text) in [
        ("thread1.gamma_s_deg", "0.30000000000000004"),
        ("thread2.albedo", "0.1 0.7 1e-300"),
        ("thread1.lengths", "2.220446049250313e-16"),
        ("thread2.eta", "1.3333333333333333"),
        ("options.gaussian_width", "sqrt2_std_dev"),
        ("name", "linen_edited"),
    ] {
        session.apply_text(field, text).unwrap();
    }
    assert!(session.is_dirty());
    let path = scratch.path().join("edited.toml");
    session.save(&path).unwrap();
    assert!(!session.is_dirty());
    assert_eq!(session.saved(), session.fabric());
    assert_eq!(session.saved_path(), Some(path.as_path()));
    let read = FabricSet::load(&path).unwrap();
    assert_eq!(read.fabrics(), std::slice::from_ref(session.fabric()));
    // No temporary file is left beside it.
    assert_eq!(std::fs::read_dir(scratch.path()).unwrap().count(), 1);
    // And a session opened from it holds the same fabric.
    let reopened = EditSession::from_path(&path).unwrap();
    assert_eq!(reopened.fabric(), session.fabric());
    // A save that cannot be written is refused beside the file.
    session.apply_text("thread1.kd", "0.5").unwrap();
    let nowhere = scratch.path().join("missing").join("x.toml");
    assert!(session.save(&nowhere).is_err());
    assert!(session.error(FILE_FIELD).unwrap().contains("missing"));
    assert!(session.is_dirty());
    assert_eq!(session.saved_path(), Some(path.as_path()));
}

#[test]
fn damaged_files_leave_the_session_as_it_was() {
    let scratch = tempfile::tempdir().unwrap();
    let mut session = EditSession::builtin("velvet").unwrap();
    session.apply_text("thread1.kd", "0.5").unwrap();
    let (fabric, revision) = (session.fabric().clone(), session.revision());
    let toml = scratch.path().join("damaged.toml");
    std::fs::write(&toml, "[[fabric]]\nname = \"x\"\neta = = 3\n").unwrap();
    let wif = scratch.path().join("damaged.wif");
    std::fs::write(
        &wif,
        "[WIF]\nVersion=1.1\n[WEAVING]\nShafts=4\nTreadles=4\n[WARP]\nThreads=abc\n",
    )
    .unwrap();
    let invalid = scratch.path().join("invalid.toml");
    let mut text = fabric_file_text_of(&fabric);
    text = text.replace("coverage = ", "coverage = 1");
    std::fs::write(&invalid, text).unwrap();
    for (path, needles) in [
        (&toml, vec!["damaged.toml", "line 3"]),
        (&wif, vec!["damaged.wif", "line 7"]),
        (&invalid, vec!["invalid.toml", "coverage"]),
        (&scratch.path().join("none.toml"), vec!["none.toml"]),
    ] {
        let error = session.open(path).unwrap_err().to_string();
        for needle in needles {
            assert!(error.contains(needle), "{needle}: {error}");
        }
        assert_eq!(session.fabric(), &fabric);
        assert_eq!(session.revision(), revision);
        assert!(session.can_undo());
        assert_eq!(session.error(FILE_FIELD), Some(error.as_str()));
    }
    // A good file replaces the session, history and all, and the revision moves on.
    session.open_target("plain", Some("plain_edit")).unwrap();
    assert!(session.revision() > revision && !session.can_undo());
    assert_eq!(session.fabric().name, "plain_edit");
    assert_eq!(session.error(FILE_FIELD), None);
}

fn fabric_file_text_of(fabric: &Fabric) -> String {
    crate::formats::fabric_toml::fabric_file_text(std::slice::from_ref(fabric), "")
}

#[test]
fn targets_resolve_to_files_builtins_and_weaves() {
    let scratch = tempfile::tempdir().unwrap();
    let set = FabricSet::builtin();
    let path = scratch.path().join("two.toml");
    let two = &set.fabrics()[..2];
    crate::formats::fabric_toml::write_fabric_file(&path, two, "").unwrap();
    let first = EditSession::from_path(&path).unwrap();
    assert_eq!(first.fabric(), &two[0]);
    let second = EditSession::from_target(path.to_str().unwrap(), Some(&two[1].name)).unwrap();
    assert_eq!(second.fabric(), &two[1]);
    assert!(matches!(second.source(), Source::File { .. }));
    let missing = EditSession::from_target(path.to_str().unwrap(), Some("nope"));
    assert!(missing.unwrap_err().to_string().contains("nope"));
    let velvet = EditSession::from_target("velvet", None).unwrap();
    assert_eq!(velvet.source(), &Source::Builtin("velvet".into()));
    assert!(EditSession::from_target("velvet", Some("x")).is_err());
    let satin = EditSession::from_target("satin:5", None).unwrap();
    assert!(satin.draft().is_some() && satin.fields().count() == FIELDS.len());
    let unknown = EditSession::from_target("velvett", None)
        .unwrap_err()
        .to_string();
    assert!(
        unknown.contains("velvet") && unknown.contains("twill"),
        "{unknown}"
    );
    let wif = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/wif/zero_unused.wif");
    let woven = EditSession::from_path(&wif).unwrap();
    assert_eq!(woven.fabric().name, "zero_unused");
    assert!(woven.draft().is_some());
}

/// The knobs set in order on a fresh weave, as `clothbake weave --warp … --weft …` would.
fn woven_by_command(spelling: &str, knobs: &[(&str, &str)], name: &str) -> Fabric {
    let (draft, _) = load_draft(spelling).unwrap();
    let mut weave = Weave::new(draft);
    for (field, value) in knobs {
        let (family, key) = field.split_once('.').unwrap();
        let yarn = if family == "warp" {
            &mut weave.warp
        } else {
            &mut weave.weft
        };
        yarn.set(key, &value.replace(' ', "/")).unwrap();
    }
    weave.fabric(name).unwrap()
}

#[test]
fn knob_edits_weave_the_fabric_the_weave_command_makes() {
    let knobs = [
        ("warp.crimp", "30"),
        ("warp.legs", "0.2"),
        ("weft.cover", "0.5"),
        ("warp.colour", "#203050"),
        ("weft.colour", "0.9 0.85 0.8"),
        ("weft.squash", "0.4"),
        ("weft.knee", "0.6"),
        ("warp.flatten", "0.8"),
        ("warp.sag", "4"),
        ("warp.eta", "1.345"),
        ("weft.albedo_scale", "0.5"),
        ("weft.kd", "0.6"),
        ("warp.gamma_s", "7"),
        ("weft.gamma_v", "30"),
    ];
    let mut session = EditSession::from_weave("satin:5", false, false, None).unwrap();
    let name = session.fabric().name.clone();
    assert_eq!(session.fabric(), &woven_by_command("satin:5", &[], &name));
    for (i, (field, value)) in knobs.iter().enumerate() {
        session.apply_text(field, value).unwrap();
        assert_eq!(
            session.fabric(),
            &woven_by_command("satin:5", &knobs[..=i], &name),
            "after {field}"
        );
    }
    // Each knob reads back what it was set to.
    assert_eq!(
        session.value("warp.crimp").unwrap(),
        EditValue::Number(30.0)
    );
    assert_eq!(
        session.value("weft.colour").unwrap(),
        EditValue::Vector(vec![0.9, 0.85, 0.8])
    );
    assert_eq!(session.value("weft.cover").unwrap(), EditValue::Number(0.5));
    let text = session.text("weft.colour").unwrap();
    let revision = session.revision();
    session.apply_text("weft.colour", &text).unwrap();
    assert_eq!(
        session.revision(),
        revision,
        "its text sets the same colour"
    );
    // Undo takes the knobs back with the fabric.
    assert!(session.undo());
    assert_eq!(
        session.value("weft.gamma_v").unwrap(),
        EditValue::Number(24.0)
    );
    assert_eq!(
        session.fabric(),
        &woven_by_command("satin:5", &knobs[..knobs.len() - 1], &name)
    );
    // Refused knob values name the knob and change nothing.
    let fabric = session.fabric().clone();
    for (field, text) in [
        ("warp.crimp", "95"),
        ("warp.crimp", "nan"),
        ("weft.cover", "0"),
    ] {
        let error = session.apply_text(field, text).unwrap_err();
        assert!(
            error.message().contains(field.split('.').nth(1).unwrap()),
            "{error}"
        );
        assert_eq!(session.fabric(), &fabric);
        assert_eq!(session.error(field), Some(error.message().as_str()));
    }
}

#[test]
fn a_knob_keeps_the_hand_edits_it_does_not_decide() {
    let mut session = EditSession::from_weave("twill:3/1", false, false, None).unwrap();
    session.apply_text("thread1.kd", "0.7").unwrap();
    session.apply_text("options.sigma_u_deg", "15").unwrap();
    session.apply_text("thread1.offsets_deg", "-10 10").unwrap();
    session.apply_text("warp.gamma_s", "5").unwrap();
    let fabric = session.fabric();
    assert_eq!((fabric.thread1.kd, fabric.options.sigma_u_deg), (0.7, 15.0));
    assert_eq!(fabric.thread1.offsets_deg, [-10.0, 10.0]);
    assert_eq!(fabric.thread1.gamma_s_deg, 5.0);
    // The shape knob makes the curve again; the optics and options edited by hand stay.
    session.apply_text("warp.crimp", "30").unwrap();
    let fabric = session.fabric();
    assert_eq!(fabric.thread1.offsets_deg.first(), Some(&-30.0));
    assert_eq!((fabric.thread1.kd, fabric.options.sigma_u_deg), (0.7, 15.0));
    session.apply_text("warp.kd", "0.2").unwrap();
    assert_eq!(session.fabric().thread1.kd, 0.2);
    assert_eq!(
        session.fabric().thread2.kd,
        0.3,
        "the weft's yarn is its own"
    );
}

#[test]
fn every_knob_reads_back_what_it_sets() {
    let mut session = EditSession::from_weave("plain", false, true, None).unwrap();
    for spec in FIELDS.iter().filter(|f| f.is_knob()) {
        let (lo, hi) = spec.range;
        let value = match spec.kind() {
            FieldKind::Colour(_) => EditValue::Vector(vec![0.25, 0.5, 0.75]),
            _ => EditValue::Number(0.3 * lo + 0.7 * hi),
        };
        session
            .apply(&Edit::new(spec.path, value.clone()))
            .unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(session.value(spec.path).unwrap(), value, "{}", spec.path);
        let text = value_text(&value);
        assert_eq!(session.text(spec.path).unwrap(), text);
    }
}
