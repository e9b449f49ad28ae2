//! Four boxes and four triangles at once: SSE on x86-64 (part of its baseline, so no runtime
//! detection), plain arithmetic elsewhere. Both give exactly the binary tests' results.

use super::{LEAF_WIDTH, Tri4, WIDTH, WideNode};
use crate::intersect::{ROBUST_EXIT, Ray, SlabRay};

/// Per axis, the plane rows (`axis` or `3 + axis`) a ray enters and leaves a box by.
fn near_far_rows(slab: &SlabRay) -> ([usize; 3], [usize; 3]) {
    let inv = slab.inv_direction.to_array();
    let near = [0, 1, 2].map(|a| if inv[a] >= 0.0 { a } else { 3 + a });
    (near, near.map(|r| if r < 3 { r + 3 } else { r - 3 }))
}

#[cfg(target_arch = "x86_64")]
mod sse {
    use std::arch::x86_64::*;

    use super::*;

    /// A ray prepared for four-box slab tests (no axis parallel: see `WideRay::entered`).
    #[derive(Clone, Copy)]
    pub struct Slab4 {
        origin: [__m128; 3],
        inv: [__m128; 3],
        near: [usize; 3],
        far: [usize; 3],
    }

    impl Slab4 {
        pub fn new(slab: &SlabRay) -> Slab4 {
            let (near, far) = near_far_rows(slab);
            // SAFETY: SSE is part of the x86-64 baseline.
            let splat = |v: f32| unsafe { _mm_set1_ps(v) };
            Slab4 {
                origin: slab.origin.to_array().map(splat),
                inv: slab.inv_direction.to_array().map(splat),
                near,
                far,
            }
        }

        /// Bit `s` set when the ray enters slot `s`'s box before `t_far`: `intersect_box`'s
        /// arithmetic on four boxes (the near and far planes chosen by the direction's sign
        /// give the same values as its min and max).
        #[inline(always)]
        pub fn entered(&self, node: &WideNode, t_far: f32) -> u32 {
            // SAFETY: SSE is part of the x86-64 baseline; the plane rows are 16-byte aligned
            // (WideNode is 64-byte aligned and each row is 16 bytes).
            unsafe {
                let rows = node.planes.as_ptr() as *const __m128;
                let mut t_enter = _mm_setzero_ps();
                let mut t_exit = _mm_set1_ps(t_far);
                for a in 0..3 {
                    let near = _mm_load_ps(rows.add(self.near[a]) as *const f32);
                    let far = _mm_load_ps(rows.add(self.far[a]) as *const f32);
                    let t_near = _mm_mul_ps(_mm_sub_ps(near, self.origin[a]), self.inv[a]);
                    let t_far = _mm_mul_ps(_mm_sub_ps(far, self.origin[a]), self.inv[a]);
                    t_enter = _mm_max_ps(t_enter, t_near);
                    t_exit = _mm_min_ps(t_exit, t_far);
                }
                t_exit = _mm_mul_ps(t_exit, _mm_set1_ps(ROBUST_EXIT));
                _mm_movemask_ps(_mm_cmple_ps(t_enter, t_exit)) as u32 & node.valid as u32
            }
        }
    }

    /// `intersect_triangle` on four lanes at once, operation for operation: the lane with the
    /// nearest hit before `t_best` (the first of equals) and its `(u, v, t)`.
    #[inline(always)]
    pub fn intersect4(tri: &Tri4, ray: &Ray, t_best: f32) -> Option<(u32, (f32, f32, f32))> {
        let lanes = intersect4_lanes(tri, ray, t_best);
        (lanes.mask != 0).then(|| nearest_lane(lanes.mask, &lanes.u, &lanes.v, &lanes.t))
    }

