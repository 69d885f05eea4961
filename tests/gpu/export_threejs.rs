//! `clothbake export --to gltf` read by another renderer: every built-in fabric's .gltf rendered
//! by three.js r187 (tools/export-check/render-gltf.mjs: GLTFLoader, MeshPhysicalMaterial,
//! WebGL 2 on SwiftShader in headless Chromium, clothbake's tone mapping) against `clothbake
//! render --evaluator gltf` of the same fitted material (wgpu on lavapipe here), at the same
//! size (320×240) and exposure (1), on the pixels both images cover.
//!
//! The two renderers do not shade the same formulas: clothbake's `gltf` unit follows the glTF
//! specification (src/evaluator/gltf/mod.rs), three.js r187 has its own sheen (V_Neubelt, an
//! exponential fit of the sheen albedo taken at the larger of both directions), Fresnel (exp2),
//! roughness (floor 0.045 plus the screen-space `geometryRoughness`), `alphaT ≥ alpha`, the
//! multi-scattering compensation of the direct specular (from its 16×16 DFG table) and the
//! (1 − F) of the diffuse with its own F. So the bound is not guessed but predicted: the view's
//! G-buffer (the render's own rasterisation, [`Headless::gbuffer`]) is shaded on the CPU in f64
//! once by the specification (`StockMaterial::eval`, through [`reference::shade_with`]) and
//! once by [`ThreeMaterial`], a transcription of three.js r187's direct-light code (each
//! formula cites its file and line), both tone mapped and quantised as the renders are
//! ([`tonemap`], 8 bits). Per pixel and channel, with `cb` and `th` the two renders' 8-bit
//! values and `s`, `t` the two CPU shadings':
//!
//! ```text
//! |cb − th| ≤ |s − t| + |cb − s| + |th − t|
//!   measured   predicted  clothbake's own     three.js's own GPU-vs-twin difference:
//!              model      GPU-vs-CPU, measured  two roundings of values that agree to
//!              difference here per pixel        f32 (SwiftShader) → at most 1 level
//! ```
//!
//! `b = |s − t| + |cb − s| + 1` dominates `|cb − th|` value by value wherever three.js's f32
//! shading is within half a level of its f64 twin, so the mean and the 99th percentile of the
//! measured `|cb − th|` must not pass those of `b` (a pointwise bound bounds every quantile).
//! The rim of the covered region (any covered pixel with an uncovered 4-neighbour) is left out
//! and counted: there the two renderers treat a normal that turns away from the eye
//! differently (clothbake flips it, three.js clamps n·v to 0), the screen-space derivatives of
//! `geometryRoughness` read helper pixels the G-buffer does not hold, and lavapipe and
//! SwiftShader may break ties of the edge function differently. Covered is: the G-buffer
//! covers it and three.js's pixel is not black (the export is double-sided, as clothbake
//! shades a sheet's back; three.js's background is black, clothbake's
//! [`clothbake::render::BACKGROUND`]).
//!
//! The measured figures, the derivation and a deliberately wrong material (the check that the
//! bound can fail; `CLOTHBAKE_EXPORT_THREEJS_SWAP=colours|roughness|rotation` renders a
//! wrongly exported material with three.js and the test then fails) are in
//! docs/notebook/2026-12-07-export-threejs.md.
//!
//! Needs `node` (20 or newer), Debian's `chromium` and tools/export-check/node_modules, which
//! scripts/setup.sh installs; missing, the test fails and says so.

use super::common::{gpu_context, output_text, temp_dir};
use super::editor::read_rgb;
use clothbake::evaluator::constant::gpu::GpuConstant;
use clothbake::evaluator::gltf::MODEL;
use clothbake::evaluator::stock::StockMaterial;
use clothbake::formats::fabric_toml::FabricSet;
use clothbake::render::image::tonemap;
use clothbake::render::{FrameSettings, GBuffer, Headless, reference};
use clothbake::scene::Scene;
use clothbake::scene::mesh::Mesh;
use glam::{DVec2, DVec3};
use std::f64::consts::PI;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

/// Both renders' size and exposure.
const WIDTH: u32 = 320;
const HEIGHT: u32 = 240;
const EXPOSURE: f32 = 1.0;
/// three.js's own shading against its f64 twin: two roundings to 8 bits of values that agree
/// to f32 precision differ by at most one level.
const THREE_ROUNDING: f64 = 1.0;

