//! What a fit may change: a [`Parametrisation`] maps a vector of bounded free parameters to a
//! valid fabric. [`LikeFabric`] frees the parameters of a given fabric and keeps its
//! structure (control points, jumps, model options); a weave parametrisation (the draft's
//! curves from yarn knobs) implements the same trait.

use crate::model::{Fabric, Thread};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;

/// One free parameter: its name (`thread1.eta`, `thread1.offsets_deg[2]`), its bounds and the
/// value a fit starts from (within the bounds).
#[derive(Clone, Debug, PartialEq)]
pub struct FreeParameter {
    pub name: String,
    pub lower: f64,
    pub upper: f64,
    pub start: f64,
}

impl FreeParameter {
    /// A parameter with bounds `[lower, upper]` widened to hold `start` (a fabric may start
    /// outside the range a fit searches; it is never moved out of the fabric's schema by that).
    pub fn new(name: impl Into<String>, lower: f64, upper: f64, start: f64) -> Self {
        Self {
            name: name.into(),
            lower: lower.min(start),
            upper: upper.max(start),
            start,
        }
    }

    /// `value` clamped to the bounds.
    pub fn clamp(&self, value: f64) -> f64 {
        value.clamp(self.lower, self.upper)
    }
}

/// A map from bounded free parameters to fabrics.
pub trait Parametrisation: Sync {
    /// The free parameters, in the order of the value vectors.
    fn parameters(&self) -> &[FreeParameter];
    /// The fabric of `values` (one per parameter). Every vector within the bounds gives a
    /// fabric that passes [`Fabric::validate`]; values outside them are clamped.
    fn fabric(&self, values: &[f64]) -> Fabric;
    /// The start values.
    fn start(&self) -> Vec<f64> {
        self.parameters().iter().map(|p| p.start).collect()
    }
    /// How many starts a fit takes unless told ([`super::solve::FitOptions::starts`]);
    /// `None` leaves it to the solver, one per schedule of broadened lobes.
    fn default_starts(&self) -> Option<usize> {
        None
    }
}

/// Range of the refractive index η of a fibre: 1 (none) to 2, beyond every textile fibre
/// (1.3–1.7).
pub const ETA_RANGE: (f64, f64) = (1.0, 2.0);
/// Range of the surface lobe width γs in degrees.
pub const GAMMA_S_RANGE_DEG: (f64, f64) = (0.5, 45.0);
/// Range of the volume lobe width γv in degrees.
pub const GAMMA_V_RANGE_DEG: (f64, f64) = (0.5, 90.0);
/// Range of a tangent curve offset in degrees: the schema's whole range (velvet's pile
/// stands at −90°).
pub const OFFSET_RANGE_DEG: (f64, f64) = (-90.0, 90.0);
/// Largest ratio of a segment length to the reference segment (lengths are scale-free),
/// unless the start fabric's ratio is larger (then twice that).
pub const MAX_LENGTH_RATIO: f64 = 4.0;

/// What each free parameter of a [`LikeFabric`] sets.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Slot {
    Eta(usize),
    /// Channel c of the RGB albedo A = albedo_scale × albedo.
    Albedo(usize, usize),
    Kd(usize),
    GammaS(usize),
    GammaV(usize),
    Offset(usize, usize),
    /// Segment length as a ratio to the thread's reference segment.
    Length(usize, usize),
    /// c1 + c2.
    CoverageTotal,
    /// c1 / (c1 + c2).
    CoverageShare,
}

/// The parameters of a given fabric, its structure kept: per thread η (unless fixed), the
/// RGB albedo A (each channel in [0, 1], written as `albedo = A / max A`,
/// `albedo_scale = max A`), kd, γs, γv, every curve offset, and every segment length but the
/// thread's reference segment (its longest: only ratios matter) and its jumps (zero lengths
/// are structure); and the coverages as their total c1 + c2 and thread 1's share of it, both
/// in [0, 1], which keeps c1 + c2 ≤ 1 for every in-bounds vector. The model options and the
/// name are kept.
#[derive(Clone, Debug)]
pub struct LikeFabric {
    base: Fabric,
    parameters: Vec<FreeParameter>,
    slots: Vec<Slot>,
    /// Per thread, the index of the reference segment and its length.
    reference: [Option<(usize, f64)>; 2],
}

