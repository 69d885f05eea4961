//! WIF reading: fixtures in the styles of several weaving programs against drawdowns derived
//! by hand, the quirks of real files, and damaged files that load or say where.

use super::ini::split_lines;
use super::*;
use crate::weave::NamedWeave;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;

const FIXTURES: [&str; 8] = [
    "twill_fiberworks_crlf.wif",
    "twill_liftplan_sinking.wif",
    "multi_treadle_multi_shaft.wif",
    "palette_65535.wif",
    "satin_private_cr_latin1.wif",
    "zero_unused.wif",
    "tieup_past_treadles.wif",
    "colour_table_sparse.wif",
];

fn fixture_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/wif")
        .join(name)
}

fn fixture_text(name: &str) -> String {
    let bytes = std::fs::read(fixture_path(name)).unwrap();
    String::from_utf8_lossy(&bytes).into_owned()
}

fn load(name: &str) -> Draft {
    load_wif(&fixture_path(name)).unwrap_or_else(|e| panic!("{e}"))
}

fn error(text: &str) -> String {
    parse_wif(text, "test.wif").unwrap_err().to_string()
}

const TWILL_2_2: &str = "##..##..\n.##..##.\n..##..##\n#..##..#\n";

#[test]
fn treadled_twill_with_crlf() {
    let text = std::fs::read(fixture_path(FIXTURES[0])).unwrap();
    assert!(text.windows(2).any(|w| w == b"\r\n"));
    let draft = load(FIXTURES[0]);
    assert_eq!(draft.drawdown(), TWILL_2_2);
    // The 2/2 twill of the named weaves, repeated twice along the warp.
    let twill: NamedWeave = "twill:2/2".parse().unwrap();
    let twill = twill.draft();
    for end in 0..8 {
        for pick in 0..4 {
            assert_eq!(draft.warp_up(end, pick), twill.warp_up(end % 4, pick));
        }
    }
    // One colour for each family from [WARP] and [WEFT] Color.
    assert_eq!(draft.warp.colours, vec![Some([1.0, 1.0, 1.0]); 8]);
    assert_eq!(draft.weft.colours, vec![Some([0.0, 0.0, 0.0]); 4]);
    assert_eq!(draft.warp.spacing, Some(0.1));
    assert_eq!(draft.weft.thickness, Some(0.08));
}

#[test]
fn sinking_lift_plan_equals_the_treadled_file() {
    let draft = load(FIXTURES[1]);
    assert_eq!(draft.drawdown(), TWILL_2_2);
    assert_eq!(draft.drawdown(), load(FIXTURES[0]).drawdown());
    assert_eq!(draft.warp.colours, vec![None; 8]);
    assert_eq!(draft.warp.spacing, None);
    // The same file with a rising shed weaves the complement.
    let text = fixture_text(FIXTURES[1]);
    assert!(text.contains("Rising Shed=no"));
    let rising = parse_wif(&text.replace("Rising Shed=no", "Rising Shed=yes"), "r.wif");
    let complement: String = TWILL_2_2
        .chars()
        .map(|c| match c {
            '#' => '.',
            '.' => '#',
            c => c,
        })
        .collect();
    assert_eq!(rising.unwrap().drawdown(), complement);
}

#[test]
fn several_treadles_per_pick_and_shafts_per_end() {
    let draft = load(FIXTURES[2]);
    // Ends 5 and 6 rise with either of their shafts (1 or 3, 2 or 4); end 7 is not
    // threaded and pick 5 has no treadle, so neither ever shows warp.
    assert_eq!(
        draft.drawdown(),
        "##..##.\n.##.##.\n..####.\n#..###.\n.......\n"
    );
    assert_eq!(draft.warp.colours, vec![None; 7]);
    assert_eq!(draft.weft.colours, vec![None; 5]);
}

#[test]
fn palette_range_and_per_thread_yarns() {
    let draft = load(FIXTURES[3]);
    assert_eq!(draft.drawdown(), "#.#.\n.#.#\n#.#.\n.#.#\n");
    let red = Some([1.0, 0.0, 0.0]);
    let blue = Some([0.0, 0.2, 1.0]);
    let white = Some([1.0, 1.0, 1.0]);
    assert_eq!(draft.warp.colours, vec![red, blue, red, white]);
    assert_eq!(draft.weft.colours, vec![blue, None, None, None]);
    // One end listed at 0.5, the three others at the default 0.25.
    assert_eq!(draft.warp.spacing, Some(0.3125));
    assert_eq!(draft.warp.thickness, Some(0.2));
    // No default: the mean of the threads listed.
    assert_eq!(draft.weft.spacing, None);
    assert_eq!(draft.weft.thickness, Some(0.3));
}