/// The glTF material's inputs in the order of the `gltf` unit's parameters.
fn material_of(gltf: &serde_json::Value) -> StockMaterial {
    let m = &gltf["materials"][0];
    let pbr = &m["pbrMetallicRoughness"];
    let sheen = &m["extensions"]["KHR_materials_sheen"];
    let aniso = &m["extensions"]["KHR_materials_anisotropy"];
    let f = |v: &serde_json::Value| v.as_f64().expect("a number in the glTF material");
    let values = [
        f(&pbr["baseColorFactor"][0]),
        f(&pbr["baseColorFactor"][1]),
        f(&pbr["baseColorFactor"][2]),
        f(&pbr["metallicFactor"]),
        f(&pbr["roughnessFactor"]),
        f(&aniso["anisotropyStrength"]),
        f(&aniso["anisotropyRotation"]),
        f(&sheen["sheenColorFactor"][0]),
        f(&sheen["sheenColorFactor"][1]),
        f(&sheen["sheenColorFactor"][2]),
        f(&sheen["sheenRoughnessFactor"]),
    ];
    StockMaterial::new(&MODEL, &values)
}

/// three.js r187's DFG table (src/renderers/shaders/DFGLUTData.js): 16×16 RG16F texels,
/// x = roughness, y = n·v, `LinearFilter`, `ClampToEdgeWrapping`; read from the installed
/// package, so that the twin uses the very numbers the shader samples.
struct Dfg {
    texels: Vec<DVec2>,
}

impl Dfg {
    const SIDE: usize = 16;

    fn load(path: &Path) -> Self {
        let text = std::fs::read_to_string(path)
            .unwrap_or_else(|e| panic!("{}: {e} (run scripts/setup.sh)", path.display()));
        let start = text
            .find("Uint16Array(")
            .expect("DFGLUTData.js holds a Uint16Array");
        let end = start + text[start..].find(']').expect("the array ends");
        let halves: Vec<f64> = text[start..end]
            .split(|c: char| c == ',' || c == '[' || c.is_whitespace())
            .filter_map(|w| w.strip_prefix("0x"))
            .map(|h| half::f16::from_bits(u16::from_str_radix(h, 16).unwrap()).to_f64())
            .collect();
        assert_eq!(halves.len(), 2 * Self::SIDE * Self::SIDE, "DFG table size");
        Self {
            texels: halves
                .chunks_exact(2)
                .map(|c| DVec2::new(c[0], c[1]))
                .collect(),
        }
    }

    /// `texture2D(dfgLUT, vec2(roughness, dotNV)).rg` (lights_fragment_begin.glsl.js:61):
    /// bilinear between texel centres, clamped to the edge.
    fn at(&self, roughness: f64, dot_nv: f64) -> DVec2 {
        let n = Self::SIDE;
        let axis = |u: f64| {
            let x = (u * n as f64 - 0.5).clamp(0.0, (n - 1) as f64);
            let i = (x.floor() as usize).min(n - 2);
            (i, x - i as f64)
        };
        let ((i, fx), (j, fy)) = (axis(roughness), axis(dot_nv));
        let t = |i: usize, j: usize| self.texels[j * n + i];
        let row0 = t(i, j).lerp(t(i + 1, j), fx);
        let row1 = t(i, j + 1).lerp(t(i + 1, j + 1), fx);
        row0.lerp(row1, fy)
    }
}

fn saturate(x: f64) -> f64 {
    x.clamp(0.0, 1.0)
}

/// The fitted glTF material as three.js r187 shades it under a punctual light (WebGL,
/// MeshPhysicalMaterial from GLTFLoader: `sheen = 1`, `sheenColor`, `sheenRoughness`,
/// `anisotropy`, `anisotropyRotation`; ShaderChunk paths below are
/// src/renderers/shaders/ShaderChunk/*.glsl.js of npm `three` 0.187.0).
struct ThreeMaterial<'a> {
    base: DVec3,
    metalness: f64,
    roughness: f64,
    anisotropy: f64,
    rotation: f64,
    sheen_color: DVec3,
    sheen_roughness: f64,
    dfg: &'a Dfg,
}

