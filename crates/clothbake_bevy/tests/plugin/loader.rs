//! Bad table files give Bevy's usual asset error, naming the file and what is wrong, and never
//! a panic: truncated, damaged texels, not an EXR at all, missing, too large.

use crate::common::{bake_tables, headless_app, scratch};

use bevy::asset::LoadState;
use bevy::prelude::*;
use bevy::render::renderer::RenderAdapterInfo;
use bevy::shader::Shader;
use clothbake_bevy::{ClothMaterial, ClothTable};
use std::time::{Duration, Instant};

#[test]
fn bad_tables_fail_to_load_with_a_reason() {
    let dir = scratch("loader");
    bake_tables(&dir, &["linen_plain"]);
    let good = std::fs::read(dir.join("linen_plain.exr")).unwrap();
    std::fs::write(dir.join("truncated.exr"), &good[..good.len() / 2]).unwrap();
    // One bit flipped in the last layer's compressed texels.
    let mut damaged = good.clone();
    let at = damaged.len() - 64;
    damaged[at] ^= 0x40;
    std::fs::write(dir.join("damaged.exr"), &damaged).unwrap();
    std::fs::write(dir.join("not_a_table.exr"), b"#?RADIANCE\nnot an EXR").unwrap();
    // Larger than any table (sparse: no disk used): refused after reading one byte more than
    // the limit, not read whole.
    std::fs::File::create(dir.join("huge.exr"))
        .unwrap()
        .set_len(4 * clothbake::formats::table_exr::MAX_TABLE_FILE_BYTES)
        .unwrap();
    let cases = [
        ("linen_plain.exr", None),
        ("truncated.exr", Some("truncated.exr")),
        ("damaged.exr", Some("damaged.exr")),
        ("not_a_table.exr", Some("not_a_table.exr")),
        ("missing.exr", Some("missing.exr")),
        ("huge.exr", Some("larger than any table")),
    ];

    let mut app = headless_app(&dir);
    app.finish();
    app.cleanup();
    let handles: Vec<Handle<ClothTable>> = {
        let server = app.world().resource::<AssetServer>();
        cases.iter().map(|(path, _)| server.load(*path)).collect()
    };
    let start = Instant::now();
    loop {
        app.update();
        let server = app.world().resource::<AssetServer>();
        let states: Vec<LoadState> = handles.iter().map(|h| server.load_state(h)).collect();
        if states
            .iter()
            .all(|s| matches!(s, LoadState::Loaded | LoadState::Failed(_)))
        {
            for ((path, expected), state) in cases.iter().zip(&states) {
                match (expected, state) {
                    (None, LoadState::Loaded) => println!("{path}: loaded"),
                    (Some(name), LoadState::Failed(error)) => {
                        let message = error.to_string();
                        println!("{path}: {message}");
                        assert!(message.contains(name), "{path}: {message}");
                    }
                    _ => panic!("{path}: {state:?}"),
                }
            }
            let tables = app.world().resource::<Assets<ClothTable>>();
            let table = tables.get(&handles[0]).expect("the good table");
            assert_eq!(table.fabric, "linen_plain");
            break;
        }
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "loads still pending: {states:?}"
        );
    }
}

/// The loader's split_frame shader is clothbake's lookup, the same on every adapter: no
/// evaluation of the model's curve inside it.
#[test]
fn split_frame_shader_is_the_lookup_on_every_adapter() {
    let dir = scratch("loader-split-frame");
    let fabric = clothbake::formats::fabric_toml::FabricSet::builtin()
        .get("linen_plain")
        .expect("built-in fabric")
        .clone();
    let table = clothbake::bake::bake(&fabric, clothbake::table::Layout::SPLIT_FRAME, 16, &|| {})
        .expect("bake");
    clothbake::formats::table_exr::write_table(&dir.join("linen_plain.exr"), &table)
        .expect("write");

    let mut app = headless_app(&dir);
    app.finish();
    app.cleanup();
    let adapter = app.world().resource::<RenderAdapterInfo>();
    println!(
        "Bevy's adapter: {} ({:?})",
        adapter.name, adapter.device_type
    );
    let handle: Handle<ClothTable> = app
        .world()
        .resource::<AssetServer>()
        .load("linen_plain.exr");
    let start = Instant::now();
    loop {
        app.update();
        let server = app.world().resource::<AssetServer>();
        let state = server.load_state(&handle);
        if let LoadState::Failed(error) = &state {
            panic!("{error}");
        }
        let tables = app.world().resource::<Assets<ClothTable>>();
        let shaders = app.world().resource::<Assets<Shader>>();
        if let Some(source) = tables
            .get(&handle)
            .and_then(|table| shaders.get(&table.shader))
            .map(|shader| shader.source.as_str())
        {
            assert!(!source.contains("fn cloth_resonant_means_"));
            assert!(source.contains("fn cloth_split_frame_brdf("));
            assert!(source.contains("fn cloth_brdf("));
            break;
        }
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "load still pending: {state:?}"
        );
    }
}

/// Every table file loads once per material: the sample taps and the albedo map are built on
/// load (seconds per table), and Bevy loads a file again for every labeled sub-asset asked
/// for by path before it has loaded, which once made the `drape` example load each table
/// seven or eight times.
#[test]
fn a_material_loads_its_table_once() {
    #[derive(Resource, Default)]
    struct TableEvents(Vec<String>);
    fn record(mut events: MessageReader<AssetEvent<ClothTable>>, mut seen: ResMut<TableEvents>) {
        seen.0.extend(events.read().map(|e| format!("{e:?}")));
    }

    let dir = scratch("loader-once");
    bake_tables(&dir, &["linen_plain"]);
    let mut app = headless_app(&dir);
    app.init_resource::<TableEvents>()
        .add_systems(Update, record);
    app.finish();
    app.cleanup();
    let material = {
        let server = app.world().resource::<AssetServer>();
        ClothMaterial::load(server, "linen_plain.exr")
    };
    assert!(material.is_pending());
    let handle = app
        .world_mut()
        .resource_mut::<Assets<ClothMaterial>>()
        .add(material);
    let start = Instant::now();
    let mut bound = None;
    // Past the binding, as long again twice over: any second load of the file, started with
    // the first, has finished by then.
    while bound.is_none_or(|at: Duration| start.elapsed() < 3 * at) {
        app.update();
        let materials = app.world().resource::<Assets<ClothMaterial>>();
        if bound.is_none() && !materials.get(&handle).expect("the material").is_pending() {
            bound = Some(start.elapsed());
        }
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "the material is still pending"
        );
    }
    let material = app
        .world()
        .resource::<Assets<ClothMaterial>>()
        .get(&handle)
        .unwrap();
    let table = app
        .world()
        .resource::<Assets<ClothTable>>()
        .get(&material.table)
        .expect("the table");
    assert_eq!(material.shader, table.shader);
    assert_eq!(material.sampling, table.sampling);
    assert_eq!(material.albedo, table.albedo);
    let events = &app.world().resource::<TableEvents>().0;
    println!("bound after {bound:?}; the table's asset events: {events:?}");
    let count = |kind: &str| events.iter().filter(|e| e.starts_with(kind)).count();
    assert_eq!(count("Added"), 1, "{events:?}");
    assert_eq!(count("Modified"), 0, "the table loaded again: {events:?}");
}
