//! One frame of the viewer: the settings the controls give, drawing and presenting.

use super::{App, TITLE_PERIOD};
use crate::render::{Camera, FrameSettings, LightSource};
use crate::viewer::ViewError;
use crate::viewer::controls;
use crate::viewer::surface::Acquired;
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
        self.edit_frame(event_loop);
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
        let frame = match g.acquire() {
            Acquired::Frame(frame) => frame,
            Acquired::Retry => {
                g.window.request_redraw();
                return;
            }
            Acquired::Failed(e) => {
                self.fail(event_loop, e);
                return;
            }
        };
        let mut encoder = g
            .gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("view frame"),
            });
        g.record(&mut encoder, &frame.texture, &settings, true);
        if let Some(timer) = &g.timer {
            timer.resolve(&mut encoder);
        }
        g.gpu.queue.submit([encoder.finish()]);
        if let Some(timer) = &mut g.timer {
            timer.submitted();
        }
        if let Some(overlay) = &mut g.overlay {
            overlay.submitted();
        }
        g.window.pre_present_notify();
        g.gpu.queue.present(frame);
        if let Some(message) = g.take_uncaptured() {
            self.fail(event_loop, ViewError::Render(message));
            return;
        }
        self.last_frame = Some(now);
        let interval_ms = interval.map(|d| d.as_secs_f64() * 1000.0);
        self.stats.frame(interval_ms);
        self.edit_presented(interval_ms, Instant::now());
        if now - self.last_title >= TITLE_PERIOD {
            self.last_title = now;
            let (interval_ms, gpu_ms) = self.stats.take_recent();
            let (name, shown) = match &self.editing {
                Some(editing) => (
                    editing.editor.session.fabric().name.clone(),
                    editing.editor.display_label(),
                ),
                None => (
                    self.setup.fabrics[self.current].name.clone(),
                    self.shown_spelling(),
                ),
            };
            let title = controls::title(&name, &shown, interval_ms, gpu_ms);
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
