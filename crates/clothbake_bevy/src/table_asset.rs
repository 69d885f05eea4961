//! [`ClothTable`]: a clothbake table file (`clothbake bake`'s EXR) as a Bevy asset, and its
//! loader.
//!
//! The loader validates the file as `clothbake check` does (`read_table_bytes`: headers
//! before any allocation sized by them, the provenance hash, the texel checksum; a bad file is
//! Bevy's usual asset load error, naming the file and what is wrong) and turns it into labeled
//! sub-assets that a [`crate::ClothMaterial`] binds:
//!
//! | label | asset | what |
//! |---|---|---|
//! | `binding4` … `binding7` | [`Image`] | one per slot of clothbake's table bindings (`clothbake::table::bindings::TEXTURE_SLOTS`, labeled by binding): the layout's texture there (`TableLookup::textures`), f16; a 1-texel stand-in where the layout has none |
//! | `albedo` | [`Image`] | the directional albedo ∫F dwi over wo (`clothbake::sampling::AlbedoMap`), for ambient light |
//! | `sampling` | [`ShaderBuffer`] | the fabric's sample taps built from the table for [`crate::DEFAULT_ENVIRONMENT_SAMPLES`] per fragment (`clothbake::sampling::SampleTaps::words`), for environment map light |
//! | `shader` | [`Shader`] | `cloth_material.wgsl` composed with the table's specialised lookup and the sample taps' functions |

use bevy::asset::io::Reader;
use bevy::asset::{AssetLoader, LoadContext, RenderAssetUsages};
use bevy::image::ImageSampler;
use bevy::prelude::*;
use bevy::render::render_resource::{
    Extent3d, TextureDimension, TextureFormat, TextureViewDescriptor, TextureViewDimension,
};
use bevy::render::storage::ShaderBuffer;
use bevy::shader::Shader;
use bevy::tasks::futures_lite::AsyncReadExt;
use clothbake::formats::table_exr::{MAX_TABLE_FILE_BYTES, TableFileError, read_table_bytes};
use clothbake::sampling::{
    ALBEDO_MAP_AZIMUTHS, ALBEDO_MAP_ELEVATIONS, AlbedoMap, SampleTaps, Sampler,
};
use clothbake::shader;
use clothbake::table::TextureData;
use clothbake::table::bindings::{SlotDimension, TEXTURE_SLOTS, TextureSlot};
use clothbake::table::wgsl::lookup_composer;

/// The fragment shader, composed by clothbake's composer after the modules its header
/// requires (the table's lookup and the fabric sampler).
const MATERIAL_WGSL: &str = include_str!("cloth_material.wgsl");
/// Its name as a generated module of the composer.
const MATERIAL_MODULE: &str = "cloth_material";

/// The view dimension of a texture slot of clothbake's table bindings.
pub(crate) fn view_dimension(slot: TextureSlot) -> TextureViewDimension {
    match slot.dimension {
        SlotDimension::D3 => TextureViewDimension::D3,
        SlotDimension::D2Array => TextureViewDimension::D2Array,
    }
}

/// Importance samples per node of the albedo map: its nodes' standard errors are then
/// 0.1–0.3% of the albedo (the sampler's variance is 100–470× below cosine sampling).
pub const ALBEDO_SAMPLES: usize = 256;

/// A loaded clothbake table: the handles of its sub-assets and what the file records.
#[derive(Asset, TypePath, Clone, Debug)]
pub struct ClothTable {
    /// The fabric's name in the table's provenance.
    pub fabric: String,
    /// The table layout (a name of `clothbake::table::Layout::ALL`) and its resolution.
    pub layout: String,
    pub resolution: u32,
    /// The textures of clothbake's table slots (`clothbake::table::bindings::TEXTURE_SLOTS`),
    /// in their order, at their bindings of the material's bind group.
    pub textures: [Handle<Image>; TEXTURE_SLOTS.len()],
    /// The directional albedo map (binding 8).
    pub albedo: Handle<Image>,
    /// The fabric's sampler (binding 9).
    pub sampling: Handle<ShaderBuffer>,
    /// The fragment shader with this table's lookup.
    pub shader: Handle<Shader>,
}

/// Why a table could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum ClothTableError {
    #[error("cannot read the table: {0}")]
    Io(#[from] std::io::Error),
    #[error(transparent)]
    Table(#[from] TableFileError),
    #[error(
        "table {path}: texture at binding {binding} has {channels} channels (1, 2 or 4 expected)"
    )]
    Channels {
        path: String,
        binding: u32,
        channels: u32,
    },
}

/// Loads clothbake tables (`.exr`) as [`ClothTable`]s. Bevy's own EXR image loader (the
/// `exr` feature, off by default) claims the extension too; load tables as `ClothTable`
/// (`asset_server.load::<ClothTable>(…)`) and Bevy picks this loader by type.
#[derive(Default, TypePath)]
pub struct ClothTableLoader;

impl AssetLoader for ClothTableLoader {
    type Asset = ClothTable;
    type Settings = ();
    type Error = ClothTableError;

