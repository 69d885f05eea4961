// The fabric sampler in f32, mirroring `clothbake::sampling::Sampler` (src/sampling/mod.rs,
// whose module doc describes the layout): directions wi drawn for a given wo with a density
// close to F(wi, wo), and that density pdf(wi | wo) per unit solid angle, in the local cloth
// frame.
//
// Requires the generated module `sampler_constants`: the constants of
// `Sampler::wgsl_constants` (SAMPLING_ELEVATION_NODES, SAMPLING_AZIMUTH_NODES, SAMPLING_ROWS,
// SAMPLING_COLUMNS, SAMPLING_NODE_STRIDE, SAMPLING_COSINE_SHARE), and sampling/grid. Expects
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

// The density at wi (wi.z > 0) of the mixture of `nodes` (one wo's bilinear weights): wi's
// cell and its solid angle are the same in every node, so they are found once.
fn sampling_mixture_pdf(nodes: SamplingNodes, wi: vec3<f32>) -> f32 {
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
    return SAMPLING_COSINE_SHARE * wi.z / SAMPLING_PI + (1.0 - SAMPLING_COSINE_SHARE) * table / solid_angle;
}

// pdf(wi | wo) per unit solid angle; 0 unless both are above the horizon.
fn sampling_pdf(wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return 0.0;
    }
    return sampling_mixture_pdf(sampling_nodes(wo), wi);
}

// A direction for wo from three uniform numbers in [0, 1): xyz = wi, w = pdf(wi | wo); w = 0
// marks a rejected draw (wo or the draw on or below the horizon).
fn sampling_sample(wo: vec3<f32>, u: vec3<f32>) -> vec4<f32> {
    if wo.z <= 0.0 {
        return vec4<f32>(0.0);
    }
    let nodes = sampling_nodes(wo);
    var wi: vec3<f32>;
    if u.z < SAMPLING_COSINE_SHARE {
        wi = sampling_direction_at_z(sqrt(1.0 - u.x), u.y * SAMPLING_TAU);
    } else {
        let chosen = sampling_pick_node(nodes, (u.z - SAMPLING_COSINE_SHARE) / (1.0 - SAMPLING_COSINE_SHARE));
        let row = sampling_invert(chosen * SAMPLING_NODE_STRIDE, SAMPLING_ROWS, u.x);
        let column = sampling_invert(sampling_column_base(chosen, row.index), SAMPLING_COLUMNS, u.y);
        let z0 = sampling_row_z(row.index);
        let z = z0 + row.rescaled * (sampling_row_z(row.index + 1u) - z0);
        wi = sampling_direction_at_z(z, (f32(column.index) + column.rescaled) * (SAMPLING_TAU / f32(SAMPLING_COLUMNS)));
    }
    if wi.z <= 0.0 {
        return vec4<f32>(0.0);
    }
    let pdf = sampling_mixture_pdf(nodes, wi);
    if pdf <= 0.0 {
        return vec4<f32>(0.0);
    }
    return vec4<f32>(wi, pdf);
}
