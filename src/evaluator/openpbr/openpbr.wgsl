// OpenPBR Surface's fuzz over its dielectric specular over a Lambert base, as MaterialX 1.39
// builds it: the twin of `eval` in mod.rs (and of zeltner.rs) beside this file, over the
// stock block (base_color rgb 0–2, specular_roughness 3, specular_roughness_anisotropy 4,
// fuzz_weight 5, fuzz_color rgb 6–8, fuzz_roughness 9).
//
// requires: evaluator/stock, evaluator/stock_lobes

// `fresnel_dielectric`.
fn cloth_openpbr_fresnel(c: f32, eta: f32) -> f32 {
    let g2 = eta * eta + c * c - 1.0;
    if g2 < 0.0 {
        return 1.0;
    }
    let g = sqrt(g2);
    let a = (g - c) / (g + c);
    let b = ((g + c) * c - 1.0) / ((g - c) * c + 1.0);
    return 0.5 * a * a * (1.0 + b * b);
}

// `ggx_dir_albedo`.
fn cloth_openpbr_ggx_albedo(x: f32, y: f32, f0: f32, f90: f32) -> f32 {
    let r = vec4<f32>(0.1003, 0.9345, 1.0, 1.0)
        + vec4<f32>(-0.6303, -2.323, -1.765, 0.2281) * x
        + vec4<f32>(9.748, 2.229, 8.263, 15.94) * y
        + vec4<f32>(-2.038, -3.748, 11.53, -55.83) * x * y
        + vec4<f32>(29.34, 1.424, 28.96, 13.08) * x * x
        + vec4<f32>(-8.245, -0.7684, -7.507, 41.26) * y * y
        + vec4<f32>(-26.44, 1.436, -36.11, 54.9) * x * x * y
        + vec4<f32>(19.99, 0.2913, 15.86, 300.2) * x * y * y
        + vec4<f32>(-5.448, 0.6286, 33.37, -285.1) * x * x * y * y;
    let ab = clamp(r.xy / r.zw, vec2<f32>(0.0), vec2<f32>(1.0));
    return f0 * ab.x + f90 * ab.y;
}

// `zeltner::dir_albedo`.
fn cloth_zeltner_albedo(mu: f32, y: f32) -> f32 {
    let s = y * (0.0206607 + 1.58491 * y) / (0.0379424 + y * (1.32227 + y));
    let m = y * (-0.193854 + y * (-1.14885 + y * (1.7932 - 0.95943 * y * y))) / (0.046391 + y);
    let o = y * (0.000654023 + (-0.0207818 + 0.119681 * y) * y) / (1.26264 + y * (-1.92021 + y));
    let z = (mu - m) / s;
    return exp(-0.5 * z * z) / (s * 2.50662827) + o;
}

// `zeltner::ltc_brdf`.
fn cloth_zeltner_ltc(l: vec3<f32>, v: vec3<f32>, r: f32) -> f32 {
    let x = v.z;
    let a_inv = (2.58126 * x + 0.813703 * r) * r / (1.0 + 0.310327 * x * x + 2.60994 * x * r);
    let b_inv = sqrt(1.0 - x) * (r - 1.0) * r * r * r
        / (0.0000254053 + 1.71228 * x - 1.71506 * x * r + 1.34174 * r * r);
    let tangential = vec3<f32>(v.x, v.y, 0.0);
    var ax = vec3<f32>(1.0, 0.0, 0.0);
    if dot(tangential, tangential) > 0.0 {
        ax = normalize(tangential);
    }
    let ay = cross(vec3<f32>(0.0, 0.0, 1.0), ax);
    let w = vec3<f32>(dot(l, ax), dot(l, ay), l.z);
    let t = vec3<f32>(a_inv * w.x + b_inv * w.z, a_inv * w.y, w.z);
    let q = a_inv / dot(t, t);
    return max(t.z, 0.0) / CLOTH_STOCK_PI * q * q;
}

// `eval`: F for l = wi, v = wo above the horizon and their half vector h.
fn cloth_stock_f(l: vec3<f32>, v: vec3<f32>, h: vec3<f32>) -> vec3<f32> {
    let base = cloth_stock_colour(0u);
    let roughness = cloth_stock_parameter(3u);
    let anisotropy = cloth_stock_parameter(4u);
    let fuzz_weight = cloth_stock_parameter(5u);
    let fuzz_colour = cloth_stock_colour(6u);
    let fuzz_roughness = clamp(cloth_stock_parameter(9u), 0.01, 1.0);

    let r2 = roughness * roughness;
    let one_minus = 1.0 - anisotropy;
    let ax = clamp(r2 * sqrt(2.0 / (1.0 + one_minus * one_minus)), 1e-6, 1.0);
    let ay = clamp(one_minus * ax, 1e-6, 1.0);
    let mean_alpha = sqrt(ax * ay);
    let d = cloth_ggx_anisotropic_d(ax, ay, vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 1.0, 0.0), h);
    let a2 = mean_alpha * mean_alpha;
    let lambda_l = sqrt(a2 + (1.0 - a2) * l.z * l.z);
    let lambda_v = sqrt(a2 + (1.0 - a2) * v.z * v.z);
    let g2 = 2.0 * l.z * v.z / (lambda_l * v.z + lambda_v * l.z);
    let fresnel = cloth_openpbr_fresnel(dot(v, h), 1.5);
    let ess = cloth_openpbr_ggx_albedo(v.z, mean_alpha, 1.0, 1.0);
    let compensation = 1.0 + fresnel * (1.0 - ess) / ess;
    let specular = d * fresnel * g2 * compensation / (4.0 * v.z);
    let specular_throughput = 1.0 - cloth_openpbr_ggx_albedo(v.z, mean_alpha, 0.04, 1.0) * compensation;
    let below_fuzz = vec3<f32>(specular) + base * (l.z / CLOTH_STOCK_PI) * specular_throughput;

    let albedo = cloth_zeltner_albedo(v.z, fuzz_roughness);
    let fuzz = fuzz_colour * (fuzz_weight * albedo * cloth_zeltner_ltc(l, v, fuzz_roughness));
    return fuzz + below_fuzz * (1.0 - fuzz_weight * albedo);
}
