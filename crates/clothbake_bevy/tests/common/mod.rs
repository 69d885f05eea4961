//! What the tests share: the workspace, scratch directories, small tables.
#![allow(dead_code)] // each test file uses part of it

use bevy::app::ScheduleRunnerPlugin;
use bevy::asset::AssetPlugin;
use bevy::log::LogPlugin;
use bevy::prelude::*;
use bevy::window::ExitCondition;
use bevy::winit::WinitPlugin;
use clothbake_bevy::ClothPlugin;
use std::path::{Path, PathBuf};
use std::time::Duration;

pub fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// `target/clothbake_bevy-tests/NAME`, created.
pub fn scratch(name: &str) -> PathBuf {
    let dir = workspace()
        .join("target")
        .join("clothbake_bevy-tests")
        .join(name);
    std::fs::create_dir_all(&dir).expect("scratch directory");
    dir
}

/// Resolution of the tests' tables: both sides of a comparison read the same table, so its
/// accuracy does not matter, and a small one bakes in about a second.
pub const TEST_RESOLUTION: u32 = 16;

/// Tables of `fabrics` (built-in names) in `dir`, at the default layout and
/// [`TEST_RESOLUTION`]; tables already there and valid are kept.
pub fn bake_tables(dir: &Path, fabrics: &[&str]) {
    let set = clothbake::formats::fabric_toml::FabricSet::builtin();
    for &name in fabrics {
        let path = dir.join(format!("{name}.exr"));
        if clothbake::formats::table_exr::read_table(&path)
            .is_ok_and(|t| t.table.resolution == TEST_RESOLUTION)
        {
            continue;
        }
        let fabric = set.get(name).expect("built-in fabric");
        let table = clothbake::bake::bake(
            fabric,
            clothbake::table::Layout::DEFAULT,
            TEST_RESOLUTION,
            &|| {},
        )
        .expect("bake");
        clothbake::formats::table_exr::write_table(&path, &table).expect("write table");
    }
}

/// A Bevy app with `ClothPlugin`, no window and no logger (one global logger per process, and
/// a test may make several apps), reading assets from `assets`; call `finish` and `cleanup`
/// after adding systems, then `update`.
pub fn headless_app(assets: &Path) -> App {
    let mut app = App::new();
    app.add_plugins(
        DefaultPlugins
            .set(WindowPlugin {
                primary_window: None,
                exit_condition: ExitCondition::DontExit,
                ..default()
            })
            .set(AssetPlugin {
                file_path: assets.to_string_lossy().into_owned(),
                ..default()
            })
            .disable::<WinitPlugin>()
            .disable::<LogPlugin>(),
    )
    .add_plugins((ScheduleRunnerPlugin::run_loop(Duration::ZERO), ClothPlugin));
    app
}
