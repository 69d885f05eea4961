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

/// The floor under cos²θd' that a thread's reflection is divided by, on the CPU and in
/// every thread layout's WGSL (`CLOTH_COS2_D_FLOOR`): where both directions run along the
/// thread, cos²θd' → 0, and the stored value's rounding would be amplified without bound.
pub const COS2_D_FLOOR: f64 = 1e-8;

/// The generated constants every thread layout's lookup reads: `CLOTH_COVERAGE` (a1, a2,
/// gap = 1 − a1 − a2, its threads weighed by their coverage) and `CLOTH_COS2_D_FLOOR`
/// ([`COS2_D_FLOOR`]).
pub fn layout_wgsl(coverage: [f64; 2], gap: f64) -> String {
    use crate::table::wgsl::{wgsl_f32, wgsl_vec};
    format!(
        "// Coverage (a1, a2, gap = 1 − a1 − a2).\nconst CLOTH_COVERAGE = {};\n\
         // The floor under cos²θd' that the reflection is divided by.\n\
         const CLOTH_COS2_D_FLOOR: f32 = {};\n",
        wgsl_vec(&[coverage[0], coverage[1], gap]),
        wgsl_f32(COS2_D_FLOOR)
    )
}
