//! Weaves: a fabric of the model made from a weave draft (docs/weave.md). The draft
//! ([`draft`]) gives each family's face fraction and floats; the yarn knobs turn them into
//! coverages and tangent curves. Pure maths, no I/O: WIF files are read by
//! [`crate::formats::wif`].

pub mod draft;

pub use draft::{Draft, DraftError, Family, NamedWeave, Yarns};
