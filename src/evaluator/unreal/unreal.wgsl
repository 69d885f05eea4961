// Unreal Engine's Cloth shading model: the twin of `eval` in mod.rs beside this file, over
// the stock block (BaseColor rgb 0–2, Metallic 3, Specular 4, Roughness 5, FuzzColor rgb
// 6–8, Cloth 9).
//
// requires: evaluator/stock, evaluator/stock_lobes

// `f_schlick`.
fn cloth_unreal_f_schlick(s: vec3<f32>, v_dot_h: f32) -> vec3<f32> {
    let fc = cloth_schlick_weight(v_dot_h);
    return vec3<f32>(clamp(50.0 * s.y, 0.0, 1.0) * fc) + (1.0 - fc) * s;
}

// `d_inv_ggx`.
fn cloth_unreal_d_inv_ggx(a2: f32, n_dot_h: f32) -> f32 {
    let d = (n_dot_h - a2 * n_dot_h) * n_dot_h + a2;
    return (1.0 + 4.0 * a2 * a2 / (d * d)) / (CLOTH_STOCK_PI * (1.0 + 4.0 * a2));
}

// `d_ggx`.
fn cloth_unreal_d_ggx(a2: f32, n_dot_h: f32) -> f32 {
    let d = (n_dot_h * a2 - n_dot_h) * n_dot_h + 1.0;
    return a2 / (CLOTH_STOCK_PI * d * d);
}

// `vis_smith_joint_approx`.
fn cloth_unreal_vis_smith(a2: f32, n_dot_v: f32, n_dot_l: f32) -> f32 {
    let a = sqrt(a2);
    return 0.5 / (n_dot_l * (n_dot_v * (1.0 - a) + a) + n_dot_v * (n_dot_l * (1.0 - a) + a));
}

// `eval`: F for l = wi, v = wo above the horizon and their half vector h.
fn cloth_stock_f(l: vec3<f32>, v: vec3<f32>, h: vec3<f32>) -> vec3<f32> {
    let base = cloth_stock_colour(0u);
    let metallic = cloth_stock_parameter(3u);
    let specular = cloth_stock_parameter(4u);
    let roughness = cloth_stock_parameter(5u);
    let fuzz = cloth_stock_colour(6u);
    let cloth = cloth_stock_parameter(9u);
    let r2 = roughness * roughness;
    let a2 = r2 * r2;
    let diffuse = base * (1.0 - metallic) / CLOTH_STOCK_PI;
    let specular_colour = mix(vec3<f32>(0.08 * specular), base, metallic);
    let v_dot_h = dot(v, h);
    let spec1 = cloth_unreal_f_schlick(specular_colour, v_dot_h)
        * (cloth_unreal_d_ggx(a2, h.z) * cloth_unreal_vis_smith(a2, v.z, l.z));
    let spec2 = cloth_unreal_f_schlick(fuzz, v_dot_h)
        * (cloth_unreal_d_inv_ggx(a2, h.z) * cloth_neubelt_visibility(v.z, l.z));
    return (diffuse + mix(spec1, spec2, cloth)) * l.z;
}
