//! Table accuracy against the direct evaluation, for all six fabrics: the default layout
//! (split_frame) at its default resolution (what `clothbake bake` writes) and at 20, and
//! thread_frame 48, kept for comparison.
//!
//! The bounds are set from measurement. A relative RMS over a few thousand pairs is
//! dominated by a handful of pairs within a degree of the horizon, so it moves between
//! seeds (thread_frame 48, satin, highlight pairs: 2.19% on 2,000 pairs, 3.07% on `clothbake
//! check`'s 20,000). Each bound is the measurement plus 20%.

use crate::common::*;
use clothbake::bake::bake;
use clothbake::measure::direction_sets::{highlight_pairs, uniform_pairs};
use clothbake::model::{Integration, Patch};
use clothbake::table::Layout;
use glam::DVec3;
use rayon::prelude::*;

/// (fabric, uniform bound, highlight bound), relative RMS. Measured at baker revision 5,
/// which revision 6 matches to every printed digit (the report at 9509d01); uniform: this
/// test's 2,000 pairs, f64 lookup / `clothbake check`'s 20,000, f32 lookup; then highlight
/// the same: linen 0.29 / 0.30%, 0.29 / 0.27%; crepe 0.77 / 0.97%, 1.05 /
/// 0.85%; satin 0.93 / 1.47%, 2.19 / 3.07%; satin back 0.83 / 0.88%, 0.82 / 1.61%;
/// silk_shot 0.96 / 0.94%, 0.74 / 1.39%; velvet 0.43 / 0.62%, 0.60 / 0.65% (at revision 7,
/// whose βH axis puts velvet's texels on its ridges: 0.61% and 0.65% on 20,000 pairs).
const BOUNDS: [(&str, f64, f64); 6] = [
    ("linen_plain", 0.0036, 0.0035),
    ("silk_crepe_de_chine", 0.0116, 0.0126),
    ("polyester_satin_charmeuse", 0.0176, 0.0369),
    ("polyester_satin_charmeuse_back", 0.0105, 0.0193),
    ("silk_shot", 0.0115, 0.0166),
    ("velvet", 0.0074, 0.0078),
];
/// Both directions at least 15° above the horizon: measured 0.21–0.96% (this test's pairs).
const ABOVE_15_BOUND: f64 = 0.0115;

#[test]
fn thread_frame_tables_meet_their_measured_error() {
    let layout = Layout::THREAD_FRAME;
    for (name, uniform_bound, highlight_bound) in BOUNDS {
        let fabric = fabric(name);
        let table = bake(&fabric, layout, layout.default_resolution(), &|| {}).unwrap();
        let direct = Patch::new(&fabric, Integration::Direct);
        let compare = |pairs: Vec<(DVec3, DVec3)>| -> (Vec<DVec3>, Vec<DVec3>, Vec<bool>) {
            let above = 15f64.to_radians().sin();
            let rows: Vec<(DVec3, DVec3, bool)> = pairs
                .par_iter()
                .map(|&(wi, wo)| {
                    (
                        table.lookup(wi, wo),
                        direct.eval(wi, wo),
                        wi.z >= above && wo.z >= above,
                    )
                })
                .collect();
            (
                rows.iter().map(|r| r.0).collect(),
                rows.iter().map(|r| r.1).collect(),
                rows.iter().map(|r| r.2).collect(),
            )
        };
        let (ut, ud, high) = compare(uniform_pairs(2000, 101));
        let (ht, hd, _) = compare(highlight_pairs(&fabric, 2000, 102));
        let pick = |v: &[DVec3]| -> Vec<DVec3> {
            v.iter()
                .zip(&high)
                .filter(|(_, h)| **h)
                .map(|(x, _)| *x)
                .collect()
        };
        let (uniform, highlight) = (relative_rms(&ut, &ud), relative_rms(&ht, &hd));
        let above = relative_rms(&pick(&ut), &pick(&ud));
        println!(
            "{name}: {} KiB, relative RMS {:.2}% uniform, {:.2}% highlight, {:.2}% above 15°",
            table.byte_size() / 1024,
            100.0 * uniform,
            100.0 * highlight,
            100.0 * above
        );
        assert!(
            table.byte_size() <= 16 << 20,
            "{name}: {} bytes",
            table.byte_size()
        );
        assert!(uniform <= uniform_bound, "{name}: uniform {uniform}");
        assert!(
            highlight <= highlight_bound,
            "{name}: highlight {highlight}"
        );
        assert!(above <= ABOVE_15_BOUND, "{name}: above 15° {above}");
    }
}

