// One thread tabulated in its resonant frame: the f32 lookup of a `ThreadGeometry` of
// src/table/thread/ (`ThreadGeometry::coordinates`, `ThreadGeometry::sample`), after
// shaders/table/lookup.wgsl (its sampler). Axes and warps: src/table/axis.rs (`Warp::unit`,
// `Axis::locate`). Required by the layouts that store threads this way (thread_frame.wgsl,
// split_frame.wgsl); their generated `table_constants` describe each thread's table by a
// `ClothThreadTable` constant (`ThreadGeometry::wgsl_constant`), which they pass to
// `cloth_thread_sample`.
//
// requires: table/lookup

// The warps of `Warp::unit` followed by the clamped texel coordinate of `Axis::locate`,
// g = clamp(x·(N − 1), 0, N − 1) (texel i's centre at g = i), with the constant factors
// folded by the generator (in f64, rounded once to f32): `last` = N − 1.

// `Warp::Linear { lo, hi }`: x = (v − lo)/(hi − lo); `scale` = (N − 1)/(hi − lo).
fn cloth_linear_texel(v: f32, lo: f32, scale: f32, last: f32) -> f32 {
    return clamp((v - lo) * scale, 0.0, last);
}

// `Warp::Knots { xs, vs }`: piece k (the first whose upper knot vs[k + 1] ≥ v, else the
// last) maps linearly; `gs[k]` = xs[k]·(N − 1), `slopes[k]` = (xs[k + 1] − xs[k])·(N − 1) /
// (vs[k + 1] − vs[k]). All three pieces are computed and one selected (no branch).
fn cloth_knots_texel(v: f32, vs: vec3<f32>, gs: vec3<f32>, slopes: vec3<f32>, last: f32) -> f32 {
    let g = gs + (v - vs) * slopes;
    return clamp(select(select(g.z, g.y, v <= vs.z), g.x, v <= vs.y), 0.0, last);
}

// `Warp::SinEnds { hi, k }`: x = ½(asin(clamp(v·sin k/hi, −1, 1))/k + 1); `c` = sin k/hi,
// `scale` = ½(N − 1)/k.
fn cloth_sin_ends_texel(v: f32, c: f32, scale: f32, last: f32) -> f32 {
    return clamp(asin(clamp(v * c, -1.0, 1.0)) * scale + 0.5 * last, 0.0, last);
}

// `ThreadGeometry::coordinates` (βH, θd', u, v; folded to u ≥ 0) and the masking angles
// βi, βo, of a pair given in the thread's own frame: x along its base tangent t0, y along
// its rotation axis b, z the normal (the generated `cloth_threadJ` swizzles wi and wo).
// `cos2_d` = cos²θd' = 1 − (wi·t')² = (wi·n')² + (wi·b)², a sum that keeps f32's relative
// precision as θd' → ±90° (where 1 − s² cancels to 0).
struct ClothCoordinates {
    beta_h: f32,
    theta_d: f32,
    cos2_d: f32,
    u: f32,
    v: f32,
    beta_i: f32,
    beta_o: f32,
}

fn cloth_thread_coordinates(wi: vec3<f32>, wo: vec3<f32>) -> ClothCoordinates {
    let h = wi + wo;
    let beta_h = atan2(h.x, h.z);
    // sin βH and cos βH without trigonometry: βH is the angle of (h.z, h.x). h.z > 0 above
    // the horizon; the floor only keeps h within ~1e-19 of b (a pair grazing the horizon
    // to that precision) from dividing by 0.
    let r = inverseSqrt(max(h.x * h.x + h.z * h.z, 1e-37));
    let sin_b = h.x * r;
    let cos_b = h.z * r;
    // Resonant frame t' = cos βH·t0 − sin βH·z, n' = sin βH·t0 + cos βH·z;
    // s = ½(wi·t' − wo·t') = ½(wi − wo)·t'.
    let d = wi - wo;
    let s = clamp(0.5 * (d.x * cos_b - d.z * sin_b), -1.0, 1.0);
    let wi_n = wi.x * sin_b + wi.z * cos_b;
    let phi_i = atan2(wi.y, wi_n);
    let phi_o = atan2(wo.y, wo.x * sin_b + wo.z * cos_b);
    var u = 0.5 * (phi_i + phi_o);
    var v = 0.5 * (phi_i - phi_o);
    if u < 0.0 {
        u = -u;
        v = -v;
    }
    let cos2_d = wi_n * wi_n + wi.y * wi.y;
    return ClothCoordinates(beta_h, asin(s), cos2_d, u, v, atan2(wi.x, wi.z), atan2(wo.x, wo.z));
}

