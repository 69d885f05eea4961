//! Table accuracy against the direct evaluation, for all six fabrics at the default layout
//! and resolution (what `clothbake bake` writes).
//!
//! The bounds are regression guards set from measurement, not the 2% goal of the baker's
//! issue (not met yet; see README, "Tables"). A relative RMS over a few thousand pairs is
//! dominated by a handful of grazing pairs, so it moves by up to a factor 1.8 between
//! seeds (satin, uniform: 2.9% on this test's 2,000 pairs, 5.0% on `clothbake check`'s
//! 4,000). Each bound is the larger of the two measurements plus 20%. The seeds differ from
//! the ones the baker uses to choose its reflection scale, so the test does not grade the
//! baker on its own exam.

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
    ("linen_plain", 0.015, 0.015),
    ("silk_crepe_de_chine", 0.055, 0.045),
    ("polyester_satin_charmeuse", 0.060, 0.064),
    ("polyester_satin_charmeuse_back", 0.050, 0.047),
    ("silk_shot", 0.037, 0.066),
    ("velvet", 0.034, 0.034),
];
/// Both directions at least 15° above the horizon: measured 0.75–2.6%.
const ABOVE_15_BOUND: f64 = 0.032;

#[test]
fn default_tables_meet_their_measured_error() {
    let layout = Layout::ThreadFrame;
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