impl<'a> ThreeMaterial<'a> {
    fn new(m: &StockMaterial, dfg: &'a Dfg) -> Self {
        let v = |name: &str| m.value(name).expect("a glTF parameter");
        let c = |name: &str| DVec3::from(m.colour(name).expect("a glTF colour"));
        Self {
            base: c("baseColorFactor"),
            metalness: v("metallicFactor"),
            roughness: v("roughnessFactor"),
            anisotropy: v("anisotropyStrength"),
            rotation: v("anisotropyRotation"),
            sheen_color: c("sheenColorFactor"),
            // lights_physical_fragment:143: clamp(sheenRoughness, 0.0001, 1.0).
            sheen_roughness: v("sheenRoughnessFactor").clamp(1e-4, 1.0),
            dfg,
        }
    }

    /// F = BRDF·(n·l) at a pixel whose `geometryRoughness` is `geometry_roughness`, wi and wo
    /// in the frame (T, B, N) three.js builds from the vertex tangent (w = +1).
    fn eval(&self, wi: DVec3, wo: DVec3, geometry_roughness: f64) -> DVec3 {
        let (l, v) = (wi, wo);
        // RE_Direct_Physical (lights_physical_pars_fragment:552ff): irradiance = dotNL·color.
        let dot_nl = saturate(l.z);
        let dot_nv = saturate(v.z);
        if dot_nl == 0.0 {
            return DVec3::ZERO;
        }
        // lights_physical_fragment:12-14: max(roughnessFactor, 0.045) + geometryRoughness,
        // at most 1.
        let roughness = (self.roughness.max(0.045) + geometry_roughness).min(1.0);
        // lights_physical_fragment:66-67: specularColor 0.04, specularColorBlended.
        let f0 = DVec3::splat(0.04).lerp(self.base, self.metalness);
        // lights_fragment_begin:59-73: dfg from the table at (roughness, n·v); Turquin's
        // multi-scattering compensation 1 + f0 (1/(dfg.x + dfg.y) − 1).
        let dfg = self.dfg.at(roughness, dot_nv);
        let compensation = DVec3::ONE + f0 * (1.0 / (dfg.x + dfg.y) - 1.0);
        let h = (l + v).normalize();
        let dot_nh = saturate(h.z);
        let dot_vh = saturate(v.dot(h));

        // Sheen (lights_physical_pars_fragment:569-578): sheenSpecularDirect gets the
        // irradiance before it is scaled by 1 − max3(sheenColor)·max(E(n·v), E(n·l)).
        let sheen = self.sheen_color
            * (d_charlie(self.sheen_roughness, dot_nh) * v_neubelt(dot_nv, dot_nl));
        let e_v = ibl_sheen_brdf(dot_nv, self.sheen_roughness);
        let e_l = ibl_sheen_brdf(dot_nl, self.sheen_roughness);
        let energy = 1.0 - self.sheen_color.max_element() * e_v.max(e_l);

        // BRDF_GGX (lights_physical_pars_fragment:222-270).
        let roughness = roughness.max(0.045); // :226
        let alpha = roughness * roughness; // :228
        let fresnel = f_schlick(f0, 1.0, dot_vh); // :237, f90 = 1 without KHR_materials_specular
        let (vis, d) = if self.anisotropy > 0.0 {
            // USE_ANISOTROPY (defined for anisotropy > 0): lights_physical_fragment:167-180,
            // anisotropyVector = strength·(cos, sin) of the rotation (WebGLMaterials.js:561).
            let strength = saturate(self.anisotropy);
            let alpha_t = (alpha + (1.0 - alpha) * strength * strength).max(alpha); // LPF:177, LPP:254
            let (c, s) = (self.rotation.cos(), self.rotation.sin());
            let t = DVec3::new(c, s, 0.0); // tbn[0]·x + tbn[1]·y
            let b = DVec3::new(-s, c, 0.0); // tbn[1]·x − tbn[0]·y
            (
                v_ggx_anisotropic(
                    alpha_t,
                    alpha,
                    t.dot(v),
                    b.dot(v),
                    t.dot(l),
                    b.dot(l),
                    dot_nv,
                    dot_nl,
                ),
                d_ggx_anisotropic(alpha_t, alpha, dot_nh, t.dot(h), b.dot(h)),
            )
        } else {
            (v_ggx(alpha, dot_nl, dot_nv), d_ggx(alpha, dot_nh))
        };
        // :595: directSpecular += irradiance · F V D · multiScatteringCompensation.
        let specular = fresnel * (vis * d) * compensation;
        // :598-622: the diffuse under 1 − F_Schlick(specularColor = 0.04, f90 = 1, v·h),
        // BRDF_Lambert(diffuseColor·(1 − metalness)) (common.glsl.js:103-107; LPF:4).
        let diffuse = self.base * (1.0 - self.metalness) / PI
            * (DVec3::ONE - f_schlick(DVec3::splat(0.04), 1.0, dot_vh));
        // meshphysical.glsl.js:203-213: diffuse + specular, then + sheenSpecularDirect.
        dot_nl * (sheen + energy * (specular + diffuse))
    }
}

