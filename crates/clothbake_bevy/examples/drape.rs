//! The six built-in fabrics on the default drape, in Bevy.
//!
//! Bake the tables first (`scripts/setup.sh`, or `cargo run --release -- bake --out tables`),
//! then `cargo run --release -p clothbake_bevy --example drape`.
//!
//! The scene is clothbake's default one: its key and point lights (casting Bevy shadows) and
//! the built-in studio environment as an `EnvironmentMapLight` (the sample taps of
//! `clothbake_bevy::DEFAULT_ENVIRONMENT_SAMPLES` per fragment, as `clothbake render`). `--env WORD` takes another environment,
//! as `clothbake render --env` does (`sky`, `overcast`, `interior`, or an `.hdr`/`.exr` file):
//! its compact bright sources (a sun, lamps) are directional lights (`source_lights`) and the
//! rest of the map is the `EnvironmentMapLight`.
//!
//! Keys: 1–6 or Tab choose the fabric; drag with the left mouse button or use the arrow keys
//! to orbit, the mouse wheel or +/− to zoom; Space stops or starts the moving light; E turns
//! the environment light off and on; Escape quits. `--frames N` quits after N frames; with
//! `--screenshot FILE.png` it saves frame N and quits once the file is written; `--tables DIR`
//! reads the tables from DIR instead of the workspace's `tables/`; `--fabric NAME` starts with
//! that fabric.

use bevy::asset::LoadState;
use bevy::input::mouse::{AccumulatedMouseMotion, AccumulatedMouseScroll};
use bevy::prelude::*;
use bevy::render::extract_plugin::MainWorld;
use bevy::render::render_resource::PipelineCache;
use bevy::render::view::screenshot::{Screenshot, ScreenshotCaptured, save_to_disk};
use bevy::render::{ExtractSchedule, RenderApp};
use clothbake::lighting::EnvironmentSource;
use clothbake::lighting::bright_sources::MAX_SOURCES;
use clothbake::scene::Scene;
use clothbake_bevy::{
    ClothMaterial, ClothPlugin, ClothTable, SceneLight, cloth_mesh, environment_cubemap,
    scene_light, source_lights,
};

#[derive(Resource)]
struct Options {
    frames: Option<u32>,
    screenshot: Option<String>,
    fabric: Option<String>,
    environment: EnvironmentSource,
}

/// The environment map light (the map's residual once its sources are split off), kept so
/// that E can put it back.
#[derive(Resource)]
struct EnvironmentLight(EnvironmentMapLight);

/// A directional light standing for one of the environment's bright sources (E switches it
/// with the map).
#[derive(Component)]
struct SourceLight;

#[derive(Resource)]
struct Fabrics {
    names: Vec<String>,
    materials: Vec<Handle<ClothMaterial>>,
    tables: Vec<Handle<ClothTable>>,
    current: usize,
}

#[derive(Component)]
struct Cloth;

/// Render pipelines still compiling (copied from the render world every frame): a table's
/// shader compiles after the table loads, and the cloth is drawn once it has.
#[derive(Resource, Default)]
struct PipelinesWaiting(usize);

/// Set when `--screenshot`'s capture arrives; `save_to_disk`'s observer writes the file on
/// the same capture, so both have run before the next frame's `count_frames` reads this.
#[derive(Resource, Default)]
struct ScreenshotSaved(bool);

fn count_waiting_pipelines(cache: Res<PipelineCache>, mut main_world: ResMut<MainWorld>) {
    main_world.resource_mut::<PipelinesWaiting>().0 = cache.waiting_pipelines().count();
}

#[derive(Component)]
struct Orbit {
    target: Vec3,
    distance: f32,
    yaw: f32,
    pitch: f32,
}

#[derive(Component)]
struct MovingLight {
    running: bool,
    angle: f32,
    elevation: f32,
}

