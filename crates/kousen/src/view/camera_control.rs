//! The viewer's camera: mouse and keyboard input turned into a `scene::Camera`, without any
//! windowing types so that the app maps its events onto it and tests can drive it directly.
//!
//! Conventions: drag deltas are in physical pixels with window coordinates (x grows to the
//! right, y grows downward). Dragging right turns the view to the right (orbit: the camera
//! circles to the left around the pivot, so the scene turns with the cursor); dragging down
//! tilts the view downward (orbit: the camera rises). Panning drags the scene with the cursor.

use glam::{Vec2, Vec3};
use scene::{Bounds, Camera};

/// Orbit turn per pixel of drag.
pub const ORBIT_RADIANS_PER_PIXEL: f32 = 0.005;
/// Look-around turn per pixel of drag; slower than orbit since the whole view swings.
pub const LOOK_RADIANS_PER_PIXEL: f32 = 0.003;
/// Distance to the pivot is multiplied by this per wheel line towards the pivot.
pub const ZOOM_FACTOR_PER_LINE: f32 = 0.9;
/// Fly speed in scene diagonals per second.
pub const FLY_SPEED_PER_SCENE_SIZE: f32 = 0.25;
/// Pitch stays this far short of the poles so that the frame never degenerates.
const MAX_PITCH: f32 = 89.0 * std::f32::consts::PI / 180.0;
/// The pivot is never closer than this fraction of the scene diagonal when starting from a camera.
const MIN_PIVOT_FRACTION: f32 = 0.1;
/// Zoom keeps the distance to the pivot within these fractions of the scene diagonal.
const MIN_DISTANCE_FRACTION: f32 = 1e-3;
const MAX_DISTANCE_FRACTION: f32 = 1e3;
/// A hitch longer than this does not fling the camera across the scene.
const MAX_FLY_STEP_SECONDS: f32 = 1.0;
/// `+Y` stays the world up unless the starting camera is rolled further than this about its
/// view axis relative to `+Y` (cos 60°): then the scene is taken to be, say, Z-up.
const MIN_UP_ALIGNMENT: f32 = 0.5;

/// What a mouse drag does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DragMode {
    /// Circle around the pivot.
    Orbit,
    /// Slide eye and pivot in the view plane.
    Pan,
    /// Turn the view direction in place.
    Look,
}

/// Which buttons/modifiers make which drag: left → Orbit, left+shift → Pan, middle → Pan,
/// right → Look. With several buttons held, left wins over middle over right.
pub fn drag_mode(left: bool, middle: bool, right: bool, shift: bool) -> Option<DragMode> {
    match (left, middle, right) {
        (true, _, _) if shift => Some(DragMode::Pan),
        (true, _, _) => Some(DragMode::Orbit),
        (false, true, _) => Some(DragMode::Pan),
        (false, false, true) => Some(DragMode::Look),
        (false, false, false) => None,
    }
}

/// A held key that moves the camera: W S A D E Q.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FlyKey {
    Forward,
    Back,
    Left,
    Right,
    Up,
    Down,
}

impl FlyKey {
    const ALL: [FlyKey; 6] = [
        FlyKey::Forward,
        FlyKey::Back,
        FlyKey::Left,
        FlyKey::Right,
        FlyKey::Up,
        FlyKey::Down,
    ];

    fn index(self) -> usize {
        self as usize
    }
}

/// Where the camera is: angles rather than vectors, so that many small moves keep the frame
/// orthonormal instead of accumulating drift.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Pose {
    pivot: Vec3,
    /// Eye-to-pivot distance, > 0.
    distance: f32,
    /// Heading about the world up axis; positive turns left.
    yaw: f32,
    /// Elevation above the horizon, within ±`MAX_PITCH`.
    pitch: f32,
}

/// The viewer's camera state, driven by drags, the wheel and held fly keys.
#[derive(Clone, Debug)]
pub struct CameraController {
    pose: Pose,
    yfov: f32,
    /// For an orthographic camera, its film's half height per unit of distance to the pivot:
    /// zooming in shrinks the view as it would a perspective camera's.
    orthographic_scale: Option<f32>,
    world_up: Vec3,
    /// Horizontal direction at yaw 0.
    yaw_zero: Vec3,
    /// Horizontal direction at yaw +90°: `world_up × yaw_zero`.
    yaw_quarter: Vec3,
    scene_center: Vec3,
    /// Scene diagonal, > 0; sets the speeds.
    scene_size: f32,
    held: [bool; 6],
}

