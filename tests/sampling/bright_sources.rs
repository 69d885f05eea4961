//! The generated environments and the split of a map into compact bright sources and a soft
//! residual (src/lighting/bright_sources.rs).

use clothbake::lighting::bright_sources::{MAX_PARTS, MAX_SOURCE_RADIUS_DEG, MAX_SOURCES};
use clothbake::lighting::sky::{self, SUN_ANGULAR_RADIUS_DEG, SUN_RADIANCE};
use clothbake::lighting::{
    DistantSource, Environment, EnvironmentSource, GeneratedEnvironment, SplitEnvironment,
    disk_above_horizon,
};
use glam::DVec3;
use std::f64::consts::PI;

/// A source's blocks: at most MAX_PARTS, carrying its whole irradiance.
fn assert_parts_carry_the_source(source: &DistantSource) {
    assert!(
        source.parts.len() <= MAX_PARTS,
        "{} parts",
        source.parts.len()
    );
    let parts: DVec3 = source.parts.iter().map(|p| p.1).sum();
    assert!(
        ((parts - source.irradiance) / source.irradiance)
            .abs()
            .max_element()
            < 1e-9
    );
}

/// The irradiance a map gives in every direction at once, 4π·mean, per channel.
fn power(map: &Environment) -> DVec3 {
    map.mean_radiance() * 4.0 * PI
}

/// The residual's power plus the sources' irradiance against the map's.
fn assert_split_keeps_power(name: &str, map: &Environment, split: &SplitEnvironment) {
    let sources: DVec3 = split.sources.iter().map(|s| s.irradiance).sum();
    let total = power(&split.residual) + sources;
    let relative = ((total - power(map)) / power(map)).abs().max_element();
    // Sums of f32 texels in f64, and the residual's texels rounded to f32 after scaling:
    // a few parts in 10⁷ of the map's power.
    assert!(
        relative < 1e-5,
        "{name}: residual + sources {total} against the map's {}",
        power(map)
    );
}

#[test]
fn every_generated_environment_is_named_deterministic_and_finite() {
    for generated in GeneratedEnvironment::ALL {
        let word = generated.name();
        let source: EnvironmentSource = word.parse().unwrap();
        assert_eq!(source, EnvironmentSource::Generated(generated));
        assert_eq!(source.to_string(), word);
        let map = source.load().unwrap().unwrap();
        assert_eq!(map, generated.environment(), "{word}");
        assert!(
            map.levels()[0]
                .texels()
                .iter()
                .all(|t| t.iter().all(|v| v.is_finite() && *v >= 0.0)),
            "{word}"
        );
        // A file named like one is written with a directory.
        let file = EnvironmentSource::File(word.into());
        assert_eq!(file.to_string(), format!("./{word}"));
    }
    assert_eq!(
        GeneratedEnvironment::Studio.environment(),
        Environment::studio()
    );
}

#[test]
fn the_sky_holds_a_half_degree_sun_with_its_power() {
    let sky = GeneratedEnvironment::Sky.environment();
    // The disc's power, L·Ω with Ω = 2π(1 − cos r), against what the map holds brighter
    // than the aureole can be (1,000): the texels the disc covers, by their coverage.
    let radius = SUN_ANGULAR_RADIUS_DEG.to_radians();
    let disc = SUN_RADIANCE * 2.0 * PI * (1.0 - radius.cos());
    let level = &sky.levels()[0];
    let width = level.width() as usize;
    let held: f64 = level
        .texels()
        .iter()
        .enumerate()
        .map(|(i, t)| {
            let y = (t[0] + t[1] + t[2]) as f64 / 3.0;
            if y > 1000.0 {
                y * level.texel_solid_angle((i / width) as u32)
            } else {
                0.0
            }
        })
        .sum();
    let colour_mean = (1.0 + 0.96 + 0.9) / 3.0;
    // 4×4 points per texel resolve the disc's edge to a sixteenth of the texels it
    // crosses: within 5%.
    assert!(
        (held / (disc * colour_mean) - 1.0).abs() < 0.05,
        "sun power {held}, disc {}",
        disc * colour_mean
    );
    // The sky near 1, the sun 10⁴ times brighter.
    let mean = sky.mean_radiance().element_sum() / 3.0;
    assert!((0.3..1.5).contains(&mean), "mean radiance {mean}");
    let peak = level.texels().iter().map(|t| t[0]).fold(0.0f32, f32::max);
    assert!(peak as f64 > 1e4 * mean, "peak {peak}");
}