fn main() -> AppExit {
    let mut options = Options {
        frames: None,
        screenshot: None,
        fabric: None,
        environment: EnvironmentSource::Default,
    };
    let mut tables = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tables");
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        match (arg.as_str(), args.next()) {
            ("--frames", Some(n)) => match n.parse() {
                Ok(n) => options.frames = Some(n),
                Err(_) => return usage(&format!("--frames {n}: not a number of frames")),
            },
            ("--screenshot", Some(path)) => options.screenshot = Some(path),
            ("--fabric", Some(name)) => options.fabric = Some(name),
            ("--env", Some(word)) => match word.parse() {
                Ok(source) => options.environment = source,
                Err(e) => return usage(&format!("--env {word}: {e}")),
            },
            // Bevy resolves a relative asset root against the executable's directory.
            ("--tables", Some(dir)) => match std::path::absolute(&dir) {
                Ok(dir) => tables = dir,
                Err(e) => return usage(&format!("--tables {dir}: {e}")),
            },
            _ => return usage(&format!("unknown argument {arg}")),
        }
    }
    let mut app = App::new();
    app.add_plugins(DefaultPlugins.set(AssetPlugin {
        file_path: tables.to_string_lossy().into_owned(),
        ..default()
    }))
    .add_plugins(ClothPlugin)
    .init_resource::<PipelinesWaiting>()
    .init_resource::<ScreenshotSaved>();
    app.sub_app_mut(RenderApp)
        .add_systems(ExtractSchedule, count_waiting_pipelines);
    app.insert_resource(options)
        .insert_resource(GlobalAmbientLight {
            brightness: 0.3,
            ..default()
        })
        .insert_resource(ClearColor(Color::srgb(0.02, 0.02, 0.025)))
        .add_systems(Startup, setup)
        .add_systems(
            Update,
            (
                choose_fabric,
                orbit_camera,
                move_light,
                toggle_environment,
                count_frames,
            ),
        )
        .run()
}

fn usage(problem: &str) -> AppExit {
    eprintln!(
        "drape: {problem}\nusage: drape [--frames N] [--screenshot FILE.png] [--tables DIR] [--fabric NAME] [--env WORD]"
    );
    AppExit::error()
}

fn setup(
    mut commands: Commands,
    options: Res<Options>,
    assets: Res<AssetServer>,
    mut images: ResMut<Assets<Image>>,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<ClothMaterial>>,
) {
    let scene = Scene::builtin();
    let names = scene.fabrics.clone();
    let current = match &options.fabric {
        None => 0,
        Some(name) => names.iter().position(|n| n == name).unwrap_or_else(|| {
            eprintln!(
                "drape: no fabric {name}; the fabrics are {}",
                names.join(", ")
            );
            0
        }),
    };
    let loaded: Vec<ClothMaterial> = names
        .iter()
        .map(|name| ClothMaterial::load(&assets, &format!("{name}.exr")))
        .collect();
    let tables = loaded.iter().map(|m| m.table.clone()).collect();
    let handles: Vec<Handle<ClothMaterial>> =
        loaded.into_iter().map(|m| materials.add(m)).collect();
    let drape = clothbake::scene::mesh::Mesh::from_spec(&scene.mesh).expect("the built-in drape");
    commands.spawn((
        Mesh3d(meshes.add(cloth_mesh(&drape))),
        MeshMaterial3d(handles[current].clone()),
        Cloth,
    ));
    println!(
        "drape: {} (keys 1–{} or Tab to switch; drag or arrows to orbit; wheel or +/− to zoom; \
         Space: light; E: environment; Escape: quit)",
        names[current],
        names.len()
    );
    commands.insert_resource(Fabrics {
        names,
        materials: handles,
        tables,
        current,
    });

    let camera = scene.camera;
    let orbit = Orbit {
        target: Vec3::from_array(camera.target.map(|v| v as f32)),
        distance: camera.distance as f32,
        yaw: (camera.yaw_deg as f32).to_radians(),
        pitch: (camera.pitch_deg as f32).to_radians(),
    };
    let camera_entity = commands
        .spawn((
            Camera3d::default(),
            Projection::Perspective(PerspectiveProjection {
                fov: (camera.fov_y_deg as f32).to_radians(),
                ..default()
            }),
            orbit_transform(&orbit),
            orbit,
            // Bevy's default exposure is for sunlight; the scene's irradiances are near 1:
            // exposure 2^(−ev100)/1.2 = 1, as `clothbake render`'s default scene.
            bevy::camera::Exposure {
                ev100: -(1.2f32.log2()),
            },
            // The ACES fit clothbake's renderer uses, and one that needs no lookup-table feature.
            bevy::core_pipeline::tonemapping::Tonemapping::AcesFitted,
        ))
        .id();
    if let Some(light) = environment_light(&mut commands, &mut images, &options.environment) {
        commands.entity(camera_entity).insert(light);
    }

    // The scene's lights, casting shadows.
    for light in &scene.lights {
        match scene_light(light) {
            SceneLight::Directional(mut light, disk, transform) => {
                light.shadow_maps_enabled = true;
                let d = transform.back();
                commands.spawn((
                    light,
                    disk,
                    transform,
                    MovingLight {
                        running: true,
                        angle: d.z.atan2(d.x),
                        elevation: d.y.asin(),
                    },
                ));
            }
            SceneLight::Point(mut light, transform) => {
                light.shadow_maps_enabled = true;
                commands.spawn((light, transform));
            }
        }
    }
}

