//! Images of rendered cloth: linear radiance buffers, the tone mapping the render shader
//! applies (mirrored on the CPU), image error metrics, error heat maps, PNG and EXR files.

use std::path::{Path, PathBuf};

/// A linear-radiance image: RGB outgoing radiance per pixel, alpha 1 where the cloth covers
/// the pixel and 0 on the background. Rows top to bottom.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LinearImage {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<[f32; 4]>,
}

/// An 8-bit RGBA image (sRGB-encoded display values), rows top to bottom.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Rgba8Image {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<[u8; 4]>,
}

impl LinearImage {
    /// Whether pixel `i` is covered by the cloth.
    pub fn covered(&self, i: usize) -> bool {
        self.pixels[i][3] > 0.5
    }

    /// Pixels covered by the cloth.
    pub fn coverage(&self) -> usize {
        (0..self.pixels.len()).filter(|&i| self.covered(i)).count()
    }

    /// The image tone mapped as the render shader does ([`tonemap`]), background `background`
    /// (display values in [0, 1]).
    pub fn tonemapped(&self, exposure: f32, background: [f32; 3]) -> Rgba8Image {
        let pixels = self
            .pixels
            .iter()
            .map(|p| {
                let c = if p[3] > 0.5 {
                    tonemap([p[0], p[1], p[2]], exposure)
                } else {
                    background
                };
                [quantise(c[0]), quantise(c[1]), quantise(c[2]), 255]
            })
            .collect();
        Rgba8Image {
            width: self.width,
            height: self.height,
            pixels,
        }
    }
}

fn quantise(v: f32) -> u8 {
    (v.clamp(0.0, 1.0) * 255.0).round() as u8
}

/// The render shader's tone mapping (`render_tonemap` in shaders/render/renderer.wgsl): radiance
/// times exposure, the ACES filmic fit x(2.51x + 0.03)/(x(2.43x + 0.59) + 0.14) clamped to
/// [0, 1], then the sRGB transfer function. Returns display values in [0, 1].
pub fn tonemap(radiance: [f32; 3], exposure: f32) -> [f32; 3] {
    radiance.map(|l| {
        let x = (l * exposure).max(0.0);
        let mapped = ((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14)).clamp(0.0, 1.0);
        srgb_encode(mapped)
    })
}

