use super::*;
use crate::editor::fields::EditValue;
use crate::editor::session::FILE_FIELD;

/// A script with every action, comments and blank lines among them.
const EVERY_ACTION: &str = "\
# a scripted session
open polyester_satin_charmeuse

set thread1.gamma_s_deg 6.5
   # indented comment
set thread1.albedo 0.2, 0.1 0.05
set warp.colour #203050
set name
undo
redo
save \"out dir/satin.toml\"
open fabrics.toml velvet
wait-bake
save-table \"baked tables\"
screenshot shots/frame-1.png
show edited
show table
show saved
compare off
compare table
compare saved
exposure 1.5
exposure -2ev
exposure +0.5EV
environment on
environment off
environment-map sky
environment-map \"my maps/hall.hdr\"
environment-rotation -45
light 0 40 -120.5
orbit 30 28
frames 3
exit
";

#[test]
fn a_script_of_every_action_parses_and_prints_back() {
    let script = parse(EVERY_ACTION).unwrap();
    let lines: Vec<usize> = script.steps.iter().map(|(l, _)| *l).collect();
    assert_eq!(lines[..3], [2, 4, 6]);
    let actions: Vec<&Action> = script.steps.iter().map(|(_, a)| a).collect();
    assert_eq!(
        actions[1],
        &Action::Set {
            field: "thread1.gamma_s_deg".into(),
            value: "6.5".into()
        }
    );
    assert_eq!(
        actions[3],
        &Action::Set {
            field: "warp.colour".into(),
            value: "#203050".into()
        }
    );
    assert_eq!(
        actions[4],
        &Action::Set {
            field: "name".into(),
            value: String::new()
        }
    );
    assert_eq!(
        actions[7],
        &Action::Save {
            path: "out dir/satin.toml".into()
        }
    );
    assert_eq!(
        actions[8],
        &Action::Open {
            target: "fabrics.toml".into(),
            fabric: Some("velvet".into())
        }
    );
    assert!(actions.contains(&&Action::Exposure(Exposure::Stops(-2.0))));
    assert!(actions.contains(&&Action::Light {
        index: 0,
        elevation_deg: 40.0,
        azimuth_deg: -120.5
    }));
    assert_eq!(actions.last(), Some(&&Action::Exit));
    // Every kind of action is there, and each prints as a line that parses back to it.
    let kinds: std::collections::HashSet<_> =
        actions.iter().map(|a| std::mem::discriminant(*a)).collect();
    assert_eq!(kinds.len(), 18);
    for (_, action) in &script.steps {
        let line = action.to_string();
        let again = parse(&line).unwrap_or_else(|e| panic!("{line}: {e}"));
        assert_eq!(again.steps, [(1, action.clone())], "{line}");
    }
    assert_eq!(Exposure::Stops(-2.0).scale(), 0.25);
    let editor = actions.iter().filter(|a| a.is_editor()).count();
    assert_eq!(editor, 9);
}

#[test]
fn errors_name_the_line_and_the_problem() {
    let cases = [
        ("set thread1.covrage 0.5", "did you mean 'thread1.coverage'"),
        ("set", "set FIELD VALUE"),
        ("jump 3", "unknown action 'jump'"),
        ("undo now", "takes 0 arguments"),
        ("open", "open takes"),
        ("open a b c", "open takes"),
        ("save", "takes 1 argument"),
        ("screenshot shot.jpg", "must end in .png"),
        ("show model", "edited|table|saved"),
        ("compare edited", "off|table|saved"),
        ("environment maybe", "on|off"),
        ("exposure nan", "finite"),
        ("exposure 0", "[0.000001, 1000000]"),
        ("exposure 1e7", "within"),
        ("exposure 40ev", "within"),
        ("exposure xev", "not a number"),
        ("environment-rotation inf", "finite"),
        ("light 8 10 10", "at most 8 lights"),
        ("light -1 10 10", "whole number"),
        ("light 0 95 10", "elevation must be within [-90, 90]"),
        ("light 0 45", "takes 3 arguments"),
        ("orbit 10 90", "pitch must be within"),
        ("orbit 1e9 10", "yaw must be within"),
        ("orbit 10 abc", "not a number"),
        ("frames 0", "from 1 to"),
        ("frames 2.5", "from 1 to"),
        ("frames 1000001", "from 1 to"),
        ("save \"unclosed", "quote is not closed"),
        ("save \"a\"b", "space must follow"),
    ];
    for (line, needle) in cases {
        let text = format!("# comment\n\nframes 1\n{line}\nexit\n");
        let error = parse(&text).unwrap_err();
        assert_eq!(error.line, 4, "{line}");
        let message = error.to_string();
        assert!(message.starts_with("line 4: "), "{message}");
        assert!(message.contains(needle), "{line}: {message}");
    }
}

