// The environment light's sample taps in WGSL: `clothbake::sampling::taps` (src/sampling/taps.rs,
// whose module doc gives the layout and the estimate). Expects from the module that requires it
// the taps (`SampleTaps::words`) as `sampling_taps: array<vec4<u32>>` in a read-only storage
// binding. Top-level names start with `sampling_` or `Sampling`.
//
// requires: sampling/grid, sampler_constants

// One tap: the direction the map is read in (patch frame), log2 of the solid angle of the
// stratum it stands for, and K·∫F dwi over that stratum (RGB).
struct SamplingTap {
    wi: vec3<f32>,
    log2_solid_angle: f32,
    weight: vec3<f32>,
}

// The taps' four nodes around wo (above the horizon) and the weights' scale (the header's
// second word): what every tap of a pixel shares, read once per pixel.
struct SamplingTapNodes {
    nodes: SamplingNodes,
    scale: f32,
}

fn sampling_tap_nodes(wo: vec3<f32>) -> SamplingTapNodes {
    return SamplingTapNodes(
        sampling_grid_nodes(wo, SAMPLING_TAP_ELEVATIONS, SAMPLING_TAP_AZIMUTHS),
        bitcast<f32>(sampling_taps[0].y),
    );
}

// K, the samples per pixel the taps were built for (the first word).
fn sampling_tap_count() -> u32 {
    return sampling_taps[0].x;
}

// `SampleTaps::pick`: sample k of the `count` of a pixel whose tap nodes are `at`, the taps k
// of the four nodes blended by their bilinear weights. A tap is four words: the direction in
// snorm16 (x, y; z), log2 of the solid angle in unorm16 over the range of the constants, the
// weight in unorm16 as a fraction of the scale.
fn sampling_tap(at: SamplingTapNodes, k: u32, count: u32) -> SamplingTap {
    var wi = vec3<f32>(0.0);
    var size = 0.0;
    var weight = vec3<f32>(0.0);
    for (var n = 0u; n < 4u; n++) {
        let words = sampling_taps[1u + at.nodes.index[n] * count + k];
        let b = at.nodes.weight[n];
        wi += b * vec3<f32>(unpack2x16snorm(words.x), unpack2x16snorm(words.y).x);
        size += b * unpack2x16unorm(words.y).y;
        weight += b * vec3<f32>(unpack2x16unorm(words.z), unpack2x16unorm(words.w).x);
    }
    let log2_solid_angle =
        SAMPLING_TAP_LOG2_SOLID_ANGLE_LOW + SAMPLING_TAP_LOG2_SOLID_ANGLE_SPAN * size;
    return SamplingTap(normalize(wi), log2_solid_angle, at.scale * weight);
}

// The mip level whose texels cover a tap's stratum, of 2^log2_solid_angle steradians, in a map
// whose level-0 texel spans `texel` steradians: ½·log2(solid angle/texel), as filtered
// importance sampling (Colbert and Křivánek, GPU Gems 3, ch. 20) takes a draw's share of the
// sphere; the caller clamps it to the map's levels.
fn sampling_lod(log2_solid_angle: f32, texel: f32) -> f32 {
    return 0.5 * (log2_solid_angle - log2(texel));
}
