//! Fabric and thread parameters (the paper's measured set, docs/model.md#the-six-built-in-fabrics),
//! the model options, and their validation.
//!
//! # Fabric schema
//!
//! A fabric file is TOML holding one or more `[[fabric]]` tables. Angles are in degrees.
//! Unknown keys are errors.
//!
//! | key | type | meaning |
//! |---|---|---|
//! | `name` | string | identifier, `[A-Za-z0-9_-]`, at most 64 characters; names the table file |
//! | `options.gaussian_width` | `"std_dev"` (default) \| `"sqrt2_std_dev"` | γ is the Gaussian's standard deviation σ, or γ = √2·σ |
//! | `options.sigma_u_deg` | number, default 20 | width σu of the reweighting Gaussian u, in (0, 180] |
//! | `options.tangent_sampling` | `"arc_length"` (default) \| `"control_points"` | curve sampled uniformly in arc length, or the mean over the control points only |
//! | `thread1`, `thread2` | table | the two thread families (thread 1 runs along x, thread 2 along y) |
//!
//! Each thread table:
//!
//! | key | type | meaning |
//! |---|---|---|
//! | `eta` | number ≥ 1 | refractive index η of the fibre |
//! | `albedo` | `[r, g, b]`, each ≥ 0 | colour of the volume term |
//! | `albedo_scale` | number ≥ 0, default 1 | `A = albedo_scale × albedo` |
//! | `kd` | number in [0, 1] | isotropic share of the volume term |
//! | `gamma_s_deg` | number > 0 | width of the surface lobe |
//! | `gamma_v_deg` | number > 0 | width of the volume lobe |
//! | `coverage` | number in [0, 1] | area coverage a; `thread1.coverage + thread2.coverage ≤ 1` |
//! | `offsets_deg` | array of 1–256 numbers in [−90, 90] | tangent curve control offsets o₀ … o_m |
//! | `lengths` | array of m numbers ≥ 0, not all 0 | relative arc length of each segment; 0 is a jump. Omitted for a single control point; ignored for a single segment |

use serde::{Deserialize, Serialize};
use std::fmt;

/// Most control points a tangent curve may have: far beyond any woven pattern, and a bound
/// on what an untrusted file can make us allocate per sample plan.
pub const MAX_CONTROL_POINTS: usize = 256;

/// How the listed γ relates to the Gaussian's standard deviation σ
/// (docs/model.md#options-and-defaults).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum GaussianWidth {
    /// γ = σ (the default).
    #[default]
    StdDev,
    /// γ = √2·σ, as some implementations read the paper.
    Sqrt2StdDev,
}

/// Where along a tangent curve the model takes its tangent samples
/// (docs/model.md#options-and-defaults).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TangentSampling {
    /// Uniform in arc length along the piecewise-linear curve, honouring segment lengths.
    #[default]
    ArcLength,
    /// The mean over the control points alone, every point weighted equally.
    ControlPoints,
}

/// The documented model options; every field has the default of docs/model.md#options-and-defaults.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ModelOptions {
    pub gaussian_width: GaussianWidth,
    pub sigma_u_deg: f64,
    pub tangent_sampling: TangentSampling,
}

impl Default for ModelOptions {
    fn default() -> Self {
        Self {
            gaussian_width: GaussianWidth::StdDev,
            sigma_u_deg: 20.0,
            tangent_sampling: TangentSampling::ArcLength,
        }
    }
}

/// One thread family's parameters (one row of the fabric table,
/// docs/model.md#the-six-built-in-fabrics).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Thread {
    pub eta: f64,
    pub albedo: [f64; 3],
    #[serde(default = "one")]
    pub albedo_scale: f64,
    pub kd: f64,
    pub gamma_s_deg: f64,
    pub gamma_v_deg: f64,
    pub coverage: f64,
    pub offsets_deg: Vec<f64>,
    #[serde(default)]
    pub lengths: Vec<f64>,
}

fn one() -> f64 {
    1.0
}

/// A woven fabric: two thread families and the model options.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Fabric {
    pub name: String,
    #[serde(default)]
    pub options: ModelOptions,
    pub thread1: Thread,
    pub thread2: Thread,
}

/// A parameter that fails validation, located by fabric, thread and field.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub struct FabricError {
    pub fabric: String,
    /// 1 or 2; `None` for fields of the fabric itself.
    pub thread: Option<u8>,
    pub field: String,
    pub message: String,
}

impl fmt::Display for FabricError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "fabric '{}'", self.fabric)?;
        if let Some(thread) = self.thread {
            write!(f, ", thread {thread}")?;
        }
        write!(f, ", field '{}': {}", self.field, self.message)
    }
}

impl Thread {
    /// The RGB albedo `A = albedo_scale × albedo`.
    pub fn albedo_rgb(&self) -> [f64; 3] {
        self.albedo.map(|c| c * self.albedo_scale)
    }

