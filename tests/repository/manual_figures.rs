//! The manual and the notebook apart (tracker issue 47): the manual pages (`README.md`,
//! `docs/*.md`) and the comments of the source (`//` in `src/**/*.rs` and
//! `shaders/**/*.wgsl`) hold no measurement history: no percentages, timings or "×" ratios
//! from a run, no "(measured ...)" and no commit hashes. Measurements live in dated entries of
//! `docs/notebook/` (each with the command that produced it) and in the generated
//! `report/REPORT.md`, which are not scanned. A figure that *defines* something (a target, a
//! tolerance's significance level, a generated map's shape, a format's example) is named in
//! `ALLOWED`, with its reason; an entry that no longer matches anything fails too, so that the
//! list stays as short as what it allows.

use std::path::{Path, PathBuf};

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// Figures that define something rather than record a measurement: (file relative to the
/// repository root, the text on one line that holds the figure, why it is allowed).
const ALLOWED: &[(&str, &str, &str)] = &[
    (
        "docs/tables.md",
        "every built-in fabric within 1% in at most 4 MiB",
        "the default layout's first budget, a goal (src/report/pick.rs holds the same)",
    ),
    (
        "docs/tables.md",
        "within 2% in at most 1 MiB",
        "the default layout's second budget, a goal",
    ),
    (
        "docs/sampling.md",
        "10% of draws come from the cosine density",
        "the sampler's mixture, a constant of its construction",
    ),
    (
        "docs/sampling.md",
        "Šidák-corrected at a 1% significance level overall",
        "the chi-square test's significance level",
    ),
    (
        "docs/testing.md",
        "chi-square at a 1% significance level overall",
        "the chi-square test's significance level",
    ),
    (
        "docs/sampling.md",
        "peak 20× the ambient",
        "the generated studio map's shape, as `src/lighting/generated.rs` builds it",
    ),
    (
        "src/lighting/generated.rs",
        "lobes 20× the ambient",
        "the generated studio map's shape, where it is built",
    ),
    (
        "docs/model.md",
        "within 0.25% relative RMS of the direct",
        "the criterion the default node counts were chosen by, a goal",
    ),
    (
        "docs/fitting.md",
        "moved by a seeded 10% of their ranges",
        "the third start's perturbation, a constant of the method",
    ),
    (
        "docs/fitting.md",
        "`src/fit/cases.rs`). The targets: a round trip within 2% relative RMS, a fit by weave",
        "the round trip's target, a goal",
    ),
    (
        "docs/fitting.md",
        "alone within 3%.",
        "the by-weave target, a goal",
    ),
    (
        "docs/python.md",
        "the satin's own F with 2% noise",
        "the example's synthetic noise, an input",
    ),
    (
        "docs/python.md",
        "# about 2%, the noise",
        "the example's expected output: the held-out error of a fit to 2% noise is that noise",
    ),
    (
        "docs/runtime.md",
        "log scale 0.1%–100%",
        "the error image's colour scale",
    ),
    (
        "src/render/image.rs",
        "floor = 1% of the mean reference radiance",
        "the error image's floor, a definition",
    ),
    (
        "src/render/image.rs",
        "on a log scale from 0.1% (black)",
        "the error image's colour scale",
    ),
    (
        "src/render/image.rs",
        "red to 100% and above (white)",
        "the error image's colour scale",
    ),
    (
        "src/render/image.rs",
        "0.1%, 1%, 10% and 100%.",
        "the error image's colour bar ticks",
    ),
    (
        "src/render/image.rs",
        "// 100%: white",
        "the error image's colour scale",
    ),
    (
        "src/report/format.rs",
        "A ratio as \"12×\" or \"1.25×\"",
        "examples of the report's number format",
    ),
    (
        "src/report/pick.rs",
        "A budget as a percentage, as short as it is exact (\"1%\", \"0.25%\")",
        "examples of the report's number format",
    ),
    (
        "src/report/pick.rs",
        "(\"0.19–0.39%\", \"296–934 KiB\")",
        "examples of the report's number format",
    ),
    (
        "src/report/pick.rs",
        "against the CPU reference render: 1%",
        "the real-time image's budget, a goal",
    ),
    (
        "src/report/pick.rs",
        "Largest error of the smallest table: 2%",
        "the smallest table's budget, a goal",
    ),
    (
        "src/report/pick.rs",
        "project states (1% in 4 MiB, 2% in 1 MiB)",
        "the two table budgets, goals",
    ),
    (
        "src/report/pick.rs",
        "Largest error of the fastest CPU evaluation: 1%",
        "the fastest CPU evaluation's budget, a goal",
    ),
    (
        "src/report/pick.rs",
        "/// 0.25%, the bound",
        "the no-bake budget, a goal",
    ),
    (
        "src/model/curve.rs",
        "within 0.25% relative",
        "the criterion the default node counts were chosen by, a goal",
    ),
    (
        "src/table/fast_math.rs",
        "at most about 1% of a texel",
        "a derivation: the approximation's angle error over a texel's width",
    ),
    (
        "src/table/thread_frame.rs",
        "70% of the",
        "the layout's axis plan, a definition",
    ),
    (
        "src/sampling/taps.rs",
        "(0.04% in the solid angle)",
        "a derivation: the quantisation step 36/65535 as a fraction",
    ),
    (
        "src/viewer/controls.rs",
        "change the distance by 2.9×",
        "a derived constant: the per-notch factor to the tenth power",
    ),
    (
        "src/viewer/mod.rs",
        "with a 10% margin",
        "the camera's framing margin, a definition",
    ),
];

