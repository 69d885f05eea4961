//! The viewer's input mapping and bookkeeping, free of any window or GPU so that it can be
//! unit-tested: keys to actions, mouse drags and wheel steps to the orbit camera, arrow keys
//! to the directional light, frame-interval statistics and the window title.

use crate::render::median;
use crate::scene::{Light, OrbitCamera};
use winit::keyboard::{Key, NamedKey};

/// Degrees of camera yaw or pitch per pixel of left-drag: a drag across an 800-pixel window
/// turns the camera by 240°, enough to go round the cloth in one or two drags.
pub const ORBIT_DEG_PER_PIXEL: f64 = 0.3;
/// Pitch stays strictly inside (-90°, 90°): at the poles the orbit's up vector is undefined
/// (the scene file's own bound is ±89.9°).
pub const MAX_PITCH_DEG: f64 = 89.0;
/// Distance factor per wheel line (one notch): ten notches change the distance by 2.9×.
pub const ZOOM_PER_LINE: f64 = 0.9;
/// Wheel pixels (touchpads) counted as one line.
pub const PIXELS_PER_LINE: f64 = 40.0;
/// Zoom stays within this factor of the scene's distance either way.
pub const ZOOM_RANGE: f64 = 10.0;
/// Light azimuth per Left/Right key press, and elevation per Up/Down press.
pub const LIGHT_AZIMUTH_STEP_DEG: f64 = 15.0;
pub const LIGHT_ELEVATION_STEP_DEG: f64 = 5.0;
/// The light's elevation above the horizontal plane stays within ±85°: the azimuth is
/// undefined at the poles, and below the cloth a light still lights the far side of folds.
pub const MAX_LIGHT_ELEVATION_DEG: f64 = 85.0;
/// Azimuth speed of the spinning light (L), degrees per second.
pub const LIGHT_SPIN_DEG_PER_S: f64 = 45.0;
/// Environment rotation about +y per `[` / `]` press.
pub const ENVIRONMENT_STEP_DEG: f64 = 15.0;
/// The key list printed at start.
pub const KEY_HELP: &str = "\
keys: left-drag orbit, wheel zoom, Tab / Shift+Tab next / previous fabric, 1-9 fabric,
      Left/Right/Up/Down move the light, L spin the light, V / Shift+V next / previous
      evaluator, + / - its finer / coarser setting (paper: N x2 / /2), E environment
      light on / off, [ / ] turn the environment, R reset view, Esc or Q quit";

/// What a key press asks for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Action {
    Quit,
    /// Move through the fabric list by this many places (wrapping).
    CycleFabric(i32),
    /// Select the fabric at this index of the list (0-based).
    SelectFabric(usize),
    /// Turn the directional light: azimuth about +y and elevation, in degrees.
    RotateLight {
        azimuth_deg: f64,
        elevation_deg: f64,
    },
    ToggleLightSpin,
    /// Move through the evaluator list by this many places (wrapping).
    CycleEvaluator(i32),
    /// Show the evaluator's finer (`true`) or coarser setting ([`crate::evaluator::Evaluator::step`]).
    Finer(bool),
    /// Switch the environment light off or on.
    ToggleEnvironment,
    /// Turn the environment (light and background) about +y by this many degrees.
    RotateEnvironment(f64),
    ResetView,
}