#[test]
fn the_sun_becomes_one_light_where_it_is_and_the_power_is_kept() {
    let sky = GeneratedEnvironment::Sky.environment();
    let split = sky.split_bright_sources(MAX_SOURCES);
    assert_eq!(split.sources.len(), 1, "{split}");
    let sun = &split.sources[0];
    let off = sun
        .direction
        .angle_between(sky::sun_direction())
        .to_degrees();
    assert!(off < 0.05, "the sun's light is {off}° off the sun");
    assert!(
        sun.angular_radius.to_degrees() < 0.5,
        "radius {}°",
        sun.angular_radius.to_degrees()
    );
    let radius = SUN_ANGULAR_RADIUS_DEG.to_radians();
    let disc = SUN_RADIANCE * 2.0 * PI * (1.0 - radius.cos()) * (1.0 + 0.96 + 0.9) / 3.0;
    let e = sun.irradiance.element_sum() / 3.0;
    assert!((e / disc - 1.0).abs() < 0.05, "E = {e}, disc {disc}");
    assert_split_keeps_power("sky", &sky, &split);
    assert_parts_carry_the_source(sun);
    // What stays is bounded by the threshold: no texel of the residual is a sun.
    let mean = sky.mean_radiance().element_sum() / 3.0;
    let peak = split.residual.levels()[0]
        .texels()
        .iter()
        .map(|t| (t[0] + t[1] + t[2]) as f64 / 3.0)
        .fold(0.0, f64::max);
    assert!(peak <= 16.0 * mean * (1.0 + 1e-6), "residual peak {peak}");
}

#[test]
fn lamps_are_found_windows_and_soft_boxes_stay_in_the_residual() {
    let interior = GeneratedEnvironment::Interior.environment();
    let split = interior.split_bright_sources(MAX_SOURCES);
    // The two lamps, 1.5° discs; the windows are too wide to be one light.
    assert_eq!(split.sources.len(), 2, "{split}");
    for source in &split.sources {
        assert!(source.angular_radius.to_degrees() <= MAX_SOURCE_RADIUS_DEG);
        // A lamp spans about 60 texels, gathered into blocks.
        assert_parts_carry_the_source(source);
    }
    assert_split_keeps_power("interior", &interior, &split);
    for soft in [GeneratedEnvironment::Studio, GeneratedEnvironment::Overcast] {
        let map = soft.environment();
        let split = map.split_bright_sources(MAX_SOURCES);
        assert!(split.sources.is_empty(), "{}: {split}", soft.name());
        assert_eq!(split.residual, map);
    }
    // No sources asked for: the map itself.
    let none = interior.split_bright_sources(0);
    assert!(none.sources.is_empty());
    assert_eq!(none.residual, interior);
}

#[test]
fn a_source_on_the_seam_is_one_light() {
    // A 2°-wide bright patch straddling u = 0 ≡ 1 (along +z) on a uniform map: the regions
    // wrap in u, so it is one source, centred on +z.
    let (width, height) = (360u32, 180u32);
    let mut texels = vec![[1.0f32; 3]; (width * height) as usize];
    for row in 89..91 {
        for col in [358u32, 359, 0, 1] {
            texels[(row * width + col) as usize] = [5000.0; 3];
        }
    }
    let map = Environment::from_texels(width, height, texels).unwrap();
    let split = map.split_bright_sources(MAX_SOURCES);
    assert_eq!(split.sources.len(), 1, "{split}");
    let off = split.sources[0]
        .direction
        .angle_between(DVec3::Z)
        .to_degrees();
    assert!(off < 0.01, "{off}°");
    assert_split_keeps_power("seam", &map, &split);
}

