//! The editor's background bake makes what `clothbake bake` makes of the same fabric file:
//! the same table file, byte for byte, and stored as `bake` stores it.

use crate::bake::clothbake;
use crate::common::*;
use clothbake::editor::background::{BackgroundBake, write_baked};
use clothbake::formats::fabric_toml::{FabricSet, write_fabric_file};

#[test]
fn a_background_bake_is_byte_identical_to_the_bake_command() {
    let dir = temp_dir("background");
    // An edited fabric, as the editor saves it.
    let mut fabric = fabric("linen_plain");
    fabric.name = "edited_linen".into();
    fabric.thread1.kd = 0.25;
    let file = dir.join("edited.toml");
    write_fabric_file(&file, std::slice::from_ref(&fabric), "# edited\n").unwrap();
    let fabric = FabricSet::load_or_builtin(Some(&file))
        .unwrap()
        .require("edited_linen")
        .unwrap()
        .clone();

    let baked = BackgroundBake::start_default(fabric, Some(4))
        .wait()
        .unwrap();
    let by_command = dir.join("by-command");
    let out = clothbake(&[
        "bake",
        "--fabrics",
        path_str(&file),
        "--no-taps",
        "--out",
        path_str(&by_command),
    ]);
    assert!(out.status.success(), "{}", output_text(&out));
    let expected = std::fs::read(by_command.join("edited_linen.exr")).unwrap();
    assert!(baked.exr == expected, "the table files differ");

    // Written as `bake` writes: the command then finds table and taps up to date.
    let by_editor = dir.join("by-editor");
    let path = write_baked(&by_editor, &baked).unwrap();
    assert_eq!(std::fs::read(&path).unwrap(), expected);
    let again = clothbake(&[
        "bake",
        "--fabrics",
        path_str(&file),
        "--env-samples",
        "4",
        "--out",
        path_str(&by_editor),
    ]);
    let text = output_text(&again);
    assert!(
        text.contains("up to date (split_frame")
            && text.contains("sample taps for 4 environment samples up to date"),
        "{text}"
    );
}
