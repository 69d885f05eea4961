//! Tables of every registered layout: deterministic bakes, the EXR round trip, the f32 and
//! batch lookups against the f64 one; and damaged files rejected with an error, never a
//! panic. What one layout's lookup does with its own texels is tested in its module.

use crate::common::*;
use clothbake::bake::bake;
use clothbake::formats::table_exr::{TableFileError, read_table, write_table};
use clothbake::table::{Layout, Table};

fn small_table(name: &str, resolution: u32) -> Table {
    bake(&fabric(name), Layout::GRID4D, resolution, &|| {}).unwrap()
}

/// A resolution every layout accepts whose tables bake in a second or two.
const SMALL: u32 = 8;

#[test]
fn bake_is_identical_for_one_and_two_threads() {
    let pool = |n| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap()
    };
    let dir = temp_dir("determinism");
    // Velvet's thread 2 jumps; satin back has point masses on both threads, sloped segments
    // and a jump on thread 1.
    let layouts = Layout::ALL.iter().copied();
    for (layout, name) in
        layouts.flat_map(|l| ["velvet", "polyester_satin_charmeuse_back"].map(|name| (l, name)))
    {
        let fabric = fabric(name);
        let one = pool(1).install(|| bake(&fabric, layout, SMALL, &|| {}).unwrap());
        let two = pool(2).install(|| bake(&fabric, layout, SMALL, &|| {}).unwrap());
        assert_eq!(one, two, "{layout}");
        write_table(&dir.join("a.exr"), &one).unwrap();
        write_table(&dir.join("b.exr"), &two).unwrap();
        let bytes = |name: &str| std::fs::read(dir.join(name)).unwrap();
        assert_eq!(bytes("a.exr"), bytes("b.exr"), "{layout}");
    }
}

#[test]
fn exr_round_trip_keeps_texels_and_provenance() {
    let dir = temp_dir("roundtrip");
    let path = dir.join("satin.exr");
    for &layout in Layout::ALL {
        let fabric = fabric("polyester_satin_charmeuse");
        let table = bake(&fabric, layout, SMALL, &|| {}).unwrap();
        let hash = write_table(&path, &table).unwrap();
        let file = read_table(&path).unwrap();
        assert_eq!(file.table, table);
        assert_eq!(file.hash, hash);
    }
    let file = read_table(&path).unwrap();
    assert_eq!(file.table.fabric, fabric("polyester_satin_charmeuse"));
    assert_eq!(file.version, env!("CARGO_PKG_VERSION"));
    // No temporary file is left beside the table.
    let names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, ["satin.exr"]);
}

/// Every damaged variant gives an error naming the file, never a panic.
#[test]
fn damaged_files_are_rejected() {
    let table = small_table("linen_plain", 4);
    let dir = temp_dir("damaged");
    let good = dir.join("good.exr");
    write_table(&good, &table).unwrap();
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
    let (mut rejected, mut unchanged) = (0, 0);
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
            // A flip in bytes that decoding ignores (padding, an unused attribute) leaves a
            // valid file: accepted only if every texel and the provenance are unchanged.
            Ok(Ok(read)) => {
                assert!(label.contains("flipped"), "{label}: accepted");
                assert_eq!(read.table, table, "{label}: accepted with other contents");
                unchanged += 1;
            }
        }
    }
    println!(
        "{rejected} of {} damaged variants rejected, {unchanged} decode to the same table",
        variants.len()
    );
    assert!(rejected >= variants.len() / 2);
}

/// Single flipped bits anywhere in a table of every layout (seeded positions): each file is
/// rejected, or decodes to exactly the table that was written. Before the texel checksum, 10
/// of 1,000 such satin files loaded with other texels.
#[test]
fn single_bit_flips_never_load_other_texels() {
    for &layout in Layout::ALL {
        let table = bake(&fabric("polyester_satin_charmeuse"), layout, SMALL, &|| {}).unwrap();
        single_bit_flips_of(&table);
    }
}

