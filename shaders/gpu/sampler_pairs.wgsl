// Compute entry points over the fabric sampler (shaders/sampling/fabric_sampler.wgsl), one
// invocation per pair, with the buffers of `clothbake::gpu::run_pairs` (as
// gpu/eval_pairs.wgsl): `sample_draws_main` reads (wo, u) and writes (wi, pdf) as
// `sampling_sample`; `sample_pdf_main` reads (wo, wi) and writes (pdf, 0, 0, 0). For tests
// and measurements (src/gpu/sampler.rs).
//
// requires: sampling/fabric_sampler

@group(0) @binding(0) var<storage, read> sampling_data: array<f32>;
@group(1) @binding(0) var<storage, read> eval_pairs: array<vec4<f32>>;
@group(1) @binding(1) var<storage, read_write> eval_results: array<vec4<f32>>;

@compute @workgroup_size(64)
fn sample_draws_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let k = id.x;
    if k >= arrayLength(&eval_results) {
        return;
    }
    eval_results[k] = sampling_sample(eval_pairs[2u * k].xyz, eval_pairs[2u * k + 1u].xyz);
}

@compute @workgroup_size(64)
fn sample_pdf_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let k = id.x;
    if k >= arrayLength(&eval_results) {
        return;
    }
    eval_results[k] = vec4<f32>(sampling_pdf(eval_pairs[2u * k].xyz, eval_pairs[2u * k + 1u].xyz), 0.0, 0.0, 0.0);
}
