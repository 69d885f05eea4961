//! Fitting a fabric to measured samples of F (issue 46): the samples
//! ([`samples`]: JSON lines of `wi`, `wo`, `f`, as untrusted input), what the fit may change
//! ([`parameters`]: a [`Parametrisation`] from bounded free parameters to valid fabrics, e.g.
//! [`LikeFabric`], the parameters of a given fabric with its structure kept), and the
//! bounded least-squares solve with its report ([`solve`]: Levenberg–Marquardt on the
//! resonant quadrature, figures by the direct rule, the directions the samples leave
//! unconstrained). `clothbake fit` (src/cli/fit.rs) is the command over it.

pub mod parameters;
pub mod samples;
pub mod solve;

pub use parameters::{FreeParameter, LikeFabric, Parametrisation, perturbed};
pub use samples::{Sample, SampleError, Samples, load_samples, parse_samples};
pub use solve::{FitError, FitOptions, FitReport, FlatDirection, Progress, ResidualScale, fit};

/// The refractive index of a named fibre, for `clothbake fit --fibre`.
///
/// TODO(lead): temporary; the fibre presets move to `crate::weave::fibre`.
pub fn fibre_eta(name: &str) -> Option<f64> {
    match name.to_ascii_lowercase().as_str() {
        "silk" => Some(1.345),
        "polyester" => Some(1.539),
        "linen" => Some(1.46),
        "cotton" => Some(1.55),
        "wool" => Some(1.55),
        "nylon" => Some(1.54),
        _ => None,
    }
}

/// The fibre names [`fibre_eta`] knows, for error messages.
pub const FIBRES: &[&str] = &["silk", "polyester", "linen", "cotton", "wool", "nylon"];