/// common.glsl.js:109-120: Schlick's Fresnel with Epic's exp2 fit of (1 − v·h)⁵.
fn f_schlick(f0: DVec3, f90: f64, dot_vh: f64) -> DVec3 {
    let fresnel = ((-5.55473 * dot_vh - 6.98316) * dot_vh).exp2();
    f0 * (1.0 - fresnel) + DVec3::splat(f90 * fresnel)
}

/// lights_physical_pars_fragment:145-152 (EPSILON = 1e-6, common.glsl.js:7).
fn v_ggx(alpha: f64, dot_nl: f64, dot_nv: f64) -> f64 {
    let a2 = alpha * alpha;
    let gv = dot_nl * (a2 + (1.0 - a2) * dot_nv * dot_nv).sqrt();
    let gl = dot_nv * (a2 + (1.0 - a2) * dot_nl * dot_nl).sqrt();
    0.5 / (gv + gl).max(1e-6)
}

/// lights_physical_pars_fragment:158-166.
fn d_ggx(alpha: f64, dot_nh: f64) -> f64 {
    let a2 = alpha * alpha;
    let denom = dot_nh * dot_nh * (a2 - 1.0) + 1.0;
    a2 / (PI * denom * denom)
}

/// lights_physical_pars_fragment:171-177.
#[allow(clippy::too_many_arguments)]
fn v_ggx_anisotropic(
    at: f64,
    ab: f64,
    tv: f64,
    bv: f64,
    tl: f64,
    bl: f64,
    nv: f64,
    nl: f64,
) -> f64 {
    let gv = nl * DVec3::new(at * tv, ab * bv, nv).length();
    let gl = nv * DVec3::new(at * tl, ab * bl, nl).length();
    0.5 / (gv + gl).max(1e-6)
}

/// lights_physical_pars_fragment:179-188.
fn d_ggx_anisotropic(at: f64, ab: f64, nh: f64, th: f64, bh: f64) -> f64 {
    let a2 = at * ab;
    let v = DVec3::new(ab * th, at * bh, a2 * nh);
    let w2 = a2 / v.length_squared();
    a2 * w2 * w2 / PI
}

/// lights_physical_pars_fragment:392-403: Charlie with α = r², sin²θh at least 2⁻⁷.
fn d_charlie(roughness: f64, dot_nh: f64) -> f64 {
    let inv_alpha = 1.0 / (roughness * roughness);
    let sin2h = (1.0 - dot_nh * dot_nh).max(0.0078125);
    (2.0 + inv_alpha) * sin2h.powf(inv_alpha * 0.5) / (2.0 * PI)
}

/// lights_physical_pars_fragment:406-411.
fn v_neubelt(dot_nv: f64, dot_nl: f64) -> f64 {
    saturate(1.0 / (4.0 * (dot_nl + dot_nv - dot_nl * dot_nv)))
}

/// lights_physical_pars_fragment:432-446: the sheen albedo's exponential fit.
fn ibl_sheen_brdf(dot_nv: f64, roughness: f64) -> f64 {
    let r2 = roughness * roughness;
    let r_inv = 1.0 / (roughness + 0.1);
    let a = -1.9362 + 1.0678 * roughness + 0.4573 * r2 - 0.8469 * r_inv;
    let b = -0.6014 + 0.5538 * roughness - 0.4670 * r2 - 0.1255 * r_inv;
    saturate((a * saturate(dot_nv) + b).exp())
}