impl CameraController {
    /// Starts from a scene camera. `scene_bounds` sets the speeds (fly speed ∝ scene size, pan
    /// ∝ distance to the pivot) and the orbit pivot: the point along the view ray at the depth
    /// of the scene's centre, but at least a tenth of the scene size ahead of the eye.
    pub fn new(camera: &Camera, scene_bounds: Bounds) -> Self {
        let diagonal = scene_bounds.extent().length();
        let scene_size = if diagonal.is_finite() && diagonal > 0.0 {
            diagonal
        } else {
            1.0
        };
        let center = scene_bounds.center();
        let scene_center = if center.is_finite() {
            center
        } else {
            camera.eye + camera.forward * scene_size
        };
        let world_up = world_up_for(camera);
        let (yaw_zero, _) = world_up.any_orthonormal_pair();
        let mut controller = CameraController {
            pose: Pose {
                pivot: Vec3::ZERO,
                distance: 1.0,
                yaw: 0.0,
                pitch: 0.0,
            },
            yfov: camera.yfov,
            orthographic_scale: None,
            world_up,
            yaw_zero,
            yaw_quarter: world_up.cross(yaw_zero),
            scene_center,
            scene_size,
            held: [false; 6],
        };
        controller.set_camera(camera);
        controller
    }

    /// The current view, named "view", with no aspect ratio of its own (the window's applies),
    /// a pinhole (the overlay's lens applies, `RenderControls::lens`), of the projection of the
    /// camera it last jumped to.
    pub fn camera(&self) -> Camera {
        let forward = self.forward();
        let right = self.right();
        let projection = match self.orthographic_scale {
            Some(scale) => scene::Projection::Orthographic {
                half_height: scale * self.pose.distance,
            },
            None => scene::Projection::Perspective,
        };
        Camera {
            name: "view".to_string(),
            eye: self.eye(),
            forward,
            up: right.cross(forward).normalize(),
            yfov: self.yfov,
            projection,
            aspect_ratio: None,
            lens: scene::Lens::PINHOLE,
        }
    }

    /// Half the height the view shows at the pivot's distance, per unit of that distance.
    fn half_height_per_distance(&self) -> f32 {
        self.orthographic_scale
            .unwrap_or_else(|| (0.5 * self.yfov).tan())
    }

    /// Jumps to `camera` (e.g. a glTF camera picked in the UI), keeping the world up axis and
    /// the speeds. The pivot is placed as in [`CameraController::new`]. A camera looking along
    /// the world up axis gets its pitch clamped just short of the pole.
    pub fn set_camera(&mut self, camera: &Camera) {
        let forward = camera.forward.try_normalize().unwrap_or(self.yaw_zero);
        let sin_pitch = forward.dot(self.world_up).clamp(-1.0, 1.0);
        let cos_pitch = (1.0 - sin_pitch * sin_pitch).sqrt();
        // For a camera without roll, up = −sin·heading + cos·world_up, so this recovers the
        // heading even when `forward` is (nearly) vertical and has no horizontal part.
        let heading = forward * cos_pitch - camera.up * sin_pitch;
        let horizontal = |v: Vec3| v - self.world_up * v.dot(self.world_up);
        let heading = horizontal(heading)
            .try_normalize()
            .or_else(|| horizontal(forward).try_normalize())
            .unwrap_or(self.yaw_zero);
        let yaw = heading
            .dot(self.yaw_quarter)
            .atan2(heading.dot(self.yaw_zero));
        let pitch = sin_pitch.asin().clamp(-MAX_PITCH, MAX_PITCH);
        let depth = (self.scene_center - camera.eye).dot(forward);
        let distance = depth.max(MIN_PIVOT_FRACTION * self.scene_size);
        self.yfov = camera.yfov;
        self.orthographic_scale = match camera.projection {
            scene::Projection::Orthographic { half_height } => Some(half_height / distance),
            scene::Projection::Perspective => None,
        };
        self.pose = Pose {
            // Along the (possibly clamped) view direction, so that the eye stays put.
            pivot: camera.eye + self.forward_for(yaw, pitch) * distance,
            distance,
            yaw,
            pitch,
        };
    }

    /// The point that orbit circles around and zoom approaches; always straight ahead.
    #[cfg(test)]
    pub fn pivot(&self) -> Vec3 {
        self.pose.pivot
    }

    /// Mouse moved by `delta` physical pixels (y down) while dragging in `mode`. Orbit and look
    /// turn by a fixed angle per pixel; pan scales by `viewport_height` (pixels) so that the
    /// point at the pivot's depth follows the cursor. Returns true if the camera changed.
    pub fn drag(&mut self, mode: DragMode, delta: Vec2, viewport_height: f32) -> bool {
        if !delta.is_finite() {
            return false;
        }
        let old = self.pose;
        let mut new = old;
        match mode {
            DragMode::Orbit => {
                // Pivot and distance stay; the eye follows the new direction.
                (new.yaw, new.pitch) = turned(old, delta * ORBIT_RADIANS_PER_PIXEL);
            }
            DragMode::Look => {
                (new.yaw, new.pitch) = turned(old, delta * LOOK_RADIANS_PER_PIXEL);
                // The eye stays; the pivot swings around it at the same distance. Skipped
                // against the pitch clamp, where re-deriving the pivot would only add rounding.
                if (new.yaw, new.pitch) != (old.yaw, old.pitch) {
                    new.pivot = self.eye() + self.forward_for(new.yaw, new.pitch) * old.distance;
                }
            }
            DragMode::Pan => {
                let visible_height = 2.0 * old.distance * self.half_height_per_distance();
                let world_per_pixel = visible_height / viewport_height.max(1.0);
                let up = self.right().cross(self.forward());
                // Dragging right moves the scene right, so the camera left; y grows downward.
                let offset = (up * delta.y - self.right() * delta.x) * world_per_pixel;
                new.pivot = old.pivot + offset;
            }
        }
        self.accept(new)
    }

