//! Fitting a fabric to measured samples of F (being written).
