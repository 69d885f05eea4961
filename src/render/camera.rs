//! The camera: where the eye is, what it looks at, and the world-to-clip transform. Plain
//! geometry, kept apart from the lights and the GPU code.

use crate::scene::OrbitCamera;
use glam::{Mat4, Vec3};

/// A perspective camera looking from `eye` at `target` with +y up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub eye: Vec3,
    pub target: Vec3,
    pub fov_y_deg: f32,
}

impl Camera {
    /// The camera of an orbit description (see [`OrbitCamera`]).
    pub fn orbit(orbit: &OrbitCamera) -> Self {
        Self {
            eye: glam::DVec3::from(orbit.eye()).as_vec3(),
            target: glam::DVec3::from(orbit.target).as_vec3(),
            fov_y_deg: orbit.fov_y_deg as f32,
        }
    }

    /// World to clip space for an image of `aspect` = width/height (wgpu's depth range
    /// [0, 1]); near and far planes at 1/100 and 100 times the distance to the target.
    pub fn view_proj(&self, aspect: f32) -> Mat4 {
        let distance = self.eye.distance(self.target).max(1e-6);
        let forward = (self.target - self.eye) / distance;
        // Up is +y unless the camera looks (almost) straight along it.
        let up = if forward.y.abs() > 0.999 {
            Vec3::Z
        } else {
            Vec3::Y
        };
        let view = glam::camera::rh::view::look_at_mat4(self.eye, self.target, up);
        // The DirectX convention (depth in [0, 1], y up) is WebGPU's.
        let proj = glam::camera::rh::proj::directx::perspective(
            self.fov_y_deg.to_radians(),
            aspect,
            0.01 * distance,
            100.0 * distance,
        );
        proj * view
    }
}
