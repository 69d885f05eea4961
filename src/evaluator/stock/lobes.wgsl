// The lobes several stock models share, in f32: each function mirrors the one of the same
// name in lobes.rs beside this file (tests/gpu/render.rs renders every stock unit against
// its CPU evaluation). Directions are in the patch frame (x the tangent, z the normal).

const CLOTH_STOCK_PI: f32 = 3.14159265;

// `charlie_d`: Estevez and Kulla's sheen distribution, α the squared sheen roughness.
fn cloth_charlie_d(alpha: f32, n_dot_h: f32, sin2_floor: f32) -> f32 {
    let sin2 = max(1.0 - n_dot_h * n_dot_h, sin2_floor);
    return (2.0 + 1.0 / alpha) * pow(sin2, 0.5 / alpha) / (2.0 * CLOTH_STOCK_PI);
}

fn cloth_charlie_l(a: f32, b: f32, c: f32, d: f32, e: f32, x: f32) -> f32 {
    return a / (1.0 + b * pow(x, c)) + d * x + e;
}

// `charlie_lambda`: the fit of Λ with its coefficients interpolated in (1 − α)².
fn cloth_charlie_lambda(alpha: f32, cosine: f32) -> f32 {
    let t = (1.0 - alpha) * (1.0 - alpha);
    let a = mix(21.5473, 25.3245, t);
    let b = mix(3.82987, 3.32435, t);
    let c = mix(0.19823, 0.16801, t);
    let d = mix(-1.97760, -1.27393, t);
    let e = mix(-4.32054, -4.85967, t);
    let mu = abs(cosine);
    if mu < 0.5 {
        return exp(cloth_charlie_l(a, b, c, d, e, mu));
    }
    return exp(2.0 * cloth_charlie_l(a, b, c, d, e, 0.5) - cloth_charlie_l(a, b, c, d, e, 1.0 - mu));
}

// `charlie_visibility`.
fn cloth_charlie_visibility(alpha: f32, n_dot_v: f32, n_dot_l: f32) -> f32 {
    let lambdas = 1.0 + cloth_charlie_lambda(alpha, n_dot_v) + cloth_charlie_lambda(alpha, n_dot_l);
    return 1.0 / (lambdas * 4.0 * n_dot_v * n_dot_l);
}

// `neubelt_visibility`.
fn cloth_neubelt_visibility(n_dot_v: f32, n_dot_l: f32) -> f32 {
    return 1.0 / (4.0 * (n_dot_l + n_dot_v - n_dot_l * n_dot_v));
}

// `schlick_weight`: (1 − |v·h|)⁵.
fn cloth_schlick_weight(v_dot_h: f32) -> f32 {
    let x = clamp(1.0 - abs(v_dot_h), 0.0, 1.0);
    let x2 = x * x;
    return x2 * x2 * x;
}

// `ggx_anisotropic_d`.
fn cloth_ggx_anisotropic_d(at: f32, ab: f32, t: vec3<f32>, b: vec3<f32>, h: vec3<f32>) -> f32 {
    let x = dot(h, t) / at;
    let y = dot(h, b) / ab;
    let s = x * x + y * y + h.z * h.z;
    return 1.0 / (CLOTH_STOCK_PI * at * ab * s * s);
}

// `ggx_anisotropic_v`.
fn cloth_ggx_anisotropic_v(
    at: f32,
    ab: f32,
    t: vec3<f32>,
    b: vec3<f32>,
    v: vec3<f32>,
    l: vec3<f32>,
) -> f32 {
    let lambda_v = length(vec3<f32>(at * dot(v, t), ab * dot(v, b), v.z));
    let lambda_l = length(vec3<f32>(at * dot(l, t), ab * dot(l, b), l.z));
    return 0.5 / (l.z * lambda_v + v.z * lambda_l);
}
