//! Distant light: environment maps (equirectangular radiance with a prefiltered mip chain),
//! the built-in studio, and where an environment comes from. Reading map files lives in
//! [`crate::formats::environment_map`], sampling a map in [`crate::sampling::environment`].

pub mod environment;
mod source;
mod studio;

pub use environment::{
    ClampedNegatives, ContentError, Environment, EnvironmentError, Level, MAX_SIDE, MAX_TEXELS,
    equirect_direction, equirect_uv,
};
pub use source::EnvironmentSource;
