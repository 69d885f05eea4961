//! The editing panel of `clothbake view --edit` (egui), over the drape.

pub mod overlay;
pub mod plots_ui;