fn single_bit_flips_of(table: &Table) {
    use rand::{Rng, SeedableRng};
    let layout = table.layout;
    let dir = temp_dir(&format!("bitflips-{layout}"));
    let good = dir.join("good.exr");
    write_table(&good, table).unwrap();
    let bytes = std::fs::read(&good).unwrap();
    let mut rng = rand_pcg::Pcg64::seed_from_u64(7);
    let (mut rejected, mut unchanged) = (0, 0);
    let path = dir.join("flipped.exr");
    for _ in 0..300 {
        let mut flipped = bytes.clone();
        let bit = rng.random_range(0..bytes.len() * 8);
        flipped[bit / 8] ^= 1 << (bit % 8);
        std::fs::write(&path, &flipped).unwrap();
        match read_table(&path) {
            Err(e) => {
                assert!(
                    e.to_string().contains("flipped.exr"),
                    "{layout} bit {bit}: {e}"
                );
                rejected += 1;
            }
            Ok(read) => {
                assert_eq!(&read.table, table, "{layout} bit {bit}: other contents");
                unchanged += 1;
            }
        }
    }
    println!(
        "{layout}: 300 single-bit flips: {rejected} rejected, {unchanged} decode to the same \
         table"
    );
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
            let mut attributes = LayerAttributes::named("grid4d");
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
    // Genuine provenance documents, taken from written tables, and edits of them: one of
    // a table whose texels are all 0.5, as the hand-written files hold, and one of a baked
    // table, whose texel checksum does not match those files.
    let provenance_of = |table: &Table| {
        let path = dir.join("written.exr");
        write_table(&path, table).unwrap();
        let meta = exr::meta::MetaData::read_from_file(&path, false).unwrap();
        match meta.headers[0]
            .own_attributes
            .other
            .get(&Text::from("clothbake"))
        {
            Some(AttributeValue::Text(t)) => t.to_string(),
            other => panic!("no provenance: {other:?}"),
        }
    };
    let baked = small_table("linen_plain", 4);
    let mut halves = baked.planes().to_vec();
    halves[0].data.fill(0.5);
    let provenance = provenance_of(&Table::new(Layout::GRID4D, 4, &baked.fabric, halves).unwrap());
    let baked_provenance = provenance_of(&baked);
    let ours = ["reflection", "transmission1", "transmission2"];
    // Hand-written files use the layer name the layout expects.
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
            "has channels",
        ),
        (
            write("size.exr", (16, 15), &ours, Some(provenance.clone())),
            "needs layer 'grid4d' of 16x16",
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
            write("texels.exr", (16, 16), &ours, Some(baked_provenance)),
            "the texels are damaged",
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
    let mut planes = small_table("linen_plain", 4).planes().to_vec();
    planes[0].data[7 * 3 + 1] = f32::NAN;
    let table = Table::new(Layout::GRID4D, 4, &fabric, planes).unwrap();
    let path = dir.join("nan.exr");
    write_table(&path, &table).unwrap();
    let message = read_table(&path).expect_err("NaN accepted").to_string();
    assert!(
        message.contains("texel (7, 0)") && message.contains("NaN"),
        "{message}"
    );
    assert!(matches!(
        read_table(&dir.join("missing.exr")),
        Err(TableFileError::Io { .. })
    ));
}

/// A header claiming an absurd data window is rejected before anything is sized by it.
#[test]
fn absurd_header_dimensions_are_rejected_without_allocating() {
    let dir = temp_dir("absurd");
    let path = dir.join("absurd.exr");
    write_table(&path, &small_table("velvet", 4)).unwrap();
    let mut bytes = std::fs::read(&path).unwrap();
    let key = b"dataWindow\0box2i\0";
    let at = bytes
        .windows(key.len())
        .position(|w| w == key)
        .expect("a dataWindow attribute")
        + key.len()
        + 4;
    for (offset, value) in [(8, 0x3fff_0000i32), (12, 0x3fff_0000i32)] {
        bytes[at + offset..at + offset + 4].copy_from_slice(&value.to_le_bytes());
    }
    std::fs::write(&path, &bytes).unwrap();
    let message = read_table(&path)
        .expect_err("absurd window accepted")
        .to_string();
    println!("{message}");
    assert!(message.contains("absurd.exr"), "{message}");
}

/// F below which the f32 lookup is compared in absolute rather than relative terms: the
/// dark pairs (F spans 1e-6 to 1e3 over the sets; split_frame's exact point masses keep the
/// narrow lobes' peaks, so a set's largest F is no scale for the rest).
const RELATIVE_FLOOR: f64 = 1e-4;

