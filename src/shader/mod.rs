//! The one WGSL composer: every shader the crate makes (a table's lookup, the GPU evaluators,
//! the renderer, the GPU sampler, the pair kernels, the Bevy material) is assembled here from
//! named modules.
//!
//! - **Files**: [`FILES`] registers each file of `shaders/` under its path there without
//!   `.wgsl` (`table/lookup`, `model/tangent_sample`, ...): the modules several units share.
//!   An evaluator's own WGSL lives in its folder beside its Rust (`src/evaluator/<name>/`) as
//!   a [`ShaderFile`] constant that its GPU form adds with [`Composer::unit_file`], so that a
//!   new evaluator touches no list here.
//! - **Generated modules**: text a caller generates (a table's constants, the resonant rules,
//!   the sampler's constants, a `GpuBrdf`'s whole WGSL, ...) is added to a [`Composer`] under
//!   a name without a `/` ([`Composer::module`]), and files require it by that name. The names
//!   in use are the `pub const`s of this module ([`BRDF`], [`TABLE_CONSTANTS`], ...).
//! - **Requirements**: a module names what it needs in its header, the leading run of `//`
//!   lines, in a line `// requires: a, b` (one or more such lines; names of files or of
//!   generated modules). A module that needs nothing has no such line. [`Composer::compose`]
//!   resolves the requirements of its roots transitively and writes each module once, every
//!   module after the modules it requires (depth first, in the order the requirements are
//!   listed); a cycle or a name that is neither registered nor added is a [`ComposeError`].
//!   WGSL itself does not care about the order of module-scope declarations: the order only
//!   makes the text readable.
//! - **The BRDF's bind group**: a `GpuBrdf` has its bindings in group 0 (`clothbake::gpu`),
//!   an engine's material may want another group (Bevy's `#{MATERIAL_BIND_GROUP}`). WGSL's
//!   `@group(...)` does take a const-expression in the specification (and in naga 30), but
//!   the composed text is also read by older WGSL front ends and by Bevy's preprocessor,
//!   which want a number or its own `#{...}` there. So the modules of a BRDF write their
//!   bindings as `@group(CLOTH_BRDF_GROUP)` ([`BRDF_GROUP_PLACEHOLDER`]), and
//!   [`Composer::compose`], when it writes the modules, replaces exactly that attribute by
//!   `@group(G)` with G as [`Composer::brdf_group`] sets it (0 unless set). This is the one
//!   textual substitution of the composer: no other text is searched or replaced, and the
//!   composed text holds no placeholder.

use std::collections::HashMap;
use std::fmt;

/// One WGSL file: a registered file of `shaders/` or a unit's own.
#[derive(Clone, Copy, Debug)]
pub struct ShaderFile {
    /// The name modules require it by: for a file of `shaders/` its path there without
    /// `.wgsl`, for a unit's file `<unit folder>/<name>` (`evaluator/paper`).
    pub name: &'static str,
    /// Its path in the repository, written above it in composed text.
    pub path: &'static str,
    pub source: &'static str,
}

macro_rules! shader_files {
    ($($name:literal),* $(,)?) => {
        /// Every WGSL file of `shaders/`, by name (see the module doc).
        pub const FILES: &[ShaderFile] = &[$(ShaderFile {
            name: $name,
            path: concat!("shaders/", $name, ".wgsl"),
            source: include_str!(concat!("../../shaders/", $name, ".wgsl")),
        }),*];
    };
}

shader_files![
    // The model in f32: one tangent sample of a thread, the resonant quadrature.
    "model/tangent_sample",
    // Table lookups: the part every layout shares, a thread tabulated in its resonant frame
    // (each layout's own file is its unit's, `LayoutUnit::wgsl_file`).
    "table/lookup",
    "table/thread_geometry",
    // Kernels over any BRDF or the sampler (src/gpu/).
    "gpu/eval_pairs",
    "gpu/sampler_pairs",
    "gpu/tap_pairs",
    "gpu/source_disk_pairs",
    // The fabric sampler and the environment light's taps (src/sampling/).
    "sampling/grid",
    "sampling/fabric_sampler",
    "sampling/sample_taps",
    // Distant light: a bright source set by the horizon (src/lighting/bright_sources.rs).
    "lighting/source_disk",
    // The render pass (src/render/renderer.rs).
    "render/renderer",
];

