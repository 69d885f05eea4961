//! The mip chain of an equirectangular map: levels halved down to 1×1, each texel the
//! solid-angle-weighted mean of the texels it covers, so every level keeps the map's mean
//! radiance (see [`super::Environment::levels`]).

use glam::{DVec2, DVec3};
use rayon::prelude::*;
use std::f64::consts::{PI, TAU};

/// One level of the mip chain: linear RGB radiance, row-major, row 0 the top row.
#[derive(Clone, Debug, PartialEq)]
pub struct Level {
    width: u32,
    height: u32,
    texels: Vec<[f32; 3]>,
}

impl Level {
    /// A level of `width`×`height` texels; the caller has checked the count.
    pub(super) fn new(width: u32, height: u32, texels: Vec<[f32; 3]>) -> Self {
        debug_assert_eq!(texels.len(), width as usize * height as usize);
        Self {
            width,
            height,
            texels,
        }
    }

    /// Width in texels (the u direction).
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in texels (the v direction).
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The texels, row-major from the top row: what a GPU upload of this level takes.
    pub fn texels(&self) -> &[[f32; 3]] {
        &self.texels
    }

    /// The texel at column `col`, row `row`.
    ///
    /// # Panics
    /// If `col >= width` or `row >= height`.
    pub fn texel(&self, col: u32, row: u32) -> [f32; 3] {
        assert!(col < self.width && row < self.height, "texel out of range");
        self.texels[row as usize * self.width as usize + col as usize]
    }

    /// The exact solid angle of one texel in `row`: `(2π/W)·(cos θ_top − cos θ_bottom)`
    /// (all texels of a row are alike; rows near the poles are small). Summed over the
    /// level it is 4π.
    pub fn texel_solid_angle(&self, row: u32) -> f64 {
        band_solid_angle(row as u64, row as u64 + 1, self.height as u64) * TAU / self.width as f64
    }

    /// The solid-angle-weighted mean radiance over the sphere.
    pub fn mean_radiance(&self) -> DVec3 {
        let width = self.width as usize;
        let sum: DVec3 = self
            .texels
            .chunks_exact(width)
            .enumerate()
            .map(|(row, texels)| {
                let row_sum: DVec3 = texels.iter().map(|t| to_dvec3(*t)).sum();
                row_sum * self.texel_solid_angle(row as u32)
            })
            .sum();
        sum / (4.0 * PI)
    }

    /// Bilinear interpolation between the four texel centres around `uv`, repeating in u
    /// and clamping in v: WGSL's linear sampler with `Repeat` in u, `ClampToEdge` in v.
    pub(super) fn bilinear(&self, uv: DVec2) -> DVec3 {
        let (width, height) = (self.width as i64, self.height as i64);
        let x = uv.x * self.width as f64 - 0.5;
        let y = uv.y * self.height as f64 - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        // Float-to-int casts saturate (NaN gives 0), so no coordinate can index out of range.
        let (x0, y0) = (x0 as i64, y0 as i64);
        let cols = [x0.rem_euclid(width), x0.saturating_add(1).rem_euclid(width)];
        let rows = [
            y0.clamp(0, height - 1),
            y0.saturating_add(1).clamp(0, height - 1),
        ];
        let at = |c: i64, r: i64| to_dvec3(self.texels[(r * width + c) as usize]);
        let top = at(cols[0], rows[0]).lerp(at(cols[1], rows[0]), fx);
        let bottom = at(cols[0], rows[1]).lerp(at(cols[1], rows[1]), fx);
        top.lerp(bottom, fy)
    }

    /// The next level: `max(1, W/2)`×`max(1, H/2)`, each texel the solid-angle-weighted
    /// mean of the parent texels it covers. The weights are exact overlaps (lengths in u,
    /// band solid angles in v), so the mean over the sphere is kept; for even sizes this is
    /// the 2×2 box weighted by texel solid angle, and it also handles odd sizes (a child
    /// texel covering parts of three parent columns) and the 2×1 / 1×2 ends.
    pub(super) fn downsample(&self) -> Level {
        let width = (self.width / 2).max(1);
        let height = (self.height / 2).max(1);
        // Overlaps in u: child column i covers [i·W, (i+1)·W) and parent column c covers
        // [c·w, (c+1)·w) in units of 1/(W·w) of the circle, so the lengths are integers.
        let columns = overlaps(self.width as u64, width as u64, |lo, hi| (hi - lo) as f64);
        // Overlaps in v: the same integer boundaries in units of π/(H·h), weighted by the
        // band's solid angle, since rows near the poles cover less of the sphere.
        let parent_height = self.height as u64;
        let rows = overlaps(parent_height, height as u64, |lo, hi| {
            band_solid_angle(lo, hi, parent_height * height as u64)
        });
        let parent_width = self.width as usize;
        let mut texels = vec![[0.0f32; 3]; width as usize * height as usize];
        texels
            .par_chunks_mut(width as usize)
            .zip(&rows)
            .for_each(|(out_row, row_weights)| {
                let row_total: f64 = row_weights.iter().map(|(_, w)| w).sum();
                for (out, column_weights) in out_row.iter_mut().zip(&columns) {
                    let column_total: f64 = column_weights.iter().map(|(_, w)| w).sum();
                    let mut sum = DVec3::ZERO;
                    for &(r, wr) in row_weights {
                        let parent_row = &self.texels[r * parent_width..(r + 1) * parent_width];
                        for &(c, wc) in column_weights {
                            sum += to_dvec3(parent_row[c]) * (wr * wc);
                        }
                    }
                    *out = (sum / (row_total * column_total)).as_vec3().to_array();
                }
            });
        Level {
            width,
            height,
            texels,
        }
    }
}

/// For each of `children` equal parts of a range split into `parents` equal parts, the
/// parents it overlaps and `weight(lo, hi)` of each overlap, with `lo..hi` in units of
/// 1/(parents·children) of the range (so every boundary is an integer).
fn overlaps(
    parents: u64,
    children: u64,
    weight: impl Fn(u64, u64) -> f64,
) -> Vec<Vec<(usize, f64)>> {
    (0..children)
        .map(|child| {
            let (start, end) = (child * parents, (child + 1) * parents);
            (start / children..end.div_ceil(children))
                .filter_map(|parent| {
                    let lo = start.max(parent * children);
                    let hi = end.min((parent + 1) * children);
                    (hi > lo).then(|| (parent as usize, weight(lo, hi)))
                })
                .collect()
        })
        .collect()
}

/// `cos θ_lo − cos θ_hi` for the polar band `θ in [lo·π/n, hi·π/n)`: its solid angle divided
/// by 2π. Written with sines (`2 sin(mid) sin(half-width)`) so thin bands lose no precision.
fn band_solid_angle(lo: u64, hi: u64, n: u64) -> f64 {
    let a = lo as f64 * PI / n as f64;
    let b = hi as f64 * PI / n as f64;
    2.0 * (0.5 * (a + b)).sin() * (0.5 * (b - a)).sin()
}

fn to_dvec3(texel: [f32; 3]) -> DVec3 {
    DVec3::new(texel[0] as f64, texel[1] as f64, texel[2] as f64)
}