    async fn load(
        &self,
        reader: &mut dyn Reader,
        _settings: &(),
        load_context: &mut LoadContext<'_>,
    ) -> Result<ClothTable, ClothTableError> {
        // At most one byte more than any table: a larger file is refused without being
        // read into memory.
        let mut bytes = Vec::new();
        reader
            .take(MAX_TABLE_FILE_BYTES + 1)
            .read_to_end(&mut bytes)
            .await?;
        let path = load_context.path().to_string();
        let file = read_table_bytes(&bytes, load_context.path().path())?;
        drop(bytes);
        let table = &file.table;

        let planes = table.geometry().textures(table.planes());
        let mut textures = Vec::with_capacity(TEXTURE_SLOTS.len());
        for slot in TEXTURE_SLOTS {
            let (binding, dimension) = (slot.binding, view_dimension(slot));
            let image = match planes.iter().find(|t| t.binding == binding) {
                Some(texture) => {
                    table_image(texture, dimension).ok_or_else(|| ClothTableError::Channels {
                        path: path.clone(),
                        binding,
                        channels: texture.channels,
                    })?
                }
                None => stand_in_image(dimension),
            };
            textures.push(load_context.add_labeled_asset(format!("binding{binding}"), image));
        }

        let sampler = Sampler::for_table(table);
        let albedo = AlbedoMap::build(
            &sampler,
            |wi, wo| clothbake::measure::accuracy::lookup_f32(table, wi, wo),
            ALBEDO_SAMPLES,
        );
        let albedo = load_context.add_labeled_asset("albedo", albedo_image(&albedo));
        let taps = SampleTaps::for_table(table, &sampler, crate::DEFAULT_ENVIRONMENT_SAMPLES);
        let data: Vec<u8> = taps.words().iter().flat_map(|v| v.to_le_bytes()).collect();
        let sampling = load_context.add_labeled_asset(
            "sampling",
            ShaderBuffer::new(&data, RenderAssetUsages::RENDER_WORLD),
        );

        // The table's bindings in the material's group, a value Bevy's preprocessor
        // substitutes.
        let source = lookup_composer(table)
            .brdf_group("#{MATERIAL_BIND_GROUP}")
            .module(shader::SAMPLER_CONSTANTS, Sampler::wgsl_constants())
            .module(MATERIAL_MODULE, MATERIAL_WGSL)
            .compose(&[MATERIAL_MODULE])
            .expect("the material's modules compose");
        let shader = load_context.add_labeled_asset(
            "shader",
            Shader::from_wgsl(source, format!("{path}#shader")),
        );

        Ok(ClothTable {
            fabric: table.fabric.name.clone(),
            layout: table.layout.name().to_string(),
            resolution: table.resolution,
            textures: textures.try_into().expect("one handle per slot"),
            albedo,
            sampling,
            shader,
        })
    }

    fn extensions(&self) -> &[&str] {
        &["exr"]
    }
}

/// An image sampled by the lookup's sampler: linear, clamp to edge, no mipmaps.
fn texture_image(
    size: [u32; 3],
    format: TextureFormat,
    view: TextureViewDimension,
    data: Vec<u8>,
) -> Image {
    let dimension = match view {
        TextureViewDimension::D3 => TextureDimension::D3,
        _ => TextureDimension::D2,
    };
    let extent = Extent3d {
        width: size[0],
        height: size[1],
        depth_or_array_layers: size[2],
    };
    let mut image = Image::new(
        extent,
        dimension,
        data,
        format,
        RenderAssetUsages::RENDER_WORLD,
    );
    // A 2D array of one layer would otherwise get a plain 2D view.
    image.texture_view_descriptor = Some(TextureViewDescriptor {
        dimension: Some(view),
        ..default()
    });
    image.sampler = ImageSampler::linear();
    image
}

fn f16_bytes(values: impl IntoIterator<Item = half::f16>) -> Vec<u8> {
    values
        .into_iter()
        .flat_map(|v| v.to_bits().to_le_bytes())
        .collect()
}

/// The image of one of the layout's textures, or `None` for an unsupported channel count.
fn table_image(texture: &TextureData, view: TextureViewDimension) -> Option<Image> {
    let format = match texture.channels {
        1 => TextureFormat::R16Float,
        2 => TextureFormat::Rg16Float,
        4 => TextureFormat::Rgba16Float,
        _ => return None,
    };
    Some(texture_image(
        texture.size,
        format,
        view,
        f16_bytes(texture.texels.iter().copied()),
    ))
}

/// One zero texel for a binding the layout does not use (the bind group layout is the same
/// for every table; the shader does not declare it).
fn stand_in_image(view: TextureViewDimension) -> Image {
    texture_image(
        [1, 1, 1],
        TextureFormat::R16Float,
        view,
        f16_bytes([half::f16::ZERO]),
    )
}

fn albedo_image(map: &AlbedoMap) -> Image {
    let texels = map
        .rgb
        .iter()
        .flat_map(|&[r, g, b]| [r, g, b, 1.0].map(half::f16::from_f32));
    texture_image(
        [ALBEDO_MAP_AZIMUTHS as u32, ALBEDO_MAP_ELEVATIONS as u32, 1],
        TextureFormat::Rgba16Float,
        TextureViewDimension::D2,
        f16_bytes(texels),
    )
}
