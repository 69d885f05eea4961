//! Weaves: a fabric of the model made from a weave draft (docs/weave.md). The draft
//! ([`draft`]) gives each family's face fraction and floats; the yarns ([`yarn`]) turn them
//! into coverages and tangent curves, and carry the optics. Pure maths, no I/O: WIF files
//! are read by [`crate::formats::wif`].

pub mod draft;
pub mod fibre;
pub mod yarn;

pub use draft::{Draft, DraftError, Family, NamedWeave, Yarns};
pub use fibre::{Fibre, UnknownFibre};
pub use yarn::{KnobError, YARN_KEYS, Yarn, srgb_to_linear, tangent_curve};

use crate::model::{Fabric, FabricError, ModelOptions, Thread};

/// A draft with its two yarns: everything a woven fabric is made from. The warp becomes
/// thread 1 (along x), the weft thread 2 (along y).
#[derive(Clone, Debug, PartialEq)]
pub struct Weave {
    pub draft: Draft,
    pub warp: Yarn,
    pub weft: Yarn,
}

/// What the draft and the yarns make of one family: printed by `clothbake weave`.
#[derive(Clone, Debug, PartialEq)]
pub struct FamilySummary {
    pub face_fraction: f64,
    pub cover: f64,
    pub coverage: f64,
    pub floats: Vec<(usize, usize)>,
    pub offsets_deg: Vec<f64>,
    pub lengths: Vec<f64>,
}

impl Weave {
    /// A weave of `draft` with default yarns.
    pub fn new(draft: Draft) -> Self {
        Self {
            draft,
            warp: Yarn::default(),
            weft: Yarn::default(),
        }
    }

    pub fn yarn(&self, family: Family) -> &Yarn {
        match family {
            Family::Warp => &self.warp,
            Family::Weft => &self.weft,
        }
    }

    /// The family's cover factor k (thickness over spacing, at most 1): the yarn's knob,
    /// else the draft's spacing and thickness, else 1.
    pub fn cover(&self, family: Family) -> f64 {
        let yarns = self.draft.yarns(family);
        self.yarn(family)
            .cover
            .unwrap_or_else(|| match (yarns.thickness, yarns.spacing) {
                (Some(d), Some(p)) if d > 0.0 && p > 0.0 => (d / p).min(1.0),
                _ => 1.0,
            })
    }

    /// Each family's area coverage `[warp, weft]`.
    ///
    /// In one crossing's cell of the cloth (spacing p_w by p_f) the warp covers a strip of
    /// width k_w·p_w and the weft a strip k_f·p_f wide. Where only one strip lies, its yarn is
    /// seen; where they cross (the share k_w·k_f) the yarn on top is, as often as the draft
    /// puts it there (its face fraction f); the rest, (1 − k_w)(1 − k_f), is gap. So
    /// `a_w = k_w(1 − k_f) + k_w·k_f·f_w` and `a_f = k_f(1 − k_w) + k_w·k_f·f_f`, which add
    /// to `1 − (1 − k_w)(1 − k_f)`, and with no gaps (k = 1) each is its face fraction.
    pub fn coverages(&self) -> [f64; 2] {
        let (kw, kf) = (self.cover(Family::Warp), self.cover(Family::Weft));
        let fw = self.draft.face_fraction(Family::Warp);
        let warp = kw * (1.0 - kf) + kw * kf * fw;
        // The weft's as the covered total less the warp's, so that the two add to at most 1
        // whatever the rounding (the schema's c1 + c2 ≤ 1).
        let mut weft = ((kw + kf - kw * kf).min(1.0) - warp).max(0.0);
        while warp + weft > 1.0 {
            weft = weft.next_down();
        }
        [warp, weft]
    }

    /// The family's colour in linear RGB: the yarn's own, else the mean of the draft's
    /// thread colours weighted by how often each thread is on top, else white.
    pub fn colour(&self, family: Family) -> [f64; 3] {
        let linear = |c: [f64; 3]| c.map(srgb_to_linear);
        if let Some(c) = self.yarn(family).colour {
            return linear(c);
        }
        let d = &self.draft;
        let colours = &d.yarns(family).colours;
        let mut sum = [0.0; 3];
        let mut weight = 0.0;
        let threads = match family {
            Family::Warp => d.ends(),
            Family::Weft => d.picks(),
        };
        for thread in 0..threads {
            let Some(Some(c)) = colours.get(thread) else {
                continue;
            };
            let on_top = match family {
                Family::Warp => (0..d.picks()).filter(|&p| d.warp_up(thread, p)).count(),
                Family::Weft => (0..d.ends()).filter(|&e| !d.warp_up(e, thread)).count(),
            };
            let c = linear(*c);
            for k in 0..3 {
                sum[k] += on_top as f64 * c[k];
            }
            weight += on_top as f64;
        }
        if weight > 0.0 {
            sum.map(|s| s / weight)
        } else {
            [1.0; 3]
        }
    }

