// Constant F = 1/π above the horizon (`GpuConstant`, gpu.rs beside this file): the frame cost floor.
fn cloth_brdf(wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    if wi.z <= 0.0 || wo.z <= 0.0 {
        return vec3<f32>(0.0);
    }
    return vec3<f32>(0.31830987);
}
