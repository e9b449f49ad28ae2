//! Newton's experiment: a narrow beam from a spot light through a flint prism, whose band of
//! colours falls on the floor (`KHR_materials_dispersion`, `render::dispersion`).

use glam::Vec3;

use super::{FLINT_ABBE, FLINT_IOR, Fixture};
use crate::{Material, PunctualKind, PunctualLight, Scene, SpotFalloff, Surface};

/// The prism: an equilateral triangle of side [`PRISM_SIDE`] (m), apex up, on a pedestal of
/// height [`PEDESTAL_HEIGHT`], running along z over [`PRISM_LENGTH`].
pub const PRISM_SIDE: f32 = 0.3;
pub const PRISM_LENGTH: f32 = 0.3;
pub const PEDESTAL_HEIGHT: f32 = 0.9;
/// The beam's elevation (degrees): it meets the prism's left face at about the angle of
/// minimum deviation for flint of [`FLINT_IOR`] (61° from the face's normal, which points 30°
/// above the horizontal), so it runs level inside and leaves descending as steeply.
pub const BEAM_ELEVATION_DEGREES: f32 = 31.0;
/// How far the spot light stands from the left face's centre (m), and its cone (degrees).
pub const LIGHT_DISTANCE: f32 = 1.0;
pub const BEAM_INNER_DEGREES: f32 = 0.7;
pub const BEAM_OUTER_DEGREES: f32 = 1.0;

/// The prism scene: a white floor and back wall, a grey pedestal, the flint prism, the spot
/// light, and a dim emitting panel high above that lights the room without reaching the
/// camera's view.
pub fn prism() -> Scene {
    let mut f = Fixture::new("testing::prism");
    let white = f.material("white", Surface::Diffuse, Vec3::splat(0.8));
    let grey = f.material("pedestal", Surface::Diffuse, Vec3::splat(0.25));
    let flint = f.builder.add_material(Material {
        name: "flint glass".into(),
        surface: Surface::Dielectric {
            ior: FLINT_IOR,
            thin_walled: false,
        },
        dispersion: crate::dispersion_from_abbe(FLINT_IOR, FLINT_ABBE),
        ..Material::default()
    });
    let panel = f.builder.add_material(Material {
        name: "panel".into(),
        emission: Vec3::splat(0.15),
        base_color: Vec3::ZERO,
        ..Material::default()
    });
    let (x0, x1, z0, z1) = (-3.0, 5.0, -1.0, 4.0);
    let floor = [[x0, z0], [x1, z0], [x1, z1], [x0, z1]].map(|[x, z]| Vec3::new(x, 0.0, z));
    f.quad(floor, white, Vec3::Y);
    let wall = [[x0, 0.0], [x1, 0.0], [x1, 2.5], [x0, 2.5]].map(|[x, y]| Vec3::new(x, y, z0));
    f.quad(wall, white, Vec3::Z);
    let ceiling = [[x0, z0], [x1, z0], [x1, z1], [x0, z1]].map(|[x, z]| Vec3::new(x, 2.5, z));
    f.quad(ceiling, panel, Vec3::NEG_Y);
    let half = 0.2;
    let pedestal = [[-half, -half], [half, -half], [half, half], [-half, half]];
    f.block(pedestal, PEDESTAL_HEIGHT, grey);
    triangular_prism(&mut f, flint);
    let [left, _, apex] = prism_cross_section();
    let face_centre = (left + apex) / 2.0;
    let elevation = BEAM_ELEVATION_DEGREES.to_radians();
    let beam = Vec3::new(elevation.cos(), elevation.sin(), 0.0);
    f.builder
        .add_punctual_light(PunctualLight {
            kind: PunctualKind::Spot {
                cos_inner: BEAM_INNER_DEGREES.to_radians().cos(),
                cos_outer: BEAM_OUTER_DEGREES.to_radians().cos(),
                falloff: SpotFalloff::Gltf,
            },
            position: face_centre - LIGHT_DISTANCE * beam,
            direction: beam,
            intensity: Vec3::splat(200.0),
        })
        .expect("the prism's spot light is valid");
    let eye = Vec3::new(0.95, 1.6, 2.9);
    let target = Vec3::new(0.95, 0.45, 0.0);
    f.camera(
        eye,
        (target - eye).normalize(),
        40f32.to_radians(),
        None,
        "prism",
    );
    f.finish()
}

/// The prism's cross-section at z = 0: base left, base right, apex. Its base stands 2 mm
/// above the pedestal, so that no two surfaces share a plane.
pub fn prism_cross_section() -> [Vec3; 3] {
    let height = PRISM_SIDE * 3f32.sqrt() / 2.0;
    let base = PEDESTAL_HEIGHT + 0.002;
    [
        Vec3::new(-PRISM_SIDE / 2.0, base, 0.0),
        Vec3::new(PRISM_SIDE / 2.0, base, 0.0),
        Vec3::new(0.0, base + height, 0.0),
    ]
}

/// The closed prism: its two triangular ends and three sides, faces outwards.
fn triangular_prism(f: &mut Fixture, material: u32) {
    let section = prism_cross_section();
    let centre = section.iter().sum::<Vec3>() / 3.0;
    let along = Vec3::new(0.0, 0.0, PRISM_LENGTH / 2.0);
    let vertex = |position| crate::Vertex {
        position,
        ..crate::Vertex::default()
    };
    f.triangle(section.map(|p| vertex(p + along)), material, Vec3::Z);
    f.triangle(section.map(|p| vertex(p - along)), material, Vec3::NEG_Z);
    for k in 0..3 {
        let (a, b) = (section[k], section[(k + 1) % 3]);
        let outward = (a + b) / 2.0 - centre;
        f.quad(
            [a - along, b - along, b + along, a + along],
            material,
            outward,
        );
    }
}
