//! clothbake's environment maps (equirectangular `.hdr`/`.exr`, or the built-in studio) as
//! Bevy cubemaps for an `EnvironmentMapLight`.

use bevy::asset::RenderAssetUsages;
use bevy::prelude::*;
use bevy::render::render_resource::{
    Extent3d, TextureDimension, TextureFormat, TextureViewDescriptor, TextureViewDimension,
};
use clothbake::lighting::Environment;
use glam::DVec3;

/// `environment` as an Rgba16Float cubemap of `side` × `side` faces (`side` a power of two)
/// with its full mip chain, each level the 2 × 2 mean of the one above: the box filtering the
/// cloth shader's filtered importance sampling assumes (Bevy's own maps are prefiltered for
/// GGX, which blurs the coarser levels more). Use it as both maps of an
/// `EnvironmentMapLight` (`ClothMaterial` reads the specular one). Texel centres are sampled
/// from the map's level 0. Bevy reads a cubemap at (x, y, −z) for world direction (x, y, z),
/// faces in Vulkan's order +x, −x, +y, −y, +z, −z.
pub fn environment_cubemap(environment: &Environment, side: u32) -> Image {
    assert!(
        side.is_power_of_two(),
        "cubemap side {side} is not a power of two"
    );
    let mut data = Vec::new();
    for face in 0..6 {
        let mut level: Vec<[f32; 3]> = (0..side * side)
            .map(|i| {
                let s = 2.0 * ((i % side) as f64 + 0.5) / side as f64 - 1.0;
                let t = 2.0 * ((i / side) as f64 + 0.5) / side as f64 - 1.0;
                let cube = match face {
                    0 => DVec3::new(1.0, -t, -s),
                    1 => DVec3::new(-1.0, -t, s),
                    2 => DVec3::new(s, 1.0, t),
                    3 => DVec3::new(s, -1.0, -t),
                    4 => DVec3::new(s, -t, 1.0),
                    _ => DVec3::new(-s, -t, -1.0),
                };
                let world = DVec3::new(cube.x, cube.y, -cube.z).normalize();
                environment.radiance(world, 0.0).as_vec3().to_array()
            })
            .collect();
        let mut width = side;
        loop {
            for &[r, g, b] in &level {
                for v in [r, g, b, 1.0] {
                    data.extend(half::f16::from_f32(v).to_bits().to_le_bytes());
                }
            }
            if width == 1 {
                break;
            }
            let half = width / 2;
            level = (0..half * half)
                .map(|i| {
                    let (x, y) = (2 * (i % half), 2 * (i / half));
                    let at = |x: u32, y: u32| level[(y * width + x) as usize];
                    let four = [at(x, y), at(x + 1, y), at(x, y + 1), at(x + 1, y + 1)];
                    std::array::from_fn(|c| four.iter().map(|p| p[c]).sum::<f32>() / 4.0)
                })
                .collect();
            width = half;
        }
    }
    let mut image = Image::new_uninit(
        Extent3d {
            width: side,
            height: side,
            depth_or_array_layers: 6,
        },
        TextureDimension::D2,
        TextureFormat::Rgba16Float,
        RenderAssetUsages::RENDER_WORLD,
    );
    // Layer-major: each face's levels, largest first (Bevy's default data order).
    image.data = Some(data);
    image.texture_descriptor.mip_level_count = side.trailing_zeros() + 1;
    image.texture_view_descriptor = Some(TextureViewDescriptor {
        dimension: Some(TextureViewDimension::Cube),
        ..default()
    });
    image
}
