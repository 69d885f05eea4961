// The fabric sampler in f32, mirroring `clothbake::sampling::Sampler` (src/sampling/mod.rs,
// whose module doc describes the layout): directions wi drawn for a given wo with a density
// close to F(wi, wo), and that density pdf(wi | wo) per unit solid angle, in the local cloth
// frame.
//
// Requires the generated module `sampler_constants`: the constants of
// `Sampler::wgsl_constants` (SAMPLING_ELEVATION_NODES, SAMPLING_AZIMUTH_NODES, SAMPLING_ROWS,
// SAMPLING_COLUMNS, SAMPLING_NODE_STRIDE, SAMPLING_COSINE_SHARE). Expects from the module
// that requires it the sampler's data (`Sampler::data`) as `sampling_data: array<f32>` in a
// read-only storage binding (its group and binding are that module's choice). Top-level
// names start with `sampling_` or `Sampling`.
//
// requires: sampler_constants

const SAMPLING_PI: f32 = 3.14159265358979;
const SAMPLING_TAU: f32 = 6.28318530717959;
const SAMPLING_HALF_PI: f32 = 1.57079632679490;

// z = sin(elevation) at the lower edge of row r.
fn sampling_row_z(r: u32) -> f32 {
    return sin(f32(r) * (SAMPLING_HALF_PI / f32(SAMPLING_ROWS)));
}

// Azimuth in [0, 2π) from x towards y.
fn sampling_azimuth(w: vec3<f32>) -> f32 {
    let a = atan2(w.y, w.x);
    return select(a, a + SAMPLING_TAU, a < 0.0);
}

fn sampling_elevation(w: vec3<f32>) -> f32 {
    return atan2(w.z, length(w.xy));
}

// The direction at height z (sin of the elevation; negative below the horizon) and azimuth.
fn sampling_direction_at_z(z: f32, azimuth: f32) -> vec3<f32> {
    let r = sqrt(max(1.0 - z * z, 0.0));
    return vec3<f32>(r * cos(azimuth), r * sin(azimuth), z);
}

// The four nodes around wo (indices) and their bilinear weights.
struct SamplingNodes {
    index: vec4<u32>,
    weight: vec4<f32>,
}

fn sampling_nodes(wo: vec3<f32>) -> SamplingNodes {
    let last = f32(SAMPLING_ELEVATION_NODES - 1u);
    // Nodes at 90°·(i/(E − 1))^1.5: the node coordinate is (elevation/90°)^(2/3)·(E − 1).
    let x = clamp(pow(max(sampling_elevation(wo) / SAMPLING_HALF_PI, 0.0), 2.0 / 3.0) * last, 0.0, last);
    let i0 = min(u32(floor(x)), SAMPLING_ELEVATION_NODES - 2u);
    let fx = x - f32(i0);
    let y = sampling_azimuth(wo) / SAMPLING_TAU * f32(SAMPLING_AZIMUTH_NODES);
    let j0 = u32(floor(y)) % SAMPLING_AZIMUTH_NODES;
    let fy = clamp(y - floor(y), 0.0, 1.0);
    let j1 = (j0 + 1u) % SAMPLING_AZIMUTH_NODES;
    let a = SAMPLING_AZIMUTH_NODES;
    return SamplingNodes(
        vec4<u32>(i0 * a + j0, i0 * a + j1, (i0 + 1u) * a + j0, (i0 + 1u) * a + j1),
        vec4<f32>((1.0 - fx) * (1.0 - fy), (1.0 - fx) * fy, fx * (1.0 - fy), fx * fy),
    );
}

fn sampling_column_base(node: u32, r: u32) -> u32 {
    return node * SAMPLING_NODE_STRIDE + SAMPLING_ROWS + 1u + r * (SAMPLING_COLUMNS + 1u);
}

// The cosine density's probability of row r, z_{r+1}² − z_r².
fn sampling_cosine_row(r: u32) -> f32 {
    let z0 = sampling_row_z(r);
    let z1 = sampling_row_z(r + 1u);
    return (z1 - z0) * (z1 + z0);
}

