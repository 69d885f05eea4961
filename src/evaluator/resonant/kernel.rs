//! The resonant quadrature's WGSL kernel (`quadrature.wgsl` in this folder) and what it reads:
//! the rule's constants (the generated module [`crate::shader::RESONANT_RULES`] that the
//! kernel requires), which depend on the node counts alone, and the fabric's block
//! ([`FabricBlock`]), the uniform buffer that `resonant.wgsl` binds in group 0: per thread its
//! parameters and its curve pieces, the reweighting width σu, coverage, gap and albedos.
//!
//! The fabric is data, not WGSL, so that one shader and pipeline serve every fabric at the
//! same node counts: the editor of `view --edit` writes each edit into the buffer
//! ([`super::gpu::GpuResonant`]'s `GpuBrdf::update_fabric`) and the next frame shades it.
//! The block has room for [`MAX_PIECES`] pieces per thread, the most any valid fabric makes.
//!
//! The resonant quadrature's shader ([`super::gpu`], which adds `cloth_brdf` and the per-thread
//! loop over the pieces) uses it; no table lookup does.

use crate::gpu::GpuError;
use crate::model::Fabric;
use crate::model::curve::{Integration, curve_pieces};
use crate::model::fabric::MAX_CONTROL_POINTS;
use crate::model::resonant::{
    FLAT_LOBE_SPAN, GaussLegendre, LOBE_Z_RANGE, MIN_NODES_PER_PART, NEGLIGIBLE_LOBE_Z,
    SPLIT_TOLERANCE, TAIL_MASS,
};
use crate::model::{ResonantNodes, thread_axes};
use crate::table::wgsl::{degenerate_threshold, unit_area_gaussian, wgsl_f32, wgsl_vec};
use bytemuck::{Pod, Zeroable};
use std::fmt::Write;

/// Most curve pieces of one thread that the fabric block holds. `curve_pieces` with
/// `Integration::Resonant` makes at most one piece per control point: one per segment of a
/// curve of m + 1 points (m ≤ [`MAX_CONTROL_POINTS`] − 1; jumps make none, and flat segments
/// in a row merge into one point), one per control point with `tangent_sampling =
/// "control_points"` (merged alike), one for a single control point. So every fabric that
/// passes `Fabric::validate` fits.
pub const MAX_PIECES: usize = MAX_CONTROL_POINTS;

/// `kind` of a piece in the block (its `w` component): a segment, its pair-wise nodes placed
/// by `cloth_resonant_segment`.
pub const PIECE_SEGMENT: f32 = 0.0;
/// `kind` of a flat piece: one node, `cloth_resonant_point`.
pub const PIECE_POINT: f32 = 1.0;

/// One thread as the block holds it (`ClothResonantThreadBlock` of resonant.wgsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct ThreadBlock {
    /// Base tangent t0 (xyz).
    pub t0: [f32; 4],
    /// Rotation axis b (xyz).
    pub b: [f32; 4],
    /// Lobe standard deviations σs, σv in radians.
    pub sigma: [f32; 4],
    /// Surface −1/(2σs²), 1/(σs√(2π)); volume −1/(2σv²), 1/(σv√(2π)).
    pub lobes: [f32; 4],
    /// η, kd, 1 if η == 1 exactly (no interface: Fr = 0) else 0, and the fabric's −1/(2σu²)
    /// (the reweighting Gaussian u, `CLOTH_RESONANT_K_U` when it was a constant).
    pub material: [f32; 4],
    /// RGB albedo A = albedo_scale · albedo, and the coverage a.
    pub albedo: [f32; 4],
    /// The thread's piece count, 0, 0, 0.
    pub pieces: [u32; 4],
}

/// The head of the fabric block: both threads and (gap = max(1 − a1 − a2, 0), 0, 0, 0).
/// The pieces follow it ([`FabricBlock::bytes`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct FabricHead {
    pub threads: [ThreadBlock; 2],
    pub misc: [f32; 4],
}

