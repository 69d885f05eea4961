// glTF 2.0's material with KHR_materials_sheen and KHR_materials_anisotropy: the twin of
// `eval` in mod.rs beside this file, over the stock block (parameters in the order of its
// list: baseColor rgb 0–2, metallic 3, roughness 4, anisotropy strength 5 and rotation 6,
// sheenColor rgb 7–9, sheenRoughness 10; derived: the sheen albedo E at 32 μ nodes).
//
// requires: evaluator/stock, evaluator/stock_lobes

// `sheen_albedo::albedo_at`: E(μ), linear between the derived nodes.
fn cloth_gltf_sheen_albedo(mu: f32) -> f32 {
    let x = clamp(mu, 0.0, 1.0) * 31.0;
    let k = min(u32(floor(x)), 30u);
    let t = x - f32(k);
    let a = cloth_stock_derived(k);
    return a + (cloth_stock_derived(k + 1u) - a) * t;
}

// `eval`: F for l = wi, v = wo above the horizon and their half vector h.
fn cloth_stock_f(l: vec3<f32>, v: vec3<f32>, h: vec3<f32>) -> vec3<f32> {
    let base = cloth_stock_colour(0u);
    let metallic = cloth_stock_parameter(3u);
    let roughness = cloth_stock_parameter(4u);
    let strength = cloth_stock_parameter(5u);
    let rotation = cloth_stock_parameter(6u);
    let sheen = cloth_stock_colour(7u);
    let sheen_roughness = cloth_stock_parameter(10u);
    let sheen_alpha = sheen_roughness * sheen_roughness;

    let alpha = roughness * roughness;
    let at = alpha + (1.0 - alpha) * strength * strength;
    let t = vec3<f32>(cos(rotation), sin(rotation), 0.0);
    let b = vec3<f32>(-sin(rotation), cos(rotation), 0.0);
    let specular = cloth_ggx_anisotropic_v(at, alpha, t, b, v, l)
        * cloth_ggx_anisotropic_d(at, alpha, t, b, h);
    let w = cloth_schlick_weight(dot(v, h));
    let fresnel = 0.04 + 0.96 * w;
    let dielectric = base / CLOTH_STOCK_PI * (1.0 - fresnel) + vec3<f32>(specular * fresnel);
    let metal = specular * (base + (vec3<f32>(1.0) - base) * w);
    let material = mix(dielectric, metal, metallic);

    let sheen_brdf = sheen * cloth_charlie_d(sheen_alpha, h.z, 0.0)
        * cloth_charlie_visibility(sheen_alpha, v.z, l.z);
    let m = max(sheen.x, max(sheen.y, sheen.z));
    let scaling = min(
        1.0 - m * cloth_gltf_sheen_albedo(v.z),
        1.0 - m * cloth_gltf_sheen_albedo(l.z),
    );
    return (sheen_brdf + material * scaling) * l.z;
}
