// Compute entry point over `source_disk_above_horizon` (shaders/lighting/source_disk.wgsl),
// one invocation per request, with the buffers of `clothbake::gpu::run_pairs`: each request
// is (wi, (sin radius, 0, 0)); the result is (centroid direction, visible fraction). For the
// twin test of `clothbake::lighting::disk_above_horizon` (src/gpu/mod.rs).
//
// requires: lighting/source_disk

@group(1) @binding(0) var<storage, read> eval_pairs: array<vec4<f32>>;
@group(1) @binding(1) var<storage, read_write> eval_results: array<vec4<f32>>;

@compute @workgroup_size(64)
fn source_disk_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let k = id.x;
    if k >= arrayLength(&eval_results) {
        return;
    }
    eval_results[k] = source_disk_above_horizon(eval_pairs[2u * k].xyz, eval_pairs[2u * k + 1u].x);
}
