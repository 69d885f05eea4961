//! A yarn family's knobs (its shape in the cloth and its optics) and the tangent curve its
//! floats make (docs/weave.md#from-a-draft-to-a-fabric).

use super::fibre::{Fibre, UnknownFibre};

/// One yarn family: how it lies in the cloth (crimp, legs, flattening, cover) and its
/// optics. Every field has a default, and [`Yarn::set`] changes one by its key, so commands
/// and Python spell a yarn the same way: `crimp=30,legs=0.4,fibre=silk`.
#[derive(Clone, Debug, PartialEq)]
pub struct Yarn {
    /// Largest tilt α of the yarn, in degrees, where it dives under a crossing yarn.
    pub crimp_deg: f64,
    /// Share of a one-crossing float spent on straight legs at ±crimp, in [0, 1).
    pub legs: f64,
    /// Share of a long float's extra length that lies flat (α = 0), in [0, 1]; the rest
    /// widens the arc over the crossing yarns.
    pub flatten: f64,
    /// How much the arc over a crossing is squashed from a circle into an ellipse of aspect
    /// `1 − squash` (height over half-length), in [0, 0.95]: a squashed arc bends fast near
    /// its legs and spends more of its length at small α.
    pub squash: f64,
    /// Where the arc's two pieces per half meet, as a share of the crimp, in [0.05, 0.95]:
    /// the tilt at which a squashed arc's fast bend near its legs gives way to its flat top.
    pub knee: f64,
    /// Tilt, in degrees, of a long float's own sag between its crossings, in [0, 89]: the
    /// part that would lie flat is drawn instead as legs at ±sag joined by an arc, as a float
    /// pulled down between the yarns it passes over.
    pub sag_deg: f64,
    /// Cover factor, thickness over spacing, in (0, 1]; `None` takes the draft's spacing and
    /// thickness where it gives them, else 1 (no gaps).
    pub cover: Option<f64>,
    /// Refractive index η.
    pub eta: f64,
    /// Colour in sRGB, overriding the draft's thread colours.
    pub colour: Option<[f64; 3]>,
    /// A = albedo_scale × the linear colour.
    pub albedo_scale: f64,
    pub kd: f64,
    pub gamma_s_deg: f64,
    pub gamma_v_deg: f64,
}

impl Default for Yarn {
    /// A plain, matte yarn: the paper's linen optics (kd 0.3, γs 12°, γv 24°, A = 0.3 ×
    /// colour), 25° of crimp, as the paper's linen curve, no legs, half-flat floats, η 1.5.
    fn default() -> Self {
        Self {
            crimp_deg: 25.0,
            legs: 0.0,
            flatten: 0.5,
            squash: 0.0,
            knee: 0.5,
            sag_deg: 0.0,
            cover: None,
            eta: 1.5,
            colour: None,
            albedo_scale: 0.3,
            kd: 0.3,
            gamma_s_deg: 12.0,
            gamma_v_deg: 24.0,
        }
    }
}

/// The keys [`Yarn::set`] takes, for help texts.
pub const YARN_KEYS: &str = "crimp (degrees, [0, 89]), legs ([0, 0.95]), flatten ([0, 1]), squash ([0, 0.95]), \
    knee ([0.05, 0.95]), sag (degrees, [0, 89]), cover ((0, 1]), \
    fibre (silk, polyester, cotton, linen, wool, nylon), eta ([1, 3]), \
    colour (#rrggbb or r/g/b in [0, 1], sRGB), albedo_scale ([0, 10]), kd ([0, 1]), \
    gamma_s and gamma_v (degrees, (0, 90])";

/// Why a yarn knob was refused; each names the knob and what it takes.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum KnobError {
    #[error("yarn knob '{key}' takes a number, got '{value}'")]
    NotANumber { key: String, value: String },
    /// `range` as the knob's help writes it, `[0, 89]` or `(0, 1]`.
    #[error("yarn knob '{key}' must be within {range}, got {value}")]
    OutOfRange {
        key: String,
        range: String,
        value: String,
    },
    #[error("unknown yarn knob '{key}'; known: {YARN_KEYS}")]
    UnknownKnob { key: String },
    #[error("yarn knobs are key=value, got '{item}'")]
    NotKeyValue { item: String },
    #[error("a colour is #rrggbb or r/g/b with each in [0, 1], got '{text}'")]
    Colour { text: String },
    #[error(transparent)]
    Fibre(#[from] UnknownFibre),
}

