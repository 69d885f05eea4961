//! A weave draft: the interlacement of warp ends and weft picks (the drawdown), the yarns'
//! colours, spacing and thickness, and the named weaves (`plain`, `basket:N`, `twill:N/M`,
//! `satin:N`, `sateen:N`). Pure data and arithmetic; WIF files are read by
//! [`crate::formats::wif`].
//!
//! Orientation: pick 1 is the first row and end 1 the first column of the drawdown. The
//! warp becomes the fabric's thread 1 (along x), the weft thread 2 (along y)
//! (docs/weave.md#from-a-draft-to-a-fabric).

use std::fmt;
use std::str::FromStr;

/// Most ends or picks a draft may have: far beyond any loom (a Jacquard loom has a few
/// thousand hooks), and a bound on what an untrusted file can make us allocate.
pub const MAX_THREADS: usize = 16_384;
/// Most cells (ends × picks) of a drawdown: 16 M booleans.
pub const MAX_CELLS: usize = 1 << 24;

/// Why a draft cannot be made.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct DraftError(pub String);

/// The yarns of one family: a colour per thread (sRGB components in [0, 1], `None` where
/// the draft gives none) and the mean spacing and thickness, in the draft's unit, where
/// given.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Yarns {
    pub colours: Vec<Option<[f64; 3]>>,
    pub spacing: Option<f64>,
    pub thickness: Option<f64>,
}

/// A weave draft reduced to what the fabric needs: which family is on top at each crossing,
/// and the yarns of each family.
#[derive(Clone, Debug, PartialEq)]
pub struct Draft {
    ends: usize,
    picks: usize,
    /// `warp_up[pick * ends + end]`: the warp end lies over the weft pick.
    warp_up: Vec<bool>,
    pub warp: Yarns,
    pub weft: Yarns,
}

/// The two families of a draft.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Family {
    Warp,
    Weft,
}

impl Draft {
    /// A draft of `ends` × `picks` crossings; `warp_up(end, pick)` (0-based) says whether the
    /// warp is on top there. The yarns are left without colour, spacing or thickness.
    pub fn from_fn(
        ends: usize,
        picks: usize,
        warp_up: impl Fn(usize, usize) -> bool,
    ) -> Result<Self, DraftError> {
        check_size(ends, picks)?;
        let cells = (0..picks)
            .flat_map(|p| (0..ends).map(move |e| (e, p)))
            .map(|(e, p)| warp_up(e, p))
            .collect();
        Ok(Self {
            ends,
            picks,
            warp_up: cells,
            warp: Yarns::default(),
            weft: Yarns::default(),
        })
    }

    pub fn ends(&self) -> usize {
        self.ends
    }

    pub fn picks(&self) -> usize {
        self.picks
    }

    /// Whether the warp end `end` lies over the weft pick `pick` (0-based).
    pub fn warp_up(&self, end: usize, pick: usize) -> bool {
        self.warp_up[pick * self.ends + end]
    }

    /// The drawdown as text: one line per pick, pick 1 first, one character per end, end 1
    /// first, `#` where the warp is on top and `.` where the weft is.
    pub fn drawdown(&self) -> String {
        let mut out = String::with_capacity((self.ends + 1) * self.picks);
        for pick in 0..self.picks {
            for end in 0..self.ends {
                out.push(if self.warp_up(end, pick) { '#' } else { '.' });
            }
            out.push('\n');
        }
        out
    }

    /// The share of crossings where `family` is on top (the warp's and the weft's add to 1).
    pub fn face_fraction(&self, family: Family) -> f64 {
        let up = self.warp_up.iter().filter(|&&u| u).count() as f64 / self.warp_up.len() as f64;
        match family {
            Family::Warp => up,
            Family::Weft => 1.0 - up,
        }
    }

    /// Every float of `family` over the draft taken as a repeat: `(length, count)` pairs in
    /// increasing length, a float's length being the number of crossing threads it lies over
    /// in a row (wrapping around the repeat). A thread that is never on top has no float; one
    /// that is on top all along has one float as long as the repeat.
    pub fn floats(&self, family: Family) -> Vec<(usize, usize)> {
        let (threads, along) = match family {
            Family::Warp => (self.ends, self.picks),
            Family::Weft => (self.picks, self.ends),
        };
        let on_top = |thread: usize, k: usize| match family {
            Family::Warp => self.warp_up(thread, k),
            Family::Weft => !self.warp_up(k, thread),
        };
        let mut histogram = std::collections::BTreeMap::new();
        for thread in 0..threads {
            // Start the walk just after a crossing where the thread is under, so that no run
            // is split by the wrap-around.
            let Some(under) = (0..along).find(|&k| !on_top(thread, k)) else {
                *histogram.entry(along).or_insert(0) += 1;
                continue;
            };
            let mut run = 0;
            for step in 1..=along {
                if on_top(thread, (under + step) % along) {
                    run += 1;
                } else if run > 0 {
                    *histogram.entry(run).or_insert(0) += 1;
                    run = 0;
                }
            }
        }
        histogram.into_iter().collect()
    }