    /// Mouse wheel by `lines` (positive = towards the pivot): the distance to the pivot is
    /// multiplied by `ZOOM_FACTOR_PER_LINE` per line, kept between a small and a large fraction
    /// of the scene size, so it never reaches zero or passes through the pivot. Touchpads
    /// report pixels; the app converts them to (fractional) lines. Returns true if changed.
    pub fn zoom(&mut self, lines: f32) -> bool {
        if !lines.is_finite() {
            return false;
        }
        let old = self.pose;
        let scaled = old.distance * ZOOM_FACTOR_PER_LINE.powf(lines);
        // The bounds include the current distance so that clamping never moves the wrong way.
        let nearest = (MIN_DISTANCE_FRACTION * self.scene_size).min(old.distance);
        let farthest = (MAX_DISTANCE_FRACTION * self.scene_size).max(old.distance);
        let distance = if scaled.is_nan() {
            old.distance
        } else {
            scaled.clamp(nearest, farthest)
        };
        self.accept(Pose { distance, ..old })
    }

    /// A fly key went down (`pressed`) or up.
    pub fn key(&mut self, key: FlyKey, pressed: bool) {
        self.held[key.index()] = pressed;
    }

    /// Releases every fly key, e.g. when the window loses focus and key-ups would be missed.
    pub fn release_keys(&mut self) {
        self.held = [false; 6];
    }

    /// Whether any fly key is held; the app keeps calling `update` (and redrawing) meanwhile.
    pub fn is_flying(&self) -> bool {
        self.held.contains(&true)
    }

    /// Fly speed in world units per second, proportional to the scene size.
    pub fn fly_speed(&self) -> f32 {
        FLY_SPEED_PER_SCENE_SIZE * self.scene_size
    }

    /// Moves eye and pivot by the held keys for `seconds` (at most one second per call):
    /// W/S along the view direction, A/D along the camera's right, E/Q along the world up.
    /// Diagonal moves are no faster than straight ones. Returns true if the camera moved.
    pub fn update(&mut self, seconds: f32) -> bool {
        if !(seconds.is_finite() && seconds > 0.0) {
            return false;
        }
        let direction = FlyKey::ALL
            .iter()
            .filter(|key| self.held[key.index()])
            .map(|key| self.fly_direction(*key))
            .sum::<Vec3>();
        let Some(direction) = direction.try_normalize() else {
            return false;
        };
        let step = direction * self.fly_speed() * seconds.min(MAX_FLY_STEP_SECONDS);
        let old = self.pose;
        self.accept(Pose {
            pivot: old.pivot + step,
            ..old
        })
    }

    fn fly_direction(&self, key: FlyKey) -> Vec3 {
        match key {
            FlyKey::Forward => self.forward(),
            FlyKey::Back => -self.forward(),
            FlyKey::Right => self.right(),
            FlyKey::Left => -self.right(),
            FlyKey::Up => self.world_up,
            FlyKey::Down => -self.world_up,
        }
    }

    /// Takes `pose` unless it is not finite (a huge pan or fly step overflowing); returns
    /// whether anything changed.
    fn accept(&mut self, pose: Pose) -> bool {
        let finite = pose.pivot.is_finite() && self.eye_for(&pose).is_finite();
        if !finite || pose == self.pose {
            return false;
        }
        self.pose = pose;
        true
    }

    fn forward(&self) -> Vec3 {
        self.forward_for(self.pose.yaw, self.pose.pitch)
    }

    fn forward_for(&self, yaw: f32, pitch: f32) -> Vec3 {
        let heading = self.yaw_zero * yaw.cos() + self.yaw_quarter * yaw.sin();
        (heading * pitch.cos() + self.world_up * pitch.sin()).normalize()
    }

    /// `forward × world_up`, normalised; it depends on the yaw alone, so it stays well defined
    /// at any pitch.
    fn right(&self) -> Vec3 {
        let yaw = self.pose.yaw;
        (self.yaw_zero * yaw.sin() - self.yaw_quarter * yaw.cos()).normalize()
    }

    fn eye(&self) -> Vec3 {
        self.eye_for(&self.pose)
    }

    fn eye_for(&self, pose: &Pose) -> Vec3 {
        pose.pivot - self.forward_for(pose.yaw, pose.pitch) * pose.distance
    }
}

