// The fabric sampler in f32, mirroring `clothbake::sampling::Sampler` (src/sampling/mod.rs,
// whose module doc describes the layout): directions wi drawn for a given wo with a density
// close to F(wi, wo), and that density pdf(wi | wo) per unit solid angle, in the local cloth
// frame.
//
// Requires the generated module `sampler_constants`: the constants of
// `Sampler::wgsl_constants` (SAMPLING_ELEVATION_NODES, SAMPLING_AZIMUTH_NODES, SAMPLING_ROWS,
// SAMPLING_COLUMNS, SAMPLING_NODE_STRIDE, SAMPLING_SUPPORT_BASE, SAMPLING_COSINE_SHARE), and
// sampling/grid. Expects
// from the module that requires it the sampler's data (`Sampler::data`) as
// `sampling_data: array<f32>` in a read-only storage binding (its group and binding are that
// module's choice). Top-level names start with `sampling_` or `Sampling`.
//
// requires: sampling/grid, sampler_constants

// z = sin(elevation) at the lower edge of row r.
fn sampling_row_z(r: u32) -> f32 {
    return sin(f32(r) * (SAMPLING_HALF_PI / f32(SAMPLING_ROWS)));
}

fn sampling_direction_at_z(z: f32, azimuth: f32) -> vec3<f32> {
    let r = sqrt(max(1.0 - z * z, 0.0));
    return vec3<f32>(r * cos(azimuth), r * sin(azimuth), z);
}

// The sampler's four nodes around wo and their bilinear weights.
fn sampling_nodes(wo: vec3<f32>) -> SamplingNodes {
    return sampling_grid_nodes(wo, SAMPLING_ELEVATION_NODES, SAMPLING_AZIMUTH_NODES);
}

// F's support for one wo (src/sampling/support.rs derives it): the whole hemisphere, or the
// union of up to two lunes L < atan2(w·t0, w.z) < U, one per thread (component j), given by
// cos and sin of their bounds and their cosine-weighted masses.
struct SamplingSupport {
    everywhere: bool,
    present: vec2<u32>,
    lower_cos: vec2<f32>,
    lower_sin: vec2<f32>,
    upper_cos: vec2<f32>,
    upper_sin: vec2<f32>,
    mass: vec2<f32>,
}

// Thread j's tangent t0 and its axis b (`thread_axes`, as the generated constants give them).
fn sampling_thread_t0(j: u32) -> vec3<f32> {
    return select(SAMPLING_T0_1, SAMPLING_T0_0, j == 0u);
}

fn sampling_thread_b(j: u32) -> vec3<f32> {
    return select(SAMPLING_B_1, SAMPLING_B_0, j == 0u);
}

// Each thread's α = inf and A = sup of its curve's intervals inside wo's window
// (−π/2 − δo, π/2 − δo); the lune is max(−π/2, −π/2 − A) < δ < min(π/2, π/2 − a).
fn sampling_support(wo: vec3<f32>) -> SamplingSupport {
    var s: SamplingSupport;
    s.everywhere = true;
    let base = SAMPLING_SUPPORT_BASE;
    if sampling_data[base] == 0.0 {
        return s;
    }
    s.everywhere = false;
    let counts = vec2<u32>(u32(sampling_data[base + 1u]), u32(sampling_data[base + 2u]));
    var at = base + 3u;
    for (var j = 0u; j < 2u; j++) {
        let delta = atan2(dot(wo, sampling_thread_t0(j)), wo.z);
        let window_lo = -SAMPLING_HALF_PI - delta;
        let window_hi = SAMPLING_HALF_PI - delta;
        var a = 1e30;
        var big_a = -1e30;
        for (var k = 0u; k < counts[j]; k++) {
            let start = sampling_data[at + 2u * k];
            let end = sampling_data[at + 2u * k + 1u];
            let lo = max(start, window_lo);
            let hi = min(end, window_hi);
            let meets = select(lo < hi, window_lo < start && start < window_hi, start == end);
            if meets {
                a = min(a, lo);
                big_a = max(big_a, hi);
            }
        }
        at += 2u * counts[j];
        if a > big_a {
            continue;
        }
        if a <= 0.0 && big_a >= 0.0 {
            s.everywhere = true;
            return s;
        }
        let lower = max(-SAMPLING_HALF_PI, -SAMPLING_HALF_PI - big_a);
        let upper = min(SAMPLING_HALF_PI, SAMPLING_HALF_PI - a);
        s.present[j] = 1u;
        s.lower_cos[j] = cos(lower);
        s.lower_sin[j] = sin(lower);
        s.upper_cos[j] = cos(upper);
        s.upper_sin[j] = sin(upper);
        s.mass[j] = 0.5 * (s.upper_sin[j] - s.lower_sin[j]);
    }
    return s;
}