/// The action of a pressed key (`shift`: whether Shift is held), if any.
pub fn action_for_key(key: &Key, shift: bool) -> Option<Action> {
    match key {
        Key::Named(named) => match named {
            NamedKey::Escape => Some(Action::Quit),
            NamedKey::Tab => Some(Action::CycleFabric(if shift { -1 } else { 1 })),
            NamedKey::ArrowLeft => Some(Action::RotateLight {
                azimuth_deg: -LIGHT_AZIMUTH_STEP_DEG,
                elevation_deg: 0.0,
            }),
            NamedKey::ArrowRight => Some(Action::RotateLight {
                azimuth_deg: LIGHT_AZIMUTH_STEP_DEG,
                elevation_deg: 0.0,
            }),
            NamedKey::ArrowUp => Some(Action::RotateLight {
                azimuth_deg: 0.0,
                elevation_deg: LIGHT_ELEVATION_STEP_DEG,
            }),
            NamedKey::ArrowDown => Some(Action::RotateLight {
                azimuth_deg: 0.0,
                elevation_deg: -LIGHT_ELEVATION_STEP_DEG,
            }),
            _ => None,
        },
        Key::Character(text) => {
            let mut chars = text.chars();
            let c = chars.next()?;
            if chars.next().is_some() {
                return None;
            }
            match c.to_ascii_lowercase() {
                'q' => Some(Action::Quit),
                'l' => Some(Action::ToggleLightSpin),
                'v' => Some(Action::CycleEvaluator(if shift { -1 } else { 1 })),
                'e' => Some(Action::ToggleEnvironment),
                'r' => Some(Action::ResetView),
                '[' => Some(Action::RotateEnvironment(-ENVIRONMENT_STEP_DEG)),
                ']' => Some(Action::RotateEnvironment(ENVIRONMENT_STEP_DEG)),
                // `=` is `+` without Shift on US layouts.
                '+' | '=' => Some(Action::Finer(true)),
                '-' | '_' => Some(Action::Finer(false)),
                '1'..='9' => Some(Action::SelectFabric(c as usize - '1' as usize)),
                _ => None,
            }
        }
        _ => None,
    }
}

/// The fabric index `step` places from `current` in a list of `count`, wrapping.
pub fn cycle_index(current: usize, step: i32, count: usize) -> usize {
    if count == 0 {
        return 0;
    }
    (current as i64 + step as i64).rem_euclid(count as i64) as usize
}

/// The orbit camera under mouse control, starting from (and reset to) the scene's camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrbitControl {
    pub camera: OrbitCamera,
    home: OrbitCamera,
}

impl OrbitControl {
    pub fn new(camera: OrbitCamera) -> Self {
        let mut camera = camera;
        camera.pitch_deg = camera.pitch_deg.clamp(-MAX_PITCH_DEG, MAX_PITCH_DEG);
        Self {
            camera,
            home: camera,
        }
    }

    /// A left-drag by (dx, dy) pixels (x right, y down). Dragging right turns the cloth
    /// right (the eye moves left: yaw decreases); dragging down raises the eye over the
    /// cloth, as a hand turning the object would.
    pub fn drag(&mut self, dx: f64, dy: f64) {
        let c = &mut self.camera;
        c.yaw_deg = (c.yaw_deg - dx * ORBIT_DEG_PER_PIXEL).rem_euclid(360.0);
        c.pitch_deg = (c.pitch_deg + dy * ORBIT_DEG_PER_PIXEL).clamp(-MAX_PITCH_DEG, MAX_PITCH_DEG);
    }

    /// A wheel movement of `lines` notches, positive away from the user (zoom in): the
    /// distance shrinks by [`ZOOM_PER_LINE`] per notch, within [`ZOOM_RANGE`] of the
    /// scene's distance.
    pub fn zoom(&mut self, lines: f64) {
        let home = self.home.distance;
        let d = self.camera.distance * ZOOM_PER_LINE.powf(lines);
        self.camera.distance = d.clamp(home / ZOOM_RANGE, home * ZOOM_RANGE);
    }

    pub fn reset(&mut self) {
        self.camera = self.home;
    }

    /// Turns the eye to `yaw_deg` about +y and `pitch_deg` above the target (clamped as a
    /// drag is), at the same distance.
    pub fn aim(&mut self, yaw_deg: f64, pitch_deg: f64) {
        self.camera.yaw_deg = yaw_deg.rem_euclid(360.0);
        self.camera.pitch_deg = pitch_deg.clamp(-MAX_PITCH_DEG, MAX_PITCH_DEG);
    }
}

/// Wheel notches from a pixel delta (touchpads): [`PIXELS_PER_LINE`] pixels a notch.
pub fn pixels_to_lines(pixels: f64) -> f64 {
    pixels / PIXELS_PER_LINE
}

/// The scene's first directional light, turned by the arrow keys and the spin: its
/// direction towards the light as azimuth about +y (0 along +z, 90° along +x) and elevation
/// above the horizontal plane.
#[derive(Clone, Debug, PartialEq)]
pub struct LightControl {
    /// The scene's lights with the controlled one's direction replaced.
    lights: Vec<Light>,
    home: Vec<Light>,
    /// Index of the controlled light, if the scene has a directional light.
    index: Option<usize>,
    azimuth_deg: f64,
    elevation_deg: f64,
    pub spinning: bool,
}

