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

// The mip level at which one filtered fetch stands for the mean of the map over a tap's
// stratum, of Ωs = 2^log2_solid_angle steradians, in a map whose level-0 texel spans `texel`
// (Ωp) steradians; the caller clamps it to the map's levels. Filtered importance sampling
// (Colbert and Křivánek, GPU Gems 3, ch. 20) takes the level whose texels cover the draw's
// share of the sphere, ½·log2(Ωs/Ωp). But a fetch there blurs more than the stratum's mean
// does: its texels are box means of side h (variance h²/12 per axis) read through a bilinear
// tent two texels wide (h²/6), h²/4 in all, three times the h²/12 of a box of area h² = Ωs.
// Matching the variances would take ½·log2(1/3) ≈ −0.8 levels, but sharper fetches also
// alias what one fetch per stratum cannot resolve (a window's edge, the horizon). Measured,
// −½ lowers the worst errors (studio, interior) by up to a third, and leaves the skies
// slightly worse but within their goal (docs/notebook/2026-12-07-sampling.md#what-was-tried).
// The taps' weights assume this blur, a variance of Ωs/8 per axis
// (`FETCH_VARIANCE_PER_SOLID_ANGLE` in src/sampling/taps/moments.rs): change both together.
fn sampling_lod(log2_solid_angle: f32, texel: f32) -> f32 {
    return 0.5 * (log2_solid_angle - log2(texel)) - 0.5;
}
