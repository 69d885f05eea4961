// The resonant quadrature (`Integration::Resonant`, src/model/resonant.rs) in f32: the
// curve means ⟨s⟩_j, ⟨P⟩_j of docs/model.md from Gauss–Legendre nodes placed per pair on each
// lobe, in the Gaussian-CDF variable t = Φ(z), plus base nodes in α. Mirrors
// `ResonantRule::means`/`segment` (same node placement, same thresholds) and
// `ThreadModel::sample`/`pair_frame` of src/model/patch.rs.
//
// This file is a template: kernel.rs beside it generates, per node counts, the constants it
// names (`CLOTH_RESONANT_*`: thresholds from the Rust constants and the Gauss–Legendre rules
// computed in f64 and rounded, the generated module `resonant_rules` that this file requires).
// Nothing here depends on a fabric: a thread's parameters come in as a `ClothResonantThread`
// and its curve pieces as arguments of `cloth_resonant_point` and `cloth_resonant_segment`,
// which resonant.wgsl reads from the fabric block in group 0 and calls once per piece of the
// thread (gpu.rs; the block is a buffer so that the editor's edits need no new shader).
//
// Where f32 would lose what f64 keeps:
// - Φ in the lower tail comes from erfc of a positive argument (relative accuracy ~1e-7
//   down to Φ ≈ 1e-38), and the segment is reflected to lie in the lower tail as on the
//   CPU; a node past the median is placed from the complement 1 − t = Φ(−b) + span·(1 − x),
//   so Φ⁻¹ never sees a p near 1, where f32 has no digits left.
// - The sample itself is model/tangent_sample.wgsl's (required below), with its f32 forms of
//   cos²θd, 1 − Fr and the angles φd, ψd.
//
// Every top-level name starts with `cloth_`/`Cloth`/`CLOTH_` (the `GpuBrdf` naming contract).
//
// requires: model/tangent_sample, resonant_rules

// One thread family (built by resonant.wgsl's `cloth_resonant_means` from the fabric block).
struct ClothResonantThread {
    // Base tangent t0 and rotation axis b.
    t0: vec3<f32>,
    b: vec3<f32>,
    // Lobe standard deviations σs, σv in radians.
    sigma: vec2<f32>,
    // Surface −1/(2σs²), 1/(σs√(2π)); volume −1/(2σv²), 1/(σv√(2π)).
    lobes: vec4<f32>,
    // η, kd, 1 if η == 1 exactly (no interface: Fr = 0) else 0, and the fabric's
    // −1/(2σu²) of the reweighting Gaussian u.
    material: vec4<f32>,
}

// `PairInThreadFrame` with the facing window and the resonant offset α*.
struct ClothResonantPair {
    s: ClothSamplePair,
    // α interval where both directions face the tangent sample.
    facing: vec2<f32>,
    resonant: f32,
    // `kinks`: where the reweighted min of P and of M have kinks inside the facing window,
    // increasing; an unused slot holds facing.y, which no clipped segment has inside it.
    kinks: vec2<f32>,
    // 0 where a direction is parallel to b (no sample contributes).
    valid: u32,
}

// erfc(x) for x ≥ 0: Numerical Recipes' Chebyshev fit `erfcc` (fractional error < 1.2e-7
// everywhere), a relative error that holds in the far tail, unlike 1 − erf.
fn cloth_resonant_erfc_positive(x: f32) -> f32 {
    let t = 1.0 / (1.0 + 0.5 * x);
    let poly = -1.26551223 + t * (1.00002368 + t * (0.37409196 + t * (0.09678418
        + t * (-0.18628806 + t * (0.27886807 + t * (-1.13520398 + t * (1.48851587
        + t * (-0.82215223 + t * 0.17087277))))))));
    return t * exp(-x * x + poly);
}

// Φ(z) = erfc(−z/√2)/2; for z > 0 from the complement, so Φ(z) for z ≤ 0 keeps its
// relative accuracy (the only side the node placement relies on for small values).
fn cloth_resonant_cdf(z: f32) -> f32 {
    let x = abs(z) * 0.70710678;
    let tail = 0.5 * cloth_resonant_erfc_positive(x);
    return select(tail, 1.0 - tail, z > 0.0);
}

// (Φ(w), Φ(−w)) from one erfc: the smaller of the two keeps its relative accuracy.
fn cloth_resonant_cdf_pair(w: f32) -> vec2<f32> {
    let tail = 0.5 * cloth_resonant_erfc_positive(abs(w) * 0.70710678);
    return select(vec2<f32>(tail, 1.0 - tail), vec2<f32>(1.0 - tail, tail), w > 0.0);
}

// φ(z), the standard normal density.
fn cloth_resonant_pdf(z: f32) -> f32 {
    return 0.39894228 * exp(-0.5 * z * z);
}

