// Evaluates `cloth_brdf` (defined by the generated module `brdf`: a GpuBrdf's WGSL, all of
// whose bindings are in @group(0), or a table's lookup) for a list of direction pairs, one per invocation:
// `eval_pairs[2k]` = wi, `eval_pairs[2k + 1]` = wo (xyz, unit, local cloth frame),
// `eval_results[k]` = F(wi, wo) (rgb, a = 0). See `evaluate_pairs` in src/gpu/mod.rs and
// src/table/shader_language.rs.
//
// requires: brdf

@group(1) @binding(0) var<storage, read> eval_pairs: array<vec4<f32>>;
@group(1) @binding(1) var<storage, read_write> eval_results: array<vec4<f32>>;

@compute @workgroup_size(64)
fn eval_pairs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let k = id.x;
    if k >= arrayLength(&eval_results) {
        return;
    }
    let wi = eval_pairs[2u * k].xyz;
    let wo = eval_pairs[2u * k + 1u].xyz;
    eval_results[k] = vec4<f32>(cloth_brdf(wi, wo), 0.0);
}