/// The sRGB transfer function (IEC 61966-2-1) of a linear value in [0, 1].
pub fn srgb_encode(c: f32) -> f32 {
    if c <= 0.0031308 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// The inverse of [`srgb_encode`]: the linear value of a display value in [0, 1].
pub fn srgb_decode(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// The error of a rendered image against a reference of the same view.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImageError {
    /// ‖render − reference‖₂ / ‖reference‖₂ over the RGB linear radiance of the pixels
    /// either image covers.
    pub relative_l2: f64,
    /// 10·log10(1/MSE) of the tone-mapped display values in [0, 1] (exposure as given, before
    /// 8-bit quantisation), over the RGB of the pixels either image covers; infinite when
    /// identical.
    pub psnr_db: f64,
    /// Pixels the reference covers.
    pub covered: usize,
    /// Pixels covered in one image but not the other (they count in both metrics, the
    /// uncovered side as 0 radiance).
    pub coverage_mismatch: usize,
}

/// Why images could not be compared, written or read.
#[derive(Debug, thiserror::Error)]
pub enum ImageFileError {
    #[error("image sizes differ: {render:?} against a {reference:?} reference")]
    SizeMismatch {
        render: (u32, u32),
        reference: (u32, u32),
    },
    #[error("cannot write {path}: {message}", path = .path.display())]
    Write { path: PathBuf, message: String },
    #[error("cannot read {path}: {message}", path = .path.display())]
    Read { path: PathBuf, message: String },
}

/// Checks that two images have the same size.
fn same_size(render: &LinearImage, reference: &LinearImage) -> Result<(), ImageFileError> {
    if (render.width, render.height) != (reference.width, reference.height)
        || render.pixels.len() != reference.pixels.len()
    {
        return Err(ImageFileError::SizeMismatch {
            render: (render.width, render.height),
            reference: (reference.width, reference.height),
        });
    }
    Ok(())
}

/// Compares `render` with `reference` (linear radiance of the same view and size).
pub fn image_error(
    render: &LinearImage,
    reference: &LinearImage,
    exposure: f32,
) -> Result<ImageError, ImageFileError> {
    same_size(render, reference)?;
    let (mut diff2, mut ref2, mut se) = (0.0f64, 0.0f64, 0.0f64);
    let (mut covered, mut mismatch, mut union) = (0usize, 0usize, 0usize);
    for i in 0..reference.pixels.len() {
        let (r_in, f_in) = (render.covered(i), reference.covered(i));
        if r_in != f_in {
            mismatch += 1;
        }
        if !(r_in || f_in) {
            continue;
        }
        covered += f_in as usize;
        union += 1;
        let rgb = |image: &LinearImage, inside: bool| {
            let p = image.pixels[i];
            if inside { [p[0], p[1], p[2]] } else { [0.0; 3] }
        };
        let (a, b) = (rgb(render, r_in), rgb(reference, f_in));
        let (ta, tb) = (tonemap(a, exposure), tonemap(b, exposure));
        for c in 0..3 {
            diff2 += (a[c] as f64 - b[c] as f64).powi(2);
            ref2 += (b[c] as f64).powi(2);
            se += (ta[c] as f64 - tb[c] as f64).powi(2);
        }
    }
    let mse = se / (3 * union).max(1) as f64;
    Ok(ImageError {
        relative_l2: if ref2 > 0.0 {
            (diff2 / ref2).sqrt()
        } else if diff2 > 0.0 {
            f64::INFINITY
        } else {
            0.0
        },
        psnr_db: if mse > 0.0 {
            -10.0 * mse.log10()
        } else {
            f64::INFINITY
        },
        covered,
        coverage_mismatch: mismatch,
    })
}

/// The heat map's range: relative errors from 10^LO to 10^HI on a log scale.
pub const HEATMAP_LOG10_RANGE: (f32, f32) = (-3.0, 0.0);
/// Rows of the colour bar under the heat map.
pub const HEATMAP_BAR_ROWS: u32 = 12;

/// A heat map of the per-pixel relative error |render − reference| / max(|reference|, floor)
/// (RGB Euclidean norms; floor = 1% of the mean reference radiance, so that near-black
/// pixels do not dominate) on a log scale from 0.1% (black) through blue, green, yellow and
/// red to 100% and above (white); background grey. Below the image, a colour bar of
/// [`HEATMAP_BAR_ROWS`] rows spans the same scale left to right with black tick marks at
/// 0.1%, 1%, 10% and 100%.
pub fn error_heatmap(
    render: &LinearImage,
    reference: &LinearImage,
) -> Result<Rgba8Image, ImageFileError> {
    same_size(render, reference)?;
    let norm = |p: &[f32; 4]| (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
    let covered: Vec<usize> = (0..reference.pixels.len())
        .filter(|&i| reference.covered(i))
        .collect();
    let mean = covered
        .iter()
        .map(|&i| norm(&reference.pixels[i]) as f64)
        .sum::<f64>()
        / covered.len().max(1) as f64;
    let floor = (0.01 * mean).max(1e-12) as f32;
    let (lo, hi) = HEATMAP_LOG10_RANGE;
    let mut pixels: Vec<[u8; 4]> = (0..reference.pixels.len())
        .map(|i| {
            if !(reference.covered(i) || render.covered(i)) {
                return [64, 64, 64, 255];
            }
            let (a, b) = (&render.pixels[i], &reference.pixels[i]);
            let d = [a[0] - b[0], a[1] - b[1], a[2] - b[2], 0.0];
            let e = norm(&d) / norm(b).max(floor);
            let x = ((e.max(1e-30).log10() - lo) / (hi - lo)).clamp(0.0, 1.0);
            heat_colour(x)
        })
        .collect();
    let width = reference.width as usize;
    for row in 0..HEATMAP_BAR_ROWS {
        for column in 0..width {
            let x = column as f32 / (width.max(2) - 1) as f32;
            let decades = (hi - lo) as usize;
            let tick = (0..=decades).any(|k| {
                let at = (k as f32 / decades as f32 * (width.max(2) - 1) as f32).round() as usize;
                at == column
            });
            pixels.push(if tick && row < HEATMAP_BAR_ROWS / 2 {
                [0, 0, 0, 255]
            } else {
                heat_colour(x)
            });
        }
    }
    Ok(Rgba8Image {
        width: reference.width,
        height: reference.height + HEATMAP_BAR_ROWS,
        pixels,
    })
}

/// Colour ramp black → blue → green → yellow → red → white over x in [0, 1].
fn heat_colour(x: f32) -> [u8; 4] {
    const STOPS: [[f32; 3]; 6] = [
        [0.0, 0.0, 0.0],
        [0.1, 0.2, 1.0],
        [0.1, 0.85, 0.2],
        [1.0, 0.9, 0.1],
        [0.95, 0.1, 0.05],
        [1.0, 1.0, 1.0],
    ];
    let f = x.clamp(0.0, 1.0) * (STOPS.len() - 1) as f32;
    let k = (f.floor() as usize).min(STOPS.len() - 2);
    let w = f - k as f32;
    let c = [0, 1, 2].map(|j| STOPS[k][j] + w * (STOPS[k + 1][j] - STOPS[k][j]));
    [quantise(c[0]), quantise(c[1]), quantise(c[2]), 255]
}

/// Writes an 8-bit RGBA PNG, atomically (encoded in memory, then a temporary file renamed
/// over `path`), so that a reader never sees part of an image.
pub fn write_png(path: &Path, image: &Rgba8Image) -> Result<(), ImageFileError> {
    let fail = |e: &dyn std::fmt::Display| ImageFileError::Write {
        path: path.to_path_buf(),
        message: e.to_string(),
    };
    let mut bytes = Vec::new();
    let mut encoder = png::Encoder::new(&mut bytes, image.width, image.height);
    encoder.set_color(png::ColorType::Rgba);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
    let mut writer = encoder.write_header().map_err(|e| fail(&e))?;
    writer
        .write_image_data(bytemuck::cast_slice(&image.pixels))
        .map_err(|e| fail(&e))?;
    writer.finish().map_err(|e| fail(&e))?;
    crate::formats::atomic::write_atomically(path, &bytes).map_err(|e| fail(&e))
}

/// Writes a linear image as an OpenEXR file of f16 RGBA (alpha = coverage).
pub fn write_linear_exr(path: &Path, image: &LinearImage) -> Result<(), ImageFileError> {
    use exr::prelude::*;
    let width = image.width as usize;
    let pixels = &image.pixels;
    let channels = SpecificChannels::rgba(|Vec2(x, y): Vec2<usize>| {
        let p = pixels[y * width + x];
        (
            f16::from_f32(p[0]),
            f16::from_f32(p[1]),
            f16::from_f32(p[2]),
            f16::from_f32(p[3]),
        )
    });
    Image::from_channels((image.width as usize, image.height as usize), channels)
        .write()
        .to_file(path)
        .map_err(|e| ImageFileError::Write {
            path: path.to_path_buf(),
            message: e.to_string(),
        })
}

/// Largest linear image read (pixels).
pub const MAX_LINEAR_EXR_PIXELS: usize = 1 << 24;

/// Reads a linear RGBA OpenEXR image (the first RGBA layer; missing alpha reads as 1).
pub fn read_linear_exr(path: &Path) -> Result<LinearImage, ImageFileError> {
    use exr::prelude::*;
    let fail = |e: &dyn std::fmt::Display| ImageFileError::Read {
        path: path.to_path_buf(),
        message: e.to_string(),
    };
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .rgba_channels(
            |resolution, _| {
                let (w, h) = (resolution.width(), resolution.height());
                (w, vec![[0.0f32; 4]; (w * h).min(MAX_LINEAR_EXR_PIXELS)])
            },
            |(width, pixels): &mut (usize, Vec<[f32; 4]>),
             position,
             (r, g, b, a): (f32, f32, f32, f32)| {
                let i = position.y() * *width + position.x();
                if let Some(p) = pixels.get_mut(i) {
                    *p = [r, g, b, a];
                }
            },
        )
        .first_valid_layer()
        .all_attributes()
        .from_file(path)
        .map_err(|e| fail(&e))?;
    let size = image.layer_data.size;
    let (_, pixels) = image.layer_data.channel_data.pixels;
    if size.width() * size.height() != pixels.len() {
        return Err(fail(&format!(
            "{}×{} pixels, over the {MAX_LINEAR_EXR_PIXELS}-pixel limit",
            size.width(),
            size.height()
        )));
    }
    Ok(LinearImage {
        width: size.width() as u32,
        height: size.height() as u32,
        pixels,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(values: &[[f32; 4]]) -> LinearImage {
        LinearImage {
            width: values.len() as u32,
            height: 1,
            pixels: values.to_vec(),
        }
    }

    #[test]
    fn identical_images_have_no_error_and_a_scaled_one_its_scale() {
        let reference = image(&[[1.0, 0.5, 0.25, 1.0], [2.0, 2.0, 2.0, 1.0], [9.0; 4]]);
        let reference = LinearImage {
            pixels: vec![reference.pixels[0], reference.pixels[1], [0.0; 4]],
            ..reference
        };
        let same = image_error(&reference, &reference, 1.0).unwrap();
        assert_eq!(same.relative_l2, 0.0);
        assert!(same.psnr_db.is_infinite());
        assert_eq!(same.covered, 2);
        let mut brighter = reference.clone();
        for p in &mut brighter.pixels[..2] {
            for c in &mut p[..3] {
                *c *= 1.1;
            }
        }
        let e = image_error(&brighter, &reference, 1.0).unwrap();
        assert!((e.relative_l2 - 0.1).abs() < 1e-6, "{e:?}");
        assert!(e.psnr_db.is_finite() && e.psnr_db > 10.0, "{e:?}");
        assert!(image_error(&image(&[[0.0; 4]]), &reference, 1.0).is_err());
    }

    #[test]
    fn tonemap_is_monotonic_black_at_zero_and_saturates() {
        assert_eq!(tonemap([0.0; 3], 1.0), [0.0; 3]);
        // sRGB(1) = 1.055 − 0.055 = 1 − 6e-8 in f32.
        assert!(
            tonemap([1e6; 3], 1.0)
                .iter()
                .all(|&v| v > 0.9999 && v <= 1.0)
        );
        // The ACES fit reaches 1 at x ≈ 7.24; below that it rises strictly.
        let mut last = 0.0;
        for k in 1..720 {
            let v = tonemap([k as f32 * 0.01; 3], 1.0)[0];
            assert!(v > last, "{k}");
            last = v;
        }
        assert_eq!(tonemap([0.5; 3], 2.0), tonemap([1.0; 3], 1.0));
    }

    #[test]
    fn heatmap_has_the_colour_bar_and_grades_errors() {
        let reference = image(&[[1.0, 1.0, 1.0, 1.0], [1.0, 1.0, 1.0, 1.0], [0.0; 4]]);
        let render = image(&[[1.0, 1.0, 1.0, 1.0], [2.0, 2.0, 2.0, 1.0], [0.0; 4]]);
        let map = error_heatmap(&render, &reference).unwrap();
        assert_eq!(map.height, 1 + HEATMAP_BAR_ROWS);
        assert_eq!(map.pixels[0], [0, 0, 0, 255]); // no error: black
        assert_eq!(map.pixels[1], [255, 255, 255, 255]); // 100%: white
        assert_eq!(map.pixels[2], [64, 64, 64, 255]); // background
    }

    #[test]
    fn exr_round_trip_keeps_f16_values() {
        let scratch = tempfile::tempdir().unwrap();
        let dir = scratch.path();
        let path = dir.join("linear.exr");
        let original = LinearImage {
            width: 3,
            height: 2,
            pixels: (0..6)
                .map(|i| [i as f32 * 0.25, 1.5, 100.0, (i % 2) as f32])
                .collect(),
        };
        write_linear_exr(&path, &original).unwrap();
        assert_eq!(read_linear_exr(&path).unwrap(), original);
    }
}
