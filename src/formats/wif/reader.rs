//! The draft a WIF file's sections describe: threading, tie-up and treadling or lift plan,
//! the shed, and per family the colours, spacing and thickness; every number checked before
//! it sizes anything.

use super::ini::{Entry, Ini, Section};
use super::{MAX_PALETTE_ENTRIES, WifError};
use crate::weave::draft::{MAX_CELLS, MAX_THREADS};
use crate::weave::{Draft, Yarns};
use std::collections::BTreeMap;

/// The warp or the weft, as the reader names their sections.
#[derive(Clone, Copy)]
enum Side {
    Warp,
    Weft,
}

impl Side {
    fn name(self) -> &'static str {
        match self {
            Side::Warp => "WARP",
            Side::Weft => "WEFT",
        }
    }

    fn thread(self) -> &'static str {
        match self {
            Side::Warp => "end",
            Side::Weft => "pick",
        }
    }
}

/// A colour as a file gives it: a palette index, or components in the palette's range.
#[derive(Clone, Copy)]
enum ColourRef {
    Index(usize),
    Rgb([f64; 3]),
}

/// The `[WARP]` or `[WEFT]` section.
struct FamilyHeader {
    threads: Option<usize>,
    colour: Option<(ColourRef, usize)>,
    spacing: Option<f64>,
    thickness: Option<f64>,
}

/// A numbered section's entries, by number: the parsed value and its entry.
type Numbered<'a, T> = BTreeMap<usize, (T, &'a Entry)>;

pub(super) struct Reader<'a> {
    pub(super) ini: &'a Ini,
    pub(super) origin: &'a str,
}

impl<'a> Reader<'a> {
    fn value_error(&self, section: &str, entry: &Entry, message: String) -> WifError {
        WifError::Value {
            origin: self.origin.to_string(),
            section: section.to_string(),
            key: entry.key.clone(),
            line: entry.line,
            message,
        }
    }

    fn draft_error(&self, message: String) -> WifError {
        WifError::Draft {
            origin: self.origin.to_string(),
            message,
        }
    }

