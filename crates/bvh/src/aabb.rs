//! The builder's axis-aligned box: `scene::Bounds` with SIMD-friendly `Vec3A` corners.
//!
//! The SAH build touches every triangle's box once per tree level, so its boxes use glam's
//! 16-byte aligned `Vec3A` (one SSE/NEON register per corner). The finished tree stores plain
//! [`scene::Bounds`]; [`Aabb::to_bounds`] converts without rounding.

use glam::Vec3A;
use scene::Bounds;

/// An axis-aligned box; [`Aabb::EMPTY`] is the identity of [`Aabb::union`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Aabb {
    /// Smallest corner.
    pub min: Vec3A,
    /// Largest corner.
    pub max: Vec3A,
}

impl Aabb {
    /// The empty box: `min = +inf`, `max = -inf`.
    pub const EMPTY: Aabb = Aabb {
        min: Vec3A::splat(f32::INFINITY),
        max: Vec3A::splat(f32::NEG_INFINITY),
    };

    pub fn to_bounds(self) -> Bounds {
        Bounds {
            min: self.min.into(),
            max: self.max.into(),
        }
    }

    #[inline]
    pub fn union(self, other: Aabb) -> Aabb {
        Aabb {
            min: self.min.min(other.min),
            max: self.max.max(other.max),
        }
    }

    #[inline]
    pub fn grow(self, point: Vec3A) -> Aabb {
        Aabb {
            min: self.min.min(point),
            max: self.max.max(point),
        }
    }

    #[inline]
    pub fn center(&self) -> Vec3A {
        0.5 * (self.min + self.max)
    }

    /// `max - min`; negative on every axis for [`Aabb::EMPTY`].
    #[inline]
    pub fn extent(&self) -> Vec3A {
        self.max - self.min
    }

    /// Half the surface area (the SAH only compares ratios); zero for an empty box.
    #[inline]
    pub fn half_area(&self) -> f32 {
        let e = self.extent().max(Vec3A::ZERO);
        e.x * e.y + e.y * e.z + e.z * e.x
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn empty_is_union_identity_and_has_no_area() {
        let b = Aabb {
            min: Vec3A::new(-1.0, 0.0, 2.0),
            max: Vec3A::new(1.0, 3.0, 2.5),
        };
        assert_eq!(Aabb::EMPTY.union(b), b);
        assert_eq!(Aabb::EMPTY.half_area(), 0.0);
        assert_eq!(b.half_area(), 2.0 * 3.0 + 3.0 * 0.5 + 0.5 * 2.0);
        assert_eq!(b.to_bounds().max, glam::Vec3::new(1.0, 3.0, 2.5));
    }
}
