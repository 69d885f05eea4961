// A stock material's uniform block (`StockBlock` of gpu.rs beside this file): its parameter
// values in the order of its model's parameter list, and the constants it derives from them;
// and `cloth_brdf` of every stock model: the horizon test and the half vector, then the
// model's `cloth_stock_f(l, v, h)` (`StockMaterial::eval` and `StockModel::eval` in mod.rs).
// Every top-level name starts with `cloth_`/`Cloth` (the `GpuBrdf` naming contract).

struct ClothStockBlock {
    parameters: array<vec4<f32>, 4>,
    derived: array<vec4<f32>, 8>,
}

@group(CLOTH_BRDF_GROUP) @binding(0) var<uniform> cloth_stock: ClothStockBlock;

// Parameter `i` of the model's list.
fn cloth_stock_parameter(i: u32) -> f32 {
    return cloth_stock.parameters[i / 4u][i % 4u];
}

// The colour of parameters i, i + 1, i + 2.
fn cloth_stock_colour(i: u32) -> vec3<f32> {
    return vec3<f32>(
        cloth_stock_parameter(i),
        cloth_stock_parameter(i + 1u),
        cloth_stock_parameter(i + 2u),
    );
}

// Derived constant `i`.
fn cloth_stock_derived(i: u32) -> f32 {
    return cloth_stock.derived[i / 4u][i % 4u];
}

fn cloth_brdf(wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    if wi.z <= 0.0 || wo.z <= 0.0 {
        return vec3<f32>(0.0);
    }
    return cloth_stock_f(wi, wo, normalize(wi + wo));
}
