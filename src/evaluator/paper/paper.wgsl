// The patch transfer F(wi, wo) of docs/model.md evaluated in f32 in paper mode: the
// curve mean ⟨x⟩_j of each thread is the weighted sum over the tangent nodes that the CPU's
// `curve_pieces(thread, options, Integration::Paper(N))` produces (uploaded by
// gpu.rs beside this file, `GpuPaper`, as (cos α, sin α, weight)), each sample evaluated by
// model/tangent_sample.wgsl (required below). Mirrors `ThreadModel::means` and `Patch::terms` of
// src/model/patch.rs. Paper-mode nodes are single points, so the interval clipping of the
// direct rule never applies. tests/gpu/paper.rs bounds the difference to the CPU.
//
// Every top-level name starts with `cloth_`/`Cloth` (the `GpuBrdf` naming contract).
//
// requires: model/tangent_sample

// One thread family (`PaperThread` in gpu.rs).
struct ClothPaperThread {
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
    // First node in cloth_paper_nodes, node count.
    nodes: vec4<u32>,
}

struct ClothPaperParams {
    threads: array<ClothPaperThread, 2>,
    // −1/(2σu²) of the reweighting Gaussian u, gap = max(1 − a1 − a2, 0), the degenerate
    // projection threshold (largest f32 below DEGENERATE_PROJECTION: `<=` it is
    // degenerate, exactly as `< 1e-9` in f64 for f32-representable lengths), 0.
    misc: vec4<f32>,
}

@group(CLOTH_BRDF_GROUP) @binding(0) var<uniform> cloth_paper: ClothPaperParams;
// Tangent nodes of both threads: (cos α, sin α, weight, 0); weights of a thread sum to 1.
@group(CLOTH_BRDF_GROUP) @binding(1) var<storage, read> cloth_paper_nodes: array<vec4<f32>>;

// `ThreadModel::means` of thread j: (⟨reflection⟩, ⟨transmission⟩, ⟨P⟩).
fn cloth_paper_means(j: u32, wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    let thread = cloth_paper.threads[j];
    var material: ClothSampleMaterial;
    material.lobes = thread.lobes;
    material.eta = thread.material.x;
    material.kd = thread.material.y;
    material.no_interface = thread.material.w;
    material.k_u = cloth_paper.misc.x;
    material.threshold = cloth_paper.misc.z;
    let pair = cloth_sample_pair(wi, wo, thread.t0.xyz, thread.b.xyz, material.k_u);
    if pair.par_i <= material.threshold || pair.par_o <= material.threshold {
        return vec3<f32>(0.0);
    }
    var sums = vec3<f32>(0.0);
    let first = thread.nodes.x;
    for (var k = first; k < first + thread.nodes.y; k++) {
        let node = cloth_paper_nodes[k];
        let s = cloth_sample_terms(pair, material, node.x, node.y);
        sums += node.z * vec3<f32>(s.y, s.z + s.w, s.x);
    }
    return sums;
}

// `Patch::eval`: F = [a1⟨s⟩1 + a2⟨s⟩2]/Q, Q = a1⟨P⟩1 + a2⟨P⟩2 + gap·wo.z; 0 below the
// horizon and where Q = 0.
fn cloth_brdf(wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    if wi.z <= 0.0 || wo.z <= 0.0 {
        return vec3<f32>(0.0);
    }
    let m1 = cloth_paper_means(0u, wi, wo);
    let m2 = cloth_paper_means(1u, wi, wo);
    let a1 = cloth_paper.threads[0].material.z;
    let a2 = cloth_paper.threads[1].material.z;
    let q = a1 * m1.z + a2 * m2.z + cloth_paper.misc.y * wo.z;
    if q <= 0.0 {
        return vec3<f32>(0.0);
    }
    let reflection = (a1 * m1.x + a2 * m2.x) / q;
    let transmission1 = a1 * m1.y / q;
    let transmission2 = a2 * m2.y / q;
    return vec3<f32>(reflection) + cloth_paper.threads[0].albedo.xyz * transmission1
        + cloth_paper.threads[1].albedo.xyz * transmission2;
}
