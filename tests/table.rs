//! Tables: the CPU lookup against stored texels, deterministic bakes, the EXR round trip,
//! and damaged files rejected with an error, never a panic.

mod common;

use clothbake::bake::bake;
use clothbake::table::{Layout, Table};
use clothbake::table_file::{TableFileError, read_table, write_table};
use common::*;
use std::path::PathBuf;

fn temp_dir(label: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("clothbake-{label}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn small_table(name: &str, resolution: u32) -> Table {
    bake(&fabric(name), Layout::Grid4d, resolution, &|| {}).unwrap()
}

#[test]
fn lookup_reproduces_texels_at_centres_and_interpolates_between() {
    let table = small_table("silk_shot", 6);
    let (width, height) = table.image_size();
    for y in 0..height {
        for x in 0..width {
            let (wi, wo) = Layout::Grid4d.texel_directions(6, x, y);
            let got = table.lookup_terms(wi, wo);
            let stored = table.texel(x, y);
            for c in 0..3 {
                // Centres map back to themselves up to the octahedral round trip (1e-15).
                assert!(
                    (got[c] - stored[c] as f64).abs() <= 1e-9 * (stored[c] as f64).max(1e-6),
                    "({x},{y}) {got:?} {stored:?}"
                );
            }
        }
    }
    // Halfway between two wo texel centres along one axis, the lookup is their mean.
    let (wi, wo_a) = Layout::Grid4d.texel_directions(6, 2 * 6 + 1, 3 * 6 + 4);
    let (_, wo_b) = Layout::Grid4d.texel_directions(6, 2 * 6 + 2, 3 * 6 + 4);
    let uv = (clothbake::table::octahedral::encode(wo_a)
        + clothbake::table::octahedral::encode(wo_b))
        * 0.5;
    let mid = table.lookup_terms(wi, clothbake::table::octahedral::decode(uv));
    let (a, b) = (table.texel(13, 22), table.texel(14, 22));
    for c in 0..3 {
        let expected = 0.5 * (a[c] as f64 + b[c] as f64);
        assert!(
            (mid[c] - expected).abs() <= 1e-9 * expected.max(1e-6),
            "{mid:?} vs {a:?} {b:?}"
        );
    }
}

#[test]
fn bake_is_identical_for_one_and_two_threads() {
    let pool = |n| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap()
    };
    let fabric = fabric("velvet");
    let one = pool(1).install(|| bake(&fabric, Layout::Grid4d, 5, &|| {}).unwrap());
    let two = pool(2).install(|| bake(&fabric, Layout::Grid4d, 5, &|| {}).unwrap());
    assert_eq!(one, two);
    let dir = temp_dir("determinism");
    write_table(&dir.join("a.exr"), &one, &fabric).unwrap();
    write_table(&dir.join("b.exr"), &two, &fabric).unwrap();
    assert_eq!(
        std::fs::read(dir.join("a.exr")).unwrap(),
        std::fs::read(dir.join("b.exr")).unwrap()
    );
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn exr_round_trip_keeps_texels_and_provenance() {
    let table = small_table("polyester_satin_charmeuse", 4);
    let fabric = fabric("polyester_satin_charmeuse");
    let dir = temp_dir("roundtrip");
    let path = dir.join("satin.exr");
    let hash = write_table(&path, &table, &fabric).unwrap();
    let file = read_table(&path).unwrap();
    assert_eq!(file.table, table);
    assert_eq!(file.fabric, fabric);
    assert_eq!(file.hash, hash);
    assert_eq!(file.version, env!("CARGO_PKG_VERSION"));
    // No temporary file is left beside the table.
    let names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, ["satin.exr"]);
    std::fs::remove_dir_all(dir).unwrap();
}

