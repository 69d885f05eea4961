//! One thread's tables in coordinates aligned with its specular resonance, shared by the
//! layouts that tabulate a thread this way ([`super::thread_frame`], whose module
//! documentation derives the coordinates, and [`super::split_frame`]'s sloped tables): the
//! axes and their sizing ([`geometry`]), reading the tables in f64 and f32 and the GPU's
//! error doing so ([`lookup`]), and baking them ([`bake`]). Which way each thread runs is
//! the model's [`crate::model::thread_axes`].

pub mod bake;
pub mod geometry;
pub mod lookup;

pub use bake::{
    MASKING_FLOOR, bake_masking, bake_thread_plane, masking_texture, stored_ratios, thread_texture,
};
pub(crate) use geometry::lanes_in_thread_axes;
pub use geometry::{AxisPlan, MASKING_TEXELS, MIN_BETA_TEXELS, ThreadGeometry};
pub use lookup::{LocatedPairs, f32_exempt, thread_errors};