// The solid angle of one cell of row r.
fn sampling_cell_solid_angle(r: u32) -> f32 {
    return (sampling_row_z(r + 1u) - sampling_row_z(r)) * (SAMPLING_TAU / f32(SAMPLING_COLUMNS));
}

// Each node's probability of row r (a difference of stored neighbours).
fn sampling_row_masses(nodes: SamplingNodes, r: u32) -> vec4<f32> {
    var masses = vec4<f32>(0.0);
    for (var k = 0u; k < 4u; k++) {
        let rows = nodes.index[k] * SAMPLING_NODE_STRIDE;
        masses[k] = sampling_data[rows + r + 1u] - sampling_data[rows + r];
    }
    return masses;
}

// The mixture's probability of the rows below r (`Sampler::mixture_rows_below`).
fn sampling_rows_below(nodes: SamplingNodes, r: u32) -> f32 {
    var table = 0.0;
    for (var k = 0u; k < 4u; k++) {
        table += nodes.weight[k] * sampling_data[nodes.index[k] * SAMPLING_NODE_STRIDE + r];
    }
    let z = sampling_row_z(r);
    return (1.0 - SAMPLING_COSINE_SHARE) * table + SAMPLING_COSINE_SHARE * z * z;
}

// The mixture's probability of the cells of row r left of column c, given the nodes' row
// masses (`Sampler::mixture_columns_left`).
fn sampling_columns_left(nodes: SamplingNodes, masses: vec4<f32>, r: u32, c: u32) -> f32 {
    var table = 0.0;
    for (var k = 0u; k < 4u; k++) {
        table += nodes.weight[k] * masses[k] * sampling_data[sampling_column_base(nodes.index[k], r) + c];
    }
    return (1.0 - SAMPLING_COSINE_SHARE) * table
        + SAMPLING_COSINE_SHARE * sampling_cosine_row(r) * f32(c) / f32(SAMPLING_COLUMNS);
}

// The mixture's probability of cell (r, c) (`Sampler::mixture_cell_probability`): each
// node's cell probability as differences of stored neighbours, and the cosine share's mass.
fn sampling_cell_probability(nodes: SamplingNodes, r: u32, c: u32) -> f32 {
    var table = 0.0;
    for (var k = 0u; k < 4u; k++) {
        let rows = nodes.index[k] * SAMPLING_NODE_STRIDE;
        let columns = sampling_column_base(nodes.index[k], r);
        table += nodes.weight[k]
            * (sampling_data[rows + r + 1u] - sampling_data[rows + r])
            * (sampling_data[columns + c + 1u] - sampling_data[columns + c]);
    }
    return (1.0 - SAMPLING_COSINE_SHARE) * table
        + SAMPLING_COSINE_SHARE * sampling_cosine_row(r) / f32(SAMPLING_COLUMNS);
}

// pdf(wi | wo) per unit solid angle, constant over each cell; 0 unless both are above the
// horizon.
fn sampling_pdf(wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return 0.0;
    }
    let r = min(u32(sampling_elevation(wi) / SAMPLING_HALF_PI * f32(SAMPLING_ROWS)), SAMPLING_ROWS - 1u);
    let c = min(u32(sampling_azimuth(wi) / SAMPLING_TAU * f32(SAMPLING_COLUMNS)), SAMPLING_COLUMNS - 1u);
    return sampling_cell_probability(sampling_nodes(wo), r, c) / sampling_cell_solid_angle(r);
}

// A draw: direction.xyz = wi, direction.w = pdf(wi | wo) (0 marks a rejected draw: wo or
// the draw on or below the horizon); derivatives = (∂z/∂u1, ∂φ/∂u2) inside the drawn cell,
// as `clothbake::sampling::Sample`.
struct SamplingDraw {
    direction: vec4<f32>,
    derivatives: vec2<f32>,
}

