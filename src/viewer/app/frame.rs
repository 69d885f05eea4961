//! One frame of the viewer: the settings the controls give, drawing and presenting.

use super::{App, TITLE_PERIOD};
use crate::render::{Camera, FrameSettings, FrameTargets, LightSource};
use crate::viewer::ViewError;
use crate::viewer::controls;
use std::time::Instant;
use winit::event_loop::ActiveEventLoop;

impl App {
    pub(super) fn frame_settings(&self) -> FrameSettings {
        let scene = &self.setup.scene;
        FrameSettings {
            camera: Camera::orbit(&self.orbit.camera),
            lights: self
                .light
                .lights()
                .iter()
                .map(LightSource::from_scene)
                .collect(),
            exposure: scene.exposure as f32,
            background: crate::render::BACKGROUND,
            environment_samples: if self.environment_on {
                scene.environment.samples
            } else {
                0
            },
            environment_rotation: self.environment_rotation_deg.to_radians() as f32,
        }
    }

    pub(super) fn redraw(&mut self, event_loop: &ActiveEventLoop) {
        let now = Instant::now();
        let interval = self.last_frame.map(|t| now - t);
        self.light
            .advance(interval.map_or(0.0, |d| d.as_secs_f64()));
        let settings = self.frame_settings();
        let Some(g) = &mut self.graphics else {
            return;
        };
        if let Some(timer) = &mut g.timer {
            for ms in timer.collect(&g.gpu) {
                self.stats.gpu_time(ms);
            }
        }
        if g.config.width == 0 || g.config.height == 0 {
            // Minimised: nothing to draw until resized.
            return;
        }
        let frame = match g.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(frame) => frame,
            wgpu::CurrentSurfaceTexture::Suboptimal(frame) => {
                // Draw this one; reconfigure for the next.
                g.configure();
                frame
            }
            wgpu::CurrentSurfaceTexture::Timeout | wgpu::CurrentSurfaceTexture::Occluded => {
                g.window.request_redraw();
                return;
            }
            wgpu::CurrentSurfaceTexture::Outdated => {
                g.configure();
                g.window.request_redraw();
                return;
            }
            wgpu::CurrentSurfaceTexture::Lost => {
                if let Err(e) = g.recreate_surface() {
                    self.fail(event_loop, e);
                    return;
                }
                g.window.request_redraw();
                return;
            }
            wgpu::CurrentSurfaceTexture::Validation => {
                let message = g.take_uncaptured().unwrap_or_default();
                self.fail(
                    event_loop,
                    ViewError::Render(format!("cannot acquire a surface texture: {message}")),
                );
                return;
            }
        };
        let view = frame
            .texture
            .create_view(&wgpu::TextureViewDescriptor::default());
        let mut encoder = g
            .gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("view frame"),
            });
        let targets = FrameTargets {
            color: &view,
            linear: None,
            depth: &g.depth,
            size: (g.config.width, g.config.height),
        };
        let writes = g.timer.as_mut().and_then(|t| t.begin());
        g.renderer
            .encode(&g.gpu.queue, &mut encoder, &targets, &settings, writes);
        if let Some(timer) = &g.timer {
            timer.resolve(&mut encoder);
        }
        g.gpu.queue.submit([encoder.finish()]);
        if let Some(timer) = &mut g.timer {
            timer.submitted();
        }
        g.window.pre_present_notify();
        g.gpu.queue.present(frame);
        if let Some(message) = g.take_uncaptured() {
            self.fail(event_loop, ViewError::Render(message));
            return;
        }
        self.last_frame = Some(now);
        self.stats.frame(interval.map(|d| d.as_secs_f64() * 1000.0));
        if now - self.last_title >= TITLE_PERIOD {
            self.last_title = now;
            let (interval_ms, gpu_ms) = self.stats.take_recent();
            let title = controls::title(
                &self.setup.fabrics[self.current].name,
                &self.shown_spelling(),
                interval_ms,
                gpu_ms,
            );
            if let Some(g) = &self.graphics {
                g.window.set_title(&title);
            }
        }
        if let Some(limit) = self.setup.frames
            && self.stats.frames() >= limit as u64
        {
            event_loop.exit();
            return;
        }
        if let Some(g) = &self.graphics {
            g.window.request_redraw();
        }
    }
}