/// The environment as the view's environment map light, and its bright sources as
/// directional lights. A file that does not load is reported and the view stays unlit by it.
fn environment_light(
    commands: &mut Commands,
    images: &mut Assets<Image>,
    source: &EnvironmentSource,
) -> Option<EnvironmentMapLight> {
    let map = match source.load() {
        Ok(map) => map?,
        Err(e) => {
            eprintln!("drape: {e}");
            return None;
        }
    };
    let split = map.split_bright_sources(MAX_SOURCES);
    println!("drape: environment {source}: {split}");
    for (light, disk, transform) in source_lights(&split) {
        commands.spawn((light, disk, transform, SourceLight));
    }
    let cubemap = images.add(environment_cubemap(&split.residual, 128));
    let light = EnvironmentMapLight {
        diffuse_map: cubemap.clone(),
        specular_map: cubemap,
        intensity: 1.0,
        ..default()
    };
    commands.insert_resource(EnvironmentLight(light.clone()));
    Some(light)
}

fn orbit_transform(orbit: &Orbit) -> Transform {
    let offset = Vec3::new(
        orbit.pitch.cos() * orbit.yaw.sin(),
        orbit.pitch.sin(),
        orbit.pitch.cos() * orbit.yaw.cos(),
    ) * orbit.distance;
    Transform::from_translation(orbit.target + offset).looking_at(orbit.target, Vec3::Y)
}

fn choose_fabric(
    keys: Res<ButtonInput<KeyCode>>,
    mut fabrics: ResMut<Fabrics>,
    mut cloth: Query<&mut MeshMaterial3d<ClothMaterial>, With<Cloth>>,
) {
    const DIGITS: [KeyCode; 6] = [
        KeyCode::Digit1,
        KeyCode::Digit2,
        KeyCode::Digit3,
        KeyCode::Digit4,
        KeyCode::Digit5,
        KeyCode::Digit6,
    ];
    let count = fabrics.names.len();
    let chosen = if keys.just_pressed(KeyCode::Tab) {
        Some((fabrics.current + 1) % count)
    } else {
        DIGITS
            .iter()
            .position(|&k| keys.just_pressed(k))
            .filter(|&i| i < count)
    };
    if let Some(i) = chosen {
        fabrics.current = i;
        for mut material in &mut cloth {
            material.0 = fabrics.materials[i].clone();
        }
        println!("drape: {}", fabrics.names[i]);
    }
}

fn toggle_environment(
    mut commands: Commands,
    keys: Res<ButtonInput<KeyCode>>,
    environment: Option<Res<EnvironmentLight>>,
    cameras: Query<(Entity, Has<EnvironmentMapLight>), With<Camera3d>>,
    mut sources: Query<&mut Visibility, With<SourceLight>>,
) {
    let Some(environment) = environment else {
        return;
    };
    if !keys.just_pressed(KeyCode::KeyE) {
        return;
    }
    for (camera, lit) in &cameras {
        if lit {
            commands.entity(camera).remove::<EnvironmentMapLight>();
        } else {
            commands.entity(camera).insert(environment.0.clone());
        }
        for mut visibility in &mut sources {
            *visibility = if lit {
                Visibility::Hidden
            } else {
                Visibility::Inherited
            };
        }
        println!(
            "drape: environment light {}",
            if lit { "off" } else { "on" }
        );
    }
}