/// split_frame at its default resolution (31) and at 20: per fabric, (uniform, highlight,
/// highlight with both directions ≥ 1° above the horizon) bounds on the relative RMS of the
/// f32 lookup on 20,000 pairs per set (the measurement size; fewer pairs move
/// satin's figures by ±0.5%), each the measurement plus 20%. Measured (`clothbake check`,
/// same seeds, baker revision 8), the lookup reading the table for every pair: at 31
/// (2.0–3.6 MiB) linen 0.60 / 0.73 / 0.58%, crepe 0.22 / 0.18 / 0.17%, satin 0.40 / 0.49 /
/// 0.34%, satin back 0.29 / 0.40 / 0.24%, silk_shot 0.36 / 0.38 / 0.32%, velvet 0.83 / 0.82
/// / 0.76%; at 20 (558–1014 KiB) linen 1.21 / 1.12 / 1.01%, crepe 0.56 / 0.58 / 0.47%, satin
/// 1.19 / 1.29 / 0.83%, satin back 0.66 / 0.85 / 0.60%, silk_shot 0.90 / 0.99 / 0.85%, velvet
/// 1.78 / 1.83 / 1.68%.
const SPLIT_FRAME_BOUNDS: [(&str, [[f64; 3]; 2]); 6] = [
    (
        "linen_plain",
        [[0.0072, 0.0088, 0.0070], [0.0145, 0.0135, 0.0121]],
    ),
    (
        "silk_crepe_de_chine",
        [[0.0027, 0.0022, 0.0021], [0.0067, 0.0069, 0.0056]],
    ),
    (
        "polyester_satin_charmeuse",
        [[0.0047, 0.0058, 0.0040], [0.0143, 0.0154, 0.0099]],
    ),
    (
        "polyester_satin_charmeuse_back",
        [[0.0035, 0.0047, 0.0029], [0.0079, 0.0102, 0.0072]],
    ),
    (
        "silk_shot",
        [[0.0043, 0.0046, 0.0039], [0.0107, 0.0119, 0.0102]],
    ),
    (
        "velvet",
        [[0.0100, 0.0098, 0.0091], [0.0214, 0.0220, 0.0202]],
    ),
];
/// The resolutions of [`SPLIT_FRAME_BOUNDS`], the largest table each may be and the error
/// the issue "One default table that wins everywhere" asks of uniform and highlight pairs
/// at that size: ≤ 1% within 4 MiB, ≤ 2% within 1 MiB.
const SPLIT_FRAME_TARGETS: [(u32, usize, f64); 2] = [(31, 4 << 20, 0.01), (20, 1 << 20, 0.02)];

#[test]
fn split_frame_tables_meet_their_measured_error() {
    let layout = Layout::SPLIT_FRAME;
    for (name, bounds) in SPLIT_FRAME_BOUNDS {
        let fabric = fabric(name);
        let reference = clothbake::measure::accuracy::Reference::new(&fabric, 20_000);
        for ((resolution, max_bytes, target), [uniform, highlight, above_1]) in
            SPLIT_FRAME_TARGETS.into_iter().zip(bounds)
        {
            let table = bake(&fabric, layout, resolution, &|| {}).unwrap();
            let error = reference
                .measure(|wi, wo| clothbake::measure::accuracy::lookup_f32(&table, wi, wo));
            println!(
                "{name}: split_frame {resolution} {} KiB, relative RMS {:.2}% uniform, \
                 {:.2}% highlight, {:.2}% highlight ≥ 1°",
                table.byte_size() / 1024,
                100.0 * error.uniform.relative_rms,
                100.0 * error.highlight.relative_rms,
                100.0 * error.highlight_above_1deg.relative_rms,
            );
            assert!(
                table.byte_size() <= max_bytes,
                "{name}: {} bytes",
                table.byte_size()
            );
            assert!(
                error.uniform.relative_rms <= uniform.min(target),
                "{name} {resolution}: {error:?}"
            );
            assert!(
                error.highlight.relative_rms <= highlight.min(target),
                "{name} {resolution}: {error:?}"
            );
            assert!(
                error.highlight_above_1deg.relative_rms <= above_1,
                "{name} {resolution}: {error:?}"
            );
        }
    }
}