    /// The same cloth seen from its back: every crossing inverted, and the ends in reverse
    /// order (turning the cloth over about the warp mirrors the ends).
    pub fn back(&self) -> Self {
        let mut back = self.mirrored();
        for up in &mut back.warp_up {
            *up = !*up;
        }
        back
    }

    /// The draft with warp and weft exchanged (the cloth turned by 90° and over, so that
    /// each family keeps its face): the end `e` of pick `p` becomes pick `e` of end `p`, and
    /// what lay on top still does.
    pub fn transposed(&self) -> Self {
        let mut turned = Self::from_fn(self.picks, self.ends, |e, p| !self.warp_up(p, e))
            .expect("same cell count as a valid draft");
        turned.warp = self.weft.clone();
        turned.weft = self.warp.clone();
        turned
    }

    /// The draft mirrored along the weft: the ends in reverse order. An S twill's mirror is
    /// the Z twill of the same counts.
    pub fn mirrored(&self) -> Self {
        let mut mirror = Self::from_fn(self.ends, self.picks, |e, p| {
            self.warp_up(self.ends - 1 - e, p)
        })
        .expect("same size as a valid draft");
        mirror.warp = Yarns {
            colours: self.warp.colours.iter().rev().copied().collect(),
            ..self.warp.clone()
        };
        mirror.weft = self.weft.clone();
        mirror
    }

    /// The draft as `--back` and `--swap` orient it, on every command and in Python: turned
    /// over ([`Draft::back`]) when `back`, then warp and weft exchanged
    /// ([`Draft::transposed`]) when `swap`.
    pub fn oriented(self, back: bool, swap: bool) -> Self {
        let turned = if back { self.back() } else { self };
        if swap { turned.transposed() } else { turned }
    }

    /// The yarns of `family`.
    pub fn yarns(&self, family: Family) -> &Yarns {
        match family {
            Family::Warp => &self.warp,
            Family::Weft => &self.weft,
        }
    }
}

fn check_size(ends: usize, picks: usize) -> Result<(), DraftError> {
    if ends == 0 || picks == 0 {
        return Err(DraftError(format!(
            "a draft needs at least one end and one pick, got {ends} ends and {picks} picks"
        )));
    }
    if ends > MAX_THREADS || picks > MAX_THREADS {
        return Err(DraftError(format!(
            "{ends} ends and {picks} picks: at most {MAX_THREADS} of each are allowed"
        )));
    }
    if ends * picks > MAX_CELLS {
        return Err(DraftError(format!(
            "{ends} ends × {picks} picks is more than {MAX_CELLS} crossings"
        )));
    }
    Ok(())
}

/// Largest repeat a named weave may have (`twill:N/M` with N + M, `basket:N` with 2N,
/// `satin:N`): wider than any woven structure of one repeat in use.
pub const MAX_NAMED_REPEAT: usize = 64;

/// The direction a twill's diagonal runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TwillDirection {
    /// Z twill (right-hand): with pick 1 at the bottom, as weaving programs draw it, the
    /// diagonal rises to the right; each pick moves the floats one end to the right.
    Z,
    /// S twill (left-hand): the mirror of Z.
    S,
}

/// A named weave, spelled the same on every command and in Python:
/// `plain`, `basket:N`, `twill:N/M` (Z) or `twill:N/M:s`, `satin:N` or `satin:N/STEP`
/// (warp-faced), `sateen:N` or `sateen:N/STEP` (weft-faced).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NamedWeave {
    Plain,
    /// Pairs (N = 2), triples, … of ends and picks woven as one.
    Basket(usize),
    /// `up` warp over, `down` under, shifted one end per pick.
    Twill {
        up: usize,
        down: usize,
        direction: TwillDirection,
    },
    /// A satin of `ends` with the given step (the move of the interlacing per pick); warp
    /// floats over `ends − 1` picks when `warp_faced`, else weft floats over `ends − 1` ends.
    Satin {
        ends: usize,
        step: usize,
        warp_faced: bool,
    },
}

impl NamedWeave {
    /// The syntax every command lists in its help.
    pub const SYNTAX: &'static str =
        "plain, basket:N, twill:N/M[:s|:z], satin:N[/STEP], sateen:N[/STEP], or a .wif file";

