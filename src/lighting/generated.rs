//! Environments generated in code (no asset, deterministic), named by `--env`: the studio, a
//! clear sky with a sun, an overcast sky and an interior with windows and lamps. Each is a
//! radiance function of the direction, rasterised onto an equirectangular map with every
//! texel the mean over a grid of points inside it where the radiance has hard edges (the sun's
//! disc, a window's frame), so that a source smaller than a texel keeps its power.

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use super::environment::equirect_direction;
use super::studio::studio_radiance;
use super::{Environment, interior, sky};

/// One of the built-in environments.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum GeneratedEnvironment {
    /// Three soft boxes over a dim backdrop ([`Environment::studio`]): soft light, 8–14°
    /// lobes 20× the ambient.
    Studio,
    /// A clear sky with a 0.5° sun of radiance 3.5·10⁴ at 30° elevation, its aureole, and
    /// the ground below ([`sky::clear_sky_radiance`]).
    Sky,
    /// The CIE standard overcast sky over a grey ground: no source at all
    /// ([`sky::overcast_radiance`]).
    Overcast,
    /// A room: walls, floor and ceiling, two windows onto a bright sky and two small lamps
    /// ([`interior::interior_radiance`]).
    Interior,
}

impl GeneratedEnvironment {
    /// Every built-in environment, in the order the docs list them.
    pub const ALL: [Self; 4] = [Self::Studio, Self::Sky, Self::Overcast, Self::Interior];

    /// The `--env` word.
    pub fn name(self) -> &'static str {
        match self {
            Self::Studio => "studio",
            Self::Sky => "sky",
            Self::Overcast => "overcast",
            Self::Interior => "interior",
        }
    }

    /// The environment of this name, if any.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|g| g.name() == name)
    }

    /// Level-0 size: the sky's 0.5° sun needs texels of 0.18° (2048 across) to be a disc;
    /// the others are smooth or have sources of degrees.
    fn size(self) -> (u32, u32) {
        match self {
            Self::Sky => (2048, 1024),
            Self::Interior => (1024, 512),
            Self::Studio | Self::Overcast => (512, 256),
        }
    }

    /// Points per side of the grid a texel is averaged over: 1 (the centre) where the
    /// radiance is smooth on the scale of a texel.
    fn supersampling(self) -> u32 {
        match self {
            Self::Studio | Self::Overcast => 1,
            Self::Sky | Self::Interior => 4,
        }
    }

    /// The radiance arriving from unit direction `d`.
    pub fn radiance(self, d: DVec3) -> DVec3 {
        match self {
            Self::Studio => studio_radiance(d),
            Self::Sky => sky::clear_sky_radiance(d),
            Self::Overcast => sky::overcast_radiance(d),
            Self::Interior => interior::interior_radiance(d),
        }
    }

    /// The map: each texel the mean radiance over an n×n grid of points inside it (uniform
    /// in u and v; the texel's solid angle varies across it by under a texel's fraction of
    /// the row, which is negligible next to the edges this resolves).
    pub fn environment(self) -> Environment {
        let (width, height) = self.size();
        let n = self.supersampling();
        let mut texels = vec![[0.0f32; 3]; (width * height) as usize];
        texels
            .par_chunks_mut(width as usize)
            .enumerate()
            .for_each(|(row, out)| {
                for (col, texel) in out.iter_mut().enumerate() {
                    let mut sum = DVec3::ZERO;
                    for i in 0..n {
                        for j in 0..n {
                            let uv = DVec2::new(
                                (col as f64 + (i as f64 + 0.5) / n as f64) / width as f64,
                                (row as f64 + (j as f64 + 0.5) / n as f64) / height as f64,
                            );
                            sum += self.radiance(equirect_direction(uv));
                        }
                    }
                    *texel = (sum / (n * n) as f64).as_vec3().to_array();
                }
            });
        Environment::from_texels(width, height, texels)
            .expect("a generated environment is finite and non-negative")
    }
}
