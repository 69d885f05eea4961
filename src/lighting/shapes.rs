//! The shapes the generated environments are drawn with: a soft lobe around a direction, and
//! a direction from its elevation and azimuth.

use glam::DVec3;

/// `colour·peak·exp(sharpness·(cos α − 1))`: a smooth lobe around a direction, about
/// `1/√sharpness` radians across (α the angle from its centre, `cos_angle` = cos α).
pub(crate) fn soft_lobe(cos_angle: f64, sharpness: f64, peak: f64) -> f64 {
    peak * (sharpness * (cos_angle - 1.0)).exp()
}

/// A unit direction from its elevation above the horizon and its azimuth, in degrees: azimuth
/// 0 looks along +z (towards the default camera), 90° along +x.
pub(crate) fn direction_deg(elevation: f64, azimuth: f64) -> DVec3 {
    let (e, a) = (elevation.to_radians(), azimuth.to_radians());
    DVec3::new(e.cos() * a.sin(), e.sin(), e.cos() * a.cos())
}
