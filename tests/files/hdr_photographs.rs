//! Environment maps with the traits of real HDR photographs (`Environment::load`): slightly
//! negative texels left by filtering and lossy compression, RGB and RGBA layers in half and
//! float, scan lines and tiles, a small sun thousands of times brighter than the sky, halves
//! at their largest finite value, and a map of 8192 × 4096. The files are made here: no
//! downloaded asset.

use crate::common::temp_dir;
use clothbake::lighting::{ContentError, Environment, EnvironmentError};
use exr::prelude::*;
use std::path::Path;

/// A sky near 1 that brightens towards the zenith, differing between neighbouring texels
/// and between channels so that a wrong index or channel shows.
fn sky(x: usize, y: usize, width: usize, height: usize) -> [f32; 3] {
    let v = (y as f32 + 0.5) / height as f32;
    let u = (x as f32 + 0.5) / width as f32;
    let base = 0.6 + 0.8 * (1.0 - v);
    [base * (0.9 + 0.1 * u), base, base * (1.1 - 0.05 * u)]
}

/// How a test file is laid out in the EXR.
#[derive(Clone, Copy, Debug)]
struct Shape {
    alpha: bool,
    half: bool,
    tiles: bool,
}

/// Writes `texels` as an EXR file of `shape` (PIZ, the usual compression of HDR photographs).
fn write(path: &Path, width: usize, height: usize, texels: &[[f32; 3]], shape: Shape) {
    let at = |position: Vec2<usize>| texels[position.y() * width + position.x()];
    let encoding = Encoding {
        compression: Compression::PIZ,
        blocks: if shape.tiles {
            Blocks::Tiles(Vec2(64, 64))
        } else {
            Blocks::ScanLines
        },
        line_order: LineOrder::Increasing,
    };
    // One layer of whichever channels: the four shapes differ only in their sample types.
    macro_rules! write_layer {
        ($channels:expr) => {
            Image::from_layer(Layer::new(
                Vec2(width, height),
                LayerAttributes::named("photograph"),
                encoding,
                $channels,
            ))
            .write()
            .to_file(path)
        };
    }
    let half = |p| at(p).map(f16::from_f32);
    let result = match (shape.alpha, shape.half) {
        (false, false) => write_layer!(SpecificChannels::rgb(|p| at(p).into())),
        (false, true) => write_layer!(SpecificChannels::rgb(|p| half(p).into())),
        (true, false) => write_layer!(SpecificChannels::rgba(|p| {
            let [r, g, b] = at(p);
            (r, g, b, 1.0f32)
        })),
        (true, true) => write_layer!(SpecificChannels::rgba(|p| {
            let [r, g, b] = half(p);
            (r, g, b, f16::ONE)
        })),
    };
    result.unwrap();
}

/// `texels` as the file stores them: rounded to halves where the file holds halves.
fn stored(texels: &[[f32; 3]], half: bool) -> Vec<[f32; 3]> {
    texels
        .iter()
        .map(|t| {
            if half {
                t.map(|v| f16::from_f32(v).to_f32())
            } else {
                *t
            }
        })
        .collect()
}

/// The residue real files carry: small negative values in a few texels and channels, the
/// most negative −0.004 at (5, 3).
const RESIDUE: [(usize, usize, usize, f32); 5] = [
    (5, 3, 1, -0.004),
    (17, 0, 0, -3e-6),
    (40, 20, 2, -0.0011),
    (63, 31, 0, -0.0002),
    (0, 12, 1, -2.5e-5),
];

#[test]
fn every_layout_of_a_real_file_loads_with_its_negative_residue_clamped() {
    let dir = temp_dir("hdr-photographs");
    let (width, height) = (64, 32);
    let mut texels: Vec<[f32; 3]> = (0..width * height)
        .map(|i| sky(i % width, i / width, width, height))
        .collect();
    for (x, y, channel, value) in RESIDUE {
        texels[y * width + x][channel] = value;
    }
    for alpha in [false, true] {
        for half in [false, true] {
            for tiles in [false, true] {
                let shape = Shape { alpha, half, tiles };
                let path = dir.join(format!("sky-{alpha}-{half}-{tiles}.exr"));
                write(&path, width, height, &texels, shape);
                let environment =
                    Environment::load(&path).unwrap_or_else(|e| panic!("{shape:?}: {e}"));
                let clamped = environment
                    .clamped_negatives()
                    .unwrap_or_else(|| panic!("{shape:?}: nothing reported clamped"));
                assert_eq!(clamped.texels, RESIDUE.len(), "{shape:?}");
                assert_eq!((clamped.col, clamped.row), (5, 3), "{shape:?}");
                let most_negative = stored(&[[-0.004; 3]], half)[0][0];
                assert_eq!(clamped.most_negative, most_negative, "{shape:?}");
                let message = clamped.to_string();
                assert!(
                    message.contains("clamped 5 texels") && message.contains("(5, 3)"),
                    "{message}"
                );
                // Every other texel as stored; the negative channels now 0.
                let mut expected = stored(&texels, half);
                for (x, y, channel, _) in RESIDUE {
                    expected[y * width + x][channel] = 0.0;
                }
                assert_eq!(
                    environment.levels()[0].texels(),
                    expected.as_slice(),
                    "{shape:?}"
                );
            }
        }
    }
}

