//! The built-in studio environment's radiance, generated in code (documented on
//! [`Environment::studio`](super::Environment::studio)).

use glam::DVec3;

use super::shapes::soft_lobe;

/// One soft box of the studio: `peak·colour·exp(sharpness·(cos α − 1))`, α the angle from
/// `towards`.
struct SoftBox {
    towards: [f64; 3],
    sharpness: f64,
    peak: f64,
    colour: [f64; 3],
}

/// The studio's soft boxes, as documented on [`Environment::studio`].
const STUDIO_LIGHTS: [SoftBox; 3] = [
    SoftBox {
        towards: [-0.55, 0.62, 0.56],
        sharpness: 30.0,
        peak: 5.0,
        colour: [1.0, 0.95, 0.88],
    },
    SoftBox {
        towards: [0.82, 0.25, 0.52],
        sharpness: 18.0,
        peak: 1.2,
        colour: [0.85, 0.92, 1.0],
    },
    SoftBox {
        towards: [0.2, 0.5, -0.84],
        sharpness: 45.0,
        peak: 4.0,
        colour: [1.0, 1.0, 1.0],
    },
];

/// The studio's radiance from unit direction `d`.
pub(crate) fn studio_radiance(d: DVec3) -> DVec3 {
    let horizon = DVec3::new(0.30, 0.27, 0.23);
    let zenith = DVec3::new(0.15, 0.18, 0.23);
    let floor = DVec3::new(0.045, 0.040, 0.035);
    let sky = horizon.lerp(zenith, d.y.max(0.0));
    let t = ((d.y + 0.2) / 0.25).clamp(0.0, 1.0);
    let mut radiance = floor.lerp(sky, t * t * (3.0 - 2.0 * t));
    for light in &STUDIO_LIGHTS {
        let cos_angle = d.dot(DVec3::from(light.towards).normalize());
        radiance += DVec3::from(light.colour) * soft_lobe(cos_angle, light.sharpness, light.peak);
    }
    radiance
}
