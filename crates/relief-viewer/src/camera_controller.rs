//! The fly and orbit camera: what held keys, mouse drags and the wheel do to the eye and the
//! target. Speeds are fractions of the scene's size, so every terrain flies alike.

use relief_core::{Camera, CoreError, DVec3};

/// How the camera moves.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Navigation {
    /// The eye moves and turns; the target stays ahead of it.
    Fly,
    /// The eye circles the target and moves towards or away from it.
    Orbit,
}

/// Continuous motion from held keys, each axis -1, 0 or 1.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Motion {
    /// Forward (+) or back along the view, level with the ground.
    pub forward: f64,
    /// Right (+) or left.
    pub right: f64,
    /// Up (+) or down, along z.
    pub up: f64,
    /// Turn right (+) or left.
    pub yaw: f64,
    /// Tilt up (+) or down.
    pub pitch: f64,
}

impl Motion {
    /// Whether any axis moves.
    pub fn is_moving(&self) -> bool {
        [self.forward, self.right, self.up, self.yaw, self.pitch].iter().any(|&a| a != 0.0)
    }
}

/// Fraction of the scene's diagonal the eye flies in a second at speed 1.
const FLY_FRACTION_PER_S: f64 = 0.25;
/// Degrees a turn key turns in a second.
const TURN_DEG_PER_S: f64 = 60.0;
/// Degrees a mouse drag of one pixel turns.
const DRAG_DEG_PER_PIXEL: f64 = 0.25;
/// The steepest pitch a turn may reach, so that up (z) never lines up with the view.
const MAX_PITCH_DEG: f64 = 89.0;

/// The field of view an orthographic starting camera is flown with, in degrees.
pub const DEFAULT_FOV_DEG: f64 = 45.0;

/// The viewer's camera: eye, target and up, moved by input.
#[derive(Debug, Clone, PartialEq)]
pub struct CameraController {
    eye: DVec3,
    target: DVec3,
    up: DVec3,
    fov_deg: f64,
    scene_size: f64,
    speed: f64,
    navigation: Navigation,
}

impl CameraController {
    /// Starts at `camera`'s eye, target, up and field of view; `scene_size` (the diagonal of
    /// the scene's bounds) sets how fast it flies. The viewer flies pinhole cameras: an
    /// orthographic `camera` starts it at the same eye and target with a field of view of
    /// [`DEFAULT_FOV_DEG`].
    pub fn new(camera: &Camera, scene_size: f64) -> Self {
        CameraController {
            eye: camera.eye(),
            target: camera.target(),
            up: camera.up(),
            fov_deg: camera.fov_deg().unwrap_or(DEFAULT_FOV_DEG),
            scene_size: if scene_size.is_finite() && scene_size > 0.0 { scene_size } else { 1.0 },
            speed: 1.0,
            navigation: Navigation::Orbit,
        }
    }

    /// The camera for a `width` x `height` image.
    pub fn camera(&self, width: u32, height: u32) -> Result<Camera, CoreError> {
        Camera::look_at(self.eye, self.target, self.up, self.fov_deg, width, height)
    }

    /// The eye.
    pub fn eye(&self) -> DVec3 {
        self.eye
    }

    /// The target.
    pub fn target(&self) -> DVec3 {
        self.target
    }

    /// The up vector.
    pub fn up(&self) -> DVec3 {
        self.up
    }

    /// The vertical field of view in degrees.
    pub fn fov_deg(&self) -> f64 {
        self.fov_deg
    }

    /// How the camera moves now.
    pub fn navigation(&self) -> Navigation {
        self.navigation
    }

    /// Switches between flying and orbiting.
    pub fn toggle_navigation(&mut self) {
        self.navigation = match self.navigation {
            Navigation::Fly => Navigation::Orbit,
            Navigation::Orbit => Navigation::Fly,
        };
    }

    /// The fly speed multiplier (1 flies a quarter of the scene a second).
    pub fn speed(&self) -> f64 {
        self.speed
    }