    /// What the draft and the yarns make of `family`.
    pub fn summary(&self, family: Family) -> FamilySummary {
        let floats = self.draft.floats(family);
        let (offsets_deg, lengths) = tangent_curve(&floats, self.yarn(family));
        let index = match family {
            Family::Warp => 0,
            Family::Weft => 1,
        };
        FamilySummary {
            face_fraction: self.draft.face_fraction(family),
            cover: self.cover(family),
            coverage: self.coverages()[index],
            floats,
            offsets_deg,
            lengths,
        }
    }

    /// The fabric called `name`: thread 1 the warp, thread 2 the weft, in today's schema;
    /// validated, so every command, table and shader takes it.
    pub fn fabric(&self, name: &str) -> Result<Fabric, FabricError> {
        let thread = |family: Family| {
            let yarn = self.yarn(family);
            let summary = self.summary(family);
            Thread {
                eta: yarn.eta,
                albedo: self.colour(family),
                albedo_scale: yarn.albedo_scale,
                kd: yarn.kd,
                gamma_s_deg: yarn.gamma_s_deg,
                gamma_v_deg: yarn.gamma_v_deg,
                coverage: summary.coverage,
                offsets_deg: summary.offsets_deg,
                lengths: summary.lengths,
            }
        };
        let fabric = Fabric {
            name: name.to_string(),
            options: ModelOptions::default(),
            thread1: thread(Family::Warp),
            thread2: thread(Family::Weft),
        };
        fabric.validate()?;
        Ok(fabric)
    }

    /// The same weave with warp and weft exchanged, each with its yarn (the cloth turned by
    /// 90°).
    pub fn transposed(&self) -> Self {
        Self {
            draft: self.draft.transposed(),
            warp: self.weft.clone(),
            weft: self.warp.clone(),
        }
    }
}

/// A fabric name made from a weave's spelling or a file's stem: the characters the schema
/// does not allow become `_`, cut to 64.
pub fn fabric_name_from(text: &str) -> String {
    let name: String = text
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '_' || c == '-' {
                c
            } else {
                '_'
            }
        })
        .take(64)
        .collect();
    if name.is_empty() {
        "weave".into()
    } else {
        name
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn weave(name: &str) -> Weave {
        Weave::new(name.parse::<NamedWeave>().unwrap().draft())
    }

    #[test]
    fn coverage_is_the_face_fraction_without_gaps() {
        let satin = weave("satin:5");
        assert_eq!(satin.coverages(), [0.8, 0.19999999999999996]);
        // Whatever the rounding, the two add to at most 1 (1e6 covers against the faces of
        // a satin: one full cover made 1 + 2⁻⁵² before).
        let mut satin = weave("satin:5");
        for i in 1..=1_000_000 {
            satin.weft.cover = Some(i as f64 / 1e6);
            let [w, f] = satin.coverages();
            assert!(w + f <= 1.0 && f >= 0.0, "{i}: {w} + {f}");
        }
    }

    #[test]
    fn gaps_from_cover_factors() {
        let mut plain = weave("plain");
        plain.warp.cover = Some(0.5);
        plain.weft.cover = Some(0.5);
        let [w, f] = plain.coverages();
        assert!((w - 0.375).abs() < 1e-15 && (f - 0.375).abs() < 1e-15);
        // The paper's crepe de chine: a dense warp over a weft at half cover.
        let mut crepe = weave("plain");
        crepe.weft.cover = Some(0.5);
        assert_eq!(crepe.coverages(), [0.75, 0.25]);
    }

    #[test]
    fn plain_weave_of_default_yarns_makes_a_valid_fabric() {
        let fabric = weave("plain").fabric("plain").unwrap();
        assert_eq!(fabric.thread1.offsets_deg, vec![-25.0, 25.0]);
        assert_eq!(fabric.thread1.coverage, 0.5);
        assert_eq!(fabric.thread1, fabric.thread2);
    }

    #[test]
    fn family_colour_weights_threads_by_their_face() {
        let mut w = weave("twill:3/1");
        w.draft.warp.colours = vec![Some([1.0, 0.0, 0.0]), None, None, Some([0.0, 0.0, 1.0])];
        assert_eq!(w.colour(Family::Warp), [0.5, 0.0, 0.5]);
        assert_eq!(w.colour(Family::Weft), [1.0; 3]);
    }

    #[test]
    fn names_from_spellings() {
        assert_eq!(fabric_name_from("twill:2/1:s"), "twill_2_1_s");
        assert_eq!(fabric_name_from(""), "weave");
    }
}
