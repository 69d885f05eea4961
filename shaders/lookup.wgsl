// Table lookup of F(wi, wo) (RGB) for both table layouts, mirroring the Rust lookup
// exactly (in f32):
// - axes and warps: src/table/axis.rs (`Warp::unit`, `Axis::locate`, texel convention);
// - thread_frame: src/table/thread_frame.rs module doc, `ThreadGeometry::coordinates`,
//   `Geometry::sample_thread`, `Geometry::lookup_terms`;
// - grid4d: src/table/grid4d.rs module doc and `lookup_terms`, src/table/octahedral.rs;
// - albedo combination: `Table::lookup` in src/table/mod.rs.
// Texture arrangement and the uniform block: src/gpu/layout.rs.
//
// No entry points and no `cloth_brdf`: `GpuTable::wgsl` (src/gpu/table.rs) appends a
// `cloth_brdf(wi, wo)` that calls `cloth_thread_frame_brdf` or `cloth_grid4d_brdf` for the
// table's layout, so only that layout's textures are used (and bound). Every top-level name
// starts with `cloth_`, `Cloth` or `CLOTH_` (the `GpuBrdf` naming contract, src/gpu/mod.rs).

const CLOTH_WARP_LINEAR: u32 = 0u;
const CLOTH_WARP_KNOTS: u32 = 1u;
const CLOTH_WARP_SIN_ENDS: u32 = 2u;

// One table axis (`AxisUniform`): info = (warp kind, texels, periodic, 0).
// Linear: a = (lo, hi); Knots: a = xs, b = vs; SinEnds: a = (hi, k, sin k).
struct ClothAxis {
    a: vec4<f32>,
    b: vec4<f32>,
    info: vec4<u32>,
}

// One thread of a thread_frame table (`ThreadUniform`); depth = (N3 + 2, N2·(N3 + 2)).
struct ClothThread {
    t0: vec4<f32>,
    b: vec4<f32>,
    axes: array<ClothAxis, 4>,
    masking: ClothAxis,
    depth: vec4<u32>,
}

// `Params`: coverage = (a1, a2, gap), albedo[j] = A_j, grid = (N of grid4d, layout).
struct ClothParams {
    threads: array<ClothThread, 2>,
    coverage: vec4<f32>,
    albedo: array<vec4<f32>, 2>,
    grid: vec4<u32>,
}

@group(0) @binding(0) var<uniform> cloth_params: ClothParams;
// Linear filtering, clamp-to-edge on every axis, no mipmaps.
@group(0) @binding(3) var cloth_sampler: sampler;
@group(0) @binding(4) var cloth_thread1_table: texture_3d<f32>;
@group(0) @binding(5) var cloth_thread2_table: texture_3d<f32>;
@group(0) @binding(6) var cloth_masking_table: texture_2d_array<f32>;
@group(0) @binding(7) var cloth_grid4d_table: texture_2d_array<f32>;

// `Warp::unit`: the unit coordinate x ∈ [0, 1] of axis value v.
fn cloth_warp_unit(axis: ClothAxis, v: f32) -> f32 {
    let kind = axis.info.x;
    if kind == CLOTH_WARP_LINEAR {
        return (v - axis.a.x) / (axis.a.y - axis.a.x);
    }
    if kind == CLOTH_WARP_KNOTS {
        // The first piece k whose upper knot vs[k + 1] is ≥ v, else the last.
        var k = 2u;
        if v <= axis.b.y {
            k = 0u;
        } else if v <= axis.b.z {
            k = 1u;
        }
        let xs = axis.a;
        let vs = axis.b;
        return xs[k] + (xs[k + 1u] - xs[k]) * (v - vs[k]) / (vs[k + 1u] - vs[k]);
    }
    // SinEnds: v = hi·sin(k(2x − 1))/sin k.
    let s = clamp(v / axis.a.x * axis.a.z, -1.0, 1.0);
    return 0.5 * (asin(s) / axis.a.y + 1.0);
}

// The continuous texel coordinate g (texel i's centre at i) of axis value v, as
// `Axis::locate` computes it: clamped axes x·(N−1) limited to [0, N−1]; periodic x·N.
fn cloth_texel_coordinate(axis: ClothAxis, v: f32) -> f32 {
    let x = cloth_warp_unit(axis, v);
    let n = f32(axis.info.y);
    if axis.info.z != 0u {
        return x * n;
    }
    return clamp(x * (n - 1.0), 0.0, n - 1.0);
}

// The hardware texture coordinate of axis value v on a clamped axis: (x·(N−1) + ½)/N.
fn cloth_texture_coordinate(axis: ClothAxis, v: f32) -> f32 {
    return (cloth_texel_coordinate(axis, v) + 0.5) / f32(axis.info.y);
}

// `Axis::locate` for an axis interpolated by hand: (i0, i1) and the weight of i1.
struct ClothLocated {
    i0: u32,
    i1: u32,
    weight: f32,
}

fn cloth_locate(axis: ClothAxis, v: f32) -> ClothLocated {
    let n = axis.info.y;
    let g = cloth_texel_coordinate(axis, v);
    if axis.info.z != 0u {
        let f = floor(g);
        let i0 = u32(((i32(f) % i32(n)) + i32(n)) % i32(n));
        return ClothLocated(i0, (i0 + 1u) % n, g - f);
    }
    let i0 = min(u32(floor(g)), max(n, 2u) - 2u);
    return ClothLocated(i0, min(i0 + 1u, n - 1u), g - f32(i0));
}

