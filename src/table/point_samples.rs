//! Single tangent samples of one thread in f32, for many direction pairs at once: the CPU
//! twin of `shaders/model/tangent_sample.wgsl` (`cloth_sample_pair`, `cloth_sample_terms`), line for
//! line the same formulas, written once for [`Lanes`] (one pair in `f32`, eight in
//! `wide::f32x8`). `split_frame` evaluates a thread's point masses (its flat segments)
//! with it. It follows the f64 kernel `ThreadModel::sample` of `src/model/patch.rs`, in the
//! forms that keep their accuracy in f32 (see `shaders/model/tangent_sample.wgsl`), with [`fast_math`]'s
//! atan2 and exp; `tests/tables/table.rs` bounds the difference through the whole lookup.
//!
//! Where a sample contributes nothing (a direction faces away from it, or a projection is
//! degenerate) its lanes are selected to 0 rather than skipped, so that every lane runs the
//! same instructions.

use super::fast_math::{self, Lanes};
use super::thread::lanes_in_thread_axes;
use super::wgsl::{degenerate_threshold, unit_area_gaussian};
use glam::Vec3;

/// One thread's sample kernel constants in f32 and its point masses.
#[derive(Clone, Debug, PartialEq)]
pub struct PointSamples {
    /// Surface lobe −1/(2σs²), 1/(σs√(2π)); volume lobe −1/(2σv²), 1/(σv√(2π)) (radians).
    pub lobes: [f32; 4],
    pub eta: f32,
    pub kd: f32,
    /// η = 1 exactly: no interface, Fr = 0.
    pub no_interface: bool,
    /// −1/(2σu²) of the reweighting Gaussian u.
    pub k_u: f32,
    /// Projections of this length or less are degenerate ([`degenerate_threshold`]).
    pub threshold: f32,
    /// Thread 2: t0 = y and b = x (thread 1: t0 = x, b = y).
    thread2: bool,
    /// (cos α_k, sin α_k, w_k) of each point mass.
    points: Vec<[f32; 3]>,
}

/// Per lane, the weighted sums over the points: `[reflection, transmission, masking]` as
/// `ThreadModel::point_sums` gives them (transmission = volume + diffuse).
pub type PointSums<L> = [L; 3];

impl PointSamples {
    /// Thread `index` (0 or 1) with lobe widths `sigmas` = (σs, σv, σu) in radians, index
    /// `eta`, diffuse share `kd` and `points` as (cos α, sin α, weight).
    pub fn new(
        index: usize,
        sigmas: [f64; 3],
        eta: f64,
        kd: f64,
        points: &[(f64, f64, f64)],
    ) -> Self {
        let [ks, ps] = unit_area_gaussian(sigmas[0]);
        let [kv, pv] = unit_area_gaussian(sigmas[1]);
        Self {
            lobes: [ks, ps, kv, pv],
            eta: eta as f32,
            kd: kd as f32,
            no_interface: eta == 1.0,
            k_u: (-0.5 / (sigmas[2] * sigmas[2])) as f32,
            threshold: degenerate_threshold(),
            thread2: index == 1,
            points: points
                .iter()
                .map(|&(c, s, w)| [c as f32, s as f32, w as f32])
                .collect(),
        }
    }

    /// The point masses' weighted sums for the `L::WIDTH` pairs `wi`, `wo` (slices of that
    /// length, directions above the horizon).
    ///
    /// Not inlined: a lookup's table arithmetic and this long kernel compiled as one body
    /// ran slower than as two.
    #[inline(never)]
    pub fn sums<L: Lanes>(&self, wi: &[Vec3], wo: &[Vec3]) -> PointSums<L> {
        let zero = L::splat(0.0);
        if self.points.is_empty() {
            return [zero; 3];
        }
        let [ti0, bi, zi] = lanes_in_thread_axes::<L>(self.thread2, wi);
        let [to0, bo, zo] = lanes_in_thread_axes::<L>(self.thread2, wo);
        let pair = Pair {
            ti0,
            zi,
            bi,
            to0,
            zo,
            bo,
        };
        let (par_i, par_o) = (
            (pair.ti0 * pair.ti0 + pair.zi * pair.zi).sqrt(),
            (pair.to0 * pair.to0 + pair.zo * pair.zo).sqrt(),
        );
        // w ∥ b is degenerate for P and s: such lanes get 0 from every sample.
        let valid = L::and(
            par_i.gt(L::splat(self.threshold)),
            par_o.gt(L::splat(self.threshold)),
        );
        let (psi_d, _) = angle(
            [pair.ti0 / par_i, pair.zi / par_i],
            [pair.to0 / par_o, pair.zo / par_o],
        );
        let u_psi = fast_math::exp(psi_d * psi_d * L::splat(self.k_u));
        let inverse_par = (L::splat(1.0) / par_i, L::splat(1.0) / par_o);
        let mut sums = [zero; 3];
        for &[cos_a, sin_a, weight] in &self.points {
            let [masking, reflection, transmission] =
                self.terms(&pair, inverse_par, u_psi, L::splat(cos_a), L::splat(sin_a));
            let weight = L::splat(weight);
            sums[0] = sums[0] + weight * L::select(valid, reflection, zero);
            sums[1] = sums[1] + weight * L::select(valid, transmission, zero);
            sums[2] = sums[2] + weight * L::select(valid, masking, zero);
        }
        sums
    }

