//! Every default the manual states is the program's (tracker issue 47):
//!
//! - `docs/commands.md` states each command's defaults in one form, a table
//!   `| option | default |` under the command's heading, with the default in the words
//!   `clothbake <command> --help` prints (`[default: X]`, or `(default: X)` in the option's
//!   help); every default `--help` prints has its row, and every row is what `--help` prints;
//! - the same section's `| layout | its own resolution |` table is each layout's
//!   `default_resolution` (which `--help` names only as "the layout's own");
//! - anywhere in the manual (`README.md`, `docs/*.md`), a `--option` followed in its sentence
//!   by `(default ...)` states what `--help` prints for that option, and a sentence that calls
//!   a layout at a resolution the default names the layout's default resolution.
//!
//! The binary is `CLOTHBAKE_BIN` when set (scripts/test.sh passes the one it built), else the
//! one cargo built for this test.

use clothbake::table::Layout;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn clothbake_bin() -> PathBuf {
    std::env::var_os("CLOTHBAKE_BIN")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_BIN_EXE_clothbake")))
}

/// A default as compared: backticks and a trailing full stop dropped, white space collapsed,
/// lower case.
fn normalise(text: &str) -> String {
    text.replace('`', "")
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
        .trim_end_matches('.')
        .to_lowercase()
}

/// The text of a parenthesis (or bracket) opening at byte `open`, up to its matching close.
fn enclosed(text: &str, open: usize) -> Option<&str> {
    let (opening, closing) = match text[open..].chars().next()? {
        '(' => ('(', ')'),
        '[' => ('[', ']'),
        _ => return None,
    };
    let mut depth = 0;
    for (i, c) in text[open..].char_indices() {
        if c == opening {
            depth += 1;
        } else if c == closing {
            depth -= 1;
            if depth == 0 {
                return Some(&text[open + 1..open + i]);
            }
        }
    }
    None
}

/// The defaults stated in a piece of text: each `[default: X]`, `(default: X)` or
/// `(default X)`, as X up to its first `;` (what follows a `;` explains, it is not the value).
/// `(default unless ...)` states a condition, not a value.
fn stated_defaults(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    for (open, _) in text.match_indices(['(', '[']) {
        let Some(inner) = enclosed(text, open) else {
            continue;
        };
        let Some(value) = inner.strip_prefix("default") else {
            continue;
        };
        if !value.starts_with([':', ' ']) || value.trim_start().starts_with("unless") {
            continue;
        }
        let value = value.trim_start_matches(':').trim();
        let value = value.split(';').next().unwrap_or("").trim();
        out.push(normalise(value));
    }
    out
}

/// Each option of a `--help` page with the defaults its help states, in order.
fn help_defaults(help: &str) -> BTreeMap<String, Vec<String>> {
    let mut options: BTreeMap<String, String> = BTreeMap::new();
    let mut current: Option<String> = None;
    for line in help.lines() {
        let trimmed = line.trim_start();
        let option_line =
            line.starts_with("  ") && (trimmed.starts_with("--") || trimmed.starts_with("-h"));
        if option_line {
            let name = trimmed
                .split(|c: char| c.is_whitespace() || c == ',')
                .find(|w| w.starts_with("--"))
                .unwrap_or("")
                .to_string();
            let text = trimmed
                .split_once(char::is_whitespace)
                .map_or("", |(_, t)| t);
            options.insert(name.clone(), text.to_string());
            current = Some(name);
        } else if let Some(name) = &current {
            // The option's possible values are not its defaults ("- paper: ... (default 32)"
            // is paper mode's own); a `[default: X]` after them is the option's.
            if !trimmed.starts_with("Possible values:") && !trimmed.starts_with("- ") {
                let entry = options.get_mut(name).unwrap();
                entry.push(' ');
                entry.push_str(trimmed);
            }
        }
    }
    options
        .into_iter()
        .map(|(name, text)| (name, stated_defaults(&text)))
        .filter(|(_, defaults)| !defaults.is_empty())
        .collect()
}

