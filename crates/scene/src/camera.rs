//! Cameras: from a file, from a look-at, or framed around a bounding box; pinholes, or thin
//! lenses that blur what lies off their plane of focus ([`Lens`]); perspective, or
//! orthographic ([`Projection`]).

use glam::{Mat4, Vec3};

use crate::Bounds;

/// A thin lens: rays leave its aperture, a disk of `radius` about the eye across the view (or
/// the regular polygon of `blades` sides inscribed in it), and every ray through one film
/// point meets the others on the plane `focus_distance` ahead of the eye (along `forward`),
/// where the scene is sharp; out of focus a point images as the aperture's shape. Radius 0 is
/// a pinhole (glTF cameras are).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Lens {
    pub radius: f32,
    pub focus_distance: f32,
    /// 0: a round aperture; 3 or more: a polygon with a vertex at angle `rotation` from the
    /// view's right towards its up.
    pub blades: u32,
    pub rotation: f32,
}

impl Lens {
    pub const PINHOLE: Lens = Lens {
        radius: 0.0,
        focus_distance: 0.0,
        blades: 0,
        rotation: 0.0,
    };

    /// The most blades an aperture may have (more is round to the eye).
    pub const MAX_BLADES: u32 = 64;

    /// This lens with a polygonal aperture of `blades` sides (0: round) turned by `rotation`
    /// radians; `None` for 1, 2 or more than [`Lens::MAX_BLADES`] blades or a non-finite turn.
    pub fn with_blades(self, blades: u32, rotation: f32) -> Option<Lens> {
        let valid =
            (blades == 0 || (3..=Self::MAX_BLADES).contains(&blades)) && rotation.is_finite();
        valid.then_some(Lens {
            blades,
            rotation,
            ..self
        })
    }

    /// A lens of `radius` focused at `focus_distance`: `None` unless the radius is finite
    /// and ≥ 0 and, for a lens (radius > 0), the distance finite and > 0.
    pub fn new(radius: f32, focus_distance: f32) -> Option<Lens> {
        let valid_radius = radius.is_finite() && radius >= 0.0;
        let valid_focus = radius == 0.0 || (focus_distance.is_finite() && focus_distance > 0.0);
        (valid_radius && valid_focus).then_some(Lens {
            radius,
            focus_distance,
            ..Lens::PINHOLE
        })
    }

    pub fn is_pinhole(&self) -> bool {
        self.radius == 0.0
    }
}

/// How a camera's rays leave its film.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Projection {
    /// From the eye, spread over the vertical field of view `Camera::yfov`.
    #[default]
    Perspective,
    /// Parallel, along the view, from the film: a rectangle about the eye across the view,
    /// `half_height` above and below it (glTF's `ymag`) and as wide as the image's aspect
    /// ratio makes it. Things keep their size however far away (plans, elevations,
    /// isometric views).
    Orthographic { half_height: f32 },
}

/// A camera. `forward`, `up` and `right()` form an orthonormal, right-handed frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    pub name: String,
    pub eye: Vec3,
    /// Unit viewing direction.
    pub forward: Vec3,
    /// Unit, orthogonal to `forward`.
    pub up: Vec3,
    /// Vertical field of view in radians, in (0, π) (a perspective camera's).
    pub yfov: f32,
    /// Perspective unless the file says otherwise.
    pub projection: Projection,
    /// Width / height, when the file states one.
    pub aspect_ratio: Option<f32>,
    /// A pinhole unless given one (`kousen render --aperture-radius`).
    pub lens: Lens,
}

/// The field of view of framed views, as in ANCHORS.md's benchmark cameras.
pub const DEFAULT_YFOV_DEGREES: f32 = 50.0;

/// Where ANCHORS.md's outside camera sits from the bounding box's centre, in diagonals.
pub const OUTSIDE_VIEW_OFFSET: Vec3 = Vec3::new(0.5, 0.35, 0.8);

impl Camera {
    /// A camera at `eye` looking at `target`. `None` when the frame is degenerate (eye equals
    /// target, or `up` is parallel to the view direction) or the field of view is not in (0, π).
    pub fn look_at(eye: Vec3, target: Vec3, up: Vec3, yfov: f32) -> Option<Camera> {
        let forward = (target - eye).try_normalize()?;
        let right = forward.cross(up).try_normalize()?;
        let valid_fov = yfov.is_finite() && yfov > 0.0 && yfov < std::f32::consts::PI;
        if !eye.is_finite() || !valid_fov {
            return None;
        }
        Some(Camera {
            name: String::new(),
            eye,
            forward,
            up: right.cross(forward),
            yfov,
            projection: Projection::Perspective,
            aspect_ratio: None,
            lens: Lens::PINHOLE,
        })
    }

