//! Thin films on metal (glTF's `KHR_materials_iridescence`: `crate::Iridescence`).

use glam::Vec3;

use super::{Fixture, cornell_room};
use crate::{Iridescence, Material, Scene, Surface};

/// A film of glTF's factor 1, index `ior` and thickness `thickness` nm (no textures).
pub fn film(ior: f32, thickness: f32) -> Iridescence {
    Iridescence {
        factor: 1.0,
        texture: None,
        ior,
        thickness_min: 100.0,
        thickness_max: thickness,
        thickness_texture: None,
    }
}

/// The room of [`super::cornell_caustics`] with two metal spheres under oxide films (index
/// 2.4), the colours of anodised and heat-tinted metal: in front (on the camera's right)
/// polished titanium under 300 nm (blue at normal incidence, purple towards the rim), behind
/// it on the left rough steel (roughness 0.2, GGX α 0.04) under 150 nm (straw gold); and a
/// soap bubble floating above them.
pub fn cornell_iridescent() -> Scene {
    let mut f = Fixture::new("testing::cornell_iridescent");
    cornell_room(&mut f);
    let titanium = f.builder.add_material(Material {
        name: "anodised titanium".into(),
        surface: Surface::Mirror,
        base_color: Vec3::new(0.55, 0.52, 0.5),
        iridescence: Some(film(2.4, 300.0)),
        ..Material::default()
    });
    let steel = f.builder.add_material(Material {
        name: "heat-tinted steel".into(),
        surface: Surface::RoughConductor { alpha: 0.2 * 0.2 },
        base_color: Vec3::new(0.6, 0.58, 0.55),
        iridescence: Some(film(2.4, 150.0)),
        ..Material::default()
    });
    // A soap bubble: a film of water (index 1.33, 450 nm) on a sheet of index 1, which bare
    // would neither reflect nor bend light.
    let bubble = f.builder.add_material(Material {
        name: "soap bubble".into(),
        surface: Surface::Dielectric {
            ior: 1.0,
            thin_walled: true,
        },
        base_color: Vec3::ONE,
        iridescence: Some(film(1.33, 450.0)),
        ..Material::default()
    });
    f.sphere(Vec3::new(180.0, 90.0, 170.0), 90.0, titanium, false);
    f.sphere(Vec3::new(380.0, 110.0, 370.0), 110.0, steel, false);
    f.sphere(Vec3::new(300.0, 300.0, 200.0), 75.0, bubble, false);
    f.finish()
}
