// The fragment shader of `ClothMaterial` (src/material.rs): Bevy's forward pass, shading cloth
// by a clothbake table. `ClothTable`'s loader (src/table_asset.rs) makes one shader per table:
// clothbake's composer (`clothbake::shader::Composer`) writes this file after what it requires
// below: the table's specialised lookup (the module `brdf` of
// `clothbake::table::wgsl::lookup_composer`: `cloth_brdf(wi, wo)` = F(wi, wo) of
// docs/model.md, its textures and sampler in the material's bind group), the environment
// light's sample taps (shaders/sampling/sample_taps.wgsl of clothbake, with its constants) and
// a directional light's disk at the horizon (shaders/lighting/source_disk.wgsl).
//
// Per fragment, as `clothbake render` (shaders/render/renderer.wgsl): the thread frame (t = thread 1
// along the mesh's UV tangent, b = n × t, n), flipped to the side facing the viewer (two-sided
// cloth); wi and wo in that frame; radiance L = Σ E·F(wi, wo)·shadow over Bevy's directional
// and point lights (a directional light set by the horizon over its `SunDisk`, as `clothbake
// render` sets an environment's sources: shaders/lighting/source_disk.wgsl), plus the ambient
// light L_a times the directional albedo ∫F dwi at wo (exact for a uniform ambient radiance),
// plus the view's environment map light by filtered importance sampling through the fabric's
// sample taps, as `clothbake render` does. E in Bevy's units: a directional light's illuminance
// (lux), a point light's luminous intensity (power/4π) times Bevy's inverse-square falloff with
// its range window. Then the camera's exposure, and tone mapping where Bevy does it in the
// shader.
//
// requires: brdf, sampling/sample_taps, lighting/source_disk

#import bevy_pbr::{
    forward_io::VertexOutput,
    mesh_view_bindings as view_bindings,
    mesh_view_types,
    clustered_forward as clustering,
    shadows,
    lighting::getDistanceAttenuation,
}
#ifdef TONEMAP_IN_SHADER
#import bevy_core_pipeline::tonemapping::tone_mapping
#endif