// Φ⁻¹(p) for p in (0, 1/2]: Acklam's rational approximation (relative error 1.2e-9, far
// below f32) and one Halley step on Φ(z) − p as on the CPU, which here corrects Acklam's
// f32 evaluation to the accuracy of `cloth_resonant_cdf`. p is kept above 0: the segments
// reaching this are within NEGLIGIBLE_LOBE_Z of the peak, so p ≥ Φ(−6)·x_min ≫ 1e-30.
fn cloth_resonant_quantile(p_in: f32) -> f32 {
    let p = max(p_in, 1e-30);
    var z: f32;
    if p < 0.02425 {
        let r = sqrt(-2.0 * log(p));
        z = (((((-7.784894002430293e-3 * r - 3.223964580411365e-1) * r - 2.400758277161838) * r
            - 2.549732539343734) * r + 4.374664141464968) * r + 2.938163982698783)
            / ((((7.784695709041462e-3 * r + 3.224671290700398e-1) * r + 2.445134137142996) * r
            + 3.754408661907416) * r + 1.0);
    } else {
        let q = p - 0.5;
        let r = q * q;
        z = (((((-3.969683028665376e1 * r + 2.209460984245205e2) * r - 2.759285104469687e2) * r
            + 1.383577518672690e2) * r - 3.066479806614716e1) * r + 2.506628277459239) * q
            / (((((-5.447609879822406e1 * r + 1.615858368580409e2) * r - 1.556989798598866e2) * r
            + 6.680131188771972e1) * r - 1.328068155288572e1) * r + 1.0);
    }
    // Halley on Φ(z) − p. The correction is relative to p (|u| ≲ 1e-6), so forming
    // e = Φ(z) − p in f32 costs no digits that the step needs.
    let e = cloth_resonant_cdf(z) - p;
    let u = e / cloth_resonant_pdf(z);
    return z - u / (1.0 + 0.5 * z * u);
}

// `ThreadModel::pair_frame` plus α* = −atan2(h·t0, h·z), h = wi + wo.
fn cloth_resonant_pair(thread: ClothResonantThread, wi: vec3<f32>, wo: vec3<f32>) -> ClothResonantPair {
    var p: ClothResonantPair;
    p.s = cloth_sample_pair(wi, wo, thread.t0, thread.b, thread.material.w);
    p.valid = 0u;
    if p.s.par_i <= CLOTH_RESONANT_THRESHOLD || p.s.par_o <= CLOTH_RESONANT_THRESHOLD {
        return p;
    }
    p.valid = 1u;
    let half_pi = 1.5707964;
    let delta_i = atan2(p.s.ti0, p.s.zi);
    let delta_o = atan2(p.s.to0, p.s.zo);
    p.facing = vec2<f32>(max(-half_pi - delta_i, -half_pi - delta_o),
        min(half_pi - delta_i, half_pi - delta_o));
    p.resonant = -atan2(p.s.ti0 + p.s.to0, p.s.zi + p.s.zo);
    p.kinks = cloth_resonant_kinks(p);
    return p;
}

// `kinks`: P(wi) = P(wo) at the facing window's centre; M(wi) = M(wo) where
// tan α = (|bo| zi − |bi| zo)/(|bo| ti0 − |bi| to0), the one solution inside the window if
// any (the window is narrower than π). As on the CPU, 0/0 (both b components 0) gives no M
// kink; atan2 folded to (−π/2, π/2] stands for atan of the quotient, ±π/2 where it is ±∞.
fn cloth_resonant_kinks(p: ClothResonantPair) -> vec2<f32> {
    let centre = 0.5 * (p.facing.x + p.facing.y);
    var kinks = vec2<f32>(centre, p.facing.y);
    let bi = abs(p.s.bi);
    let bo = abs(p.s.bo);
    let num = bo * p.s.zi - bi * p.s.zo;
    let den = bo * p.s.ti0 - bi * p.s.to0;
    if num == 0.0 && den == 0.0 {
        return kinks;
    }
    let pi = 3.14159265;
    var m = atan2(num, den);
    if m > 0.5 * pi {
        m -= pi;
    } else if m < -0.5 * pi {
        m += pi;
    }
    for (var k = -1.0; k <= 1.0; k += 1.0) {
        let a = m + k * pi;
        if a > p.facing.x && a < p.facing.y && a != centre {
            kinks = vec2<f32>(min(a, centre), max(a, centre));
        }
    }
    return kinks;
}

