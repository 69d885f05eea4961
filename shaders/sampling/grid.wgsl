// Directions and grids over wo shared by the fabric sampler (sampling/fabric_sampler) and
// the environment light's taps (sampling/sample_taps), mirroring the helpers of
// src/sampling/mod.rs (`azimuth_of`, `elevation_of`, `grid_nodes`, `pick_node`). Top-level
// names start with `sampling_` or `Sampling`.

const SAMPLING_PI: f32 = 3.14159265358979;
const SAMPLING_TAU: f32 = 6.28318530717959;
const SAMPLING_HALF_PI: f32 = 1.57079632679490;

// Azimuth in [0, 2π) from x towards y.
fn sampling_azimuth(w: vec3<f32>) -> f32 {
    let a = atan2(w.y, w.x);
    return select(a, a + SAMPLING_TAU, a < 0.0);
}

fn sampling_elevation(w: vec3<f32>) -> f32 {
    return atan2(w.z, length(w.xy));
}

// Four nodes of a grid over wo (indices) and their bilinear weights.
struct SamplingNodes {
    index: vec4<u32>,
    weight: vec4<f32>,
}

// The four nodes around wo on a grid of `elevations` × `azimuths` nodes: elevation i at
// 90°·(i/(E − 1))^1.5, so the node coordinate is (elevation/90°)^(2/3)·(E − 1); azimuth j at
// j·360°/A, periodic; node index i·A + j.
fn sampling_grid_nodes(wo: vec3<f32>, elevations: u32, azimuths: u32) -> SamplingNodes {
    let last = f32(elevations - 1u);
    let x = clamp(pow(max(sampling_elevation(wo) / SAMPLING_HALF_PI, 0.0), 2.0 / 3.0) * last, 0.0, last);
    let i0 = min(u32(floor(x)), elevations - 2u);
    let fx = x - f32(i0);
    let y = sampling_azimuth(wo) / SAMPLING_TAU * f32(azimuths);
    let j0 = u32(floor(y)) % azimuths;
    let fy = clamp(y - floor(y), 0.0, 1.0);
    let j1 = (j0 + 1u) % azimuths;
    return SamplingNodes(
        vec4<u32>(i0 * azimuths + j0, i0 * azimuths + j1, (i0 + 1u) * azimuths + j0, (i0 + 1u) * azimuths + j1),
        vec4<f32>((1.0 - fx) * (1.0 - fy), (1.0 - fx) * fy, fx * (1.0 - fy), fx * fy),
    );
}

// The node that `pick` in [0, 1) falls on when the unit interval is cut into the nodes'
// weights in order (a node of weight 0 is never chosen).
fn sampling_pick_node(nodes: SamplingNodes, pick_in: f32) -> u32 {
    var pick = pick_in;
    var chosen = nodes.index.x;
    for (var k = 0u; k < 4u; k++) {
        if nodes.weight[k] > 0.0 {
            chosen = nodes.index[k];
            if pick < nodes.weight[k] {
                break;
            }
            pick -= nodes.weight[k];
        }
    }
    return chosen;
}