/// One figure found on a line: what kind, and its byte range in the line.
#[derive(Debug, Clone, PartialEq)]
struct Figure {
    kind: &'static str,
    start: usize,
    end: usize,
}

/// Units of time that follow a number in a timing ("12 ms", "3.4 s", "20 minutes").
const TIME_UNITS: &[&str] = &[
    "ns", "µs", "us", "ms", "s", "min", "minutes", "seconds", "hours",
];
/// Words after "N times" that make it a measured ratio ("1.6 times faster").
const RATIO_WORDS: &[&str] = &[
    "faster", "slower", "less", "more", "lower", "higher", "dearer", "cheaper", "as",
];

fn is_word_char(c: char) -> bool {
    c.is_alphanumeric() || c == '_'
}

/// The numbers of a line: byte ranges of runs like `12`, `3.4`, `2,615` that do not continue
/// a word (`f32`, `thread1` and `x86` are names, not figures).
fn numbers(line: &str) -> Vec<(usize, usize)> {
    let chars: Vec<(usize, char)> = line.char_indices().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let (start, c) = chars[i];
        let after_word = i > 0 && (is_word_char(chars[i - 1].1) || chars[i - 1].1 == '.');
        if !c.is_ascii_digit() || after_word {
            i += 1;
            continue;
        }
        let mut j = i;
        while j < chars.len() {
            let c = chars[j].1;
            let separator_then_digit =
                (c == '.' || c == ',') && chars.get(j + 1).is_some_and(|(_, d)| d.is_ascii_digit());
            if c.is_ascii_digit() || separator_then_digit {
                j += 1;
            } else {
                break;
            }
        }
        let end = chars.get(j).map_or(line.len(), |(b, _)| *b);
        out.push((start, end));
        i = j.max(i + 1);
    }
    out
}

/// The word starting at byte `at` (letters, digits, `_`: `s1` is a name, not a unit), and
/// where it ends.
fn word_at(line: &str, at: usize) -> (&str, usize) {
    let rest = &line[at..];
    let len = rest
        .char_indices()
        .find(|(_, c)| !is_word_char(*c))
        .map_or(rest.len(), |(i, _)| i);
    (&rest[..len], at + len)
}