/// A fabric as the resonant shader reads it (`ClothResonantFabric` of resonant.wgsl): the
/// head, then per thread [`MAX_PIECES`] slots of (start, end, density or weight, kind), the
/// thread's pieces first and zeros after them. Thread j's pieces start at slot
/// j·[`MAX_PIECES`].
#[derive(Clone, Debug, PartialEq)]
pub struct FabricBlock {
    pub head: FabricHead,
    pub pieces: Vec<[f32; 4]>,
}

impl FabricBlock {
    /// The block's size in bytes, the same for every fabric.
    pub const SIZE: usize = std::mem::size_of::<FabricHead>() + 2 * MAX_PIECES * 16;

    /// The values `fabric` gives the shader, each the f32 rounding of the f64 that the
    /// constants of the WGSL held before the block (so the kernel's arithmetic is unchanged):
    /// `ThreadModel::new`'s per-thread parameters and, per curve piece of
    /// `curve_pieces(thread, options, Integration::Resonant(_))` (the pieces do not depend on
    /// the node counts), a flat piece as (α, α, weight, [`PIECE_POINT`]) and a sloped one as
    /// (start, end, density per radian in f64 as `ResonantRule::segment` forms it,
    /// [`PIECE_SEGMENT`]). Fails with [`GpuError::Invalid`] if a thread has more than
    /// [`MAX_PIECES`] pieces, which no valid fabric has; it does not validate the rest of the
    /// fabric (`Fabric::validate` does).
    pub fn new(fabric: &Fabric) -> Result<Self, GpuError> {
        let options = fabric.options;
        let sigma_u = options.sigma_u_deg.to_radians();
        let k_u = (-0.5 / (sigma_u * sigma_u)) as f32;
        let mut head = FabricHead::default();
        let mut pieces = vec![[0.0f32; 4]; 2 * MAX_PIECES];
        for (j, thread) in fabric.threads().into_iter().enumerate() {
            let (t0, b) = thread_axes(j);
            let sigma_s = options.lobe_sigma_deg(thread.gamma_s_deg).to_radians();
            let sigma_v = options.lobe_sigma_deg(thread.gamma_v_deg).to_radians();
            let [ks, ps] = unit_area_gaussian(sigma_s);
            let [kv, pv] = unit_area_gaussian(sigma_v);
            let no_interface = if thread.eta == 1.0 { 1.0 } else { 0.0 };
            let [r, g, bl] = thread.albedo_rgb().map(|c| c as f32);
            let thread_pieces = curve_pieces(
                thread,
                &options,
                Integration::Resonant(ResonantNodes::DEFAULT),
            );
            if thread_pieces.len() > MAX_PIECES {
                return Err(GpuError::Invalid {
                    name: format!("fabric '{}' thread {}", fabric.name, j + 1),
                    message: format!(
                        "its curve has {} pieces, the resonant shader's block holds at most \
                         {MAX_PIECES} (one per control point)",
                        thread_pieces.len()
                    ),
                });
            }
            for (slot, piece) in pieces[j * MAX_PIECES..].iter_mut().zip(&thread_pieces) {
                *slot = if piece.start == piece.end {
                    [
                        piece.start as f32,
                        piece.start as f32,
                        piece.weight as f32,
                        PIECE_POINT,
                    ]
                } else {
                    // The density per radian in f64, as `ResonantRule::segment` forms it.
                    let density = piece.weight / (piece.end - piece.start);
                    [
                        piece.start as f32,
                        piece.end as f32,
                        density as f32,
                        PIECE_SEGMENT,
                    ]
                };
            }
            let axis = |v: glam::DVec3| [v.x as f32, v.y as f32, v.z as f32, 0.0];
            head.threads[j] = ThreadBlock {
                t0: axis(t0),
                b: axis(b),
                sigma: [sigma_s as f32, sigma_v as f32, 0.0, 0.0],
                lobes: [ks, ps, kv, pv],
                material: [thread.eta as f32, thread.kd as f32, no_interface, k_u],
                albedo: [r, g, bl, thread.coverage as f32],
                pieces: [thread_pieces.len() as u32, 0, 0, 0],
            };
        }
        let gap = (1.0 - fabric.thread1.coverage - fabric.thread2.coverage).max(0.0);
        head.misc = [gap as f32, 0.0, 0.0, 0.0];
        Ok(Self { head, pieces })
    }

