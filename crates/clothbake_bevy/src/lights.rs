//! clothbake scene lights as Bevy lights.

use bevy::light::SunDisk;
use bevy::prelude::*;
use clothbake::lighting::SplitEnvironment;
use clothbake::scene::Light;

/// A clothbake scene light ([`clothbake::scene::Light`]) as a Bevy light and its transform.
/// A directional one comes with [`SunDisk::OFF`]: clothbake's scene lights are exact
/// directions, while the material sets a directional light over its `SunDisk` at the horizon,
/// and Bevy gives a light without one the sun's (0.53°; velvet's terminator moves the image by
/// 0.5% between the two).
pub enum SceneLight {
    Directional(DirectionalLight, SunDisk, Transform),
    Point(PointLight, Transform),
}

/// Bevy's point-light range for scene lights: far beyond any scene, so that Bevy's range
/// window (1 − (d/range)⁴)² is 1 within 1e-6 where the cloth is.
pub const POINT_LIGHT_RANGE: f32 = 100.0;

/// `light` in Bevy's units, without shadows (set `shadow_maps_enabled` to cast them). A
/// directional light of perpendicular irradiance E is a `DirectionalLight` of illuminance E;
/// a point light of intensity I (irradiance I/d²) is a `PointLight` of luminous power 4π·I
/// (Bevy divides power by 4π), of radius 0 and range [`POINT_LIGHT_RANGE`]. Under Bevy's
/// exposure 1 (ev100 = −log2 1.2) the cloth's radiance is then `clothbake render`'s.
pub fn scene_light(light: &Light) -> SceneLight {
    let vector = |v: [f64; 3]| Vec3::from_array(v.map(|x| x as f32));
    let color = |c: [f64; 3]| Color::linear_rgb(c[0] as f32, c[1] as f32, c[2] as f32);
    match *light {
        Light::Directional {
            direction,
            color: rgb,
            irradiance,
        } => SceneLight::Directional(
            DirectionalLight {
                color: color(rgb),
                illuminance: irradiance as f32,
                shadow_maps_enabled: false,
                ..default()
            },
            SunDisk::OFF,
            Transform::default().looking_to(-vector(direction).normalize(), Vec3::Y),
        ),
        Light::Point {
            position,
            color: rgb,
            intensity,
        } => SceneLight::Point(
            PointLight {
                color: color(rgb),
                intensity: 4.0 * std::f32::consts::PI * intensity as f32,
                range: POINT_LIGHT_RANGE,
                radius: 0.0,
                shadow_maps_enabled: false,
                ..default()
            },
            Transform::from_translation(vector(position)),
        ),
    }
}

/// The compact bright sources of a split environment map (the sun, lamps:
/// `Environment::split_bright_sources`) as Bevy directional lights in the units of
/// [`scene_light`], without shadows. Light the view with them and with the split's residual as
/// the `EnvironmentMapLight` ([`crate::environment_cubemap`] of `split.residual`), as
/// `clothbake render` does: the residual is sampled, the sources are looked up once each,
/// each set by the horizon over its disk, which its `SunDisk` carries (angular diameter
/// twice `DistantSource::disk_radius`; intensity 0, so that an `Atmosphere` does not draw it
/// again over the map that holds it).
pub fn source_lights(split: &SplitEnvironment) -> Vec<(DirectionalLight, SunDisk, Transform)> {
    split
        .sources
        .iter()
        .map(|source| {
            let irradiance = source.irradiance.as_vec3();
            // Bevy's light is colour × illuminance: the brightest channel as illuminance.
            let illuminance = irradiance.max_element().max(f32::MIN_POSITIVE);
            let colour = irradiance / illuminance;
            let light = DirectionalLight {
                color: Color::linear_rgb(colour.x, colour.y, colour.z),
                illuminance,
                shadow_maps_enabled: false,
                ..default()
            };
            // clothbake's glam is not Bevy's: through an array.
            let towards = Vec3::from_array(source.direction.as_vec3().to_array());
            let disk = SunDisk {
                angular_size: 2.0 * source.disk_radius as f32,
                intensity: 0.0,
            };
            (
                light,
                disk,
                Transform::default().looking_to(-towards, Vec3::Y),
            )
        })
        .collect()
}
