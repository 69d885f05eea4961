//! The editing panel of `clothbake view --edit` (egui), over the drape: what it shows of the
//! fabric being edited ([`editor`]), its widgets ([`panel`]) and plots ([`plots_ui`]), and
//! egui's input and painting ([`overlay`]). The fabric, its history and the script language
//! are the window-free [`crate::editor`].

pub mod editor;
pub mod overlay;
pub mod panel;
pub mod plots_ui;