    fn validate(&self, fail: &dyn Fn(&str, String) -> FabricError) -> Result<(), FabricError> {
        let finite = |field: &str, v: f64| {
            if v.is_finite() {
                Ok(())
            } else {
                Err(fail(field, format!("must be a finite number, got {v}")))
            }
        };
        for (field, v) in [
            ("eta", self.eta),
            ("albedo_scale", self.albedo_scale),
            ("kd", self.kd),
            ("gamma_s_deg", self.gamma_s_deg),
            ("gamma_v_deg", self.gamma_v_deg),
            ("coverage", self.coverage),
        ] {
            finite(field, v)?;
        }
        if self.eta < 1.0 {
            return Err(fail("eta", format!("must be at least 1, got {}", self.eta)));
        }
        for (i, &c) in self.albedo.iter().enumerate() {
            finite("albedo", c)?;
            if c < 0.0 {
                return Err(fail(
                    "albedo",
                    format!("component {i} must be ≥ 0, got {c}"),
                ));
            }
        }
        if self.albedo_scale < 0.0 {
            let v = self.albedo_scale;
            return Err(fail("albedo_scale", format!("must be ≥ 0, got {v}")));
        }
        if !(0.0..=1.0).contains(&self.kd) {
            let v = self.kd;
            return Err(fail("kd", format!("must be within [0, 1], got {v}")));
        }
        for (field, v) in [
            ("gamma_s_deg", self.gamma_s_deg),
            ("gamma_v_deg", self.gamma_v_deg),
        ] {
            if v <= 0.0 {
                return Err(fail(field, format!("must be > 0, got {v}")));
            }
        }
        if !(0.0..=1.0).contains(&self.coverage) {
            let v = self.coverage;
            return Err(fail("coverage", format!("must be within [0, 1], got {v}")));
        }
        let points = self.offsets_deg.len();
        if points == 0 {
            return Err(fail(
                "offsets_deg",
                "needs at least one control point".into(),
            ));
        }
        if points > MAX_CONTROL_POINTS {
            return Err(fail(
                "offsets_deg",
                format!("has {points} control points, at most {MAX_CONTROL_POINTS} allowed"),
            ));
        }
        for (i, &o) in self.offsets_deg.iter().enumerate() {
            finite("offsets_deg", o)?;
            if !(-90.0..=90.0).contains(&o) {
                return Err(fail(
                    "offsets_deg",
                    format!("offset {i} must be within [-90, 90] degrees, got {o}"),
                ));
            }
        }
        let segments = points - 1;
        if self.lengths.len() != segments {
            return Err(fail(
                "lengths",
                format!(
                    "needs one length per segment: {points} control points make {segments} \
                     segments, got {} lengths",
                    self.lengths.len()
                ),
            ));
        }
        for (i, &l) in self.lengths.iter().enumerate() {
            finite("lengths", l)?;
            if l < 0.0 {
                return Err(fail("lengths", format!("length {i} must be ≥ 0, got {l}")));
            }
        }
        // A single segment ignores its length (docs/model.md#tangent-curves), so only a curve of
        // several segments can be left without any arc length.
        if segments > 1 && self.lengths.iter().all(|&l| l == 0.0) {
            return Err(fail(
                "lengths",
                "are all zero: the curve holds no samples".into(),
            ));
        }
        Ok(())
    }
}

impl ModelOptions {
    /// The standard deviation, in degrees, of a lobe whose listed width is `gamma_deg`.
    pub fn lobe_sigma_deg(&self, gamma_deg: f64) -> f64 {
        match self.gaussian_width {
            GaussianWidth::StdDev => gamma_deg,
            GaussianWidth::Sqrt2StdDev => gamma_deg / std::f64::consts::SQRT_2,
        }
    }

    fn validate(&self, fail: &dyn Fn(&str, String) -> FabricError) -> Result<(), FabricError> {
        let v = self.sigma_u_deg;
        if !v.is_finite() || v <= 0.0 || v > 180.0 {
            return Err(fail(
                "options.sigma_u_deg",
                format!("must be within (0, 180], got {v}"),
            ));
        }
        Ok(())
    }
}

impl Fabric {
    /// The threads in the model's order (docs/model.md#frames-and-directions): thread 1 (along x),
    /// thread 2 (along y).
    pub fn threads(&self) -> [&Thread; 2] {
        [&self.thread1, &self.thread2]
    }

    /// Checks every parameter against the ranges of docs/model.md#parameters-and-their-ranges; the
    /// error names the fabric, the thread and the field.
    pub fn validate(&self) -> Result<(), FabricError> {
        let at = |thread: Option<u8>| {
            let fabric = self.name.clone();
            move |field: &str, message: String| FabricError {
                fabric: fabric.clone(),
                thread,
                field: field.to_string(),
                message,
            }
        };
        let fabric_fail = at(None);
        validate_name(&self.name).map_err(|m| fabric_fail("name", m.to_string()))?;
        self.options.validate(&fabric_fail)?;
        self.thread1.validate(&at(Some(1)))?;
        self.thread2.validate(&at(Some(2)))?;
        let total = self.thread1.coverage + self.thread2.coverage;
        if total > 1.0 {
            return Err(FabricError {
                fabric: self.name.clone(),
                thread: None,
                field: "coverage".into(),
                message: format!("thread1.coverage + thread2.coverage must be ≤ 1, got {total}"),
            });
        }
        Ok(())
    }
}

/// What is wrong with a fabric's name (it names a file, `NAME.exr`, so it is kept to a
/// portable file-name alphabet).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum NameProblem {
    #[error("must be 1 to 64 characters, got {0}")]
    Length(usize),
    #[error("may hold only A-Z, a-z, 0-9, '_' and '-', found {0:?}")]
    Character(char),
}

fn validate_name(name: &str) -> Result<(), NameProblem> {
    if name.is_empty() || name.len() > 64 {
        return Err(NameProblem::Length(name.len()));
    }
    if let Some(c) = name
        .chars()
        .find(|c| !(c.is_ascii_alphanumeric() || *c == '_' || *c == '-'))
    {
        return Err(NameProblem::Character(c));
    }
    Ok(())
}
