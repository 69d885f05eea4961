//! REPORT.md is generated from report.json, never edited by hand: re-rendering the committed
//! `report/report.json` reproduces the committed `report/REPORT.md` byte for byte, and the
//! page's "Which table or evaluation to pick" names, for every fabric of the JSON, a table
//! or evaluation that the fabric's data holds, within the need's budget and the best there.
//! The picks are checked against the JSON read as plain values, not through the code that
//! made them.

use clothbake::report::{self, ReportError, markdown};
use serde_json::Value;
use std::path::{Path, PathBuf};

/// The committed report: `report/` at the repository root.
fn committed() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("report")
}

fn committed_md() -> String {
    std::fs::read_to_string(committed().join(markdown::FILE_NAME)).expect("report/REPORT.md")
}

fn committed_json() -> Value {
    let text = std::fs::read_to_string(committed().join(report::JSON_FILE_NAME))
        .expect("report/report.json");
    serde_json::from_str(&text).expect("report/report.json is JSON")
}

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("report-render-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Panics at the first line where `actual` and `expected` differ.
fn assert_same_text(actual: &str, expected: &str, what: &str) {
    if actual == expected {
        return;
    }
    let (a, e): (Vec<&str>, Vec<&str>) = (actual.lines().collect(), expected.lines().collect());
    let line = (0..a.len().max(e.len()))
        .find(|&i| a.get(i) != e.get(i))
        .unwrap_or(a.len().min(e.len()));
    panic!(
        "{what} differs at line {}:\n  rendered:  {:?}\n  committed: {:?}\n(rendered {} bytes, \
         committed {}; regenerate with `clothbake report --rerender` or a new report run)",
        line + 1,
        a.get(line),
        e.get(line),
        actual.len(),
        expected.len()
    );
}

#[test]
fn committed_report_md_is_rendered_from_committed_report_json() {
    let report = report::read(&committed()).expect("report/report.json reads as a Report");
    assert_same_text(
        &markdown::render(&report),
        &committed_md(),
        "REPORT.md rendered from report/report.json",
    );
}

#[test]
fn committed_report_json_reads_back_field_for_field() {
    // Written back, the report read is the committed file to the byte: no field is lost or
    // defaulted in reading, and every float survives the round trip.
    let report = report::read(&committed()).unwrap();
    let text = std::fs::read_to_string(committed().join(report::JSON_FILE_NAME)).unwrap();
    assert_same_text(
        &serde_json::to_string_pretty(&report).unwrap(),
        &text,
        "report.json written back",
    );
}

#[test]
fn rerender_rewrites_report_md_from_report_json_alone() {
    let dir = scratch("rerender");
    std::fs::copy(
        committed().join(report::JSON_FILE_NAME),
        dir.join(report::JSON_FILE_NAME),
    )
    .unwrap();
    // A stale page is replaced.
    std::fs::write(dir.join(markdown::FILE_NAME), "stale").unwrap();
    let report = report::rerender(&dir).expect("rerender");
    assert_eq!(report.fabrics.len(), report.fabric_names.len());
    let md = std::fs::read_to_string(dir.join(markdown::FILE_NAME)).unwrap();
    assert_same_text(&md, &committed_md(), "REPORT.md written by rerender");
    // Written atomically: nothing but the report's files (REPORT.md, report.json and the
    // plots) is left behind.
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    let mut files = report.files.clone();
    // The stock section's grid of renders is not in report.json: rerender leaves it be.
    files.retain(|f| f != report::plots::stock::STOCK_GRID);
    files.sort();
    assert_eq!(names, files);
    assert!(files.iter().any(|f| f.ends_with(".png")), "{files:?}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn rerender_fails_on_a_missing_or_damaged_report_json() {
    let dir = scratch("damaged");
    let missing = report::rerender(&dir).unwrap_err();
    assert!(matches!(missing, ReportError::Read { .. }), "{missing}");
    // A report.json cut short.
    let text = std::fs::read_to_string(committed().join(report::JSON_FILE_NAME)).unwrap();
    std::fs::write(dir.join(report::JSON_FILE_NAME), &text[..text.len() / 2]).unwrap();
    let damaged = report::rerender(&dir).unwrap_err();
    assert!(matches!(damaged, ReportError::Json { .. }), "{damaged}");
    // A report.json without its fabrics.
    let mut json = committed_json();
    json.as_object_mut().unwrap().remove("fabrics");
    std::fs::write(dir.join(report::JSON_FILE_NAME), json.to_string()).unwrap();
    let incomplete = report::rerender(&dir).unwrap_err();
    assert!(
        matches!(incomplete, ReportError::Json { .. }),
        "{incomplete}"
    );
    assert!(
        !dir.join(markdown::FILE_NAME).exists(),
        "no REPORT.md from a bad report.json"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Rewrites every evaluator point of `value` in the form reports had before points named
/// their evaluator by spelling: one family per integration rule.
fn to_earlier_point_forms(value: &mut Value) {
    match value {
        Value::Object(map) if map.get("family").and_then(Value::as_str) == Some("evaluator") => {
            let spelling = map["spelling"].as_str().unwrap().to_string();
            *value = match spelling.split_once(':').unwrap() {
                ("paper", n) => {
                    serde_json::json!({"family": "paper", "samples": n.parse::<u32>().unwrap()})
                }
                ("resonant", nodes) => {
                    let n: Vec<u32> = nodes.split('/').map(|x| x.parse().unwrap()).collect();
                    serde_json::json!({"family": "resonant",
                        "nodes": {"surface": n[0], "volume": n[1], "base": n[2]}})
                }
                _ => panic!("no earlier form of {spelling}"),
            };
        }
        Value::Object(map) => map.values_mut().for_each(to_earlier_point_forms),
        Value::Array(items) => items.iter_mut().for_each(to_earlier_point_forms),
        _ => {}
    }
}

#[test]
fn a_report_json_in_the_earlier_point_forms_renders_the_same_page() {
    // A report.json written before the configuration listed its evaluators' spellings and
    // before points named their evaluator by spelling still reads, to the same page.
    let mut json = committed_json();
    to_earlier_point_forms(&mut json);
    let config = json["config"].as_object_mut().unwrap();
    config.remove("evaluators");
    config.remove("gpu_evaluators");
    assert!(!json.to_string().contains("\"evaluator\""));
    let dir = scratch("earlier");
    std::fs::write(dir.join(report::JSON_FILE_NAME), json.to_string()).unwrap();
    let report = report::read(&dir).expect("an earlier report.json reads");
    assert_same_text(
        &markdown::render(&report),
        &committed_md(),
        "REPORT.md rendered from the earlier forms",
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The lines of the section under `## {heading}`, up to the next `## ` heading.
fn section<'a>(md: &'a str, heading: &str) -> Vec<&'a str> {
    let start = format!("## {heading}");
    md.lines()
        .skip_while(|l| *l != start)
        .skip(1)
        .take_while(|l| !l.starts_with("## "))
        .collect()
}

/// The cells of a Markdown table row.
fn cells(row: &str) -> Vec<&str> {
    let inner = row.trim().trim_start_matches('|').trim_end_matches('|');
    inner.split(" | ").map(str::trim).collect()
}

#[path = "../common/anchor.rs"]
mod anchor_of;
use anchor_of::github_anchor as anchor;

/// One way of getting F that a fabric's data holds, as REPORT.md names it.
#[derive(Debug)]
struct Candidate {
    name: String,
    /// "cpu table", "cpu model" (any registered evaluator), "direct" or "gpu".
    kind: &'static str,
    error: f64,
    /// ns per evaluation on the CPU, ms per frame on the GPU.
    cost: f64,
    bytes: Option<f64>,
}

fn number(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

fn worst(error: &Value) -> f64 {
    number(&error["uniform"]["relative_rms"]).max(number(&error["highlight"]["relative_rms"]))
}

/// An evaluator's spelling, as REPORT.md names it ("paper:32").
fn spelling(evaluation: &Value) -> String {
    evaluation["spelling"].as_str().unwrap().to_string()
}

/// A table as REPORT.md names it, "thread_frame 48".
fn table(evaluation: &Value) -> String {
    format!(
        "{} {}",
        evaluation["layout"].as_str().unwrap(),
        evaluation["resolution"]
    )
}

/// Everything measured for the fabric `name` in the JSON, CPU and GPU.
fn candidates(json: &Value, name: &str) -> Vec<Candidate> {
    let fabric = json["fabrics"]
        .as_array()
        .unwrap()
        .iter()
        .find(|f| f["name"] == name)
        .unwrap_or_else(|| panic!("{name} is not in report.json"));
    let mut out = vec![Candidate {
        name: "direct".into(),
        kind: "direct",
        error: 0.0,
        cost: number(&fabric["direct"]["ns_per_eval"]),
        bytes: None,
    }];
    for p in fabric["points"].as_array().unwrap() {
        let e = &p["evaluation"];
        let (name, kind) = match e["family"].as_str().unwrap() {
            "evaluator" => (spelling(e), "cpu model"),
            "table" => (table(e), "cpu table"),
            other => panic!("unknown family {other:?}"),
        };
        out.push(Candidate {
            name,
            kind,
            error: worst(&p["error"]),
            cost: number(&p["timing"]["ns_per_eval"]),
            bytes: p["bytes"].as_f64(),
        });
    }
    let gpu = &json["gpu"];
    let gpu_fabric = gpu["fabrics"]
        .as_array()
        .unwrap()
        .iter()
        .find(|f| f["name"] == name)
        .filter(|_| gpu["measured"] == true);
    if let Some(f) = gpu_fabric {
        for p in f["points"].as_array().unwrap() {
            let e = &p["evaluation"];
            let name = match e["family"].as_str().unwrap() {
                "evaluator" => format!("{} shader", spelling(e)),
                _ => format!("lookup shader, {}", table(e)),
            };
            out.push(Candidate {
                name,
                kind: "gpu",
                error: number(&p["image_relative_l2"]),
                cost: number(&p["ms_per_frame"]),
                bytes: None,
            });
        }
    }
    out
}

/// The budget a column header states ("smallest table ≤ 2%" → 0.02).
fn column_budget(header: &str) -> Option<f64> {
    let (_, after) = header.split_once("≤ ")?;
    let percent: f64 = after.trim_end_matches('%').parse().ok()?;
    Some(percent / 100.0)
}

#[test]
fn pick_section_names_a_measured_choice_within_budget_for_every_fabric() {
    let md = committed_md();
    let json = committed_json();
    let lines = section(&md, "Which table or evaluation to pick");
    assert!(!lines.is_empty(), "REPORT.md has no pick section");
    let header = lines
        .iter()
        .position(|l| l.starts_with("| fabric |"))
        .expect("the pick section's per-fabric table");
    let columns = cells(lines[header]);
    for needed in [
        "real-time image",
        "smallest table",
        "fastest CPU evaluation",
        "no bake",
        "ground truth",
    ] {
        assert!(
            columns.iter().any(|c| c.starts_with(needed)),
            "no column {needed:?} in {columns:?}"
        );
    }
    let rows: Vec<Vec<&str>> = lines[header + 2..]
        .iter()
        .take_while(|l| l.starts_with('|'))
        .map(|l| cells(l))
        .collect();
    let fabrics: Vec<&str> = json["fabrics"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f["name"].as_str().unwrap())
        .collect();
    let named: Vec<&str> = rows.iter().map(|r| r[0]).collect();
    assert_eq!(
        named, fabrics,
        "one row per fabric of report.json, in order"
    );
    for row in &rows {
        let fabric = row[0];
        assert_eq!(row.len(), columns.len(), "{fabric}: {row:?}");
        let all = candidates(&json, fabric);
        for (column, cell) in columns.iter().zip(row).skip(1) {
            let what = format!("{fabric}, {column}: {cell:?}");
            let budget = column_budget(column);
            let eligible: Vec<&Candidate> = all
                .iter()
                .filter(|c| match *column {
                    c2 if c2.starts_with("real-time image") => c.kind == "gpu",
                    c2 if c2.starts_with("smallest table") => c.kind == "cpu table",
                    c2 if c2.starts_with("fastest CPU") => c.kind != "gpu",
                    c2 if c2.starts_with("no bake") => c.kind == "cpu model",
                    _ => c.kind == "direct",
                })
                .filter(|c| budget.is_none_or(|b| c.error <= b))
                .collect();
            if cell.starts_with("none within") {
                assert!(eligible.is_empty(), "{what}, but {eligible:?} is");
                continue;
            }
            let name = cell.split(" (").next().unwrap();
            let pick = all
                .iter()
                .find(|c| c.name == name)
                .unwrap_or_else(|| panic!("{what}: {name:?} is not in the fabric's data"));
            assert!(
                eligible.iter().any(|c| c.name == name),
                "{what}: {pick:?} is not of the column's kind or over its budget"
            );
            // And the best of them: the smallest table, else the cheapest.
            let better = eligible.iter().find(|c| match (c.bytes, pick.bytes) {
                (Some(b), Some(p)) if column.starts_with("smallest") => b < p,
                _ => !column.starts_with("smallest") && c.cost < pick.cost,
            });
            assert!(better.is_none(), "{what}: {better:?} beats it");
        }
    }
}

#[test]
fn pick_section_links_resolve() {
    let md = committed_md();
    let anchors: Vec<String> = md
        .lines()
        .filter(|l| l.starts_with('#'))
        .map(anchor)
        .collect();
    assert!(anchors.contains(&"which-table-or-evaluation-to-pick".to_string()));
    assert!(anchors.contains(&"error-budgets".to_string()));
    let text = section(&md, "Which table or evaluation to pick").join("\n");
    let mut links = 0;
    for (_, rest) in text.match_indices("](").map(|(i, _)| text.split_at(i + 2)) {
        let target = rest.split(')').next().unwrap();
        links += 1;
        match target.strip_prefix('#') {
            Some(a) => assert!(anchors.iter().any(|x| x == a), "no heading for #{a}"),
            None => assert!(
                committed().join(target).is_file(),
                "report/{target} does not exist"
            ),
        }
    }
    assert!(
        links >= 5,
        "the pick section links its figures and sections"
    );
}