/// Every figure of measurement history on one line of text.
fn figures(line: &str) -> Vec<Figure> {
    let mut found = Vec::new();
    for (start, end) in numbers(line) {
        let rest = &line[end..];
        let gap = rest.len() - rest.trim_start_matches([' ', '\u{2009}', '\u{202f}']).len();
        let after = &rest[gap..];
        if after.starts_with('%') {
            found.push(Figure {
                kind: "percentage",
                start,
                end: end + gap + 1,
            });
            continue;
        }
        if gap == 0 && after.starts_with('×') {
            // "2.4×" is a ratio; "2×2" a size.
            let tail = after['×'.len_utf8()..].trim_start();
            if !tail.starts_with(|c: char| c.is_ascii_digit()) {
                found.push(Figure {
                    kind: "ratio",
                    start,
                    end: end + '×'.len_utf8(),
                });
            }
            continue;
        }
        let (word, word_end) = word_at(line, end + gap);
        // "12 ms", and "12ms" for the units that cannot be anything else.
        let unit = if gap > 0 {
            TIME_UNITS.contains(&word)
        } else {
            ["ns", "µs", "us", "ms"].contains(&word)
        };
        if unit {
            found.push(Figure {
                kind: "timing",
                start,
                end: word_end,
            });
        } else if gap > 0 && word == "times" {
            let rest = line[word_end..].trim_start();
            let (next, _) = word_at(rest, 0);
            if RATIO_WORDS.contains(&next) {
                found.push(Figure {
                    kind: "ratio",
                    start,
                    end: word_end,
                });
            }
        }
    }
    let lower = line.to_ascii_lowercase();
    for phrase in ["(measured", "measured here", "measured on lavapipe"] {
        let overlaps = |at: usize| found.iter().any(|f: &Figure| f.start <= at && at < f.end);
        if let Some(at) = lower.find(phrase).filter(|at| !overlaps(*at)) {
            found.push(Figure {
                kind: "measurement",
                start: at,
                end: at + phrase.len(),
            });
        }
    }
    // "measured 0.3–1.0 points worse": a figure said to be measured.
    for (at, _) in lower.match_indices("measured ") {
        let after = at + "measured ".len();
        if lower[after..].starts_with(|c: char| c.is_ascii_digit()) {
            found.push(Figure {
                kind: "measurement",
                start: at,
                end: after,
            });
        }
    }
    found.extend(commit_hashes(line).into_iter().map(|(start, end)| Figure {
        kind: "commit hash",
        start,
        end,
    }));
    found.sort_by_key(|f| f.start);
    found
}

/// Runs of 7 to 40 lower-case hex digits, standing alone, with at least one digit and one
/// letter (so that neither `1234567` nor a word such as `defaced` counts).
fn commit_hashes(line: &str) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let bytes = line.as_bytes();
    let mut i = 0;
    while i < bytes.len() {
        let standalone_start = i == 0 || !(bytes[i - 1] as char).is_ascii_alphanumeric();
        if !standalone_start || !bytes[i].is_ascii_hexdigit() {
            i += 1;
            continue;
        }
        let mut j = i;
        while j < bytes.len() && matches!(bytes[j], b'0'..=b'9' | b'a'..=b'f') {
            j += 1;
        }
        let standalone_end = j == bytes.len() || !(bytes[j] as char).is_ascii_alphanumeric();
        let run = &line[i..j];
        if standalone_end
            && (7..=40).contains(&run.len())
            && run.bytes().any(|b| b.is_ascii_digit())
            && run.bytes().any(|b| b.is_ascii_alphabetic())
        {
            out.push((i, j));
        }
        i = j.max(i + 1);
    }
    out
}