/// three.js's `geometryRoughness` per pixel (lights_physical_fragment:7-8): the largest
/// component of max(|dFdx n|, |dFdy n|) of the view-space normal, the derivatives taken
/// within each 2×2 quad (fine: the pixel's own row and column of its quad) from the G-buffer's
/// normal; where the quad partner is not covered, from the neighbour on the other side.
fn geometry_roughness(g: &GBuffer, settings: &FrameSettings) -> Vec<f64> {
    let camera = &settings.camera;
    // The view rotation (right, up, back) of a right-handed look-at with +y up.
    let forward = (camera.target - camera.eye).as_dvec3().normalize();
    let right = forward.cross(DVec3::Y).normalize();
    let up = right.cross(forward);
    let (w, h) = (g.width as i64, g.height as i64);
    let covered = |x: i64, y: i64| {
        (0..w).contains(&x) && (0..h).contains(&y) && g.position[(y * w + x) as usize][3] > 0.5
    };
    let normal = |x: i64, y: i64| {
        let n = g.normal[(y * w + x) as usize];
        let n = DVec3::new(n[0] as f64, n[1] as f64, n[2] as f64);
        DVec3::new(n.dot(right), n.dot(up), -n.dot(forward))
    };
    let derivative = |x: i64, y: i64, dx: i64, dy: i64, partner: i64| {
        let (px, py) = (x + dx * partner, y + dy * partner);
        if covered(px, py) {
            (normal(px, py) - normal(x, y)) * partner as f64
        } else if covered(x - dx * partner, y - dy * partner) {
            (normal(x, y) - normal(x - dx * partner, y - dy * partner)) * partner as f64
        } else {
            DVec3::ZERO
        }
    };
    (0..w * h)
        .map(|i| {
            let (x, y) = (i % w, i / w);
            if !covered(x, y) {
                return 0.0;
            }
            // The partner within the quad: +1 for an even coordinate, −1 for an odd one.
            let sx = if x % 2 == 0 { 1 } else { -1 };
            let sy = if y % 2 == 0 { 1 } else { -1 };
            let ddx = derivative(x, y, 1, 0, sx).abs();
            let ddy = derivative(x, y, 0, 1, sy).abs();
            ddx.max(ddy).max_element()
        })
        .collect()
}

/// Linear radiance Σ_lights E·F of three.js's twin on the G-buffer, as
/// [`reference::shade_with`] builds each pixel's frame and lights (directional: colour ×
/// illuminance; point: colour × intensity / d², lights_pars_begin.glsl.js:56-70 with no
/// range, decay 2).
fn shade_three(
    g: &GBuffer,
    settings: &FrameSettings,
    material: &ThreeMaterial,
    geometry_roughness: &[f64],
) -> Vec<[f64; 3]> {
    let eye = settings.camera.eye.as_dvec3();
    let v = |a: [f32; 4]| DVec3::new(a[0] as f64, a[1] as f64, a[2] as f64);
    (0..g.position.len())
        .map(|i| {
            let p = g.position[i];
            if p[3] <= 0.5 {
                return [0.0; 3];
            }
            let position = v(p);
            let n = v(g.normal[i]).normalize();
            let t = (v(g.tangent[i]) - n * n.dot(v(g.tangent[i]))).normalize();
            let b = n.cross(t);
            let local = |w: DVec3| DVec3::new(w.dot(t), w.dot(b), w.dot(n));
            let wo = local((eye - position).normalize());
            let mut sum = DVec3::ZERO;
            for light in &settings.lights {
                let (direction, irradiance) = light.at(position);
                sum += irradiance * material.eval(local(direction), wo, geometry_roughness[i]);
            }
            sum.to_array()
        })
        .collect()
}

fn quantise(v: f32) -> u8 {
    (v.clamp(0.0, 1.0) * 255.0).round() as u8
}

fn display(radiance: [f64; 3]) -> [u8; 3] {
    tonemap(radiance.map(|c| c as f32), EXPOSURE).map(quantise)
}

/// The 99th percentile (nearest rank) of `values`.
fn p99(values: &mut [f64]) -> f64 {
    values.sort_by(f64::total_cmp);
    let rank = ((0.99 * values.len() as f64).ceil() as usize).clamp(1, values.len());
    values[rank - 1]
}