impl Yarn {
    /// Sets the knob `key` from its text; the error names the key and its range.
    pub fn set(&mut self, key: &str, value: &str) -> Result<(), KnobError> {
        let key = key.trim();
        let value = value.trim();
        let number = |lo: f64, hi: f64, lo_open: bool| -> Result<f64, KnobError> {
            let v: f64 = value.parse().map_err(|_| KnobError::NotANumber {
                key: key.to_string(),
                value: value.to_string(),
            })?;
            let inside = v.is_finite() && v <= hi && if lo_open { v > lo } else { v >= lo };
            if !inside {
                let open = if lo_open { "(" } else { "[" };
                return Err(KnobError::OutOfRange {
                    key: key.to_string(),
                    range: format!("{open}{lo}, {hi}]"),
                    value: value.to_string(),
                });
            }
            Ok(v)
        };
        match key.to_ascii_lowercase().as_str() {
            "crimp" => self.crimp_deg = number(0.0, 89.0, false)?,
            "legs" => self.legs = number(0.0, 0.95, false)?,
            "flatten" => self.flatten = number(0.0, 1.0, false)?,
            "squash" => self.squash = number(0.0, 0.95, false)?,
            "knee" => self.knee = number(0.05, 0.95, false)?,
            "sag" => self.sag_deg = number(0.0, 89.0, false)?,
            "cover" => self.cover = Some(number(0.0, 1.0, true)?),
            "fibre" | "fiber" => self.eta = value.parse::<Fibre>()?.eta(),
            "eta" => self.eta = number(1.0, 3.0, false)?,
            "colour" | "color" => self.colour = Some(parse_colour(value)?),
            "albedo_scale" => self.albedo_scale = number(0.0, 10.0, false)?,
            "kd" => self.kd = number(0.0, 1.0, false)?,
            "gamma_s" => self.gamma_s_deg = number(0.0, 90.0, true)?,
            "gamma_v" => self.gamma_v_deg = number(0.0, 90.0, true)?,
            other => {
                return Err(KnobError::UnknownKnob {
                    key: other.to_string(),
                });
            }
        }
        Ok(())
    }

    /// Sets every `key=value` of a comma-separated list, in order.
    pub fn set_all(&mut self, list: &str) -> Result<(), KnobError> {
        for item in list.split(',').filter(|s| !s.trim().is_empty()) {
            let (key, value) = item.split_once('=').ok_or_else(|| KnobError::NotKeyValue {
                item: item.to_string(),
            })?;
            self.set(key, value)?;
        }
        Ok(())
    }
}

fn parse_colour(text: &str) -> Result<[f64; 3], KnobError> {
    let bad = || KnobError::Colour {
        text: text.to_string(),
    };
    if let Some(hex) = text.strip_prefix('#') {
        if hex.len() != 6 || !hex.is_ascii() {
            return Err(bad());
        }
        let channel = |i: usize| {
            u8::from_str_radix(&hex[2 * i..2 * i + 2], 16)
                .map(|v| f64::from(v) / 255.0)
                .map_err(|_| bad())
        };
        return Ok([channel(0)?, channel(1)?, channel(2)?]);
    }
    let parts: Vec<f64> = text
        .split('/')
        .map(|p| p.trim().parse::<f64>().map_err(|_| bad()))
        .collect::<Result<_, _>>()?;
    match parts[..] {
        [r, g, b] if parts.iter().all(|c| (0.0..=1.0).contains(c)) => Ok([r, g, b]),
        _ => Err(bad()),
    }
}