#[test]
fn private_sections_comments_cr_bom_and_latin1() {
    let bytes = std::fs::read(fixture_path(FIXTURES[4])).unwrap();
    assert!(bytes.starts_with(b"\xef\xbb\xbf"));
    assert!(!bytes.contains(&b'\n'));
    assert!(std::str::from_utf8(&bytes).is_err());
    let draft = load(FIXTURES[4]);
    let satin: NamedWeave = "satin:5".parse().unwrap();
    assert_eq!(draft.drawdown(), ".####\n##.##\n####.\n#.###\n###.#\n");
    assert_eq!(draft.drawdown(), satin.draft().drawdown());
    // Default range 0..255.
    assert_eq!(draft.warp.colours, vec![Some([1.0, 0.2, 0.0]); 5]);
    assert_eq!(draft.weft.colours, vec![None; 5]);
}

#[test]
fn zero_is_an_unused_shaft_or_treadle() {
    let draft = load(FIXTURES[5]);
    // End 4 (threaded on 0) never rises; end 5 (0,2) rises with shaft 2; treadle 3 (tied
    // to 0) and pick 4 (treadle 0) lift nothing.
    assert_eq!(draft.drawdown(), "#.....\n.#..#.\n......\n......\n##..#.\n");
    // A 0 in a lift plan lifts nothing either, and the sinking shed still sinks the rest.
    let lifted = format!("{PLAIN}[LIFTPLAN]\n1=0\n2=2,0\n");
    assert_eq!(parse_wif(&lifted, "p.wif").unwrap().drawdown(), "..\n.#\n");
    let sinking = lifted.replace("Treadles=2\n", "Treadles=2\nRising Shed=no\n");
    assert_eq!(parse_wif(&sinking, "p.wif").unwrap().drawdown(), "##\n#.\n");
    // Numbers past the count are still refused, and say that 0 is allowed.
    let past = PLAIN.replacen("[THREADING]\n1=1", "[THREADING]\n1=0,3", 1);
    assert!(
        error(&past).contains(
            "[THREADING] 1 (line 9): shaft '3' is not a number from 1 to 2 (or 0, unused)"
        )
    );
}

#[test]
fn the_tieup_may_tie_treadles_past_the_count() {
    let draft = load(FIXTURES[6]);
    assert_eq!(draft.drawdown(), "..#..#\n.#..#.\n#..#..\n");
    // Treadles 4 and 5 are tied but not counted; pressing one is still refused.
    let pressed = fixture_text(FIXTURES[6]).replace("[TREADLING]\n1=3", "[TREADLING]\n1=5");
    let message = parse_wif(&pressed, "t.wif").unwrap_err().to_string();
    assert!(message.contains("[TREADLING] 1 (line "), "{message}");
    assert!(
        message.contains("treadle '5' is not a number from 1 to 3"),
        "{message}"
    );
    // The tie-up's shafts are still held to Shafts.
    let shaft = fixture_text(FIXTURES[6]).replace("5=2,3", "5=2,4");
    assert!(
        parse_wif(&shaft, "t.wif")
            .unwrap_err()
            .to_string()
            .contains("shaft '4'")
    );
}

#[test]
fn colour_numbers_may_skip_past_the_entries() {
    let draft = load(FIXTURES[7]);
    assert_eq!(draft.drawdown(), "#.#.\n.#.#\n");
    let blue = Some([0.0, 0.2, 1.0]);
    let white = Some([1.0, 1.0, 1.0]);
    assert_eq!(draft.warp.colours, vec![blue, white, blue, blue]);
    assert_eq!(draft.weft.colours, vec![Some([0.0, 0.0, 0.0]); 2]);
    // A colour the table lacks is still refused, and so is an Entries that is no number.
    let missing = fixture_text(FIXTURES[7]).replace("Color=7", "Color=5");
    let message = parse_wif(&missing, "c.wif").unwrap_err().to_string();
    assert!(message.contains("[WARP] Color (line "), "{message}");
    assert!(
        message.contains("colour 5 is not in the [COLOR TABLE]"),
        "{message}"
    );
    let entries = fixture_text(FIXTURES[7]).replace("Entries=3", "Entries=three");
    assert!(
        parse_wif(&entries, "c.wif")
            .unwrap_err()
            .to_string()
            .contains("[COLOR PALETTE] Entries")
    );
}

/// A small treadled plain weave, for the error tests to damage one line of.
const PLAIN: &str = "[WEAVING]\nShafts=2\nTreadles=2\n[WARP]\nThreads=2\n[WEFT]\nThreads=2\n\
    [THREADING]\n1=1\n2=2\n[TIEUP]\n1=1\n2=2\n[TREADLING]\n1=1\n2=2\n";