fn mean(values: &[f64]) -> f64 {
    values.iter().sum::<f64>() / values.len().max(1) as f64
}

/// What the commands made for one fabric.
struct Renders {
    name: String,
    gltf: PathBuf,
    three: PathBuf,
    clothbake: PathBuf,
    renderer: String,
    seconds: [f64; 3],
}

fn checked(what: &str, output: Output) -> Output {
    assert!(
        output.status.success(),
        "{what} failed ({}):\n{}",
        output.status,
        output_text(&output)
    );
    output
}

/// Exports `name`, then renders the .gltf with three.js and the fitted material with
/// clothbake, the two at once.
fn render_fabric(name: &str, dir: &Path, tool: &Path) -> Renders {
    let file = |suffix: &str| dir.join(format!("{name}{suffix}"));
    let (gltf, three, clothbake) = (file(".gltf"), file("-three.png"), file("-clothbake.png"));
    let bin = env!("CARGO_BIN_EXE_clothbake");
    let start = Instant::now();
    let exported = Command::new(bin)
        .args(["export", name, "--to", "gltf", "--out"])
        .arg(&gltf)
        .env("XDG_RUNTIME_DIR", std::env::temp_dir())
        .output()
        .expect("spawn clothbake export");
    checked(&format!("clothbake export {name}"), exported);
    let export_s = start.elapsed().as_secs_f64();
    // Every fabric's asset passes the Khronos validator (exit 1 on any error).
    let validated = Command::new("node")
        .arg(tool.join("validate-gltf.mjs"))
        .arg(&gltf)
        .output()
        .expect("spawn node");
    let report = checked(&format!("validate-gltf.mjs {name}.gltf"), validated);
    assert!(
        output_text(&report).contains("0 errors"),
        "{}",
        output_text(&report)
    );
    // The negative control renders a wrongly exported copy; the prediction reads the export.
    let shown = match std::env::var("CLOTHBAKE_EXPORT_THREEJS_SWAP") {
        Ok(swap) => swap_material(&gltf, &file("-swapped.gltf"), &swap),
        Err(_) => gltf.clone(),
    };
    let (width, height) = (WIDTH.to_string(), HEIGHT.to_string());
    let start = Instant::now();
    let node = Command::new("node")
        .arg(tool.join("render-gltf.mjs"))
        .args([&shown, &three])
        .args(["--width", &width, "--height", &height])
        .args(["--exposure", &EXPOSURE.to_string()])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("spawn node");
    let own = Command::new(bin)
        .args([
            "render",
            "--fabric",
            name,
            "--evaluator",
            "gltf",
            "--env",
            "none",
        ])
        .args([
            "--width", &width, "--height", &height, "--frames", "1", "--out",
        ])
        .arg(&clothbake)
        .env("XDG_RUNTIME_DIR", std::env::temp_dir())
        .output()
        .expect("spawn clothbake render");
    let own_s = start.elapsed().as_secs_f64();
    checked(
        &format!("clothbake render --fabric {name} --evaluator gltf"),
        own,
    );
    let node = checked(
        &format!("node render-gltf.mjs {name}.gltf"),
        node.wait_with_output().expect("node runs"),
    );
    let node_s = start.elapsed().as_secs_f64();
    let renderer = String::from_utf8_lossy(&node.stdout)
        .lines()
        .find_map(|l| l.strip_prefix("WebGL renderer: ").map(str::to_string))
        .unwrap_or_else(|| {
            panic!(
                "render-gltf.mjs printed no renderer:\n{}",
                output_text(&node)
            )
        });
    Renders {
        name: name.to_string(),
        gltf,
        three,
        clothbake,
        renderer,
        seconds: [export_s, own_s, node_s],
    }
}

