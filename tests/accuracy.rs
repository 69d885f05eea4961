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
