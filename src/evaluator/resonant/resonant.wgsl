// The resonant quadrature's `cloth_brdf` (gpu.rs beside this file), after the kernel
// quadrature.wgsl: the fabric block in group 0 (`FabricBlock` of kernel.rs, rewritten in
// place by `GpuResonant::update_fabric` when the editor changes the fabric, so one shader
// serves every fabric), the loop over a thread's curve pieces, and F. The generated module
// `resonant_fabric` holds the block's capacity.
//
// requires: evaluator/resonant_quadrature, resonant_fabric

// One thread as the block holds it (`ThreadBlock` in kernel.rs).
struct ClothResonantThreadBlock {
    // Base tangent t0 and rotation axis b (xyz).
    t0: vec4<f32>,
    b: vec4<f32>,
    // σs, σv in radians.
    sigma: vec4<f32>,
    // Surface −1/(2σs²), 1/(σs√(2π)); volume −1/(2σv²), 1/(σv√(2π)).
    lobes: vec4<f32>,
    // η, kd, 1 if η == 1 exactly else 0, −1/(2σu²) (`ClothResonantThread::material`).
    material: vec4<f32>,
    // RGB albedo, coverage a.
    albedo: vec4<f32>,
    // The thread's piece count.
    pieces: vec4<u32>,
}

struct ClothResonantFabric {
    threads: array<ClothResonantThreadBlock, 2>,
    // gap = max(1 − a1 − a2, 0), 0, 0, 0.
    misc: vec4<f32>,
    // Thread j's pieces from slot j·CLOTH_RESONANT_MAX_PIECES: (start, end, density per
    // radian, CLOTH_RESONANT_PIECE_POINT or 0) for a segment, (α, α, weight, ..._POINT) for a
    // flat piece, in the order of `curve_pieces`.
    pieces: array<vec4<f32>, CLOTH_RESONANT_PIECE_SLOTS>,
}

@group(CLOTH_BRDF_GROUP) @binding(0) var<uniform> cloth_resonant: ClothResonantFabric;

// `ThreadModel::means` of thread j: (⟨reflection⟩, ⟨transmission⟩, ⟨P⟩), the thread's
// pieces summed in order, as the CPU sums them.
fn cloth_resonant_means(j: u32, wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    let block = cloth_resonant.threads[j];
    let thread = ClothResonantThread(block.t0.xyz, block.b.xyz, block.sigma.xy, block.lobes,
        block.material);
    let pair = cloth_resonant_pair(thread, wi, wo);
    var sums = vec3<f32>(0.0);
    if pair.valid == 0u {
        return sums;
    }
    let first = j * CLOTH_RESONANT_MAX_PIECES;
    let count = min(block.pieces.x, CLOTH_RESONANT_MAX_PIECES);
    for (var k = first; k < first + count; k++) {
        let piece = cloth_resonant.pieces[k];
        if piece.w == CLOTH_RESONANT_PIECE_POINT {
            sums += cloth_resonant_point(thread, pair, piece.x, piece.z);
        } else {
            sums += cloth_resonant_segment(thread, pair, piece.x, piece.y, piece.z);
        }
    }
    return sums;
}

// `Patch::eval`: F = [a1⟨s⟩1 + a2⟨s⟩2]/Q, Q = a1⟨P⟩1 + a2⟨P⟩2 + gap·wo.z; 0 below the
// horizon and where Q = 0.
fn cloth_brdf(wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    if wi.z <= 0.0 || wo.z <= 0.0 {
        return vec3<f32>(0.0);
    }
    let m1 = cloth_resonant_means(0u, wi, wo);
    let m2 = cloth_resonant_means(1u, wi, wo);
    let a1 = cloth_resonant.threads[0].albedo.w;
    let a2 = cloth_resonant.threads[1].albedo.w;
    let q = a1 * m1.z + a2 * m2.z + cloth_resonant.misc.x * wo.z;
    if q <= 0.0 {
        return vec3<f32>(0.0);
    }
    return vec3<f32>((a1 * m1.x + a2 * m2.x) / q)
        + cloth_resonant.threads[0].albedo.xyz * (a1 * m1.y / q)
        + cloth_resonant.threads[1].albedo.xyz * (a2 * m2.y / q);
}