/// The negative control: a wrongly exported material (by hand, see the notebook).
fn swap_material(path: &Path, out: &Path, swap: &str) -> PathBuf {
    let mut gltf: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let m = &mut gltf["materials"][0];
    match swap {
        "colours" => {
            let base = m["pbrMetallicRoughness"]["baseColorFactor"].clone();
            let sheen = m["extensions"]["KHR_materials_sheen"]["sheenColorFactor"].clone();
            m["pbrMetallicRoughness"]["baseColorFactor"] =
                serde_json::json!([sheen[0], sheen[1], sheen[2], 1.0]);
            m["extensions"]["KHR_materials_sheen"]["sheenColorFactor"] =
                serde_json::json!([base[0], base[1], base[2]]);
        }
        "roughness" => {
            let r = m["pbrMetallicRoughness"]["roughnessFactor"].clone();
            let s = m["extensions"]["KHR_materials_sheen"]["sheenRoughnessFactor"].clone();
            m["pbrMetallicRoughness"]["roughnessFactor"] = s;
            m["extensions"]["KHR_materials_sheen"]["sheenRoughnessFactor"] = r;
        }
        "rotation" => {
            let a = &mut m["extensions"]["KHR_materials_anisotropy"]["anisotropyRotation"];
            *a = serde_json::json!(a.as_f64().unwrap() + std::f64::consts::FRAC_PI_2);
        }
        other => panic!("CLOTHBAKE_EXPORT_THREEJS_SWAP={other}: colours, roughness or rotation"),
    }
    std::fs::write(out, serde_json::to_string(&gltf).unwrap()).unwrap();
    out.to_path_buf()
}

/// The comparison of one fabric's two renders.
struct Comparison {
    covered: usize,
    rim: usize,
    only_clothbake: usize,
    measured: [f64; 2],
    predicted: [f64; 2],
    own: [f64; 2],
    bound: [f64; 2],
    over: usize,
}

fn compare(
    renders: &Renders,
    gbuffer: &GBuffer,
    settings: &FrameSettings,
    dfg: &Dfg,
    roughness: &[f64],
) -> Comparison {
    let gltf: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&renders.gltf).unwrap()).unwrap();
    let material = material_of(&gltf);
    let spec = reference::shade_with(gbuffer, settings, |wi, wo| material.eval(wi, wo), None);
    let three = shade_three(
        gbuffer,
        settings,
        &ThreeMaterial::new(&material, dfg),
        roughness,
    );
    let (tw, th, three_png) = read_rgb(&renders.three);
    let (cw, ch, own_png) = read_rgb(&renders.clothbake);
    assert_eq!(
        (tw, th, cw, ch),
        (WIDTH, HEIGHT, WIDTH, HEIGHT),
        "{}",
        renders.name
    );
    let (w, h) = (WIDTH as i64, HEIGHT as i64);
    let both = |x: i64, y: i64| {
        (0..w).contains(&x) && (0..h).contains(&y) && {
            let i = (y * w + x) as usize;
            gbuffer.position[i][3] > 0.5 && three_png[i] != [0, 0, 0]
        }
    };
    let (mut covered, mut rim, mut only_clothbake) = (0, 0, 0);
    let (mut m, mut p, mut c, mut b) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let mut over = 0;
    for i in 0..(w * h) as usize {
        let (x, y) = (i as i64 % w, i as i64 / w);
        if gbuffer.position[i][3] > 0.5 && !both(x, y) {
            only_clothbake += 1;
        }
        if !both(x, y) {
            continue;
        }
        covered += 1;
        if ![(1, 0), (-1, 0), (0, 1), (0, -1)]
            .iter()
            .all(|&(dx, dy)| both(x + dx, y + dy))
        {
            rim += 1;
            continue;
        }
        let s = display(spec.pixels[i].map(f64::from)[..3].try_into().unwrap());
        let t = display(three[i]);
        for k in 0..3 {
            let d = |a: u8, b: u8| (a as f64 - b as f64).abs();
            let measured = d(own_png[i][k], three_png[i][k]);
            let bound = d(s[k], t[k]) + d(own_png[i][k], s[k]) + THREE_ROUNDING;
            over += usize::from(measured > bound);
            m.push(measured);
            p.push(d(s[k], t[k]));
            c.push(d(own_png[i][k], s[k]));
            b.push(bound);
        }
    }
    let stats = |v: &mut Vec<f64>| [mean(v), p99(v)];
    Comparison {
        covered,
        rim,
        only_clothbake,
        measured: stats(&mut m),
        predicted: stats(&mut p),
        own: stats(&mut c),
        bound: stats(&mut b),
        over,
    }
}

