// Compute entry points over the environment light's sample taps
// (shaders/sampling/sample_taps.wgsl), one invocation per request, with the buffers of
// `clothbake::gpu::run_pairs`: each request is (wo, (k, K, 0)); `tap_draws_main`
// writes the picked tap's (wi, solid angle), `tap_weights_main` its (weight, 0). For tests
// (src/gpu/sampler.rs).
//
// requires: sampling/sample_taps

@group(0) @binding(0) var<storage, read> sampling_taps: array<vec4<u32>>;
@group(1) @binding(0) var<storage, read> eval_pairs: array<vec4<f32>>;
@group(1) @binding(1) var<storage, read_write> eval_results: array<vec4<f32>>;

fn tap_request(k: u32) -> SamplingTap {
    let wo = eval_pairs[2u * k].xyz;
    let numbers = eval_pairs[2u * k + 1u];
    return sampling_tap(sampling_tap_nodes(wo), u32(numbers.x), u32(numbers.y));
}

@compute @workgroup_size(64)
fn tap_draws_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let k = id.x;
    if k >= arrayLength(&eval_results) {
        return;
    }
    let tap = tap_request(k);
    eval_results[k] = vec4<f32>(tap.wi, tap.log2_solid_angle);
}

@compute @workgroup_size(64)
fn tap_weights_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let k = id.x;
    if k >= arrayLength(&eval_results) {
        return;
    }
    eval_results[k] = vec4<f32>(tap_request(k).weight, 0.0);
}
