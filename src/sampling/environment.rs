//! Importance sampling of an environment map by its brightness.

use glam::{DVec2, DVec3};
use std::f64::consts::{PI, TAU};

use super::{invert_cdf, write_cdf};
use crate::lighting::{Environment, equirect_direction, equirect_uv};

/// Widest level [`EnvironmentSampler`] is built on: a 512×256 level holds every feature a
/// distribution needs to find (a light of a few degrees) in 0.5 MiB of CDFs.
pub const SAMPLER_MAX_WIDTH: u32 = 512;

/// Importance sampling of an environment map by its brightness, for multiple importance
/// sampling with a fabric's sampler in the CPU reference of a render
/// (`render::reference`), where a small bright light must not be left to chance.
///
/// Built on the first mip level at most [`SAMPLER_MAX_WIDTH`] wide: a texel is picked with
/// probability proportional to its mean RGB radiance times its solid angle, then a direction
/// uniform in solid angle inside it (uniform in azimuth and in cos θ), so the density per
/// unit solid angle is the texel's probability over its solid angle
/// `(2π/W)·(cos θ_top − cos θ_bottom)`. Data: the row CDF (H + 1 f32, 0 first, exactly 1
/// last), then each row's column CDF (W + 1 f32 each); probabilities are differences of
/// stored neighbours in sampling and in the pdf alike.
#[derive(Clone, Debug, PartialEq)]
pub struct EnvironmentSampler {
    width: u32,
    height: u32,
    data: Vec<f32>,
}

impl EnvironmentSampler {
    /// The sampler of `map` (see the type's doc for the level it uses).
    pub fn new(map: &Environment) -> Self {
        let level = map
            .levels()
            .iter()
            .find(|l| l.width() <= SAMPLER_MAX_WIDTH)
            .unwrap_or_else(|| map.levels().last().expect("a map has a level"));
        let (width, height) = (level.width() as usize, level.height() as usize);
        let weights: Vec<f64> = level
            .texels()
            .iter()
            .enumerate()
            .map(|(i, t)| {
                let mean = (t[0] as f64 + t[1] as f64 + t[2] as f64) / 3.0;
                mean * level.texel_solid_angle((i / width) as u32)
            })
            .collect();
        let rows: Vec<f64> = weights
            .chunks_exact(width)
            .map(|r| r.iter().sum())
            .collect();
        let mut data = vec![0.0; height + 1 + height * (width + 1)];
        write_cdf(&rows, &mut data[..height + 1]);
        for (row, out) in weights
            .chunks_exact(width)
            .zip(data[height + 1..].chunks_exact_mut(width + 1))
        {
            write_cdf(row, out);
        }
        Self {
            width: level.width(),
            height: level.height(),
            data,
        }
    }

    fn column_cdf(&self, row: usize) -> &[f32] {
        let w = self.width as usize + 1;
        let start = self.height as usize + 1 + row * w;
        &self.data[start..start + w]
    }

    /// cos θ at the top edge of row `row` (θ the polar angle from +y).
    fn cos_top(&self, row: usize) -> f64 {
        (PI * row as f64 / self.height as f64).cos()
    }

    /// A world direction from two uniform numbers in [0, 1), and its density per unit
    /// solid angle.
    pub fn sample(&self, u: [f64; 2]) -> (DVec3, f64) {
        let (row, v) = invert_cdf(&self.data[..self.height as usize + 1], u[0]);
        let (column, w) = invert_cdf(self.column_cdf(row), u[1]);
        let (top, bottom) = (self.cos_top(row), self.cos_top(row + 1));
        let polar = (top + v * (bottom - top)).clamp(-1.0, 1.0).acos();
        let direction = equirect_direction(DVec2::new(
            (column as f64 + w) / self.width as f64,
            polar / PI,
        ));
        (direction, self.pdf(direction))
    }

    /// The density per unit solid angle of [`EnvironmentSampler::sample`] at `direction`.
    pub fn pdf(&self, direction: DVec3) -> f64 {
        let uv = equirect_uv(direction);
        let (w, h) = (self.width as usize, self.height as usize);
        let column = ((uv.x.rem_euclid(1.0) * w as f64) as usize).min(w - 1);
        let row = ((uv.y * h as f64) as usize).min(h - 1);
        let rows = &self.data[..h + 1];
        let columns = self.column_cdf(row);
        let p = (rows[row + 1] as f64 - rows[row] as f64)
            * (columns[column + 1] as f64 - columns[column] as f64);
        let solid_angle = (TAU / w as f64) * (self.cos_top(row) - self.cos_top(row + 1));
        p / solid_angle
    }
}