/// The linear value of an sRGB component in [0, 1] (IEC 61966-2-1).
pub fn srgb_to_linear(c: f64) -> f64 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// A family's tangent curve: `(offsets_deg, lengths)` in the fabric schema, from its floats
/// (`(length, count)` pairs, [`super::Draft::floats`]) and the yarn's shape knobs.
///
/// Each float is drawn as the yarn's visible spine, in units of the crossing yarns' spacing
/// p: a straight leg at −crimp, an arc from −crimp to 0, a flat part at α = 0, an arc from 0
/// to +crimp and a leg at +crimp. On a circle α grows linearly with arc length, so each arc
/// is one segment of the schema; an arc squashed into an ellipse (`squash`) is drawn as two
/// segments per half, split at the tilt `knee × crimp`, holding the ellipse's shares of its
/// length. A float over one crossing is one arc of length p (the paper's linen curve with no
/// legs), with legs of total length `legs/(1 − legs)·p`, so that they hold the share `legs`
/// of it. A float over L crossings has L − 1 more spacings, of which the share `flatten`
/// lies flat and the rest widens the arc; with `sag` the flat part is itself drawn as legs
/// at ±sag (the share `legs` of it) and a circular arc between them. The model needs only
/// the distribution of α along the curve (the curve mean is an integral over arc length), so
/// the floats of a family add up, part by part, into one curve, and where the flat part's
/// small curve sits within it does not matter.
pub fn tangent_curve(floats: &[(usize, usize)], yarn: &Yarn) -> (Vec<f64>, Vec<f64>) {
    let count: usize = floats.iter().map(|&(_, n)| n).sum();
    if count == 0 || yarn.crimp_deg == 0.0 {
        return (vec![0.0], vec![]);
    }
    let mut arc = 0.0;
    let mut flat = 0.0;
    for &(length, n) in floats {
        let extra = (length - 1) as f64;
        arc += n as f64 * (1.0 + (1.0 - yarn.flatten) * extra);
        flat += n as f64 * yarn.flatten * extra;
    }
    // Per float, so the lengths read in crossing spacings.
    let (arc, flat) = (arc / count as f64, flat / count as f64);
    let legs = yarn.legs / (1.0 - yarn.legs);
    let c = yarn.crimp_deg;
    // Each half of the arc in two pieces, split where α is knee × crimp, holding the shares
    // of the elliptic arc's length (on a circle the slopes are equal and they merge again).
    let k = yarn.knee;
    let outer_share = ellipse_outer_share(1.0 - yarn.squash, k, c.to_radians());
    let half = arc / 2.0;
    let (outer, inner) = (half * outer_share, half * (1.0 - outer_share));
    // The flat part's own legs and arc; at sag 0 they are all at α = 0 and merge, and with
    // no flat part there is nothing to sag (rather than jumps of no length).
    let s = if flat > 0.0 { yarn.sag_deg } else { 0.0 };
    let (sag_legs, sag_arc) = (flat * yarn.legs / 2.0, flat * (1.0 - yarn.legs));
    let points = [
        (-c, legs / 2.0),
        (-c, outer),
        (-k * c, inner),
        (0.0, 0.0),
        (-s, sag_legs),
        (-s, sag_arc),
        (s, sag_legs),
        (s, 0.0),
        (0.0, inner),
        (k * c, outer),
        (c, legs / 2.0),
        (c, 0.0),
    ];
    simplified(&points)
}

/// The share of an elliptic arc's length between the tilts α = knee·c and c, of its length
/// between 0 and c, for an ellipse of aspect `r` (height over half-length).
///
/// On x = sin t, z = r cos t the tilt is α = atan(r tan t) and the arc length element is
/// sqrt(cos² t + r² sin² t) dt; both integrals are taken by the midpoint rule in t, smooth
/// integrands for r ≥ 0.05, so 256 nodes leave an error far below any length the fit can
/// tell apart.
fn ellipse_outer_share(r: f64, knee: f64, c: f64) -> f64 {
    let t_of = |alpha: f64| (alpha.tan() / r).atan();
    let length = |t0: f64, t1: f64| {
        let n = 256;
        let h = (t1 - t0) / n as f64;
        (0..n)
            .map(|i| {
                let t = t0 + (i as f64 + 0.5) * h;
                (t.cos().powi(2) + r * r * t.sin().powi(2)).sqrt() * h
            })
            .sum::<f64>()
    };
    let (t_knee, t_full) = (t_of(knee * c), t_of(c));
    let (inner, outer) = (length(0.0, t_knee), length(t_knee, t_full));
    outer / (inner + outer)
}