// A direction for wo from two uniform numbers in [0, 1) (`Sampler::sample`): the four nodes'
// bilinear mixture and the cosine share inverted as one CDF, u.x the row and z inside it,
// u.y the column and the azimuth inside it.
fn sampling_sample(wo: vec3<f32>, u: vec2<f32>) -> SamplingDraw {
    var draw = SamplingDraw(vec4<f32>(0.0), vec2<f32>(0.0));
    if wo.z <= 0.0 {
        return draw;
    }
    let nodes = sampling_nodes(wo);
    var lo = 0u;
    var hi = SAMPLING_ROWS - 1u;
    while lo < hi {
        let mid = (lo + hi) / 2u;
        if sampling_rows_below(nodes, mid + 1u) <= u.x {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    let r = lo;
    let below = sampling_rows_below(nodes, r);
    let ur = clamp((u.x - below) / (sampling_rows_below(nodes, r + 1u) - below), 0.0, 0.99999994);
    let masses = sampling_row_masses(nodes, r);
    let row_p = (1.0 - SAMPLING_COSINE_SHARE) * dot(nodes.weight, masses)
        + SAMPLING_COSINE_SHARE * sampling_cosine_row(r);
    // The column against u2 scaled to the row's probability (its partial sums' total:
    // each node's column CDF ends at exactly 1).
    let target_p = u.y * row_p;
    lo = 0u;
    hi = SAMPLING_COLUMNS - 1u;
    while lo < hi {
        let mid = (lo + hi) / 2u;
        if sampling_columns_left(nodes, masses, r, mid + 1u) <= target_p {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    let c = lo;
    let left = sampling_columns_left(nodes, masses, r, c);
    let uc = clamp((target_p - left) / (sampling_columns_left(nodes, masses, r, c + 1u) - left), 0.0, 0.99999994);
    let cell_p = sampling_cell_probability(nodes, r, c);
    let z0 = sampling_row_z(r);
    let height = sampling_row_z(r + 1u) - z0;
    let wi = sampling_direction_at_z(z0 + ur * height, (f32(c) + uc) * (SAMPLING_TAU / f32(SAMPLING_COLUMNS)));
    if wi.z <= 0.0 || cell_p <= 0.0 {
        return draw;
    }
    draw.direction = vec4<f32>(wi, cell_p / sampling_cell_solid_angle(r));
    draw.derivatives = vec2<f32>(height / row_p, (SAMPLING_TAU / f32(SAMPLING_COLUMNS)) * row_p / cell_p);
    return draw;
}

// Point k of the K-point 2D Hammersley set ((k + ½)/K, the base-2 radical inverse of k plus
// half its step), as `clothbake::sampling::net_point`.
fn sampling_net_point(k: u32, count: u32) -> vec2<f32> {
    let bits = 32u - countLeadingZeros(max(count, 2u) - 1u);
    let step = exp2(-f32(bits));
    return vec2<f32>((f32(k) + 0.5) / f32(count), f32(reverseBits(k)) * 2.3283064e-10 + 0.5 * step);
}

// Half h (0 or 1) of the part of the sphere that a draw of a K-point net stands for: xyz its
// centre (unit, local frame; may lie below the horizon), w its solid angle
// (`clothbake::sampling::Sample::footprint_half`, which derives it).
fn sampling_footprint_half(draw: SamplingDraw, count: u32, h: u32) -> vec4<f32> {
    let extent = min(inverseSqrt(f32(max(count, 1u))) * draw.derivatives, vec2<f32>(2.0, SAMPLING_TAU));
    let wi = draw.direction.xyz;
    let cos_elevation = max(length(wi.xy), 1e-3);
    let sign = f32(h) - 0.5;
    var offset = vec2<f32>(0.0, 0.5 * sign * extent.y);
    if extent.x / cos_elevation > extent.y * cos_elevation {
        offset = vec2<f32>(0.5 * sign * extent.x, 0.0);
    }
    let z = clamp(wi.z + offset.x, -1.0, 1.0);
    let azimuth = atan2(wi.y, wi.x) + offset.y;
    return vec4<f32>(sampling_direction_at_z(z, azimuth), 0.5 * extent.x * extent.y);
}

// Filtered importance sampling's mip level (Colbert and Křivánek, GPU Gems 3, ch. 20): the
// level whose texels cover `solid_angle` (a draw's share of the sphere, or half of it), ½·log2(solid_angle/texel) for a level-0 texel of `texel` steradians; the caller
// clamps it to the map's levels.
fn sampling_lod(solid_angle: f32, texel: f32) -> f32 {
    return 0.5 * log2(solid_angle / texel);
}
