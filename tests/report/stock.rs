//! The stock section (`clothbake report --section stock`): every fabric by every export
//! target of the registry, with finite figures, beside the default table, merged into a
//! report.json, with its page and pictures written. One fabric and tiny tiles: the
//! registry's iteration is under test, not the fits.

use crate::run::check_png;
use clothbake::bake::job::{BakeJob, Outcome, ResolutionChoice, run};
use clothbake::export::TARGETS;
use clothbake::formats::fabric_toml::FabricSet;
use clothbake::model::Fabric;
use clothbake::report::plots::stock::{DRAPE_COLOUR, HIGHLIGHT_COLOUR, UNIFORM_COLOUR};
use clothbake::report::run_stock;
use clothbake::report::stock::StockConfig;
use clothbake::table::Layout;
use serde_json::Value;
use std::path::Path;

fn finite(v: &Value, what: &str) -> f64 {
    let x = v
        .as_f64()
        .unwrap_or_else(|| panic!("{what} is not a number: {v}"));
    assert!(x.is_finite() && x >= 0.0, "{what} = {x}");
    x
}

fn png_size(path: &Path) -> (u32, u32) {
    let decoder = png::Decoder::new(std::io::BufReader::new(
        std::fs::File::open(path).expect("picture exists"),
    ));
    let reader = decoder.read_info().expect("valid PNG");
    (reader.info().width, reader.info().height)
}

/// Bakes FABRIC's table at the smallest resolution of the default layout into DIR, as
/// `bake` writes it: a fresh clone has no baked tables, and the section's table row reads
/// the tables directory.
fn bake_small_table(fabric: &Fabric, dir: &Path) {
    let layout = Layout::DEFAULT;
    let job = BakeJob {
        fabrics: vec![fabric.clone()],
        layout,
        resolution: ResolutionChoice::Fixed(layout.resolution_ladder()[0]),
        out: dir.to_path_buf(),
        force: true,
        environment_samples: None,
    };
    let progress = |_: &str, _: u32, _: u64| -> Box<dyn Fn() + Sync> { Box::new(|| {}) };
    run(&job, &progress, &mut |_: &Fabric, _: &Outcome| {}).expect("the bake runs");
}

#[test]
fn stock_section_lists_every_fabric_by_every_target_and_merges_into_the_report() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("stock-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    std::fs::create_dir_all(&out).unwrap();
    // The committed report takes the section, as `--section stock` merges it into report/.
    std::fs::copy(root.join("report/report.json"), out.join("report.json")).unwrap();
    let fabric = FabricSet::builtin().get("velvet").unwrap().clone();
    let tables = out.join("tables");
    bake_small_table(&fabric, &tables);
    let config = StockConfig {
        tables,
        tile: 48,
        environment_samples: 4,
        grid: true,
    };
    let (section, merged) = run_stock(&config, &[fabric], &out, vec!["test".into()], &mut |l| {
        println!("{l}")
    })
    .expect("the section runs");
    assert!(merged, "report.json took the section");
    let targets: Vec<&str> = TARGETS.iter().map(|t| t.name).collect();
    assert_eq!(section.fabrics.len(), 1);

    let json: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap()).unwrap();
    let stock = &json["stock"];
    let fabrics = stock["fabrics"].as_array().expect("stock.fabrics");
    assert_eq!(fabrics.len(), 1);
    let names: Vec<&str> = stock["targets"]
        .as_array()
        .unwrap()
        .iter()
        .map(|t| t["name"].as_str().unwrap())
        .collect();
    assert_eq!(names, targets);
    let page = std::fs::read_to_string(out.join("stock.md")).unwrap();
    for f in fabrics {
        let name = f["name"].as_str().unwrap();
        let table = &f["table"];
        assert!(
            table.is_object(),
            "{name}: no table row: {}",
            stock["status"]
        );
        let table_error = finite(&table["uniform"], "table uniform")
            .max(finite(&table["highlight"], "table highlight"));
        let points = f["points"].as_array().unwrap();
        let listed: Vec<&str> = points
            .iter()
            .map(|p| p["target"].as_str().unwrap())
            .collect();
        assert_eq!(listed, targets, "{name}");
        for p in points {
            let what = format!("{name} {}", p["target"]);
            let worst = finite(&p["uniform"], &what).max(finite(&p["highlight"], &what));
            for key in [
                "albedo_rms_relative",
                "albedo_largest_relative",
                "image_relative_l2",
                "image_psnr_db",
            ] {
                finite(&p[key], &format!("{what} {key}"));
            }
            assert!(!p["parameters"].as_array().unwrap().is_empty(), "{what}");
            // A stock model is not the fabric: its error is above the table's.
            assert!(worst > table_error, "{what}: {worst} against {table_error}");
            let row = format!("| {name} | `{}`", p["target"].as_str().unwrap());
            assert!(page.contains(&row), "stock.md lacks {row:?}");
        }
        assert!(
            page.contains(&format!("- **{name}**: ")),
            "stock.md: {name}"
        );
    }
    let report_md = std::fs::read_to_string(out.join("REPORT.md")).unwrap();
    assert!(report_md.contains("## Every engine's stock model"));
    assert!(report_md.contains("](stock.md)"));
    let files: Vec<&str> = json["files"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f.as_str().unwrap())
        .collect();
    for file in ["stock.md", "stock_error.png", "stock_grid.png"] {
        assert!(files.contains(&file), "files lacks {file}");
    }
    let (width, height) = png_size(&out.join("stock_grid.png"));
    assert!(
        width >= (targets.len() as u32 + 1) * 48 && height >= 48,
        "{width}×{height}"
    );
    let series = [UNIFORM_COLOUR, HIGHLIGHT_COLOUR, DRAPE_COLOUR].map(|c| [c.0, c.1, c.2]);
    check_png(&out.join("stock_error.png"), &series);
    let _ = std::fs::remove_dir_all(&out);
}