/// The generated module that defines `fn cloth_brdf(wi, wo)`: a `GpuBrdf`'s whole WGSL, or
/// the wrapper of a table's lookup ([`crate::table::wgsl::lookup_composer`]).
pub const BRDF: &str = "brdf";
/// A table lookup's generated constants: the thread albedos and the layout's
/// `TableLookup::wgsl_constants`.
pub const TABLE_CONSTANTS: &str = "table_constants";
/// The resonant quadrature's rules: `crate::evaluator::resonant::kernel::resonant_rules_wgsl`.
pub const RESONANT_RULES: &str = "resonant_rules";
/// The resonant quadrature's fabric block layout: its capacity in curve pieces
/// (`crate::evaluator::resonant::kernel::fabric_layout_wgsl`; the fabric is in a buffer).
pub const RESONANT_FABRIC: &str = "resonant_fabric";
/// The fabric sampler's layout constants: [`crate::sampling::Sampler::wgsl_constants`].
pub const SAMPLER_CONSTANTS: &str = "sampler_constants";

/// The attribute that a BRDF's modules write for their bind group (see the module doc).
pub const BRDF_GROUP_PLACEHOLDER: &str = "@group(CLOTH_BRDF_GROUP)";

/// The registered file `name`, if any.
pub fn file(name: &str) -> Option<&'static ShaderFile> {
    FILES.iter().find(|f| f.name == name)
}

/// Why a composition failed.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum ComposeError {
    /// A root or a requirement names no registered file and no added module.
    #[error("unknown WGSL module '{name}'{}", required_by.as_ref().map_or(String::new(), |by| format!(" (required by '{by}')")))]
    Unknown {
        name: String,
        required_by: Option<String>,
    },
    /// Modules require each other in a circle: `path` from the first back to it.
    #[error("WGSL modules require each other in a cycle: {}", path.join(" -> "))]
    Cycle { path: Vec<String> },
    /// A generated module added under a name already taken (by a file or an earlier module).
    #[error("WGSL module '{name}' is defined twice")]
    Duplicate { name: String },
}

/// The names that `source`'s header requires (see the module doc): the comma- or
/// space-separated names of its `// requires:` lines, in order.
pub fn requirements(source: &str) -> Vec<&str> {
    source
        .lines()
        .map(str::trim_start)
        .take_while(|line| line.starts_with("//"))
        .filter_map(|line| {
            line.strip_prefix("//")?
                .trim_start()
                .strip_prefix("requires:")
        })
        .flat_map(|names| names.split([',', ' ']).filter(|n| !n.is_empty()))
        .collect()
}

/// A set of generated modules over the registered files, and the choices of one composition.
#[derive(Clone, Debug)]
pub struct Composer {
    unit_files: Vec<&'static ShaderFile>,
    generated: Vec<(String, String)>,
    brdf_group: String,
    title: Vec<String>,
    error: Option<ComposeError>,
}

impl Default for Composer {
    fn default() -> Self {
        Self::new()
    }
}

impl Composer {
    /// The registered files only, the BRDF in group 0.
    pub fn new() -> Self {
        Self {
            unit_files: Vec::new(),
            generated: Vec::new(),
            brdf_group: "0".into(),
            title: Vec::new(),
            error: None,
        }
    }

    /// Adds the generated module `name` (no `/`), whose header may require others like a
    /// file's. A name already taken is reported by [`Self::compose`].
    pub fn module(mut self, name: impl Into<String>, source: impl Into<String>) -> Self {
        let name = name.into();
        self.check_free(&name);
        self.generated.push((name, source.into()));
        self
    }

    /// Adds a unit's own file (see the module doc). A name already taken is reported by
    /// [`Self::compose`].
    pub fn unit_file(mut self, file: &'static ShaderFile) -> Self {
        self.check_free(file.name);
        self.unit_files.push(file);
        self
    }