// Whether w (w.z > 0) is strictly inside lune j.
fn sampling_in_lune(s: SamplingSupport, j: u32, w: vec3<f32>) -> bool {
    let p = dot(w, sampling_thread_t0(j));
    return s.present[j] == 1u && p * s.lower_cos[j] - w.z * s.lower_sin[j] > 0.0
        && w.z * s.upper_sin[j] - p * s.upper_cos[j] > 0.0;
}

fn sampling_in_support(s: SamplingSupport, w: vec3<f32>) -> bool {
    return s.everywhere || sampling_in_lune(s, 0u, w) || sampling_in_lune(s, 1u, w);
}

fn sampling_support_mass(s: SamplingSupport) -> f32 {
    return select(0.0, s.mass.x, s.present.x == 1u) + select(0.0, s.mass.y, s.present.y == 1u);
}

// The cosine density restricted to the support: cos θ/π times the number of lunes holding w
// over their total mass.
fn sampling_cosine_pdf(s: SamplingSupport, w: vec3<f32>) -> f32 {
    if s.everywhere {
        return w.z / SAMPLING_PI;
    }
    let total = sampling_support_mass(s);
    let holding = select(0.0, 1.0, sampling_in_lune(s, 0u, w)) + select(0.0, 1.0, sampling_in_lune(s, 1u, w));
    return select(0.0, w.z / SAMPLING_PI * holding / total, total > 0.0);
}

// A draw of sampling_cosine_pdf from u (xy the point, z in [0, 1) the lune); w = 0 where the
// support is empty, else 1. Malley's method, the disk's point then mapped affinely along t0
// on its chord onto the lune's shadow (sin L, sin U)·√(1 − q²).
fn sampling_sample_cosine(s: SamplingSupport, u: vec3<f32>) -> vec4<f32> {
    let disk = sampling_direction_at_z(sqrt(1.0 - u.x), u.y * SAMPLING_TAU);
    if s.everywhere {
        return vec4<f32>(disk, 1.0);
    }
    let total = sampling_support_mass(s);
    if total <= 0.0 {
        return vec4<f32>(0.0);
    }
    var j = select(1u, 0u, s.present.x == 1u);
    if s.present.x == 1u && s.present.y == 1u && u.z * total >= s.mass.x {
        j = 1u;
    }
    let t0 = sampling_thread_t0(j);
    let b = sampling_thread_b(j);
    let q = dot(disk, b);
    let h = sqrt(max(1.0 - q * q, 0.0));
    let chord = select(0.0, clamp(dot(disk, t0) / h, -1.0, 1.0), h > 0.0);
    let p = h * (s.lower_sin[j] + 0.5 * (chord + 1.0) * (s.upper_sin[j] - s.lower_sin[j]));
    let z = sqrt(max(1.0 - p * p - q * q, 0.0));
    return vec4<f32>(t0 * p + b * q + vec3<f32>(0.0, 0.0, z), 1.0);
}

// The interval k of the CDF of n + 1 values at sampling_data[base..] holding u, and u
// rescaled into it (x: k, y: the rescaled u).
struct SamplingPick {
    index: u32,
    rescaled: f32,
}