    /// Moves by `motion` held for `dt_s` seconds; whether anything moved.
    pub fn apply(&mut self, motion: Motion, dt_s: f64) -> bool {
        if !motion.is_moving() || dt_s.is_nan() || dt_s <= 0.0 {
            return false;
        }
        let turn = TURN_DEG_PER_S * dt_s;
        match self.navigation {
            Navigation::Fly => {
                let step = FLY_FRACTION_PER_S * self.scene_size * self.speed * dt_s;
                let (level_forward, right) = self.level_axes();
                let shift = (level_forward * motion.forward + right * motion.right) * step
                    + DVec3::Z * (motion.up * step);
                self.eye += shift;
                self.target += shift;
                self.turn_view(motion.yaw * turn, motion.pitch * turn);
            }
            Navigation::Orbit => {
                let dolly = (1.0 - FLY_FRACTION_PER_S * self.speed * dt_s).max(0.05);
                let distance = (self.eye - self.target).length();
                let ratio = if motion.forward > 0.0 { dolly } else { 1.0 / dolly };
                let distance = if motion.forward != 0.0 { distance * ratio } else { distance };
                let yaw = (motion.right + motion.yaw) * turn;
                let pitch = (motion.up + motion.pitch) * turn;
                self.orbit(yaw, pitch, distance);
            }
        }
        true
    }

    /// A mouse drag of (`dx`, `dy`) pixels: looks around (fly) or circles the target (orbit).
    pub fn drag(&mut self, dx: f64, dy: f64) {
        let (yaw, pitch) = (dx * DRAG_DEG_PER_PIXEL, -dy * DRAG_DEG_PER_PIXEL);
        match self.navigation {
            Navigation::Fly => self.turn_view(yaw, pitch),
            Navigation::Orbit => {
                let distance = (self.eye - self.target).length();
                self.orbit(-yaw, -pitch, distance);
            }
        }
    }

    /// Wheel `steps` (positive away from the user): faster flight, or closer to the target.
    pub fn wheel(&mut self, steps: f64) {
        match self.navigation {
            Navigation::Fly => self.speed = (self.speed * 1.25f64.powf(steps)).clamp(1e-3, 1e3),
            Navigation::Orbit => {
                let distance = (self.eye - self.target).length() * 0.9f64.powf(steps);
                self.orbit(0.0, 0.0, distance.max(1e-6 * self.scene_size));
            }
        }
    }

    /// The view direction flattened onto the ground, and the right-hand direction.
    fn level_axes(&self) -> (DVec3, DVec3) {
        let (yaw, _) = yaw_pitch(self.target - self.eye);
        let forward = DVec3::new(yaw.sin(), yaw.cos(), 0.0);
        (forward, DVec3::new(forward.y, -forward.x, 0.0))
    }

    /// Turns the view about the eye by `yaw_deg` (right) and `pitch_deg` (up).
    fn turn_view(&mut self, yaw_deg: f64, pitch_deg: f64) {
        if yaw_deg == 0.0 && pitch_deg == 0.0 {
            return;
        }
        let offset = self.target - self.eye;
        let dir = turned(offset, yaw_deg, pitch_deg);
        self.target = self.eye + dir * offset.length();
        self.up = DVec3::Z;
    }

    /// Moves the eye about the target by `yaw_deg` and `pitch_deg` to `distance` from it.
    fn orbit(&mut self, yaw_deg: f64, pitch_deg: f64, distance: f64) {
        let offset = self.eye - self.target;
        let turned_offset = if yaw_deg == 0.0 && pitch_deg == 0.0 {
            offset.normalize()
        } else {
            self.up = DVec3::Z;
            turned(offset, yaw_deg, pitch_deg)
        };
        self.eye = self.target + turned_offset * distance;
    }
}

/// Compass azimuth (radians, clockwise from north, +y) and elevation (radians) of `v`.
fn yaw_pitch(v: DVec3) -> (f64, f64) {
    let v = v.normalize();
    (v.x.atan2(v.y), v.z.clamp(-1.0, 1.0).asin())
}

