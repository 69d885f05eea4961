//! The textures the renderer draws into: their formats, what the device can render to, and
//! one offscreen target. Shared by the renderer, which only records into targets it is
//! given, and the headless path, which makes them and reads them back.

use crate::gpu::{GpuContext, GpuError};

/// Depth buffer format of every pass.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// Format of the linear-radiance target (alpha = coverage) where the device can render to
/// it (Vulkan, Metal, DX12); see [`linear_format`].
pub const LINEAR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
/// The fallback linear format (wgpu's GL backend cannot render to 32-bit float): relative
/// rounding 2^-11, largest value 65504.
pub const LINEAR_FORMAT_F16: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// Format of the three G-buffer targets (position, tangent, normal): 32-bit only, as f16
/// positions would move the reference's directions by ~1e-3 rad.
pub const GBUFFER_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

/// Fails with a clear message where the device cannot render to [`GBUFFER_FORMAT`].
pub(super) fn check_gbuffer_support(context: &GpuContext) -> Result<(), GpuError> {
    if float32_renderable(context) {
        return Ok(());
    }
    Err(GpuError::Invalid {
        name: "G-buffer (CPU reference)".into(),
        message: "needs Rgba32Float render targets, which this device lacks (wgpu's GL \
                  backend); use Vulkan (lavapipe without a GPU), Metal or DX12"
            .into(),
    })
}

/// Whether the device can render to `Rgba32Float` (tried on a 1×1 texture).
pub fn float32_renderable(context: &GpuContext) -> bool {
    context
        .checked(|| target(context, "probe", wgpu::TextureFormat::Rgba32Float, 1, 1))
        .is_ok()
}

/// The linear-radiance format for this device: [`LINEAR_FORMAT`], else [`LINEAR_FORMAT_F16`].
pub fn linear_format(context: &GpuContext) -> wgpu::TextureFormat {
    if float32_renderable(context) {
        LINEAR_FORMAT
    } else {
        LINEAR_FORMAT_F16
    }
}

/// A 2-D texture of `format` to render into and copy out of (read back).
pub(crate) fn target(
    context: &GpuContext,
    name: &str,
    format: wgpu::TextureFormat,
    width: u32,
    height: u32,
) -> wgpu::Texture {
    context.device.create_texture(&wgpu::TextureDescriptor {
        label: Some(name),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    })
}