    /// This camera made orthographic, its film `half_height` above and below the eye;
    /// `None` unless that is finite and > 0.
    pub fn orthographic(self, half_height: f32) -> Option<Camera> {
        (half_height.is_finite() && half_height > 0.0).then_some(Camera {
            projection: Projection::Orthographic { half_height },
            ..self
        })
    }

    pub fn is_orthographic(&self) -> bool {
        matches!(self.projection, Projection::Orthographic { .. })
    }

    /// A glTF camera: it looks down its node's −Z with +Y up. `None` if the matrix has no
    /// usable frame (a zero scale, say) or `yfov` is out of range.
    pub fn from_world_matrix(world_from_camera: Mat4, yfov: f32) -> Option<Camera> {
        let eye = world_from_camera.transform_point3(Vec3::ZERO);
        let forward = world_from_camera.transform_vector3(Vec3::NEG_Z);
        let up = world_from_camera.transform_vector3(Vec3::Y);
        Camera::look_at(eye, eye + forward, up, yfov)
    }

    /// ANCHORS.md's "outside" camera: from `c + D·(0.5, 0.35, 0.8)` towards the centre `c`,
    /// where `D` is the diagonal's length. Also the auto-framed view of a scene without cameras.
    pub fn outside_view(bounds: Bounds) -> Camera {
        Camera::outside_view_from(bounds, OUTSIDE_VIEW_OFFSET).named("auto (outside)")
    }

    /// A view of the bounding box's centre from `c + D·offset` (`offset` about unit length,
    /// not parallel to +Y), at the default field of view; [`Camera::outside_view`]'s kind.
    ///
    /// # Panics
    /// If `offset` is parallel to +Y (no frame).
    pub fn outside_view_from(bounds: Bounds, offset: Vec3) -> Camera {
        let center = bounds.center();
        let diagonal = bounds.extent().length().max(f32::MIN_POSITIVE);
        let eye = center + diagonal * offset;
        Camera::look_at(eye, center, Vec3::Y, DEFAULT_YFOV_DEGREES.to_radians())
            .expect("outside views look along no parallel of +Y")
            .named("auto (outside)")
    }

    /// ANCHORS.md's "inside" camera (the sponzas): from `lo + (hi−lo)·(0.85, 0.25, 0.5)`
    /// towards `lo + (hi−lo)·(0, 0.35, 0.5)`.
    pub fn inside_view(bounds: Bounds) -> Camera {
        let size = bounds.extent();
        let eye = bounds.min + size * Vec3::new(0.85, 0.25, 0.5);
        let target = bounds.min + size * Vec3::new(0.0, 0.35, 0.5);
        Camera::look_at(eye, target, Vec3::Y, DEFAULT_YFOV_DEGREES.to_radians())
            .unwrap_or_else(|| Camera::outside_view(bounds))
            .named("auto (inside)")
    }

    pub fn named(mut self, name: impl Into<String>) -> Camera {
        self.name = name.into();
        self
    }

    pub fn with_lens(mut self, lens: Lens) -> Camera {
        self.lens = lens;
        self
    }

    pub fn right(&self) -> Vec3 {
        self.forward.cross(self.up)
    }

    /// The film's half extents across the view, right and up, for an image of the given
    /// aspect ratio (width / height): on the plane one unit ahead of the eye for a perspective
    /// camera (film x = ±1 lies at forward ± right times the first), on the film itself for an
    /// orthographic one.
    pub fn film_half_extents(&self, aspect_ratio: f32) -> (Vec3, Vec3) {
        let half_height = match self.projection {
            Projection::Perspective => (0.5 * self.yfov).tan(),
            Projection::Orthographic { half_height } => half_height,
        };
        (
            self.right() * (half_height * aspect_ratio),
            self.up * half_height,
        )
    }

    /// The origin and unit direction of the pinhole ray through the film point (`sx`, `sy`)
    /// in [−1, 1]², +y up, for an image of the given aspect ratio (width / height): from the
    /// eye for a perspective camera, from the film point along the view for an orthographic
    /// one.
    pub fn ray(&self, sx: f32, sy: f32, aspect_ratio: f32) -> (Vec3, Vec3) {
        let (right, up) = self.film_half_extents(aspect_ratio);
        match self.projection {
            Projection::Perspective => {
                (self.eye, (self.forward + sx * right + sy * up).normalize())
            }
            Projection::Orthographic { .. } => (self.eye + sx * right + sy * up, self.forward),
        }
    }

    /// The unit direction of [`Camera::ray`].
    pub fn direction(&self, sx: f32, sy: f32, aspect_ratio: f32) -> Vec3 {
        self.ray(sx, sy, aspect_ratio).1
    }
}