fn help(command: &str) -> String {
    let output = Command::new(clothbake_bin())
        .args([command, "--help"])
        .output()
        .expect("clothbake runs");
    assert!(output.status.success(), "clothbake {command} --help failed");
    String::from_utf8(output.stdout).unwrap()
}

/// The `| first | second |` tables with the given header under each `## command` heading of a
/// page: command to rows of (first cell, second cell).
fn section_tables(page: &str, header: (&str, &str)) -> BTreeMap<String, Vec<(String, String)>> {
    let mut tables: BTreeMap<String, Vec<(String, String)>> = BTreeMap::new();
    let mut section = String::new();
    let mut in_table = false;
    for line in page.lines() {
        if let Some(heading) = line.strip_prefix("## ") {
            section = heading.trim().to_string();
            in_table = false;
            continue;
        }
        let cells: Vec<&str> = line
            .trim()
            .trim_matches('|')
            .split('|')
            .map(str::trim)
            .collect();
        if !line.trim_start().starts_with('|') || cells.len() != 2 {
            in_table = false;
            continue;
        }
        if cells[0] == header.0 && cells[1] == header.1 {
            in_table = true;
            tables.entry(section.clone()).or_default();
        } else if in_table && !cells[0].starts_with("---") {
            tables
                .get_mut(&section)
                .unwrap()
                .push((cells[0].trim_matches('`').to_string(), cells[1].to_string()));
        }
    }
    tables
}

/// The disagreements between the defaults `commands.md` states and those each command's
/// `--help` prints (`helps`: command to its `--help` text).
fn command_table_mismatches(commands_page: &str, helps: &BTreeMap<String, String>) -> Vec<String> {
    let tables = section_tables(commands_page, ("option", "default"));
    let mut out = Vec::new();
    for (command, help) in helps {
        let printed = help_defaults(help);
        let stated: BTreeMap<String, String> = tables
            .get(command)
            .map(|rows| rows.iter().cloned().collect())
            .unwrap_or_default();
        for (option, defaults) in &printed {
            match stated.get(option) {
                None => out.push(format!(
                    "docs/commands.md, {command}: no row for {option}, whose --help states \
                     default {:?}",
                    defaults[0]
                )),
                Some(value) if !defaults.contains(&normalise(value)) => out.push(format!(
                    "docs/commands.md, {command}: {option} stated as {value:?}, --help prints \
                     {defaults:?}"
                )),
                Some(_) => {}
            }
        }
        for option in stated.keys() {
            if !printed.contains_key(option) {
                out.push(format!(
                    "docs/commands.md, {command}: a default for {option}, which --help gives none"
                ));
            }
        }
    }
    for command in tables.keys() {
        if !helps.contains_key(command) {
            out.push(format!(
                "docs/commands.md: a defaults table under {command:?}, no such command"
            ));
        }
    }
    out
}

/// The manual's statements "`--option` ... (default ...)" in one paragraph of a page, as
/// (option, stated value): the option is the nearest one before the parenthesis in its
/// sentence.
fn prose_defaults(paragraph: &str) -> Vec<(String, String)> {
    let mut out = Vec::new();
    for sentence in paragraph.split(". ") {
        for (open, _) in sentence.match_indices("(default") {
            let before = &sentence[..open];
            let Some(at) = before.rfind("`--") else {
                continue;
            };
            let option: String = before[at + 1..]
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '-')
                .collect();
            let Some(value) = stated_defaults(&sentence[open..]).into_iter().next() else {
                continue;
            };
            out.push((option, value));
        }
    }
    out
}

/// The paragraphs of a Markdown page outside code blocks, lines joined by spaces, with the
/// line each starts on.
fn paragraphs(page: &str) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    let mut current: Option<(usize, String)> = None;
    let mut in_fence = false;
    for (n, line) in page.lines().enumerate() {
        if line.trim_start().starts_with("```") {
            in_fence = !in_fence;
        }
        if in_fence || line.trim().is_empty() || line.trim_start().starts_with("```") {
            out.extend(current.take());
            continue;
        }
        // A list item or a table row is a paragraph of its own.
        if line.trim_start().starts_with(['-', '*', '|']) {
            out.extend(current.take());
        }
        match &mut current {
            Some((_, text)) => {
                text.push(' ');
                text.push_str(line.trim());
            }
            None => current = Some((n + 1, line.trim().to_string())),
        }
    }
    out.extend(current);
    out
}

