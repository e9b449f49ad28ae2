//! The medium a path travels through, for Beer–Lambert absorption inside solid dielectrics and
//! translucent solids (glTF's `KHR_materials_volume` attenuation,
//! `scene::Material::absorption`).
//!
//! A path is in the medium around the scene's surfaces until it refracts (or, through a
//! translucent solid's surface, is diffusely transmitted: `scene::DiffuseTransmission::volume`)
//! into a solid through its front face, and inside it until it passes out through a back
//! face, into the solid around it (`crate::nesting`: a marble in water, whose back face leads
//! back into the water) or outside every solid: the solid's material id is the path's medium,
//! and every segment it then travels absorbs, whatever surface ends it. A floor under
//! coloured water, a sphere inside a glass block: their segments inside end at front faces of
//! other materials, which the side of the hit alone cannot tell. Reflections, diffuse
//! reflections, thin sheets and cut-outs leave the medium as it is.
//!
//! Paths start in the medium where they start: a camera under water, a lamp inside a glass
//! block ([`MediumLocator`], once a render for the camera and each light). A segment that
//! ends at the back face of an absorbing solid ran inside it whatever the path believed, so
//! there the solid's own absorption counts.

use glam::Vec3;
use scene::{Scene, Triangle};

use crate::buffers::{LIGHT_POINT, LIGHT_SPOT, LIGHT_TRIANGLE, Light, RAY_T_MAX, vec3};
use crate::dispersion::WAVELENGTH_LEVELS;

/// The medium of a path outside every solid.
pub const NO_MEDIUM: u32 = u32::MAX;

