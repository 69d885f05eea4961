// Direct evaluation of the patch transfer F(wi, wo) of MODEL.md in f32, paper mode: the
// curve mean ⟨x⟩_j of each thread is the weighted sum over the tangent nodes that the CPU's
// `curve_pieces(thread, options, Integration::Paper(N))` produces (uploaded by
// src/gpu/direct.rs as (cos α, sin α, weight)). Mirrors `ThreadModel::means`,
// `ThreadModel::accumulate` and `Patch::terms` of src/model/patch.rs (same quantities, same
// bounded products, clipping and degenerate-projection rules) and `fresnel_dielectric` of
// src/model/lobes.rs. Paper-mode nodes are single points, so the interval clipping of the
// direct rule never applies.
//
// Where the CPU's f64 formulas lose their accuracy in f32, mathematically identical forms
// that keep it are used instead: cos²θd near θd → ±π/2 (both directions near ±t), 1 − Fr
// near grazing Fresnel incidence, and φd, ψd, cos(φd/2) by half-angle forms instead of
// acos and √((1 + cos)/2). tests/gpu_direct.rs bounds the difference to the CPU.
//
// Every top-level name starts with `cloth_`/`Cloth` (the `GpuBrdf` naming contract).

// One thread family (`DirectThread` in src/gpu/direct.rs).
struct ClothDirectThread {
    // Base tangent t0 (xyz).
    t0: vec4<f32>,
    // Rotation axis b (xyz).
    b: vec4<f32>,
    // RGB albedo A = albedo_scale · albedo.
    albedo: vec4<f32>,
    // Surface lobe −1/(2σs²), 1/(σs√(2π)); volume lobe −1/(2σv²), 1/(σv√(2π)) (radians).
    lobes: vec4<f32>,
    // η, kd, coverage a, 1 if η == 1 exactly (no interface: Fr = 0) else 0.
    material: vec4<f32>,
    // First node in cloth_direct_nodes, node count.
    nodes: vec4<u32>,
}

struct ClothDirectParams {
    threads: array<ClothDirectThread, 2>,
    // −1/(2σu²) of the reweighting Gaussian u, gap = max(1 − a1 − a2, 0), the degenerate
    // projection threshold (largest f32 below DEGENERATE_PROJECTION: `<=` it is
    // degenerate, exactly as `< 1e-9` in f64 for f32-representable lengths), 0.
    misc: vec4<f32>,
}

@group(0) @binding(0) var<uniform> cloth_direct: ClothDirectParams;
// Tangent nodes of both threads: (cos α, sin α, weight, 0); weights of a thread sum to 1.
@group(0) @binding(1) var<storage, read> cloth_direct_nodes: array<vec4<f32>>;

// `reweighted`: (1 − u)·a·b + u·min(a, b).
fn cloth_direct_reweighted(u: f32, a: f32, b: f32) -> f32 {
    return (1.0 - u) * a * b + u * min(a, b);
}

// `fresnel_dielectric` as (Fr, (1 − Fr)²), the Fresnel reflectance from air into η at
// incidence cosine cos_i and the two-way transmittance Ft. 1 − Fr is formed without
// cancellation, `1 − rs² = 4 cos i η cos t/(cos i + η cos t)²` and likewise for rp, so Ft
// keeps its relative accuracy at grazing incidence, where Fr → 1.
fn cloth_direct_fresnel(eta: f32, no_interface: bool, cos_i_in: f32) -> vec2<f32> {
    if no_interface {
        return vec2<f32>(0.0, 1.0);
    }
    let cos_i = clamp(cos_i_in, 0.0, 1.0);
    let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    let cos_t = sqrt(max(1.0 - sin2_t, 0.0));
    let ds = cos_i + eta * cos_t;
    let dp = eta * cos_i + cos_t;
    let rs = (cos_i - eta * cos_t) / ds;
    let rp = (eta * cos_i - cos_t) / dp;
    let transmitted = 2.0 * eta * cos_i * cos_t * (1.0 / (ds * ds) + 1.0 / (dp * dp));
    return vec2<f32>(0.5 * (rs * rs + rp * rp), transmitted * transmitted);
}

// For unit 2D vectors a and c: (the angle between them in [0, π], the cosine of half of
// it). Half-angle forms, angle = 2·atan2(|a − c|, |a + c|) and cos(angle/2) = |a + c|/2, keep
// their accuracy where acos(a·c) and √((1 + a·c)/2) lose it in f32 (a ≈ ±c).
fn cloth_direct_angle(a: vec2<f32>, c: vec2<f32>) -> vec2<f32> {
    let sum = length(a + c);
    return vec2<f32>(2.0 * atan2(length(a - c), sum), min(0.5 * sum, 1.0));
}

