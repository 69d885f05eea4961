//! The generated interior ([`GeneratedEnvironment`](super::GeneratedEnvironment) `interior`):
//! a room seen from its middle.

use glam::DVec3;

use super::shapes::{direction_deg, soft_lobe};

/// A window: a rectangle in azimuth and elevation (degrees) showing a bright sky, split by a
/// vertical mullion at its middle.
struct Window {
    azimuth: [f64; 2],
    elevation: [f64; 2],
    radiance: [f64; 3],
}

/// A lamp: a small bright disc in a soft glow (its shade lit from inside).
struct Lamp {
    elevation: f64,
    azimuth: f64,
    radius_deg: f64,
    radiance: f64,
}

const WINDOWS: [Window; 2] = [
    Window {
        azimuth: [-75.0, -35.0],
        elevation: [-5.0, 30.0],
        radiance: [4.5, 4.8, 5.2],
    },
    Window {
        azimuth: [100.0, 130.0],
        elevation: [0.0, 25.0],
        radiance: [3.0, 3.0, 2.85],
    },
];

const LAMPS: [Lamp; 2] = [
    Lamp {
        elevation: 50.0,
        azimuth: 20.0,
        radius_deg: 1.5,
        radiance: 900.0,
    },
    Lamp {
        elevation: 20.0,
        azimuth: 160.0,
        radius_deg: 1.5,
        radiance: 900.0,
    },
];

/// Half the width of a window's mullion, degrees.
const MULLION_HALF_WIDTH_DEG: f64 = 0.75;

/// The interior's radiance from unit direction `d`: floor (wood), walls (warm white) and
/// ceiling by elevation; two windows of 40°×35° and 30°×25° onto a sky of radiance 3–5; two
/// lamps, discs of 1.5° radius and radiance 900 (warm), each in a 4° glow of peak 2. About
/// a third of the light comes from each of the lamps, the windows and the room.
pub fn interior_radiance(d: DVec3) -> DVec3 {
    let elevation = d.y.clamp(-1.0, 1.0).asin().to_degrees();
    let azimuth = d.x.atan2(d.z).to_degrees();
    let warm = DVec3::new(1.0, 0.78, 0.5);
    for lamp in &LAMPS {
        let cos_angle = d.dot(direction_deg(lamp.elevation, lamp.azimuth));
        if cos_angle >= lamp.radius_deg.to_radians().cos() {
            return warm * lamp.radiance;
        }
    }
    for window in &WINDOWS {
        let inside = |v: f64, [lo, hi]: [f64; 2]| (lo..hi).contains(&v);
        let middle = 0.5 * (window.azimuth[0] + window.azimuth[1]);
        if inside(azimuth, window.azimuth)
            && inside(elevation, window.elevation)
            && (azimuth - middle).abs() > MULLION_HALF_WIDTH_DEG
        {
            return DVec3::from(window.radiance);
        }
    }
    let room = if elevation < -3.0 {
        DVec3::new(0.16, 0.11, 0.07)
    } else if elevation > 48.0 {
        DVec3::new(0.32, 0.31, 0.30)
    } else {
        DVec3::new(0.26, 0.24, 0.21)
    };
    let glow: f64 = LAMPS
        .iter()
        .map(|lamp| {
            soft_lobe(
                d.dot(direction_deg(lamp.elevation, lamp.azimuth)),
                200.0,
                2.0,
            )
        })
        .sum();
    room + warm * glow
}
