//! Fixtures of murky glass: solid glass that scatters inside (`Material::has_murky_glass`).

use glam::Vec3;

use super::{Fixture, cornell_room, furnace_around};
use crate::{Material, Scene, Surface};

/// [`crate::testing::furnace_sphere`] with a ball of lossless murky glass in view (radius 0.3
/// half a unit ahead of the camera, smooth, index `ior`; inside, `scattering` σs, no
/// absorption, Henyey–Greenstein of `anisotropy`): every path entering it leaves it again, so
/// in the furnace it is invisible. Eye paths end inside it where they scatter and gather the
/// volume photons there.
pub fn furnace_with_murky_glass(scattering: Vec3, anisotropy: f32, ior: f32) -> Scene {
    furnace_around(
        "testing::furnace_with_murky_glass",
        Material {
            name: "murky glass".into(),
            surface: Surface::Dielectric {
                ior,
                thin_walled: false,
            },
            base_color: Vec3::ONE,
            scattering,
            scatter_anisotropy: anisotropy,
            ..Material::default()
        },
    )
}

/// [`crate::testing::furnace_sphere`] filled with a lossless atmosphere (`Scene::atmosphere`:
/// `scattering` σs, no absorption, Henyey–Greenstein of `anisotropy`) that the camera and the
/// walls are in: as much light scatters into every ray as out of it, so in the furnace the
/// fog is invisible. Eye paths end where they scatter and gather the volume photons there.
pub fn furnace_in_an_atmosphere(scattering: Vec3, anisotropy: f32) -> Scene {
    let mut scene = crate::testing::furnace_sphere();
    let fog = crate::Medium {
        absorption: Vec3::ZERO,
        scattering,
        anisotropy,
    };
    scene.atmosphere = Some(scene.materials.len() as u32);
    scene.materials.push(fog.atmosphere());
    scene
}

/// [`crate::testing::cornell_caustics`]'s room with murky glass: a ball of milky quartz front
/// right (index 1.5, scattering about twice across its radius, forward-leaning, absorbing
/// a little, blue least), whose caustic on the floor is blurred by the light it scatters, and
/// a block of murky sea water back left (index 1.33, scattering isotropically, absorbing red
/// most), lit by the ceiling light.
pub fn cornell_murky() -> Scene {
    let mut f = Fixture::new("testing::cornell_murky");
    cornell_room(&mut f);
    let quartz = f.builder.add_material(Material {
        name: "milky quartz".into(),
        surface: Surface::Dielectric {
            ior: 1.5,
            thin_walled: false,
        },
        base_color: Vec3::ONE,
        absorption: Vec3::new(0.0006, 0.0004, 0.0002),
        scattering: Vec3::splat(0.01),
        scatter_anisotropy: 0.6,
        ..Material::default()
    });
    let water = f.builder.add_material(Material {
        name: "murky water".into(),
        surface: Surface::Dielectric {
            ior: 1.33,
            thin_walled: false,
        },
        base_color: Vec3::ONE,
        absorption: Vec3::new(0.004, 0.0012, 0.0015),
        scattering: Vec3::new(0.006, 0.007, 0.006),
        ..Material::default()
    });
    f.sphere(Vec3::new(380.0, 100.0, 200.0), 100.0, quartz, false);
    f.closed_box(
        Vec3::new(90.0, 0.0, 300.0),
        Vec3::new(270.0, 240.0, 460.0),
        water,
    );
    f.finish()
}
