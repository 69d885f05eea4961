// Layout thread_frame: the lookup of src/table/thread_frame.rs (module doc,
// `Geometry::lookup_terms`), after shaders/table/lookup.wgsl and
// shaders/table/thread_geometry.wgsl (each thread's coordinates and interpolation). Texture
// arrangement: `thread_frame::textures`.
//
// requires: table/lookup, table/thread_geometry, table_constants
//
// The generated `table_constants` define `CLOTH_COVERAGE` (vec3<f32>: a1, a2, gap),
// `CLOTH_COS2_D_FLOOR` (the floor under cos²θd' that the reflection is divided by) and
// `cloth_thread1_axes()`, `cloth_thread2_axes()` (`ClothThreadTable` values: each thread's
// table, ⟨P⟩ in layer j − 1 of the masking texture).

@group(CLOTH_BRDF_GROUP) @binding(4) var cloth_thread1_table: texture_3d<f32>;
@group(CLOTH_BRDF_GROUP) @binding(5) var cloth_thread2_table: texture_3d<f32>;
// ⟨P⟩ of thread j in layer j − 1: column βi, row βo.
@group(CLOTH_BRDF_GROUP) @binding(6) var cloth_masking_table: texture_2d_array<f32>;

// `Geometry::lookup_terms`: (reflection, transmission1, transmission2), divided by Q.
fn cloth_thread_frame_terms(wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    // `Geometry::sample_thread`: reflection, transmission, ⟨P⟩, cos²θd'.
    let t1 = cloth_thread_sample(cloth_thread1_table, cloth_masking_table, cloth_thread1_axes(), wi, wo);
    let t2 = cloth_thread_sample(cloth_thread2_table, cloth_masking_table, cloth_thread2_axes(), wi, wo);
    let a = CLOTH_COVERAGE;
    let reflection = a.x * t1.x * t1.z / max(t1.w, CLOTH_COS2_D_FLOOR)
        + a.y * t2.x * t2.z / max(t2.w, CLOTH_COS2_D_FLOOR);
    let transmission = vec2<f32>(a.x * t1.y * t1.z, a.y * t2.y * t2.z);
    let q = a.z * wo.z + a.x * t1.z + a.y * t2.z;
    if q <= 0.0 {
        return vec3<f32>(0.0);
    }
    return vec3<f32>(reflection, transmission) / q;
}

// F(wi, wo) by a thread_frame table; 0 below the horizon.
fn cloth_thread_frame_brdf(wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    if wi.z <= 0.0 || wo.z <= 0.0 {
        return vec3<f32>(0.0);
    }
    return cloth_combine(cloth_thread_frame_terms(wi, wo));
}