/// The f32 CPU lookup (fast atan2/asin, f32 arithmetic) against the f64 lookup of the same
/// table on the same f32 directions, for every fabric and every registered layout (at the
/// second rung of its resolution ladder): 20,000 uniform and 20,000 highlight pairs and the
/// curated hard cases. Also checks that the batch entry point gives the single lookups'
/// values exactly.
///
/// The bound: the approximations move an angle by at most 2e-5 rad, under 0.5% of the
/// narrowest texel (thread_frame's βH spacing at σs/3 = 0.83° for satin), so a lookup moves
/// by at most 0.5% of the largest texel difference around it; f32 sums of 16 corners add
/// ~1e-6 relative; split_frame's point masses go through the f32 sample kernel of
/// `src/table/point_samples.rs`, with the fast atan2 and exp. Pairs the layout declares
/// exempt (`TableLookup::f32_exempt`: a division f32 cannot resolve, such as the hard cases
/// exactly at the horizon, wi = −wo at elevation 1e-12 with ⟨P⟩ ≈ 1e-16, or wi = −wo grazing
/// along a thread beyond the end of the θd' axis) are only checked for finite, non-negative
/// values. Elsewhere the difference, relative to max(F, [`RELATIVE_FLOOR`]), is held to
/// 1e-3, a margin of 4× over the largest seen.
#[test]
fn f32_lookup_follows_the_f64_lookup() {
    let mut worst_overall = 0.0f64;
    for fabric in builtin() {
        let (mut pairs, _) = f32_validation_pairs(&fabric, 20_000, 0x5eed_0f32);
        for (f, hard, _) in f32_hard_cases_by_fabric() {
            if f.name == fabric.name {
                pairs.extend(hard);
            }
        }
        for &layout in Layout::ALL {
            let table = bake(&fabric, layout, layout.resolution_ladder()[1], &|| {}).unwrap();
            let reference: Vec<glam::DVec3> = pairs
                .iter()
                .map(|&(wi, wo)| table.lookup(wi.as_dvec3(), wo.as_dvec3()))
                .collect();
            let mut batch = vec![glam::Vec3::ZERO; pairs.len()];
            table.lookup_batch(&pairs, &mut batch);
            let (mut worst, mut worst_at) = (0.0f64, 0);
            let mut exempt = 0;
            for (k, (&(wi, wo), f64_value)) in pairs.iter().zip(&reference).enumerate() {
                let single = table.lookup_f32(wi, wo);
                assert_eq!(single, batch[k], "batch and single lookups differ");
                assert!(
                    single.is_finite() && single.min_element() >= 0.0,
                    "{single}"
                );
                if table.f32_exempt(wi.as_dvec3(), wo.as_dvec3()) {
                    exempt += 1;
                    continue;
                }
                let difference = (single.as_dvec3() - *f64_value).abs().max_element();
                let relative = difference / f64_value.max_element().max(RELATIVE_FLOOR);
                if relative > worst {
                    (worst, worst_at) = (relative, k);
                }
            }
            let (wi, wo) = pairs[worst_at];
            println!(
                "{:32} {layout:12} largest relative difference {worst:.2e} at wi {wi} wo {wo} \
                 (F {}); {exempt} pairs exempt",
                fabric.name, reference[worst_at]
            );
            worst_overall = worst_overall.max(worst);
        }
    }
    assert!(
        worst_overall <= 1e-3,
        "f32 lookup differs by {worst_overall:e}"
    );
}

/// The batch lookup on pairs whose lanes mix directions above, on and below the horizon,
/// for lengths that fill whole groups of eight lanes and leave remainders: every pair as
/// its single lookup (bit for bit), and 0 wherever a direction is not above the horizon
/// (the model's one-sided cloth), whatever the other lanes hold.
#[test]
fn batch_lookup_matches_single_lookups_across_lanes_and_the_horizon() {
    let fabric = builtin()
        .into_iter()
        .find(|f| f.name == "polyester_satin_charmeuse_back")
        .unwrap();
    let up = glam::Vec3::new(0.3, -0.4, 0.866).normalize();
    let directions = [
        up,
        glam::Vec3::new(-0.8, 0.1, 0.59).normalize(),
        glam::Vec3::new(0.6, 0.8, 0.0),
        glam::Vec3::new(0.2, 0.3, -0.93).normalize(),
        glam::Vec3::new(0.99, 0.0, 0.01).normalize(),
        glam::Vec3::new(-0.995, 0.05, 0.002).normalize(),
    ];
    let pairs: Vec<(glam::Vec3, glam::Vec3)> = (0..directions.len() * directions.len())
        .map(|k| (directions[k % 6], directions[(k / 6 + k) % 6]))
        .collect();
    for &layout in Layout::ALL {
        let table = bake(&fabric, layout, layout.resolution_ladder()[0], &|| {}).unwrap();
        for count in [8, 13, 16, 36] {
            let mut batch = vec![glam::Vec3::splat(-1.0); count];
            table.lookup_batch(&pairs[..count], &mut batch);
            for (k, &(wi, wo)) in pairs[..count].iter().enumerate() {
                assert_eq!(
                    batch[k],
                    table.lookup_f32(wi, wo),
                    "{layout} pair {k} of {count}"
                );
                if wi.z <= 0.0 || wo.z <= 0.0 {
                    assert_eq!(
                        batch[k],
                        glam::Vec3::ZERO,
                        "{layout} pair {k} below the horizon"
                    );
                } else {
                    assert!(batch[k].min_element() >= 0.0 && batch[k].is_finite());
                }
            }
        }
        let lit = pairs.iter().filter(|p| p.0.z > 0.0 && p.1.z > 0.0).count();
        println!(
            "{layout}: {} pairs, {lit} above the horizon, batch = single",
            pairs.len()
        );
    }
}
