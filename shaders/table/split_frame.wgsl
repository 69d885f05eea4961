// Layout split_frame: the lookup of src/table/split_frame/ (module doc,
// `Geometry::terms`), after shaders/table/lookup.wgsl, shaders/table/thread_geometry.wgsl
// (the sloped segments' tables) and shaders/model/tangent_sample.wgsl (one tangent sample,
// for the point masses).
//
// requires: table/lookup, table/thread_geometry, model/tangent_sample,
// requires: table_constants
//
// The generated `table_constants` declare the textures of the threads that have sloped
// segments and define `CLOTH_COVERAGE` (vec3<f32>: a1, a2, gap) and
// `cloth_split_thread1(wi, wo)`, `cloth_split_thread2(wi, wo)` -> vec3<f32>: the thread's
// curve sums (reflection, transmission, ⟨P⟩), the point masses by `cloth_sample_terms` and
// the sloped part by its table.

// `Geometry::terms`: (reflection, transmission1, transmission2), divided by Q.
fn cloth_split_frame_terms(wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    let s1 = cloth_split_thread1(wi, wo);
    let s2 = cloth_split_thread2(wi, wo);
    let a = CLOTH_COVERAGE;
    let q = a.z * wo.z + a.x * s1.z + a.y * s2.z;
    if q <= 0.0 {
        return vec3<f32>(0.0);
    }
    return vec3<f32>(a.x * s1.x + a.y * s2.x, a.x * s1.y, a.y * s2.y) / q;
}

// F(wi, wo) by a split_frame table; 0 below the horizon.
fn cloth_split_frame_brdf(wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    if wi.z <= 0.0 || wo.z <= 0.0 {
        return vec3<f32>(0.0);
    }
    return cloth_combine(cloth_split_frame_terms(wi, wo));
}