    /// The draft of one repeat.
    pub fn draft(&self) -> Draft {
        let draft = match *self {
            NamedWeave::Plain => Draft::from_fn(2, 2, |e, p| (e + p) % 2 == 0),
            NamedWeave::Basket(n) => Draft::from_fn(2 * n, 2 * n, |e, p| (e / n + p / n) % 2 == 0),
            NamedWeave::Twill {
                up,
                down,
                direction,
            } => {
                let repeat = up + down;
                Draft::from_fn(repeat, repeat, |e, p| {
                    let shift = match direction {
                        TwillDirection::Z => repeat - p % repeat,
                        TwillDirection::S => p,
                    };
                    (e + shift) % repeat < up
                })
            }
            NamedWeave::Satin {
                ends,
                step,
                warp_faced,
            } => Draft::from_fn(ends, ends, |e, p| {
                let interlacing = e == (p * step) % ends;
                interlacing != warp_faced
            }),
        };
        draft.expect("named weaves are parsed within MAX_NAMED_REPEAT")
    }
}

impl fmt::Display for NamedWeave {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            NamedWeave::Plain => write!(f, "plain"),
            NamedWeave::Basket(n) => write!(f, "basket:{n}"),
            NamedWeave::Twill {
                up,
                down,
                direction,
            } => {
                let d = match direction {
                    TwillDirection::Z => "z",
                    TwillDirection::S => "s",
                };
                write!(f, "twill:{up}/{down}:{d}")
            }
            NamedWeave::Satin {
                ends,
                step,
                warp_faced,
            } => {
                let name = if warp_faced { "satin" } else { "sateen" };
                write!(f, "{name}:{ends}/{step}")
            }
        }
    }
}

fn parse_count(text: &str, what: &str, least: usize) -> Result<usize, DraftError> {
    let n: usize = text
        .trim()
        .parse()
        .map_err(|_| DraftError(format!("{what} must be a whole number, got '{text}'")))?;
    if n < least || n > MAX_NAMED_REPEAT {
        return Err(DraftError(format!(
            "{what} must be within {least}..={MAX_NAMED_REPEAT}, got {n}"
        )));
    }
    Ok(n)
}

fn gcd(a: usize, b: usize) -> usize {
    if b == 0 { a } else { gcd(b, a % b) }
}

/// The smallest step of a regular satin of `ends`: coprime with it and neither 1 nor
/// `ends − 1`, which would make a twill.
fn default_satin_step(ends: usize) -> Option<usize> {
    (2..ends.saturating_sub(1)).find(|&s| gcd(s, ends) == 1)
}

impl FromStr for NamedWeave {
    type Err = DraftError;

