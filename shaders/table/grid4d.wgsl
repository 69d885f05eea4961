// Layout grid4d: the lookup of src/table/grid4d.rs (module doc and `lookup_terms`,
// src/table/octahedral.rs), after shaders/table/lookup.wgsl. Texture arrangement:
// `grid4d::textures`. The generated `table_constants` define `CLOTH_GRID_N` (u32, N).
//
// requires: table/lookup, table_constants

@group(CLOTH_BRDF_GROUP) @binding(7) var cloth_grid4d_table: texture_2d_array<f32>;

// `octahedral::encode`: texture coordinates in [0, 1]² of a direction with w.z ≥ 0.
fn cloth_octahedral_encode(w: vec3<f32>) -> vec2<f32> {
    let p = w.xy / (abs(w.x) + abs(w.y) + abs(w.z));
    return (vec2<f32>(p.x + p.y, p.x - p.y) + 1.0) * 0.5;
}

// `grid4d::lookup_terms`: bilinear over wo by hardware filtering within a layer (texture
// coordinate = the octahedral coordinate, texel centres at (i + ½)/N, clamp-to-edge), and a
// manual bilinear blend of the 4 layers around wi with indices clamped to [0, N−1].
fn cloth_grid4d_terms(wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    let n = CLOTH_GRID_N;
    let ci = cloth_octahedral_encode(wi) * f32(n) - 0.5;
    let fl = floor(ci);
    let f = ci - fl;
    let last = i32(n) - 1;
    let x0 = u32(clamp(i32(fl.x), 0, last));
    let x1 = u32(clamp(i32(fl.x) + 1, 0, last));
    let y0 = u32(clamp(i32(fl.y), 0, last));
    let y1 = u32(clamp(i32(fl.y) + 1, 0, last));
    let uv = cloth_octahedral_encode(wo);
    let s00 = textureSampleLevel(cloth_grid4d_table, cloth_sampler, uv, x0 + n * y0, 0.0).xyz;
    let s10 = textureSampleLevel(cloth_grid4d_table, cloth_sampler, uv, x1 + n * y0, 0.0).xyz;
    let s01 = textureSampleLevel(cloth_grid4d_table, cloth_sampler, uv, x0 + n * y1, 0.0).xyz;
    let s11 = textureSampleLevel(cloth_grid4d_table, cloth_sampler, uv, x1 + n * y1, 0.0).xyz;
    return mix(mix(s00, s10, f.x), mix(s01, s11, f.x), f.y);
}

// F(wi, wo) by a grid4d table; 0 below the horizon.
fn cloth_grid4d_brdf(wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    if wi.z <= 0.0 || wo.z <= 0.0 {
        return vec3<f32>(0.0);
    }
    return cloth_combine(cloth_grid4d_terms(wi, wo));
}
