// Filament's cloth model with a subsurface colour: the twin of `eval` in mod.rs beside this
// file, over the stock block (baseColor rgb 0–2, perceptual roughness 3, sheenColor rgb
// 4–6, subsurfaceColor rgb 7–9).
//
// requires: evaluator/stock, evaluator/stock_lobes

// `eval`: F for l = wi, v = wo above the horizon and their half vector h.
fn cloth_stock_f(l: vec3<f32>, v: vec3<f32>, h: vec3<f32>) -> vec3<f32> {
    let base = cloth_stock_colour(0u);
    let roughness = cloth_stock_parameter(3u);
    let alpha = roughness * roughness;
    let sheen = cloth_stock_colour(4u);
    let subsurface = cloth_stock_colour(7u);
    let fr = sheen * (cloth_charlie_d(alpha, h.z, 0.0078125) * cloth_neubelt_visibility(v.z, l.z));
    let wrap = clamp((l.z + 0.5) / 2.25, 0.0, 1.0);
    let fd = base / CLOTH_STOCK_PI * wrap * clamp(subsurface + vec3<f32>(l.z), vec3<f32>(0.0), vec3<f32>(1.0));
    return fd + fr * l.z;
}