// The fabric's sample taps (`clothbake::sampling::SampleTaps::words`, built from the table
// for `DEFAULT_ENVIRONMENT_SAMPLES` per fragment).
@group(#{MATERIAL_BIND_GROUP}) @binding(9) var<storage, read> sampling_taps: array<vec4<u32>>;

// The directional albedo ∫F dwi (RGB) over wo in the cloth frame
// (`clothbake::sampling::AlbedoMap`): x = azimuth/2π from thread 1, y = (elevation/(π/2))^(2/3)
// (rows dense at the horizon), node centres at the texel centres (65 × 33 texels; the last
// column repeats the first).
@group(#{MATERIAL_BIND_GROUP}) @binding(8) var cloth_albedo_map: texture_2d<f32>;

fn cloth_ambient_albedo(wo: vec3<f32>) -> vec3<f32> {
    let size = vec2<f32>(textureDimensions(cloth_albedo_map));
    var azimuth = atan2(wo.y, wo.x);
    if azimuth < 0.0 {
        azimuth += 6.2831853;
    }
    let elevation = max(atan2(wo.z, length(wo.xy)), 0.0);
    let node = vec2<f32>(azimuth / 6.2831853, pow(elevation / 1.5707963, 2.0 / 3.0)) * (size - 1.0);
    return textureSampleLevel(cloth_albedo_map, cloth_sampler, (node + 0.5) / size, 0.0).rgb;
}

// Any unit vector orthogonal to unit n (a mesh without UV tangents, or a degenerate one).
fn cloth_perpendicular(n: vec3<f32>) -> vec3<f32> {
    var a = vec3<f32>(1.0, 0.0, 0.0);
    if abs(n.x) > 0.9 {
        a = vec3<f32>(0.0, 1.0, 0.0);
    }
    return normalize(a - n * dot(n, a));
}

#ifdef ENVIRONMENT_MAP
// `v` rotated by the unit quaternion `q` (xyz, w).
fn cloth_rotate(q: vec4<f32>, v: vec3<f32>) -> vec3<f32> {
    let t = 2.0 * cross(q.xyz, v);
    return v + q.w * t + cross(q.xyz, t);
}

// ∫ L_env(wi) F(wi, wo) dwi over the view's environment map light by filtered importance
// sampling (shaders/render/renderer.wgsl's `render_environment_light`, on a cubemap): the K
// sample taps of the tap nodes around wo (each a stratum of the fabric's sampler: its weight
// K·∫F dwi, read in the direction of F's centroid), each at the mip level that blurs the map
// about as the stratum's mean does (`sampling_lod`), Ωp = 4π/(6W²) the mean texel of a W × W
// face. Bevy's maps are prefiltered for GGX roughness rather than box-filtered, so their
// coarser levels blur more than the lod assumes.
fn cloth_environment_light(t: vec3<f32>, b: vec3<f32>, n: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    let probes = view_bindings::light_probes;
    if probes.view_cubemap_index < 0 {
        return vec3<f32>(0.0);
    }
#ifdef MULTIPLE_LIGHT_PROBES_IN_ARRAY
    let map = view_bindings::specular_environment_maps[probes.view_cubemap_index];
#else
    let map = view_bindings::specular_environment_map;
#endif
    let count = sampling_tap_count();
    let nodes = sampling_tap_nodes(wo);
    let width = f32(textureDimensions(map).x);
    let texel = 12.5663706 / (6.0 * width * width);
    let top = f32(textureNumLevels(map) - 1u);
    var sum = vec3<f32>(0.0);
    for (var k = 0u; k < count; k++) {
        let tap = sampling_tap(nodes, k, count);
        // World direction, rotated as Bevy rotates the view's map; cubemaps are left-handed.
        var d = cloth_rotate(probes.view_rotation, t * tap.wi.x + b * tap.wi.y + n * tap.wi.z);
        d.z = -d.z;
        let lod = clamp(sampling_lod(tap.log2_solid_angle, texel), 0.0, top);
        let radiance = textureSampleLevel(map, view_bindings::environment_map_sampler, d, lod).rgb;
        sum += radiance * tap.weight;
    }
    return sum * (probes.intensity_for_view / f32(max(count, 1u)));
}
#endif

@fragment
fn fragment(in: VertexOutput) -> @location(0) vec4<f32> {
    let view = view_bindings::view;
    let is_orthographic = view.clip_from_view[3].w == 1.0;
    var to_eye = normalize(view.world_position.xyz - in.world_position.xyz);
    if is_orthographic {
        to_eye = normalize(vec3<f32>(view.view_from_world[0].z, view.view_from_world[1].z, view.view_from_world[2].z));
    }
    var n = normalize(in.world_normal);
    if dot(n, to_eye) < 0.0 {
        n = -n;
    }
#ifdef VERTEX_TANGENTS
    var t = in.world_tangent.xyz - n * dot(n, in.world_tangent.xyz);
    if length(t) < 1e-6 {
        t = cloth_perpendicular(n);
    } else {
        t = normalize(t);
    }
#else
    let t = cloth_perpendicular(n);
#endif
    let b = cross(n, t);
    let wo = vec3<f32>(dot(to_eye, t), dot(to_eye, b), dot(to_eye, n));

    var radiance = view_bindings::lights.ambient_color.rgb * cloth_ambient_albedo(wo);
#ifdef ENVIRONMENT_MAP
    if wo.z > 0.0 {
        radiance += cloth_environment_light(t, b, n, wo);
    }
#endif

    let view_z = dot(vec4<f32>(
        view.view_from_world[0].z,
        view.view_from_world[1].z,
        view.view_from_world[2].z,
        view.view_from_world[3].z
    ), in.world_position);

    for (var i = 0u; i < view_bindings::lights.n_directional_lights; i++) {
        let light = &view_bindings::lights.directional_lights[i];
        let l = (*light).direction_to_light.xyz;
        // Bevy's `SunDisk` gives the disk's angular diameter (`SunDisk::EARTH`, the sun's,
        // for a light without one).
        let disk = source_disk_above_horizon(
            vec3<f32>(dot(l, t), dot(l, b), dot(l, n)),
            sin(0.5 * (*light).sun_disk_angular_size),
        );
        let wi = disk.xyz;
        if wi.z <= 0.0 || wo.z <= 0.0 {
            continue;
        }
        var shadow = 1.0;
        if ((*light).flags & mesh_view_types::DIRECTIONAL_LIGHT_FLAGS_SHADOWS_ENABLED_BIT) != 0u {
            shadow = shadows::fetch_directional_shadow(i, in.world_position, n, view_z, in.position.xy);
        }
        radiance += (*light).color.rgb * (disk.w * cloth_brdf(wi, wo)) * shadow;
    }

    let cluster_index = clustering::view_fragment_cluster_index(in.position.xy, view_z, is_orthographic);
    let ranges = clustering::unpack_clusterable_object_index_ranges(cluster_index);
    for (var i = ranges.first_point_light_index_offset; i < ranges.first_spot_light_index_offset; i++) {
        let light_id = clustering::get_clusterable_object_id(i);
        let light = &view_bindings::clustered_lights.data[light_id];
        let to_light = (*light).position_radius.xyz - in.world_position.xyz;
        let d2 = dot(to_light, to_light);
        let l = to_light * inverseSqrt(max(d2, 1e-12));
        let wi = vec3<f32>(dot(l, t), dot(l, b), dot(l, n));
        if wi.z <= 0.0 || wo.z <= 0.0 {
            continue;
        }
        var shadow = 1.0;
        if ((*light).flags & mesh_view_types::POINT_LIGHT_FLAGS_SHADOWS_ENABLED_BIT) != 0u {
            shadow = shadows::fetch_point_shadow(light_id, in.world_position, n, in.position.xy);
        }
        let irradiance = (*light).color_inverse_square_range.rgb
            * getDistanceAttenuation(d2, (*light).color_inverse_square_range.w);
        radiance += irradiance * cloth_brdf(wi, wo) * shadow;
    }

    var color = vec4<f32>(radiance * view.exposure, 1.0);
#ifdef TONEMAP_IN_SHADER
    color = tone_mapping(color, view.color_grading);
#endif
    return color;
}