// Samples thread j's 3D texture at u block `block`, hardware-filtered over (βH, θd', v).
// `xy` are the βH, θd' texture coordinates, `g3` the continuous v texel coordinate.
fn cloth_sample_block(j: u32, xy: vec2<f32>, block: u32, g3: f32) -> vec2<f32> {
    let thread = cloth_params.threads[j];
    // Slice i3 of block i2 lies at depth i2·(N3 + 2) + 1 + i3 (one padding slice before).
    let z = (f32(block * thread.depth.x + 1u) + g3 + 0.5) / f32(thread.depth.y);
    let coordinate = vec3<f32>(xy, z);
    if j == 0u {
        return textureSampleLevel(cloth_thread1_table, cloth_sampler, coordinate, 0.0).xy;
    }
    return textureSampleLevel(cloth_thread2_table, cloth_sampler, coordinate, 0.0).xy;
}

// `Geometry::sample_thread`: thread j's interpolated (reflection, transmission, ⟨P⟩, cos²θd').
fn cloth_sample_thread(j: u32, wi: vec3<f32>, wo: vec3<f32>) -> vec4<f32> {
    let thread = cloth_params.threads[j];
    let t0 = thread.t0.xyz;
    let b = thread.b.xyz;
    // `ThreadGeometry::coordinates`: βH, the resonant frame, θd', φi', φo', (u, v) folded.
    let h = wi + wo;
    let beta_h = atan2(dot(h, t0), h.z);
    let sc = vec2<f32>(sin(beta_h), cos(beta_h));
    let z_axis = vec3<f32>(0.0, 0.0, 1.0);
    let t_res = sc.y * t0 - sc.x * z_axis;
    let n_res = sc.x * t0 + sc.y * z_axis;
    let s = clamp(0.5 * (dot(wi, t_res) - dot(wo, t_res)), -1.0, 1.0);
    let theta_d = asin(s);
    let phi_i = atan2(dot(wi, b), dot(wi, n_res));
    let phi_o = atan2(dot(wo, b), dot(wo, n_res));
    var u = 0.5 * (phi_i + phi_o);
    var v = 0.5 * (phi_i - phi_o);
    if u < 0.0 {
        u = -u;
        v = -v;
    }
    // Axes 0, 1, 3 by hardware filtering, axis 2 (u) by a manual blend of two blocks.
    let xy = vec2<f32>(
        cloth_texture_coordinate(thread.axes[0], beta_h),
        cloth_texture_coordinate(thread.axes[1], theta_d),
    );
    let g3 = cloth_texel_coordinate(thread.axes[3], v);
    let l2 = cloth_locate(thread.axes[2], u);
    let stored = mix(cloth_sample_block(j, xy, l2.i0, g3), cloth_sample_block(j, xy, l2.i1, g3), l2.weight);
    // ⟨P⟩_j bilinearly over (βi, βo): column βi, row βo, layer j.
    let beta_i = atan2(dot(wi, t0), wi.z);
    let beta_o = atan2(dot(wo, t0), wo.z);
    let mp = vec2<f32>(
        cloth_texture_coordinate(thread.masking, beta_i),
        cloth_texture_coordinate(thread.masking, beta_o),
    );
    let masking = max(textureSampleLevel(cloth_masking_table, cloth_sampler, mp, j, 0.0).x, 0.0);
    // cos²θd' = 1 − sin²θd' = 1 − s² exactly (s already clamped).
    return vec4<f32>(stored, masking, 1.0 - s * s);
}

// `Geometry::lookup_terms`: (reflection, transmission1, transmission2), divided by Q.
fn cloth_thread_frame_terms(wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    var reflection = 0.0;
    var transmission = vec2<f32>(0.0);
    var q = cloth_params.coverage.z * wo.z;
    for (var j = 0u; j < 2u; j++) {
        let st = cloth_sample_thread(j, wi, wo);
        let a = cloth_params.coverage[j];
        reflection += a * st.x * st.z / max(st.w, 1e-8);
        transmission[j] = a * st.y * st.z;
        q += a * st.z;
    }
    if q <= 0.0 {
        return vec3<f32>(0.0);
    }
    return vec3<f32>(reflection, transmission) / q;
}

// `octahedral::encode`: texture coordinates in [0, 1]² of a direction with w.z ≥ 0.
fn cloth_octahedral_encode(w: vec3<f32>) -> vec2<f32> {
    let p = w.xy / (abs(w.x) + abs(w.y) + abs(w.z));
    return (vec2<f32>(p.x + p.y, p.x - p.y) + 1.0) * 0.5;
}

// `grid4d::lookup_terms`: bilinear over wo by hardware filtering within a layer (texture
// coordinate = the octahedral coordinate, texel centres at (i + ½)/N, clamp-to-edge), and a
// manual bilinear blend of the 4 layers around wi with indices clamped to [0, N−1].
fn cloth_grid4d_terms(wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    let n = cloth_params.grid.x;
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

// `Table::lookup`: F = reflection + A1·transmission1 + A2·transmission2; 0 below the horizon.
fn cloth_combine(terms: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(terms.x) + cloth_params.albedo[0].xyz * terms.y + cloth_params.albedo[1].xyz * terms.z;
}

// F(wi, wo) by a thread_frame table; 0 below the horizon.
fn cloth_thread_frame_brdf(wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    if wi.z <= 0.0 || wo.z <= 0.0 {
        return vec3<f32>(0.0);
    }
    return cloth_combine(cloth_thread_frame_terms(wi, wo));
}

// F(wi, wo) by a grid4d table; 0 below the horizon.
fn cloth_grid4d_brdf(wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    if wi.z <= 0.0 || wo.z <= 0.0 {
        return vec3<f32>(0.0);
    }
    return cloth_combine(cloth_grid4d_terms(wi, wo));
}
