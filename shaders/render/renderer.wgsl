// The cloth render pass (src/render/renderer.rs): after a GpuBrdf's WGSL (the generated module
// `brdf`), which defines `cloth_brdf(wi, wo)` = F(wi, wo) (docs/model.md) in the local cloth
// frame with its bindings in @group(0), and the environment light's sample taps
// (shaders/sampling/sample_taps.wgsl). This file's own resources are in @group(1) (the
// frame) and @group(2) (the environment light: its map and the fabric's taps); its names
// avoid the `cloth_` and `sampling_` prefixes of those modules.
//
// Per pixel: the thread frame (t = thread 1 along u, b = n × t, n) from the interpolated
// vertex frame, re-orthonormalised; wi (to each light) and wo (to the eye) in that frame;
// radiance L = Σ_lights E·F(wi, wo), with E = colour·irradiance for a directional light and
// colour·I/d² for a point light (docs/model.md: a distant light of perpendicular irradiance E
// gives L_o = E·F; F already holds every cosine), plus the environment light: its compact
// bright sources (sun, lamps) are directional lights in the same list
// (src/lighting/bright_sources.rs), each set by the horizon over its disk
// (shaders/lighting/source_disk.wgsl), and the rest of the map, ∫ L_residual(wi) F(wi, wo)
// dwi, is integrated by filtered importance sampling (`render_environment_light`).
// No shadows.
//
// Two-sided cloth: the side facing the viewer is shaded, judged by the interpolated normal
// (n is flipped when n·wo < 0, so wo.z ≥ 0 always; t is kept, so the flipped frame is still
// right-handed with y = n × t). Lights on the other side of the cloth give nothing (wi.z ≤ 0:
// the model's one-sided patch).
//
// requires: brdf, sampling/sample_taps, lighting/source_disk

// One light: vector.w = 0: directional, vector.xyz the unit direction towards it;
// vector.w = 1: point, vector.xyz its position. power.rgb = colour·irradiance (directional)
// or colour·intensity (point); power.w = sin of the angular radius of a directional
// light's disk (an environment's source; 0 for the scene's lights).
struct RenderLight {
    vector: vec4<f32>,
    power: vec4<f32>,
}

// `FrameUniform` in src/render/mod.rs.
struct RenderFrameUniform {
    view_proj: mat4x4<f32>,
    inverse_view_proj: mat4x4<f32>,
    // xyz: the eye position.
    eye: vec4<f32>,
    // x: exposure; y: 1 to encode the display output as sRGB in the shader (UNORM targets),
    // 0 when the target format encodes it (…Srgb formats).
    params: vec4<f32>,
    // x: number of lights; y: environment samples per pixel K (0: no environment light),
    // the number the sample taps were built for.
    counts: vec4<u32>,
    // The environment map: x, y: level-0 width and height; z: mip levels; w: its rotation
    // about +y, radians (the light from world direction d is the map's at R_y(−w)·d).
    environment: vec4<f32>,
    // The scene's lights (at most 8), then the environment's sources (at most 8).
    lights: array<RenderLight, 16>,
}

@group(1) @binding(0) var<uniform> render_frame: RenderFrameUniform;

// The environment map (equirectangular, +y up, `clothbake::environment`; mip level k is
// level 0 box-filtered 2^k times by solid angle), its trilinear sampler, and the fabric's
// sample taps (`clothbake::sampling::SampleTaps::words`).
@group(2) @binding(0) var render_environment: texture_2d<f32>;
@group(2) @binding(1) var render_environment_sampler: sampler;
@group(2) @binding(2) var<storage, read> sampling_taps: array<vec4<u32>>;

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) tangent: vec3<f32>,
    @location(3) uv: vec2<f32>,
}

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) tangent: vec3<f32>,
}

@vertex
fn vs_main(in: VertexIn) -> VertexOut {
    var out: VertexOut;
    out.clip = render_frame.view_proj * vec4<f32>(in.position, 1.0);
    out.world = in.position;
    out.normal = in.normal;
    out.tangent = in.tangent;
    return out;
}

// The orthonormal thread frame of a pixel (columns t, b, n in world space).
struct ShadingFrame {
    t: vec3<f32>,
    b: vec3<f32>,
    n: vec3<f32>,
}