/// The part of a disk of angular radius `radius` centred at elevation `elevation` (azimuth
/// along +x) that lies above z = 0, integrated on the sphere: (its centroid's direction, its
/// share of the disk's solid angle), over a grid of equal solid angles.
fn disk_above_horizon_on_the_sphere(radius: f64, elevation: f64) -> (DVec3, f64) {
    const STEPS: usize = 400;
    let centre = DVec3::new(elevation.cos(), 0.0, elevation.sin());
    let up = DVec3::new(-elevation.sin(), 0.0, elevation.cos());
    let (mut sum, mut above) = (DVec3::ZERO, 0usize);
    for i in 0..STEPS {
        // cos θ uniform over [cos r, 1]: equal solid angles.
        let cos_theta = 1.0 - (1.0 - radius.cos()) * (i as f64 + 0.5) / STEPS as f64;
        let sin_theta = (1.0 - cos_theta * cos_theta).sqrt();
        for j in 0..STEPS {
            let phi = 2.0 * PI * (j as f64 + 0.5) / STEPS as f64;
            let d = cos_theta * centre + sin_theta * (phi.cos() * DVec3::Y + phi.sin() * up);
            if d.z > 0.0 {
                sum += d;
                above += 1;
            }
        }
    }
    (
        sum.normalize_or(centre),
        above as f64 / (STEPS * STEPS) as f64,
    )
}

#[test]
fn a_source_sets_over_its_disk() {
    // The sun's disc, the interior's lamps, the widest source taken as a light.
    let (mut worst_fraction, mut worst_elevation) = (0.0f64, 0.0f64);
    for radius_deg in [SUN_ANGULAR_RADIUS_DEG, 1.5, MAX_SOURCE_RADIUS_DEG] {
        let radius = radius_deg.to_radians();
        for step in -12..=12 {
            let elevation = radius * step as f64 / 10.0;
            let (centroid, fraction) = disk_above_horizon_on_the_sphere(radius, elevation);
            let wi = glam::Vec3::new(elevation.cos() as f32, 0.0, elevation.sin() as f32);
            let (got_centroid, got_fraction) = disk_above_horizon(wi, radius.sin() as f32);
            worst_fraction = worst_fraction.max((got_fraction as f64 - fraction).abs());
            if fraction > 0.0 {
                let got = (got_centroid.z as f64).asin();
                // Relative to the radius: how far into the disk the centroid is misplaced.
                worst_elevation = worst_elevation.max((got - centroid.z.asin()).abs() / radius);
            }
            assert_eq!(
                got_fraction == 0.0,
                fraction == 0.0,
                "r {radius_deg}° h {step}"
            );
        }
    }
    println!("worst fraction {worst_fraction:.2e}, centroid elevation {worst_elevation:.2e} r");
    // Measured 5.9e-5 and 1.2e-4 r: the flat-disk derivation is off the sphere by O(r²),
    // and the 400² grid resolves the cut to about that; the bounds are ten times that.
    assert!(worst_fraction < 6e-4, "fraction off by {worst_fraction}");
    assert!(
        worst_elevation < 1.2e-3,
        "centroid off by {worst_elevation} radii"
    );
}

#[test]
fn a_source_disk_has_the_spread_of_its_texels() {
    let sky = GeneratedEnvironment::Sky.environment();
    let sun = &sky.split_bright_sources(MAX_SOURCES).sources[0];
    let interior = GeneratedEnvironment::Interior.environment();
    let lamps = interior.split_bright_sources(MAX_SOURCES).sources;
    // The equal-spread disk of a source drawn as a uniform disc is that disc, up to the
    // texels that draw its rim: measured 0.279° for the 0.265° sun (texels of 0.18°), 1.509°
    // for the 1.5° lamps, where the largest texel angle is 0.455° and 1.90°.
    let off =
        |source: &DistantSource, disc_deg: f64| source.disk_radius.to_degrees() / disc_deg - 1.0;
    assert!(
        off(sun, SUN_ANGULAR_RADIUS_DEG).abs() < 0.1,
        "sun {:?}",
        sun.disk_radius.to_degrees()
    );
    assert_eq!(lamps.len(), 2);
    for lamp in &lamps {
        assert!(
            off(lamp, 1.5).abs() < 0.02,
            "lamp {:?}",
            lamp.disk_radius.to_degrees()
        );
    }
}
