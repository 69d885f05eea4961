//! The window's surface: its configuration, depth buffer and recovery after loss, and the
//! wording of the window system's errors.

use super::ViewError;
use super::edit::overlay::Overlay;
use super::timer::GpuTimer;
use crate::gpu::GpuContext;
use crate::render::image::Rgba8Image;
use crate::render::{
    DEPTH_FORMAT, FrameSettings, FrameTargets, GpuEnvironment, Renderer, read_texture,
};
use std::sync::{Arc, Mutex};
use winit::dpi::PhysicalSize;
use winit::window::Window;

use super::shading::FabricGpu;

/// The window and everything drawn into it.
pub(super) struct Graphics {
    pub window: Arc<Window>,
    pub instance: wgpu::Instance,
    pub surface: wgpu::Surface<'static>,
    pub config: wgpu::SurfaceConfiguration,
    pub gpu: GpuContext,
    pub renderer: Renderer,
    /// The scene's environment map, uploaded.
    pub environment: Option<GpuEnvironment>,
    pub depth: wgpu::TextureView,
    /// Per fabric of the list, once loaded.
    pub fabrics: Vec<Option<FabricGpu>>,
    pub timer: Option<GpuTimer>,
    /// Validation errors wgpu reported outside any error scope (its default handler panics).
    pub uncaptured: Arc<Mutex<Option<String>>>,
    /// The editing panel's UI, drawn over the drape (`view --edit`).
    pub overlay: Option<Overlay>,
}

/// What [`Graphics::acquire`] got from the surface.
pub(super) enum Acquired {
    Frame(wgpu::SurfaceTexture),
    /// Nothing to draw into this time (timed out, occluded, reconfigured): ask for another
    /// frame.
    Retry,
    Failed(ViewError),
}

impl Graphics {
    pub fn configure(&self) {
        if self.config.width > 0 && self.config.height > 0 {
            self.surface.configure(&self.gpu.device, &self.config);
        }
    }

    pub fn resize(&mut self, size: PhysicalSize<u32>) {
        self.config.width = size.width;
        self.config.height = size.height;
        if size.width > 0 && size.height > 0 {
            self.depth = depth_view(&self.gpu, &self.config);
        }
        self.configure();
    }

    /// After [`wgpu::CurrentSurfaceTexture::Lost`]: a new surface for the same window.
    pub fn recreate_surface(&mut self) -> Result<(), ViewError> {
        self.surface = self
            .instance
            .create_surface(self.window.clone())
            .map_err(|e| ViewError::Display(format!("cannot recreate the wgpu surface: {e}")))?;
        self.configure();
        Ok(())
    }

    /// The surface's next texture, reconfiguring or recreating the surface where it asks.
    pub fn acquire(&mut self) -> Acquired {
        match self.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(frame) => Acquired::Frame(frame),
            wgpu::CurrentSurfaceTexture::Suboptimal(frame) => {
                // Draw this one; reconfigure for the next.
                self.configure();
                Acquired::Frame(frame)
            }
            wgpu::CurrentSurfaceTexture::Timeout | wgpu::CurrentSurfaceTexture::Occluded => {
                Acquired::Retry
            }
            wgpu::CurrentSurfaceTexture::Outdated => {
                self.configure();
                Acquired::Retry
            }
            wgpu::CurrentSurfaceTexture::Lost => match self.recreate_surface() {
                Ok(()) => Acquired::Retry,
                Err(e) => Acquired::Failed(e),
            },
            wgpu::CurrentSurfaceTexture::Validation => {
                let message = self.take_uncaptured().unwrap_or_default();
                Acquired::Failed(ViewError::Render(format!(
                    "cannot acquire a surface texture: {message}"
                )))
            }
        }
    }

    /// Records the drape shaded for `settings` into `texture` (the surface's format and
    /// size) and, in edit mode, the panel over it; `timed`: the drape's pass is bracketed by
    /// the GPU timer's timestamps.
    pub fn record(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        texture: &wgpu::Texture,
        settings: &FrameSettings,
        timed: bool,
    ) {
        let timestamps = match timed {
            true => self.timer.as_mut().and_then(|t| t.begin()),
            false => None,
        };
        let view = texture.create_view(&wgpu::TextureViewDescriptor::default());
        let size = (self.config.width, self.config.height);
        let targets = FrameTargets {
            color: &view,
            linear: None,
            depth: &self.depth,
            size,
        };
        self.renderer
            .encode(&self.gpu.queue, encoder, &targets, settings, timestamps);
        if let Some(overlay) = &mut self.overlay {
            overlay.paint(&self.gpu, encoder, &view, size);
        }
    }

    /// The window's next frame for `settings`, drawn offscreen and read back (a script's
    /// screenshot; a surface texture cannot be read).
    pub fn capture(&mut self, settings: &FrameSettings) -> Result<Rgba8Image, ViewError> {
        let (width, height) = (self.config.width.max(1), self.config.height.max(1));
        let format = self.config.format;
        let texture = self.gpu.checked(|| {
            crate::render::target(&self.gpu, "view screenshot", format, width, height)
        })?;
        let mut encoder = self
            .gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("view screenshot"),
            });
        self.record(&mut encoder, &texture, settings, false);
        self.gpu.queue.submit([encoder.finish()]);
        let bytes = read_texture(&self.gpu, &texture, 4, (width, height))?;
        let bgra = matches!(
            format,
            wgpu::TextureFormat::Bgra8Unorm | wgpu::TextureFormat::Bgra8UnormSrgb
        );
        let pixels = bytes
            .chunks_exact(4)
            .map(|p| match bgra {
                true => [p[2], p[1], p[0], 255],
                false => [p[0], p[1], p[2], 255],
            })
            .collect();
        Ok(Rgba8Image {
            width,
            height,
            pixels,
        })
    }

    pub fn take_uncaptured(&self) -> Option<String> {
        self.uncaptured.lock().ok().and_then(|mut slot| slot.take())
    }
}