// Any unit vector orthogonal to unit n (for the rare pixel whose interpolated tangent is
// parallel to the normal).
fn render_perpendicular(n: vec3<f32>) -> vec3<f32> {
    var a = vec3<f32>(1.0, 0.0, 0.0);
    if abs(n.x) > 0.9 {
        a = vec3<f32>(0.0, 1.0, 0.0);
    }
    return normalize(a - n * dot(n, a));
}

fn shading_frame(in: VertexOut) -> ShadingFrame {
    let wo = normalize(render_frame.eye.xyz - in.world);
    var n = in.normal;
    let n_length = length(n);
    if n_length < 1e-12 {
        n = wo;
    } else {
        n = n / n_length;
    }
    if dot(n, wo) < 0.0 {
        n = -n;
    }
    // Gram-Schmidt: the tangent's component orthogonal to n (interpolation tilts it).
    var t = in.tangent - n * dot(n, in.tangent);
    let t_length = length(t);
    if t_length < 1e-6 {
        t = render_perpendicular(n);
    } else {
        t = t / t_length;
    }
    return ShadingFrame(t, cross(n, t), n);
}

fn to_local(f: ShadingFrame, w: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(dot(w, f.t), dot(w, f.b), dot(w, f.n));
}

// (cos, sin) of the environment's rotation about +y: computed once per fragment.
fn render_environment_turn() -> vec2<f32> {
    return vec2<f32>(cos(render_frame.environment.w), sin(render_frame.environment.w));
}

// The equirectangular coordinates of the map's texel seen in world direction `world`: the
// direction turned back by the environment's rotation (`turn`, from
// `render_environment_turn`), then mapped as `clothbake::lighting::equirect_uv` (+y up;
// u = 0.5 looks along −z).
fn render_environment_uv(world: vec3<f32>, turn: vec2<f32>) -> vec2<f32> {
    let c = turn.x;
    let s = turn.y;
    let d = vec3<f32>(c * world.x - s * world.z, world.y, s * world.x + c * world.z);
    let u = 0.5 + atan2(d.x, -d.z) * (0.5 / 3.14159265);
    let v = acos(clamp(d.y, -1.0, 1.0)) * (1.0 / 3.14159265);
    return vec2<f32>(u, v);
}

// ∫ L_env(wi) F(wi, wo) dwi as a sum over K strata of the hemisphere, each stratum's ∫F dwi
// times the map filtered over it (src/sampling/taps.rs: the strata for a grid of wo,
// computed once per fabric and shared by every pixel, so the error is a smooth bias rather
// than noise): one fetch per stratum, in the direction of F's centroid in it, at the mip
// level whose bilinear fetch blurs the map about as the stratum's mean does,
// lod = ½·log2(Ωs/Ωp) − ½ for a stratum of solid angle Ωs (`sampling_lod`, which derives it
// from filtered importance sampling's ½·log2(Ωs/Ωp), Colbert and Křivánek, GPU Gems 3,
// ch. 20); Ωp = (2π/W)(π/H)·sin θ a level-0 texel at the tap's polar angle θ.
fn render_environment_light(f: ShadingFrame, wo: vec3<f32>) -> vec3<f32> {
    let turn = render_environment_turn();
    let count = render_frame.counts.y;
    let size = render_frame.environment;
    let nodes = sampling_tap_nodes(wo);
    var sum = vec3<f32>(0.0);
    for (var k = 0u; k < count; k++) {
        let tap = sampling_tap(nodes, k, count);
        let world = f.t * tap.wi.x + f.b * tap.wi.y + f.n * tap.wi.z;
        let sin_theta = sqrt(max(1.0 - world.y * world.y, 1e-8));
        let texel = (6.2831853 / size.x) * (3.14159265 / size.y) * sin_theta;
        let lod = clamp(sampling_lod(tap.log2_solid_angle, texel), 0.0, size.z - 1.0);
        let radiance = textureSampleLevel(
            render_environment,
            render_environment_sampler,
            render_environment_uv(world, turn),
            lod,
        ).rgb;
        sum += radiance * tap.weight;
    }
    return sum / f32(max(count, 1u));
}