/// Every damaged variant gives an error naming the file, never a panic.
#[test]
fn damaged_files_are_rejected() {
    let fabric = fabric("linen_plain");
    let table = small_table("linen_plain", 4);
    let dir = temp_dir("damaged");
    let good = dir.join("good.exr");
    write_table(&good, &table, &fabric).unwrap();
    let bytes = std::fs::read(&good).unwrap();
    let mut variants: Vec<(String, Vec<u8>)> = vec![
        ("empty".into(), vec![]),
        ("not exr".into(), b"hello, world".to_vec()),
        ("header only".into(), bytes[..bytes.len().min(300)].to_vec()),
    ];
    for cut in [bytes.len() / 2, bytes.len() - 1] {
        variants.push((format!("truncated at {cut}"), bytes[..cut].to_vec()));
    }
    for step in (0..bytes.len()).step_by(bytes.len() / 97 + 1) {
        let mut flipped = bytes.clone();
        flipped[step] ^= 0x5a;
        variants.push((format!("byte {step} flipped"), flipped));
    }
    let mut rejected = 0;
    for (label, data) in &variants {
        let path = dir.join("bad.exr");
        std::fs::write(&path, data).unwrap();
        let result = std::panic::catch_unwind(|| read_table(&path));
        match result {
            Err(_) => panic!("{label}: panicked"),
            Ok(Err(e)) => {
                assert!(e.to_string().contains("bad.exr"), "{label}: {e}");
                rejected += 1;
            }
            // A flip inside compressed texels can decode to other finite values; the file
            // is then a valid table with different data, which only a checksum of the
            // texels could catch.
            Ok(Ok(_)) => assert!(label.contains("flipped"), "{label}: accepted"),
        }
    }
    println!("{rejected} of {} damaged variants rejected", variants.len());
    assert!(rejected >= variants.len() / 2);
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn wrong_channels_dimensions_attributes_and_nan_texels_are_rejected() {
    use exr::prelude::*;
    let dir = temp_dir("wrongexr");
    let write =
        |name: &str, size: (usize, usize), channels: &[&str], provenance: Option<String>| {
            let list: Vec<AnyChannel<FlatSamples>> = channels
                .iter()
                .map(|c| {
                    AnyChannel::new(
                        *c,
                        FlatSamples::F16(vec![half::f16::from_f32(0.5); size.0 * size.1]),
                    )
                })
                .collect();
            let mut attributes = LayerAttributes::named("clothbake");
            if let Some(text) = provenance {
                attributes.other.insert(
                    Text::from("clothbake"),
                    AttributeValue::Text(Text::from(text.as_str())),
                );
            }
            let layer = Layer::new(
                size,
                attributes,
                Encoding::UNCOMPRESSED,
                AnyChannels::sort(list.into()),
            );
            let path = dir.join(name);
            Image::from_layer(layer).write().to_file(&path).unwrap();
            path
        };
    // A genuine provenance document, taken from a baked table, and edits of it.
    let baked = dir.join("baked.exr");
    write_table(
        &baked,
        &small_table("linen_plain", 4),
        &fabric("linen_plain"),
    )
    .unwrap();
    let meta = exr::meta::MetaData::read_from_file(&baked, false).unwrap();
    let provenance = match meta.headers[0]
        .own_attributes
        .other
        .get(&Text::from("clothbake"))
    {
        Some(AttributeValue::Text(t)) => t.to_string(),
        other => panic!("no provenance: {other:?}"),
    };
    let ours = ["reflection", "transmission1", "transmission2"];
    let cases = [
        (
            write("valid.exr", (16, 16), &ours, Some(provenance.clone())),
            "",
        ),
        (
            write(
                "channels.exr",
                (16, 16),
                &["R", "G", "B"],
                Some(provenance.clone()),
            ),
            "channels are",
        ),
        (
            write("size.exr", (16, 15), &ours, Some(provenance.clone())),
            "needs 16x16",
        ),
        (
            write(
                "absurd.exr",
                (16, 16),
                &ours,
                Some(provenance.replace("resolution = 4", "resolution = 4000000000")),
            ),
            "does not match",
        ),
        (
            write("none.exr", (16, 16), &ours, None),
            "lacks the text attribute 'clothbake'",
        ),
        (
            write(
                "hash.exr",
                (16, 16),
                &ours,
                Some(provenance.replace("kd = 0.3", "kd = 0.4")),
            ),
            "does not match",
        ),
        (
            write(
                "garbage.exr",
                (16, 16),
                &ours,
                Some("resolution = [".into()),
            ),
            "is not valid",
        ),
    ];
    for (path, expected) in cases {
        if expected.is_empty() {
            read_table(&path).expect("a well-formed table written by hand loads");
            continue;
        }
        let message = match read_table(&path) {
            Err(e) => e.to_string(),
            Ok(_) => panic!("{} accepted", path.display()),
        };
        assert!(message.contains(expected), "{}: {message}", path.display());
    }
    // NaN texels in an otherwise valid file: write a real table, then patch its texels.
    let fabric = fabric("linen_plain");
    let mut texels = small_table("linen_plain", 4).texels().to_vec();
    texels[7][1] = f32::NAN;
    let table = Table::new(Layout::Grid4d, 4, [[0.0; 3]; 2], texels);
    let path = dir.join("nan.exr");
    write_table(&path, &table, &fabric).unwrap();
    let message = read_table(&path).expect_err("NaN accepted").to_string();
    assert!(
        message.contains("texel (7, 0)") && message.contains("NaN"),
        "{message}"
    );
    assert!(matches!(
        read_table(&dir.join("missing.exr")),
        Err(TableFileError::Io { .. })
    ));
    std::fs::remove_dir_all(dir).unwrap();
}