    /// `cloth_sample_terms` at the tangent offset (cos_a, sin_a): (P, reflection,
    /// volume + diffuse), 0 where a direction faces away or a projection is degenerate.
    #[inline(always)]
    fn terms<L: Lanes>(
        &self,
        p: &Pair<L>,
        (inverse_par_i, inverse_par_o): (L, L),
        u_psi: L,
        cos_a: L,
        sin_a: L,
    ) -> [L; 3] {
        let (zero, one) = (L::splat(0.0), L::splat(1.0));
        // w·n(α); cos θ = |w⊥| = √((w·n)² + (w·b)²).
        let ni = p.zi * cos_a - p.ti0 * sin_a;
        let no = p.zo * cos_a - p.to0 * sin_a;
        let perp_i = (ni * ni + p.bi * p.bi).sqrt();
        let perp_o = (no * no + p.bo * p.bo).sqrt();
        let threshold = L::splat(self.threshold);
        let counts = L::and(
            L::and(ni.gt(zero), no.gt(zero)),
            L::and(perp_i.gt(threshold), perp_o.gt(threshold)),
        );
        let masking_p = reweighted(u_psi, ni * inverse_par_i, no * inverse_par_o);
        // φd between the unit projections w⊥/|w⊥| = ((w·n), (w·b))/|w⊥|.
        let (inverse_perp_i, inverse_perp_o) = (one / perp_i, one / perp_o);
        let (mi, mo) = (ni * inverse_perp_i, no * inverse_perp_o);
        let (phi_d, cos_half_phi_d) =
            angle([mi, p.bi * inverse_perp_i], [mo, p.bo * inverse_perp_o]);
        let u_phi = fast_math::exp(phi_d * phi_d * L::splat(self.k_u));
        let shadowing_m = reweighted(u_phi, mi, mo);
        // θh and cos²θd by `half_angle_and_difference` (src/model/sample.rs): (|w⊥|, w·t) is
        // each direction's (cos θ, sin θ), of length |w| = 1, so their sum is
        // 2 cos θd (cos θh, sin θh).
        let si = p.ti0 * cos_a + p.zi * sin_a;
        let so = p.to0 * cos_a + p.zo * sin_a;
        let (x, y) = (perp_i + perp_o, si + so);
        let theta_h = fast_math::atan2(y, x);
        let cos2_theta_d = (L::splat(0.25) * (x * x + y * y)).min(one);
        let (fr, ft) = self.fresnel(cos2_theta_d.sqrt() * cos_half_phi_d);
        // The bounded products: M·P·cos θi/cos²θd, and cos θi/(cos θi + cos θo) ≤ 1.
        let bounded = shadowing_m * masking_p / cos2_theta_d;
        let transmission = bounded * ft * (perp_i / (perp_i + perp_o));
        let [surface, volume] = self.lobes(theta_h * theta_h);
        let reflection = bounded * fr * cos_half_phi_d * surface * perp_i;
        let volume = transmission * L::splat(1.0 - self.kd) * volume;
        let diffuse = transmission * L::splat(self.kd);
        [masking_p, reflection, volume + diffuse].map(|x| L::select(counts, x, zero))
    }

    /// σv = 2σs, as for every built-in thread but crepe's second: then ks = 4kv exactly,
    /// and the surface lobe's Gaussian is the volume lobe's to the fourth power.
    fn surface_from_volume(&self) -> bool {
        self.lobes[0] == 4.0 * self.lobes[2]
    }

