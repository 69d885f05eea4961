//! The report on a tiny configuration: every file is written, report.json has the structure
//! the report documents with finite figures, and the plots are valid PNGs with drawn curves.
//! No timing is asserted (the machine's speed is not under test).

use clothbake::evaluator::parse;
use clothbake::formats::fabric_toml::FabricSet;
use clothbake::report::{ReportConfig, planned_units, run};
use clothbake::table::Layout;
use serde_json::Value;
use std::path::{Path, PathBuf};

fn out_dir() -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("report-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

/// Two fabrics (so the plots have several panels), the smallest resolutions that bake in
/// well under a second, a few pairs, one repetition; no GPU.
fn tiny_config() -> ReportConfig {
    let set = FabricSet::builtin();
    let fabrics = ["linen_plain", "velvet"]
        .iter()
        .map(|n| set.get(n).expect("built-in fabric").clone())
        .collect();
    ReportConfig {
        mode: "test".into(),
        error_pairs: 200,
        timing_pairs: 16,
        timing_samples: 3,
        min_sample_seconds: 0.001,
        resolutions: vec![
            (Layout::THREAD_FRAME, vec![8, 12]),
            (Layout::GRID4D, vec![4, 6]),
        ],
        evaluators: ["paper:1", "paper:4", "paper:16", "resonant:3/2/2"]
            .into_iter()
            .map(String::from)
            .chain([default_resonant()])
            .collect(),
        bake_repetitions: 1,
        speedup_layout: Layout::GRID4D,
        speedup_resolution: 4,
        speedup_repetitions: 1,
        gpu: false,
        // The stock section has its own test (stock.rs).
        stock: None,
        ..ReportConfig::quick(fabrics)
    }
}

/// The resonant unit's default spelling ("resonant:6/5/2").
fn default_resonant() -> String {
    parse("resonant").unwrap().spelling()
}

/// The spelling of a point's evaluator, or None for a table.
fn spelling(point: &Value) -> Option<&str> {
    let evaluation = &point["evaluation"];
    (evaluation["family"] == "evaluator").then(|| evaluation["spelling"].as_str().unwrap())
}

fn finite(v: &Value, what: &str) -> f64 {
    let x = v
        .as_f64()
        .unwrap_or_else(|| panic!("{what} is not a number: {v}"));
    assert!(x.is_finite(), "{what} = {x}");
    x
}

fn check_error(e: &Value, what: &str) {
    for set in ["uniform", "highlight", "uniform_above_15deg"] {
        let rms = finite(&e[set]["relative_rms"], &format!("{what}.{set}"));
        assert!(rms >= 0.0, "{what}.{set} = {rms}");
    }
}

fn check_timing(t: &Value, samples: usize, what: &str) {
    assert!(finite(&t["ns_per_eval"], what) > 0.0, "{what}");
    assert_eq!(
        t["samples_ns"].as_array().map(Vec::len),
        Some(samples),
        "{what}"
    );
}

/// Decodes a PNG and checks that it is a real plot: its size, a share of non-background
/// pixels (axes, text, curves) between 1% and 60%, and pixels of each expected series
/// colour (the curves were drawn, not only the frame).
pub(crate) fn check_png(path: &Path, colours: &[[u8; 3]]) {
    let decoder = png::Decoder::new(std::io::BufReader::new(
        std::fs::File::open(path).expect("plot exists"),
    ));
    let mut reader = decoder.read_info().expect("valid PNG header");
    let mut buffer = vec![0; reader.output_buffer_size().expect("size")];
    let info = reader.next_frame(&mut buffer).expect("valid PNG data");
    assert_eq!(info.color_type, png::ColorType::Rgb, "{}", path.display());
    assert!(
        info.width >= 400 && info.height >= 300,
        "{}",
        path.display()
    );
    let pixels: Vec<[u8; 3]> = buffer[..info.buffer_size()]
        .chunks_exact(3)
        .map(|p| [p[0], p[1], p[2]])
        .collect();
    let drawn = pixels.iter().filter(|p| **p != [255, 255, 255]).count();
    let share = drawn as f64 / pixels.len() as f64;
    println!("{}: {:.1}% drawn", path.display(), 100.0 * share);
    assert!((0.01..0.6).contains(&share), "{}: {share}", path.display());
    for colour in colours {
        let count = pixels.iter().filter(|p| *p == colour).count();
        assert!(
            count > 50,
            "{}: {count} pixels of {colour:?}",
            path.display()
        );
    }
}

#[test]
fn tiny_report_writes_json_markdown_and_plots() {
    let config = tiny_config();
    let out = out_dir();
    let report = run(&config, &out, vec!["test".into()], &mut |line| {
        println!("{line}")
    })
    .expect("report runs");
    assert_eq!(report.fabrics.len(), 2);

    let json: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap()).unwrap();
    assert_eq!(json["clothbake_version"], env!("CARGO_PKG_VERSION"));
    for key in [
        "date_utc",
        "command_line",
        "machine",
        "config",
        "gpu",
        "files",
    ] {
        assert!(!json[key].is_null(), "report.json lacks {key}");
    }
    assert!(json["machine"]["logical_cores"].as_u64().unwrap() >= 1);
    assert_eq!(json["gpu"]["measured"], false);
    let fabrics = json["fabrics"].as_array().expect("fabrics array");
    assert_eq!(fabrics.len(), 2);
    for f in fabrics {
        let name = f["name"].as_str().unwrap().to_string();
        check_timing(&f["direct"], 3, &format!("{name} direct"));
        let points = f["points"].as_array().expect("points array");
        let of = |unit: &str| -> Vec<&Value> {
            points
                .iter()
                .filter(|p| spelling(p).is_some_and(|s| s.split(':').next() == Some(unit)))
                .collect()
        };
        let paper = of("paper");
        assert_eq!(
            paper
                .iter()
                .map(|p| spelling(p).unwrap())
                .collect::<Vec<_>>(),
            ["paper:1", "paper:4", "paper:16"]
        );
        for p in &paper {
            check_error(&p["error"], &format!("{name} paper"));
            check_timing(&p["timing"], 3, &format!("{name} paper"));
            // Paper mode is the baseline: compared with nothing.
            assert!(p["vs_baseline"].is_null() && p["vs_best"].is_null(), "{p}");
            assert!(p["evaluations_per_light"].is_null(), "{p}");
        }
        let resonant = of("resonant");
        assert_eq!(
            resonant
                .iter()
                .map(|r| spelling(r).unwrap().to_string())
                .collect::<Vec<_>>(),
            ["resonant:3/2/2".to_string(), default_resonant()]
        );
        for r in &resonant {
            let what = format!("{name} {}", spelling(r).unwrap());
            check_error(&r["error"], &what);
            check_timing(&r["timing"], 3, &what);
            let per_light = &r["evaluations_per_light"];
            let uniform = finite(&per_light["uniform"], &what);
            let highlight = finite(&per_light["highlight"], &what);
            assert!(uniform > 0.0 && highlight > 0.0, "{what}");
            assert!(per_light["max"].as_u64().unwrap() as f64 >= uniform.max(highlight));
            // Against paper mode: either a paper-mode point at least as accurate with the
            // speed ratio to it, or neither.
            let vs_paper = &r["vs_baseline"];
            assert!(vs_paper["wins"].is_boolean(), "{what}: {vs_paper}");
            assert_eq!(
                vs_paper["equal_error"].is_null(),
                vs_paper["speed_ratio"].is_null(),
                "{what}"
            );
            if !vs_paper["speed_ratio"].is_null() {
                assert!(finite(&vs_paper["speed_ratio"], &what) > 0.0);
                let equal = vs_paper["equal_error"]["evaluation"]["spelling"].as_str();
                assert!(equal.unwrap().starts_with("paper:"), "{what}: {vs_paper}");
            }
            assert!(
                r["vs_best"].is_null(),
                "{what}: only tables are judged against all"
            );
        }
        // More nodes: at least as many kernel evaluations per light.
        assert!(
            resonant[1]["evaluations_per_light"]["uniform"].as_f64()
                >= resonant[0]["evaluations_per_light"]["uniform"].as_f64()
        );
        let tables: Vec<&Value> = points.iter().filter(|p| spelling(p).is_none()).collect();
        let ids: Vec<(String, u64)> = tables
            .iter()
            .map(|t| {
                (
                    t["evaluation"]["layout"].as_str().unwrap().to_string(),
                    t["evaluation"]["resolution"].as_u64().unwrap(),
                )
            })
            .collect();
        assert_eq!(
            ids,
            [
                ("thread_frame".into(), 8),
                ("thread_frame".into(), 12),
                ("grid4d".into(), 4),
                ("grid4d".into(), 6)
            ]
        );
        for t in &tables {
            check_error(&t["error"], &format!("{name} table"));
            check_timing(&t["timing"], 3, &format!("{name} lookup"));
            assert!(t["bytes"].as_u64().unwrap() > 0);
            assert!(finite(&t["bake"]["seconds"], "bake") > 0.0);
        }
        // A larger grid4d table has more texels than a smaller one.
        assert!(tables[3]["bytes"].as_u64() > tables[2]["bytes"].as_u64());
        for t in &tables {
            let (paper, best) = (&t["vs_baseline"], &t["vs_best"]);
            assert!(paper["wins"].is_boolean(), "{name}: {t}");
            assert!(best["wins"].is_boolean(), "{name}: {t}");
            // Judged against paper mode and resonant together, a table wins at most where
            // it wins against paper mode alone.
            if best["wins"] == true {
                assert_eq!(paper["wins"], true, "{name}: {t}");
            }
            if let Some(e) = best["equal_error"].as_object() {
                assert_eq!(e["evaluation"]["family"], "evaluator", "{name}: {t}");
                assert!(finite(&best["speed_ratio"], "speed ratio") > 0.0);
            }
        }
        // The bake is documented bit-identical for any thread count.
        assert_eq!(f["speedup"]["identical"], true, "{name}");
        assert!(finite(&f["speedup"]["speedup"], "speedup") > 0.0);
    }

    let md = std::fs::read_to_string(out.join("REPORT.md")).unwrap();
    let default_label = format!("{} (default)", default_resonant());
    for needle in [
        "## Summary",
        "## Error against table size",
        "## Error against CPU cost",
        "## The resonant evaluator",
        default_label.as_str(),
        "winner vs best",
        "resonant against paper at equal error",
        "## Bake time",
        "## GPU",
        "linen_plain",
        "velvet",
        "error_vs_size.png",
    ] {
        assert!(md.contains(needle), "REPORT.md lacks {needle}");
    }

    // Series colours of the plots (src/report/plots/chart.rs): thread_frame blue, grid4d
    // red, the first unit with a report plan (paper mode) orange, the second (resonant)
    // brown.
    let blue = [31, 119, 180];
    let red = [214, 39, 40];
    let orange = [255, 127, 14];
    let brown = [140, 86, 75];
    check_png(&out.join("error_vs_size.png"), &[blue, red]);
    check_png(&out.join("error_vs_cost.png"), &[blue, red, orange, brown]);
    check_png(&out.join("bake_time.png"), &[blue]);
    let files: Vec<&str> = json["files"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f.as_str().unwrap())
        .collect();
    for file in [
        "error_vs_size.png",
        "error_vs_cost.png",
        "bake_time.png",
        "REPORT.md",
        "report.json",
    ] {
        assert!(files.contains(&file), "files lacks {file}");
        assert!(out.join(file).is_file(), "{file} not written");
    }
}

