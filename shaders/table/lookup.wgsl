// Table lookup of F(wi, wo) (RGB), the part every layout shares. The lookup of a table is
// this file, then its layout's own WGSL file (shaders/table/<layout>.wgsl, e.g.
// thread_frame.wgsl, grid4d.wgsl), each mirroring the Rust lookup of src/table/<layout>.rs
// in f32.
//
// `clothbake::table::wgsl::lookup_wgsl` (the text of `GpuTable::wgsl` and of `clothbake wgsl`)
// specialises them for one table: the composer (src/shader/mod.rs) writes first the generated
// module `table_constants`, holding everything the table's geometry fixes (fabric constants;
// the layout's axes, texel counts and frames as literals, from `TableLookup::wgsl_constants`
// of the layout), then this file, the layout's file (and what it requires), and the generated
// module `brdf`: `cloth_brdf(wi, wo)` calling the layout's `cloth_<layout>_brdf`.
// `table_constants` always defines `CLOTH_ALBEDO1`, `CLOTH_ALBEDO2` (vec3<f32>, the thread
// albedos A_j, albedo scale applied); each layout file lists what else it expects.
// Specialising leaves no uniform block and no branch on table parameters: the shader
// compiler folds the literals into the generic functions.
//
// Bindings are in the BRDF's group, written with the placeholder `CLOTH_BRDF_GROUP` that the
// composer binds (0 for a `GpuBrdf`, the material's group in an engine).
//
// Every top-level name starts with `cloth_`, `Cloth` or `CLOTH_` (the `GpuBrdf` naming
// contract, src/gpu/mod.rs).
//
// requires: table_constants

// Linear filtering, clamp-to-edge on every axis, no mipmaps.
@group(CLOTH_BRDF_GROUP) @binding(3) var cloth_sampler: sampler;

// `Table::lookup`: F = reflection + A1·transmission1 + A2·transmission2.
fn cloth_combine(terms: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(terms.x) + CLOTH_ALBEDO1 * terms.y + CLOTH_ALBEDO2 * terms.z;
}