    fn from_str(text: &str) -> Result<Self, DraftError> {
        let text = text.trim();
        let (name, parameter) = match text.split_once(':') {
            Some((name, parameter)) => (name, Some(parameter)),
            None => (text, None),
        };
        let needs = |syntax: &str| {
            parameter.ok_or_else(|| DraftError(format!("'{name}' needs a parameter: {syntax}")))
        };
        match name.to_ascii_lowercase().as_str() {
            "plain" => match parameter {
                None => Ok(NamedWeave::Plain),
                Some(p) => Err(DraftError(format!("'plain' takes no parameter, got '{p}'"))),
            },
            "basket" => {
                let n = parse_count(needs("basket:N")?, "basket's N", 1)?;
                if 2 * n > MAX_NAMED_REPEAT {
                    return Err(DraftError(format!(
                        "basket:{n} repeats on {} ends, more than {MAX_NAMED_REPEAT}",
                        2 * n
                    )));
                }
                Ok(NamedWeave::Basket(n))
            }
            "twill" => {
                let parameter = needs("twill:N/M[:s|:z]")?;
                let (counts, direction) = match parameter.split_once(':') {
                    Some((counts, d)) => (counts, d),
                    None => (parameter, "z"),
                };
                let direction = match direction.to_ascii_lowercase().as_str() {
                    "z" => TwillDirection::Z,
                    "s" => TwillDirection::S,
                    other => {
                        return Err(DraftError(format!(
                            "a twill's direction is 's' or 'z', got '{other}'"
                        )));
                    }
                };
                let (up, down) = counts.split_once('/').ok_or_else(|| {
                    DraftError(format!("twill needs N/M (ends up/down), got '{counts}'"))
                })?;
                let up = parse_count(up, "twill's N", 1)?;
                let down = parse_count(down, "twill's M", 1)?;
                if up + down < 3 || up + down > MAX_NAMED_REPEAT {
                    return Err(DraftError(format!(
                        "twill:{up}/{down} repeats on {} ends: a twill needs 3..={MAX_NAMED_REPEAT} \
                         (twill:1/1 is plain)",
                        up + down
                    )));
                }
                Ok(NamedWeave::Twill {
                    up,
                    down,
                    direction,
                })
            }
            "satin" | "sateen" => {
                let warp_faced = name.eq_ignore_ascii_case("satin");
                let parameter = needs(&format!("{name}:N[/STEP]"))?;
                let (ends, step) = match parameter.split_once('/') {
                    Some((ends, step)) => (ends, Some(step)),
                    None => (parameter, None),
                };
                let ends = parse_count(ends, &format!("{name}'s N"), 5)?;
                let step = match step {
                    Some(step) => parse_count(step, &format!("{name}'s step"), 2)?,
                    None => default_satin_step(ends).ok_or_else(|| {
                        DraftError(format!("there is no regular {name} of {ends} ends"))
                    })?,
                };
                if step >= ends - 1 || gcd(step, ends) != 1 {
                    return Err(DraftError(format!(
                        "{name}:{ends}/{step}: the step must be coprime with {ends} and within \
                         2..={}",
                        ends - 2
                    )));
                }
                Ok(NamedWeave::Satin {
                    ends,
                    step,
                    warp_faced,
                })
            }
            other => Err(DraftError(format!(
                "unknown weave '{other}'; expected {}",
                NamedWeave::SYNTAX
            ))),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn weave(text: &str) -> Draft {
        text.parse::<NamedWeave>().unwrap().draft()
    }

    #[test]
    fn named_drawdowns() {
        assert_eq!(weave("plain").drawdown(), "#.\n.#\n");
        assert_eq!(weave("basket:2").drawdown(), "##..\n##..\n..##\n..##\n");
        // Each pick moves the floats one end to the right (Z, pick 1 printed first so the
        // diagonal descends to the right here and rises when pick 1 is drawn at the bottom).
        assert_eq!(weave("twill:2/1").drawdown(), "##.\n.##\n#.#\n");
        assert_eq!(weave("twill:2/1:s").drawdown(), "##.\n#.#\n.##\n");
        assert_eq!(
            weave("satin:5").drawdown(),
            ".####\n##.##\n####.\n#.###\n###.#\n"
        );
        assert_eq!(weave("sateen:5/3").face_fraction(Family::Warp), 0.2);
    }

    #[test]
    fn floats_and_face() {
        let satin = weave("satin:8");
        assert_eq!(satin.floats(Family::Warp), vec![(7, 8)]);
        assert_eq!(satin.floats(Family::Weft), vec![(1, 8)]);
        assert_eq!(satin.face_fraction(Family::Warp), 7.0 / 8.0);
        let twill = weave("twill:3/1");
        assert_eq!(twill.floats(Family::Warp), vec![(3, 4)]);
        assert_eq!(twill.floats(Family::Weft), vec![(1, 4)]);
        assert_eq!(weave("basket:3").floats(Family::Weft), vec![(3, 6)]);
    }

    #[test]
    fn mirror_transpose_back() {
        // A Z twill's floats move one end to the right per pick; the mirror of an S twill's
        // do too.
        let z_diagonal = |d: &Draft| {
            let (e, p) = (d.ends(), d.picks());
            (0..e).all(|i| (0..p).all(|j| d.warp_up(i, j) == d.warp_up((i + 1) % e, (j + 1) % p)))
        };
        assert!(z_diagonal(&weave("twill:2/2:z")));
        assert!(!z_diagonal(&weave("twill:2/2:s")));
        assert!(z_diagonal(&weave("twill:2/2:s").mirrored()));
        let twill = weave("twill:3/1");
        assert_eq!(twill.transposed().transposed(), twill);
        assert_eq!(twill.back().face_fraction(Family::Warp), 0.25);
        assert_eq!(
            twill.transposed().floats(Family::Weft),
            twill.floats(Family::Warp)
        );
    }

    #[test]
    fn bad_names_say_why() {
        for (text, needle) in [
            ("twill", "needs a parameter"),
            ("twill:1/1", "plain"),
            ("twill:2/1:x", "'s' or 'z'"),
            ("satin:6", "no regular satin"),
            ("satin:5/5", "coprime"),
            ("basket:0", "within"),
            ("basket:99999999999999999999999", "whole number"),
            ("houndstooth", "unknown weave"),
        ] {
            let error = text.parse::<NamedWeave>().unwrap_err().0;
            assert!(error.contains(needle), "{text}: {error}");
        }
        for name in [
            "plain",
            "basket:2",
            "twill:2/1:s",
            "satin:8/3",
            "sateen:5/2",
        ] {
            let weave: NamedWeave = name.parse().unwrap();
            assert_eq!(weave.to_string().parse::<NamedWeave>().unwrap(), weave);
        }
    }
}