/// In sentences that speak of a default, each "`layout` N" or "layout N" must be the layout's
/// default resolution: (layout, stated resolution) pairs that are not.
fn layout_resolution_mismatches(sentence: &str) -> Vec<(String, u32)> {
    let mut out = Vec::new();
    if !sentence.to_lowercase().contains("default") {
        return out;
    }
    for layout in Layout::ALL {
        for (at, _) in sentence.match_indices(layout.name()) {
            let rest = sentence[at + layout.name().len()..].trim_start_matches('`');
            let Some(rest) = rest.strip_prefix(' ') else {
                continue;
            };
            let digits: String = rest.chars().take_while(char::is_ascii_digit).collect();
            let Ok(resolution) = digits.parse::<u32>() else {
                continue;
            };
            if resolution != layout.default_resolution() {
                out.push((layout.name().to_string(), resolution));
            }
        }
    }
    out
}

fn manual_pages() -> Vec<PathBuf> {
    let mut pages = vec![root().join("README.md")];
    for entry in std::fs::read_dir(root().join("docs")).unwrap().flatten() {
        let path = entry.path();
        if path.is_file() && path.extension().is_some_and(|e| e == "md") {
            pages.push(path);
        }
    }
    pages.sort();
    pages
}

/// Every subcommand `clothbake --help` lists.
fn commands() -> Vec<String> {
    let output = Command::new(clothbake_bin())
        .arg("--help")
        .output()
        .expect("clothbake runs");
    let help = String::from_utf8(output.stdout).unwrap();
    help.lines()
        .skip_while(|l| !l.starts_with("Commands:"))
        .skip(1)
        .take_while(|l| l.starts_with("  "))
        .filter_map(|l| l.split_whitespace().next())
        .filter(|c| *c != "help")
        .map(str::to_string)
        .collect()
}

#[test]
fn the_defaults_the_manual_states_are_the_programs() {
    let commands = commands();
    assert!(
        commands.len() >= 10,
        "only {commands:?} found in clothbake --help"
    );
    let helps: BTreeMap<String, String> = commands.iter().map(|c| (c.clone(), help(c))).collect();
    let commands_page = std::fs::read_to_string(root().join("docs/commands.md")).unwrap();
    let mut wrong = command_table_mismatches(&commands_page, &helps);

    let resolutions = section_tables(&commands_page, ("layout", "its own resolution"));
    let stated = resolutions.get("bake").cloned().unwrap_or_default();
    for layout in Layout::ALL {
        let row = stated.iter().find(|(name, _)| name == layout.name());
        if row.is_none_or(|(_, r)| r.trim() != layout.default_resolution().to_string()) {
            wrong.push(format!(
                "docs/commands.md, bake: {} stated at {:?}, its default resolution is {}",
                layout.name(),
                row.map(|(_, r)| r.as_str()),
                layout.default_resolution()
            ));
        }
    }

    let all_printed: Vec<(String, Vec<String>)> = helps
        .values()
        .flat_map(|h| help_defaults(h).into_iter())
        .collect();
    let mut prose_checked = 0;
    for page in manual_pages() {
        let name = page.strip_prefix(root()).unwrap().display().to_string();
        let text = std::fs::read_to_string(&page).unwrap();
        for (line, paragraph) in paragraphs(&text) {
            if paragraph.starts_with('|') && name == "docs/commands.md" {
                continue; // the defaults tables, checked above
            }
            for (option, value) in prose_defaults(&paragraph) {
                let printed: Vec<&String> = all_printed
                    .iter()
                    .filter(|(o, _)| *o == option)
                    .flat_map(|(_, d)| d)
                    .collect();
                prose_checked += 1;
                if !printed.contains(&&value) {
                    wrong.push(format!(
                        "{name}:{line}: {option} stated with default {value:?}, --help prints \
                         {printed:?}"
                    ));
                }
            }
            for sentence in paragraph.split(". ") {
                for (layout, resolution) in layout_resolution_mismatches(sentence) {
                    wrong.push(format!(
                        "{name}:{line}: \"{layout} {resolution}\" in a sentence about a \
                         default; {layout}'s default resolution is another: {sentence}"
                    ));
                }
            }
        }
    }
    println!(
        "checked the defaults tables of {} commands and {prose_checked} defaults in prose",
        helps.len()
    );
    assert!(
        prose_checked > 0,
        "no default found in the manual's prose: is the parser broken?"
    );
    assert!(
        wrong.is_empty(),
        "defaults the manual states wrongly:\n{}",
        wrong.join("\n")
    );
}

