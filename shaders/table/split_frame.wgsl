// Layout split_frame: the lookup of src/table/split_frame/ (module doc,
// `Geometry::terms`), after shaders/table/lookup.wgsl, shaders/table/thread_geometry.wgsl
// (the sloped segments' tables) and shaders/model/tangent_sample.wgsl (one tangent sample,
// for the point masses).
//
// requires: table/lookup, table/thread_geometry, model/tangent_sample,
// requires: table_constants
//
// The generated `table_constants` define `CLOTH_COVERAGE` (vec3<f32>: a1, a2, gap),
// `CLOTH_COS2_D_FLOOR` (the floor under cos²θd' that the reflection is divided by) and per
// thread J (`Geometry::thread_wgsl`): its point masses `CLOTH_SPLIT_POINT_COUNTJ` (u32) and
// `cloth_split_point_massesJ(pair, material)` (the sum of `cloth_split_point` over its masses,
// written out with the masses as literals), `cloth_split_materialJ()` (ClothSampleMaterial), its axes `CLOTH_SPLIT_T0_J`,
// `CLOTH_SPLIT_BJ`, and its sloped part: `CLOTH_SPLIT_SLOPEDJ` (bool), its share
// `CLOTH_SPLIT_SLOPED_SHAREJ` (w_c) and its table `cloth_split_slopesJ()` (ClothThreadTable).
// Branches on these constants are folded by the shader compiler. Struct and array values are
// functions returning a literal, not module-scope constants: glslang's HLSL front end reads
// two constants of one such type, as naga's HLSL writes them, as a recursion.

// The sloped tables of threads 1 and 2 (a one-texel stand-in for a thread without one) and
// their ⟨P⟩, one layer per tabulated thread (a stand-in where there is none).
@group(CLOTH_BRDF_GROUP) @binding(4) var cloth_split_table1: texture_3d<f32>;
@group(CLOTH_BRDF_GROUP) @binding(5) var cloth_split_table2: texture_3d<f32>;
@group(CLOTH_BRDF_GROUP) @binding(6) var cloth_split_masking: texture_2d_array<f32>;

// What a thread without sloped segments has for a table: never read.
fn cloth_split_no_table() -> ClothThreadTable {
    let no_axis = ClothAxis(0u, vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0), 0.0);
    return ClothThreadTable(
        false,
        array<ClothAxis, 4>(no_axis, no_axis, no_axis, no_axis),
        vec4<f32>(0.0),
        no_axis,
        0.0,
        0i,
    );
}

// One point mass `point` = (cos α_k, sin α_k, w_k) of a thread as its sums add it
// (`ThreadModel::point_sums`): w_k·(R_k, T_k, P_k).
fn cloth_split_point(pair: ClothSamplePair, material: ClothSampleMaterial, point: vec3<f32>) -> vec3<f32> {
    let s = cloth_sample_terms(pair, material, point.x, point.y);
    return point.z * vec3<f32>(s.y, s.z + s.w, s.x);
}

// The sloped part of a thread's sums from its table's sample `c` (reflection, transmission,
// ⟨P⟩_c, cos²θd') and share `share` = w_c: reflection divided by cos²θd', as in thread_frame.
fn cloth_split_sloped(c: vec4<f32>, share: f32) -> vec3<f32> {
    let p = share * c.z;
    return vec3<f32>(c.x * p / max(c.w, CLOTH_COS2_D_FLOOR), c.y * p, p);
}

// `Geometry::thread_sums` of thread 1: (reflection, transmission, ⟨P⟩) of its curve.
fn cloth_split_thread1(wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    var sums = vec3<f32>(0.0);
    if CLOTH_SPLIT_POINT_COUNT1 > 0u {
        let material = cloth_split_material1();
        let pair = cloth_sample_pair(wi, wo, CLOTH_SPLIT_T0_1, CLOTH_SPLIT_B1, material.k_u);
        if pair.par_i > material.threshold && pair.par_o > material.threshold {
            sums += cloth_split_point_masses1(pair, material);
        }
    }
    if CLOTH_SPLIT_SLOPED1 {
        let c = cloth_thread_sample(cloth_split_table1, cloth_split_masking, cloth_split_slopes1(), wi, wo);
        sums += cloth_split_sloped(c, CLOTH_SPLIT_SLOPED_SHARE1);
    }
    return sums;
}

// `Geometry::thread_sums` of thread 2, as of thread 1.
fn cloth_split_thread2(wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    var sums = vec3<f32>(0.0);
    if CLOTH_SPLIT_POINT_COUNT2 > 0u {
        let material = cloth_split_material2();
        let pair = cloth_sample_pair(wi, wo, CLOTH_SPLIT_T0_2, CLOTH_SPLIT_B2, material.k_u);
        if pair.par_i > material.threshold && pair.par_o > material.threshold {
            sums += cloth_split_point_masses2(pair, material);
        }
    }
    if CLOTH_SPLIT_SLOPED2 {
        let c = cloth_thread_sample(cloth_split_table2, cloth_split_masking, cloth_split_slopes2(), wi, wo);
        sums += cloth_split_sloped(c, CLOTH_SPLIT_SLOPED_SHARE2);
    }
    return sums;
}

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