/// The medium after a path leaves a surface of material `root` (a blend's root: it carries
/// the solid's absorption) along a way that `crosses` the surface or not, the surface being a
/// `solid` (`scene::Material::bounds_volume`; its member, for blends) met from its `front` or
/// from inside, and `exterior` the solid around `root` (`crate::nesting::Nesting::exterior`,
/// or [`NO_MEDIUM`]).
pub fn medium_after(
    medium: u32,
    root: u32,
    exterior: u32,
    solid: bool,
    front: bool,
    crosses: bool,
) -> u32 {
    match (solid && crosses, front) {
        (false, _) => medium,
        (true, true) => root,
        (true, false) => exterior,
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
/// diffuse surface; bits 1–24 its medium plus one (so [`NO_MEDIUM`] packs to 0: material ids
/// stay below 2²⁴ − 1, `bvh::PackedTriangle::MAX_MATERIAL`); bits 25–31 the wavelength it
/// keeps plus one (`crate::dispersion`: [`WHOLE_SPECTRUM`](crate::dispersion::WHOLE_SPECTRUM)
/// packs to 0).
pub fn pack_slot_state(bounced: bool, medium: u32, wavelength: u32) -> u32 {
    (wavelength.wrapping_add(1) << WAVELENGTH_SHIFT)
        | ((medium.wrapping_add(1) & MEDIUM_MASK) << 1)
        | bounced as u32
}

/// Where a slot's wavelength starts in its state word ([`pack_slot_state`]).
pub const WAVELENGTH_SHIFT: u32 = 25;
const _: () = assert!(WAVELENGTH_LEVELS < 1 << (32 - WAVELENGTH_SHIFT));
/// A slot's medium plus one, shifted down ([`pack_slot_state`]).
pub const MEDIUM_MASK: u32 = (1 << 24) - 1;

/// Whether a slot's path has left a diffuse surface ([`pack_slot_state`]).
pub fn slot_bounced(state: u32) -> bool {
    state & 1 != 0
}

/// A slot's medium ([`pack_slot_state`]).
pub fn slot_medium(state: u32) -> u32 {
    ((state >> 1) & MEDIUM_MASK).wrapping_sub(1)
}

/// The wavelength a slot's path keeps, or `crate::dispersion::WHOLE_SPECTRUM`
/// ([`pack_slot_state`]).
pub fn slot_wavelength(state: u32) -> u32 {
    (state >> WAVELENGTH_SHIFT).wrapping_sub(1)
}

/// How a [`MediumLocator`]'s tree is built: without spatial splits. Its walks find the same
/// closest hits in any tree, and the split trees' probe (a second tree and probe rays) took
/// most of the build: 1,009,201 triangles of water, 2.57 s → 0.39 s a build (a render built
/// three: the backend's nesting, the lights' media, the camera's).
fn locator_build_options() -> bvh::BuildOptions {
    bvh::BuildOptions {
        split_percent: 0,
        probe_split: false,
        ..bvh::BuildOptions::default()
    }
}

/// Which solid (`crate::nesting::is_solid`) a point lies in, for the places paths start and
/// for how solids nest (`crate::nesting`): a tree over the solids' triangles (no other surface
/// bounds a medium), and rays from the point. A ray walks through the solids it enters (front
/// faces) until it leaves one it had not entered (a back face): the point lies in that solid,
/// the innermost one around it; a ray that meets surfaces and leaves the scene finds the point
/// outside every solid. The rays look up first, tilted four ways, then down: open water (a
/// pool's surface, closed by the floor and walls) is left through its surface, and a point
/// near the edge of an open sheet finds it on another side. Empty where no solid is. A point
/// outside every solid is in the scene's atmosphere (`scene::Scene::atmosphere`), where it
/// has one.
pub struct MediumLocator {
    bvh: Option<bvh::PackedBvh>,
    /// The medium outside every solid: the atmosphere, or [`NO_MEDIUM`].
    outside: u32,
    /// How far past a surface a walking ray goes on (a millionth of the solids' size).
    step: f32,
}

/// The directions [`MediumLocator`] looks in, in order: up, tilted off the axes (so as not to
/// run along the edges of axis-aligned meshes) four ways, then down likewise.
const LOCATOR_DIRECTIONS: [Vec3; 8] = [
    Vec3::new(0.123, 0.985, 0.122),
    Vec3::new(-0.122, 0.985, 0.123),
    Vec3::new(-0.123, 0.985, -0.122),
    Vec3::new(0.122, 0.985, -0.123),
    Vec3::new(0.123, -0.985, 0.122),
    Vec3::new(-0.122, -0.985, 0.123),
    Vec3::new(-0.123, -0.985, -0.122),
    Vec3::new(0.122, -0.985, -0.123),
];

/// The most surfaces one [`MediumLocator`] ray walks through.
const LOCATOR_MAX_SURFACES: usize = 64;

impl MediumLocator {
    pub fn new(scene: &Scene) -> MediumLocator {
        let solid: Vec<bool> = scene
            .materials
            .iter()
            .enumerate()
            .map(|(id, _)| crate::nesting::is_solid(&scene.materials, id as u32))
            .collect();
        let solids: Vec<Triangle> = scene
            .triangles
            .iter()
            .filter(|t| solid[t.material as usize])
            .copied()
            .collect();
        let bvh =
            (!solids.is_empty()).then(|| bvh::PackedBvh::build(&solids, &locator_build_options()));
        MediumLocator {
            bvh,
            outside: scene.atmosphere.unwrap_or(NO_MEDIUM),
            step: 1e-6 * scene.bounds().extent().length().max(1e-3),
        }
    }

    /// The medium outside every solid: the scene's atmosphere, or [`NO_MEDIUM`].
    pub fn outside(&self) -> u32 {
        self.outside
    }

    /// The medium at `point`: the innermost solid it lies in, or [`MediumLocator::outside`].
    pub fn medium_at(&self, point: Vec3) -> u32 {
        let found = self.bvh.as_ref().and_then(|bvh| {
            (LOCATOR_DIRECTIONS.map(Vec3::normalize))
                .into_iter()
                .find_map(|direction| self.walk(bvh, point, direction))
        });
        match found {
            Some(medium) if medium != NO_MEDIUM => medium,
            _ => self.outside,
        }
    }

    /// One ray's answer: the first solid it leaves without having entered it, [`NO_MEDIUM`]
    /// where it meets surfaces and leaves the scene (or meets too many), `None` where it
    /// meets none.
    fn walk(&self, bvh: &bvh::PackedBvh, point: Vec3, direction: Vec3) -> Option<u32> {
        let mut entered: Vec<u32> = Vec::new();
        let mut origin = point;
        for surfaces in 0..LOCATOR_MAX_SURFACES {
            let ray = bvh::Ray {
                origin,
                direction,
                t_max: f32::INFINITY,
            };
            let Some(hit) = bvh::closest_hit_mtbvh(bvh, &ray) else {
                return (surfaces > 0).then_some(NO_MEDIUM);
            };
            let triangle = &bvh.triangles[hit.triangle as usize];
            let [a, b, c] = triangle.positions();
            let material = triangle.material();
            if (b - a).cross(c - a).dot(direction) > 0.0 {
                // Leaving a solid: one this ray entered, or the one around the point.
                match entered.iter().rposition(|&m| m == material) {
                    Some(at) => entered.truncate(at),
                    None => return Some(material),
                }
            } else {
                entered.push(material);
            }
            origin = ray.origin + direction * hit.t + direction * self.step;
        }
        Some(NO_MEDIUM)
    }

    /// Where each light's paths start, for [`Light::medium`]: a point or spot light's position,
    /// a triangle's centroid just off its emitting face (the front, or either for a
    /// double-sided one: the front); the sky and directional lights start outside the scene,
    /// in its atmosphere if it has one.
    pub fn set_light_media(&self, lights: &mut [Light]) {
        for light in lights {
            light.medium = match light.kind {
                LIGHT_POINT | LIGHT_SPOT => self.medium_at(vec3(light.v0)),
                LIGHT_TRIANGLE => {
                    let (v0, e1, e2) = (vec3(light.v0), vec3(light.edge1), vec3(light.edge2));
                    let normal = e1.cross(e2).normalize_or_zero();
                    let size = e1.length().max(e2.length());
                    self.medium_at(v0 + (e1 + e2) / 3.0 + 1e-4 * size * normal)
                }
                _ => self.outside,
            };
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crossings_enter_and_leave_solids_and_nothing_else_changes_the_medium() {
        let water = 7;
        let marble = 8;
        // Into the water through its front face, out through its back face.
        assert_eq!(
            medium_after(NO_MEDIUM, water, NO_MEDIUM, true, true, true),
            water
        );
        assert_eq!(
            medium_after(water, water, NO_MEDIUM, true, false, true),
            NO_MEDIUM
        );
        // Into a marble in the water and out of it again, into the water.
        assert_eq!(medium_after(water, marble, water, true, true, true), marble);
        assert_eq!(
            medium_after(marble, marble, water, true, false, true),
            water
        );
        // Reflections off the water (either side) keep the medium.
        assert_eq!(
            medium_after(NO_MEDIUM, water, NO_MEDIUM, true, true, false),
            NO_MEDIUM
        );
        assert_eq!(
            medium_after(water, water, NO_MEDIUM, true, false, false),
            water
        );
        assert_eq!(
            medium_after(marble, marble, water, true, false, false),
            marble
        );
        // A thin sheet or an opaque surface under water, crossed or not, keeps it.
        for crosses in [false, true] {
            assert_eq!(medium_after(water, 3, water, false, true, crosses), water);
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
    fn slot_state_round_trips_the_flag_the_medium_and_the_wavelength() {
        use crate::dispersion::WHOLE_SPECTRUM;
        for bounced in [false, true] {
            for medium in [
                NO_MEDIUM,
                0,
                1,
                12345,
                bvh::PackedTriangle::MAX_MATERIAL - 1,
            ] {
                for wavelength in [WHOLE_SPECTRUM, 0, 77, WAVELENGTH_LEVELS - 1] {
                    let state = pack_slot_state(bounced, medium, wavelength);
                    assert_eq!(slot_bounced(state), bounced);
                    assert_eq!(slot_medium(state), medium);
                    assert_eq!(slot_wavelength(state), wavelength);
                }
            }
        }
        // A fresh slot (state 0) has not bounced, is outside every solid and carries the
        // whole spectrum.
        assert_eq!(pack_slot_state(false, NO_MEDIUM, WHOLE_SPECTRUM), 0);
    }

    /// Points under the pool's open surface (closed by the floor and walls) and inside the
    /// tinted glass spheres are found in them; points above the water, outside the spheres
    /// and in scenes where nothing absorbs are outside every solid.
    #[test]
    fn the_locator_finds_points_inside_water_and_glass() {
        let pool = scene::testing::cornell_pool();
        let water = pool
            .materials
            .iter()
            .position(|m| m.name == "water")
            .unwrap() as u32;
        let locator = MediumLocator::new(&pool);
        let level = scene::testing::POOL_LEVEL;
        let lamp = scene::testing::underwater_lamp();
        let camera = lamp.camera(None).unwrap();
        let in_lamp_scene = MediumLocator::new(&lamp);
        assert_eq!(in_lamp_scene.medium_at(camera.eye), 1);
        // Near the open layer's edge the first ray up passes beside it; another finds it.
        assert_eq!(in_lamp_scene.medium_at(Vec3::new(0.0, 0.6, 0.95)), 1);
        assert_eq!(in_lamp_scene.medium_at(Vec3::new(0.0, 0.6, 1.5)), NO_MEDIUM);
        assert_eq!(in_lamp_scene.medium_at(Vec3::new(0.0, 1.5, 0.0)), NO_MEDIUM);
        assert_eq!(locator.medium_at(Vec3::new(278.0, 40.0, 100.0)), water);
        assert_eq!(
            locator.medium_at(Vec3::new(100.0, level - 20.0, 500.0)),
            water
        );
        assert_eq!(
            locator.medium_at(Vec3::new(278.0, level + 20.0, 100.0)),
            NO_MEDIUM
        );
        assert_eq!(
            locator.medium_at(Vec3::new(278.0, 273.0, -800.0)),
            NO_MEDIUM
        );

        let tinted = scene::testing::cornell_tinted();
        let locator = MediumLocator::new(&tinted);
        let teal = tinted
            .materials
            .iter()
            .position(|m| m.name == "teal glass")
            .unwrap() as u32;
        assert_eq!(locator.medium_at(Vec3::new(180.0, 90.0, 170.0)), teal);
        assert_eq!(locator.medium_at(Vec3::new(180.0, 90.0, 60.0)), NO_MEDIUM);

        let clear = MediumLocator::new(&scene::testing::cornell_caustics());
        assert_eq!(clear.medium_at(Vec3::new(278.0, 100.0, 200.0)), NO_MEDIUM);
    }
}
