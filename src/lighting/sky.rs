//! The generated skies: a clear sky with a sun, and the CIE overcast sky
//! ([`GeneratedEnvironment`](super::GeneratedEnvironment) `sky` and `overcast`).

use glam::DVec3;

use super::shapes::{direction_deg, soft_lobe};

/// The sun's elevation and azimuth (degrees; azimuth 0 along +z, 90° along +x): in front
/// of the cloth and to the left of the default camera, high enough to light the drape's top.
pub const SUN_ELEVATION_DEG: f64 = 30.0;
/// See [`SUN_ELEVATION_DEG`].
pub const SUN_AZIMUTH_DEG: f64 = -40.0;
/// The sun's angular radius: the real sun's 0.53° disc.
pub const SUN_ANGULAR_RADIUS_DEG: f64 = 0.265;
/// The sun's radiance relative to a sky near 1: what HDR photographs of a clear day hold
/// (3·10⁴–4·10⁴ after exposure for the sky).
pub const SUN_RADIANCE: f64 = 3.5e4;

/// The unit direction towards the sky's sun.
pub fn sun_direction() -> DVec3 {
    direction_deg(SUN_ELEVATION_DEG, SUN_AZIMUTH_DEG)
}

/// The clear sky's radiance from unit direction `d`: the sun's disc (warm white, uniform);
/// above the horizon a blue zenith fading to a pale horizon, plus the aureole around the sun
/// (a 3° lobe of peak 6 and a broad one of peak 0.8); below, a uniform ground.
pub fn clear_sky_radiance(d: DVec3) -> DVec3 {
    let cos_angle = d.dot(sun_direction());
    if cos_angle >= SUN_ANGULAR_RADIUS_DEG.to_radians().cos() {
        return DVec3::new(1.0, 0.96, 0.9) * SUN_RADIANCE;
    }
    if d.y < 0.0 {
        return DVec3::new(0.16, 0.14, 0.11);
    }
    let zenith = DVec3::new(0.20, 0.38, 0.85);
    let horizon = DVec3::new(0.90, 0.95, 1.05);
    let base = zenith.lerp(horizon, (1.0 - d.y).powi(4));
    let aureole = soft_lobe(cos_angle, 300.0, 6.0) + soft_lobe(cos_angle, 8.0, 0.8);
    base + DVec3::new(1.0, 0.92, 0.8) * aureole
}

/// The CIE standard overcast sky, `L = Lz·(1 + 2 sin e)/3` at elevation e with zenith
/// radiance Lz = 1.2 (three times the horizon's), over a uniform grey ground.
pub fn overcast_radiance(d: DVec3) -> DVec3 {
    if d.y < 0.0 {
        return DVec3::splat(0.2);
    }
    DVec3::new(0.95, 0.97, 1.0) * (1.2 * (1.0 + 2.0 * d.y) / 3.0)
}