/// The yaw and pitch after turning by `angles` (x right, y down, radians): right turns right,
/// down tilts down. Yaw wraps so it keeps its precision; pitch stops short of the poles.
fn turned(pose: Pose, angles: Vec2) -> (f32, f32) {
    let yaw = (pose.yaw - angles.x).rem_euclid(std::f32::consts::TAU);
    let pitch = (pose.pitch - angles.y).clamp(-MAX_PITCH, MAX_PITCH);
    (yaw, pitch)
}

/// The axis that orbit yaws about and E/Q move along: `+Y` if it fits the camera, else the
/// coordinate axis nearest the camera's up if that fits (a Z-up scene, say), else the camera's
/// own up. An axis fits unless the camera is rolled more than 60° about its view direction
/// relative to it; a camera looking straight along an axis says nothing about roll, so a
/// camera looking straight up or down keeps `+Y`.
fn world_up_for(camera: &Camera) -> Vec3 {
    let fits = |axis: Vec3| {
        let along = camera.forward.dot(axis);
        let horizontal = (1.0 - along * along).max(0.0).sqrt();
        // Without roll, up·axis equals the horizontal part of forward; a roll r scales it by
        // cos r.
        camera.up.dot(axis) >= MIN_UP_ALIGNMENT * horizontal - 1e-4
    };
    let nearest_axis = {
        let up = camera.up;
        let index = up.abs().max_position();
        Vec3::AXES[index] * up[index].signum()
    };
    [Vec3::Y, nearest_axis]
        .into_iter()
        .find(|&axis| fits(axis))
        .unwrap_or_else(|| camera.up.try_normalize().unwrap_or(Vec3::Y))
}

#[cfg(test)]
mod tests {
    use super::*;

    const TOLERANCE: f32 = 1e-5;

    fn bounds() -> Bounds {
        Bounds {
            min: Vec3::new(-1.0, -1.0, -1.0),
            max: Vec3::new(1.0, 1.0, 1.0),
        }
    }

    fn start_camera() -> Camera {
        Camera::look_at(
            Vec3::new(1.0, 2.0, 5.0),
            Vec3::ZERO,
            Vec3::Y,
            50f32.to_radians(),
        )
        .unwrap()
    }

    fn controller() -> CameraController {
        CameraController::new(&start_camera(), bounds())
    }

    fn assert_close(a: Vec3, b: Vec3, tolerance: f32) {
        assert!(
            a.distance(b) <= tolerance,
            "{a} and {b} differ by {}",
            a.distance(b)
        );
    }

    /// Unit, orthogonal forward and up, all finite.
    fn assert_valid_frame(camera: &Camera) {
        assert!(camera.eye.is_finite(), "eye {}", camera.eye);
        assert!((camera.forward.length() - 1.0).abs() < TOLERANCE);
        assert!((camera.up.length() - 1.0).abs() < TOLERANCE);
        assert!(camera.forward.dot(camera.up).abs() < TOLERANCE);
        assert!(camera.yfov > 0.0 && camera.yfov < std::f32::consts::PI);
    }

    /// The pivot lies straight ahead of the eye at the kept distance.
    fn assert_pivot_centred(c: &CameraController) {
        let camera = c.camera();
        let to_pivot = c.pivot() - camera.eye;
        assert_close(to_pivot.normalize(), camera.forward, 1e-4);
    }

    #[test]
    fn drag_mode_maps_buttons() {
        assert_eq!(drag_mode(false, false, false, false), None);
        assert_eq!(drag_mode(false, false, false, true), None);
        assert_eq!(drag_mode(true, false, false, false), Some(DragMode::Orbit));
        assert_eq!(drag_mode(true, false, false, true), Some(DragMode::Pan));
        assert_eq!(drag_mode(false, true, false, false), Some(DragMode::Pan));
        assert_eq!(drag_mode(false, true, false, true), Some(DragMode::Pan));
        assert_eq!(drag_mode(false, false, true, false), Some(DragMode::Look));
        assert_eq!(drag_mode(false, false, true, true), Some(DragMode::Look));
        assert_eq!(drag_mode(true, true, true, false), Some(DragMode::Orbit));
        assert_eq!(drag_mode(false, true, true, false), Some(DragMode::Pan));
    }

    #[test]
    fn new_controller_reproduces_the_starting_camera() {
        let start = start_camera();
        let camera = controller().camera();
        assert_close(camera.eye, start.eye, TOLERANCE);
        assert_close(camera.forward, start.forward, TOLERANCE);
        assert_close(camera.up, start.up, TOLERANCE);
        assert_eq!(camera.yfov, start.yfov);
        assert_eq!(camera.name, "view");
        assert_eq!(camera.aspect_ratio, None);
        assert_valid_frame(&camera);
    }