// `Geometry::sample_thread` from the continuous texel coordinates: (reflection,
// transmission, ⟨P⟩, cos²θd'). `table` is the thread's 3D texture, `layer` its layer in
// `masking_table`; `g` = (βH, θd', u, v) texel coordinates of its 4D table of `n` = (N0, N1, N2, N3)
// texels; `gm` = (βi, βo) texel coordinates of its ⟨P⟩ table of `nm` texels per axis.
//
// Axes βH, θd', v by hardware filtering; u by a blend of the two u blocks around it
// (`Axis::locate`: i0 = min(⌊g⌋, N2 − 2), weight g − i0), whose slice i3 lies at depth
// i0·(N3 + 2) + 1 + i3 (`thread_frame::thread_texture`: one padding slice either side of a block).
fn cloth_sample_thread(
    table: texture_3d<f32>,
    masking_table: texture_2d_array<f32>,
    layer: i32,
    g: vec4<f32>,
    n: vec4<f32>,
    gm: vec2<f32>,
    nm: f32,
    cos2_d: f32,
) -> vec4<f32> {
    let xy = (g.xy + 0.5) / n.xy;
    let block = n.w + 2.0;
    let depth = n.z * block;
    let i0 = min(floor(g.z), n.z - 2.0);
    let z0 = (i0 * block + 1.5 + g.w) / depth;
    let z1 = ((i0 + 1.0) * block + 1.5 + g.w) / depth;
    let lower = textureSampleLevel(table, cloth_sampler, vec3<f32>(xy, z0), 0.0).xy;
    let upper = textureSampleLevel(table, cloth_sampler, vec3<f32>(xy, z1), 0.0).xy;
    let stored = mix(lower, upper, g.z - i0);
    // ⟨P⟩ bilinearly over (βi, βo).
    let mp = (gm + 0.5) / nm;
    let masking = max(textureSampleLevel(masking_table, cloth_sampler, mp, layer, 0.0).x, 0.0);
    return vec4<f32>(stored, masking, cos2_d);
}

// One axis of a thread's table (`AxisF32::wgsl_axis`): its warp, `kind` 0 `Warp::Linear`,
// 1 `Warp::Knots`, 2 `Warp::SinEnds`, with the constants of the warp functions above: (lo,
// scale) in `p.xy` for Linear, (c, scale) for SinEnds; `vs` in `p`, `gs`, `slopes` for
// Knots; `last` = N − 1.
struct ClothAxis {
    kind: u32,
    p: vec3<f32>,
    gs: vec3<f32>,
    slopes: vec3<f32>,
    last: f32,
}

// The continuous texel coordinate of `v` on `axis`. The axes are constants of the generated
// `table_constants`, so the shader compiler keeps only the branch of each axis's warp.
fn cloth_axis_texel(v: f32, axis: ClothAxis) -> f32 {
    switch axis.kind {
        case 0u: {
            return cloth_linear_texel(v, axis.p.x, axis.p.y, axis.last);
        }
        case 1u: {
            return cloth_knots_texel(v, axis.p, axis.gs, axis.slopes, axis.last);
        }
        default: {
            return cloth_sin_ends_texel(v, axis.p.x, axis.p.y, axis.last);
        }
    }
}

// A thread's table (`ThreadGeometry::wgsl_constant`): whether its base tangent t0 is y
// (thread 2, whose pairs are swizzled so that x runs along t0; else t0 is x), its 4D axes
// (βH, θd', u, v) and their texel counts `n`, its ⟨P⟩ axis and texels per axis `nm`, and the
// layer of the masking array texture that holds its ⟨P⟩.
struct ClothThreadTable {
    along_y: bool,
    axes: array<ClothAxis, 4>,
    n: vec4<f32>,
    masking: ClothAxis,
    nm: f32,
    layer: i32,
}

// `ThreadGeometry::sample`: (reflection, transmission, ⟨P⟩, cos²θd') of the thread described
// by `thread`, whose 4D table is the 3D texture `table` and whose ⟨P⟩ is a layer of
// `masking_table`.
fn cloth_thread_sample(
    table: texture_3d<f32>,
    masking_table: texture_2d_array<f32>,
    thread: ClothThreadTable,
    wi: vec3<f32>,
    wo: vec3<f32>,
) -> vec4<f32> {
    let c = cloth_thread_coordinates(
        select(wi, wi.yxz, thread.along_y),
        select(wo, wo.yxz, thread.along_y),
    );
    // Continuous texel coordinates of the 4D table (`Axis::locate`).
    let g = vec4<f32>(
        cloth_axis_texel(c.beta_h, thread.axes[0]),
        cloth_axis_texel(c.theta_d, thread.axes[1]),
        cloth_axis_texel(c.u, thread.axes[2]),
        cloth_axis_texel(c.v, thread.axes[3]),
    );
    let gm = vec2<f32>(
        cloth_axis_texel(c.beta_i, thread.masking),
        cloth_axis_texel(c.beta_o, thread.masking),
    );
    return cloth_sample_thread(table, masking_table, thread.layer, g, thread.n, gm, thread.nm, c.cos2_d);
}
