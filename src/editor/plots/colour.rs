//! The hemisphere image's false colour: the luminance of F on a log scale through a
//! perceptually uniform colour map.

/// Decades of luminance the hemisphere image spans below its brightest pixel; darker
/// pixels take the bottom colour. Three decades show a satin's surface highlight and the
/// volume term's diffuse floor together without the grazing fall-off to 0 taking the scale.
pub const HEMISPHERE_DECADES: f64 = 3.0;

/// The luminance of a linear RGB value with Rec. 709 (sRGB) primaries.
pub fn luminance(rgb: [f64; 3]) -> f64 {
    0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]
}

/// Viridis (van der Walt and Smith's perceptually uniform map, matplotlib's default) at
/// nine evenly spaced stops, 8-bit sRGB.
const VIRIDIS: [[u8; 3]; 9] = [
    [68, 1, 84],
    [72, 40, 120],
    [62, 73, 137],
    [49, 104, 142],
    [38, 130, 142],
    [31, 158, 137],
    [53, 183, 121],
    [110, 206, 88],
    [253, 231, 37],
];

/// The colour map at `x` in [0, 1] (clamped; NaN gives the bottom colour), opaque 8-bit
/// sRGB: dark violet at 0 through blue and green to yellow at 1, interpolated linearly
/// between the stops of viridis.
pub fn colour_map(x: f64) -> [u8; 4] {
    let x = if x.is_nan() { 0.0 } else { x.clamp(0.0, 1.0) };
    let f = x * (VIRIDIS.len() - 1) as f64;
    let k = (f.floor() as usize).min(VIRIDIS.len() - 2);
    let w = f - k as f64;
    let (a, b) = (VIRIDIS[k], VIRIDIS[k + 1]);
    let channel = |j: usize| (a[j] as f64 + w * (b[j] as f64 - a[j] as f64)).round() as u8;
    [channel(0), channel(1), channel(2), 255]
}

/// The false colour of each pixel (`None`: outside the disc, transparent) and the range of
/// log10 luminance the colours span: from [`HEMISPHERE_DECADES`] below the brightest pixel
/// to it. Where no pixel has a positive luminance the range is (−1, 0) (an arbitrary
/// decade, as there is no scale) and every pixel inside takes the bottom colour.
pub fn false_colour(f: &[Option<[f64; 3]>]) -> (Vec<[u8; 4]>, (f64, f64)) {
    let top = f
        .iter()
        .flatten()
        .map(|&rgb| luminance(rgb))
        .filter(|y| y.is_finite())
        .fold(0.0, f64::max);
    let range = if top > 0.0 {
        let hi = top.log10();
        (hi - HEMISPHERE_DECADES, hi)
    } else {
        (-1.0, 0.0)
    };
    let rgba = f
        .iter()
        .map(|pixel| match pixel {
            None => [0; 4],
            Some(rgb) => {
                let y = luminance(*rgb);
                let x = if y > 0.0 {
                    (y.log10() - range.0) / (range.1 - range.0)
                } else {
                    0.0
                };
                colour_map(x)
            }
        })
        .collect();
    (rgba, range)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_map_runs_from_dark_to_bright_and_clamps() {
        assert_eq!(colour_map(0.0), [68, 1, 84, 255]);
        assert_eq!(colour_map(1.0), [253, 231, 37, 255]);
        assert_eq!(colour_map(-3.0), colour_map(0.0));
        assert_eq!(colour_map(7.0), colour_map(1.0));
        assert_eq!(colour_map(f64::NAN), colour_map(0.0));
        // Perceptual maps rise in lightness throughout: the luminance of the 8-bit values
        // (as a proxy) never falls along the map.
        let lightness = |c: [u8; 4]| luminance([c[0], c[1], c[2]].map(f64::from));
        let steps: Vec<f64> = (0..=100)
            .map(|i| lightness(colour_map(i as f64 / 100.0)))
            .collect();
        assert!(steps.windows(2).all(|w| w[1] >= w[0]), "{steps:?}");
    }

    #[test]
    fn the_scale_spans_three_decades_below_the_brightest_pixel() {
        let grey = |y: f64| Some([y; 3]);
        let (rgba, range) = false_colour(&[None, grey(10.0), grey(0.1), grey(0.01), grey(0.0)]);
        assert!(
            (range.1 - 1.0).abs() < 1e-12 && (range.0 + 2.0).abs() < 1e-12,
            "{range:?}"
        );
        assert_eq!(rgba[0], [0; 4]);
        assert_eq!(rgba[1], colour_map(1.0));
        // 0.1 is one decade above the floor of 0.01: a third of the way up.
        assert_eq!(rgba[2], colour_map(1.0 / 3.0));
        assert_eq!(rgba[3], colour_map(0.0));
        assert_eq!(rgba[4], colour_map(0.0));
        let (black, range) = false_colour(&[grey(0.0), None]);
        assert_eq!(range, (-1.0, 0.0));
        assert_eq!(black, vec![colour_map(0.0), [0; 4]]);
    }
}
