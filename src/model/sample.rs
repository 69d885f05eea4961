//! One tangent sample of a thread: which way the thread runs, a direction pair in its frame,
//! the sample's terms, and the curve means they add up to. What every curve rule
//! ([`super::patch`]'s midpoint rules, [`super::resonant`]'s quadrature) sums.

use glam::DVec3;

/// Thread `index`'s base tangent t0 and rotation axis b: thread 1 (index 0) runs along x
/// and turns about y, thread 2 along y about x (docs/model.md#frames-and-directions). Every
/// part of the crate that puts a pair into a thread's frame takes it from here.
pub fn thread_axes(index: usize) -> (DVec3, DVec3) {
    if index == 0 {
        (DVec3::X, DVec3::Y)
    } else {
        (DVec3::Y, DVec3::X)
    }
}

/// The curve means of one thread, split so that the RGB albedo factors out:
/// `⟨s⟩ = reflection + A · transmission`, and `masking = ⟨P⟩`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ThreadMeans {
    /// `⟨Fr cos(φd/2) g(γs, θh) M P cos θi / cos²θd⟩`
    pub reflection: f64,
    /// `⟨Ft ((1 − kd) g(γv, θh) + kd) M P cos θi / ((cos θi + cos θo) cos²θd)⟩`
    pub transmission: f64,
    /// `⟨P⟩`
    pub masking: f64,
}

/// The integrand of one tangent sample, split by the lobe each part follows in α:
/// `s = reflection + A · (volume + diffuse)`, and `P = masking`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct SampleTerms {
    /// P
    pub masking: f64,
    /// `Fr cos(φd/2) g(γs, θh) M P cos θi / cos²θd`: follows the surface lobe.
    pub reflection: f64,
    /// `Ft (1 − kd) g(γv, θh) M P cos θi / ((cos θi + cos θo) cos²θd)`: the volume lobe.
    pub volume: f64,
    /// `Ft kd M P cos θi / ((cos θi + cos θo) cos²θd)`: no lobe.
    pub diffuse: f64,
}

/// The components of a direction pair in a thread's fixed axes {t0, b, z}, with the
/// α-independent parts of P.
pub(crate) struct PairInThreadFrame {
    pub ti0: f64,
    pub zi: f64,
    pub bi: f64,
    pub to0: f64,
    pub zo: f64,
    pub bo: f64,
    pub par_i: f64,
    pub par_o: f64,
    pub u_psi: f64,
}

impl PairInThreadFrame {
    /// The facing window: the α interval where both directions face the tangent sample
    /// (w·n(α) > 0). Only the curve rules need it, not single samples.
    pub fn facing(&self) -> (f64, f64) {
        let half_pi = std::f64::consts::FRAC_PI_2;
        let (delta_i, delta_o) = (self.ti0.atan2(self.zi), self.to0.atan2(self.zo));
        (
            (-half_pi - delta_i).max(-half_pi - delta_o),
            (half_pi - delta_i).min(half_pi - delta_o),
        )
    }
}

/// θh = (θi + θo)/2 and cos θd = cos((θi − θo)/2) from each direction's `(cos θ, sin θ)` up
/// to a positive scale: `(|w⊥|, w·t)` with θ = atan2(w·t, |w⊥|) as docs/model.md#angles-of-a-direction defines it.
///
/// The sum of the unit vectors at angles θi and θo is `2 cos θd · (cos θh, sin θh)`, and
/// cos θd ≥ 0 because |θi − θo| ≤ π (both |w⊥| ≥ 0). So one atan2 of the sum gives θh and
/// its length gives cos θd: the same values as two atan2 and a cos up to rounding (about
/// 1e-16 absolute in cos θd, and 1e-16/cos θd in θh, which grows only where wi and wo lie
/// within a hair of +t and −t, far inside any lobe's width), at about half the cost of the
/// transcendental calls that dominate the curve means.
#[inline]
pub(crate) fn half_angle_and_difference(
    (cos_i, sin_i): (f64, f64),
    (cos_o, sin_o): (f64, f64),
) -> (f64, f64) {
    let length = |c: f64, s: f64| (c * c + s * s).sqrt();
    let (li, lo) = (length(cos_i, sin_i), length(cos_o, sin_o));
    let (x, y) = (cos_i / li + cos_o / lo, sin_i / li + sin_o / lo);
    (y.atan2(x), 0.5 * length(x, y))
}