// `split_counts`: the nodes a part holding `fraction` of an interval gets out of its `n`,
// the share rounded up unless within CLOTH_RESONANT_SPLIT_TOLERANCE of a whole number, at
// least CLOTH_RESONANT_MIN_NODES_PER_PART (or n), at most n.
fn cloth_resonant_split_count(n: u32, fraction: f32) -> u32 {
    let share = u32(max(ceil(f32(n) * fraction - CLOTH_RESONANT_SPLIT_TOLERANCE), 0.0));
    return clamp(share, min(CLOTH_RESONANT_MIN_NODES_PER_PART, n), n);
}

// The first index of the n-point rule in `cloth_resonant_gl` (n ≥ 1).
fn cloth_resonant_rule_start(n: u32) -> u32 {
    return n * (n - 1u) / 2u;
}

// `theta_h_and_slope`: θh at α and dθh/dα = (cos φi + cos φo)/2.
fn cloth_resonant_theta_h(p: ClothResonantPair, alpha: f32) -> vec2<f32> {
    let cos_a = cos(alpha);
    let sin_a = sin(alpha);
    let ni = p.s.zi * cos_a - p.s.ti0 * sin_a;
    let no = p.s.zo * cos_a - p.s.to0 * sin_a;
    let si = p.s.ti0 * cos_a + p.s.zi * sin_a;
    let so = p.s.to0 * cos_a + p.s.zo * sin_a;
    let perp_i = sqrt(ni * ni + p.s.bi * p.s.bi);
    let perp_o = sqrt(no * no + p.s.bo * p.s.bo);
    let ki = select(0.0, ni / perp_i, perp_i > 0.0);
    let ko = select(0.0, no / perp_o, perp_o > 0.0);
    return vec2<f32>(0.5 * (atan2(si, perp_i) + atan2(so, perp_o)), 0.5 * (ki + ko));
}

// `ThreadModel::sample` at α (model/tangent_sample.wgsl): (P, reflection, volume, diffuse).
fn cloth_resonant_sample(thread: ClothResonantThread, p: ClothResonantPair, alpha: f32) -> vec4<f32> {
    var material: ClothSampleMaterial;
    material.lobes = thread.lobes;
    material.eta = thread.material.x;
    material.kd = thread.material.y;
    material.no_interface = thread.material.z;
    material.k_u = thread.material.w;
    material.threshold = CLOTH_RESONANT_THRESHOLD;
    return cloth_sample_terms(p.s, material, cos(alpha), sin(alpha));
}

// A flat piece: its whole share `weight` at α, every term, if α is inside the facing window.
// Returns (⟨reflection⟩, ⟨transmission⟩, ⟨P⟩) contributions.
fn cloth_resonant_point(thread: ClothResonantThread, p: ClothResonantPair, alpha: f32, weight: f32) -> vec3<f32> {
    if !(alpha > p.facing.x && alpha < p.facing.y) {
        return vec3<f32>(0.0);
    }
    let s = cloth_resonant_sample(thread, p, alpha);
    return weight * vec3<f32>(s.y, s.z + s.w, s.x);
}