    #[test]
    fn pivot_is_at_the_depth_of_the_scene_centre() {
        let c = controller();
        let start = start_camera();
        // The camera looks straight at the centre, so the pivot is the centre.
        assert_close(c.pivot(), Vec3::ZERO, 1e-5);

        // Looking away from the scene: the pivot is still a little way ahead.
        let away = Camera::look_at(start.eye, start.eye * 2.0, Vec3::Y, start.yfov).unwrap();
        let c = CameraController::new(&away, bounds());
        let depth = (c.pivot() - away.eye).dot(away.forward);
        assert!(depth > 0.0);
        assert!((depth - MIN_PIVOT_FRACTION * bounds().extent().length()).abs() < 1e-5);
        assert_pivot_centred(&c);
    }

    #[test]
    fn orbit_keeps_the_pivot_and_the_distance() {
        let mut c = controller();
        let pivot = c.pivot();
        let distance = c.camera().eye.distance(pivot);
        let start = c.camera();
        assert!(c.drag(DragMode::Orbit, Vec2::new(40.0, -25.0), 600.0));
        let camera = c.camera();
        assert_eq!(c.pivot(), pivot);
        assert!((camera.eye.distance(pivot) - distance).abs() < 1e-4);
        assert!(camera.eye.distance(start.eye) > 0.1);
        assert_pivot_centred(&c);
        assert_valid_frame(&camera);
    }

    #[test]
    fn orbit_directions_follow_the_conventions() {
        // Dragging right circles the camera to the left, dragging down raises it.
        let start = start_camera();
        let mut c = controller();
        c.drag(DragMode::Orbit, Vec2::new(20.0, 0.0), 600.0);
        assert!((c.camera().eye - start.eye).dot(start.right()) < 0.0);
        assert!((c.camera().eye.y - start.eye.y).abs() < 1e-4);

        let mut c = controller();
        c.drag(DragMode::Orbit, Vec2::new(0.0, 20.0), 600.0);
        assert!(c.camera().eye.y > start.eye.y);
        assert!(c.camera().forward.y < start.forward.y);
    }

    #[test]
    fn orbit_there_and_back_returns_to_the_start() {
        let start = controller().camera();
        let mut c = controller();
        for _ in 0..100 {
            c.drag(DragMode::Orbit, Vec2::new(-7.0, 1.0), 600.0);
        }
        for _ in 0..100 {
            c.drag(DragMode::Orbit, Vec2::new(7.0, -1.0), 600.0);
        }
        let camera = c.camera();
        assert_close(camera.eye, start.eye, 1e-4);
        assert_close(camera.forward, start.forward, 1e-4);
        assert_close(camera.up, start.up, 1e-4);
    }

    #[test]
    fn many_small_orbits_do_not_drift_from_a_valid_frame() {
        let mut c = controller();
        let distance = c.camera().eye.distance(c.pivot());
        for i in 0..10_000 {
            let delta = Vec2::new((i as f32 * 0.37).sin() * 5.0, (i as f32 * 0.11).cos() * 5.0);
            c.drag(DragMode::Orbit, delta, 600.0);
        }
        let camera = c.camera();
        assert_valid_frame(&camera);
        assert!((camera.eye.distance(c.pivot()) - distance).abs() < 1e-3);
        assert!(camera.right().dot(Vec3::Y).abs() < TOLERANCE, "no roll");
    }

    #[test]
    fn pitch_is_clamped_short_of_the_poles() {
        for vertical in [1e6, -1e6, f32::MAX, -f32::MAX] {
            let mut c = controller();
            assert!(c.drag(DragMode::Orbit, Vec2::new(0.0, vertical), 600.0));
            let camera = c.camera();
            assert_valid_frame(&camera);
            let alignment = camera.forward.dot(Vec3::Y).abs();
            assert!(alignment < 0.9999, "forward nearly parallel to up");
            assert!(alignment > 0.999, "clamped near, not far from, the pole");
            assert_pivot_centred(&c);
            // Further pushes against the clamp change nothing.
            assert!(!c.drag(DragMode::Orbit, Vec2::new(0.0, vertical), 600.0));
            assert!(!c.drag(DragMode::Look, Vec2::new(0.0, vertical), 600.0));
        }
    }

    #[test]
    fn zero_and_non_finite_deltas_change_nothing() {
        let mut c = controller();
        let start = c.camera();
        for mode in [DragMode::Orbit, DragMode::Pan, DragMode::Look] {
            assert!(!c.drag(mode, Vec2::ZERO, 600.0));
            assert!(!c.drag(mode, Vec2::new(f32::NAN, 1.0), 600.0));
            assert!(!c.drag(mode, Vec2::new(1.0, f32::INFINITY), 600.0));
        }
        assert!(!c.zoom(0.0));
        assert!(!c.zoom(f32::NAN));
        assert!(!c.update(0.0));
        assert_eq!(c.camera(), start);
    }

    #[test]
    fn huge_horizontal_drags_stay_valid() {
        let mut c = controller();
        c.drag(DragMode::Orbit, Vec2::new(f32::MAX, 0.0), 600.0);
        c.drag(DragMode::Look, Vec2::new(-f32::MAX, 0.0), 600.0);
        c.drag(DragMode::Pan, Vec2::new(f32::MAX, f32::MAX), 600.0);
        c.drag(DragMode::Pan, Vec2::new(1e30, 0.0), 0.0);
        assert_valid_frame(&c.camera());
        assert!(c.pivot().is_finite());
    }