    /// The block as the uniform buffer holds it, [`FabricBlock::SIZE`] bytes.
    pub fn bytes(&self) -> Vec<u8> {
        let mut bytes = Vec::with_capacity(Self::SIZE);
        bytes.extend_from_slice(bytemuck::bytes_of(&self.head));
        bytes.extend_from_slice(bytemuck::cast_slice(&self.pieces));
        debug_assert_eq!(bytes.len(), Self::SIZE);
        bytes
    }
}

/// The generated module [`crate::shader::RESONANT_FABRIC`]: the block's capacity, from
/// [`MAX_PIECES`] (resonant.wgsl declares the block with it).
pub fn fabric_layout_wgsl() -> String {
    format!(
        "// Curve pieces per thread in the fabric block (`MAX_PIECES` of \
         src/evaluator/resonant/kernel.rs).\n\
         const CLOTH_RESONANT_MAX_PIECES: u32 = {MAX_PIECES}u;\n\
         // Piece slots of both threads.\n\
         const CLOTH_RESONANT_PIECE_SLOTS: u32 = {}u;\n\
         // A piece's kind (its w): one node at α, else a segment.\n\
         const CLOTH_RESONANT_PIECE_POINT: f32 = {};\n",
        2 * MAX_PIECES,
        wgsl_f32(PIECE_POINT)
    )
}

/// The rule's constants for `nodes`: the thresholds of `src/model/resonant.rs`, the node
/// counts and the Gauss–Legendre rules they can pick. Nothing of a fabric (σu is in the
/// fabric block).
pub fn resonant_rules_wgsl(nodes: ResonantNodes) -> String {
    let mut out = String::new();
    let w = &mut out;
    let consts = [
        ("CLOTH_RESONANT_THRESHOLD", degenerate_threshold()),
        ("CLOTH_RESONANT_FLAT_LOBE_SPAN", FLAT_LOBE_SPAN as f32),
        ("CLOTH_RESONANT_NEGLIGIBLE_LOBE_Z", NEGLIGIBLE_LOBE_Z as f32),
        ("CLOTH_RESONANT_TAIL_MASS", TAIL_MASS as f32),
        ("CLOTH_RESONANT_LOBE_Z_RANGE", LOBE_Z_RANGE as f32),
        ("CLOTH_RESONANT_SPLIT_TOLERANCE", SPLIT_TOLERANCE as f32),
    ];
    for (name, value) in consts {
        let _ = writeln!(w, "const {name}: f32 = {};", wgsl_f32(value));
    }
    let _ = writeln!(
        w,
        "const CLOTH_RESONANT_MIN_NODES_PER_PART: u32 = {MIN_NODES_PER_PART}u;\n\
         const CLOTH_RESONANT_NODES: vec3<u32> = vec3<u32>({}u, {}u, {}u);",
        nodes.surface, nodes.volume, nodes.base
    );
    // The n-point rules for every count a part can get, n = 1..=max(surface, volume, base)
    // (`ResonantRule::rule`; tail rules and kink splits only lower a count), flattened: the
    // n-point rule starts at n(n − 1)/2.
    let max = nodes.surface.max(nodes.volume).max(nodes.base) as usize;
    let mut gl = Vec::new();
    for n in 1..=max {
        let rule = GaussLegendre::new(n);
        for (&x, &wt) in rule.nodes.iter().zip(&rule.weights) {
            gl.push(wgsl_vec(&[x as f32, wt as f32]));
        }
    }
    debug_assert_eq!(gl.len(), max * (max + 1) / 2);
    let _ = writeln!(
        w,
        "// Gauss–Legendre nodes on [0, 1] and weights (summing to 1 per rule), the n-point \
         rule at n(n − 1)/2, n = 1..={max}.\n\
         fn cloth_resonant_gl(k: u32) -> vec2<f32> {{\n    \
         let rules = array<vec2<f32>, {}>(\n        {});\n    \
         return rules[k];\n}}",
        gl.len(),
        gl.join(",\n        ")
    );
    out
}