// `ResonantRule::segment`: the segment [start, end] (density = share/length per radian)
// clipped to the facing window, its node sets split at the pair's kinks inside it. Returns
// (⟨reflection⟩, ⟨transmission⟩, ⟨P⟩) contributions.
fn cloth_resonant_segment(thread: ClothResonantThread, p: ClothResonantPair, start: f32, end: f32, density: f32) -> vec3<f32> {
    let lo = max(start, p.facing.x);
    let hi = min(end, p.facing.y);
    if lo >= hi {
        return vec3<f32>(0.0);
    }
    // `Segment::inner_cuts`: the kinks strictly inside [lo, hi], increasing, then hi.
    // Small arrays are vectors here (indexed alike): naga declares a local array that is
    // not initialised from constants with the zero value `(float[3])0` in HLSL, which
    // glslang's HLSL front end does not parse, and the lookups of split_frame tables, which
    // include this kernel, are translated to HLSL (`clothbake wgsl --lang hlsl`).
    var cuts = vec3<f32>(hi);
    var n_cuts = 0u;
    for (var k = 0u; k < 2u; k++) {
        let c = p.kinks[k];
        if c > lo && c < hi {
            cuts[n_cuts] = c;
            n_cuts++;
        }
    }
    let centre = clamp(p.resonant, lo, hi);
    let probe = cloth_resonant_theta_h(p, centre);
    let theta_c = probe.x;
    let slope = probe.y;
    var sums = vec3<f32>(0.0);
    var on_base = vec2<bool>(false, false);
    for (var lobe = 0u; lobe < 2u; lobe++) {
        let sigma = thread.sigma[lobe];
        // z linearised at the point nearest α*.
        let z_lo = (theta_c + slope * (lo - centre)) / sigma;
        let z_hi = (theta_c + slope * (hi - centre)) / sigma;
        // `!(slope > 0)` also sends a NaN slope to the base nodes.
        if !(slope > 0.0) || z_hi - z_lo <= CLOTH_RESONANT_FLAT_LOBE_SPAN {
            on_base[lobe] = true;
            continue;
        }
        if abs(theta_c) / sigma > CLOTH_RESONANT_NEGLIGIBLE_LOBE_Z {
            continue;
        }
        // Reflect a segment wholly above the peak into the lower tail; the part ends in
        // w = side·z, clamped to ±LOBE_Z_RANGE, increasing (t = Φ(w)).
        let side = select(1.0, -1.0, z_lo > 0.0);
        let range = CLOTH_RESONANT_LOBE_Z_RANGE;
        var ends = vec4<f32>(0.0);
        ends[0] = clamp(select(z_lo, -z_hi, side < 0.0), -range, range);
        for (var k = 0u; k < n_cuts; k++) {
            let zc = (theta_c + slope * (cuts[k] - centre)) / sigma;
            ends[k + 1u] = clamp(side * zc, -range, range);
        }
        if n_cuts == 2u && ends[1] > ends[2] {
            let swap = ends[1];
            ends[1] = ends[2];
            ends[2] = swap;
        }
        ends[n_cuts + 1u] = clamp(select(z_hi, -z_lo, side < 0.0), -range, range);
        // (Φ(w), Φ(−w)) at each end.
        var cdf = vec4<f32>(0.0);
        var cdf_complement = vec4<f32>(0.0);
        for (var k = 0u; k <= n_cuts + 1u; k++) {
            let pair = cloth_resonant_cdf_pair(ends[k]);
            cdf[k] = pair.x;
            cdf_complement[k] = pair.y;
        }
        let mass = cdf[n_cuts + 1u] - cdf[0];
        // The lobe's mass in the segment sets how many of its nodes the segment gets.
        var n = CLOTH_RESONANT_NODES[lobe];
        if mass < CLOTH_RESONANT_TAIL_MASS / 8.0 {
            n = (n + 3u) / 4u;
        } else if mass < CLOTH_RESONANT_TAIL_MASS {
            n = (n + 1u) / 2u;
        }
        for (var part = 0u; part <= n_cuts; part++) {
            let ta = cdf[part];
            let tb = cdf[part + 1u];
            // 1 − tb = Φ(−wb), accurate where tb is near 1.
            let ub = cdf_complement[part + 1u];
            // A part wholly above the median takes its width from the complements.
            let width = select(tb - ta, cdf_complement[part] - ub, ends[part] >= 0.0);
            if !(width > 0.0) {
                continue;
            }
            let count = cloth_resonant_split_count(n, width / mass);
            let first = cloth_resonant_rule_start(count);
            // dα = (σ/k) dz and dz = dt/φ(z).
            let scale = density * width * sigma / slope;
            for (var k = first; k < first + count; k++) {
                let node = cloth_resonant_gl(k);
                let t = ta + width * node.x;
                var zn: f32;
                if t <= 0.5 {
                    zn = cloth_resonant_quantile(t);
                } else {
                    zn = -cloth_resonant_quantile(ub + width * (1.0 - node.x));
                }
                zn *= side;
                let alpha = centre + (sigma * zn - theta_c) / slope;
                let weight = scale * node.y / cloth_resonant_pdf(zn);
                let s = cloth_resonant_sample(thread, p, alpha);
                if lobe == 0u {
                    sums.x += weight * s.y;
                } else {
                    sums.y += weight * s.z;
                }
            }
        }
    }
    // Base nodes in α, per part between the cuts: ⟨P⟩, the kd term, and the lobes smooth
    // over the segment.
    // A lobe riding on the base nodes brings its node count with it.
    var base_count = CLOTH_RESONANT_NODES.z;
    if on_base.x {
        base_count = max(base_count, CLOTH_RESONANT_NODES.x);
    }
    if on_base.y {
        base_count = max(base_count, CLOTH_RESONANT_NODES.y);
    }
    for (var part = 0u; part <= n_cuts; part++) {
        var a = lo;
        if part > 0u {
            a = cuts[part - 1u];
        }
        let b = cuts[part];
        let width = b - a;
        if !(width > 0.0) {
            continue;
        }
        let count = cloth_resonant_split_count(base_count, width / (hi - lo));
        let first = cloth_resonant_rule_start(count);
        for (var k = first; k < first + count; k++) {
            let node = cloth_resonant_gl(k);
            let weight = density * width * node.y;
            let s = cloth_resonant_sample(thread, p, a + width * node.x);
            sums.z += weight * s.x;
            sums.y += weight * s.w;
            if on_base.x {
                sums.x += weight * s.y;
            }
            if on_base.y {
                sums.y += weight * s.z;
            }
        }
    }
    return sums;
}