#[test]
fn a_map_without_negatives_reports_nothing_clamped() {
    let dir = temp_dir("hdr-clean");
    let (width, height) = (16, 8);
    let texels: Vec<[f32; 3]> = (0..width * height)
        .map(|i| sky(i % width, i / width, width, height))
        .collect();
    let path = dir.join("clean.exr");
    let shape = Shape {
        alpha: true,
        half: true,
        tiles: false,
    };
    write(&path, width, height, &texels, shape);
    let environment = Environment::load(&path).unwrap();
    assert_eq!(environment.clamped_negatives(), None);
}

#[test]
fn signed_data_and_non_finite_texels_are_refused_by_position() {
    let dir = temp_dir("hdr-signed");
    let (width, height) = (16, 8);
    let shape = Shape {
        alpha: false,
        half: true,
        tiles: true,
    };
    // A value more negative than the sky's mean (about 1) is not a residue. Infinity in a
    // half file is what a value beyond 65504 becomes.
    for (name, x, y, value) in [
        ("signed.exr", 3usize, 6usize, -1.5f32),
        ("infinite.exr", 9, 1, f32::INFINITY),
        ("nan.exr", 0, 7, f32::NAN),
    ] {
        let mut texels: Vec<[f32; 3]> = (0..width * height)
            .map(|i| sky(i % width, i / width, width, height))
            .collect();
        texels[y * width + x][2] = value;
        let path = dir.join(name);
        write(&path, width, height, &texels, shape);
        let error = Environment::load(&path).expect_err(name);
        let message = error.to_string();
        assert!(
            message.contains(&format!("({x}, {y})")) && message.contains(name),
            "{message}"
        );
        match (&error, value < 0.0) {
            (
                EnvironmentError::Content {
                    problem: ContentError::Negative { col, row, .. },
                    ..
                },
                true,
            )
            | (
                EnvironmentError::Content {
                    problem: ContentError::Texel { col, row, .. },
                    ..
                },
                false,
            ) => assert_eq!((*col as usize, *row as usize), (x, y), "{message}"),
            _ => panic!("{name}: {message}"),
        }
    }
}

/// The equirectangular texel of the direction at `elevation` above the horizon and
/// `azimuth` (both in degrees, azimuth 0 at u = 0.5).
fn texel_at(elevation: f64, azimuth: f64, width: usize, height: usize) -> (usize, usize) {
    let u = 0.5 + azimuth / 360.0;
    let v = (90.0 - elevation) / 180.0;
    (
        (u * width as f64) as usize % width,
        ((v * height as f64) as usize).min(height - 1),
    )
}

#[test]
fn an_8k_sunlit_sky_in_halves_at_their_limit_loads_whole() {
    let dir = temp_dir("hdr-8k");
    let (width, height) = (8192, 4096);
    let mut texels: Vec<[f32; 3]> = (0..width * height)
        .map(|i| sky(i % width, i / width, width, height))
        .collect();
    // A sun of 0.5° diameter 30° above the horizon at 3.5e4, its core at half's largest
    // finite value, 65504: 11 texels across at this width (0.044° per texel).
    let (sun_x, sun_y) = texel_at(30.0, 40.0, width, height);
    let radius = 0.25 / (360.0 / width as f64);
    let mut sun_texels = 0;
    for y in sun_y - 8..=sun_y + 8 {
        for x in sun_x - 8..=sun_x + 8 {
            let r = ((x as f64 - sun_x as f64).powi(2) + (y as f64 - sun_y as f64).powi(2)).sqrt();
            if r <= radius {
                texels[y * width + x] = if r < 1.0 { [65504.0; 3] } else { [3.5e4; 3] };
                sun_texels += 1;
            }
        }
    }
    assert!(sun_texels > 50, "{sun_texels} sun texels");
    for (x, y, channel, value) in RESIDUE {
        texels[(y * 97) * width + x * 101][channel] = value;
    }
    let path = dir.join("sunlit-8k.exr");
    let shape = Shape {
        alpha: true,
        half: true,
        tiles: false,
    };
    write(&path, width, height, &texels, shape);
    let environment = Environment::load(&path).unwrap();
    assert_eq!((environment.width(), environment.height()), (8192, 4096));
    assert_eq!(environment.clamped_negatives().map(|c| c.texels), Some(5));
    let level = &environment.levels()[0];
    // The sun is kept exactly: halves of 3.5e4 and 65504 are exact.
    assert_eq!(level.texel(sun_x as u32, sun_y as u32), [65504.0; 3]);
    let bright = level.texels().iter().filter(|t| t[0] >= 3.5e4).count();
    assert_eq!(bright, sun_texels);
    // Nothing overflowed or was lost on the way down the mip chain: every level is finite
    // and keeps the map's mean radiance, to which the sun (6e-5 sr at 3.5e4) gives about a
    // seventh. The bound is 10× the f32 rounding the mip test of the sampling binary allows
    // (1e-5), for the 1e5:1 range of this map's texels.
    let mean = environment.mean_radiance();
    for (index, level) in environment.levels().iter().enumerate() {
        let m = level.mean_radiance();
        assert!(m.is_finite(), "level {index}: {m}");
        let difference = (m - mean).abs().max_element() / mean.max_element();
        assert!(difference < 1e-4, "level {index}: {difference:e}");
    }
}