#[test]
fn the_lift_plan_rules_over_the_treadling() {
    assert_eq!(parse_wif(PLAIN, "p.wif").unwrap().drawdown(), "#.\n.#\n");
    let lifted = format!("{PLAIN}[LIFTPLAN]\n1=1,2\n");
    assert_eq!(parse_wif(&lifted, "p.wif").unwrap().drawdown(), "##\n..\n");
    // An empty lift plan beside a treadling is ignored.
    let empty = format!("{PLAIN}[LIFTPLAN]\n");
    assert_eq!(parse_wif(&empty, "p.wif").unwrap().drawdown(), "#.\n.#\n");
}

#[test]
fn errors_name_the_file_and_the_place() {
    for (from, to, needle) in [
        (
            "2=2\n[TIEUP]",
            "2=2\n2=1\n[TIEUP]",
            "[THREADING] 2 (line 11): the key is given twice (first on line 10)",
        ),
        (
            "2=2\n[TIEUP]",
            "2=2\n02=2\n[TIEUP]",
            "[THREADING] 02 (line 11): end 2 is given twice (first on line 10)",
        ),
        (
            "[THREADING]\n1=1",
            "[THREADING]\n1=3",
            "[THREADING] 1 (line 9): shaft '3' is not a number from 1 to 2",
        ),
        ("[THREADING]\n1=1", "[THREADING]\n1=-1", "shaft '-1'"),
        (
            "[THREADING]\n1=1",
            "[THREADING]\n3=1",
            "[THREADING] 3 (line 9): 3 is beyond the 2 of [WARP] Threads",
        ),
        (
            "[THREADING]\n1=1",
            "[THREADING]\n0=1",
            "[THREADING] 0 (line 9): end numbers run from 1 to 16384",
        ),
        (
            "[TREADLING]\n1=1",
            "[TREADLING]\n1=7",
            "[TREADLING] 1 (line 15): treadle '7'",
        ),
        (
            "[WARP]\nThreads=2",
            "[WARP]\nThreads=99999999999999999999",
            "[WARP] Threads (line 5)",
        ),
        (
            "[WARP]\nThreads=2\n[WEFT]\nThreads=2",
            "[WARP]\nThreads=16384\n[WEFT]\nThreads=16384",
            "16384 ends ([WARP] Threads or [THREADING]) × 16384 picks ([WEFT] Threads or \
             [TREADLING]) is more than 16777216 crossings",
        ),
        (
            "[WARP]\nThreads=2",
            "[WARP]\nThreads=16385",
            "[WARP] Threads (line 5): 16385 is not within 1..=16384",
        ),
        (
            "[WARP]\nThreads=2",
            "[WARP]\nThreads=2\nSpacing=-1",
            "[WARP] Spacing (line 6): -1 is not a positive length",
        ),
        (
            "[WARP]\nThreads=2",
            "[WARP]\nThreads=2\nColor=4",
            "[WARP] Color (line 6): colour 4 is not in the [COLOR TABLE]",
        ),
        (
            "[WARP]\nThreads=2",
            "[WARP]\nThreads=2\nColor=1,2,300",
            "outside the palette's range 0,255",
        ),
        (
            "Treadles=2\n",
            "Treadles=2\nRising Shed=maybe\n",
            "[WEAVING] Rising Shed (line 4)",
        ),
        (
            "[WEAVING]\n",
            "Shafts=2\n[WEAVING]\n",
            "line 1: 'Shafts=2' comes before the first [SECTION]",
        ),
        (
            "[WEAVING]\n",
            "[WEAVING\n",
            "line 1: '[WEAVING' is not a section header",
        ),
        (
            "Treadles=2\n",
            "Treadles 2\n",
            "line 3: 'Treadles 2' in [WEAVING] is not a key=value line",
        ),
        ("[TIEUP]\n", "[TIE]\n", "a [TREADLING] but no [TIEUP]"),
        (
            "[THREADING]\n",
            "[THREAD]\n",
            "there is no [THREADING] section",
        ),
    ] {
        assert!(PLAIN.contains(from), "{from}");
        let damaged = PLAIN.replacen(from, to, 1);
        let Err(e) = parse_wif(&damaged, "test.wif") else {
            panic!("{damaged} loads");
        };
        let message = e.to_string();
        assert!(message.starts_with("WIF file test.wif"), "{message}");
        assert!(message.contains(needle), "{needle}\n{message}");
    }
    let bare = "[WEAVING]\nShafts=2\n[THREADING]\n1=1\n";
    assert!(error(bare).contains("it has neither"));
    let range = "[COLOR PALETTE]\nRange=255,0\n";
    assert!(error(range).contains("[COLOR PALETTE] Range (line 2): the range 255,0 is empty"));
}

