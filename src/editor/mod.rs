//! The fabric editor behind `clothbake view --edit`, without window or GPU: the edited
//! fabric and its history ([`session`]), its fields as data ([`fields`]), the actions a
//! panel or a script applies ([`script`]), the pictures of F ([`plots`]) and the bake that
//! runs behind the edits ([`background`]). The viewer draws it (`src/viewer/edit/`);
//! everything here is usable and tested headless.

pub mod background;
pub mod fields;
pub mod plots;
pub mod script;
pub mod session;