/// The curve through `points` (offset, length of the segment to the next point; the last
/// length unused) in the schema's form: segments of no length between equal offsets
/// dropped, and neighbouring segments of the same slope dα/ds merged (exactly the same
/// distribution of α).
fn simplified(points: &[(f64, f64)]) -> (Vec<f64>, Vec<f64>) {
    let mut offsets: Vec<f64> = vec![points[0].0];
    let mut lengths: Vec<f64> = vec![];
    for window in points.windows(2) {
        let ((o0, l), (o1, _)) = (window[0], window[1]);
        if l == 0.0 && o0 == o1 {
            continue;
        }
        if let (Some(&last_l), true) = (lengths.last(), offsets.len() >= 2) {
            let last_o = offsets[offsets.len() - 2];
            let o_prev = offsets[offsets.len() - 1];
            let same_slope = last_l > 0.0
                && l > 0.0
                && ((o_prev - last_o) / last_l - (o1 - o0) / l).abs()
                    <= 1e-9 * ((o1 - o0) / l).abs().max(1e-300);
            if same_slope {
                *offsets.last_mut().expect("a point") = o1;
                *lengths.last_mut().expect("a segment") += l;
                continue;
            }
        }
        offsets.push(o1);
        lengths.push(l);
    }
    (offsets, lengths)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_crossing_without_legs_is_the_papers_linen_curve() {
        let (offsets, lengths) = tangent_curve(&[(1, 2)], &Yarn::default());
        assert_eq!(offsets, vec![-25.0, 25.0]);
        assert_eq!(lengths, vec![1.0]);
    }

    #[test]
    fn long_floats_get_legs_arcs_and_a_flat_part() {
        let yarn = Yarn {
            crimp_deg: 32.0,
            legs: 0.5,
            flatten: 0.5,
            ..Yarn::default()
        };
        let (offsets, lengths) = tangent_curve(&[(4, 5)], &yarn);
        assert_eq!(offsets, vec![-32.0, -32.0, 0.0, 0.0, 32.0, 32.0]);
        // legs 1 in all, arcs 1 + 1.5, flat 1.5.
        assert_eq!(lengths, vec![0.5, 1.25, 1.5, 1.25, 0.5]);
    }

    #[test]
    fn a_squashed_arc_spends_more_of_its_length_at_small_tilts() {
        let yarn = Yarn {
            crimp_deg: 32.0,
            squash: 0.6,
            ..Yarn::default()
        };
        let (offsets, lengths) = tangent_curve(&[(1, 1)], &yarn);
        assert_eq!(offsets, vec![-32.0, -16.0, 16.0, 32.0]);
        assert!(lengths[1] > 2.0 * lengths[0], "{lengths:?}");
        assert!((lengths.iter().sum::<f64>() - 1.0).abs() < 1e-12);
        // A circle's two pieces per half are one segment again.
        assert!((ellipse_outer_share(1.0, 0.5, 0.5) - 0.5).abs() < 1e-12);
    }

    #[test]
    fn the_knee_moves_where_a_squashed_arc_bends() {
        let yarn = Yarn {
            crimp_deg: 32.0,
            squash: 0.6,
            knee: 0.5625,
            ..Yarn::default()
        };
        let (offsets, _) = tangent_curve(&[(1, 1)], &yarn);
        assert_eq!(offsets, vec![-32.0, -18.0, 18.0, 32.0]);
        // Further out, less of the arc lies beyond the knee.
        assert!(ellipse_outer_share(0.4, 0.7, 0.5) < ellipse_outer_share(0.4, 0.5, 0.5));
    }

    #[test]
    fn a_sagging_float_draws_its_flat_part_as_a_small_arc_with_legs() {
        let flat = Yarn {
            crimp_deg: 30.0,
            legs: 0.5,
            flatten: 1.0,
            ..Yarn::default()
        };
        let sagging = Yarn {
            sag_deg: 5.0,
            ..flat.clone()
        };
        let (offsets, lengths) = tangent_curve(&[(4, 1)], &sagging);
        // legs 1 and arc 1 over the crossing; the flat part, 3, as legs 1.5 and arc 1.5.
        assert_eq!(
            offsets,
            vec![-30.0, -30.0, 0.0, -5.0, -5.0, 5.0, 5.0, 0.0, 30.0, 30.0]
        );
        assert_eq!(lengths, vec![0.5, 0.5, 0.0, 0.75, 1.5, 0.75, 0.0, 0.5, 0.5]);
        // No sag is the flat float; a float over one crossing has nothing to sag.
        assert_eq!(
            tangent_curve(
                &[(4, 1)],
                &Yarn {
                    sag_deg: 0.0,
                    ..sagging.clone()
                }
            ),
            tangent_curve(&[(4, 1)], &flat)
        );
        assert_eq!(
            tangent_curve(&[(1, 1)], &sagging),
            tangent_curve(&[(1, 1)], &flat)
        );
    }

    #[test]
    fn knobs_parse_and_name_what_is_wrong() {
        let mut yarn = Yarn::default();
        yarn.set_all("crimp=30, legs=0.4,fibre=silk,colour=#ff8000")
            .unwrap();
        assert_eq!((yarn.crimp_deg, yarn.legs, yarn.eta), (30.0, 0.4, 1.345));
        assert_eq!(yarn.colour, Some([1.0, 128.0 / 255.0, 0.0]));
        for (list, needle) in [
            ("crimp=95", "crimp"),
            ("legs=1", "legs"),
            ("cover=0", "cover"),
            ("fibre=hemp", "unknown fibre"),
            ("colour=#12", "colour"),
            ("colour=1/2/0", "colour"),
            ("twist=3", "unknown yarn knob"),
            ("knee=1", "knee"),
            ("sag=-1", "sag"),
            ("crimp", "key=value"),
            ("eta=NaN", "eta"),
        ] {
            let error = Yarn::default().set_all(list).unwrap_err().to_string();
            assert!(error.contains(needle), "{list}: {error}");
        }
    }
}
