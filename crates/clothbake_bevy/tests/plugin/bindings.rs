//! The material's bind group layout holds clothbake's table bindings exactly as the core
//! declares them (`clothbake::table::bindings`): Bevy's `AsBindGroup` derive takes binding
//! numbers and dimensions as literals, and this pins those literals to the core's list.

use crate::common::{headless_app, scratch};
use bevy::render::render_resource::{
    AsBindGroup, BindingType, SamplerBindingType, TextureViewDimension,
};
use bevy::render::renderer::RenderDevice;
use clothbake::table::bindings::{SAMPLER_BINDING, SlotDimension, TEXTURE_SLOTS};
use clothbake_bevy::ClothMaterial;

#[test]
fn material_layout_binds_the_core_table_slots() {
    let mut app = headless_app(&scratch("bindings"));
    app.finish();
    app.cleanup();
    let device = app.world().resource::<RenderDevice>();
    let entries = ClothMaterial::bind_group_layout_entries(device, false);
    let entry = |binding: u32| {
        entries
            .iter()
            .find(|e| e.binding == binding)
            .unwrap_or_else(|| panic!("no binding {binding} in {entries:#?}"))
    };
    for slot in TEXTURE_SLOTS {
        let want = match slot.dimension {
            SlotDimension::D3 => TextureViewDimension::D3,
            SlotDimension::D2Array => TextureViewDimension::D2Array,
        };
        let found = entry(slot.binding);
        assert!(
            matches!(found.ty, BindingType::Texture { view_dimension, .. } if view_dimension == want),
            "slot {slot:?}: {found:?}"
        );
    }
    assert!(
        matches!(
            entry(SAMPLER_BINDING).ty,
            BindingType::Sampler(SamplerBindingType::Filtering)
        ),
        "{:?}",
        entry(SAMPLER_BINDING)
    );
    // Besides the table's: the albedo map and the sample taps, at bindings of their own.
    let mut bindings: Vec<u32> = entries.iter().map(|e| e.binding).collect();
    bindings.sort_unstable();
    bindings.dedup();
    assert_eq!(bindings.len(), entries.len(), "{bindings:?}");
    assert_eq!(entries.len(), TEXTURE_SLOTS.len() + 1 + 2, "{bindings:?}");
}