    /// Every lane's hit before `t_best`: `intersect_triangle` on four lanes at once, operation
    /// for operation.
    #[inline(always)]
    pub fn intersect4_lanes(tri: &Tri4, ray: &Ray, t_best: f32) -> Lanes {
        // SAFETY: SSE is part of the x86-64 baseline; the rows are 16-byte aligned.
        unsafe {
            let row = |i: usize| _mm_load_ps(tri.rows[i].as_ptr());
            let (p0x, p0y, p0z) = (row(0), row(1), row(2));
            let (e0x, e0y, e0z) = (row(3), row(4), row(5));
            let (e1x, e1y, e1z) = (row(6), row(7), row(8));
            let splat = |v: f32| _mm_set1_ps(v);
            let (dx, dy, dz) = (
                splat(ray.direction.x),
                splat(ray.direction.y),
                splat(ray.direction.z),
            );
            let mul = |a, b| _mm_mul_ps(a, b);
            let sub = |a, b| _mm_sub_ps(a, b);
            let add = |a, b| _mm_add_ps(a, b);
            // glam's cross and dot, term for term.
            let cross = |ax, ay, az, bx, by, bz| {
                (
                    sub(mul(ay, bz), mul(by, az)),
                    sub(mul(az, bx), mul(bz, ax)),
                    sub(mul(ax, by), mul(bx, ay)),
                )
            };
            let dot = |ax, ay, az, bx, by, bz| add(add(mul(ax, bx), mul(ay, by)), mul(az, bz));
            let (pvx, pvy, pvz) = cross(dx, dy, dz, e1x, e1y, e1z);
            let det = dot(e0x, e0y, e0z, pvx, pvy, pvz);
            let tvx = sub(splat(ray.origin.x), p0x);
            let tvy = sub(splat(ray.origin.y), p0y);
            let tvz = sub(splat(ray.origin.z), p0z);
            let (qx, qy, qz) = cross(tvx, tvy, tvz, e0x, e0y, e0z);
            let zero = _mm_setzero_ps();
            let one = splat(1.0);
            let nonzero = _mm_cmpneq_ps(det, zero);
            let safe_det = _mm_or_ps(_mm_and_ps(nonzero, det), _mm_andnot_ps(nonzero, one));
            let u = _mm_div_ps(dot(tvx, tvy, tvz, pvx, pvy, pvz), safe_det);
            let v = _mm_div_ps(dot(dx, dy, dz, qx, qy, qz), safe_det);
            let t = _mm_div_ps(dot(e1x, e1y, e1z, qx, qy, qz), safe_det);
            let w = sub(sub(one, u), v);
            let hit = _mm_and_ps(
                _mm_and_ps(
                    _mm_and_ps(nonzero, _mm_cmpge_ps(u, zero)),
                    _mm_and_ps(_mm_cmpge_ps(v, zero), _mm_cmpge_ps(w, zero)),
                ),
                _mm_and_ps(_mm_cmpge_ps(t, zero), _mm_cmplt_ps(t, splat(t_best))),
            );
            let mask = _mm_movemask_ps(hit) as u32 & ((1 << tri.count) - 1);
            let mut lanes = Lanes {
                mask,
                ..Lanes::default()
            };
            if mask != 0 {
                _mm_storeu_ps(lanes.u.as_mut_ptr(), u);
                _mm_storeu_ps(lanes.v.as_mut_ptr(), v);
                _mm_storeu_ps(lanes.t.as_mut_ptr(), t);
            }
            lanes
        }
    }
}

#[cfg(target_arch = "x86_64")]
pub use sse::{Slab4, intersect4, intersect4_lanes};

/// Four triangle tests' results: bit `i` of `mask` set where lane `i` was hit, at `t[i]`,
/// with barycentrics `u[i]`, `v[i]`.
#[derive(Clone, Copy, Debug, Default)]
pub struct Lanes {
    pub mask: u32,
    pub u: [f32; 4],
    pub v: [f32; 4],
    pub t: [f32; 4],
}