impl LightControl {
    pub fn new(lights: &[Light]) -> Self {
        let index = lights
            .iter()
            .position(|l| matches!(l, Light::Directional { .. }));
        let mut control = Self {
            lights: lights.to_vec(),
            home: lights.to_vec(),
            index,
            azimuth_deg: 0.0,
            elevation_deg: 0.0,
            spinning: false,
        };
        control.reset();
        control
    }

    /// Whether the scene has a directional light to move.
    pub fn has_light(&self) -> bool {
        self.index.is_some()
    }

    /// The lights as they are now.
    pub fn lights(&self) -> &[Light] {
        &self.lights
    }

    /// (azimuth, elevation) of the controlled light in degrees.
    pub fn angles(&self) -> (f64, f64) {
        (self.azimuth_deg, self.elevation_deg)
    }

    /// Back to the scene's lights (spin off).
    pub fn reset(&mut self) {
        self.lights = self.home.clone();
        self.spinning = false;
        if let Some(Light::Directional { direction, .. }) = self.index.map(|i| self.home[i]) {
            (self.azimuth_deg, self.elevation_deg) = direction_angles(direction);
            // A light given exactly overhead keeps its direction until moved; clamping it
            // here would change the scene's look.
        }
    }

    /// Turns the light by the given angles (elevation clamped to ±85°).
    pub fn rotate(&mut self, azimuth_deg: f64, elevation_deg: f64) {
        let Some(index) = self.index else {
            return;
        };
        self.azimuth_deg = (self.azimuth_deg + azimuth_deg).rem_euclid(360.0);
        self.elevation_deg = (self.elevation_deg + elevation_deg)
            .clamp(-MAX_LIGHT_ELEVATION_DEG, MAX_LIGHT_ELEVATION_DEG);
        let (az, el) = (
            self.azimuth_deg.to_radians(),
            self.elevation_deg.to_radians(),
        );
        if let Light::Directional { direction, .. } = &mut self.lights[index] {
            *direction = [el.cos() * az.sin(), el.sin(), el.cos() * az.cos()];
        }
    }

    /// The scene's directional lights: (index in the scene, azimuth, elevation) in degrees.
    pub fn directional_angles(&self) -> Vec<(usize, f64, f64)> {
        self.lights
            .iter()
            .enumerate()
            .filter_map(|(i, light)| match light {
                Light::Directional { direction, .. } => {
                    let (azimuth, elevation) = direction_angles(*direction);
                    Some((i, azimuth.rem_euclid(360.0), elevation))
                }
                _ => None,
            })
            .collect()
    }

    /// Points the scene's light `index`, a directional one, from `azimuth_deg` and
    /// `elevation_deg` (clamped to ±85° as the keys do).
    pub fn aim(
        &mut self,
        index: usize,
        azimuth_deg: f64,
        elevation_deg: f64,
    ) -> Result<(), String> {
        let count = self.lights.len();
        let Some(Light::Directional { direction, .. }) = self.lights.get_mut(index) else {
            return Err(format!(
                "the scene has no directional light {index} (it has {count} lights, from 0)"
            ));
        };
        let elevation_deg = elevation_deg.clamp(-MAX_LIGHT_ELEVATION_DEG, MAX_LIGHT_ELEVATION_DEG);
        let (az, el) = (azimuth_deg.to_radians(), elevation_deg.to_radians());
        *direction = [el.cos() * az.sin(), el.sin(), el.cos() * az.cos()];
        if self.index == Some(index) {
            self.azimuth_deg = azimuth_deg.rem_euclid(360.0);
            self.elevation_deg = elevation_deg;
        }
        Ok(())
    }

    /// Advances the spin by `seconds` of wall time, if spinning.
    pub fn advance(&mut self, seconds: f64) {
        if self.spinning {
            self.rotate(LIGHT_SPIN_DEG_PER_S * seconds, 0.0);
        }
    }
}