/// A depth buffer of the surface's size (at least 1×1).
pub(super) fn depth_view(
    gpu: &GpuContext,
    config: &wgpu::SurfaceConfiguration,
) -> wgpu::TextureView {
    gpu.device
        .create_texture(&wgpu::TextureDescriptor {
            label: Some("view depth"),
            size: wgpu::Extent3d {
                width: config.width.max(1),
                height: config.height.max(1),
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: DEPTH_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            view_formats: &[],
        })
        .create_view(&wgpu::TextureViewDescriptor::default())
}

/// The surface configuration: an sRGB format when offered (the renderer then leaves the
/// sRGB encoding to the format; otherwise its shader encodes), else an 8-bit UNORM one,
/// else the first; a present mode that does not wait for vertical blank when there is one
/// (the frame time then shows the cost of a frame, not the display's refresh), else Fifo.
pub(super) fn surface_config(
    instance: &wgpu::Instance,
    surface: &wgpu::Surface<'_>,
    size: PhysicalSize<u32>,
) -> Result<wgpu::SurfaceConfiguration, ViewError> {
    // Capabilities belong to the adapter; `GpuContext` does not hand out its
    // `wgpu::Adapter`, so ask for the same one again (same instance, surface and environment
    // make the same choice).
    let adapter = pollster::block_on(wgpu::util::initialize_adapter_from_env_or_default(
        instance,
        Some(surface),
    ))
    .map_err(|e| ViewError::Display(format!("no adapter can present to the window: {e}")))?;
    let caps = surface.get_capabilities(&adapter);
    let unorm = [
        wgpu::TextureFormat::Bgra8Unorm,
        wgpu::TextureFormat::Rgba8Unorm,
    ];
    let format = caps
        .formats
        .iter()
        .copied()
        .find(|f| f.is_srgb())
        .or_else(|| caps.formats.iter().copied().find(|f| unorm.contains(f)))
        .or_else(|| caps.formats.first().copied())
        .ok_or_else(|| {
            ViewError::Display(format!(
                "adapter {} cannot present to this window (no surface formats)",
                adapter.get_info().name
            ))
        })?;
    let present_mode = [wgpu::PresentMode::Mailbox, wgpu::PresentMode::Immediate]
        .into_iter()
        .find(|m| caps.present_modes.contains(m))
        .unwrap_or(wgpu::PresentMode::Fifo);
    Ok(wgpu::SurfaceConfiguration {
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
        format,
        width: size.width,
        height: size.height,
        present_mode,
        desired_maximum_frame_latency: 2,
        alpha_mode: caps
            .alpha_modes
            .first()
            .copied()
            .unwrap_or(wgpu::CompositeAlphaMode::Auto),
        view_formats: vec![],
        // The renderer writes display-referred sRGB (tone mapped to [0, 1]).
        color_space: wgpu::SurfaceColorSpace::Srgb,
    })
}

/// A winit error without the source location winit puts in front of OS errors
/// ("os error at FILE:LINE: message"), which means nothing to a user.
pub(super) fn os_message(error: &dyn std::fmt::Display) -> String {
    let text = error.to_string();
    text.strip_prefix("os error at ")
        .and_then(|rest| rest.split_once(": "))
        .map_or_else(|| text.clone(), |(_, message)| message.to_string())
}

#[cfg(test)]
mod tests {
    use super::os_message;

    #[test]
    fn os_errors_lose_their_source_location() {
        assert_eq!(
            os_message(&"os error at /src/x11/mod.rs:788: Failed to open connection to X server"),
            "Failed to open connection to X server"
        );
        assert_eq!(os_message(&"the event loop broke"), "the event loop broke");
    }
}
