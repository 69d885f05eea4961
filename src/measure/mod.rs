//! Measuring a table or an evaluator against the direct evaluation of the model: the seeded
//! direction pairs errors are measured on, and the error statistics themselves.

pub mod accuracy;
pub mod direction_sets;
