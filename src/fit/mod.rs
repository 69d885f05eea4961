//! Fitting a fabric to measured samples of F (issue 46): the samples
//! ([`samples`]: JSON lines of `wi`, `wo`, `f`, as untrusted input), what the fit may change
//! ([`parameters`]: a [`Parametrisation`] from bounded free parameters to valid fabrics, e.g.
//! [`LikeFabric`], the parameters of a given fabric with its structure kept), and the
//! bounded least-squares solve with its report ([`solve`]: Levenberg–Marquardt on the
//! resonant quadrature, figures by the direct rule, the directions the samples leave
//! unconstrained). `clothbake fit` (src/cli/fit.rs) is the command over it.

pub mod bounded;
pub mod cases;
pub mod identifiability;
pub mod output;
pub mod parameters;
pub mod samples;
pub mod solve;
pub mod weave;

pub use identifiability::FlatDirection;
pub use parameters::{FreeParameter, LikeFabric, Parametrisation, perturbed};
pub use samples::{Sample, SampleError, Samples, load_samples, parse_samples};
pub use solve::{FitError, FitOptions, FitReport, Progress, ResidualScale, fit};
