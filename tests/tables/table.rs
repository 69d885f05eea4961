//! Tables: the CPU lookup against stored texels, deterministic bakes, the EXR round trip,
//! and damaged files rejected with an error, never a panic.

use crate::common::*;
use clothbake::bake::bake;
use clothbake::formats::table_exr::{TableFileError, read_table, write_table};
use clothbake::table::{Layout, Table, grid4d, split_frame, thread_frame};

fn small_table(name: &str, resolution: u32) -> Table {
    bake(&fabric(name), Layout::GRID4D, resolution, &|| {}).unwrap()
}

/// A thread_frame table at its smallest useful resolution (a few seconds to bake).
fn small_thread_frame(name: &str) -> Table {
    bake(&fabric(name), Layout::THREAD_FRAME, 8, &|| {}).unwrap()
}

#[test]
fn grid4d_lookup_reproduces_texels_at_centres_and_interpolates_between() {
    let table = small_table("silk_shot", 6);
    let plane = &table.planes()[0];
    for y in 0..plane.spec.height {
        for x in 0..plane.spec.width {
            let (wi, wo) = grid4d::texel_directions(6, x, y);
            let got = table.lookup_terms(wi, wo);
            let stored = plane.texel(x, y);
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
    let (wi, wo_a) = grid4d::texel_directions(6, 2 * 6 + 1, 3 * 6 + 4);
    let (_, wo_b) = grid4d::texel_directions(6, 2 * 6 + 2, 3 * 6 + 4);
    let uv = (clothbake::table::octahedral::encode(wo_a)
        + clothbake::table::octahedral::encode(wo_b))
        * 0.5;
    let mid = table.lookup_terms(wi, clothbake::table::octahedral::decode(uv));
    let (a, b) = (plane.texel(13, 22), plane.texel(14, 22));
    for c in 0..3 {
        let expected = 0.5 * (a[c] as f64 + b[c] as f64);
        assert!(
            (mid[c] - expected).abs() <= 1e-9 * expected.max(1e-6),
            "{mid:?} vs {a:?} {b:?}"
        );
    }
}

/// At a texel's own coordinates the thread_frame lookup returns that texel's stored
/// channels, and halfway between two texels along an axis their mean.
#[test]
fn thread_frame_lookup_reproduces_texels_at_their_coordinates() {
    let table = small_thread_frame("linen_plain");
    let Some(geometry) = table.geometry_as::<thread_frame::Geometry>() else {
        panic!("not thread_frame")
    };
    let planes = table.planes();
    for j in 0..2 {
        let thread = &geometry.threads[j];
        let n = thread.axes.map(|a| a.texels);
        let mut checked = 0;
        let all = (0..n[0]).flat_map(|i0| {
            (0..n[1]).flat_map(move |i1| {
                (0..n[2]).flat_map(move |i2| (0..n[3]).map(move |i3| [i0, i1, i2, i3]))
            })
        });
        for index in all {
            let coordinates = [0, 1, 2, 3].map(|a| thread.axes[a].texel_value(index[a]));
            let (wi, wo) = thread.directions(coordinates);
            // Texels below the horizon extend the function; only pairs above it are
            // looked up (and only there is the coordinate map invertible).
            if wi.z <= 1e-3 || wo.z <= 1e-3 {
                continue;
            }
            let stored = &planes[j].data[thread.texel_index(index) * 2..][..2];
            let [r, t, _, _] = geometry.sample_thread(planes, j, wi, wo);
            for (got, want) in [(r, stored[0]), (t, stored[1])] {
                assert!(
                    (got - want as f64).abs() <= 1e-6 * (want as f64).abs().max(1e-3),
                    "thread {j} {index:?}: {got} vs {want}"
                );
            }
            // Halfway along v (a linear axis) between this texel and the next.
            if index[3] + 1 == n[3] {
                continue;
            }
            let next = [index[0], index[1], index[2], index[3] + 1];
            let mut halfway = coordinates;
            halfway[3] = 0.5 * (coordinates[3] + thread.axes[3].texel_value(index[3] + 1));
            let (wi, wo) = thread.directions(halfway);
            if wi.z <= 1e-3 || wo.z <= 1e-3 {
                continue;
            }
            let following = &planes[j].data[thread.texel_index(next) * 2..][..2];
            let [r, t, _, _] = geometry.sample_thread(planes, j, wi, wo);
            for (got, a, b) in [(r, stored[0], following[0]), (t, stored[1], following[1])] {
                let want = 0.5 * (a as f64 + b as f64);
                assert!(
                    (got - want).abs() <= 1e-6 * want.abs().max(1e-3),
                    "thread {j} {index:?} halfway: {got} vs {want}"
                );
            }
            checked += 1;
        }
        assert!(
            checked > 100,
            "thread {j}: only {checked} texels above the horizon"
        );
    }
}

/// The fold (u, v) → (−u, −v) (the exact b → −b symmetry of every tangent sample) glues the
/// table's u = 0 slice to itself with v → −v: a lookup just below u = 0 reads the slice at −v.
/// The slice must therefore be symmetric in v, or F jumps across the fold. Baked texels are
/// symmetric up to rounding; the filled ones (⟨P⟩ below the floor) must be too.
#[test]
fn thread_frame_u0_slice_is_symmetric_in_v() {
    for name in ["polyester_satin_charmeuse", "linen_plain"] {
        let table = bake(&fabric(name), Layout::THREAD_FRAME, 12, &|| {}).unwrap();
        let Some(geometry) = table.geometry_as::<thread_frame::Geometry>() else {
            panic!("not thread_frame")
        };
        for j in 0..2 {
            let thread = &geometry.threads[j];
            let n = thread.axes.map(|a| a.texels);
            let data = &table.planes()[j].data;
            let mut worst = 0.0f64;
            for i0 in 0..n[0] {
                for i1 in 0..n[1] {
                    for i3 in 0..n[3] {
                        let a = thread.texel_index([i0, i1, 0, i3]) * 2;
                        let b = thread.texel_index([i0, i1, 0, n[3] - 1 - i3]) * 2;
                        for c in 0..2 {
                            let (x, y) = (data[a + c] as f64, data[b + c] as f64);
                            worst = worst.max((x - y).abs() / x.abs().max(y.abs()).max(1e-3));
                        }
                    }
                }
            }
            // f16 storage: symmetric values round identically, so any difference beyond
            // one f16 step (2^-11 relative) is a real asymmetry.
            assert!(
                worst <= 1e-3,
                "{name} thread {j}: u = 0 slice asymmetric by {worst:.2e}"
            );
            eprintln!("{name} thread {j}: u = 0 slice symmetric to {worst:.1e}");
        }
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
    let dir = temp_dir("determinism");
    for (layout, resolution, name) in [
        (Layout::GRID4D, 5, "velvet"),
        (Layout::THREAD_FRAME, 8, "velvet"),
        // Point masses on both threads, sloped segments and a jump on thread 1.
        (Layout::SPLIT_FRAME, 8, "polyester_satin_charmeuse_back"),
    ] {
        let fabric = fabric(name);
        let one = pool(1).install(|| bake(&fabric, layout, resolution, &|| {}).unwrap());
        let two = pool(2).install(|| bake(&fabric, layout, resolution, &|| {}).unwrap());
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
    for table in [
        small_table("polyester_satin_charmeuse", 4),
        small_thread_frame("polyester_satin_charmeuse"),
    ] {
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

/// Single flipped bits anywhere in a thread_frame table (seeded positions): each file is
/// rejected, or decodes to exactly the table that was written. Before the texel checksum, 10
/// of 1,000 such satin files loaded with other texels.
#[test]
fn single_bit_flips_never_load_other_texels() {
    use rand::{Rng, SeedableRng};
    let table = small_thread_frame("polyester_satin_charmeuse");
    let dir = temp_dir("bitflips");
    let good = dir.join("good.exr");
    write_table(&good, &table).unwrap();
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
                assert!(e.to_string().contains("flipped.exr"), "bit {bit}: {e}");
                rejected += 1;
            }
            Ok(read) => {
                assert_eq!(read.table, table, "bit {bit}: loaded with other contents");
                unchanged += 1;
            }
        }
    }
    println!("300 single-bit flips: {rejected} rejected, {unchanged} decode to the same table");
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

/// Whether a pair is one the f32 lookup is not held to (see the test below): Q positive but
/// below 1e-6, or a tabulated thread beyond the end of its θd' axis.
fn degenerate_for_f32(table: &Table, wi: glam::DVec3, wo: glam::DVec3) -> bool {
    let planes = table.planes();
    let (q, beyond_theta_axis) =
        if let Some(geometry) = table.geometry_as::<thread_frame::Geometry>() {
            let samples = [0, 1].map(|j| geometry.sample_thread(planes, j, wi, wo));
            (
                geometry.gap * wo.z
                    + (0..2)
                        .map(|j| geometry.coverage[j] * samples[j][2])
                        .sum::<f64>(),
                samples.iter().any(|s| s[3] < 1e-8),
            )
        } else if let Some(geometry) = table.geometry_as::<split_frame::Geometry>() {
            let q = geometry.gap * wo.z
                + (0..2)
                    .map(|j| geometry.coverage[j] * geometry.thread_sums(planes, j, wi, wo)[2])
                    .sum::<f64>();
            let beyond = geometry.tabulated().any(|(j, slopes)| {
                let (t, m) = geometry.plane_indices(j).expect("tabulated");
                slopes.geometry.sample(&planes[t], &planes[m], wi, wo)[3] < 1e-8
            });
            (q, beyond)
        } else {
            return false;
        };
    (q > 0.0 && q < 1e-6) || beyond_theta_axis
}

/// The f32 CPU lookup (fast atan2/asin, f32 arithmetic) against the f64 lookup of the same
/// table on the same f32 directions, for every fabric and layout: 20,000 uniform and 20,000
/// highlight pairs and the curated hard cases. Also checks that the batch entry point gives
/// the single lookups' values exactly.
///
/// The bound: the approximations move an angle by at most 2e-5 rad, under 0.5% of the
/// narrowest texel (thread_frame's βH spacing at σs/3 = 0.83° for satin), so a lookup moves
/// by at most 0.5% of the largest texel difference around it; f32 sums of 16 corners add
/// ~1e-6 relative. Pairs whose normalisation Q (f64) is positive but below 1e-6 are only
/// checked for finite, non-negative values: there F is a 0/0 limit (hard cases exactly at
/// the horizon, e.g. wi = −wo at elevation 1e-12 with ⟨P⟩ ≈ 1e-16) that f32 weights cannot
/// resolve, and f32 returns the model's value for Q = 0, namely 0. So are pairs beyond the
/// end of the θd' axis (|θd'| > 90° − 1e-4 rad, cos²θd' < 1e-8: wi = −wo grazing along a
/// thread), where both lookups divide a clamped texel by the 1e-8 floor of cos²θd' and
/// any rounding of the tiny stored reflection is amplified 1e8 times. Measured largest
/// difference elsewhere, relative to max(F, [`RELATIVE_FLOOR`]): 2.5e-4 (silk_shot,
/// thread_frame R = 24), split_frame ≤ 1.2e-4 (its point masses by the f32 sample kernel
/// of `src/table/point_samples.rs`, with the fast atan2 and exp, against the f64 model),
/// grid4d 6e-6–1.8e-4; the bound 1e-3 keeps a margin of 4×.
/// F below which the f32 lookup is compared in absolute rather than relative terms: the
/// dark pairs (F spans 1e-6 to 1e3 over the sets; split_frame's exact point masses keep the
/// narrow lobes' peaks, so a set's largest F is no scale for the rest).
const RELATIVE_FLOOR: f64 = 1e-4;

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
        for (layout, resolution) in [
            (Layout::THREAD_FRAME, 24),
            (Layout::SPLIT_FRAME, 16),
            (Layout::GRID4D, 12),
        ] {
            let table = bake(&fabric, layout, resolution, &|| {}).unwrap();
            let reference: Vec<glam::DVec3> = pairs
                .iter()
                .map(|&(wi, wo)| table.lookup(wi.as_dvec3(), wo.as_dvec3()))
                .collect();
            let mut batch = vec![glam::Vec3::ZERO; pairs.len()];
            table.lookup_batch(&pairs, &mut batch);
            let (mut worst, mut worst_at) = (0.0f64, 0);
            let mut degenerate = 0;
            for (k, (&(wi, wo), f64_value)) in pairs.iter().zip(&reference).enumerate() {
                let single = table.lookup_f32(wi, wo);
                assert_eq!(single, batch[k], "batch and single lookups differ");
                assert!(
                    single.is_finite() && single.min_element() >= 0.0,
                    "{single}"
                );
                if degenerate_for_f32(&table, wi.as_dvec3(), wo.as_dvec3()) {
                    degenerate += 1;
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
                 (F {}); {degenerate} pairs with 0 < Q < 1e-6 or cos²θd' < 1e-8",
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
    for (layout, resolution) in [
        (Layout::THREAD_FRAME, 16),
        (Layout::SPLIT_FRAME, 16),
        (Layout::GRID4D, 8),
    ] {
        let table = bake(&fabric, layout, resolution, &|| {}).unwrap();
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
