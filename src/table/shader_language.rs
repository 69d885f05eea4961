//! The specialised lookup of a table in other shading languages: GLSL, HLSL and MSL,
//! translated from its WGSL ([`super::wgsl::lookup_wgsl`]) by naga's back ends (the compiler
//! wgpu itself uses), for engines that do not speak WGSL (Unity and Unreal: HLSL; Godot and
//! three.js: GLSL; Metal: MSL).
//!
//! A shader language needs an entry point to translate anything, so the lookup is translated
//! together with a compute kernel, `eval_pairs_main` (shaders/gpu/eval_pairs.wgsl, composed
//! with the lookup by [`super::wgsl::lookup_composer`]): per
//! invocation k it evaluates `cloth_brdf(eval_pairs[2k], eval_pairs[2k + 1])` (wi, wo) into
//! `eval_results[k]`. Take `cloth_brdf` and the declarations it uses into your own shader;
//! the kernel evaluates the lookup for a list of pairs as it is. Bindings keep the WGSL's
//! group and binding: the table's textures and sampler in group 0 (see the layout), the
//! kernel's two buffers in group 1. GLSL (4.50 core) combines each texture with the
//! sampler it is used with into one `sampler3D`/`sampler2DArray` uniform, bound at the
//! texture's binding; HLSL (shader model 5.1) puts group g's binding b at register
//! `t`/`s`/`u`b in `space`g; MSL (2.4) uses the fake bindings of naga's `fake_missing_bindings`
//! (buffer, texture and sampler indices in declaration order).

use super::Table;
use super::wgsl::{LookupShaderOptions, lookup_composer, lookup_wgsl_with};
use std::fmt;

/// The registered module of the compute kernel translated with the lookup.
pub const KERNEL_MODULE: &str = "gpu/eval_pairs";
/// Its entry point.
pub const KERNEL_ENTRY: &str = "eval_pairs_main";

/// A shading language the lookup is available in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShaderLanguage {
    Wgsl,
    Glsl,
    Hlsl,
    Msl,
}

impl ShaderLanguage {
    /// Every language, WGSL first.
    pub const ALL: [Self; 4] = [Self::Wgsl, Self::Glsl, Self::Hlsl, Self::Msl];

    /// The name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Self::Wgsl => "wgsl",
            Self::Glsl => "glsl",
            Self::Hlsl => "hlsl",
            Self::Msl => "msl",
        }
    }
}

impl fmt::Display for ShaderLanguage {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for ShaderLanguage {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        Self::ALL
            .into_iter()
            .find(|l| l.name() == s)
            .ok_or_else(|| format!("unknown shading language '{s}' (wgsl, glsl, hlsl or msl)"))
    }
}

/// `table`'s specialised lookup in `language`: the WGSL of `clothbake wgsl` as it is, or its
/// translation with the pair kernel (see the module doc).
pub fn lookup_shader(
    table: &Table,
    language: ShaderLanguage,
    options: &LookupShaderOptions,
) -> Result<String, String> {
    if language == ShaderLanguage::Wgsl {
        return Ok(lookup_wgsl_with(table, options));
    }
    let source = lookup_composer(table, options)
        .compose(&[KERNEL_MODULE])
        .map_err(|e| e.to_string())?;
    let module = naga::front::wgsl::parse_str(&source).map_err(|e| {
        format!(
            "the generated WGSL does not parse: {}",
            e.emit_to_string(&source)
        )
    })?;
    let info = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(&module)
    .map_err(|e| format!("the generated WGSL does not validate: {e:?}"))?;
    let stage = naga::ShaderStage::Compute;
    let error = |e: &dyn fmt::Display| format!("cannot translate the lookup to {language}: {e}");
    match language {
        ShaderLanguage::Wgsl => unreachable!("returned above"),
        ShaderLanguage::Glsl => {
            // Each resource at its WGSL binding number: the groups' numbers do not collide
            // (group 0: the table, 3 and up; group 1: the kernel's 0 and 1).
            let binding_map = module
                .global_variables
                .iter()
                .filter_map(|(_, v)| v.binding)
                .map(|b| (b, b.binding as u8))
                .collect();
            let options = naga::back::glsl::Options {
                version: naga::back::glsl::Version::Desktop(450),
                writer_flags: naga::back::glsl::WriterFlags::empty(),
                binding_map,
                zero_initialize_workgroup_memory: true,
            };
            let pipeline = naga::back::glsl::PipelineOptions {
                shader_stage: stage,
                entry_point: KERNEL_ENTRY.to_string(),
                multiview: None,
            };
            let mut out = String::new();
            let mut writer = naga::back::glsl::Writer::new(
                &mut out,
                &module,
                &info,
                &options,
                &pipeline,
                naga::proc::BoundsCheckPolicies::default(),
            )
            .map_err(|e| error(&e))?;
            writer.write().map_err(|e| error(&e))?;
            Ok(out)
        }
        ShaderLanguage::Hlsl => {
            let options = naga::back::hlsl::Options::default();
            let pipeline = naga::back::hlsl::PipelineOptions {
                entry_point: Some((stage, KERNEL_ENTRY.to_string())),
            };
            let mut out = String::new();
            let mut writer = naga::back::hlsl::Writer::new(&mut out, &options, &pipeline);
            writer.write(&module, &info, None).map_err(|e| error(&e))?;
            Ok(out)
        }
        ShaderLanguage::Msl => {
            let options = naga::back::msl::Options {
                lang_version: (2, 4),
                ..Default::default()
            };
            let pipeline = naga::back::msl::PipelineOptions {
                entry_point: Some((stage, KERNEL_ENTRY.to_string())),
                ..Default::default()
            };
            naga::back::msl::write_string(&module, &info, &options, &pipeline)
                .map(|(text, _)| text)
                .map_err(|e| error(&e))
        }
    }
}
