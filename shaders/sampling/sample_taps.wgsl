// The environment light's sample taps in WGSL: `clothbake::sampling::taps` (src/sampling/taps.rs,
// whose module doc gives the layout and the estimate). Expects from the module that requires it
// the taps (`SampleTaps::values`) as `sampling_taps: array<vec4<f32>>` in a read-only storage
// binding. Top-level names start with `sampling_` or `Sampling`.
//
// requires: sampling/grid, sampler_constants

// One tap: the draw wi (patch frame), its density (0: rejected, weight 0) and F/pdf.
struct SamplingTap {
    wi: vec3<f32>,
    pdf: f32,
    weight: vec3<f32>,
}

// The taps' four nodes around wo (above the horizon): computed once per pixel.
fn sampling_tap_nodes(wo: vec3<f32>) -> SamplingNodes {
    return sampling_grid_nodes(wo, SAMPLING_TAP_ELEVATIONS, SAMPLING_TAP_AZIMUTHS);
}

// `tap_choice`: k times the golden ratio modulo 1, in 24 bits (exact in f32).
fn sampling_tap_choice(k: u32) -> f32 {
    return f32((k * 0x9E3779B9u) >> 8u) * (1.0 / 16777216.0);
}

// K, the samples per pixel the taps were built for (the first value).
fn sampling_tap_count() -> u32 {
    return u32(sampling_taps[0].x);
}

// `SampleTaps::pick`: sample k of the `count` of a pixel whose tap nodes are `nodes`.
fn sampling_tap(nodes: SamplingNodes, k: u32, count: u32) -> SamplingTap {
    let node = sampling_pick_node(nodes, sampling_tap_choice(k));
    let at = 1u + 2u * (node * count + k);
    let draw = sampling_taps[at];
    return SamplingTap(draw.xyz, draw.w, sampling_taps[at + 1u].xyz);
}

// Filtered importance sampling's mip level (Colbert and Křivánek, GPU Gems 3, ch. 20) for one
// of `count` draws of density `pdf` from a map whose level-0 texel spans `texel` steradians:
// the level whose texels cover the draw's share of the sphere, 1/(count·pdf), i.e.
// ½·log2(1/(count·pdf·texel)); the caller clamps it to the map's levels. Without the
// original's +1: measured against the CPU reference (docs/sampling.md#what-was-tried), +1 blurs
// cloth's narrow cone-shaped lobes too much, and −1 or −2 alias.
fn sampling_lod(count: u32, pdf: f32, texel: f32) -> f32 {
    return 0.5 * log2(1.0 / (f32(count) * pdf * texel));
}