#[test]
fn the_exported_gltf_renders_in_threejs_as_clothbake_renders_its_material_within_the_model_difference()
 {
    let start = Instant::now();
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let tool = root.join("tools/export-check");
    let node = Command::new("node").arg("--version").output();
    assert!(
        node.as_ref().is_ok_and(|o| o.status.success()),
        "this test needs Node.js 20 or newer on PATH (`node`), which scripts/setup.sh installs: {:?}",
        node.map(|o| output_text(&o))
    );
    for package in ["three/package.json", "playwright-core/package.json"] {
        let path = tool.join("node_modules").join(package);
        assert!(
            path.is_file(),
            "this test needs {} (scripts/setup.sh, or by hand: cd tools/export-check && npm ci)",
            path.display()
        );
    }
    let dfg = Dfg::load(&tool.join("node_modules/three/src/renderers/shaders/DFGLUTData.js"));

    // The view of `clothbake render --env none`: the built-in scene's drape, camera and lights.
    let context = gpu_context();
    let scene = Scene::builtin();
    let mesh = Mesh::from_spec(&scene.mesh).expect("the built-in drape");
    let mut settings = FrameSettings::from_scene(&scene);
    settings.environment_samples = 0;
    assert_eq!(settings.exposure, EXPOSURE, "the built-in scene's exposure");
    let brdf = GpuConstant::new(&context);
    let mut headless = Headless::new(&context, &mesh, &brdf, WIDTH, HEIGHT).expect("targets");
    let gbuffer = headless.gbuffer(&context, &settings).expect("G-buffer");
    let roughness = geometry_roughness(&gbuffer, &settings);

    // The commands, two fabrics at a time (each export keeps both cores busy only part of the
    // time; node mostly waits on Chromium).
    let fabrics: Vec<String> = FabricSet::builtin()
        .fabrics()
        .iter()
        .map(|f| f.name.clone())
        .collect();
    let dir = temp_dir("export-threejs");
    let next = AtomicUsize::new(0);
    let done = Mutex::new(Vec::new());
    std::thread::scope(|s| {
        for _ in 0..2 {
            s.spawn(|| {
                while let Some(name) = fabrics.get(next.fetch_add(1, Ordering::SeqCst)) {
                    let renders = render_fabric(name, &dir, &tool);
                    done.lock().unwrap().push(renders);
                }
            });
        }
    });
    let mut all = done.into_inner().unwrap();
    all.sort_by_key(|r| fabrics.iter().position(|f| *f == r.name));

    println!(
        "{:<32} {:>7} {:>5} {:>6} | {:>13} {:>13} {:>13} {:>13} | {:>5} | export/clothbake/three s",
        "fabric",
        "covered",
        "rim",
        "cb only",
        "measured",
        "predicted",
        "clothbake own",
        "bound",
        "over"
    );
    let mut failures = Vec::new();
    for r in &all {
        let c = compare(r, &gbuffer, &settings, &dfg, &roughness);
        let pair = |v: [f64; 2]| format!("{:>5.2} / {:>4.0}", v[0], v[1]);
        println!(
            "{:<32} {:>7} {:>5} {:>6} | {} {} {} {} | {:>5} | {:.1}/{:.1}/{:.1}",
            r.name,
            c.covered,
            c.rim,
            c.only_clothbake,
            pair(c.measured),
            pair(c.predicted),
            pair(c.own),
            pair(c.bound),
            c.over,
            r.seconds[0],
            r.seconds[1],
            r.seconds[2],
        );
        println!("    WebGL renderer: {}", r.renderer);
        // Coverage: most of the drape is in view (the figures are in the notebook).
        if c.covered < 5_000 {
            failures.push(format!(
                "{}: only {} pixels covered by both",
                r.name, c.covered
            ));
        }
        if c.measured[0] > c.bound[0] || c.measured[1] > c.bound[1] {
            failures.push(format!(
                "{}: |clothbake − three.js| mean {:.2}, 99th percentile {:.0} levels; bound \
                 (predicted model difference + clothbake's own GPU-vs-CPU + {THREE_ROUNDING} \
                 rounding) mean {:.2}, 99th percentile {:.0}",
                r.name, c.measured[0], c.measured[1], c.bound[0], c.bound[1]
            ));
        }
    }
    println!(
        "{} fabrics in {:.1} s",
        all.len(),
        start.elapsed().as_secs_f64()
    );
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
