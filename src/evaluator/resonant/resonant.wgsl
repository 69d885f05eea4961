// The resonant quadrature's `cloth_brdf` (gpu.rs beside this file), after the kernel
// quadrature.wgsl and the generated module `resonant_fabric`: the
// constants `CLOTH_RESONANT_COVERAGE`, `CLOTH_RESONANT_GAP` and `CLOTH_RESONANT_ALBEDO_0/1`
// and the functions `cloth_resonant_means_0/1`; the kernel is its own file, apart from this
// `cloth_brdf`.
//
// requires: evaluator/resonant_quadrature, resonant_fabric

// `Patch::eval`: F = [a1⟨s⟩1 + a2⟨s⟩2]/Q, Q = a1⟨P⟩1 + a2⟨P⟩2 + gap·wo.z; 0 below the
// horizon and where Q = 0.
fn cloth_brdf(wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    if wi.z <= 0.0 || wo.z <= 0.0 {
        return vec3<f32>(0.0);
    }
    let m1 = cloth_resonant_means_0(wi, wo);
    let m2 = cloth_resonant_means_1(wi, wo);
    let a1 = CLOTH_RESONANT_COVERAGE.x;
    let a2 = CLOTH_RESONANT_COVERAGE.y;
    let q = a1 * m1.z + a2 * m2.z + CLOTH_RESONANT_GAP * wo.z;
    if q <= 0.0 {
        return vec3<f32>(0.0);
    }
    return vec3<f32>((a1 * m1.x + a2 * m2.x) / q) + CLOTH_RESONANT_ALBEDO_0 * (a1 * m1.y / q)
        + CLOTH_RESONANT_ALBEDO_1 * (a2 * m2.y / q);
}
