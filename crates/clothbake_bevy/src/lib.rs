//! Cloth for Bevy 0.19, shaded by clothbake tables.
//!
//! Bake a fabric with `clothbake bake`, then:
//!
//! ```no_run
//! use bevy::prelude::*;
//! use clothbake_bevy::{ClothMaterial, ClothPlugin, cloth_mesh};
//!
//! fn setup(
//!     mut commands: Commands,
//!     assets: Res<AssetServer>,
//!     mut meshes: ResMut<Assets<Mesh>>,
//!     mut materials: ResMut<Assets<ClothMaterial>>,
//! ) {
//!     let drape = clothbake::scene::mesh::Mesh::drape(160, 9, 0.1);
//!     commands.spawn((
//!         Mesh3d(meshes.add(cloth_mesh(&drape))),
//!         MeshMaterial3d(materials.add(ClothMaterial::load(&assets, "velvet.exr"))),
//!     ));
//! }
//! # App::new().add_plugins((DefaultPlugins, ClothPlugin)).add_systems(Startup, setup);
//! ```
//!
//! - [`ClothTable`] (an asset, loaded from the table's EXR by [`ClothTableLoader`]) holds the
//!   table's textures, its directional albedo map and a fragment shader with the table's
//!   specialised WGSL lookup.
//! - [`ClothMaterial`] binds them; its fragment shader sums F(wi, wo)·E over Bevy's
//!   directional and point lights (shadows included), adds the ambient light times the
//!   directional albedo, and the view's environment map light by filtered importance
//!   sampling with the fabric's sampler. See this crate's README.md for what is and is
//!   not supported.
//! - [`environment_cubemap`] turns a clothbake environment map (the studio, or an
//!   equirectangular `.hdr`/`.exr`) into a cubemap for Bevy's `EnvironmentMapLight`.
//! - [`scene_light`] turns a clothbake scene light into a Bevy light in Bevy's units, and
//!   [`source_lights`] the bright sources of a split environment map (its sun, lamps) into
//!   directional lights, to light beside the map's residual as `clothbake render` does.
//! - [`cloth_mesh`] turns a clothbake mesh (procedural drape, curtain, plane, or an OBJ) into
//!   a Bevy mesh with the thread frame in its tangents.
//!
//! The crate depends on clothbake's core only (`default-features = false`): one wgpu in the
//! build, Bevy's.

mod environment;
mod lights;
mod material;
mod mesh;
mod table_asset;

pub use environment::environment_cubemap;
pub use lights::{POINT_LIGHT_RANGE, SceneLight, scene_light, source_lights};
pub use material::{ClothMaterial, ClothMaterialKey, DEFAULT_ENVIRONMENT_SAMPLES};
pub use mesh::cloth_mesh;
pub use table_asset::{ALBEDO_SAMPLES, ClothTable, ClothTableError, ClothTableLoader};

use bevy::prelude::*;
use bevy::shader::Shader;

/// Registers [`ClothTable`], its loader and [`ClothMaterial`], whose pending materials it binds
/// once their tables have loaded.
pub struct ClothPlugin;

impl Plugin for ClothPlugin {
    fn build(&self, app: &mut App) {
        app.init_asset::<ClothTable>()
            .register_asset_loader(ClothTableLoader)
            .add_plugins(MaterialPlugin::<ClothMaterial>::default())
            .add_systems(PostUpdate, material::bind_loaded_tables);
        app.world_mut()
            .resource_mut::<Assets<Shader>>()
            .insert(
                &material::PLACEHOLDER_SHADER,
                Shader::from_wgsl(
                    material::PLACEHOLDER_SOURCE,
                    "clothbake_bevy/placeholder.wgsl",
                ),
            )
            .expect("a UUID handle is always valid");
    }
}