/// A direction towards a light as (azimuth, elevation) in degrees: elevation = asin(y/|d|),
/// azimuth = atan2(x, z); the scene file forbids the zero vector.
fn direction_angles([x, y, z]: [f64; 3]) -> (f64, f64) {
    let length = (x * x + y * y + z * z).sqrt().max(f64::MIN_POSITIVE);
    (
        x.atan2(z).to_degrees(),
        (y / length).clamp(-1.0, 1.0).asin().to_degrees(),
    )
}

/// Frame intervals (CPU wall time between successive frames) and GPU times, in
/// milliseconds: all of them for the final median, and those since the last title update.
#[derive(Clone, Debug, Default)]
pub struct FrameStats {
    intervals: Vec<f64>,
    gpu: Vec<f64>,
    recent_intervals: Vec<f64>,
    recent_gpu: Vec<f64>,
    frames: u64,
}

/// Most intervals kept for the final median (about half an hour at 60 frames a second);
/// later ones are still counted.
const MAX_KEPT: usize = 1 << 17;

impl FrameStats {
    /// Counts a frame drawn, with the interval since the previous one (none for the first).
    pub fn frame(&mut self, interval_ms: Option<f64>) {
        self.frames += 1;
        if let Some(ms) = interval_ms {
            if self.intervals.len() < MAX_KEPT {
                self.intervals.push(ms);
            }
            self.recent_intervals.push(ms);
        }
    }

    /// Records a GPU time measured for a frame (timestamps arrive a frame or two late).
    pub fn gpu_time(&mut self, ms: f64) {
        if self.gpu.len() < MAX_KEPT {
            self.gpu.push(ms);
        }
        self.recent_gpu.push(ms);
    }

    pub fn frames(&self) -> u64 {
        self.frames
    }

    /// Median of all frame intervals so far.
    pub fn median_interval(&self) -> Option<f64> {
        median(&self.intervals)
    }

    /// Median of all GPU times so far.
    pub fn median_gpu(&self) -> Option<f64> {
        median(&self.gpu)
    }

    /// Median of the frame intervals since the title's last update.
    pub fn median_recent(&self) -> Option<f64> {
        median(&self.recent_intervals)
    }

    /// Medians (interval, GPU time) since the last call, and starts a new window.
    pub fn take_recent(&mut self) -> (Option<f64>, Option<f64>) {
        let result = (median(&self.recent_intervals), median(&self.recent_gpu));
        self.recent_intervals.clear();
        self.recent_gpu.clear();
        result
    }

    /// Forgets the recent frame intervals and GPU times (after switching fabric or
    /// evaluator, old ones would mix two costs).
    pub fn clear_recent(&mut self) {
        self.recent_intervals.clear();
        self.recent_gpu.clear();
    }
}

/// The window title: fabric, the evaluator shown, frame interval (and rate) and GPU time.
pub fn title(fabric: &str, mode: &str, interval_ms: Option<f64>, gpu_ms: Option<f64>) -> String {
    let mut title = format!("clothbake view: {fabric}, {mode}");
    if let Some(ms) = interval_ms {
        title += &format!(", {ms:.1} ms/frame ({:.0} fps)", 1000.0 / ms.max(1e-3));
    }
    if let Some(ms) = gpu_ms {
        title += &format!(", GPU {ms:.2} ms");
    }
    title
}

#[cfg(test)]
mod tests {
    use super::*;
    use winit::keyboard::SmolStr;

    fn ch(s: &str) -> Key {
        Key::Character(SmolStr::new(s))
    }

