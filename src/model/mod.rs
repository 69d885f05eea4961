//! The microcylinder cloth model of Sadeghi et al. 2013 as specified in docs/model.md: pure
//! functions of directions and parameters, no I/O.
//!
//! Frame: x = thread 1, y = thread 2, z = surface normal; `wi` points to the light, `wo` to
//! the viewer. Everything returns the cosine-weighted patch transfer `F(wi, wo)`.

pub mod curve;
pub mod fabric;
pub mod lobes;
pub mod patch;
pub mod resonant;
pub mod sample;

pub use curve::{Integration, NodeCountError, ResonantNodes};
pub use fabric::{Fabric, FabricError, GaussianWidth, ModelOptions, TangentSampling, Thread};
pub use patch::{Patch, PatchTerms};
pub use sample::{ThreadMeans, thread_axes};
