//! The model (`clothbake::model`): the direct evaluation, converged and against an
//! independent reference; the resonant quadrature against it; the invariants of the
//! building blocks; stability on the hard cases; properties over random fabrics; a fit
//! (`clothbake::fit`) recovering a moved fabric's F from its noisy samples.
//!
//! One binary per part of the crate, each module a former test file: each integration-test
//! binary is another release link of the whole crate with wgpu, naga, exr and ash.

#[path = "../common/mod.rs"]
mod common;

mod direct_convergence;
mod evaluators;
mod fit_round_trip;
mod invariants;
mod properties;
mod reference;
mod resonant;
mod stability;
mod stock;
mod weave;