#[test]
fn load_checks_the_size_first() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("huge.wif");
    let file = std::fs::File::create(&path).unwrap();
    file.set_len(MAX_WIF_BYTES + 1).unwrap();
    let message = load_wif(&path).unwrap_err().to_string();
    assert!(
        message.contains("huge.wif") && message.contains("limit"),
        "{message}"
    );
    let missing = load_wif(&dir.path().join("missing.wif")).unwrap_err();
    assert!(matches!(missing, WifError::Io { .. }));
    assert!(missing.to_string().contains("missing.wif"));
}

/// Numbers a damaged file may hold.
const BAD_NUMBERS: [&str; 12] = [
    "99999999999999999999",
    "18446744073709551616",
    "4294967296",
    "16385",
    "4096",
    "-1",
    "0",
    "abc",
    "1e308",
    "NaN",
    "",
    ",,,",
];

/// `original` with one to three random kinds of damage.
fn damage(original: &[u8], rng: &mut Pcg64) -> Vec<u8> {
    let text = String::from_utf8_lossy(original);
    let ending = if text.contains("\r\n") {
        "\r\n"
    } else if text.contains('\r') {
        "\r"
    } else {
        "\n"
    };
    let mut lines: Vec<String> = split_lines(&text).into_iter().map(String::from).collect();
    let mut bytes = None;
    for _ in 0..rng.random_range(1..=3) {
        let n = lines.len().max(1);
        let at = rng.random_range(0..n).min(lines.len().saturating_sub(1));
        match rng.random_range(0..8) {
            0 if !lines.is_empty() => {
                lines.remove(at);
            }
            1 if !lines.is_empty() => {
                let copy = lines[at].clone();
                let to = rng.random_range(0..=lines.len());
                lines.insert(to, copy);
            }
            2 if !lines.is_empty() => {
                let other = rng.random_range(0..lines.len());
                lines.swap(at, other);
            }
            3 | 4 => {
                // Byte damage ends the line edits: truncate or flip bytes.
                let mut b = lines.join(ending).into_bytes();
                if b.is_empty() {
                    continue;
                }
                if rng.random_range(0..2) == 0 {
                    b.truncate(rng.random_range(0..b.len()));
                } else {
                    for _ in 0..rng.random_range(1..=4) {
                        let i = rng.random_range(0..b.len());
                        b[i] ^= rng.random_range(1..=255u8);
                    }
                }
                bytes = Some(b);
                break;
            }
            5 | 6 => {
                // Replace the value of a key=value line.
                let keyed: Vec<usize> = (0..lines.len())
                    .filter(|&i| lines[i].contains('=') && !lines[i].starts_with(';'))
                    .collect();
                if keyed.is_empty() {
                    continue;
                }
                let i = keyed[rng.random_range(0..keyed.len())];
                let key = lines[i].split('=').next().unwrap_or_default().to_string();
                let bad = BAD_NUMBERS[rng.random_range(0..BAD_NUMBERS.len())];
                lines[i] = if rng.random_range(0..2) == 0 {
                    format!("{key}={bad}")
                } else {
                    format!("{bad}={}", lines[i].split_once('=').map_or("", |kv| kv.1))
                };
            }
            _ => {
                // Drop a section header.
                let headers: Vec<usize> = (0..lines.len())
                    .filter(|&i| lines[i].trim_start().starts_with('['))
                    .collect();
                if !headers.is_empty() {
                    lines.remove(headers[rng.random_range(0..headers.len())]);
                }
            }
        }
    }
    bytes.unwrap_or_else(|| lines.join(ending).into_bytes())
}

#[test]
fn damaged_drafts_load_or_say_where() {
    let originals: Vec<Vec<u8>> = FIXTURES
        .iter()
        .map(|name| std::fs::read(fixture_path(name)).unwrap())
        .collect();
    let mut rng = Pcg64::seed_from_u64(0x0057_4946);
    let (mut loaded, mut rejected, mut panics) = (0, 0, Vec::new());
    for i in 0..1000 {
        let text = String::from_utf8_lossy(&damage(&originals[i % originals.len()], &mut rng))
            .into_owned();
        let origin = format!("damaged-{i}.wif");
        match std::panic::catch_unwind(|| parse_wif(&text, &origin)) {
            Err(_) => panics.push(i),
            Ok(Ok(_)) => loaded += 1,
            Ok(Err(e)) => {
                rejected += 1;
                let message = e.to_string();
                let located = match &e {
                    WifError::Line { line, .. } => *line > 0,
                    WifError::Value { section, key, .. } => {
                        message.contains(&format!("[{section}] {key} (line "))
                    }
                    WifError::Draft { message, .. } => message.contains('['),
                    _ => false,
                };
                assert!(
                    message.contains(&origin) && located,
                    "variant {i}: {message}\n{text}"
                );
            }
        }
    }
    assert!(panics.is_empty(), "variants that panicked: {panics:?}");
    // Both outcomes are exercised.
    assert!(
        loaded >= 100 && rejected >= 100,
        "{loaded} loaded, {rejected} rejected"
    );
}