// `ThreadModel::means` of thread j: (⟨reflection⟩, ⟨transmission⟩, ⟨P⟩).
fn cloth_direct_means(j: u32, wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    let thread = cloth_direct.threads[j];
    let threshold = cloth_direct.misc.z;
    let t0 = thread.t0.xyz;
    let b = thread.b.xyz;
    let ti0 = dot(wi, t0);
    let zi = wi.z;
    let bi = dot(wi, b);
    let to0 = dot(wo, t0);
    let zo = wo.z;
    let bo = dot(wo, b);
    // |w∥| = √((w·t0)² + (w·z)²) does not depend on α; w ∥ b is degenerate for P and s.
    let par_i = sqrt(ti0 * ti0 + zi * zi);
    let par_o = sqrt(to0 * to0 + zo * zo);
    if par_i <= threshold || par_o <= threshold {
        return vec3<f32>(0.0);
    }
    let k_u = cloth_direct.misc.x;
    let psi_d = cloth_direct_angle(vec2<f32>(ti0, zi) / par_i, vec2<f32>(to0, zo) / par_o).x;
    let u_psi = exp(psi_d * psi_d * k_u);
    let eta = thread.material.x;
    let kd = thread.material.y;
    let no_interface = thread.material.w != 0.0;

    var sums = vec3<f32>(0.0);
    let first = thread.nodes.x;
    for (var k = first; k < first + thread.nodes.y; k++) {
        let node = cloth_direct_nodes[k];
        let cos_a = node.x;
        let sin_a = node.y;
        // w·n(α); a sample facing away from either direction has M = P = 0.
        let ni = zi * cos_a - ti0 * sin_a;
        let no = zo * cos_a - to0 * sin_a;
        if ni <= 0.0 || no <= 0.0 {
            continue;
        }
        // cos θ = |w⊥| = √((w·n)² + (w·b)²); w ∥ t is degenerate.
        let perp_i = sqrt(ni * ni + bi * bi);
        let perp_o = sqrt(no * no + bo * bo);
        if perp_i <= threshold || perp_o <= threshold {
            continue;
        }
        let weight = node.z;
        let masking_p = cloth_direct_reweighted(u_psi, ni / par_i, no / par_o);
        sums.z += weight * masking_p;

        // φd between the unit projections w⊥/|w⊥| = ((w·n), (w·b))/|w⊥|.
        let phi = cloth_direct_angle(vec2<f32>(ni, bi) / perp_i, vec2<f32>(no, bo) / perp_o);
        let u_phi = exp(phi.x * phi.x * k_u);
        let cos_half_phi_d = phi.y;
        let shadowing_m = cloth_direct_reweighted(u_phi, ni / perp_i, no / perp_o);

        // θ from atan2 of accurate sine (w·t) and cosine (|w⊥|).
        let si = ti0 * cos_a + zi * sin_a;
        let so = to0 * cos_a + zo * sin_a;
        let theta_i = atan2(si, perp_i);
        let theta_o = atan2(so, perp_o);
        let theta_h = 0.5 * (theta_i + theta_o);
        // cos²θd = (1 + cos(θi − θo))/2 = (1 + ĉi ĉo + ŝi ŝo)/2 with (ĉ, ŝ) = (cos θ, sin θ).
        // When ŝi ŝo < 0 it cancels as both directions approach ±t (θd → ±π/2, where the CPU's
        // f64 cos((θi − θo)/2) is still accurate but f32 is not): there
        // 1 + ŝi ŝo = di + do − di do with d = 1 − |ŝ| = ĉ²/(1 + |ŝ|), all terms accurate.
        let ri = sqrt(si * si + perp_i * perp_i);
        let ro = sqrt(so * so + perp_o * perp_o);
        let ci = perp_i / ri;
        let co = perp_o / ro;
        let sin_i = si / ri;
        let sin_o = so / ro;
        var cos2_theta_d = 0.5 * (1.0 + ci * co + sin_i * sin_o);
        if sin_i * sin_o < 0.0 {
            let di = ci * ci / (1.0 + abs(sin_i));
            let do_ = co * co / (1.0 + abs(sin_o));
            cos2_theta_d = 0.5 * (di + do_ - di * do_ + ci * co);
        }
        cos2_theta_d = min(cos2_theta_d, 1.0);
        let fresnel = cloth_direct_fresnel(eta, no_interface, sqrt(cos2_theta_d) * cos_half_phi_d);
        let fr = fresnel.x;
        let ft = fresnel.y;

        // The bounded products: M·P·cos θi/cos²θd, and cos θi/(cos θi + cos θo) ≤ 1.
        let product = weight * shadowing_m * masking_p / cos2_theta_d;
        let theta_h2 = theta_h * theta_h;
        let surface = thread.lobes.y * exp(theta_h2 * thread.lobes.x);
        let volume = (1.0 - kd) * thread.lobes.w * exp(theta_h2 * thread.lobes.z) + kd;
        sums.x += product * fr * cos_half_phi_d * surface * perp_i;
        sums.y += product * ft * volume * (perp_i / (perp_i + perp_o));
    }
    return sums;
}

// `Patch::eval`: F = [a1⟨s⟩1 + a2⟨s⟩2]/Q, Q = a1⟨P⟩1 + a2⟨P⟩2 + gap·wo.z; 0 below the
// horizon and where Q = 0.
fn cloth_brdf(wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    if wi.z <= 0.0 || wo.z <= 0.0 {
        return vec3<f32>(0.0);
    }
    let m1 = cloth_direct_means(0u, wi, wo);
    let m2 = cloth_direct_means(1u, wi, wo);
    let a1 = cloth_direct.threads[0].material.z;
    let a2 = cloth_direct.threads[1].material.z;
    let q = a1 * m1.z + a2 * m2.z + cloth_direct.misc.y * wo.z;
    if q <= 0.0 {
        return vec3<f32>(0.0);
    }
    let reflection = (a1 * m1.x + a2 * m2.x) / q;
    let transmission1 = a1 * m1.y / q;
    let transmission2 = a2 * m2.y / q;
    return vec3<f32>(reflection) + cloth_direct.threads[0].albedo.xyz * transmission1
        + cloth_direct.threads[1].albedo.xyz * transmission2;
}