#[test]
fn every_unit_with_a_report_plan_is_measured_and_written_without_being_named() {
    let fabric = FabricSet::builtin().get("velvet").unwrap().clone();
    let quick = ReportConfig::quick(vec![fabric.clone()]);
    // The presets measure every spelling every plan names, and nothing else.
    let planned: Vec<String> = planned_units()
        .flat_map(|(_, plan)| plan.cpu(true).iter().map(|s| s.to_string()))
        .collect();
    assert_eq!(quick.evaluators, planned);
    // The cheapest spelling of every plan, on a tiny run.
    let spellings: Vec<String> = planned_units()
        .map(|(_, plan)| plan.cpu(true)[0].to_string())
        .collect();
    let config = ReportConfig {
        mode: "test".into(),
        error_pairs: 100,
        timing_pairs: 8,
        timing_samples: 1,
        min_sample_seconds: 0.0,
        resolutions: vec![(Layout::GRID4D, vec![4])],
        evaluators: spellings.clone(),
        bake_repetitions: 1,
        speedup_layout: Layout::GRID4D,
        speedup_resolution: 4,
        speedup_repetitions: 1,
        gpu: false,
        // The stock section has its own test (stock.rs).
        stock: None,
        ..quick
    };
    let out = out_dir().with_extension("units");
    let report = run(&config, &out, vec!["test".into()], &mut |_| {}).expect("report runs");
    let md = std::fs::read_to_string(out.join("REPORT.md")).unwrap();
    let measured: Vec<String> = report.fabrics[0]
        .model()
        .map(|p| p.evaluation.to_string())
        .collect();
    assert_eq!(measured, spellings);
    for ((unit, plan), spelling) in planned_units().zip(&spellings) {
        let point = report.fabrics[0]
            .of_unit(unit)
            .next()
            .unwrap_or_else(|| panic!("no point of {}", unit.name));
        assert_eq!(&point.evaluation.to_string(), spelling);
        assert!(point.error.uniform.relative_rms.is_finite(), "{spelling}");
        // The baseline is compared with nothing; every other unit with the baseline.
        assert_eq!(point.vs_baseline.is_none(), plan.baseline, "{spelling}");
        let row = format!("| velvet | {spelling}");
        assert!(md.contains(&row), "REPORT.md has no row {row:?}");
        if !plan.baseline {
            let heading = format!("## The {} evaluator", unit.name);
            assert!(md.contains(&heading), "REPORT.md lacks {heading:?}");
            assert!(
                md.contains(plan.setting),
                "REPORT.md lacks {}'s setting",
                unit.name
            );
        }
    }
    let _ = std::fs::remove_dir_all(&out);
}
