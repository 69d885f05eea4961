//! The fabric file's fields: the name, the model options and each thread's parameters.

use super::{Access, FieldSpec};
use serde::de::{DeserializeOwned, IntoDeserializer};

/// The variant of a serde enum named `text` as the fabric file names it.
fn variant<T: DeserializeOwned>(text: &str) -> Option<T> {
    T::deserialize(IntoDeserializer::<serde::de::value::Error>::into_deserializer(text)).ok()
}

/// A number of a thread.
macro_rules! thread_number {
    ($t:ident . $f:ident, $label:expr, $unit:expr, $range:expr) => {
        FieldSpec {
            path: concat!(stringify!($t), ".", stringify!($f)),
            label: $label,
            unit: $unit,
            range: $range,
            access: Access::Number {
                get: |fabric| fabric.$t.$f,
                set: |fabric, v| fabric.$t.$f = v,
            },
        }
    };
}

/// A list of a thread's tangent curve.
macro_rules! thread_list {
    ($t:ident . $f:ident, $label:expr, $unit:expr, $range:expr, $set:expr) => {
        FieldSpec {
            path: concat!(stringify!($t), ".", stringify!($f)),
            label: $label,
            unit: $unit,
            range: $range,
            access: Access::List {
                get: |fabric| &fabric.$t.$f,
                set: $set,
            },
        }
    };
}

/// Every field of one thread.
macro_rules! thread_fields {
    ($t:ident) => {
        [
            thread_number!($t.eta, "η, refractive index", "", (1.0, 2.5)),
            FieldSpec {
                path: concat!(stringify!($t), ".albedo"),
                label: "albedo colour, linear RGB",
                unit: "",
                range: (0.0, 1.0),
                access: Access::Rgb {
                    get: |fabric| fabric.$t.albedo,
                    set: |fabric, v| fabric.$t.albedo = v,
                },
            },
            thread_number!($t.albedo_scale, "albedo scale", "", (0.0, 10.0)),
            thread_number!($t.kd, "kd, isotropic share", "", (0.0, 1.0)),
            thread_number!($t.gamma_s_deg, "γs, surface lobe width", "°", (0.1, 90.0)),
            thread_number!($t.gamma_v_deg, "γv, volume lobe width", "°", (0.1, 90.0)),
            thread_number!($t.coverage, "coverage", "", (0.0, 1.0)),
            thread_list!(
                $t.offsets_deg,
                "tangent curve offsets",
                "°",
                (-90.0, 90.0),
                |fabric, v| {
                    let thread = &mut fabric.$t;
                    resize_lengths(&mut thread.lengths, v.len());
                    thread.offsets_deg = v;
                }
            ),
            thread_list!(
                $t.lengths,
                "tangent curve segment lengths",
                "",
                (0.0, 10.0),
                |fabric, v| fabric.$t.lengths = v
            ),
        ]
    };
}

/// A list of offsets of another count of points keeps the lengths of the segments that
/// remain and gives each new segment the last segment's length (1 where there was none), so
/// that a curve can gain or lose points by editing its offsets alone.
fn resize_lengths(lengths: &mut Vec<f64>, points: usize) {
    let segments = points.saturating_sub(1);
    let last = lengths.last().copied().unwrap_or(1.0);
    lengths.resize(segments, last);
}

pub(super) const THREAD1: [FieldSpec; 9] = thread_fields!(thread1);
pub(super) const THREAD2: [FieldSpec; 9] = thread_fields!(thread2);

pub(super) const FABRIC: [FieldSpec; 4] = [
    FieldSpec {
        path: "name",
        label: "name",
        unit: "",
        range: (0.0, 0.0),
        access: Access::Name,
    },
    FieldSpec {
        path: "options.gaussian_width",
        label: "γ is σ or √2·σ",
        unit: "",
        range: (0.0, 0.0),
        access: Access::Choice {
            choices: &["std_dev", "sqrt2_std_dev"],
            holds: |fabric, c| variant(c) == Some(fabric.options.gaussian_width),
            set: |fabric, c| {
                variant(c)
                    .map(|v| fabric.options.gaussian_width = v)
                    .is_some()
            },
        },
    },
    FieldSpec {
        path: "options.sigma_u_deg",
        label: "σu, reweighting width",
        unit: "°",
        range: (0.1, 180.0),
        access: Access::Number {
            get: |fabric| fabric.options.sigma_u_deg,
            set: |fabric, v| fabric.options.sigma_u_deg = v,
        },
    },
    FieldSpec {
        path: "options.tangent_sampling",
        label: "tangent samples",
        unit: "",
        range: (0.0, 0.0),
        access: Access::Choice {
            choices: &["arc_length", "control_points"],
            holds: |fabric, c| variant(c) == Some(fabric.options.tangent_sampling),
            set: |fabric, c| {
                variant(c)
                    .map(|v| fabric.options.tangent_sampling = v)
                    .is_some()
            },
        },
    },
];