/// `--help` of a made-up command, in clap's two layouts (short help on one line, long help
/// with `[default: X]` on its own line, possible values after).
const SAMPLE_HELP: &str = "Bake things

Usage: clothbake bake [OPTIONS]

Options:
      --layout <LAYOUT>          Table layout (default: the scene's, else split_frame)
      --out <OUT>                Output directory [default: tables]
      --pairs <PAIRS>
          Pairs to measure on

          [default: 20000]

      --mode <MODE>
          The mode (default unless --fast is given)

          Possible values:
          - fast: quick (default 32)
  -h, --help                     Print help
";

#[test]
fn help_defaults_are_parsed_in_both_layouts() {
    let defaults = help_defaults(SAMPLE_HELP);
    assert_eq!(defaults["--layout"], ["the scene's, else split_frame"]);
    assert_eq!(defaults["--out"], ["tables"]);
    assert_eq!(defaults["--pairs"], ["20000"]);
    assert!(!defaults.contains_key("--mode"), "{defaults:?}");
}

#[test]
fn a_wrong_or_missing_default_in_the_manual_is_found() {
    let helps = BTreeMap::from([("bake".to_string(), SAMPLE_HELP.to_string())]);
    let right = "## bake\n\n| option | default |\n|---|---|\n| `--layout` | the scene's, else \
                 `split_frame` |\n| `--out` | `tables` |\n| `--pairs` | 20000 |\n";
    assert_eq!(
        command_table_mismatches(right, &helps),
        Vec::<String>::new()
    );
    let wrong = right.replace("| 20000 |", "| 2000 |");
    let found = command_table_mismatches(&wrong, &helps);
    assert_eq!(found.len(), 1, "{found:?}");
    assert!(found[0].contains("--pairs stated as \"2000\""), "{found:?}");
    let missing = right.replace("| `--out` | `tables` |\n", "");
    let found = command_table_mismatches(&missing, &helps);
    assert!(
        found.len() == 1 && found[0].contains("no row for --out"),
        "{found:?}"
    );
    let extra = format!("{right}| `--threads` | 2 |\n");
    assert_eq!(command_table_mismatches(&extra, &helps).len(), 1);
}

#[test]
fn prose_defaults_and_layout_resolutions_are_read() {
    assert_eq!(
        prose_defaults("`--env-sources N` the most sources lit (default 8; 0 samples the map)"),
        [("--env-sources".to_string(), "8".to_string())]
    );
    assert_eq!(
        prose_defaults("`--starts` sets the starts (default 2 with `--like`, 3 with `--weave`)"),
        [(
            "--starts".to_string(),
            "2 with --like, 3 with --weave".to_string()
        )]
    );
    assert!(prose_defaults("paper mode, N samples (default 32)").is_empty());
    let default_resolution = Layout::SPLIT_FRAME.default_resolution();
    let right = format!("By default it bakes at `split_frame` {default_resolution}");
    assert!(layout_resolution_mismatches(&right).is_empty());
    let wrong = format!(
        "By default it bakes at `split_frame` {}",
        default_resolution + 1
    );
    assert_eq!(
        layout_resolution_mismatches(&wrong),
        [("split_frame".to_string(), default_resolution + 1)]
    );
    assert!(layout_resolution_mismatches("split_frame 20 fits in 1 MiB").is_empty());
}
