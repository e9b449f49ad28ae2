//! How solids nest: a glass marble in water, an air bubble in glass. The scene says nothing of
//! it (glTF gives each material one index of refraction, against vacuum), so it is found from
//! the geometry: per material, the solid dielectric its surfaces lie in (the medium around
//! them, [`Nesting::exterior`]), and every index of refraction is made relative to that
//! medium's, once, before a render. Light crossing from water into glass then bends and
//! reflects by 1.5 / 1.33, not 1.5, and a path leaving the marble is in the water again
//! (`crate::medium::medium_after`), which goes on absorbing.
//!
//! The answer is per material, as in Mitsuba (a dielectric's `ext_ior`) and pbrt (a shape's
//! medium interface): a material used both in water and in air takes the medium most of its
//! sampled surfaces lie in. Touching solids (water filling a glass exactly) have no interface
//! of their own: the surface that a path meets first is the one it crosses.

use scene::{Material, Scene, Surface, blend_members};

use crate::medium::{MediumLocator, NO_MEDIUM};

/// The triangles of a material whose surroundings are looked up (spread over its list).
const SAMPLES_PER_MATERIAL: usize = 16;

/// The scene's materials as they are rendered where solids nest.
#[derive(Clone, Debug, PartialEq)]
pub struct Nesting {
    /// Per material, the solid (material id) its surfaces lie in, else the scene's atmosphere
    /// (`scene::Scene::atmosphere`) or [`NO_MEDIUM`]. A blend's members take their root's.
    pub exterior: Vec<u32>,
    /// The scene's materials with each index of refraction (dielectrics' and plastic coats')
    /// divided by that of the medium around it; a coat in a denser medium than itself keeps
    /// index 1 (no coat).
    pub materials: Vec<Material>,
}

impl Nesting {
    /// The scene's nesting, found by [`MediumLocator`] from points just off the front of
    /// up to [`SAMPLES_PER_MATERIAL`] triangles of each material (the most frequent answer).
    pub fn of(scene: &Scene) -> Nesting {
        Nesting::of_with(scene, &MediumLocator::new(scene))
    }

    /// [`Nesting::of`] with the scene's `locator` built already (one build serves a render).
    pub fn of_with(scene: &Scene, locator: &MediumLocator) -> Nesting {
        let count = scene.materials.len();
        // Outside every solid: the atmosphere, which has no surface and no outside itself.
        let outside = locator.outside();
        let mut exterior = vec![outside; count];
        if let Some(atmosphere) = scene.atmosphere {
            exterior[atmosphere as usize] = NO_MEDIUM;
        }
        let any_solid = (0..count as u32).any(|id| is_solid(&scene.materials, id));
        if any_solid {
            let mut by_material: Vec<Vec<usize>> = vec![Vec::new(); count];
            for (index, triangle) in scene.triangles.iter().enumerate() {
                by_material[triangle.material as usize].push(index);
            }
            for (id, triangles) in by_material.iter().enumerate() {
                if triangles.is_empty() {
                    continue;
                }
                let stride = triangles.len().div_ceil(SAMPLES_PER_MATERIAL);
                let mut votes: Vec<(u32, usize)> = Vec::new();
                for &index in triangles.iter().step_by(stride) {
                    let [a, b, c] = scene.triangles[index].positions();
                    let normal = (b - a).cross(c - a).normalize_or_zero();
                    let size = (b - a).length().max((c - a).length());
                    let just_off = (a + b + c) / 3.0 + 1e-4 * size * normal;
                    let mut around = locator.medium_at(just_off);
                    if around == id as u32 {
                        around = outside;
                    }
                    match votes.iter_mut().find(|(m, _)| *m == around) {
                        Some((_, n)) => *n += 1,
                        None => votes.push((around, 1)),
                    }
                }
                // The most votes; the first counted among equals.
                let best = votes.iter().rev().max_by_key(|(_, n)| *n);
                exterior[id] = best.map_or(outside, |&(m, _)| m);
            }
            for root in 0..count as u32 {
                for member in blend_members(&scene.materials, root).skip(1) {
                    exterior[member as usize] = exterior[root as usize];
                }
            }
        }
        let materials = scene
            .materials
            .iter()
            .zip(&exterior)
            .map(|(material, &around)| {
                let outside = interior_ior(&scene.materials, around);
                relative_to(material, outside)
            })
            .collect();
        Nesting {
            exterior,
            materials,
        }
    }

    /// Whether some material lies inside a solid (the atmosphere is none).
    pub fn any(&self, scene: &Scene) -> bool {
        (self.exterior.iter()).any(|&e| e != NO_MEDIUM && Some(e) != scene.atmosphere)
    }
}

/// Whether material `id` bounds a medium: a solid dielectric or translucent solid
/// (`Material::bounds_volume`), or a blend with one among its members (whose root the path's
/// medium then names, `crate::medium`).
pub fn is_solid(materials: &[Material], id: u32) -> bool {
    blend_members(materials, id).any(|m| materials[m as usize].bounds_volume())
}

/// The index of refraction inside material `id`'s solid ([`NO_MEDIUM`] and other surfaces:
/// 1, vacuum): its first solid dielectric member's (a translucent solid's is 1: light enters
/// it diffusely, bending nowhere).
pub fn interior_ior(materials: &[Material], id: u32) -> f32 {
    if id == NO_MEDIUM {
        return 1.0;
    }
    blend_members(materials, id)
        .find_map(|m| materials[m as usize].surface.solid_ior())
        .unwrap_or(1.0)
}

