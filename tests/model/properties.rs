//! Property tests over random valid fabrics and directions: F is finite and non-negative,
//! and exactly 0 below the horizon.

use clothbake::model::{
    Fabric, GaussianWidth, Integration, ModelOptions, Patch, TangentSampling, Thread,
};
use glam::DVec3;
use proptest::prelude::*;

fn thread(max_coverage: f64) -> impl Strategy<Value = Thread> {
    (
        1.0..2.5f64,
        prop::array::uniform3(0.0..1.0f64),
        0.0..1.0f64,
        prop_oneof![Just(0.01f64), 0.5..60.0f64],
        prop_oneof![Just(0.01f64), 0.5..60.0f64],
        0.0..=max_coverage,
        prop::collection::vec(-90.0..=90.0f64, 1..7),
        prop::collection::vec(prop_oneof![Just(0.0), 0.01..3.0f64], 6),
    )
        .prop_map(
            |(eta, albedo, kd, gamma_s_deg, gamma_v_deg, coverage, offsets_deg, lengths)| {
                let segments = offsets_deg.len() - 1;
                let mut lengths = lengths[..segments].to_vec();
                if lengths.iter().all(|&l| l == 0.0) && segments > 0 {
                    lengths[0] = 1.0;
                }
                Thread {
                    eta,
                    albedo,
                    albedo_scale: 1.0,
                    kd,
                    gamma_s_deg,
                    gamma_v_deg,
                    coverage,
                    offsets_deg,
                    lengths,
                }
            },
        )
}

fn fabric() -> impl Strategy<Value = Fabric> {
    (
        thread(1.0),
        0.0..=1.0f64,
        thread(1.0),
        any::<bool>(),
        5.0..40.0f64,
        any::<bool>(),
    )
        .prop_map(
            |(thread1, share, mut thread2, sqrt2, sigma_u_deg, points)| {
                thread2.coverage = (1.0 - thread1.coverage) * share;
                let options = ModelOptions {
                    gaussian_width: if sqrt2 {
                        GaussianWidth::Sqrt2StdDev
                    } else {
                        GaussianWidth::StdDev
                    },
                    sigma_u_deg,
                    tangent_sampling: if points {
                        TangentSampling::ControlPoints
                    } else {
                        TangentSampling::ArcLength
                    },
                };
                Fabric {
                    name: "random".into(),
                    options,
                    thread1,
                    thread2,
                }
            },
        )
}

/// Directions anywhere on the sphere, including the horizon and poles exactly.
fn direction() -> impl Strategy<Value = DVec3> {
    prop_oneof![
        (-1.0..1.0f64, -1.0..1.0f64, -0.2..1.0f64)
            .prop_filter_map("zero", |(x, y, z)| DVec3::new(x, y, z).try_normalize()),
        (0.0..std::f64::consts::TAU).prop_map(|a| DVec3::new(a.cos(), a.sin(), 0.0)),
        Just(DVec3::Z),
        (0.0..std::f64::consts::TAU, 1e-12..1e-6f64).prop_map(|(a, z)| DVec3::new(
            a.cos(),
            a.sin(),
            z
        )
        .normalize()),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    fn random_fabrics_give_finite_non_negative_values(
        fabric in fabric(),
        pairs in prop::collection::vec((direction(), direction()), 8),
        n in 1u32..64,
    ) {
        prop_assert!(fabric.validate().is_ok(), "{:?}", fabric.validate());
        let paper = Patch::new(&fabric, Integration::Paper(n));
        for &(wi, wo) in &pairs {
            let f = paper.eval(wi, wo);
            prop_assert!(f.is_finite() && f.min_element() >= 0.0, "paper {n}: {wi} {wo} -> {f}");
            if wi.z <= 0.0 || wo.z <= 0.0 {
                prop_assert_eq!(f, DVec3::ZERO);
            }
        }
    }
}

proptest! {
    // The direct rule can take up to 2^19 nodes per thread on a 0.01° lobe: fewer cases.
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn random_fabrics_direct_evaluation_is_finite_and_non_negative(
        fabric in fabric(),
        pairs in prop::collection::vec((direction(), direction()), 4),
    ) {
        let direct = Patch::new(&fabric, Integration::Direct);
        for &(wi, wo) in &pairs {
            let f = direct.eval(wi, wo);
            prop_assert!(f.is_finite() && f.min_element() >= 0.0, "direct: {wi} {wo} -> {f}");
        }
    }
}