/// Of the lanes in `mask`, the one with the smallest `t` (the first of equals).
#[inline(always)]
fn nearest_lane(mut mask: u32, u: &[f32; 4], v: &[f32; 4], t: &[f32; 4]) -> (u32, (f32, f32, f32)) {
    let mut lane = mask.trailing_zeros() as usize;
    mask &= mask - 1;
    while mask != 0 {
        let other = mask.trailing_zeros() as usize;
        mask &= mask - 1;
        if t[other] < t[lane] {
            lane = other;
        }
    }
    (lane as u32, (u[lane], v[lane], t[lane]))
}

#[cfg(not(target_arch = "x86_64"))]
mod portable {
    use glam::Vec3;

    use super::*;

    #[derive(Clone, Copy)]
    pub struct Slab4 {
        origin: [f32; 3],
        inv: [f32; 3],
        near: [usize; 3],
        far: [usize; 3],
    }

    impl Slab4 {
        pub fn new(slab: &SlabRay) -> Slab4 {
            let (near, far) = near_far_rows(slab);
            Slab4 {
                origin: slab.origin.to_array(),
                inv: slab.inv_direction.to_array(),
                near,
                far,
            }
        }

        #[inline(always)]
        pub fn entered(&self, node: &WideNode, t_far: f32) -> u32 {
            let mut mask = 0;
            for s in 0..WIDTH {
                let (mut t_enter, mut t_exit) = (0.0f32, t_far);
                for a in 0..3 {
                    let t_near = (node.planes[self.near[a]][s] - self.origin[a]) * self.inv[a];
                    let t_far = (node.planes[self.far[a]][s] - self.origin[a]) * self.inv[a];
                    t_enter = if t_enter < t_near { t_near } else { t_enter };
                    t_exit = if t_far < t_exit { t_far } else { t_exit };
                }
                mask |= u32::from(t_enter <= t_exit * ROBUST_EXIT) << s;
            }
            mask & node.valid as u32
        }
    }

    /// The lane with the nearest hit before `t_best` (the first of equals) and its `(u, v, t)`.
    pub fn intersect4(tri: &Tri4, ray: &Ray, t_best: f32) -> Option<(u32, (f32, f32, f32))> {
        let Lanes { mask, u, v, t } = intersect4_lanes(tri, ray, t_best);
        (mask != 0).then(|| nearest_lane(mask, &u, &v, &t))
    }

    /// Every lane's hit before `t_best`.
    pub fn intersect4_lanes(tri: &Tri4, ray: &Ray, t_best: f32) -> Lanes {
        let (mut u, mut v, mut t) = ([0.0f32; 4], [0.0f32; 4], [0.0f32; 4]);
        let mut mask = 0;
        for lane in 0..tri.count as usize {
            let p = |k: usize| Vec3::from([0, 1, 2].map(|a| tri.rows[3 * k + a][lane]));
            let (p0, e0, e1) = (p(0), p(1), p(2));
            let pv = ray.direction.cross(e1);
            let det = e0.dot(pv);
            let tv = ray.origin - p0;
            let qv = tv.cross(e0);
            let safe_det = if det != 0.0 { det } else { 1.0 };
            u[lane] = tv.dot(pv) / safe_det;
            v[lane] = ray.direction.dot(qv) / safe_det;
            t[lane] = e1.dot(qv) / safe_det;
            let w = 1.0 - u[lane] - v[lane];
            let hit = det != 0.0
                && u[lane] >= 0.0
                && v[lane] >= 0.0
                && w >= 0.0
                && t[lane] >= 0.0
                && t[lane] < t_best;
            mask |= u32::from(hit) << lane;
        }
        Lanes { mask, u, v, t }
    }
}

#[cfg(not(target_arch = "x86_64"))]
pub use portable::{Slab4, intersect4, intersect4_lanes};

const _: () = assert!(LEAF_WIDTH == 4 && WIDTH == 4);