#[test]
fn set_keeps_its_value_as_typed_for_the_session_to_judge() {
    let script = parse("set thread1.coverage   nan  \nset thread1.albedo [0.1, 0.2, 0.3]").unwrap();
    let mut session = EditSession::builtin("velvet").unwrap();
    let before = session.fabric().clone();
    let (line, action) = &script.steps[0];
    let error = session.run_editor_action(action).unwrap_err();
    let step = StepError {
        line: *line,
        action: action.clone(),
        source: error,
    };
    assert_eq!(
        step.to_string(),
        "line 1: set thread1.coverage nan: thread1.coverage: must be a finite number, got nan"
    );
    assert_eq!(session.fabric(), &before);
    assert!(session.error("thread1.coverage").is_some());
    let (_, action) = &script.steps[1];
    assert_eq!(session.run_editor_action(action).unwrap(), Handled::Editor);
    assert_eq!(session.fabric().thread1.albedo, [0.1, 0.2, 0.3]);
}

#[test]
fn the_editor_runs_its_actions_and_leaves_the_rest_to_the_viewer() {
    let scratch = tempfile::tempdir().unwrap();
    let saved = scratch.path().join("edited satin.toml");
    let text = format!(
        "open satin:5 my_satin\nset warp.crimp 30\nset thread1.coverage 0.7\nundo\nredo\n\
         save \"{}\"\nframes 2\nscreenshot a.png\nexit\n",
        saved.display()
    );
    let script = parse(&text).unwrap();
    let mut session = EditSession::builtin("velvet").unwrap();
    let mut handled = Vec::new();
    for (_, action) in &script.steps {
        handled.push(session.run_editor_action(action).unwrap());
    }
    use Handled::{Editor, Viewer};
    assert_eq!(
        handled,
        [
            Editor, Editor, Editor, Editor, Editor, Editor, Viewer, Viewer, Viewer
        ]
    );
    assert_eq!(session.fabric().name, "my_satin");
    assert_eq!(session.fabric().thread1.coverage, 0.7);
    assert_eq!(
        session.value("warp.crimp").unwrap(),
        EditValue::Number(30.0)
    );
    let read = crate::formats::fabric_toml::FabricSet::load(&saved).unwrap();
    assert_eq!(read.fabrics(), std::slice::from_ref(session.fabric()));
    // Nothing to undo after an open, and a damaged open, are errors that change nothing.
    let mut fresh = EditSession::builtin("velvet").unwrap();
    assert!(matches!(
        fresh.run_editor_action(&Action::Redo),
        Err(ActionError::NothingToRedo)
    ));
    let missing = Action::Open {
        target: scratch.path().join("missing.wif").display().to_string(),
        fabric: None,
    };
    assert!(fresh.run_editor_action(&missing).is_err());
    assert!(fresh.error(FILE_FIELD).unwrap().contains("missing.wif"));
    assert_eq!(fresh.fabric().name, "velvet");
}

#[test]
fn ranges_are_the_scene_files() {
    let scene = |key: &str, value: f64| {
        let text = format!("fabrics = [\"velvet\"]\n{key} = {value:e}\n");
        crate::scene::Scene::parse(&text).is_ok()
    };
    let camera = |key: &str, value: f64| {
        let text = format!("fabrics = [\"velvet\"]\n[camera]\n{key} = {value:e}\n");
        crate::scene::Scene::parse(&text).is_ok()
    };
    let (lo, hi) = EXPOSURE_RANGE;
    assert!(scene("exposure", lo) && scene("exposure", hi));
    assert!(!scene("exposure", lo.next_down()) && !scene("exposure", hi.next_up()));
    for (key, (lo, hi)) in [("yaw_deg", YAW_RANGE_DEG), ("pitch_deg", PITCH_RANGE_DEG)] {
        assert!(camera(key, lo) && camera(key, hi), "{key}");
        assert!(
            !camera(key, lo.next_down()) && !camera(key, hi.next_up()),
            "{key}"
        );
    }
}

#[test]
fn script_files_are_bounded_and_named_in_errors() {
    let scratch = tempfile::tempdir().unwrap();
    let path = scratch.path().join("bad.script");
    std::fs::write(&path, "frames 1\nframes x\n").unwrap();
    let error = Script::load(&path).unwrap_err().to_string();
    assert!(
        error.contains("bad.script") && error.contains("line 2"),
        "{error}"
    );
    let big = scratch.path().join("big.script");
    std::fs::write(&big, vec![b'#'; MAX_SCRIPT_BYTES as usize + 1]).unwrap();
    assert!(matches!(
        Script::load(&big),
        Err(ScriptFileError::TooLarge { .. })
    ));
    assert!(Script::load(&scratch.path().join("none")).is_err());
}