/// The unit direction of `v` turned by `yaw_deg` clockwise and `pitch_deg` up, the pitch
/// kept within ±[`MAX_PITCH_DEG`].
fn turned(v: DVec3, yaw_deg: f64, pitch_deg: f64) -> DVec3 {
    let (yaw, pitch) = yaw_pitch(v);
    let limit = MAX_PITCH_DEG.to_radians();
    let yaw = yaw + yaw_deg.to_radians();
    let pitch = (pitch + pitch_deg.to_radians()).clamp(-limit, limit);
    DVec3::new(yaw.sin() * pitch.cos(), yaw.cos() * pitch.cos(), pitch.sin())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn start() -> CameraController {
        let camera =
            Camera::look_at(DVec3::new(0.0, -100.0, 50.0), DVec3::ZERO, DVec3::Z, 45.0, 64, 36)
                .unwrap();
        CameraController::new(&camera, 200.0)
    }

    fn close(a: DVec3, b: DVec3) -> bool {
        (a - b).length() < 1e-9 * (1.0 + a.length())
    }

    #[test]
    fn an_untouched_controller_gives_back_the_camera_it_started_from() {
        let camera = Camera::look_at(
            DVec3::new(10.0, 10.0, 10.0),
            DVec3::new(10.0, 10.0, 0.0),
            DVec3::Y,
            30.0,
            64,
            36,
        )
        .unwrap();
        let controller = CameraController::new(&camera, 50.0);
        assert_eq!(controller.camera(64, 36).unwrap(), camera);
        let mut idle = controller.clone();
        assert!(!idle.apply(Motion::default(), 0.5));
        assert_eq!(idle, controller);
    }

    #[test]
    fn flying_forward_moves_level_and_keeps_the_view_direction() {
        let mut c = start();
        c.toggle_navigation();
        assert_eq!(c.navigation(), Navigation::Fly);
        let before = c.target() - c.eye();
        assert!(c.apply(Motion { forward: 1.0, ..Motion::default() }, 1.0));
        // A quarter of the scene's size (200) a second, due north, at the same height.
        assert!(close(c.eye(), DVec3::new(0.0, -50.0, 50.0)), "{}", c.eye());
        assert!(close(c.target() - c.eye(), before));
        c.apply(Motion { up: -1.0, right: 1.0, ..Motion::default() }, 0.2);
        assert!(close(c.eye(), DVec3::new(10.0, -50.0, 40.0)), "{}", c.eye());
    }

    #[test]
    fn turning_in_flight_keeps_the_eye_and_stops_short_of_straight_down() {
        let mut c = start();
        c.toggle_navigation();
        let eye = c.eye();
        c.apply(Motion { yaw: 1.0, ..Motion::default() }, 1.5); // 90 degrees to the right
        assert_eq!(c.eye(), eye);
        let dir = (c.target() - c.eye()).normalize();
        assert!(dir.x > 0.89 && dir.y.abs() < 1e-9, "{dir}");
        c.drag(0.0, 10_000.0); // far down
        let dir = (c.target() - c.eye()).normalize();
        assert!((dir.z.asin().to_degrees() + MAX_PITCH_DEG).abs() < 1e-9, "{dir}");
        assert!(c.camera(64, 36).is_ok());
    }

    #[test]
    fn orbiting_keeps_the_target_and_the_distance_and_the_wheel_dollies() {
        let mut c = start();
        let (target, distance) = (c.target(), (c.eye() - c.target()).length());
        c.apply(Motion { right: 1.0, up: 1.0, ..Motion::default() }, 0.5);
        assert_eq!(c.target(), target);
        assert!(((c.eye() - target).length() - distance).abs() < 1e-9);
        assert!(c.eye().x.abs() > 1.0, "the eye went round: {}", c.eye());
        c.wheel(1.0);
        assert!(((c.eye() - target).length() - 0.9 * distance).abs() < 1e-9);
        c.apply(Motion { forward: 1.0, ..Motion::default() }, 0.1);
        assert!((c.eye() - target).length() < 0.9 * distance);
    }

    #[test]
    fn the_wheel_changes_the_fly_speed_within_bounds() {
        let mut c = start();
        c.toggle_navigation();
        c.wheel(2.0);
        assert!((c.speed() - 1.5625).abs() < 1e-12);
        c.wheel(-1000.0);
        assert_eq!(c.speed(), 1e-3);
    }
}
