// The part of a bright source's disk above the local horizon, for a source lit as one
// directional light (src/lighting/bright_sources.rs, `disk_above_horizon`, its twin, where
// the derivation is): the source's centre in direction `wi` (unit, local frame, z the
// normal), its angular radius r given as `sin_radius`. Returns (the visible part's centroid
// direction, the visible fraction of the disk): the source gives fraction·E·F(centroid, wo).
// The centroid is above the horizon (z > 0) only where some of the disk is (the fraction is
// then positive), so a caller tests its z alone. With sin_radius = 0 it is a plain directional light: (wi, 1) above the
// horizon, 0 below.

fn source_disk_above_horizon(wi: vec3<f32>, sin_radius: f32) -> vec4<f32> {
    if wi.z >= sin_radius {
        return vec4<f32>(wi, 1.0);
    }
    if wi.z <= -sin_radius {
        return vec4<f32>(wi, 0.0);
    }
    let radius = asin(sin_radius);
    let d = clamp(asin(wi.z) / radius, -1.0, 1.0);
    let s = sqrt(max(1.0 - d * d, 0.0));
    let area = 3.14159265 - acos(d) + d * s;
    let centroid = (2.0 / 3.0) * s * s * s / max(area, 1e-12);
    let elevation = radius * (d + centroid);
    let horizontal = wi.xy / max(length(wi.xy), 1e-12);
    return vec4<f32>(horizontal * cos(elevation), sin(elevation), area / 3.14159265);
}