    fn section(&self, name: &str) -> Option<&'a Section> {
        self.ini.sections.get(name)
    }

    fn entry(&self, section: &str, key: &str) -> Option<&'a Entry> {
        let section = self.section(section)?;
        section.index.get(key).map(|&i| &section.entries[i])
    }

    /// A whole number within `least..=most`.
    fn count(
        &self,
        section: &str,
        entry: &Entry,
        text: &str,
        least: usize,
        most: usize,
    ) -> Result<usize, WifError> {
        let n = text.trim().parse::<u64>().map_err(|_| {
            self.value_error(
                section,
                entry,
                format!("'{text}' is not a whole number from {least} to {most}"),
            )
        })?;
        match usize::try_from(n) {
            Ok(n) if (least..=most).contains(&n) => Ok(n),
            _ => Err(self.value_error(
                section,
                entry,
                format!("{n} is not within {least}..={most}"),
            )),
        }
    }

    /// A finite number.
    fn number(&self, section: &str, entry: &Entry, text: &str) -> Result<f64, WifError> {
        match text.trim().parse::<f64>() {
            Ok(x) if x.is_finite() => Ok(x),
            _ => Err(self.value_error(
                section,
                entry,
                format!("'{}' is not a finite number", text.trim()),
            )),
        }
    }

    /// A length (spacing or thickness): finite and positive.
    fn length(&self, section: &str, entry: &Entry) -> Result<f64, WifError> {
        let x = self.number(section, entry, &entry.value)?;
        if x > 0.0 {
            Ok(x)
        } else {
            Err(self.value_error(section, entry, format!("{x} is not a positive length")))
        }
    }

    /// A comma-separated list of whole numbers within `1..=most` (empty items skipped: some
    /// programs end a list with a comma). A 0 is skipped too: WIF 1.1 gives every shaft and
    /// treadle the initial value 0, "unused", and programs write it (`3=0,2` for a pick on
    /// treadle 2 alone, or `4=0` for an end threaded on no shaft).
    fn list(
        &self,
        section: &str,
        entry: &Entry,
        most: usize,
        what: &str,
    ) -> Result<Vec<usize>, WifError> {
        let mut items = Vec::new();
        for item in entry.value.split(',').map(str::trim) {
            if item.is_empty() {
                continue;
            }
            let n = item
                .parse::<u64>()
                .ok()
                .and_then(|n| usize::try_from(n).ok());
            match n {
                Some(0) => {}
                Some(n) if (1..=most).contains(&n) => items.push(n),
                _ => {
                    return Err(self.value_error(
                        section,
                        entry,
                        format!("{what} '{item}' is not a number from 1 to {most} (or 0, unused)"),
                    ));
                }
            }
        }
        items.sort_unstable();
        items.dedup();
        Ok(items)
    }

    /// The entries of a numbered section (`N=value`, N from 1 to `most`), each value parsed.
    fn numbered<T>(
        &self,
        name: &str,
        what: &str,
        most: usize,
        mut parse: impl FnMut(&Entry) -> Result<T, WifError>,
    ) -> Result<Numbered<'a, T>, WifError> {
        let mut out = BTreeMap::new();
        let Some(section) = self.section(name) else {
            return Ok(out);
        };
        for entry in &section.entries {
            let n = self.count(name, entry, &entry.key, 1, most).map_err(|_| {
                self.value_error(
                    name,
                    entry,
                    format!("{what} numbers run from 1 to {most}; the key is not one"),
                )
            })?;
            let value = parse(entry)?;
            // The string keys are unique, but "01" and "1" are the same number.
            if let Some((_, first)) = out.insert(n, (value, entry)) {
                return Err(self.value_error(
                    name,
                    entry,
                    format!("{what} {n} is given twice (first on line {})", first.line),
                ));
            }
        }
        Ok(out)
    }

    /// Checks that every number of a numbered section is at most `count`.
    fn within<T>(
        &self,
        name: &str,
        map: &Numbered<'_, T>,
        count: usize,
        counted_by: &str,
    ) -> Result<(), WifError> {
        match map.last_key_value() {
            Some((&n, (_, entry))) if n > count => Err(self.value_error(
                name,
                entry,
                format!("{n} is beyond the {count} of {counted_by}"),
            )),
            _ => Ok(()),
        }
    }

    fn boolean(&self, section: &str, entry: &Entry) -> Result<bool, WifError> {
        match entry.value.to_ascii_lowercase().as_str() {
            "yes" | "true" | "1" | "on" => Ok(true),
            "no" | "false" | "0" | "off" => Ok(false),
            other => Err(self.value_error(
                section,
                entry,
                format!("'{other}' is not yes/no, true/false, 1/0 or on/off"),
            )),
        }
    }

    /// A colour: a palette index, or `r,g,b` in the palette's range.
    fn colour_ref(
        &self,
        section: &str,
        entry: &Entry,
        range: (f64, f64),
    ) -> Result<ColourRef, WifError> {
        if entry.value.contains(',') {
            self.rgb(section, entry, range).map(ColourRef::Rgb)
        } else {
            self.count(section, entry, &entry.value, 1, MAX_PALETTE_ENTRIES)
                .map(ColourRef::Index)
        }
    }

    /// `r,g,b` within `range`, as sRGB components in [0, 1].
    fn rgb(&self, section: &str, entry: &Entry, range: (f64, f64)) -> Result<[f64; 3], WifError> {
        let parts: Vec<&str> = entry.value.split(',').collect();
        if parts.len() != 3 {
            return Err(self.value_error(
                section,
                entry,
                format!("'{}' is not a colour r,g,b", entry.value),
            ));
        }
        let (min, max) = range;
        let mut rgb = [0.0; 3];
        for (out, part) in rgb.iter_mut().zip(parts) {
            let v = self.number(section, entry, part)?;
            if !(min..=max).contains(&v) {
                return Err(self.value_error(
                    section,
                    entry,
                    format!(
                        "{v} is outside the palette's range {min},{max} ([COLOR PALETTE] Range)"
                    ),
                ));
            }
            *out = (v - min) / (max - min);
        }
        Ok(rgb)
    }

    fn family_header(&self, side: Side, range: (f64, f64)) -> Result<FamilyHeader, WifError> {
        let name = side.name();
        let threads = match self.entry(name, "threads") {
            Some(e) => Some(self.count(name, e, &e.value, 1, MAX_THREADS)?),
            None => None,
        };
        let colour = match self.entry(name, "color") {
            Some(e) => Some((self.colour_ref(name, e, range)?, e.line)),
            None => None,
        };
        let spacing = match self.entry(name, "spacing") {
            Some(e) => Some(self.length(name, e)?),
            None => None,
        };
        let thickness = match self.entry(name, "thickness") {
            Some(e) => Some(self.length(name, e)?),
            None => None,
        };
        Ok(FamilyHeader {
            threads,
            colour,
            spacing,
            thickness,
        })
    }

    /// The palette's range, `[COLOR PALETTE] Range=min,max`, 0..255 if not given.
    fn palette_range(&self) -> Result<(f64, f64), WifError> {
        const NAME: &str = "COLOR PALETTE";
        let Some(entry) = self.entry(NAME, "range") else {
            return Ok((0.0, 255.0));
        };
        let Some((min, max)) = entry.value.split_once(',') else {
            return Err(self.value_error(
                NAME,
                entry,
                format!("'{}' is not a range min,max", entry.value),
            ));
        };
        let (min, max) = (
            self.number(NAME, entry, min)?,
            self.number(NAME, entry, max)?,
        );
        if max <= min || !(max - min).is_finite() {
            return Err(self.value_error(NAME, entry, format!("the range {min},{max} is empty")));
        }
        Ok((min, max))
    }

    /// The colour table, by index. `[COLOR PALETTE] Entries` is checked as a number but does
    /// not bound the indices: programs write it as the count of the table's lines, whose
    /// numbers may skip (colours 1, 2 and 7 are `Entries=3`), so a colour is refused only
    /// when a thread names one the table lacks.
    fn colour_table(&self, range: (f64, f64)) -> Result<Numbered<'a, [f64; 3]>, WifError> {
        const NAME: &str = "COLOR PALETTE";
        if let Some(e) = self.entry(NAME, "entries") {
            self.count(NAME, e, &e.value, 0, MAX_PALETTE_ENTRIES)?;
        }
        self.numbered("COLOR TABLE", "colour", MAX_PALETTE_ENTRIES, |e| {
            self.rgb("COLOR TABLE", e, range)
        })
    }

    /// The yarns of one family: colours, mean spacing and mean thickness.
    fn yarns(
        &self,
        side: Side,
        header: &FamilyHeader,
        count: usize,
        range: (f64, f64),
        table: &Numbered<'a, [f64; 3]>,
    ) -> Result<Yarns, WifError> {
        let family = side.name();
        let counted_by = format!("[{family}] Threads or the draft's {}s", side.thread());
        let resolve = |colour: ColourRef, section: &str, key: &str, line: usize| match colour {
            ColourRef::Rgb(rgb) => Ok(rgb),
            ColourRef::Index(i) => match table.get(&i) {
                Some((rgb, _)) => Ok(*rgb),
                None => Err(WifError::Value {
                    origin: self.origin.to_string(),
                    section: section.to_string(),
                    key: key.to_string(),
                    line,
                    message: format!("colour {i} is not in the [COLOR TABLE]"),
                }),
            },
        };
        let default = match header.colour {
            Some((colour, line)) => Some(resolve(colour, family, "Color", line)?),
            None => None,
        };
        let colours_name = format!("{family} COLORS");
        let colours = self.numbered(&colours_name, "thread", MAX_THREADS, |e| {
            self.colour_ref(&colours_name, e, range)
        })?;
        self.within(&colours_name, &colours, count, &counted_by)?;
        let mut per_thread = vec![default; count];
        for (&n, &(colour, entry)) in &colours {
            per_thread[n - 1] = Some(resolve(colour, &colours_name, &entry.key, entry.line)?);
        }

        let mean = |what: &str, default: Option<f64>| -> Result<Option<f64>, WifError> {
            let name = format!("{family} {what}");
            let values = self.numbered(&name, "thread", MAX_THREADS, |e| self.length(&name, e))?;
            self.within(&name, &values, count, &counted_by)?;
            let listed: f64 = values.values().map(|(x, _)| x).sum();
            Ok(match default {
                Some(d) => Some((listed + d * (count - values.len()) as f64) / count as f64),
                None if values.is_empty() => None,
                None => Some(listed / values.len() as f64),
            })
        };
        Ok(Yarns {
            colours: per_thread,
            spacing: mean("SPACING", header.spacing)?,
            thickness: mean("THICKNESS", header.thickness)?,
        })
    }

    pub(super) fn draft(&self) -> Result<Draft, WifError> {
        const WEAVING: &str = "WEAVING";
        let limit = |key: &str| -> Result<Option<usize>, WifError> {
            match self.entry(WEAVING, key) {
                Some(e) => Ok(Some(self.count(WEAVING, e, &e.value, 0, MAX_THREADS)?)),
                None => Ok(None),
            }
        };
        let shafts = limit("shafts")?;
        let treadles = limit("treadles")?;
        let rising = match self.entry(WEAVING, "rising shed") {
            Some(e) => self.boolean(WEAVING, e)?,
            None => true,
        };
        let shaft_most = shafts.unwrap_or(MAX_THREADS);
        let treadle_most = treadles.unwrap_or(MAX_THREADS);

        let range = self.palette_range()?;
        let table = self.colour_table(range)?;
        let warp = self.family_header(Side::Warp, range)?;
        let weft = self.family_header(Side::Weft, range)?;

        let threading = self.numbered("THREADING", "end", MAX_THREADS, |e| {
            self.list("THREADING", e, shaft_most, "shaft")
        })?;
        // The tie-up may hold treadles past `Treadles` (Fiberworks PCW counts the treadles the
        // treadling presses and still writes the tie-up of the tabby treadles past them); the
        // treadling is what is held to `Treadles`.
        let tieup = self.numbered("TIEUP", "treadle", MAX_THREADS, |e| {
            self.list("TIEUP", e, shaft_most, "shaft")
        })?;
        let treadling = self.numbered("TREADLING", "pick", MAX_THREADS, |e| {
            self.list("TREADLING", e, treadle_most, "treadle")
        })?;
        let liftplan = self.numbered("LIFTPLAN", "pick", MAX_THREADS, |e| {
            self.list("LIFTPLAN", e, shaft_most, "shaft")
        })?;

        let has = |name: &str| self.section(name).is_some();
        if !has("THREADING") {
            return Err(self.draft_error(
                "there is no [THREADING] section: the draft says on which shafts the ends lie"
                    .to_string(),
            ));
        }
        // The lift plan rules where there is one, unless it is an empty section written
        // beside a treadling and tie-up.
        let treadled = has("TREADLING") && has("TIEUP");
        let use_liftplan = has("LIFTPLAN") && (!liftplan.is_empty() || !treadled);
        if !use_liftplan && !treadled {
            let missing = match (has("TREADLING"), has("TIEUP")) {
                (true, false) => "a [TREADLING] but no [TIEUP]",
                (false, true) => "a [TIEUP] but no [TREADLING]",
                _ => "neither",
            };
            return Err(self.draft_error(format!(
                "the draft needs a [LIFTPLAN], or a [TREADLING] and a [TIEUP], to say which \
                 shafts rise on each pick; it has {missing}"
            )));
        }
        let (pick_section, picks_listed) = if use_liftplan {
            ("LIFTPLAN", liftplan.last_key_value().map(|(&n, _)| n))
        } else {
            ("TREADLING", treadling.last_key_value().map(|(&n, _)| n))
        };

        let ends = match warp.threads {
            Some(n) => n,
            None => threading.last_key_value().map_or(0, |(&n, _)| n),
        };
        let picks = match weft.threads {
            Some(n) => n,
            None => picks_listed.unwrap_or(0),
        };
        if ends == 0 {
            return Err(self.draft_error(
                "no ends: [WARP] Threads is not given and [THREADING] is empty".to_string(),
            ));
        }
        if picks == 0 {
            return Err(self.draft_error(format!(
                "no picks: [WEFT] Threads is not given and [{pick_section}] is empty"
            )));
        }
        let ends_by = "[WARP] Threads";
        let picks_by = "[WEFT] Threads";
        self.within("THREADING", &threading, ends, ends_by)?;
        // Only the section that says which shafts rise is read; the other may be longer.
        if use_liftplan {
            self.within("LIFTPLAN", &liftplan, picks, picks_by)?;
        } else {
            self.within("TREADLING", &treadling, picks, picks_by)?;
        }
        if ends * picks > MAX_CELLS {
            return Err(self.draft_error(format!(
                "{ends} ends ([WARP] Threads or [THREADING]) × {picks} picks ([WEFT] Threads or \
                 [{pick_section}]) is more than {MAX_CELLS} crossings"
            )));
        }

        // Every number is checked: now allocate by the counts.
        let mut end_shafts: Vec<&[usize]> = vec![&[]; ends];
        for (&end, (shafts, _)) in &threading {
            end_shafts[end - 1] = shafts;
        }
        let mut pick_shafts: Vec<Vec<usize>> = vec![Vec::new(); picks];
        if use_liftplan {
            for (&pick, (shafts, _)) in &liftplan {
                pick_shafts[pick - 1].clone_from(shafts);
            }
        } else {
            for (&pick, (pedals, _)) in &treadling {
                let lifted = &mut pick_shafts[pick - 1];
                for treadle in pedals {
                    if let Some((shafts, _)) = tieup.get(treadle) {
                        lifted.extend_from_slice(shafts);
                    }
                }
                lifted.sort_unstable();
                lifted.dedup();
            }
        }
        let mut draft = Draft::from_fn(ends, picks, |end, pick| {
            let named = end_shafts[end]
                .iter()
                .any(|s| pick_shafts[pick].binary_search(s).is_ok());
            // Rising: the end rises with any of its shafts. Sinking: the listed shafts sink,
            // and the end stays up only where none of its shafts does.
            named == rising
        })
        .map_err(|e| self.draft_error(e.0))?;
        draft.warp = self.yarns(Side::Warp, &warp, ends, range, &table)?;
        draft.weft = self.yarns(Side::Weft, &weft, picks, range, &table)?;
        Ok(draft)
    }
}