/// The `//` comment of a line of Rust or WGSL (from the first `//` outside a string
/// literal), with its byte offset; `None` for a line without one.
fn comment(line: &str) -> Option<(usize, &str)> {
    let mut in_string = false;
    let mut previous = ' ';
    let mut chars = line.char_indices().peekable();
    while let Some((i, c)) = chars.next() {
        match c {
            '"' if previous != '\\' && !line[..i].ends_with('\'') => in_string = !in_string,
            '/' if !in_string && chars.peek().is_some_and(|(_, n)| *n == '/') => {
                return Some((i, &line[i..]));
            }
            _ => {}
        }
        previous = if previous == '\\' && c == '\\' {
            ' '
        } else {
            c
        };
    }
    None
}

/// The text each scanned file contributes, line by line: a manual page whole, a source file's
/// comments only (other lines empty, so that line numbers stay the file's).
fn scanned_files() -> Vec<(PathBuf, Vec<String>)> {
    let mut files = Vec::new();
    let mut pages = vec![root().join("README.md")];
    for entry in std::fs::read_dir(root().join("docs")).unwrap().flatten() {
        let path = entry.path();
        if path.is_file() && path.extension().is_some_and(|e| e == "md") {
            pages.push(path);
        }
    }
    for page in pages {
        let text = std::fs::read_to_string(&page).unwrap();
        files.push((page, text.lines().map(str::to_string).collect()));
    }
    let mut sources = Vec::new();
    source_files(&root().join("src"), "rs", &mut sources);
    source_files(&root().join("shaders"), "wgsl", &mut sources);
    for source in sources {
        let text = std::fs::read_to_string(&source).unwrap();
        let lines = text
            .lines()
            .map(|line| comment(line).map_or(String::new(), |(_, c)| c.to_string()))
            .collect();
        files.push((source, lines));
    }
    files.sort();
    files
}

fn source_files(dir: &Path, extension: &str, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap().flatten() {
        let path = entry.path();
        if path.is_dir() {
            source_files(&path, extension, out);
        } else if path.extension().is_some_and(|e| e == extension) {
            out.push(path);
        }
    }
}

/// The findings that `allowed` does not cover, as `file:line: kind "figure" in: line`, and the
/// allow-list entries that covered nothing.
fn violations<'a>(
    files: &[(String, Vec<String>)],
    allowed: &'a [(&'a str, &'a str, &'a str)],
) -> (Vec<String>, Vec<&'a (&'a str, &'a str, &'a str)>) {
    let mut used = vec![false; allowed.len()];
    let mut out = Vec::new();
    for (file, lines) in files {
        for (n, line) in lines.iter().enumerate() {
            for figure in figures(line) {
                let covering = allowed.iter().enumerate().find(|(_, (f, text, _))| {
                    f == file
                        && line
                            .match_indices(text)
                            .any(|(at, _)| at <= figure.start && figure.end <= at + text.len())
                });
                if let Some((index, _)) = covering {
                    used[index] = true;
                } else {
                    out.push(format!(
                        "{file}:{}: {} \"{}\" in: {}",
                        n + 1,
                        figure.kind,
                        &line[figure.start..figure.end],
                        line.trim()
                    ));
                }
            }
        }
    }
    let unused = allowed
        .iter()
        .zip(used)
        .filter(|(_, used)| !used)
        .map(|(entry, _)| entry)
        .collect();
    (out, unused)
}

#[test]
fn manual_pages_and_comments_hold_no_measurement_history() {
    let files: Vec<(String, Vec<String>)> = scanned_files()
        .into_iter()
        .map(|(path, lines)| {
            let relative = path.strip_prefix(root()).unwrap();
            (relative.to_string_lossy().replace('\\', "/"), lines)
        })
        .collect();
    assert!(
        files.len() > 100,
        "only {} files scanned: is the walk broken?",
        files.len()
    );
    let (found, unused) = violations(&files, ALLOWED);
    assert!(
        unused.is_empty(),
        "allow-list entries that match nothing any more (remove them):\n{}",
        unused
            .iter()
            .map(|(file, text, _)| format!("{file}: {text}"))
            .collect::<Vec<_>>()
            .join("\n")
    );
    assert!(
        found.is_empty(),
        "measurement history in the manual or in comments; move it to a dated entry of \
         docs/notebook/ (with its command) or link the report, or, for a figure that defines \
         something, add it to ALLOWED with its reason:\n{}",
        found.join("\n")
    );
}