    #[test]
    fn keys_map_to_actions() {
        assert_eq!(
            action_for_key(&Key::Named(NamedKey::Escape), false),
            Some(Action::Quit)
        );
        assert_eq!(action_for_key(&ch("q"), false), Some(Action::Quit));
        assert_eq!(action_for_key(&ch("Q"), true), Some(Action::Quit));
        assert_eq!(
            action_for_key(&Key::Named(NamedKey::Tab), false),
            Some(Action::CycleFabric(1))
        );
        assert_eq!(
            action_for_key(&Key::Named(NamedKey::Tab), true),
            Some(Action::CycleFabric(-1))
        );
        assert_eq!(
            action_for_key(&ch("1"), false),
            Some(Action::SelectFabric(0))
        );
        assert_eq!(
            action_for_key(&ch("6"), false),
            Some(Action::SelectFabric(5))
        );
        assert_eq!(action_for_key(&ch("0"), false), None);
        assert_eq!(
            action_for_key(&ch("v"), false),
            Some(Action::CycleEvaluator(1))
        );
        assert_eq!(
            action_for_key(&ch("V"), true),
            Some(Action::CycleEvaluator(-1))
        );
        assert_eq!(
            action_for_key(&ch("l"), false),
            Some(Action::ToggleLightSpin)
        );
        assert_eq!(action_for_key(&ch("+"), true), Some(Action::Finer(true)));
        assert_eq!(action_for_key(&ch("="), false), Some(Action::Finer(true)));
        assert_eq!(action_for_key(&ch("-"), false), Some(Action::Finer(false)));
        assert_eq!(action_for_key(&ch("r"), false), Some(Action::ResetView));
        assert_eq!(
            action_for_key(&ch("["), false),
            Some(Action::RotateEnvironment(-ENVIRONMENT_STEP_DEG))
        );
        assert_eq!(
            action_for_key(&ch("]"), false),
            Some(Action::RotateEnvironment(ENVIRONMENT_STEP_DEG))
        );
        assert_eq!(action_for_key(&ch("dd"), false), None);
        assert_eq!(action_for_key(&ch("x"), false), None);
        assert_eq!(
            action_for_key(&Key::Named(NamedKey::ArrowRight), false),
            Some(Action::RotateLight {
                azimuth_deg: LIGHT_AZIMUTH_STEP_DEG,
                elevation_deg: 0.0
            })
        );
        assert_eq!(
            action_for_key(&Key::Named(NamedKey::ArrowDown), false),
            Some(Action::RotateLight {
                azimuth_deg: 0.0,
                elevation_deg: -LIGHT_ELEVATION_STEP_DEG
            })
        );
    }

    #[test]
    fn fabric_cycling_wraps_both_ways() {
        assert_eq!(cycle_index(0, 1, 6), 1);
        assert_eq!(cycle_index(5, 1, 6), 0);
        assert_eq!(cycle_index(0, -1, 6), 5);
        assert_eq!(cycle_index(0, 1, 1), 0);
        assert_eq!(cycle_index(0, 1, 0), 0);
    }

    #[test]
    fn drag_orbits_and_clamps_pitch() {
        let mut orbit = OrbitControl::new(OrbitCamera::default());
        let start = orbit.camera;
        // 100 px right: yaw down by 30°.
        orbit.drag(100.0, 0.0);
        assert!((orbit.camera.yaw_deg - (start.yaw_deg - 30.0).rem_euclid(360.0)).abs() < 1e-9);
        assert_eq!(orbit.camera.pitch_deg, start.pitch_deg);
        // 10 px down: pitch up by 3°.
        orbit.drag(0.0, 10.0);
        assert!((orbit.camera.pitch_deg - (start.pitch_deg + 3.0)).abs() < 1e-9);
        orbit.drag(0.0, 1e6);
        assert_eq!(orbit.camera.pitch_deg, MAX_PITCH_DEG);
        orbit.drag(0.0, -1e6);
        assert_eq!(orbit.camera.pitch_deg, -MAX_PITCH_DEG);
        // The eye stays at the orbit's distance from the target.
        let eye = orbit.camera.eye();
        let t = orbit.camera.target;
        let d =
            ((eye[0] - t[0]).powi(2) + (eye[1] - t[1]).powi(2) + (eye[2] - t[2]).powi(2)).sqrt();
        assert!((d - start.distance).abs() < 1e-9);
        orbit.reset();
        assert_eq!(orbit.camera, start);
    }

    #[test]
    fn wheel_zooms_within_range() {
        let mut orbit = OrbitControl::new(OrbitCamera::default());
        let d0 = orbit.camera.distance;
        orbit.zoom(1.0);
        assert!((orbit.camera.distance - d0 * ZOOM_PER_LINE).abs() < 1e-12);
        orbit.zoom(-2.0);
        assert!((orbit.camera.distance - d0 / ZOOM_PER_LINE).abs() < 1e-12);
        orbit.zoom(1000.0);
        assert!((orbit.camera.distance - d0 / ZOOM_RANGE).abs() < 1e-12);
        orbit.zoom(-1000.0);
        assert!((orbit.camera.distance - d0 * ZOOM_RANGE).abs() < 1e-12);
        assert_eq!(pixels_to_lines(PIXELS_PER_LINE * 3.0), 3.0);
    }