fn orbit_camera(
    keys: Res<ButtonInput<KeyCode>>,
    buttons: Res<ButtonInput<MouseButton>>,
    motion: Res<AccumulatedMouseMotion>,
    scroll: Res<AccumulatedMouseScroll>,
    time: Res<Time>,
    mut cameras: Query<(&mut Orbit, &mut Transform)>,
) {
    let step = 1.5 * time.delta_secs();
    let key = |k: KeyCode| if keys.pressed(k) { step } else { 0.0 };
    for (mut orbit, mut transform) in &mut cameras {
        let mut turn = Vec2::new(
            key(KeyCode::ArrowRight) - key(KeyCode::ArrowLeft),
            key(KeyCode::ArrowUp) - key(KeyCode::ArrowDown),
        );
        if buttons.pressed(MouseButton::Left) {
            turn += Vec2::new(-motion.delta.x, motion.delta.y) * 0.005;
        }
        orbit.yaw += turn.x;
        orbit.pitch = (orbit.pitch + turn.y).clamp(-1.4, 1.4);
        let zoom = key(KeyCode::Minus) - key(KeyCode::Equal) - 0.1 * scroll.delta.y;
        orbit.distance = (orbit.distance * (1.0 + zoom)).clamp(1.0, 20.0);
        *transform = orbit_transform(&orbit);
    }
}

fn move_light(
    keys: Res<ButtonInput<KeyCode>>,
    time: Res<Time>,
    mut lights: Query<(&mut MovingLight, &mut Transform)>,
) {
    for (mut light, mut transform) in &mut lights {
        if keys.just_pressed(KeyCode::Space) {
            light.running = !light.running;
        }
        if light.running {
            light.angle += 0.4 * time.delta_secs();
        }
        let d = Vec3::new(
            light.elevation.cos() * light.angle.cos(),
            light.elevation.sin(),
            light.elevation.cos() * light.angle.sin(),
        );
        *transform = Transform::default().looking_to(-d, Vec3::Y);
    }
}

/// Frames `--screenshot` waits for its capture before giving up (it took 4 on lavapipe).
const SCREENSHOT_FRAMES: u32 = 30;

/// Quits on Escape, on a table that fails to load, or `--frames` frames after every table
/// has loaded and no pipeline has been compiling for three frames; with `--screenshot`, asks
/// for a capture of frame N and quits once it has been written.
#[allow(clippy::too_many_arguments)] // a system: each argument is a resource it reads
fn count_frames(
    mut commands: Commands,
    keys: Res<ButtonInput<KeyCode>>,
    options: Res<Options>,
    fabrics: Res<Fabrics>,
    assets: Res<AssetServer>,
    waiting: Res<PipelinesWaiting>,
    saved: Res<ScreenshotSaved>,
    time: Res<Time<Real>>,
    mut settled: Local<u32>,
    mut frame: Local<u32>,
    mut exit: MessageWriter<AppExit>,
) {
    if keys.just_pressed(KeyCode::Escape) {
        exit.write(AppExit::Success);
    }
    for (name, table) in fabrics.names.iter().zip(&fabrics.tables) {
        if let LoadState::Failed(error) = assets.load_state(table) {
            eprintln!(
                "drape: {name}: {error} (bake the tables first: cargo run --release -- bake)"
            );
            exit.write(AppExit::error());
            return;
        }
    }
    if *frame == 0 {
        let loaded = fabrics
            .tables
            .iter()
            .all(|t| assets.is_loaded_with_dependencies(t));
        *settled = if loaded && waiting.0 == 0 {
            *settled + 1
        } else {
            0
        };
        if *settled < 3 {
            return;
        }
        println!(
            "drape: {} tables loaded and shaders compiled after {:.1} s",
            fabrics.tables.len(),
            time.elapsed_secs()
        );
    }
    *frame += 1;
    let Some(frames) = options.frames else {
        return;
    };
    match (&options.screenshot, *frame) {
        (Some(path), f) if f == frames => {
            commands
                .spawn(Screenshot::primary_window())
                .observe(save_to_disk(path.clone()))
                .observe(
                    |_: On<ScreenshotCaptured>, mut saved: ResMut<ScreenshotSaved>| saved.0 = true,
                );
        }
        // The capture arrives a few frames after it is asked for (4 on lavapipe, whose first
        // capture also compiles the copy's pipeline).
        (Some(_), f) if saved.0 => {
            println!("drape: drew {f} frames");
            exit.write(AppExit::Success);
        }
        (Some(path), f) if f >= frames + SCREENSHOT_FRAMES => {
            eprintln!("drape: no screenshot captured for {path} after {SCREENSHOT_FRAMES} frames");
            exit.write(AppExit::error());
        }
        (None, f) if f >= frames => {
            println!("drape: drew {f} frames");
            exit.write(AppExit::Success);
        }
        _ => {}
    }
}