    /// `cloth_sample_lobes`: the surface and volume lobes, each unit-area Gaussian
    /// `norm·exp(k·θh²)`, at `theta_h2` = θh².
    #[inline(always)]
    fn lobes<L: Lanes>(&self, theta_h2: L) -> [L; 2] {
        let surface_from_volume = self.surface_from_volume();
        let [ks, ps, kv, pv] = self.lobes.map(L::splat);
        let volume = fast_math::exp(theta_h2 * kv);
        let surface = if surface_from_volume {
            let square = volume * volume;
            square * square
        } else {
            fast_math::exp(theta_h2 * ks)
        };
        [ps * surface, pv * volume]
    }

    /// `cloth_sample_fresnel`: (Fr, Ft = (1 − Fr)²) from air into η at incidence cosine
    /// `cos_i`, with 1 − Fr formed without cancellation.
    #[inline(always)]
    fn fresnel<L: Lanes>(&self, cos_i: L) -> (L, L) {
        if self.no_interface {
            return (L::splat(0.0), L::splat(1.0));
        }
        let (zero, one, eta) = (L::splat(0.0), L::splat(1.0), L::splat(self.eta));
        let cos_i = cos_i.max(zero).min(one);
        let sin2_t = (one - cos_i * cos_i) / (eta * eta);
        let cos_t = (one - sin2_t).max(zero).sqrt();
        let ds = cos_i + eta * cos_t;
        let dp = eta * cos_i + cos_t;
        let rs = (cos_i - eta * cos_t) / ds;
        let rp = (eta * cos_i - cos_t) / dp;
        let transmitted = L::splat(2.0) * eta * cos_i * cos_t * (one / (ds * ds) + one / (dp * dp));
        (
            L::splat(0.5) * (rs * rs + rp * rp),
            transmitted * transmitted,
        )
    }
}

/// A pair's components in a thread's fixed axes {t0, b, z}.
struct Pair<L> {
    ti0: L,
    zi: L,
    bi: L,
    to0: L,
    zo: L,
    bo: L,
}

/// `reweighted`: (1 − u)·a·b + u·min(a, b).
#[inline(always)]
fn reweighted<L: Lanes>(u: L, a: L, b: L) -> L {
    (L::splat(1.0) - u) * a * b + u * a.min(b)
}

/// `cloth_sample_angle`: for unit 2D vectors a and c, the angle between them, 2·atan2(|a −
/// c|, |a + c|), and the cosine of half of it, |a + c|/2 (at most 1).
#[inline(always)]
fn angle<L: Lanes>(a: [L; 2], c: [L; 2]) -> (L, L) {
    let length = |x: L, y: L| (x * x + y * y).sqrt();
    let sum = length(a[0] + c[0], a[1] + c[1]);
    let difference = length(a[0] - c[0], a[1] - c[1]);
    (
        L::splat(2.0) * fast_math::atan2(difference, sum),
        (L::splat(0.5) * sum).min(L::splat(1.0)),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formats::fabric_toml::FabricSet;

    /// The fourth-power shortcut is taken for exactly the threads with γv = 2γs, and agrees
    /// with the two exps of the general form to f32 rounding across the lobes' range (where
    /// the lobe has fallen below 10⁻³⁰ of its peak, near f32's underflow, both are 0 for
    /// any purpose).
    #[test]
    fn surface_lobe_from_volume_lobe_where_twice_as_wide() {
        for fabric in FabricSet::builtin().fabrics() {
            for (j, thread) in fabric.threads().into_iter().enumerate() {
                let sigma = |gamma: f64| fabric.options.lobe_sigma_deg(gamma).to_radians();
                let samples = PointSamples::new(
                    j,
                    [sigma(thread.gamma_s_deg), sigma(thread.gamma_v_deg), 0.3],
                    thread.eta,
                    thread.kd,
                    &[],
                );
                let twice = thread.gamma_v_deg == 2.0 * thread.gamma_s_deg;
                assert_eq!(
                    samples.surface_from_volume(),
                    twice,
                    "{} thread {j}",
                    fabric.name
                );
                let [ks, ps, ..] = samples.lobes;
                for i in 0..=1000 {
                    let theta_h = 1.5 * i as f32 / 1000.0;
                    let [surface, _] = samples.lobes::<f32>(theta_h * theta_h);
                    let general = ps * fast_math::exp(theta_h * theta_h * ks);
                    assert!(
                        (surface - general).abs() <= 4e-6 * general + 1e-30 * ps,
                        "{} thread {j} θh {theta_h}: {surface} against {general}",
                        fabric.name
                    );
                }
            }
        }
    }
}