/// `material` in a medium of index `outside`: its index of refraction divided by it.
fn relative_to(material: &Material, outside: f32) -> Material {
    let mut material = material.clone();
    if outside != 1.0 {
        match &mut material.surface {
            Surface::Dielectric { ior, .. } | Surface::RoughDielectric { ior, .. } => {
                *ior /= outside;
                material.dispersion /= outside;
            }
            Surface::Plastic { ior, .. } => *ior = (*ior / outside).max(1.0),
            Surface::Diffuse | Surface::Mirror | Surface::RoughConductor { .. } => {}
        }
    }
    material
}

#[cfg(test)]
mod tests {
    use super::*;

    fn id_of(scene: &Scene, name: &str) -> u32 {
        scene.materials.iter().position(|m| m.name == name).unwrap() as u32
    }

    /// The pool with a marble under water: the marble's surface lies in the water, the
    /// water and the room in nothing, and the marble's index becomes 1.5 / 1.33.
    #[test]
    fn a_marble_under_water_lies_in_the_water() {
        let scene = scene::testing::cornell_marble();
        let nesting = Nesting::of(&scene);
        let (water, marble) = (id_of(&scene, "water"), id_of(&scene, "marble"));
        assert_eq!(nesting.exterior[marble as usize], water);
        assert_eq!(nesting.exterior[water as usize], NO_MEDIUM);
        assert_eq!(nesting.exterior[id_of(&scene, "white") as usize], NO_MEDIUM);
        let ior = |m: &Material| match m.surface {
            Surface::Dielectric { ior, .. } => ior,
            _ => panic!("{} is not glass", m.name),
        };
        let relative = ior(&nesting.materials[marble as usize]);
        let want = scene::testing::MARBLE_IOR / scene::testing::POOL_IOR;
        assert!((relative - want).abs() < 1e-6, "{relative} vs {want}");
        assert_eq!(
            ior(&nesting.materials[water as usize]),
            scene::testing::POOL_IOR
        );
        assert!(nesting.any(&scene));
    }

    /// Under an atmosphere (`scene::Scene::atmosphere`) every surface outside the solids lies
    /// in it, and so does every point outside them; a solid's inside is still the solid's.
    #[test]
    fn an_atmosphere_is_around_everything_outside_the_solids() {
        let mut scene = scene::testing::cornell_caustics();
        let fog = scene::Medium {
            absorption: glam::Vec3::splat(0.1),
            scattering: glam::Vec3::splat(0.3),
            anisotropy: 0.0,
        };
        let atmosphere = scene.materials.len() as u32;
        scene.materials.push(fog.atmosphere());
        scene.atmosphere = Some(atmosphere);
        let locator = MediumLocator::new(&scene);
        let nesting = Nesting::of_with(&scene, &locator);
        for (id, &around) in nesting.exterior.iter().enumerate() {
            let want = if id as u32 == atmosphere {
                NO_MEDIUM
            } else {
                atmosphere
            };
            assert_eq!(around, want, "{}", scene.materials[id].name);
        }
        assert!(!nesting.any(&scene));
        assert_eq!(nesting.materials, scene.materials);
        let glass = id_of(&scene, "glass");
        let centre = |id: u32| {
            let corners = (scene.triangles.iter())
                .filter(|t| t.material == id)
                .flat_map(|t| t.positions());
            let (sum, n) = corners.fold((glam::Vec3::ZERO, 0.0), |(s, n), p| (s + p, n + 1.0));
            sum / n
        };
        assert_eq!(locator.medium_at(centre(glass)), glass);
        let camera = scene.camera(None).unwrap();
        assert_eq!(locator.medium_at(camera.eye), atmosphere);
    }

    /// Scenes whose solids stand apart keep their materials as they are; the pool's ball,
    /// half under water, lies in it (most of its sampled triangles do), which changes nothing
    /// of a diffuse surface.
    #[test]
    fn solids_apart_nest_nowhere() {
        for scene in [
            scene::testing::cornell_caustics(),
            scene::testing::cornell_tinted(),
        ] {
            let nesting = Nesting::of(&scene);
            assert!(!nesting.any(&scene), "{:?}", nesting.exterior);
            assert_eq!(nesting.materials, scene.materials);
        }
        let pool = scene::testing::cornell_pool();
        let nesting = Nesting::of(&pool);
        let water = id_of(&pool, "water");
        assert_eq!(nesting.exterior[id_of(&pool, "blue") as usize], water);
        assert_eq!(nesting.exterior[water as usize], NO_MEDIUM);
        assert_eq!(nesting.materials, pool.materials);
    }

    /// A plastic coat under water of a lower index than the water's has none.
    #[test]
    fn indices_divide_by_the_medium_around() {
        let glass = Material {
            surface: Surface::RoughDielectric {
                ior: 1.5,
                thin_walled: true,
                alpha: 0.1,
            },
            ..Material::default()
        };
        let relative = relative_to(&glass, 1.25);
        assert_eq!(
            relative.surface,
            Surface::RoughDielectric {
                ior: 1.2,
                thin_walled: true,
                alpha: 0.1
            }
        );
        let coat = Material {
            surface: Surface::Plastic {
                ior: 1.2,
                alpha: 0.0,
            },
            ..Material::default()
        };
        assert_eq!(
            relative_to(&coat, 1.33).surface,
            Surface::Plastic {
                ior: 1.0,
                alpha: 0.0
            }
        );
        assert_eq!(relative_to(&coat, 1.0), coat);
    }
}