    /// Records a [`ComposeError::Duplicate`] if `name` is taken.
    fn check_free(&mut self, name: &str) {
        if self.error.is_none() && self.lookup(name).is_some() {
            self.error = Some(ComposeError::Duplicate {
                name: name.to_string(),
            });
        }
    }

    /// The bind group that [`BRDF_GROUP_PLACEHOLDER`] becomes: a number, or an engine's
    /// placeholder such as Bevy's `#{MATERIAL_BIND_GROUP}`.
    pub fn brdf_group(mut self, group: impl fmt::Display) -> Self {
        self.brdf_group = group.to_string();
        self
    }

    /// A comment line (without `// `) written at the top of the composed text.
    pub fn title(mut self, line: impl Into<String>) -> Self {
        self.title.push(line.into());
        self
    }

    fn generated(&self, name: &str) -> Option<&str> {
        self.generated
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, s)| s.as_str())
    }

    /// The source of module `name` and the label it is written under.
    fn lookup(&self, name: &str) -> Option<(String, &str)> {
        if let Some(f) =
            file(name).or_else(|| self.unit_files.iter().copied().find(|f| f.name == name))
        {
            Some((f.path.to_string(), f.source))
        } else {
            self.generated(name)
                .map(|s| (format!("{name} (generated)"), s))
        }
    }

    /// The modules that `roots` need, each once, every module after those it requires.
    pub fn order(&self, roots: &[&str]) -> Result<Vec<String>, ComposeError> {
        if let Some(e) = &self.error {
            return Err(e.clone());
        }
        #[derive(Clone, Copy, PartialEq)]
        enum State {
            Visiting,
            Done,
        }
        fn visit(
            composer: &Composer,
            name: &str,
            required_by: Option<&str>,
            state: &mut HashMap<String, State>,
            stack: &mut Vec<String>,
            out: &mut Vec<String>,
        ) -> Result<(), ComposeError> {
            match state.get(name) {
                Some(State::Done) => return Ok(()),
                Some(State::Visiting) => {
                    let start = stack.iter().position(|n| n == name).unwrap_or(0);
                    let mut path = stack[start..].to_vec();
                    path.push(name.to_string());
                    return Err(ComposeError::Cycle { path });
                }
                None => {}
            }
            let (_, source) = composer.lookup(name).ok_or_else(|| ComposeError::Unknown {
                name: name.to_string(),
                required_by: required_by.map(str::to_string),
            })?;
            state.insert(name.to_string(), State::Visiting);
            stack.push(name.to_string());
            for required in requirements(source) {
                visit(composer, required, Some(name), state, stack, out)?;
            }
            stack.pop();
            state.insert(name.to_string(), State::Done);
            out.push(name.to_string());
            Ok(())
        }
        let mut state = HashMap::new();
        let mut stack = Vec::new();
        let mut out = Vec::new();
        for root in roots {
            visit(self, root, None, &mut state, &mut stack, &mut out)?;
        }
        Ok(out)
    }

    /// The WGSL of `roots` and everything they require (see the module doc): the title, a line
    /// naming the modules in order, then each module under a comment naming it, with
    /// [`BRDF_GROUP_PLACEHOLDER`] bound.
    pub fn compose(&self, roots: &[&str]) -> Result<String, ComposeError> {
        let order = self.order(roots)?;
        let mut out = String::new();
        for line in &self.title {
            out += "// ";
            out += line;
            out.push('\n');
        }
        out += "// Composed by clothbake::shader: ";
        out += &order.join(", ");
        out += ".\n";
        let group = format!("@group({})", self.brdf_group);
        for name in &order {
            let (label, source) = self.lookup(name).expect("ordered modules exist");
            out += "\n// ---- ";
            out += &label;
            out += " ----\n";
            out += &source.replace(BRDF_GROUP_PLACEHOLDER, &group);
            if !source.ends_with('\n') {
                out.push('\n');
            }
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests;
