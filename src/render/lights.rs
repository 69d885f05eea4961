//! The lights as the renderer uses them: a scene light with its colour multiplied in, and
//! ([`LightSource::at`]) the direction and irradiance it gives at a point, which the CPU
//! reference's light loop sums over. Kept apart so that new kinds of light join here.

use crate::scene::Light;
use glam::Vec3;

/// A light as the renderer uses it: colour already multiplied in.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightSource {
    /// `direction`: unit, towards the light; `irradiance`: colour × perpendicular irradiance.
    Directional { direction: Vec3, irradiance: Vec3 },
    /// `intensity`: colour × radiant intensity; irradiance `intensity/d²` at distance d.
    Point { position: Vec3, intensity: Vec3 },
}

impl LightSource {
    /// The light of a scene file.
    pub fn from_scene(light: &Light) -> Self {
        let v = |a: [f64; 3]| glam::DVec3::from(a).as_vec3();
        match *light {
            Light::Directional {
                direction,
                color,
                irradiance,
            } => Self::Directional {
                direction: v(direction).normalize_or(Vec3::Y),
                irradiance: v(color) * irradiance as f32,
            },
            Light::Point {
                position,
                color,
                intensity,
            } => Self::Point {
                position: v(position),
                intensity: v(color) * intensity as f32,
            },
        }
    }

    /// Unit direction towards the light and the RGB irradiance `E` it gives at `point`.
    pub fn at(&self, point: glam::DVec3) -> (glam::DVec3, glam::DVec3) {
        match *self {
            Self::Directional {
                direction,
                irradiance,
            } => (direction.as_dvec3(), irradiance.as_dvec3()),
            Self::Point {
                position,
                intensity,
            } => {
                let d = position.as_dvec3() - point;
                let d2 = d.length_squared().max(1e-12);
                (d / d2.sqrt(), intensity.as_dvec3() / d2)
            }
        }
    }
}