#[test]
fn the_detector_finds_figures_and_leaves_names_alone() {
    let kinds = |line: &str| {
        figures(line)
            .into_iter()
            .map(|f| f.kind)
            .collect::<Vec<_>>()
    };
    assert_eq!(kinds("velvet reads 1.28% after the fit"), ["percentage"]);
    assert_eq!(
        kinds("a frame took 12 ms, the bake 3.4 s"),
        ["timing", "timing"]
    );
    assert_eq!(kinds("in 20 minutes on two cores"), ["timing"]);
    assert_eq!(kinds("a kernel at 19ns"), ["timing"]);
    assert_eq!(kinds("a pure parabola would gain 2.4×"), ["ratio"]);
    assert_eq!(kinds("about 1.6 times faster than before"), ["ratio"]);
    assert_eq!(kinds("at commit 665c86f, a cold run"), ["commit hash"]);
    assert_eq!(kinds("the bound (measured on lavapipe)"), ["measurement"]);
    assert_eq!(kinds("which measured 3e-6 there"), ["measurement"]);
    for name in [
        "a 1024 × 1024 frame, a 2×2 quad",
        "f32 lanes of wide::f32x8 on x86_64",
        "split_frame 31, thread_frame 48, K = 96 samples",
        "σu = 20° by default, 1e-4 relative",
        "a word such as defaced or a number such as 1234567",
        "along axis 1 s1, along v s3",
    ] {
        assert!(kinds(name).is_empty(), "{name}: {:?}", figures(name));
    }
}

#[test]
fn the_scan_fails_on_an_injected_figure_and_names_its_line() {
    let page = |lines: &[&str]| {
        vec![(
            "docs/sample.md".to_string(),
            lines.iter().map(|l| l.to_string()).collect::<Vec<_>>(),
        )]
    };
    let clean = page(&[
        "# A page",
        "The table holds F.",
        "Within 1% in 4 MiB is the goal.",
    ]);
    let allowed = [("docs/sample.md", "Within 1% in 4 MiB", "a goal")];
    let (found, unused) = violations(&clean, &allowed);
    assert!(
        found.is_empty() && unused.is_empty(),
        "{found:?} {unused:?}"
    );
    // The same page with a measurement added: the allow-list entry does not cover it.
    let injected = page(&[
        "# A page",
        "The table holds F.",
        "Within 1% in 4 MiB is the goal; velvet read 0.83% (measured: 2026-12-05).",
    ]);
    let (found, _) = violations(&injected, &allowed);
    assert_eq!(found.len(), 2, "{found:?}");
    assert!(found[0].starts_with("docs/sample.md:3: percentage \"0.83%\""));
    assert!(found[1].starts_with("docs/sample.md:3: measurement"));
    // An entry that matches nothing is reported.
    let (_, unused) = violations(&page(&["nothing here"]), &allowed);
    assert_eq!(unused.len(), 1);
}

#[test]
fn comments_are_found_outside_strings() {
    assert_eq!(
        comment("let x = 1; // took 3 ms").map(|(_, c)| c),
        Some("// took 3 ms")
    );
    assert_eq!(comment("let url = \"http://example\";"), None);
    assert_eq!(
        comment("let s = \"a\"; /// doc 2%").map(|(_, c)| c),
        Some("/// doc 2%")
    );
    assert_eq!(
        comment("if c == '\"' { x } // 5%").map(|(_, c)| c),
        Some("// 5%")
    );
}