    #[test]
    fn zoom_scales_the_distance_by_the_factor() {
        let mut c = controller();
        let pivot = c.pivot();
        let distance = c.camera().eye.distance(pivot);
        assert!(c.zoom(1.0));
        let zoomed = c.camera().eye.distance(pivot);
        assert!((zoomed - distance * ZOOM_FACTOR_PER_LINE).abs() < 1e-5);
        assert!(c.zoom(2.0));
        let zoomed = c.camera().eye.distance(pivot);
        assert!((zoomed - distance * ZOOM_FACTOR_PER_LINE.powi(3)).abs() < 1e-5);
        assert_eq!(c.pivot(), pivot);
        assert_pivot_centred(&c);

        // Out by as much returns to the start.
        assert!(c.zoom(-3.0));
        assert_close(c.camera().eye, start_camera().eye, 1e-5);
    }

    /// An orthographic camera stays one, its film as tall as the file says at first, and
    /// zooming shrinks the film with the distance to the pivot, as a perspective view shrinks
    /// what it shows; panning moves the pivot by the film's own scale.
    #[test]
    fn an_orthographic_camera_zooms_by_its_film() {
        let start = start_camera().orthographic(1.5).unwrap();
        let mut c = CameraController::new(&start, bounds());
        let half_height = |c: &CameraController| match c.camera().projection {
            scene::Projection::Orthographic { half_height } => half_height,
            scene::Projection::Perspective => panic!("the view turned perspective"),
        };
        assert!((half_height(&c) - 1.5).abs() < 1e-5);
        assert!(c.zoom(2.0));
        let expected = 1.5 * ZOOM_FACTOR_PER_LINE.powi(2);
        assert!((half_height(&c) - expected).abs() < 1e-5);
        // Dragging by the viewport's height pans by the film's height.
        let pivot = c.pivot();
        assert!(c.drag(DragMode::Pan, Vec2::new(0.0, 600.0), 600.0));
        assert!((c.pivot().distance(pivot) - 2.0 * expected).abs() < 1e-4);
        c.set_camera(&start_camera());
        assert_eq!(c.camera().projection, scene::Projection::Perspective);
    }

    #[test]
    fn zoom_never_reaches_or_passes_the_pivot() {
        let mut c = controller();
        let forward = c.camera().forward;
        for lines in [1e3, 1e9, f32::MAX] {
            c.zoom(lines);
            let camera = c.camera();
            let distance = camera.eye.distance(c.pivot());
            let minimum = MIN_DISTANCE_FRACTION * bounds().extent().length();
            assert!(distance > 0.0);
            assert!(distance >= minimum * 0.999, "{distance} < {minimum}");
            assert!(
                (c.pivot() - camera.eye).dot(forward) > 0.0,
                "passed the pivot"
            );
            assert_valid_frame(&camera);
        }
        // At the minimum, further zooming in changes nothing.
        assert!(!c.zoom(1.0));
        // Huge zooms out stay finite.
        c.zoom(-f32::MAX);
        assert_valid_frame(&c.camera());
        assert!(!c.zoom(-1.0));
        assert!(c.zoom(1.0));
    }

    #[test]
    fn pan_moves_eye_and_pivot_together_in_the_view_plane() {
        let mut c = controller();
        let before = c.camera();
        let pivot = c.pivot();
        assert!(c.drag(DragMode::Pan, Vec2::new(30.0, -10.0), 600.0));
        let after = c.camera();
        let eye_move = after.eye - before.eye;
        let pivot_move = c.pivot() - pivot;
        assert_close(eye_move, pivot_move, 1e-5);
        assert!(eye_move.length() > 0.0);
        assert!(eye_move.dot(before.forward).abs() < 1e-5);
        assert_close(after.forward, before.forward, 1e-6);
        assert_close(after.up, before.up, 1e-6);
    }

    #[test]
    fn pan_by_the_viewport_height_moves_by_the_visible_height() {
        let height = 720.0;
        let mut c = controller();
        let start = c.camera();
        let distance = start.eye.distance(c.pivot());
        let visible = 2.0 * distance * (0.5 * start.yfov).tan();

        // Dragging down moves the scene down, so the camera up.
        assert!(c.drag(DragMode::Pan, Vec2::new(0.0, height), height));
        assert_close(c.camera().eye, start.eye + start.up * visible, 1e-4);

        // Dragging right moves the camera left.
        let mut c = controller();
        assert!(c.drag(DragMode::Pan, Vec2::new(height, 0.0), height));
        assert_close(c.camera().eye, start.eye - start.right() * visible, 1e-4);
    }

