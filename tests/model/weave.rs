//! Invariants of fabrics made from weave drafts (docs/weave.md#invariants): an S and a Z
//! twill give mirrored F, exchanging warp and weft turns F by 90°, and a plain weave of
//! equal yarns is unchanged by that turn; and the knobs reach the paper's satin curves.

use clothbake::measure::direction_sets::{highlight_pairs, uniform_pairs};
use clothbake::model::{Fabric, Integration, Patch};
use clothbake::weave::{NamedWeave, Weave};
use glam::DVec3;

fn woven(spelling: &str, warp: &str, weft: &str) -> Weave {
    let mut weave = Weave::new(spelling.parse::<NamedWeave>().unwrap().draft());
    weave.warp.set_all(warp).unwrap();
    weave.weft.set_all(weft).unwrap();
    weave
}

/// Pairs uniform over the hemispheres and on the highlight cones of `fabric`.
fn pairs(fabric: &Fabric) -> Vec<(DVec3, DVec3)> {
    let mut pairs = uniform_pairs(150, 71);
    pairs.extend(highlight_pairs(fabric, 150, 72));
    pairs
}

/// The largest `|F_a(wi, wo) − F_b(map wi, map wo)|` over `fabric_a`'s pairs, relative to the
/// largest F. The two evaluations add the same terms in the same order, so they agree to
/// rounding (1e-12 leaves room for a few ulps of the largest term).
fn largest_difference(a: &Fabric, b: &Fabric, map: impl Fn(DVec3) -> DVec3) -> f64 {
    let (pa, pb) = (
        Patch::new(a, Integration::Direct),
        Patch::new(b, Integration::Direct),
    );
    let mut largest = 0.0_f64;
    let mut peak = 0.0_f64;
    for (wi, wo) in pairs(a) {
        let fa = pa.eval(wi, wo);
        let fb = pb.eval(map(wi), map(wo));
        largest = largest.max((fa - fb).abs().max_element());
        peak = peak.max(fa.max_element());
    }
    assert!(peak > 0.0);
    largest / peak
}

#[test]
fn s_and_z_twills_give_mirrored_f() {
    let (warp, weft) = (
        "fibre=cotton,crimp=30,legs=0.3",
        "crimp=15,kd=0.6,colour=#c0c0b0",
    );
    let s = woven("twill:3/1:s", warp, weft).fabric("s").unwrap();
    let z = woven("twill:3/1:z", warp, weft).fabric("z").unwrap();
    // An S twill is a Z twill with its ends in reverse order: mirrored across the warp,
    // y → −y.
    let mirror = |w: DVec3| DVec3::new(w.x, -w.y, w.z);
    let difference = largest_difference(&s, &z, mirror);
    assert!(difference < 1e-12, "{difference}");
}

#[test]
fn exchanging_warp_and_weft_turns_f_by_90_degrees() {
    let weave = woven(
        "satin:5",
        "fibre=polyester,crimp=32,legs=0.4,flatten=0.6,gamma_s=3,gamma_v=6,kd=0.1",
        "crimp=10,kd=0.7,gamma_s=30,gamma_v=60,colour=#ff8060,cover=0.7",
    );
    let fabric = weave.fabric("satin").unwrap();
    let turned = weave.transposed().fabric("turned").unwrap();
    assert_eq!(turned.thread1.offsets_deg, fabric.thread2.offsets_deg);
    assert_eq!(turned.thread2.coverage, fabric.thread1.coverage);
    // The turned fabric's thread 1 (x) is the original's thread 2 (y) and its thread 2 (y)
    // the original's thread 1 along −x: a rotation by 90° about the normal.
    let turn = |w: DVec3| DVec3::new(-w.y, w.x, w.z);
    let difference = largest_difference(&turned, &fabric, turn);
    assert!(difference < 1e-12, "{difference}");
    // And the turn matters: a satin is not symmetric under it.
    let unturned = largest_difference(&fabric, &fabric, turn);
    assert!(unturned > 0.05, "{unturned}");
}

#[test]
fn a_plain_weave_of_equal_yarns_is_symmetric_under_the_turn() {
    let weave = woven("plain", "fibre=linen,legs=0.2", "fibre=linen,legs=0.2");
    let fabric = weave.fabric("plain").unwrap();
    let turn = |w: DVec3| DVec3::new(-w.y, w.x, w.z);
    let difference = largest_difference(&fabric, &fabric, turn);
    assert!(difference < 1e-12, "{difference}");
}

/// The relative RMS difference of F between the paper's fabric `name` and `satin:5` (turned
/// over and swapped for the back) with the given knobs: their curves and coverages, the
/// paper's optics.
fn satin_knobs_against_the_paper(name: &str, back: bool, warp: &str, weft: &str) -> f64 {
    use clothbake::fit::samples::synthetic_samples;
    use clothbake::fit::solve::relative_rms;
    let paper = clothbake::formats::fabric_toml::FabricSet::builtin()
        .get(name)
        .unwrap()
        .clone();
    let mut weave = woven("satin:5", warp, weft);
    weave.draft = weave.draft.oriented(back, back);
    let knobs = weave.fabric(name).unwrap();
    let mut drawn = paper.clone();
    for (thread, from) in [
        (&mut drawn.thread1, &knobs.thread1),
        (&mut drawn.thread2, &knobs.thread2),
    ] {
        thread.offsets_deg = from.offsets_deg.clone();
        thread.lengths = from.lengths.clone();
        thread.coverage = from.coverage;
    }
    relative_rms(&drawn, &synthetic_samples(&paper, &pairs(&paper), 0.0, 0))
}

/// The paper's hand-made satin curves are within the knobs' reach: the charmeuse's arc bends
/// at 18° of its 32° (`knee`), its back's long floats sag to ±5° between crossings (`sag`).
/// The knobs are those a fit by weave alone found (docs/notebook/2026-12-07-satins-by-weave.md),
/// rounded; they draw both within 0.2% on these pairs, so 1% is the bound: a change to the
/// curve drawing that loses either shape fails it, as the same knobs with the knee at 0.5 and
/// no sag do (2.3% and 20%).
#[test]
fn the_knobs_reach_the_papers_satin_curves() {
    let front = satin_knobs_against_the_paper(
        "polyester_satin_charmeuse",
        false,
        "crimp=32,legs=0.592,flatten=0.365,squash=0.63,knee=0.564,cover=1",
        "crimp=0,cover=0.5",
    );
    let back = satin_knobs_against_the_paper(
        "polyester_satin_charmeuse_back",
        true,
        "crimp=30,legs=0.761,flatten=0.739,squash=0.662,knee=0.127,sag=4.94,cover=0.837",
        "crimp=0,cover=1",
    );
    println!("knobs against the paper's satins: front {front:.4}, back {back:.4}");
    assert!(front < 0.01 && back < 0.01, "front {front}, back {back}");
}