fn sampling_invert(base: u32, n: u32, u: f32) -> SamplingPick {
    // First k with cdf[k + 1] > u (binary search), as the CPU's partition_point.
    var lo = 0u;
    var hi = n - 1u;
    while lo < hi {
        let mid = (lo + hi) / 2u;
        if sampling_data[base + mid + 1u] <= u {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    let c0 = sampling_data[base + lo];
    let c1 = sampling_data[base + lo + 1u];
    let rescaled = select(0.0, (u - c0) / (c1 - c0), c1 > c0);
    return SamplingPick(lo, clamp(rescaled, 0.0, 0.99999994));
}

fn sampling_column_base(node: u32, r: u32) -> u32 {
    return node * SAMPLING_NODE_STRIDE + SAMPLING_ROWS + 1u + r * (SAMPLING_COLUMNS + 1u);
}

// The density at wi (wi.z > 0, inside the support) of the mixture of `nodes` (one wo's
// bilinear weights) and the cosine share on the support: wi's cell and its solid angle are
// the same in every node, so they are found once.
fn sampling_mixture_pdf(nodes: SamplingNodes, support: SamplingSupport, wi: vec3<f32>) -> f32 {
    let r = min(u32(sampling_elevation(wi) / SAMPLING_HALF_PI * f32(SAMPLING_ROWS)), SAMPLING_ROWS - 1u);
    let c = min(u32(sampling_azimuth(wi) / SAMPLING_TAU * f32(SAMPLING_COLUMNS)), SAMPLING_COLUMNS - 1u);
    var table = 0.0;
    for (var k = 0u; k < 4u; k++) {
        if nodes.weight[k] > 0.0 {
            let rows = nodes.index[k] * SAMPLING_NODE_STRIDE;
            let columns = sampling_column_base(nodes.index[k], r);
            table += nodes.weight[k]
                * (sampling_data[rows + r + 1u] - sampling_data[rows + r])
                * (sampling_data[columns + c + 1u] - sampling_data[columns + c]);
        }
    }
    let solid_angle = (sampling_row_z(r + 1u) - sampling_row_z(r)) * (SAMPLING_TAU / f32(SAMPLING_COLUMNS));
    return SAMPLING_COSINE_SHARE * sampling_cosine_pdf(support, wi) + (1.0 - SAMPLING_COSINE_SHARE) * table / solid_angle;
}

// pdf(wi | wo) per unit solid angle; 0 unless both are above the horizon and wi is inside F's
// support.
fn sampling_pdf(wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return 0.0;
    }
    let support = sampling_support(wo);
    if !sampling_in_support(support, wi) {
        return 0.0;
    }
    return sampling_mixture_pdf(sampling_nodes(wo), support, wi);
}

// A direction for wo from three uniform numbers in [0, 1): xyz = wi, w = pdf(wi | wo); w = 0
// marks a rejected draw (wo or the draw on or below the horizon, or outside F's support).
fn sampling_sample(wo: vec3<f32>, u: vec3<f32>) -> vec4<f32> {
    if wo.z <= 0.0 {
        return vec4<f32>(0.0);
    }
    let nodes = sampling_nodes(wo);
    let support = sampling_support(wo);
    var wi: vec3<f32>;
    if u.z < SAMPLING_COSINE_SHARE {
        let drawn = sampling_sample_cosine(support, vec3<f32>(u.xy, u.z / SAMPLING_COSINE_SHARE));
        if drawn.w == 0.0 {
            return vec4<f32>(0.0);
        }
        wi = drawn.xyz;
    } else {
        let chosen = sampling_pick_node(nodes, (u.z - SAMPLING_COSINE_SHARE) / (1.0 - SAMPLING_COSINE_SHARE));
        let row = sampling_invert(chosen * SAMPLING_NODE_STRIDE, SAMPLING_ROWS, u.x);
        let column = sampling_invert(sampling_column_base(chosen, row.index), SAMPLING_COLUMNS, u.y);
        let z0 = sampling_row_z(row.index);
        let z = z0 + row.rescaled * (sampling_row_z(row.index + 1u) - z0);
        wi = sampling_direction_at_z(z, (f32(column.index) + column.rescaled) * (SAMPLING_TAU / f32(SAMPLING_COLUMNS)));
    }
    if wi.z <= 0.0 || !sampling_in_support(support, wi) {
        return vec4<f32>(0.0);
    }
    let pdf = sampling_mixture_pdf(nodes, support, wi);
    if pdf <= 0.0 {
        return vec4<f32>(0.0);
    }
    return vec4<f32>(wi, pdf);
}
