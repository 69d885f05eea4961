//! The bind group of a table's lookup, declared once: the sampler's binding and the texture
//! slots that layouts fill, each with its view dimension. A layout's WGSL file declares the
//! textures it uses at these bindings and its [`super::TableLookup::textures`] gives them
//! (the tests of every registered layout check both against this list); whoever binds a
//! table (the GPU table upload, an engine's material) builds its bind group layout from it.
//! All are in the BRDF's group (`CLOTH_BRDF_GROUP`, see [`crate::shader`]).

use super::TextureData;

/// How a texture slot is viewed by the shader.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SlotDimension {
    /// `texture_3d<f32>`.
    D3,
    /// `texture_2d_array<f32>`.
    D2Array,
}

/// One texture binding a layout may use: filterable float texels, read through the sampler at
/// [`SAMPLER_BINDING`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TextureSlot {
    pub binding: u32,
    pub dimension: SlotDimension,
}

impl TextureSlot {
    const fn new(binding: u32, dimension: SlotDimension) -> Self {
        Self { binding, dimension }
    }

    /// Whether the slot holds a 3D texture (else a 2D array texture).
    pub fn three_d(self) -> bool {
        self.dimension == SlotDimension::D3
    }
}

/// The binding of the lookup's sampler: linear filtering, clamp to edge, no mipmaps.
pub const SAMPLER_BINDING: u32 = 3;

/// The slots of 3D textures (a layout's per-thread 4D tables, one each).
pub const VOLUME_SLOTS: [TextureSlot; 2] = [
    TextureSlot::new(4, SlotDimension::D3),
    TextureSlot::new(5, SlotDimension::D3),
];

/// The slots of 2D array textures: the first for per-thread 2D tables as layers, the second
/// for a whole table of 2D layers.
pub const ARRAY_SLOTS: [TextureSlot; 2] = [
    TextureSlot::new(6, SlotDimension::D2Array),
    TextureSlot::new(7, SlotDimension::D2Array),
];

/// Every texture slot, in binding order: a table's textures are at some of these, and a bind
/// group layout that serves every layout has all of them.
pub const TEXTURE_SLOTS: [TextureSlot; 4] = [
    VOLUME_SLOTS[0],
    VOLUME_SLOTS[1],
    ARRAY_SLOTS[0],
    ARRAY_SLOTS[1],
];

/// One zero texel in `slot`, for a texture that a layout's WGSL declares and a table does
/// not fill (the lookup never reads it).
pub fn stand_in_texture(slot: TextureSlot) -> TextureData {
    TextureData {
        name: format!("unused{}", slot.binding),
        binding: slot.binding,
        three_d: slot.three_d(),
        size: [1, 1, 1],
        channels: 1,
        texels: vec![half::f16::ZERO],
    }
}

/// The slot at `binding`, if one is declared.
pub fn slot(binding: u32) -> Option<TextureSlot> {
    TEXTURE_SLOTS.into_iter().find(|s| s.binding == binding)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::table::Layout;

    #[test]
    fn slots_are_distinct_and_leave_the_sampler_alone() {
        let mut bindings: Vec<u32> = TEXTURE_SLOTS.iter().map(|s| s.binding).collect();
        bindings.push(SAMPLER_BINDING);
        bindings.sort_unstable();
        bindings.dedup();
        assert_eq!(bindings.len(), TEXTURE_SLOTS.len() + 1, "{bindings:?}");
    }

    /// Every registered layout's textures, for every built-in fabric, are at declared slots
    /// (each at most once) and have the slot's dimension.
    #[test]
    fn every_layout_fills_declared_slots_only() {
        for fabric in crate::formats::fabric_toml::FabricSet::builtin().fabrics() {
            for &layout in Layout::ALL {
                let resolution = layout.resolution_ladder()[0];
                let table = crate::table::zero_table(fabric, layout, resolution);
                let textures = table.geometry().textures(table.planes());
                let mut used = Vec::new();
                for texture in &textures {
                    let Some(slot) = slot(texture.binding) else {
                        panic!(
                            "{layout} {}: texture {} at undeclared binding {}",
                            fabric.name, texture.name, texture.binding
                        )
                    };
                    assert_eq!(
                        texture.three_d,
                        slot.three_d(),
                        "{layout} {}: {}",
                        fabric.name,
                        texture.name
                    );
                    assert!(!used.contains(&slot.binding), "{layout}: binding reused");
                    used.push(slot.binding);
                }
            }
        }
    }
}