    #[test]
    fn pan_with_a_zero_viewport_stays_finite() {
        let mut c = controller();
        assert!(c.drag(DragMode::Pan, Vec2::new(3.0, 4.0), 0.0));
        assert_valid_frame(&c.camera());
        assert!(c.pivot().is_finite());
    }

    #[test]
    fn look_keeps_the_eye_and_turns_the_view() {
        let mut c = controller();
        let before = c.camera();
        let distance = before.eye.distance(c.pivot());
        assert!(c.drag(DragMode::Look, Vec2::new(50.0, 20.0), 600.0));
        let after = c.camera();
        assert_close(after.eye, before.eye, 1e-5);
        assert!(after.forward.distance(before.forward) > 0.05);
        // Right turns right, down tilts down.
        assert!(after.forward.dot(before.right()) > 0.0);
        assert!(after.forward.y < before.forward.y);
        assert!((after.eye.distance(c.pivot()) - distance).abs() < 1e-4);
        assert_pivot_centred(&c);
        assert_valid_frame(&after);
    }

    fn fly(c: &mut CameraController, keys: &[FlyKey], seconds: f32) -> bool {
        for &key in keys {
            c.key(key, true);
        }
        let moved = c.update(seconds);
        for &key in keys {
            c.key(key, false);
        }
        moved
    }

    #[test]
    fn fly_forward_moves_along_the_view_at_the_speed() {
        let mut c = controller();
        let start = c.camera();
        let pivot = c.pivot();
        let speed = c.fly_speed();
        assert!((speed - FLY_SPEED_PER_SCENE_SIZE * bounds().extent().length()).abs() < 1e-6);
        assert!(fly(&mut c, &[FlyKey::Forward], 1.0));
        assert_close(c.camera().eye, start.eye + start.forward * speed, 1e-5);
        assert_close(c.pivot(), pivot + start.forward * speed, 1e-5);
        assert_close(c.camera().forward, start.forward, 1e-6);
    }

    #[test]
    fn fly_keys_move_in_their_directions() {
        let start = start_camera();
        let cases = [
            (FlyKey::Back, -start.forward),
            (FlyKey::Right, start.right()),
            (FlyKey::Left, -start.right()),
            (FlyKey::Up, Vec3::Y),
            (FlyKey::Down, -Vec3::Y),
        ];
        for (key, direction) in cases {
            let mut c = controller();
            let speed = c.fly_speed();
            assert!(fly(&mut c, &[key], 0.5));
            assert_close(c.camera().eye, start.eye + direction * speed * 0.5, 1e-5);
        }
    }

    #[test]
    fn diagonal_flight_is_no_faster() {
        let mut c = controller();
        let start = c.camera();
        assert!(fly(&mut c, &[FlyKey::Forward, FlyKey::Right], 1.0));
        let moved = c.camera().eye.distance(start.eye);
        assert!((moved - c.fly_speed()).abs() < 1e-5);
    }

    #[test]
    fn held_keys_stop_when_released_and_opposites_cancel() {
        let mut c = controller();
        assert!(!c.is_flying());
        assert!(!c.update(1.0), "nothing held");

        c.key(FlyKey::Forward, true);
        assert!(c.is_flying());
        assert!(c.update(0.1));
        c.key(FlyKey::Forward, false);
        assert!(!c.is_flying());
        let stopped = c.camera();
        assert!(!c.update(0.1));
        assert_eq!(c.camera(), stopped);

        c.key(FlyKey::Left, true);
        c.key(FlyKey::Right, true);
        assert!(c.is_flying());
        assert!(!c.update(0.1), "opposite keys cancel");
        assert_eq!(c.camera(), stopped);

        c.release_keys();
        assert!(!c.is_flying());
    }

    #[test]
    fn fly_ignores_bad_and_caps_long_steps() {
        let mut c = controller();
        c.key(FlyKey::Forward, true);
        assert!(!c.update(-1.0));
        assert!(!c.update(f32::NAN));
        assert!(!c.update(f32::INFINITY));
        let start = c.camera();
        assert!(c.update(f32::MAX));
        let moved = c.camera().eye.distance(start.eye);
        assert!((moved - c.fly_speed() * MAX_FLY_STEP_SECONDS).abs() < 1e-4);
    }

    #[test]
    fn a_camera_looking_straight_down_works() {
        for up in [Vec3::NEG_Z, Vec3::X, Vec3::Z] {
            let down = Camera {
                name: "down".into(),
                eye: Vec3::new(0.0, 5.0, 0.0),
                forward: Vec3::NEG_Y,
                up,
                yfov: 0.8,
                projection: scene::Projection::Perspective,
                aspect_ratio: None,
                lens: scene::Lens::PINHOLE,
            };
            let mut c = CameraController::new(&down, bounds());
            let camera = c.camera();
            assert_valid_frame(&camera);
            assert!(camera.forward.dot(Vec3::NEG_Y) > 0.999);
            // The image keeps its orientation: up stays (nearly) where it was.
            assert!(camera.up.dot(up) > 0.999);
            assert_close(camera.eye, down.eye, 1e-5);
            // The scene keeps +Y as its world up: E moves upward.
            assert!(fly(&mut c, &[FlyKey::Up], 1.0));
            assert!(c.camera().eye.y > down.eye.y);
            assert!(c.drag(DragMode::Orbit, Vec2::new(30.0, 30.0), 600.0));
            assert!(c.drag(DragMode::Look, Vec2::new(-30.0, -30.0), 600.0));
            assert_valid_frame(&c.camera());
            assert_pivot_centred(&c);
        }
    }