    fn direction(control: &LightControl) -> [f64; 3] {
        match control.lights()[0] {
            Light::Directional { direction, .. } => direction,
            _ => panic!("light 0 is directional"),
        }
    }

    #[test]
    fn arrows_turn_the_directional_light_and_keep_the_others() {
        let lights = crate::scene::default_lights();
        let mut control = LightControl::new(&lights);
        assert!(control.has_light());
        // The default key light [0.4, 1.0, 0.6]: azimuth atan2(0.4, 0.6), elevation
        // asin(1/|d|).
        let (az, el) = control.angles();
        assert!((az - 0.4f64.atan2(0.6).to_degrees()).abs() < 1e-9);
        let len = (0.16f64 + 1.0 + 0.36).sqrt();
        assert!((el - (1.0 / len).asin().to_degrees()).abs() < 1e-9);
        // Before any move the scene's light is kept as given (not normalised).
        assert_eq!(control.lights(), &lights[..]);
        // A quarter turn about +y maps (x, z) to (z, -x) up to the length.
        control.rotate(90.0, 0.0);
        let d = direction(&control);
        assert!((d[0] - 0.6 / len).abs() < 1e-9, "{d:?}");
        assert!((d[1] - 1.0 / len).abs() < 1e-9, "{d:?}");
        assert!((d[2] + 0.4 / len).abs() < 1e-9, "{d:?}");
        assert_eq!(control.lights()[1], lights[1]);
        control.rotate(0.0, 1000.0);
        assert_eq!(control.angles().1, MAX_LIGHT_ELEVATION_DEG);
        let d = direction(&control);
        assert!((d.iter().map(|v| v * v).sum::<f64>() - 1.0).abs() < 1e-12);
        control.spinning = true;
        control.advance(2.0);
        assert!(
            (control.angles().0 - (az + 90.0 + 2.0 * LIGHT_SPIN_DEG_PER_S).rem_euclid(360.0)).abs()
                < 1e-9
        );
        control.reset();
        assert_eq!(control.lights(), &lights[..]);
        assert!(!control.spinning);
    }

    #[test]
    fn scenes_without_a_directional_light_ignore_the_arrows() {
        let lights = vec![Light::Point {
            position: [1.0, 2.0, 3.0],
            color: [1.0; 3],
            intensity: 1.0,
        }];
        let mut control = LightControl::new(&lights);
        assert!(!control.has_light());
        control.rotate(30.0, 10.0);
        assert_eq!(control.lights(), &lights[..]);
    }

    #[test]
    fn medians_and_windows() {
        assert_eq!(median(&[]), None);
        assert_eq!(median(&[3.0, 1.0, 2.0]), Some(2.0));
        assert_eq!(median(&[4.0, 1.0, 3.0, 2.0]), Some(2.5));
        let mut stats = FrameStats::default();
        stats.frame(None);
        stats.frame(Some(10.0));
        stats.frame(Some(30.0));
        stats.frame(Some(20.0));
        stats.gpu_time(5.0);
        assert_eq!(stats.frames(), 4);
        assert_eq!(stats.take_recent(), (Some(20.0), Some(5.0)));
        assert_eq!(stats.take_recent(), (None, None));
        stats.frame(Some(40.0));
        assert_eq!(stats.median_interval(), Some(25.0));
        assert_eq!(stats.median_gpu(), Some(5.0));
    }

    #[test]
    fn title_shows_fabric_evaluator_and_times() {
        let t = title("velvet", "lookup", Some(12.5), Some(8.25));
        assert_eq!(
            t,
            "clothbake view: velvet, lookup, 12.5 ms/frame (80 fps), GPU 8.25 ms"
        );
        assert_eq!(
            title("velvet", "paper:32", None, None),
            "clothbake view: velvet, paper:32"
        );
    }
}
