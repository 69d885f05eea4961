// One tangent sample of one thread family in f32: `ThreadModel::pair_frame` and
// `ThreadModel::sample` of src/model/patch.rs (and `fresnel_dielectric` of
// src/model/lobes.rs), shared by the shaders that evaluate the model itself (evaluator/paper,
// paper mode; evaluator/resonant_quadrature, the resonant quadrature; split_frame's point
// masses), as both CPU rules share `ThreadModel::sample`. Those modules require it (the
// composer, src/shader/mod.rs, writes it before them).
//
// Where the CPU's f64 formulas lose their accuracy in f32, mathematically identical forms
// that keep it are used instead: cos²θd near θd → ±π/2 (both directions near ±t), 1 − Fr
// near grazing Fresnel incidence, and φd, ψd, cos(φd/2) by half-angle forms instead of
// acos and √((1 + cos)/2). tests/gpu/paper.rs and tests/gpu/resonant.rs bound the
// difference to the CPU.

// A direction pair in a thread's fixed axes {t0, b, z} with the α-independent parts of P
// (`PairInThreadFrame`).
struct ClothSamplePair {
    ti0: f32,
    zi: f32,
    bi: f32,
    to0: f32,
    zo: f32,
    bo: f32,
    // |w∥| = √((w·t0)² + (w·z)²), independent of α, and its reciprocal.
    par_i: f32,
    par_o: f32,
    inverse_par_i: f32,
    inverse_par_o: f32,
    // u(ψd), the reweighting of P.
    u_psi: f32,
}

// What the sample needs of a thread family and of the fabric.
struct ClothSampleMaterial {
    // Surface lobe −1/(2σs²), 1/(σs√(2π)); volume lobe −1/(2σv²), 1/(σv√(2π)) (radians).
    lobes: vec4<f32>,
    eta: f32,
    kd: f32,
    // 1 if η == 1 exactly (no interface: Fr = 0) else 0.
    no_interface: f32,
    // −1/(2σu²) of the reweighting Gaussian u.
    k_u: f32,
    // Degenerate projection threshold (largest f32 below DEGENERATE_PROJECTION: `<=` it is
    // degenerate, exactly as `< 1e-9` in f64 for f32-representable lengths).
    threshold: f32,
}

// `reweighted`: (1 − u)·a·b + u·min(a, b).
fn cloth_sample_reweighted(u: f32, a: f32, b: f32) -> f32 {
    return (1.0 - u) * a * b + u * min(a, b);
}