    #[test]
    fn a_camera_looking_straight_up_works() {
        let up_view = Camera {
            name: "up".into(),
            eye: Vec3::ZERO,
            forward: Vec3::Y,
            up: Vec3::X,
            yfov: 0.8,
            projection: scene::Projection::Perspective,
            aspect_ratio: None,
            lens: scene::Lens::PINHOLE,
        };
        let c = CameraController::new(&up_view, bounds());
        let camera = c.camera();
        assert_valid_frame(&camera);
        assert!(camera.forward.y > 0.999);
        assert!(camera.up.dot(Vec3::X) > 0.999);
    }

    #[test]
    fn a_z_up_scene_keeps_its_orientation() {
        let camera = Camera::look_at(
            Vec3::new(-6.0, 1.0, 2.0),
            Vec3::ZERO,
            Vec3::Z,
            50f32.to_radians(),
        )
        .unwrap();
        let mut c = CameraController::new(&camera, bounds());
        let view = c.camera();
        assert_close(view.eye, camera.eye, 1e-5);
        assert_close(view.forward, camera.forward, 1e-5);
        assert_close(view.up, camera.up, 1e-5);
        // E moves along +Z, and orbiting sideways keeps the height along +Z.
        assert!(fly(&mut c, &[FlyKey::Up], 1.0));
        assert_close(c.camera().eye, camera.eye + Vec3::Z * c.fly_speed(), 1e-5);
        let height = c.camera().eye.z;
        assert!(c.drag(DragMode::Orbit, Vec2::new(100.0, 0.0), 600.0));
        assert!((c.camera().eye.z - height).abs() < 1e-4);
    }

    #[test]
    fn a_strongly_rolled_camera_takes_the_nearest_fitting_axis() {
        // Rolled 80° about its view direction: +Y no longer fits, +X does.
        let roll = 80f32.to_radians();
        let rolled = Camera::look_at(
            Vec3::new(0.0, 0.0, -5.0),
            Vec3::ZERO,
            Vec3::new(roll.sin(), roll.cos(), 0.0),
            0.8,
        )
        .unwrap();
        let mut c = CameraController::new(&rolled, bounds());
        let view = c.camera();
        assert_close(view.eye, rolled.eye, 1e-5);
        assert_close(view.forward, rolled.forward, 1e-5);
        // The frame is rebuilt without roll about +X.
        assert!(view.right().dot(Vec3::X).abs() < 1e-5);
        assert!(view.up.dot(rolled.up) > 0.98);
        assert!(fly(&mut c, &[FlyKey::Up], 1.0));
        assert_close(c.camera().eye, rolled.eye + Vec3::X * c.fly_speed(), 1e-5);
    }

    #[test]
    fn set_camera_jumps_and_keeps_the_speeds() {
        let mut c = controller();
        let speed = c.fly_speed();
        let other = Camera::look_at(
            Vec3::new(-3.0, 0.5, -2.0),
            Vec3::new(0.5, 0.0, 0.0),
            Vec3::Y,
            0.6,
        )
        .unwrap();
        c.set_camera(&other);
        let camera = c.camera();
        assert_close(camera.eye, other.eye, 1e-5);
        assert_close(camera.forward, other.forward, 1e-5);
        assert_close(camera.up, other.up, 1e-5);
        assert_eq!(camera.yfov, other.yfov);
        assert_eq!(c.fly_speed(), speed);
        assert_pivot_centred(&c);
        let depth = (c.pivot() - other.eye).dot(other.forward);
        assert!((depth - (-other.eye).dot(other.forward)).abs() < 1e-4);
    }

    #[test]
    fn empty_or_flat_bounds_still_give_a_usable_controller() {
        let start = start_camera();
        for bounds in [
            Bounds::EMPTY,
            Bounds {
                min: Vec3::ONE,
                max: Vec3::ONE,
            },
        ] {
            let mut c = CameraController::new(&start, bounds);
            assert_close(c.camera().eye, start.eye, 1e-5);
            assert!(c.fly_speed() > 0.0);
            assert!(c.zoom(1.0));
            assert!(c.drag(DragMode::Orbit, Vec2::new(5.0, 5.0), 600.0));
            assert!(c.drag(DragMode::Pan, Vec2::new(5.0, 5.0), 600.0));
            assert_valid_frame(&c.camera());
            assert!(c.pivot().is_finite());
        }
    }
}