impl LikeFabric {
    /// Frees `fabric`'s parameters (it is assumed valid, see [`Fabric::validate`]). With
    /// `fixed_eta`, both threads' η are set to it and not fitted.
    pub fn new(fabric: &Fabric, fixed_eta: Option<f64>) -> Self {
        let mut base = fabric.clone();
        if let Some(eta) = fixed_eta {
            base.thread1.eta = eta;
            base.thread2.eta = eta;
        }
        let mut parameters = Vec::new();
        let mut slots = Vec::new();
        let mut reference = [None, None];
        let mut push = |slot: Slot, name: String, (lo, hi): (f64, f64), start: f64| {
            parameters.push(FreeParameter::new(name, lo, hi, start));
            slots.push(slot);
        };
        for (j, thread) in base.threads().into_iter().enumerate() {
            let t = format!("thread{}", j + 1);
            if fixed_eta.is_none() {
                push(Slot::Eta(j), format!("{t}.eta"), ETA_RANGE, thread.eta);
            }
            for (c, a) in thread.albedo_rgb().into_iter().enumerate() {
                push(Slot::Albedo(j, c), format!("{t}.A[{c}]"), (0.0, 1.0), a);
            }
            push(Slot::Kd(j), format!("{t}.kd"), (0.0, 1.0), thread.kd);
            push(
                Slot::GammaS(j),
                format!("{t}.gamma_s_deg"),
                GAMMA_S_RANGE_DEG,
                thread.gamma_s_deg,
            );
            push(
                Slot::GammaV(j),
                format!("{t}.gamma_v_deg"),
                GAMMA_V_RANGE_DEG,
                thread.gamma_v_deg,
            );
            for (i, &o) in thread.offsets_deg.iter().enumerate() {
                push(
                    Slot::Offset(j, i),
                    format!("{t}.offsets_deg[{i}]"),
                    OFFSET_RANGE_DEG,
                    o,
                );
            }
            // One segment ignores its length; several are free relative to the longest.
            if thread.lengths.len() > 1 {
                let (r, &l_ref) = thread
                    .lengths
                    .iter()
                    .enumerate()
                    .max_by(|a, b| a.1.total_cmp(b.1).then(b.0.cmp(&a.0)))
                    .expect("several segments");
                reference[j] = Some((r, l_ref));
                for (i, &l) in thread.lengths.iter().enumerate() {
                    if i == r || l == 0.0 {
                        continue;
                    }
                    let ratio = l / l_ref;
                    push(
                        Slot::Length(j, i),
                        format!("{t}.lengths[{i}]/lengths[{r}]"),
                        (0.0, MAX_LENGTH_RATIO.max(2.0 * ratio)),
                        ratio,
                    );
                }
            }
        }
        let (c1, c2) = (base.thread1.coverage, base.thread2.coverage);
        let total = c1 + c2;
        push(
            Slot::CoverageTotal,
            "coverage.total".into(),
            (0.0, 1.0),
            total.min(1.0),
        );
        let share = if total > 0.0 { c1 / total } else { 0.5 };
        push(
            Slot::CoverageShare,
            "coverage.share1".into(),
            (0.0, 1.0),
            share,
        );
        Self {
            base,
            parameters,
            slots,
            reference,
        }
    }

    /// The same parametrisation writing fabrics named `name`.
    pub fn with_name(mut self, name: &str) -> Self {
        self.base.name = name.to_string();
        self
    }
}

fn thread_mut(fabric: &mut Fabric, j: usize) -> &mut Thread {
    if j == 0 {
        &mut fabric.thread1
    } else {
        &mut fabric.thread2
    }
}

/// Sets a thread's RGB albedo A (each channel ≥ 0) as `albedo = A / max A`,
/// `albedo_scale = max A`, the fitted parameters' form in a fabric file.
pub(super) fn set_albedo(thread: &mut Thread, a: [f64; 3]) {
    let max = a[0].max(a[1]).max(a[2]);
    if max > 0.0 {
        thread.albedo = a.map(|c| c / max);
        thread.albedo_scale = max;
    } else {
        thread.albedo = [1.0; 3];
        thread.albedo_scale = 0.0;
    }
}

impl Parametrisation for LikeFabric {
    fn parameters(&self) -> &[FreeParameter] {
        &self.parameters
    }