// Outgoing radiance towards the eye (linear RGB).
fn render_radiance(in: VertexOut) -> vec3<f32> {
    let f = shading_frame(in);
    let wo = to_local(f, normalize(render_frame.eye.xyz - in.world));
    var sum = vec3<f32>(0.0);
    if wo.z > 0.0 && render_frame.counts.y > 0u {
        sum = render_environment_light(f, wo);
    }
    for (var k = 0u; k < render_frame.counts.x; k++) {
        let light = render_frame.lights[k];
        var direction = light.vector.xyz;
        var irradiance = light.power.rgb;
        if light.vector.w != 0.0 {
            let d = light.vector.xyz - in.world;
            let d2 = max(dot(d, d), 1e-12);
            direction = d * inverseSqrt(d2);
            irradiance = irradiance / d2;
        }
        let disk = source_disk_above_horizon(to_local(f, direction), light.power.w);
        if disk.z > 0.0 && wo.z > 0.0 {
            sum += irradiance * (disk.w * cloth_brdf(disk.xyz, wo));
        }
    }
    return sum;
}

// sRGB transfer function (IEC 61966-2-1) of a value in [0, 1].
fn render_srgb(c: vec3<f32>) -> vec3<f32> {
    let low = c * 12.92;
    let high = 1.055 * pow(c, vec3<f32>(1.0 / 2.4)) - 0.055;
    return select(high, low, c <= vec3<f32>(0.0031308));
}

// Tone mapping, mirrored by `render::image::tonemap`: exposure, then the ACES filmic curve
// fit x(2.51x + 0.03)/(x(2.43x + 0.59) + 0.14) clamped to [0, 1], then sRGB (here or by
// the target format).
fn render_tonemap(radiance: vec3<f32>) -> vec3<f32> {
    let x = max(radiance * render_frame.params.x, vec3<f32>(0.0));
    let mapped = clamp(
        (x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14),
        vec3<f32>(0.0),
        vec3<f32>(1.0),
    );
    if render_frame.params.y > 0.5 {
        return render_srgb(mapped);
    }
    return mapped;
}

@fragment
fn fs_display(in: VertexOut) -> @location(0) vec4<f32> {
    return vec4<f32>(render_tonemap(render_radiance(in)), 1.0);
}

struct DisplayAndLinear {
    @location(0) display: vec4<f32>,
    // Linear radiance; alpha 1 marks covered pixels (the clear value has alpha 0).
    @location(1) linear: vec4<f32>,
}

@fragment
fn fs_display_linear(in: VertexOut) -> DisplayAndLinear {
    let radiance = render_radiance(in);
    return DisplayAndLinear(vec4<f32>(render_tonemap(radiance), 1.0), vec4<f32>(radiance, 1.0));
}

// The environment behind the cloth: a triangle covering the screen, drawn before the cloth,
// each pixel the map's level-0 radiance along its camera ray, tone mapped (the display
// target only: the linear target keeps radiance 0 and coverage 0 there).
struct BackgroundOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) ndc: vec2<f32>,
}

@vertex
fn vs_background(@builtin(vertex_index) index: u32) -> BackgroundOut {
    let ndc = vec2<f32>(f32(index & 1u) * 4.0 - 1.0, f32(index >> 1u) * 4.0 - 1.0);
    return BackgroundOut(vec4<f32>(ndc, 1.0, 1.0), ndc);
}

@fragment
fn fs_background(in: BackgroundOut) -> @location(0) vec4<f32> {
    // Any depth between the planes gives a point on the pixel's ray.
    let point = render_frame.inverse_view_proj * vec4<f32>(in.ndc, 0.5, 1.0);
    let ray = normalize(point.xyz / point.w - render_frame.eye.xyz);
    let radiance = textureSampleLevel(
        render_environment,
        render_environment_sampler,
        render_environment_uv(ray, render_environment_turn()),
        0.0,
    ).rgb;
    return vec4<f32>(render_tonemap(radiance), 1.0);
}

// The G-buffer of the CPU reference: what `render_radiance` starts from, per pixel.
struct GBufferOut {
    // xyz: world position; w = 1 marks covered pixels.
    @location(0) position: vec4<f32>,
    @location(1) tangent: vec4<f32>,
    @location(2) normal: vec4<f32>,
}

@fragment
fn fs_gbuffer(in: VertexOut) -> GBufferOut {
    let f = shading_frame(in);
    return GBufferOut(vec4<f32>(in.world, 1.0), vec4<f32>(f.t, 0.0), vec4<f32>(f.n, 0.0));
}
