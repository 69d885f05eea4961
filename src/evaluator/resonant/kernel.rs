//! The resonant quadrature's WGSL kernel (`quadrature.wgsl` in this folder)
//! specialised for a fabric: the rule's constants (the generated module
//! [`crate::shader::RESONANT_RULES`] that the kernel requires) and, per thread, `cloth_resonant_means_j(wi, wo)`, the thread's curve
//! means (⟨reflection⟩, ⟨transmission⟩, ⟨P⟩) of `ThreadModel::means` with
//! `Integration::Resonant(nodes)`, in f32.
//!
//! The resonant quadrature's shader ([`super::gpu`], which adds `cloth_brdf`) uses it; no
//! table lookup does.

use crate::model::Fabric;
use crate::model::curve::{Integration, curve_pieces};
use crate::model::fabric::ModelOptions;
use crate::model::resonant::{
    FLAT_LOBE_SPAN, GaussLegendre, LOBE_Z_RANGE, MIN_NODES_PER_PART, NEGLIGIBLE_LOBE_Z,
    SPLIT_TOLERANCE, TAIL_MASS,
};
use crate::model::{ResonantNodes, thread_axes};
use crate::table::wgsl::{degenerate_threshold, unit_area_gaussian, wgsl_f32, wgsl_vec};
use std::fmt::Write;

/// The rule's constants for the reweighting width σu of `options` and `nodes`: the
/// thresholds of `src/model/resonant.rs`, the node counts and the Gauss–Legendre rules they
/// can pick.
pub fn resonant_rules_wgsl(options: &ModelOptions, nodes: ResonantNodes) -> String {
    let mut out = String::new();
    let w = &mut out;
    let sigma_u = options.sigma_u_deg.to_radians();
    let consts = [
        ("CLOTH_RESONANT_K_U", (-0.5 / (sigma_u * sigma_u)) as f32),
        ("CLOTH_RESONANT_THRESHOLD", degenerate_threshold()),
        ("CLOTH_RESONANT_FLAT_LOBE_SPAN", FLAT_LOBE_SPAN as f32),
        ("CLOTH_RESONANT_NEGLIGIBLE_LOBE_Z", NEGLIGIBLE_LOBE_Z as f32),
        ("CLOTH_RESONANT_TAIL_MASS", TAIL_MASS as f32),
        ("CLOTH_RESONANT_LOBE_Z_RANGE", LOBE_Z_RANGE as f32),
        ("CLOTH_RESONANT_SPLIT_TOLERANCE", SPLIT_TOLERANCE as f32),
    ];
    for (name, value) in consts {
        let _ = writeln!(w, "const {name}: f32 = {};", wgsl_f32(value));
    }
    let _ = writeln!(
        w,
        "const CLOTH_RESONANT_MIN_NODES_PER_PART: u32 = {MIN_NODES_PER_PART}u;\n\
         const CLOTH_RESONANT_NODES: vec3<u32> = vec3<u32>({}u, {}u, {}u);",
        nodes.surface, nodes.volume, nodes.base
    );
    // The n-point rules for every count a part can get, n = 1..=max(surface, volume, base)
    // (`ResonantRule::rule`; tail rules and kink splits only lower a count), flattened: the
    // n-point rule starts at n(n − 1)/2.
    let max = nodes.surface.max(nodes.volume).max(nodes.base) as usize;
    let mut gl = Vec::new();
    for n in 1..=max {
        let rule = GaussLegendre::new(n);
        for (&x, &wt) in rule.nodes.iter().zip(&rule.weights) {
            gl.push(wgsl_vec(&[x as f32, wt as f32]));
        }
    }
    debug_assert_eq!(gl.len(), max * (max + 1) / 2);
    let _ = writeln!(
        w,
        "// Gauss–Legendre nodes on [0, 1] and weights (summing to 1 per rule), the n-point \
         rule at n(n − 1)/2, n = 1..={max}.\n\
         fn cloth_resonant_gl(k: u32) -> vec2<f32> {{\n    \
         let rules = array<vec2<f32>, {}>(\n        {});\n    \
         return rules[k];\n}}",
        gl.len(),
        gl.join(",\n        ")
    );
    out
}

/// `cloth_resonant_means_j(wi, wo)` of `fabric`'s thread `j`: the thread's parameters as a
/// `ClothResonantThread` literal, then its curve unrolled, one `cloth_resonant_point` per
/// flat piece and one `cloth_resonant_segment` per sloped one.
///
/// The literal is built inside the function, not as a module-scope constant: naga's HLSL
/// initialises a struct constant through a constructor function, and glslang's HLSL front
/// end reports two such constants as recursion (`clothbake wgsl --lang hlsl` of a table
/// whose lookup included this kernel failed to compile).
pub fn resonant_thread_wgsl(fabric: &Fabric, j: usize, nodes: ResonantNodes) -> String {
    let mut out = String::new();
    let w = &mut out;
    let options = fabric.options;
    let thread = fabric.threads()[j];
    let (t0, b) = thread_axes(j);
    let sigma_s = options.lobe_sigma_deg(thread.gamma_s_deg).to_radians();
    let sigma_v = options.lobe_sigma_deg(thread.gamma_v_deg).to_radians();
    let [ks, ps] = unit_area_gaussian(sigma_s);
    let [kv, pv] = unit_area_gaussian(sigma_v);
    let no_interface = if thread.eta == 1.0 { 1.0 } else { 0.0 };
    let _ = writeln!(
        w,
        "// `ThreadModel::means` of thread {}: (⟨reflection⟩, ⟨transmission⟩, ⟨P⟩).\n\
         fn cloth_resonant_means_{j}(wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {{\n    \
         let thread = ClothResonantThread({}, {}, {}, {}, {});\n    \
         let pair = cloth_resonant_pair(thread, wi, wo);\n    \
         var sums = vec3<f32>(0.0);\n    \
         if pair.valid == 0u {{\n        return sums;\n    }}",
        j + 1,
        wgsl_vec(&t0.to_array()),
        wgsl_vec(&b.to_array()),
        wgsl_vec(&[sigma_s as f32, sigma_v as f32]),
        wgsl_vec(&[ks, ps, kv, pv]),
        wgsl_vec(&[thread.eta as f32, thread.kd as f32, no_interface, 0.0])
    );
    for piece in curve_pieces(thread, &options, Integration::Resonant(nodes)) {
        if piece.start == piece.end {
            let _ = writeln!(
                w,
                "    sums += cloth_resonant_point(thread, pair, {}, {});",
                wgsl_f32(piece.start as f32),
                wgsl_f32(piece.weight as f32)
            );
        } else {
            // The density per radian in f64, as `ResonantRule::segment` forms it.
            let density = piece.weight / (piece.end - piece.start);
            let _ = writeln!(
                w,
                "    sums += cloth_resonant_segment(thread, pair, {}, {}, {});",
                wgsl_f32(piece.start as f32),
                wgsl_f32(piece.end as f32),
                wgsl_f32(density as f32)
            );
        }
    }
    let _ = writeln!(w, "    return sums;\n}}");
    out
}
