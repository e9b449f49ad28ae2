//! Thin films on metal (glTF's `KHR_materials_iridescence`: `crate::Iridescence`).

use glam::{Vec2, Vec3};

use super::{Fixture, cornell_room};
use crate::{Iridescence, Material, Scene, Surface, Texels, Texture};

/// [`bubble_thickness`]'s range (nm): its texture's green from 0 to 1 spans it.
pub const BUBBLE_THICKNESS: [f32; 2] = [150.0, 750.0];

/// A soap bubble's film thickness as glTF's `iridescenceThicknessTexture` (linear data, the
/// green channel; red 1 for the factor): one column of 64 rows from the top (v = 0), thin
/// where the water has drained off the top and growing towards the bottom, with slow ripples
/// of the flow. Texels are whole 8-bit steps, so a PNG round trip keeps them.
pub fn bubble_thickness() -> Texture {
    let rows = 64;
    let texels = (0..rows)
        .map(|row| {
            let v = (row as f32 + 0.5) / rows as f32;
            let ripple = 0.08 * (v * 23.0).sin();
            let g = (v.powf(0.8) + ripple).clamp(0.0, 1.0);
            [1.0, (g * 255.0).round() / 255.0, 0.0, 1.0]
        })
        .collect();
    Texture {
        name: "bubble thickness".into(),
        width: 1,
        height: rows,
        texels: Texels::LinearF32(texels),
    }
}

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
/// soap bubble floating above them; in front on the left a small glossy beetle-shell sphere,
/// near-black plastic (roughness 0.15) whose coat wears a film of index 2.2, 330 nm.
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
    // A soap bubble: a film of water (index 1.33) on a sheet of index 1, which bare would
    // neither reflect nor bend light; drained thin at the top, thick at the bottom
    // ([`bubble_thickness`], read by latitude).
    let thickness = f.builder.add_texture(bubble_thickness());
    let bubble = f.builder.add_material(Material {
        name: "soap bubble".into(),
        surface: Surface::Dielectric {
            ior: 1.0,
            thin_walled: true,
        },
        base_color: Vec3::ONE,
        iridescence: Some(Iridescence {
            thickness_min: BUBBLE_THICKNESS[0],
            thickness_texture: Some(thickness),
            ..film(1.33, BUBBLE_THICKNESS[1])
        }),
        ..Material::default()
    });
    let shell = f.builder.add_material(Material {
        name: "beetle shell".into(),
        surface: Surface::Plastic {
            ior: 1.5,
            alpha: 0.15 * 0.15,
        },
        base_color: Vec3::new(0.02, 0.03, 0.02),
        iridescence: Some(film(2.2, 330.0)),
        ..Material::default()
    });
    f.sphere(Vec3::new(180.0, 90.0, 170.0), 90.0, titanium, false);
    f.sphere(Vec3::new(410.0, 55.0, 140.0), 55.0, shell, false);
    f.sphere(Vec3::new(380.0, 110.0, 370.0), 110.0, steel, false);
    let centre = Vec3::new(300.0, 300.0, 200.0);
    f.sphere(centre, 75.0, bubble, false);
    let mut scene = f.finish();
    // Latitude as the texture's v (0 at the top); the texture does not vary along u, so the
    // longitude seam shows nothing.
    for triangle in (scene.triangles.iter_mut()).filter(|t| t.material == bubble) {
        for v in &mut triangle.vertices {
            let d = (v.position - centre).normalize();
            v.uv = Vec2::new(0.5, d.y.clamp(-1.0, 1.0).acos() / std::f32::consts::PI);
        }
    }
    scene
}
