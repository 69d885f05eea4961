//! Table accuracy against the direct evaluation, for all six fabrics at the default layout
//! and resolution (what `clothbake bake` writes).
//!
//! The bounds are set from measurement. A relative RMS over a few thousand pairs is
//! dominated by a handful of pairs within a degree of the horizon, so it moves between
//! seeds (satin, highlight pairs: 3.1% on `clothbake check`'s 4,000, 6.4% on this test's
//! 2,000, two or three pairs 0.1–0.3° above the horizon carrying most of it). Each bound is
//! the larger of the two measurements plus 20%. Five fabrics meet the baker's 2% goal on
//! both sets; satin's highlight pairs do not (README, "Tables").

mod common;

use clothbake::bake::bake;
use clothbake::direction_sets::{highlight_pairs, uniform_pairs};
use clothbake::model::{Integration, Patch};
use clothbake::table::Layout;
use common::*;
use glam::DVec3;
use rayon::prelude::*;

/// (fabric, uniform bound, highlight bound), relative RMS.
const BOUNDS: [(&str, f64, f64); 6] = [
    ("linen_plain", 0.0066, 0.0063),
    ("silk_crepe_de_chine", 0.0193, 0.0157),
    ("polyester_satin_charmeuse", 0.0232, 0.077),
    ("polyester_satin_charmeuse_back", 0.0239, 0.0208),
    ("silk_shot", 0.015, 0.0175),
    ("velvet", 0.0229, 0.0201),
];
/// Both directions at least 15° above the horizon: measured 0.38–1.2%.
const ABOVE_15_BOUND: f64 = 0.0146;

#[test]
fn default_tables_meet_their_measured_error() {
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

/// split_frame at its default resolution (32): (fabric, uniform, highlight, highlight with
/// both directions ≥ 1° above the horizon) bounds, relative RMS of the f32 lookup on 20,000
/// pairs per set (the measurement size; fewer pairs move satin's figures by ±0.5%).
/// Measured (`clothbake check`, same seeds): linen 0.92 / 1.06 / 0.89%, crepe 0.42 / 0.42 /
/// 0.31%, satin 0.72 / 1.20 / 0.76%, satin back 0.48 / 2.19 / 0.42%, silk_shot 0.65 /
/// 1.35 / 0.62%, velvet 1.96 / 1.88 / 1.76%; each bound is the measurement plus 20%.
/// Satin back's highlight figure is one pair at elevation 0.00° (README, "Tables").
const SPLIT_FRAME_BOUNDS: [(&str, f64, f64, f64); 6] = [
    ("linen_plain", 0.0110, 0.0128, 0.0107),
    ("silk_crepe_de_chine", 0.0051, 0.0051, 0.0038),
    ("polyester_satin_charmeuse", 0.0087, 0.0144, 0.0092),
    ("polyester_satin_charmeuse_back", 0.0058, 0.0263, 0.0051),
    ("silk_shot", 0.0078, 0.0163, 0.0075),
    ("velvet", 0.0236, 0.0226, 0.0212),
];

#[test]
fn split_frame_tables_meet_their_measured_error() {
    let layout = Layout::SPLIT_FRAME;
    for (name, uniform_bound, highlight_bound, above_1_bound) in SPLIT_FRAME_BOUNDS {
        let fabric = fabric(name);
        let table = bake(&fabric, layout, layout.default_resolution(), &|| {}).unwrap();
        let error = clothbake::accuracy::measure(&table, &fabric, 20_000);
        println!(
            "{name}: split_frame {} KiB, relative RMS {:.2}% uniform, {:.2}% highlight, \
             {:.2}% highlight ≥ 1°",
            table.byte_size() / 1024,
            100.0 * error.uniform.relative_rms,
            100.0 * error.highlight.relative_rms,
            100.0 * error.highlight_above_1deg.relative_rms,
        );
        assert!(
            table.byte_size() <= 5 << 20,
            "{name}: {} bytes",
            table.byte_size()
        );
        assert!(
            error.uniform.relative_rms <= uniform_bound,
            "{name}: {error:?}"
        );
        assert!(
            error.highlight.relative_rms <= highlight_bound,
            "{name}: {error:?}"
        );
        assert!(
            error.highlight_above_1deg.relative_rms <= above_1_bound,
            "{name}: {error:?}"
        );
    }
}
