//! The medium a path travels through, for Beer–Lambert absorption inside solid dielectrics
//! (glTF's `KHR_materials_volume` attenuation, `scene::Material::absorption`).
//!
//! A path is outside every solid until it refracts into one through its front face, and inside
//! it until it refracts out through a back face: the solid's material id is the path's medium,
//! and every segment it then travels absorbs, whatever surface ends it. A floor under
//! coloured water, a sphere inside a glass block: their segments inside end at front faces of
//! other materials, which the side of the hit alone cannot tell. Reflections, diffuse bounces,
//! thin sheets and cut-outs leave the medium as it is. Solids do not nest: leaving one puts the
//! path outside every solid.
//!
//! A segment that ends at the back face of an absorbing solid ran inside it whatever the path
//! believed (a light inside water: its paths start outside every solid), so there the solid's
//! own absorption counts.

use glam::Vec3;

use crate::buffers::RAY_T_MAX;

/// The medium of a path outside every solid.
pub const NO_MEDIUM: u32 = u32::MAX;

/// The medium after a path leaves a surface of material `root` (a blend's root: it carries
/// the solid's absorption) along a way that `crosses` the surface or not, the surface being a
/// `solid` dielectric (its member, for blends) met from its `front` or from inside.
pub fn medium_after(medium: u32, root: u32, solid: bool, front: bool, crosses: bool) -> u32 {
    match (solid && crosses, front) {
        (false, _) => medium,
        (true, true) => root,
        (true, false) => NO_MEDIUM,
    }
}

/// The medium a segment ran through that ended at a surface of material `root` met from its
/// `front` or not, `absorbs_inside` saying whether `root` is a solid that absorbs: that solid
/// where the segment ends at its back face, else the path's `medium`.
pub fn segment_medium(medium: u32, root: u32, absorbs_inside: bool, front: bool) -> u32 {
    if !front && absorbs_inside {
        root
    } else {
        medium
    }
}

/// What light keeps over `distance` in a medium of `absorption`: exp(−absorption · distance),
/// channel by channel; from [`RAY_T_MAX`] on (a ray leaving the scene inside water, a light
/// sample of the sky) the distance is infinite, which keeps nothing of an absorbing channel
/// and all of a clear one.
pub fn transmittance(absorption: Vec3, distance: f32) -> Vec3 {
    if distance < RAY_T_MAX {
        return (-absorption * distance).exp();
    }
    Vec3::select(absorption.cmpgt(Vec3::ZERO), Vec3::ZERO, Vec3::ONE)
}

/// A path slot's state word (`buffers::PathSlot::state`): bit 0 whether the path has left a
/// diffuse surface, the bits above its medium plus one (so [`NO_MEDIUM`] packs to 0: material
/// ids stay below 2³¹ − 1).
pub fn pack_slot_state(bounced: bool, medium: u32) -> u32 {
    (medium.wrapping_add(1) << 1) | bounced as u32
}

/// Whether a slot's path has left a diffuse surface ([`pack_slot_state`]).
pub fn slot_bounced(state: u32) -> bool {
    state & 1 != 0
}

/// A slot's medium ([`pack_slot_state`]).
pub fn slot_medium(state: u32) -> u32 {
    (state >> 1).wrapping_sub(1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crossings_enter_and_leave_solids_and_nothing_else_changes_the_medium() {
        let water = 7;
        // Into the water through its front face, out through its back face.
        assert_eq!(medium_after(NO_MEDIUM, water, true, true, true), water);
        assert_eq!(medium_after(water, water, true, false, true), NO_MEDIUM);
        // Reflections off the water (either side) keep the medium.
        assert_eq!(medium_after(NO_MEDIUM, water, true, true, false), NO_MEDIUM);
        assert_eq!(medium_after(water, water, true, false, false), water);
        // A thin sheet or an opaque surface under water, crossed or not, keeps it.
        for crosses in [false, true] {
            assert_eq!(medium_after(water, 3, false, true, crosses), water);
        }
    }

    #[test]
    fn a_segment_to_a_solid_s_back_face_ran_inside_it() {
        let (water, glass) = (7, 9);
        assert_eq!(segment_medium(NO_MEDIUM, glass, true, false), glass);
        assert_eq!(segment_medium(water, glass, true, true), water);
        // A clear solid's back face: the tracked medium stands.
        assert_eq!(segment_medium(water, glass, false, false), water);
        assert_eq!(segment_medium(NO_MEDIUM, 2, false, true), NO_MEDIUM);
    }

    #[test]
    fn transmittance_is_beer_lambert_and_an_escape_keeps_only_clear_channels() {
        let absorption = Vec3::new(0.5, 0.0, 2.0);
        let kept = transmittance(absorption, 2.0);
        assert!((kept - Vec3::new((-1.0f32).exp(), 1.0, (-4.0f32).exp())).length() < 1e-6);
        assert_eq!(
            transmittance(absorption, f32::INFINITY),
            Vec3::new(0.0, 1.0, 0.0)
        );
        assert_eq!(
            transmittance(absorption, RAY_T_MAX),
            Vec3::new(0.0, 1.0, 0.0)
        );
        assert_eq!(transmittance(Vec3::ZERO, f32::INFINITY), Vec3::ONE);
    }

    #[test]
    fn slot_state_round_trips_the_flag_and_the_medium() {
        for bounced in [false, true] {
            for medium in [NO_MEDIUM, 0, 1, 12345, (1 << 31) - 2] {
                let state = pack_slot_state(bounced, medium);
                assert_eq!(slot_bounced(state), bounced);
                assert_eq!(slot_medium(state), medium);
            }
        }
        // A fresh slot (state 0) has not bounced and is outside every solid.
        assert_eq!(pack_slot_state(false, NO_MEDIUM), 0);
    }
}