// `fresnel_dielectric` as (Fr, (1 − Fr)²), the Fresnel reflectance from air into η at
// incidence cosine cos_i and the two-way transmittance Ft. 1 − Fr is formed without
// cancellation, `1 − rs² = 4 cos i η cos t/(cos i + η cos t)²` and likewise for rp, so Ft
// keeps its relative accuracy at grazing incidence, where Fr → 1.
fn cloth_sample_fresnel(eta: f32, no_interface: bool, cos_i_in: f32) -> vec2<f32> {
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

// The surface and volume lobes at θh² (each unit-area Gaussian norm·exp(k·θh²)). Where
// σv = 2σs (every built-in thread but crepe's second) ks = 4kv holds exactly in f32, and the
// surface Gaussian is the volume Gaussian to the fourth power: one exp instead of two.
fn cloth_sample_lobes(lobes: vec4<f32>, theta_h2: f32) -> vec2<f32> {
    let volume = exp(theta_h2 * lobes.z);
    var surface: f32;
    if lobes.x == 4.0 * lobes.z {
        let square = volume * volume;
        surface = square * square;
    } else {
        surface = exp(theta_h2 * lobes.x);
    }
    return vec2<f32>(lobes.y * surface, lobes.w * volume);
}

// For unit 2D vectors a and c: (the angle between them in [0, π], the cosine of half of
// it). Half-angle forms, angle = 2·atan2(|a − c|, |a + c|) and cos(angle/2) = |a + c|/2, keep
// their accuracy where acos(a·c) and √((1 + a·c)/2) lose it in f32 (a ≈ ±c).
fn cloth_sample_angle(a: vec2<f32>, c: vec2<f32>) -> vec2<f32> {
    let sum = length(a + c);
    return vec2<f32>(2.0 * atan2(length(a - c), sum), min(0.5 * sum, 1.0));
}

// `pair_frame`: wi, wo in the axes {t0, b, z} of a thread. The caller checks par_i and
// par_o against the threshold (w ∥ b is degenerate for P and s) before using u_psi.
fn cloth_sample_pair(wi: vec3<f32>, wo: vec3<f32>, t0: vec3<f32>, b: vec3<f32>, k_u: f32) -> ClothSamplePair {
    var p: ClothSamplePair;
    p.ti0 = dot(wi, t0);
    p.zi = wi.z;
    p.bi = dot(wi, b);
    p.to0 = dot(wo, t0);
    p.zo = wo.z;
    p.bo = dot(wo, b);
    p.par_i = sqrt(p.ti0 * p.ti0 + p.zi * p.zi);
    p.par_o = sqrt(p.to0 * p.to0 + p.zo * p.zo);
    p.inverse_par_i = 1.0 / p.par_i;
    p.inverse_par_o = 1.0 / p.par_o;
    let psi_d = cloth_sample_angle(vec2<f32>(p.ti0, p.zi) / p.par_i,
        vec2<f32>(p.to0, p.zo) / p.par_o).x;
    p.u_psi = exp(psi_d * psi_d * k_u);
    return p;
}

// `ThreadModel::sample` at the tangent offset with cosine cos_a and sine sin_a:
// (P, reflection, volume, diffuse) of `SampleTerms`, 0 where either direction faces away
// (M = P = 0) or a projection is degenerate.
fn cloth_sample_terms(p: ClothSamplePair, m: ClothSampleMaterial, cos_a: f32, sin_a: f32) -> vec4<f32> {
    // w·n(α).
    let ni = p.zi * cos_a - p.ti0 * sin_a;
    let no = p.zo * cos_a - p.to0 * sin_a;
    if ni <= 0.0 || no <= 0.0 {
        return vec4<f32>(0.0);
    }
    // cos θ = |w⊥| = √((w·n)² + (w·b)²); w ∥ t is degenerate.
    let perp_i = sqrt(ni * ni + p.bi * p.bi);
    let perp_o = sqrt(no * no + p.bo * p.bo);
    if perp_i <= m.threshold || perp_o <= m.threshold {
        return vec4<f32>(0.0);
    }
    let masking_p = cloth_sample_reweighted(p.u_psi, ni * p.inverse_par_i, no * p.inverse_par_o);

    // φd between the unit projections w⊥/|w⊥| = ((w·n), (w·b))/|w⊥|.
    let inverse_perp_i = 1.0 / perp_i;
    let inverse_perp_o = 1.0 / perp_o;
    let mi = ni * inverse_perp_i;
    let mo = no * inverse_perp_o;
    let phi = cloth_sample_angle(vec2<f32>(mi, p.bi * inverse_perp_i),
        vec2<f32>(mo, p.bo * inverse_perp_o));
    let u_phi = exp(phi.x * phi.x * m.k_u);
    let cos_half_phi_d = phi.y;
    let shadowing_m = cloth_sample_reweighted(u_phi, mi, mo);

    // θh and cos²θd as `half_angle_and_difference` (src/model/sample.rs) takes them: (|w⊥|, w·t)
    // is each direction's (cos θ, sin θ), of length |w| = 1, so their sum is
    // 2 cos θd (cos θh, sin θh). Its x is a sum of non-negative terms, so cos²θd keeps its
    // relative accuracy as both directions approach ±t, where y cancels.
    let si = p.ti0 * cos_a + p.zi * sin_a;
    let so = p.to0 * cos_a + p.zo * sin_a;
    let x = perp_i + perp_o;
    let y = si + so;
    let theta_h = atan2(y, x);
    let cos2_theta_d = min(0.25 * (x * x + y * y), 1.0);
    let fresnel = cloth_sample_fresnel(m.eta, m.no_interface != 0.0,
        sqrt(cos2_theta_d) * cos_half_phi_d);

    // The bounded products: M·P·cos θi/cos²θd, and cos θi/(cos θi + cos θo) ≤ 1.
    let bounded = shadowing_m * masking_p / cos2_theta_d;
    let transmission = bounded * fresnel.y * (perp_i / (perp_i + perp_o));
    let lobes = cloth_sample_lobes(m.lobes, theta_h * theta_h);
    return vec4<f32>(
        masking_p,
        bounded * fresnel.x * cos_half_phi_d * lobes.x * perp_i,
        transmission * (1.0 - m.kd) * lobes.y,
        transmission * m.kd);
}
