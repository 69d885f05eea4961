//! Distant light: environment maps (equirectangular radiance with a prefiltered mip chain),
//! the built-in environments (studio, sky, overcast, interior), and where an environment comes from. Reading map files lives in
//! [`crate::formats::environment_map`], sampling a map in [`crate::sampling::environment`].

pub mod bright_sources;
pub mod environment;
pub(crate) mod errors;
mod generated;
pub mod interior;
mod mip;
mod shapes;
pub mod sky;
mod source;
mod studio;

pub use bright_sources::{DistantSource, SplitEnvironment, disk_above_horizon};
pub use environment::{ClampedNegatives, Environment, equirect_direction, equirect_uv};
pub use errors::{ContentError, EnvironmentError, MAX_SIDE, MAX_TEXELS};
pub use generated::GeneratedEnvironment;
pub use mip::Level;
pub use source::EnvironmentSource;
