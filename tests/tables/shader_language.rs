//! The lookup in other shading languages (`clothbake wgsl --lang`, src/table/shader_language.rs):
//! for every layout and two fabrics, the GLSL and HLSL translations compile with an
//! independent compiler, Khronos' glslangValidator (GLSL 4.50 and HLSL compute shaders to
//! Vulkan SPIR-V; CI installs Debian's glslang-tools), and the MSL translation declares the
//! lookup and its kernel (there is no Metal compiler on Linux).

use crate::common::*;

use clothbake::bake::bake;
use clothbake::table::Layout;
use clothbake::table::shader_language::{KERNEL_ENTRY, ShaderLanguage, lookup_shader};
use std::process::Command;

/// Runs glslangValidator on `file` with `args`; its output when it fails.
fn glslang(args: &[&str]) -> Result<(), String> {
    let output = Command::new("glslangValidator")
        .args(args)
        .output()
        .map_err(|e| {
            format!(
                "this test needs glslangValidator ({e}); on Debian: apt-get install glslang-tools \
             (scripts/setup.sh installs it)"
            )
        })?;
    if output.status.success() {
        Ok(())
    } else {
        Err(output_text(&output))
    }
}

#[test]
fn translations_compile_with_glslang_for_every_layout() {
    let dir = temp_dir("shader-language");
    let mut failures = Vec::new();
    for &layout in Layout::ALL {
        for name in ["polyester_satin_charmeuse", "velvet"] {
            let resolution = layout.resolution_ladder()[0];
            let table = bake(&fabric(name), layout, resolution, &|| {}).unwrap();
            let stem = dir.join(format!("{}-{name}", layout.name()));
            let glsl = stem.with_extension("comp");
            std::fs::write(&glsl, lookup_shader(&table, ShaderLanguage::Glsl).unwrap()).unwrap();
            let spv = stem.with_extension("spv");
            if let Err(e) = glslang(&["-V", path_str(&glsl), "-o", path_str(&spv)]) {
                failures.push(format!("{} GLSL: {e}", glsl.display()));
            }
            let hlsl = stem.with_extension("hlsl");
            std::fs::write(&hlsl, lookup_shader(&table, ShaderLanguage::Hlsl).unwrap()).unwrap();
            let args = [
                "-D",
                "-V",
                "-S",
                "comp",
                "-e",
                KERNEL_ENTRY,
                path_str(&hlsl),
                "-o",
                path_str(&spv),
            ];
            if let Err(e) = glslang(&args) {
                failures.push(format!("{} HLSL: {e}", hlsl.display()));
            }
            let msl = lookup_shader(&table, ShaderLanguage::Msl).unwrap();
            for declaration in ["cloth_brdf(", &format!("kernel void {KERNEL_ENTRY}(")] {
                if !msl.contains(declaration) {
                    failures.push(format!(
                        "{} {name} MSL lacks `{declaration}`",
                        layout.name()
                    ));
                }
            }
            println!(
                "{} {name}: GLSL, HLSL compiled by glslangValidator; MSL declares the lookup",
                layout.name()
            );
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

#[test]
fn unknown_languages_are_refused() {
    assert_eq!("hlsl".parse::<ShaderLanguage>(), Ok(ShaderLanguage::Hlsl));
    let error = "spirv".parse::<ShaderLanguage>().unwrap_err().to_string();
    assert!(error.contains("spirv") && error.contains("glsl"), "{error}");
}