    fn fabric(&self, values: &[f64]) -> Fabric {
        let mut fabric = self.base.clone();
        let mut albedo = [
            self.base.thread1.albedo_rgb(),
            self.base.thread2.albedo_rgb(),
        ];
        let (mut total, mut share) = (None, None);
        for ((slot, p), &v) in self.slots.iter().zip(&self.parameters).zip(values) {
            let v = if v.is_finite() { p.clamp(v) } else { p.start };
            match *slot {
                Slot::Eta(j) => thread_mut(&mut fabric, j).eta = v,
                Slot::Albedo(j, c) => albedo[j][c] = v,
                Slot::Kd(j) => thread_mut(&mut fabric, j).kd = v,
                Slot::GammaS(j) => thread_mut(&mut fabric, j).gamma_s_deg = v,
                Slot::GammaV(j) => thread_mut(&mut fabric, j).gamma_v_deg = v,
                Slot::Offset(j, i) => thread_mut(&mut fabric, j).offsets_deg[i] = v,
                Slot::Length(j, i) => {
                    let l_ref = self.reference[j].map_or(1.0, |r| r.1);
                    thread_mut(&mut fabric, j).lengths[i] = v * l_ref;
                }
                Slot::CoverageTotal => total = Some(v),
                Slot::CoverageShare => share = Some(v),
            }
        }
        for (j, a) in albedo.into_iter().enumerate() {
            set_albedo(thread_mut(&mut fabric, j), a);
        }
        if let (Some(total), Some(share)) = (total, share) {
            let c1 = (total * share).clamp(0.0, 1.0);
            let mut c2 = (total - c1).clamp(0.0, 1.0);
            // Rounding may leave c1 + c2 an ulp above 1.
            while c1 + c2 > 1.0 {
                c2 = c2.next_down();
            }
            fabric.thread1.coverage = c1;
            fabric.thread2.coverage = c2;
        }
        fabric
    }
}

/// `parametrisation`'s start moved by up to ±`fraction` of each value (uniform, seeded), kept
/// within the bounds: the "moved" fabrics of the round-trip tests. A value of 0 stays 0.
pub fn perturbed(parametrisation: &dyn Parametrisation, fraction: f64, seed: u64) -> Vec<f64> {
    let mut rng = Pcg64::seed_from_u64(seed);
    parametrisation
        .parameters()
        .iter()
        .map(|p| {
            let factor = 1.0 + fraction * (2.0 * rng.random::<f64>() - 1.0);
            p.clamp(p.start * factor)
        })
        .collect()
}

/// Checks that `parametrisation` makes a valid fabric at the lower bounds, the upper bounds
/// and 198 seeded vectors between them.
#[cfg(test)]
pub(super) fn assert_every_vector_is_valid(parametrisation: &dyn Parametrisation, seed: u64) {
    let mut rng = Pcg64::seed_from_u64(seed);
    for trial in 0..200 {
        let values: Vec<f64> = parametrisation
            .parameters()
            .iter()
            .map(|p| match trial {
                0 => p.lower,
                1 => p.upper,
                _ => p.lower + (p.upper - p.lower) * rng.random::<f64>(),
            })
            .collect();
        parametrisation.fabric(&values).validate().unwrap();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formats::fabric_toml::FabricSet;

    #[test]
    fn start_values_give_back_the_fabric_and_every_vector_is_valid() {
        for fabric in FabricSet::builtin().fabrics() {
            let like = LikeFabric::new(fabric, None);
            let back = like.fabric(&like.start());
            for (a, b) in [
                (&back.thread1, &fabric.thread1),
                (&back.thread2, &fabric.thread2),
            ] {
                for (x, y) in a.albedo_rgb().iter().zip(b.albedo_rgb()) {
                    assert!((x - y).abs() < 1e-15);
                }
                assert_eq!(a.offsets_deg, b.offsets_deg);
                for (x, y) in a.lengths.iter().zip(&b.lengths) {
                    assert!((x - y).abs() < 1e-12 * y.max(1.0), "{:?} {:?}", a, b);
                }
                assert!((a.coverage - b.coverage).abs() < 1e-15);
                assert_eq!((a.eta, a.kd), (b.eta, b.kd));
            }
            let params = like.parameters();
            assert_every_vector_is_valid(&like, 7);
            let fixed = LikeFabric::new(fabric, Some(1.5));
            assert_eq!(fixed.parameters().len() + 2, params.len());
            assert_eq!(fixed.fabric(&fixed.start()).thread2.eta, 1.5);
        }
    }
}
