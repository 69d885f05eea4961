//! egui over the drape: the UI context, its winit input and its wgpu painter.
//!
//! The painter draws into the window's own format. On an sRGB surface egui-wgpu switches to
//! its shader for linear framebuffers; a non-sRGB view of the surface would need a
//! swapchain whose format can be reinterpreted, which not every Vulkan driver offers.

use crate::gpu::GpuContext;
use winit::window::Window;

/// The UI of one window: context, input state and painter, plus what the last
/// [`Overlay::run`] laid out until [`Overlay::paint`] draws it.
pub struct Overlay {
    context: egui::Context,
    state: egui_winit::State,
    renderer: egui_wgpu::Renderer,
    laid_out: Option<LaidOut>,
    /// Fixed input time for scripted sessions (screenshots do not depend on the clock).
    scripted_time: Option<f64>,
}

/// The tessellated UI of one frame and the texture changes it needs.
struct LaidOut {
    primitives: Vec<egui::ClippedPrimitive>,
    textures: egui::TexturesDelta,
    pixels_per_point: f32,
}

impl Overlay {
    /// A UI for `window`, painting into textures of `format`. `scripted` fixes
    /// the scale at one pixel per point and the clock, so that a script's screenshots are
    /// the same on every display.
    pub fn new(
        window: &Window,
        gpu: &GpuContext,
        format: wgpu::TextureFormat,
        scripted: bool,
    ) -> Self {
        let context = egui::Context::default();
        let pixels_per_point = if scripted {
            1.0
        } else {
            window.scale_factor() as f32
        };
        let max_side = gpu.device.limits().max_texture_dimension_2d as usize;
        let state = egui_winit::State::new(
            context.clone(),
            egui::ViewportId::ROOT,
            window,
            Some(pixels_per_point),
            None,
            Some(max_side),
        );
        let options = if scripted {
            egui_wgpu::RendererOptions::PREDICTABLE
        } else {
            egui_wgpu::RendererOptions::default()
        };
        let renderer = egui_wgpu::Renderer::new(&gpu.device, format, options);
        if scripted {
            context.set_zoom_factor(1.0);
        }
        Self {
            context,
            state,
            renderer,
            laid_out: None,
            scripted_time: scripted.then_some(0.0),
        }
    }

    /// Passes a window event to the UI; true when the UI used it (a click on the panel, a
    /// key typed into a field), so the orbit and key controls should not.
    pub fn on_window_event(&mut self, window: &Window, event: &winit::event::WindowEvent) -> bool {
        self.state.on_window_event(window, event).consumed
    }

    /// Lays out one frame of the UI with `ui` (which adds the panels).
    pub fn run(&mut self, window: &Window, ui: impl FnMut(&mut egui::Ui)) {
        let mut input = self.state.take_egui_input(window);
        if let Some(time) = &mut self.scripted_time {
            input.time = Some(*time);
            *time += 1.0 / 60.0;
        }
        let output = self.context.run_ui(input, ui);
        self.state
            .handle_platform_output(window, output.platform_output);
        let primitives = self
            .context
            .tessellate(output.shapes, output.pixels_per_point);
        // A frame laid out but never painted keeps its texture changes for this one.
        let mut textures = self
            .laid_out
            .take()
            .map(|previous| previous.textures)
            .unwrap_or_default();
        textures.append(output.textures_delta);
        self.laid_out = Some(LaidOut {
            primitives,
            textures,
            pixels_per_point: output.pixels_per_point,
        });
    }

    /// Draws the UI laid out by the last [`Overlay::run`] over `view` (`size` pixels),
    /// keeping what is there. Records into
    /// `encoder`; the texture memory egui no longer needs is freed once it is submitted, at
    /// the next call.
    pub fn paint(
        &mut self,
        gpu: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        view: &wgpu::TextureView,
        size: (u32, u32),
    ) {
        let Some(laid_out) = self.laid_out.as_mut() else {
            return;
        };
        for (id, deltas) in &laid_out.textures.set {
            for delta in deltas {
                self.renderer
                    .update_texture(&gpu.device, &gpu.queue, *id, delta);
            }
        }
        laid_out.textures.set.clear();
        let screen = egui_wgpu::ScreenDescriptor {
            size_in_pixels: [size.0, size.1],
            pixels_per_point: laid_out.pixels_per_point,
        };
        let commands = self.renderer.update_buffers(
            &gpu.device,
            &gpu.queue,
            encoder,
            &laid_out.primitives,
            &screen,
        );
        if !commands.is_empty() {
            gpu.queue.submit(commands);
        }
        let pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("editor panel"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        // egui-wgpu records into a pass that owns no borrow of the encoder.
        self.renderer
            .render(&mut pass.forget_lifetime(), &laid_out.primitives, &screen);
    }

    /// After the frame [`Overlay::paint`] recorded was submitted: frees the textures egui
    /// dropped in it. The laid-out frame is kept, so a screenshot can paint it again.
    pub fn submitted(&mut self) {
        if let Some(laid_out) = self.laid_out.as_mut() {
            let free = std::mem::take(&mut laid_out.textures.free);
            self.flush_textures(free);
        }
    }

    fn flush_textures(&mut self, free: impl IntoIterator<Item = egui::TextureId>) {
        for id in free {
            self.renderer.free_texture(&id);
        }
    }

    /// The UI's context (for widgets' state and the wanted repaint).
    pub fn context(&self) -> &egui::Context {
        &self.context
    }
}
