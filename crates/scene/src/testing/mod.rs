//! Scenes built in code, for tests and benchmarks that should not depend on files (STYLE.md,
//! "Fixtures built in code", after Mitsuba's `cornell_box()`). Each goes through
//! [`SceneBuilder`], so the scene invariants hold, and each has a camera.
//!
//! - [`cornell_box`]: the Cornell box as measured (geometry, camera), 38 triangles.
//! - [`cornell_caustics`]: the same box without its blocks, with a glass and a mirror sphere.
//! - [`furnace_sphere`]: a closed emissive diffuse sphere seen from inside; radiance is
//!   [`FURNACE_RADIANCE`] everywhere.
//! - [`lit_plane`]: a diffuse square under a large parallel area light; radiance is
//!   [`lit_plane_radiance`].
//! - [`punctual_plane`]: a diffuse square lit only by the punctual lights given.
//! - [`cornell_box_punctual`]: the Cornell box with a point, a spot and a directional light
//!   and a sky besides its own.
//! - [`cornell_spot`]: [`cornell_caustics`] with a spot light on the glass sphere.
//! - [`cornell_bumpy`]: [`cornell_caustics`]'s room with normal-mapped tiles and spheres.
//! - [`cornell_plastic`]: [`cornell_caustics`]'s room with a plastic floor and spheres.
//! - [`cornell_blended`]: [`cornell_caustics`]'s room with blended floor and spheres.
//! - [`cornell_pool`]: [`cornell_caustics`]'s room flooded to a wavy water surface, a diffuse
//!   sphere half under it: caustics on the floor below the water.
//! - [`translucent_slab_over_plane`], [`lamp_in_translucent_cube`]: translucent solids
//!   absorbing inside, seen from above; radiance [`translucent_slab_radiance`] and the lamp's
//!   through the cube; [`cornell_translucent_solids`]: a wax sphere with a lamp inside and a
//!   jade block in [`cornell_caustics`]'s room.
//! - [`furnace_sphere_blended`]: [`furnace_sphere`] in a blend of mirror and diffuse; radiance
//!   [`FURNACE_RADIANCE`] again.
//! - [`glass_pane`]: a thin glass sheet between two emitters, seen head-on; an eye path's
//!   emission is [`glass_pane_radiance`]; [`glass_panes`] has more sheets.
//! - [`spheres_on_a_floor`]: glass, rough gold and white spheres on an open floor, no light;
//!   [`spheres_under_sky_map`] lights it with [`sunset_sky_map`], [`plane_under_sky_map`] the
//!   bare [`punctual_plane`]; [`sunset_sky`] is the shipped `scenes/skies/sunset.hdr`.
//!
//! The shipped `scenes/cornell-box.gltf` and `scenes/cornell-caustics.gltf` are written from
//! these by `cargo run -p scene --example make_scenes -- scenes/`.

mod iridescent;
mod metallic_roughness;
mod murky;
mod prism;
mod translucent;

pub use iridescent::*;
pub use metallic_roughness::*;
pub use murky::*;
pub use prism::*;
pub use translucent::*;

use std::path::{Path, PathBuf};

use glam::{Vec2, Vec3};

use crate::{
    Blend, Camera, Material, PunctualKind, PunctualLight, Scene, SceneBuilder, SpotFalloff,
    Surface, Texels, Texture, Triangle, Vertex,
};

/// The Cornell box's white, red and green reflectances (linear RGB). The Cornell data gives
/// spectra; these RGB values are the common ones (McGuire's `CornellBox-Original.mtl`,
/// Tungsten, pbrt-v4-scenes).
pub const CORNELL_WHITE: Vec3 = Vec3::new(0.725, 0.71, 0.68);
pub const CORNELL_RED: Vec3 = Vec3::new(0.63, 0.065, 0.05);
pub const CORNELL_GREEN: Vec3 = Vec3::new(0.14, 0.45, 0.091);
/// The light's emitted radiance, the value most renderers use for this box.
pub const CORNELL_LIGHT_RADIANCE: Vec3 = Vec3::new(17.0, 12.0, 4.0);
/// The light's own reflectance (McGuire's `Kd`).
pub const CORNELL_LIGHT_ALBEDO: Vec3 = Vec3::splat(0.78);
/// Triangles (and UV-sphere tessellation) of the fixtures.
pub const CORNELL_BOX_TRIANGLES: usize = 38;
pub const SPHERE_SEGMENTS: u32 = 32;
pub const SPHERE_RINGS: u32 = 16;
pub const SPHERE_TRIANGLES: usize = (2 * SPHERE_SEGMENTS * (SPHERE_RINGS - 1)) as usize;

/// Furnace: albedo ρ and emitted radiance Le of every point of the sphere's inside.
pub const FURNACE_ALBEDO: f32 = 0.5;
pub const FURNACE_EMISSION: f32 = 0.5;
/// Inside a closed surface that everywhere emits Le and reflects diffusely with albedo ρ, the
/// radiance is the same at every point and in every direction: L = Le + ρL, so
/// L = Le / (1 − ρ) = 1 (the furnace test of pbrt's `integrators_test.cpp`).
pub const FURNACE_RADIANCE: f32 = FURNACE_EMISSION / (1.0 - FURNACE_ALBEDO);

/// Blended furnace: a mirror of tint [`FURNACE_BLEND_MIRROR`] with probability
/// [`FURNACE_BLEND_MIRROR_WEIGHT`], else diffuse of albedo [`FURNACE_BLEND_DIFFUSE`]: the
/// mixture reflects 0.25 × 0.8 + 0.75 × 0.4 = 0.5 = [`FURNACE_ALBEDO`] of the uniform
/// radiance, so the radiance is [`FURNACE_RADIANCE`]; a blend choosing its members the wrong
/// way round would reflect 0.7 and give 1.67.
pub const FURNACE_BLEND_MIRROR_WEIGHT: f32 = 0.25;
pub const FURNACE_BLEND_MIRROR: f32 = 0.8;
pub const FURNACE_BLEND_DIFFUSE: f32 = 0.4;

/// Lit plane: a square of half-size [`LIT_PLANE_HALF_SIZE`] at y = 0 facing +y with albedo
/// [`LIT_PLANE_ALBEDO`], under a black square light of half-size [`LIT_PLANE_LIGHT_HALF_SIZE`]
/// at y = [`LIT_PLANE_LIGHT_HEIGHT`] facing down, emitting [`LIT_PLANE_EMISSION`].
pub const LIT_PLANE_HALF_SIZE: f32 = 0.5;
pub const LIT_PLANE_ALBEDO: f32 = 0.5;
pub const LIT_PLANE_LIGHT_HALF_SIZE: f32 = 10.0;
pub const LIT_PLANE_LIGHT_HEIGHT: f32 = 1.0;
pub const LIT_PLANE_EMISSION: f32 = 1.0;

/// Punctual plane: a square of half-size [`PUNCTUAL_PLANE_HALF_SIZE`] at y = 0 facing +y with
/// albedo [`LIT_PLANE_ALBEDO`].
pub const PUNCTUAL_PLANE_HALF_SIZE: f32 = 1.0;

/// The Cornell box as published by the Cornell Program of Computer Graphics, "Cornell Box
/// Data" (<http://www.graphics.cornell.edu/online/box/data.html>): walls, blocks, light and
/// camera in the published units (millimetres), y up, the camera at z = −800 looking +z. The
/// data places the light in the ceiling's plane; here the ceiling has a hole the light's size
/// where the light sits (as in the physical box), so that no two surfaces overlap. The light
/// emits downwards only.
pub fn cornell_box() -> Scene {
    let mut f = Fixture::new("testing::cornell_box");
    let white = cornell_room(&mut f);
    let short_block = [[130.0, 65.0], [82.0, 225.0], [240.0, 272.0], [290.0, 114.0]];
    let tall_block = [
        [423.0, 247.0],
        [265.0, 296.0],
        [314.0, 456.0],
        [472.0, 406.0],
    ];
    f.block(short_block, 165.0, white);
    f.block(tall_block, 330.0, white);
    f.finish()
}

/// The Cornell box without its blocks, with a solid glass sphere (ior 1.5) front right and a
/// mirror sphere (reflectance 0.9) back left, both resting on the floor: caustics on the
/// floor and walls. Spheres are UV spheres of [`SPHERE_SEGMENTS`] × [`SPHERE_RINGS`] with
/// exact (smooth) normals.
pub fn cornell_caustics() -> Scene {
    let mut f = Fixture::new("testing::cornell_caustics");
    cornell_room(&mut f);
    let glass = f.clear_glass();
    let mirror = f.material("mirror", Surface::Mirror, Vec3::splat(0.9));
    f.sphere(Vec3::new(180.0, 90.0, 170.0), 90.0, glass, false);
    f.sphere(Vec3::new(380.0, 110.0, 370.0), 110.0, mirror, false);
    f.finish()
}

/// The room of [`cornell_caustics`] with two rough metal spheres in place of its glass and
/// mirror: gold of glTF roughness 0.3 (GGX α 0.09) and silver of roughness 0.45 (α 0.2025).
pub fn cornell_rough() -> Scene {
    let mut f = Fixture::new("testing::cornell_rough");
    cornell_room(&mut f);
    let gold = f.material(
        "rough gold",
        Surface::RoughConductor { alpha: 0.3 * 0.3 },
        Vec3::new(0.95, 0.75, 0.4),
    );
    let silver = f.material(
        "rough silver",
        Surface::RoughConductor { alpha: 0.45 * 0.45 },
        Vec3::splat(0.9),
    );
    f.sphere(Vec3::new(180.0, 90.0, 170.0), 90.0, gold, false);
    f.sphere(Vec3::new(380.0, 110.0, 370.0), 110.0, silver, false);
    f.finish()
}

/// The room of [`cornell_caustics`] with two frosted (rough) glass spheres in place of its
/// glass and mirror, solid, ior 1.5: front right of glTF roughness 0.3 (GGX α 0.09), back left
/// of roughness 0.6 (α 0.36), slightly blue. Blurred refractions and soft caustics.
pub fn cornell_frosted() -> Scene {
    let mut f = Fixture::new("testing::cornell_frosted");
    cornell_room(&mut f);
    let frosted = f.material(
        "frosted glass",
        Surface::RoughDielectric {
            ior: 1.5,
            thin_walled: false,
            alpha: 0.3 * 0.3,
        },
        Vec3::ONE,
    );
    let milky = f.material(
        "milky glass",
        Surface::RoughDielectric {
            ior: 1.5,
            thin_walled: false,
            alpha: 0.6 * 0.6,
        },
        Vec3::new(0.85, 0.9, 1.0),
    );
    f.sphere(Vec3::new(180.0, 90.0, 170.0), 90.0, frosted, false);
    f.sphere(Vec3::new(380.0, 110.0, 370.0), 110.0, milky, false);
    f.finish()
}

/// The room of [`cornell_caustics`] with two tinted solid glass spheres (ior 1.5) whose colour
/// is absorption inside them (glTF's `KHR_materials_volume` attenuation, Beer–Lambert), not a
/// tint at their surfaces: front right smooth teal glass (white light turns (0.35, 0.75, 0.95)
/// after 100), back left frosted amber glass, roughness 0.2 (α 0.04), turning (0.95, 0.6, 0.2)
/// after 150. Thicker paths through them are deeper in colour, and so are their caustics.
pub fn cornell_tinted() -> Scene {
    let mut f = Fixture::new("testing::cornell_tinted");
    cornell_room(&mut f);
    let teal = f.builder.add_material(Material {
        name: "teal glass".into(),
        surface: Surface::Dielectric {
            ior: 1.5,
            thin_walled: false,
        },
        base_color: Vec3::ONE,
        absorption: crate::absorption_from_attenuation(Vec3::new(0.35, 0.75, 0.95), 100.0),
        ..Material::default()
    });
    let amber = f.builder.add_material(Material {
        name: "amber glass".into(),
        surface: Surface::RoughDielectric {
            ior: 1.5,
            thin_walled: false,
            alpha: 0.2 * 0.2,
        },
        base_color: Vec3::ONE,
        absorption: crate::absorption_from_attenuation(Vec3::new(0.95, 0.6, 0.2), 150.0),
        ..Material::default()
    });
    f.sphere(Vec3::new(180.0, 90.0, 170.0), 90.0, teal, false);
    f.sphere(Vec3::new(380.0, 110.0, 370.0), 110.0, amber, false);
    f.finish()
}

/// The room of [`cornell_caustics`] in plastic (`Surface::Plastic`, coats of ior 1.5): the
/// floor smooth white plastic (it mirrors the room faintly, more towards grazing), a smooth red
/// plastic sphere front right and a glossy blue one back left (glTF roughness 0.3, GGX α 0.09).
pub fn cornell_plastic() -> Scene {
    let mut f = Fixture::new("testing::cornell_plastic");
    let white = f.material("white", Surface::Diffuse, CORNELL_WHITE);
    let coat = |alpha| Surface::Plastic { ior: 1.5, alpha };
    let floor = f.material("white plastic", coat(0.0), CORNELL_WHITE);
    cornell_room_on(&mut f, white, floor);
    let red = f.material("red plastic", coat(0.0), Vec3::new(0.7, 0.08, 0.06));
    let blue = f.material("blue plastic", coat(0.3 * 0.3), Vec3::new(0.1, 0.25, 0.7));
    f.sphere(Vec3::new(180.0, 90.0, 170.0), 90.0, red, false);
    f.sphere(Vec3::new(380.0, 110.0, 370.0), 110.0, blue, false);
    f.finish()
}

/// The room of [`cornell_caustics`] under glTF's clear coats (`scene::Clearcoat`, index 1.5):
/// the floor white Lambertian under a full smooth coat, a sphere front right brushed gold
/// (rough metal, GGX α 0.04) under half a rough coat (roughness 0.2), and one back left, a
/// blend half mirror half blue plastic, under a full smooth coat.
pub fn cornell_clearcoat() -> Scene {
    let mut f = Fixture::new("testing::cornell_clearcoat");
    let white = f.material("white", Surface::Diffuse, CORNELL_WHITE);
    let coated = |f: &mut Fixture, name: &str, surface, color, coat| {
        f.builder.add_material(Material {
            name: String::from(name),
            surface,
            base_color: color,
            clearcoat: coat,
            ..Material::default()
        })
    };
    let floor = coated(
        &mut f,
        "coated white",
        Surface::Diffuse,
        CORNELL_WHITE,
        crate::Clearcoat::new(1.0, 0.0),
    );
    cornell_room_on(&mut f, white, floor);
    let gold = coated(
        &mut f,
        "coated gold",
        Surface::RoughConductor { alpha: 0.2 * 0.2 },
        Vec3::new(0.9, 0.7, 0.3),
        crate::Clearcoat::new(0.5, 0.2),
    );
    let base = Material {
        name: "coated mirror and plastic".into(),
        base_color: Vec3::new(0.1, 0.25, 0.7),
        clearcoat: crate::Clearcoat::new(1.0, 0.0),
        ..Material::default()
    };
    let plastic = Surface::Plastic {
        ior: 1.5,
        alpha: 0.0,
    };
    let blend = f
        .builder
        .add_blend(base, &[(0.5, Surface::Mirror), (0.5, plastic)]);
    f.sphere(Vec3::new(180.0, 90.0, 170.0), 90.0, gold, false);
    f.sphere(Vec3::new(380.0, 110.0, 370.0), 110.0, blend, false);
    f.finish()
}

/// The room of [`cornell_caustics`] with glTF sheens (`scene::Sheen`): a sphere front right
/// of red velvet (a dark red Lambertian base under a pink sheen of roughness 0.3), and one
/// back left of blue plastic (coat roughness 0.2) under a white sheen of roughness 0.6 and
/// half a smooth clear coat: every layer over one another.
pub fn cornell_sheen() -> Scene {
    let mut f = Fixture::new("testing::cornell_sheen");
    let white = f.material("white", Surface::Diffuse, CORNELL_WHITE);
    cornell_room_on(&mut f, white, white);
    let velvet = f.builder.add_material(Material {
        name: "red velvet".into(),
        base_color: Vec3::new(0.25, 0.01, 0.03),
        sheen: crate::Sheen::new(Vec3::new(1.0, 0.45, 0.55), 0.3),
        ..Material::default()
    });
    let layered = f.builder.add_material(Material {
        name: "sheen over coated blue plastic".into(),
        surface: Surface::Plastic {
            ior: 1.5,
            alpha: 0.2 * 0.2,
        },
        base_color: Vec3::new(0.1, 0.25, 0.7),
        sheen: crate::Sheen::new(Vec3::splat(0.8), 0.6),
        clearcoat: crate::Clearcoat::new(0.5, 0.0),
        ..Material::default()
    });
    f.sphere(Vec3::new(180.0, 90.0, 170.0), 90.0, velvet, false);
    f.sphere(Vec3::new(380.0, 110.0, 370.0), 110.0, layered, false);
    f.finish()
}

/// The room of [`cornell_caustics`] with brushed metal (glTF's `KHR_materials_anisotropy`):
/// a gold sphere front right (GGX α 0.04) brushed at strength 0.9 around its vertical axis,
/// and a silver one back left (α 0.02) brushed at 0.8 from pole to pole (rotated a quarter
/// turn); their texture coordinates run along longitude (u) and latitude (v), which only
/// the brushing reads.
pub fn cornell_brushed() -> Scene {
    let mut f = Fixture::new("testing::cornell_brushed");
    cornell_room(&mut f);
    let brushed = |f: &mut Fixture, name: &str, color: Vec3, roughness: f32, strength, rotation| {
        f.builder.add_material(Material {
            name: name.into(),
            surface: Surface::RoughConductor {
                alpha: roughness * roughness,
            },
            base_color: color,
            anisotropy: Some(crate::Anisotropy {
                strength,
                rotation,
                texture: None,
            }),
            ..Material::default()
        })
    };
    let gold = brushed(
        &mut f,
        "brushed gold",
        Vec3::new(0.95, 0.75, 0.4),
        0.2,
        0.9,
        0.0,
    );
    let quarter = std::f32::consts::FRAC_PI_2;
    let silver = brushed(
        &mut f,
        "brushed silver",
        Vec3::splat(0.9),
        0.15,
        0.8,
        quarter,
    );
    let spheres = [
        (Vec3::new(180.0, 90.0, 170.0), 90.0, gold),
        (Vec3::new(380.0, 110.0, 370.0), 110.0, silver),
    ];
    for (centre, radius, material) in spheres {
        f.sphere(centre, radius, material, false);
    }
    let mut scene = f.finish();
    // Longitude and latitude as texture coordinates (the seam's triangles see u run the
    // other way, which a brushing does not tell from its own).
    for triangle in &mut scene.triangles {
        let Some(&(centre, _, _)) = spheres.iter().find(|s| s.2 == triangle.material) else {
            continue;
        };
        for v in &mut triangle.vertices {
            let d = (v.position - centre).normalize();
            let u = d.z.atan2(d.x) / std::f32::consts::TAU;
            v.uv = Vec2::new(u, d.y.clamp(-1.0, 1.0).acos() / std::f32::consts::PI);
        }
    }
    scene
}

/// The room of [`cornell_box`] with glTF's diffuse transmission (`KHR_materials_diffuse_
/// transmission`): a paper lantern back left (a white sphere resting on the floor that lets
/// 60 % of what reaches its Lambertian lobe through, warmed, from a bulb inside it), and a
/// green leaf-like sheet hung tilted under the ceiling light, letting half its light through
/// onto the floor tinted green.
pub fn cornell_translucent() -> Scene {
    let mut f = Fixture::new("testing::cornell_translucent");
    cornell_room(&mut f);
    let paper = f.builder.add_material(Material {
        name: "lantern paper".into(),
        base_color: Vec3::new(0.85, 0.83, 0.78),
        diffuse_transmission: crate::DiffuseTransmission::new(0.6, Vec3::new(1.0, 0.85, 0.6)),
        ..Material::default()
    });
    let bulb = f.builder.add_material(Material {
        name: "bulb".into(),
        base_color: Vec3::ZERO,
        emission: Vec3::new(40.0, 30.0, 15.0),
        ..Material::default()
    });
    let leaf = f.builder.add_material(Material {
        name: "leaf".into(),
        base_color: Vec3::new(0.2, 0.4, 0.08),
        diffuse_transmission: crate::DiffuseTransmission::new(0.5, Vec3::new(0.5, 0.9, 0.2)),
        ..Material::default()
    });
    let lantern = Vec3::new(380.0, 110.0, 370.0);
    f.sphere(lantern, 110.0, paper, false);
    f.sphere(lantern, 20.0, bulb, false);
    let leaf_corners = [
        Vec3::new(150.0, 340.0, 160.0),
        Vec3::new(350.0, 340.0, 160.0),
        Vec3::new(350.0, 460.0, 330.0),
        Vec3::new(150.0, 460.0, 330.0),
    ];
    f.quad(leaf_corners, leaf, Vec3::new(0.0, -1.0, 0.7));
    f.finish()
}

/// The room of [`cornell_caustics`] with blends (`SceneBuilder::add_blend`, as glTF's partial
/// metallic and transmission factors make them): the floor 30 % mirror over white plastic,
/// a gold sphere front right half rough metal (GGX α 0.04) half rough plastic, and a sphere
/// back left 60 % solid glass and 40 % smooth white plastic (glTF: metallic 0.3 roughness 0;
/// metallic 0.5 roughness 0.2; transmission 0.6 roughness 0).
pub fn cornell_blended() -> Scene {
    let mut f = Fixture::new("testing::cornell_blended");
    let white = f.material("white", Surface::Diffuse, CORNELL_WHITE);
    let blend = |f: &mut Fixture, name: &str, color: Vec3, members: &[(f32, Surface)]| {
        let base = Material {
            name: name.into(),
            base_color: color,
            ..Material::default()
        };
        f.builder.add_blend(base, members)
    };
    let coat = |alpha| Surface::Plastic { ior: 1.5, alpha };
    let floor_members = [(0.3, Surface::Mirror), (0.7, coat(0.0))];
    let floor = blend(&mut f, "mirror over plastic", CORNELL_WHITE, &floor_members);
    cornell_room_on(&mut f, white, floor);
    let gold = Vec3::new(0.9, 0.6, 0.2);
    let alpha = 0.2 * 0.2;
    let gold_members = [(0.5, Surface::RoughConductor { alpha }), (0.5, coat(alpha))];
    let gold = blend(&mut f, "half gold", gold, &gold_members);
    let glass = Surface::Dielectric {
        ior: 1.5,
        thin_walled: false,
    };
    let milky = blend(
        &mut f,
        "glass and plastic",
        Vec3::splat(0.9),
        &[(0.6, glass), (0.4, coat(0.0))],
    );
    f.sphere(Vec3::new(180.0, 90.0, 170.0), 90.0, gold, false);
    f.sphere(Vec3::new(380.0, 110.0, 370.0), 110.0, milky, false);
    f.finish()
}

/// The water of [`cornell_pool`]: its mean level, its waves' amplitude (two crossing sine
/// waves, the second at 0.6 of it) and their wavelengths, all in millimetres, and its index.
pub const POOL_LEVEL: f32 = 150.0;
pub const POOL_WAVE_AMPLITUDE: f64 = 5.0;
pub const POOL_WAVELENGTHS: [f64; 2] = [130.0, 85.0];
pub const POOL_IOR: f32 = 1.33;
/// The water's tint (`KHR_materials_volume`): white light turns this colour after this many
/// millimetres in it, so that red fades first, as in a pool.
pub const POOL_ATTENUATION: Vec3 = Vec3::new(0.5, 0.82, 0.88);
pub const POOL_ATTENUATION_DISTANCE: f32 = 250.0;
/// Quads along each side of the water surface's grid.
pub const POOL_GRID: u32 = 40;

/// [`cornell_caustics`]'s room flooded to [`POOL_LEVEL`]: the water's surface a grid of
/// [`POOL_GRID`]² quads over the floor's footprint, displaced by two crossing sine waves
/// with exact normals, its front face up, a solid dielectric of [`POOL_IOR`], closed towards
/// the camera by a flat front in the room's open side (the floor and walls close the rest),
/// so the floor, the walls' lower parts and a blue diffuse sphere back left (radius 100, its
/// top 50 above the water) lie under water. The waves focus the light into a network of
/// caustics on the floor; eye paths end on the floor inside the water, whose photons crossed
/// the surface once (`render::optics::eye_refraction_scale`). The water is tinted
/// ([`POOL_ATTENUATION`]): its segments end at front faces of the floor, walls and sphere, so
/// only a path that knows it is in the water absorbs along them (`render::medium`). Camera 0
/// is the Cornell camera; camera 1 looks from under water, where its paths start.
pub fn cornell_pool() -> Scene {
    let mut f = Fixture::new("testing::cornell_pool");
    flooded_room(&mut f);
    f.finish()
}

/// The glass marble of [`cornell_marble`]: its index, centre and radius (millimetres), and
/// its amber tint (white light turns this colour after [`MARBLE_ATTENUATION_DISTANCE`]).
pub const MARBLE_IOR: f32 = 1.5;
pub const MARBLE_CENTRE: Vec3 = Vec3::new(165.0, 70.0, 230.0);
pub const MARBLE_RADIUS: f32 = 65.0;
pub const MARBLE_ATTENUATION: Vec3 = Vec3::new(0.92, 0.62, 0.3);
pub const MARBLE_ATTENUATION_DISTANCE: f32 = 120.0;

/// [`cornell_pool`] with an amber glass marble of [`MARBLE_IOR`] lying under the water, front
/// right: solids nested (`render::nesting`). Light crossing from the water into the marble
/// bends by 1.5 / 1.33 (so it focuses far less than in air) and, leaving it, is in the water
/// again, which absorbs on. Same two cameras.
pub fn cornell_marble() -> Scene {
    let mut f = Fixture::new("testing::cornell_marble");
    flooded_room(&mut f);
    let marble = f.builder.add_material(Material {
        name: "marble".into(),
        surface: Surface::Dielectric {
            ior: MARBLE_IOR,
            thin_walled: false,
        },
        base_color: Vec3::ONE,
        absorption: crate::absorption_from_attenuation(
            MARBLE_ATTENUATION,
            MARBLE_ATTENUATION_DISTANCE,
        ),
        ..Material::default()
    });
    f.sphere(MARBLE_CENTRE, MARBLE_RADIUS, marble, false);
    f.finish()
}

/// [`cornell_pool`]'s room, water, ball and cameras.
fn flooded_room(f: &mut Fixture) {
    cornell_room(f);
    let water = f.builder.add_material(Material {
        name: "water".into(),
        surface: Surface::Dielectric {
            ior: POOL_IOR,
            thin_walled: false,
        },
        base_color: Vec3::ONE,
        absorption: crate::absorption_from_attenuation(POOL_ATTENUATION, POOL_ATTENUATION_DISTANCE),
        ..Material::default()
    });
    let blue = f.material("blue", Surface::Diffuse, Vec3::new(0.1, 0.25, 0.7));
    f.sphere(Vec3::new(370.0, 100.0, 360.0), 100.0, blue, false);
    // Heights and slopes in f64, rounded once (the shipped file regenerates byte for byte).
    let [ka, kb] = POOL_WAVELENGTHS.map(|l| std::f64::consts::TAU / l);
    let (a, b) = (POOL_WAVE_AMPLITUDE, 0.6 * POOL_WAVE_AMPLITUDE);
    let (ca, sa) = (0.8f64, 0.6f64); // the second wave's direction in the floor's plane
    let surface = |x: f64, z: f64| {
        let (pa, pb) = (ka * (x + 0.3 * z), kb * (ca * x - sa * z));
        let height = POOL_LEVEL as f64 + a * pa.sin() + b * pb.sin();
        let dx = a * ka * pa.cos() + b * kb * ca * pb.cos();
        let dz = a * ka * 0.3 * pa.cos() - b * kb * sa * pb.cos();
        Vertex {
            position: glam::DVec3::new(x, height, z).as_vec3(),
            normal: glam::DVec3::new(-dx, 1.0, -dz).normalize().as_vec3(),
            ..Vertex::default()
        }
    };
    // The floor's corners: its footprint, x from the right wall (0) to the left one.
    let [near_left, _, _, far_left] = CORNELL_QUADS[0].map(|c| glam::DVec3::from(c.map(f64::from)));
    let depth = far_left.z;
    let point = |i: u32, j: u32| {
        let (u, v) = (i as f64 / POOL_GRID as f64, j as f64 / POOL_GRID as f64);
        let left = near_left.x + v * (far_left.x - near_left.x);
        surface(u * left, v * depth)
    };
    for i in 0..POOL_GRID {
        for j in 0..POOL_GRID {
            let [p, q] = [point(i, j), point(i + 1, j)];
            let [r, t] = [point(i + 1, j + 1), point(i, j + 1)];
            f.triangle([p, q, r], water, Vec3::Y);
            f.triangle([p, r, t], water, Vec3::Y);
        }
    }
    // The water's front, in the room's open side: from the floor's front edge up to the
    // surface's, sharing its vertices, so that the water is a closed volume (with the floor
    // and walls) and the camera sees the water below its surface through it, as into a tank.
    for i in 0..POOL_GRID {
        let [p, q] = [point(i, 0), point(i + 1, 0)];
        let on_floor = |v: Vertex| Vertex {
            position: Vec3::new(v.position.x, 0.0, v.position.z),
            ..Vertex::default()
        };
        let flat = |v: Vertex| Vertex {
            normal: Vec3::ZERO,
            ..v
        };
        f.triangle([on_floor(p), on_floor(q), flat(q)], water, Vec3::NEG_Z);
        f.triangle([on_floor(p), flat(q), flat(p)], water, Vec3::NEG_Z);
    }
    // A second camera under water, behind the front, looking at the ball and up at the
    // surface from beneath (`kousen render --camera 1`): its paths start in the water.
    let eye = Vec3::new(120.0, 40.0, 30.0);
    let target = Vec3::new(300.0, 150.0, 500.0);
    f.camera(
        eye,
        target - eye,
        60f32.to_radians(),
        Some(1.0),
        "under water",
    );
}

/// The room of [`cornell_caustics`] with normal maps (`Material::normal_texture`): the floor
/// and back wall laid with bevelled tiles ([`tile_normal_map`], a tile 139.75 mm wide), a
/// white diffuse sphere front right and a mirror sphere back left, both hammered
/// ([`dimple_normal_map`] at scale 0.6 and 0.5). Texture coordinates: planar on the
/// walls, longitude and latitude on the spheres, which carry their own tangents too (along
/// the longitude, [`spherical_tangents`]: the frame their maps follow, smooth across
/// triangles).
pub fn cornell_bumpy() -> Scene {
    let mut f = Fixture::new("testing::cornell_bumpy");
    let white = cornell_room(&mut f);
    let clay = f.material("hammered clay", Surface::Diffuse, CORNELL_WHITE);
    let mirror = f.material("hammered mirror", Surface::Mirror, Vec3::splat(0.9));
    let (front, back) = (
        Vec3::new(180.0, 90.0, 170.0),
        Vec3::new(380.0, 110.0, 370.0),
    );
    f.sphere(front, 90.0, clay, false);
    f.sphere(back, 110.0, mirror, false);
    let mut scene = f.finish();
    let tiles = scene.textures.len() as u32;
    scene.textures.push(tile_normal_map(64));
    scene.textures.push(dimple_normal_map(64));
    let tiled = scene.materials.len() as u32;
    scene.materials.push(Material {
        name: "tiled white".into(),
        normal_texture: Some(tiles),
        ..scene.materials[white as usize].clone()
    });
    scene.materials[clay as usize].normal_texture = Some(tiles + 1);
    scene.materials[clay as usize].normal_scale = 0.6;
    scene.materials[mirror as usize].normal_texture = Some(tiles + 1);
    scene.materials[mirror as usize].normal_scale = 0.5;
    let tile = 559.0 / 4.0;
    for triangle in &mut scene.triangles {
        let centre = triangle.vertices.iter().map(|v| v.position).sum::<Vec3>() / 3.0;
        let on_floor = triangle.material == white && centre.y < 1.0;
        let on_back = triangle.material == white && centre.z > 559.0;
        if on_floor || on_back {
            triangle.material = tiled;
            for v in &mut triangle.vertices {
                let p = v.position / tile;
                // u along +x; v down the back wall and towards the viewer on the floor.
                v.uv = if on_floor {
                    Vec2::new(p.x, -p.z)
                } else {
                    Vec2::new(p.x, -p.y)
                };
            }
        } else if triangle.material == clay || triangle.material == mirror {
            let centre = if triangle.material == clay {
                front
            } else {
                back
            };
            spherical_uvs(triangle, centre);
            spherical_tangents(triangle, centre);
        }
    }
    scene
}

/// The tangents of a sphere about `centre` whose u runs with the longitude
/// ([`spherical_uvs`]): along increasing longitude at each corner (at a pole, the triangle's
/// centre's), of the handedness that puts w · normal × tangent towards +y, the image's top.
fn spherical_tangents(triangle: &mut Triangle, centre: Vec3) {
    let along_longitude = |d: Vec3| Vec3::new(-d.z, 0.0, d.x).normalize_or_zero();
    let middle = (triangle.vertices.iter().map(|v| v.position).sum::<Vec3>() / 3.0 - centre)
        .normalize_or_zero();
    for v in &mut triangle.vertices {
        let d = (v.position - centre).normalize_or_zero();
        let mut tangent = along_longitude(d);
        if tangent.length_squared() < 1e-6 {
            tangent = along_longitude(middle);
        }
        let top = Vec3::Y - middle * middle.y;
        let handedness = if v.normal.cross(tangent).dot(top) < 0.0 {
            -1.0
        } else {
            1.0
        };
        v.tangent = tangent.extend(handedness);
    }
}

/// Longitude and latitude of a sphere's triangle about `centre`, twelve times around (u) and
/// six times from pole to pole (v): u unwrapped across the seam so no triangle spans the
/// texture.
fn spherical_uvs(triangle: &mut Triangle, centre: Vec3) {
    let mut uvs = triangle.vertices.map(|v| {
        let d = (v.position - centre).normalize();
        let u = 0.5 + d.z.atan2(d.x) / std::f32::consts::TAU;
        Vec2::new(u, d.y.clamp(-1.0, 1.0).acos() / std::f32::consts::PI)
    });
    let largest = uvs.iter().map(|uv| uv.x).fold(f32::MIN, f32::max);
    for uv in &mut uvs {
        if largest - uv.x > 0.5 {
            uv.x += 1.0;
        }
    }
    for (v, uv) in triangle.vertices.iter_mut().zip(uvs) {
        v.uv = uv * Vec2::new(12.0, 6.0);
    }
}

/// A tangent-space normal map of `side`² texels (linear data, glTF's convention): one square
/// tile whose outer fifth bevels down to a grout line at 45°.
pub fn tile_normal_map(side: u32) -> Texture {
    normal_map("tiles", side, |s, t| {
        let edge = |c: f32| {
            if c < 0.1 {
                -1.0
            } else if c > 0.9 {
                1.0
            } else {
                0.0
            }
        };
        // Bevelled edges face outwards: +X at the right, towards the top (+Y) at t's low end.
        Vec3::new(edge(s), -edge(t), 1.0)
    })
}

/// A tangent-space normal map of `side`² texels: a hammered look, the slopes of the height
/// field 0.7/2π · sin(2πs)·sin(2πt), 35° at most.
pub fn dimple_normal_map(side: u32) -> Texture {
    normal_map("dimples", side, |s, t| {
        let k = 0.7;
        let (a, b) = (std::f32::consts::TAU * s, std::f32::consts::TAU * t);
        // Slopes ∂h/∂s and ∂h/∂t; the image's top is −t.
        Vec3::new(-k * a.cos() * b.sin(), k * a.sin() * b.cos(), 1.0)
    })
}

/// A normal map from `normal(s, t)` (unnormalised, tangent space) at texel centres, 8 bits a
/// channel.
fn normal_map(name: &str, side: u32, normal: impl Fn(f32, f32) -> Vec3) -> Texture {
    let centre = |i: u32| (i as f32 + 0.5) / side as f32;
    let texels = (0..side * side)
        .map(|i| {
            let n = normal(centre(i % side), centre(i / side)).normalize();
            // 8 bits a channel, as an image file holds it (the shipped glTF does).
            let c = ((n * 0.5 + Vec3::splat(0.5)) * 255.0).round() / 255.0;
            [c.x, c.y, c.z, 1.0]
        })
        .collect();
    Texture {
        name: name.into(),
        width: side,
        height: side,
        texels: Texels::LinearF32(texels),
    }
}

/// Glass pane: a thin-walled glass sheet (ior [`GLASS_PANE_IOR`]) at z = 1, an emitter of
/// radiance [`GLASS_PANE_FRONT_EMISSION`] behind it at z = 2 facing the camera, and one of
/// [`GLASS_PANE_BACK_EMISSION`] at z = −1 facing the sheet, behind the camera (which sits at
/// the origin looking +z with a 2° field of view, so it sees only the sheet). Between the
/// camera and the back emitter, at z = −0.5, hangs an alpha cut-out that is all hole: camera
/// rays start past it, and what the sheet reflects passes through it.
pub const GLASS_PANE_IOR: f32 = 1.5;
pub const GLASS_PANE_FRONT_EMISSION: f32 = 1.0;
pub const GLASS_PANE_BACK_EMISSION: f32 = 3.0;

/// The scene of [`GLASS_PANE_IOR`] and the constants after it. Both emitters are black, so
/// what reaches the camera is the back emitter reflected by the sheet and the front one seen
/// through it: [`glass_pane_radiance`].
pub fn glass_pane() -> Scene {
    glass_panes(1)
}

/// [`glass_pane`] with `count` sheets, 0.2 apart from z = 1 on (at most 4, before the front
/// emitter): a camera ray meets glass again after the first sheet.
pub fn glass_panes(count: u32) -> Scene {
    assert!((1..=4).contains(&count), "1 to 4 sheets");
    let mut f = Fixture::new("testing::glass_pane");
    let glass = f.material(
        "sheet",
        Surface::Dielectric {
            ior: GLASS_PANE_IOR,
            thin_walled: true,
        },
        Vec3::ONE,
    );
    let mut emitter = |name: &str, radiance: f32| {
        f.builder.add_material(Material {
            name: name.into(),
            base_color: Vec3::ZERO,
            emission: Vec3::splat(radiance),
            ..Material::default()
        })
    };
    let (front, back) = (
        emitter("front", GLASS_PANE_FRONT_EMISSION),
        emitter("back", GLASS_PANE_BACK_EMISSION),
    );
    let square = |half: f32, z: f32| {
        [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]]
            .map(|[x, y]| Vec3::new(x * half, y * half, z))
    };
    for sheet in 0..count {
        f.quad(square(1.0, 1.0 + 0.2 * sheet as f32), glass, Vec3::NEG_Z);
    }
    let veil = f.builder.add_material(Material {
        name: "veil".into(),
        base_color: Vec3::ONE,
        alpha: 0.0,
        alpha_mode: crate::AlphaMode::Mask { cutoff: 0.5 },
        ..Material::default()
    });
    f.quad(square(4.0, -0.5), veil, Vec3::Z);
    f.quad(square(2.0, 2.0), front, Vec3::NEG_Z);
    f.quad(square(4.0, -1.0), back, Vec3::Z);
    f.camera(Vec3::ZERO, Vec3::Z, 2f32.to_radians(), None, "head-on");
    f.finish()
}

/// What a camera ray of [`glass_pane`] meeting the sheet at `cos_incident` sees: the back
/// emitter reflected with the sheet's total reflectance R' = 2R/(1 + R) (R: Fresnel's) and
/// the front one through it with 1 − R'. `fresnel` is Fresnel's reflectance of a smooth
/// dielectric for (cos θ, η), which this crate does not define.
pub fn glass_pane_radiance(cos_incident: f32, fresnel: impl Fn(f32, f32) -> f32) -> f32 {
    let r = fresnel(cos_incident, 1.0 / GLASS_PANE_IOR);
    let sheet = 2.0 * r / (1.0 + r);
    sheet * GLASS_PANE_BACK_EMISSION + (1.0 - sheet) * GLASS_PANE_FRONT_EMISSION
}

/// `2∫ f(μ) μ dμ` over [0, 1]: the mean of `f` over the cosine of a direction drawn from a
/// uniform sky's light on a plane (its cosine-weighted hemisphere), by the midpoint rule.
pub fn cosine_weighted_mean(f: impl Fn(f32) -> f64) -> f64 {
    let steps = 100_000;
    (0..steps)
        .map(|i| {
            let mu = (i as f64 + 0.5) / steps as f64;
            2.0 * mu * f(mu as f32) / steps as f64
        })
        .sum()
}

/// What a Lambertian plane of `albedo` under a smooth clear coat of `weight` (index
/// [`crate::Clearcoat::IOR`]) returns under a uniform sky of radiance `sky`, seen at cosine
/// `cos`: sky·(w·F(θ) + (1 − w·F(θ))·ρ·(1 − w·F̄)), the coat's reflection of the sky plus the
/// plane lit through the coat, F̄ = 2∫F(μ)μ dμ by the midpoint rule (computed once here).
/// `fresnel` is as [`glass_pane_radiance`]'s.
pub fn clear_coated_sky_plane(
    sky: f32,
    albedo: f32,
    weight: f32,
    fresnel: impl Fn(f32, f32) -> f32,
) -> impl Fn(f32) -> f64 {
    let fresnel = move |cos: f32| fresnel(cos, 1.0 / crate::Clearcoat::IOR) as f64;
    let mean_fresnel = cosine_weighted_mean(&fresnel);
    let weight = weight as f64;
    move |cos| {
        let reflected = weight * fresnel(cos);
        let beneath = (1.0 - reflected) * albedo as f64 * (1.0 - weight * mean_fresnel);
        sky as f64 * (reflected + beneath)
    }
}

/// A unit sphere at the origin facing inwards, every point emitting [`FURNACE_EMISSION`] and
/// reflecting with albedo [`FURNACE_ALBEDO`]; the camera sits at the centre. Every pixel's
/// radiance is [`FURNACE_RADIANCE`] (the triangulation does not matter: any closed surface
/// gives the same answer).
pub fn furnace_sphere() -> Scene {
    let mut f = Fixture::new("testing::furnace_sphere");
    let inside = f.builder.add_material(Material {
        name: "furnace".into(),
        base_color: Vec3::splat(FURNACE_ALBEDO),
        emission: Vec3::splat(FURNACE_EMISSION),
        ..Material::default()
    });
    f.sphere(Vec3::ZERO, 1.0, inside, true);
    f.camera(Vec3::ZERO, Vec3::NEG_Z, 60f32.to_radians(), None, "centre");
    f.finish()
}

/// Dense flint glass, strongly dispersive: its index (at the d line, 587.6 nm) and Abbe number.
pub const FLINT_IOR: f32 = 1.75;
pub const FLINT_ABBE: f32 = 25.0;

/// [`furnace_sphere`] with a ball of dispersive flint glass ([`FLINT_IOR`], [`FLINT_ABBE`])
/// in view, radius 0.3 and half a unit ahead of the camera: lossless, so in the furnace it is
/// invisible, each wavelength refracting its own way through it.
pub fn furnace_with_dispersive_glass() -> Scene {
    furnace_with_dispersive_glass_of(Surface::Dielectric {
        ior: FLINT_IOR,
        thin_walled: false,
    })
}

/// [`furnace_with_dispersive_glass`] whose flint is frosted (GGX α 0.3): still lossless and
/// invisible, though each wavelength's light samples and paths go through rough glass.
pub fn furnace_with_frosted_dispersive_glass() -> Scene {
    furnace_with_dispersive_glass_of(Surface::RoughDielectric {
        ior: FLINT_IOR,
        thin_walled: false,
        alpha: 0.3,
    })
}

/// [`furnace_sphere`] with a ball of clear glass (index 1.5) under glTF's specular layer,
/// strongly tinted and weak (strength 0.4, colour (2.5, 1, 0.2)): each channel reflects its own
/// share and lets the rest through, and total internal reflection inside is kept, so the
/// ball is lossless and in the furnace invisible.
pub fn furnace_with_layered_glass() -> Scene {
    let ior = 1.5;
    furnace_around(
        "testing::furnace_with_layered_glass",
        Material {
            name: "glass under a specular layer".into(),
            surface: Surface::Dielectric {
                ior,
                thin_walled: false,
            },
            base_color: Vec3::ONE,
            specular: Some(crate::SpecularLayer::new(
                ior,
                Vec3::new(2.5, 1.0, 0.2),
                0.4,
            )),
            ..Material::default()
        },
    )
}

fn furnace_with_dispersive_glass_of(glass: Surface) -> Scene {
    furnace_around(
        "testing::furnace_with_dispersive_glass",
        Material {
            name: "flint glass".into(),
            surface: glass,
            base_color: Vec3::ONE,
            dispersion: crate::dispersion_from_abbe(FLINT_IOR, FLINT_ABBE),
            ..Material::default()
        },
    )
}

/// [`furnace_sphere`] with a ball of `ball` in view, radius 0.3 and half a unit ahead of the
/// camera (at the furnace's centre).
fn furnace_around(name: &str, ball: Material) -> Scene {
    let mut f = Fixture::new(name);
    let inside = f.builder.add_material(Material {
        name: "furnace".into(),
        base_color: Vec3::splat(FURNACE_ALBEDO),
        emission: Vec3::splat(FURNACE_EMISSION),
        ..Material::default()
    });
    let ball = f.builder.add_material(ball);
    f.sphere(Vec3::ZERO, 1.0, inside, true);
    f.sphere(Vec3::new(0.0, 0.0, -0.5), 0.3, ball, false);
    f.camera(Vec3::ZERO, Vec3::NEG_Z, 60f32.to_radians(), None, "centre");
    f.finish()
}

/// [`cornell_spot`] with its glass sphere of dispersive flint ([`FLINT_IOR`], [`FLINT_ABBE`]):
/// the spot's caustic splits by colour, blue focused nearest the sphere.
pub fn cornell_dispersion() -> Scene {
    let mut scene = cornell_spot();
    let glass = scene
        .materials
        .iter_mut()
        .find(|m| m.name == "glass")
        .expect("cornell_caustics has glass");
    glass.name = "flint glass".into();
    glass.surface = Surface::Dielectric {
        ior: FLINT_IOR,
        thin_walled: false,
    };
    glass.dispersion = crate::dispersion_from_abbe(FLINT_IOR, FLINT_ABBE);
    scene
}

/// [`furnace_sphere`] whose inside is a blend (`Material::blend`) of a mirror and a diffuse
/// surface of different reflectances ([`FURNACE_BLEND_MIRROR_WEIGHT`] and the constants after
/// it), both emitting [`FURNACE_EMISSION`]: every pixel's radiance is [`FURNACE_RADIANCE`].
pub fn furnace_sphere_blended() -> Scene {
    let mut f = Fixture::new("testing::furnace_sphere_blended");
    let member = |surface, albedo: f32, blend| Material {
        name: "blended furnace".into(),
        surface,
        base_color: Vec3::splat(albedo),
        emission: Vec3::splat(FURNACE_EMISSION),
        blend,
        ..Material::default()
    };
    let mirror = f.builder.materials().len() as u32;
    let blend = Blend {
        weight: FURNACE_BLEND_MIRROR_WEIGHT,
        other: mirror + 1,
    };
    let mirror = f
        .builder
        .add_material(member(Surface::Mirror, FURNACE_BLEND_MIRROR, Some(blend)));
    f.builder
        .add_material(member(Surface::Diffuse, FURNACE_BLEND_DIFFUSE, None));
    f.sphere(Vec3::ZERO, 1.0, mirror, true);
    f.camera(Vec3::ZERO, Vec3::NEG_Z, 60f32.to_radians(), None, "centre");
    f.finish()
}

/// [`furnace_sphere_blended`] made by [`crate::SceneBuilder::add_mixture`] from whole
/// materials of their own colours (as pbrt's `mix` and Mitsuba's `blendbsdf` make them): a
/// mirror of tint (0.8, 0.2, 0.5) with probability ¼ and a diffuse surface of albedo
/// (0.4, 0.6, 0.5), which mix to 0.5 in every channel: every pixel's radiance is
/// [`FURNACE_RADIANCE`], grey, only where each member reflects its own colour.
pub fn furnace_sphere_mixed() -> Scene {
    let mut f = Fixture::new("testing::furnace_sphere_mixed");
    let member = |surface, colour: Vec3| Material {
        name: "mixed furnace".into(),
        surface,
        base_color: colour,
        emission: Vec3::splat(FURNACE_EMISSION),
        ..Material::default()
    };
    let mixture = vec![
        (0.25, member(Surface::Mirror, Vec3::new(0.8, 0.2, 0.5))),
        (0.75, member(Surface::Diffuse, Vec3::new(0.4, 0.6, 0.5))),
    ];
    let fallback = member(Surface::Diffuse, Vec3::ZERO);
    let (inside, simplified) = f.builder.add_mixture(mixture, fallback);
    assert_eq!(simplified, None);
    f.sphere(Vec3::ZERO, 1.0, inside, true);
    f.camera(Vec3::ZERO, Vec3::NEG_Z, 60f32.to_radians(), None, "centre");
    f.finish()
}

/// A diffuse square under a much larger parallel area light (see [`LIT_PLANE_HALF_SIZE`] and
/// the constants after it). The light is black, so the plane is lit once: its radiance is
/// [`lit_plane_radiance`]. The camera looks down at the plane from between the two.
pub fn lit_plane() -> Scene {
    lit_plane_under(LIT_PLANE_LIGHT_HALF_SIZE)
}

/// [`lit_plane`] with a square light of half-size `light_half_size` instead (its radiance:
/// [`square_light_radiance`]).
pub fn lit_plane_under(light_half_size: f32) -> Scene {
    let mut f = Fixture::new("testing::lit_plane");
    let plane = f.material("plane", Surface::Diffuse, Vec3::splat(LIT_PLANE_ALBEDO));
    let light = f.builder.add_material(Material {
        name: "light".into(),
        base_color: Vec3::ZERO,
        emission: Vec3::splat(LIT_PLANE_EMISSION),
        ..Material::default()
    });
    let square = |half: f32, y: f32| {
        [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]]
            .map(|[x, z]| Vec3::new(x * half, y, z * half))
    };
    f.quad(square(LIT_PLANE_HALF_SIZE, 0.0), plane, Vec3::Y);
    f.quad(
        square(light_half_size, LIT_PLANE_LIGHT_HEIGHT),
        light,
        Vec3::NEG_Y,
    );
    let eye = Vec3::new(0.0, 0.8, 0.8);
    f.camera(eye, -eye, 60f32.to_radians(), None, "above");
    f.finish()
}

/// The tangent of half the field of view of [`emitter_ahead`]'s camera: the film plane one
/// unit ahead of the eye spans ±this vertically (and horizontally, for square images).
pub const EMITTER_AHEAD_TAN_HALF_FOV: f32 = 0.25;

/// A lone emitting square of half-size `half`, radiance 1, `depth` ahead of a camera at the
/// origin that looks down −Z: its pinhole image is a square of half-size `half / depth` on
/// the film plane one unit ahead. Nothing else is there, so a camera ray sees radiance 1 where
/// it meets the square and 0 elsewhere, and photons leave at once: the image is the square as
/// the camera's rays cover it (a thin lens's blur, `render::lens`).
pub fn emitter_ahead(half: f32, depth: f32) -> Scene {
    let mut f = Fixture::new("testing::emitter_ahead");
    let light = f.builder.add_material(Material {
        name: "emitter".into(),
        base_color: Vec3::ZERO,
        emission: Vec3::ONE,
        ..Material::default()
    });
    let corners = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]]
        .map(|[x, y]| Vec3::new(x * half, y * half, -depth));
    f.quad(corners, light, Vec3::Z);
    let yfov = 2.0 * EMITTER_AHEAD_TAN_HALF_FOV.atan();
    f.camera(Vec3::ZERO, Vec3::NEG_Z, yfov, Some(1.0), "ahead");
    f.finish()
}

/// A diffuse square (see [`PUNCTUAL_PLANE_HALF_SIZE`]) lit by `lights` alone; nothing else
/// is there, so its radiance is the light's direct irradiance × ρ/π. The camera looks down at
/// it from above.
pub fn punctual_plane(lights: &[PunctualLight]) -> Scene {
    let mut f = Fixture::new("testing::punctual_plane");
    diffuse_square(&mut f);
    for light in lights {
        f.builder.add_punctual_light(*light).expect("a valid light");
    }
    let eye = Vec3::new(0.0, 2.0, 2.0);
    f.camera(eye, -eye, 60f32.to_radians(), None, "above");
    f.finish()
}

/// [`punctual_plane`]'s square at y = 0, facing +y, of albedo [`LIT_PLANE_ALBEDO`].
fn diffuse_square(f: &mut Fixture) {
    let plane = f.material("plane", Surface::Diffuse, Vec3::splat(LIT_PLANE_ALBEDO));
    let half = PUNCTUAL_PLANE_HALF_SIZE;
    let corners = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]]
        .map(|[x, z]| Vec3::new(x * half, 0.0, z * half));
    f.quad(corners, plane, Vec3::Y);
}

/// The tint of [`plane_in_a_mirror`]'s mirror.
pub const MIRROR_TINT: Vec3 = Vec3::new(0.9, 0.5, 0.2);

/// [`punctual_plane`]'s diffuse square (albedo [`LIT_PLANE_ALBEDO`], no light) seen only in a
/// mirror of tint [`MIRROR_TINT`] at every angle (no Fresnel rise: `Material::metal_edge` 0,
/// so what it shows is the tint times the plane's exactly): the camera at (0, 0.5, 2) looks along −z, with a 10°
/// field of view, at a square mirror centred at (0, 0.5, 0) and tilted 45° (normal
/// (0, −1, 1)/√2), which sends every camera ray straight down onto the plane.
pub fn plane_in_a_mirror() -> Scene {
    let mut f = Fixture::new("testing::plane_in_a_mirror");
    diffuse_square(&mut f);
    let mirror = f.builder.add_material(Material {
        name: "mirror".into(),
        surface: Surface::Mirror,
        base_color: MIRROR_TINT,
        metal_edge: Vec3::ZERO,
        ..Material::default()
    });
    let slope = Vec3::new(0.0, 1.0, 1.0).normalize() * 0.4;
    let centre = Vec3::new(0.0, 0.5, 0.0);
    let across = Vec3::new(0.4, 0.0, 0.0);
    let corners = [
        centre - across - slope,
        centre + across - slope,
        centre + across + slope,
        centre - across + slope,
    ];
    f.quad(corners, mirror, Vec3::new(0.0, -1.0, 1.0));
    f.camera(
        Vec3::new(0.0, 0.5, 2.0),
        Vec3::NEG_Z,
        10f32.to_radians(),
        None,
        "at the mirror",
    );
    f.finish()
}

/// [`punctual_plane`] under a layer of index-matched absorbing "water" `depth` deep: a solid
/// dielectric of ior 1 (no refraction, no reflection) with `absorption`, an open sheet the
/// plane's size facing up, so that the plane lies inside it (below its back face). Light
/// reaching the plane and leaving it loses exp(−absorption · length) over its way through the
/// layer, which the plane's own front face cannot tell (`render::medium`).
pub fn plane_under_water(depth: f32, absorption: Vec3) -> Scene {
    let mut f = Fixture::new("testing::plane_under_water");
    plane_and_water(&mut f, depth, absorption);
    let eye = Vec3::new(0.0, 2.0, 2.0);
    f.camera(eye, -eye, 60f32.to_radians(), None, "above");
    f.finish()
}

/// [`punctual_plane`]'s plane and [`plane_under_water`]'s layer over it.
fn plane_and_water(f: &mut Fixture, depth: f32, absorption: Vec3) {
    let plane = f.material("plane", Surface::Diffuse, Vec3::splat(LIT_PLANE_ALBEDO));
    let water = f.builder.add_material(Material {
        name: "index-matched water".into(),
        surface: Surface::Dielectric {
            ior: 1.0,
            thin_walled: false,
        },
        base_color: Vec3::ONE,
        absorption,
        ..Material::default()
    });
    let half = PUNCTUAL_PLANE_HALF_SIZE;
    let square = |y: f32| {
        [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]]
            .map(|[x, z]| Vec3::new(x * half, y, z * half))
    };
    f.quad(square(0.0), plane, Vec3::Y);
    f.quad(square(depth), water, Vec3::Y);
}

/// An underwater lamp: [`plane_under_water`] [`UNDERWATER_DEPTH`] deep with
/// [`UNDERWATER_ABSORPTION`], a point light of [`UNDERWATER_LAMP_INTENSITY`] candela
/// [`UNDERWATER_LAMP_HEIGHT`] above the plane's centre and the camera, both in the water:
/// paths from the lamp and from the camera start inside it (`render::medium::MediumLocator`),
/// so that the plane's radiance is ρ/π · I·h/r³ · exp(−σr) seen through
/// exp(−σ·distance to the eye).
pub fn underwater_lamp() -> Scene {
    let mut f = Fixture::new("testing::underwater_lamp");
    lamp_in_water(&mut f);
    f.finish()
}

/// [`underwater_lamp`]'s plane, water, lamp and camera.
fn lamp_in_water(f: &mut Fixture) {
    plane_and_water(f, UNDERWATER_DEPTH, UNDERWATER_ABSORPTION);
    f.builder
        .add_punctual_light(PunctualLight {
            kind: PunctualKind::Point,
            position: Vec3::new(0.0, UNDERWATER_LAMP_HEIGHT, 0.0),
            direction: Vec3::ZERO,
            intensity: Vec3::splat(UNDERWATER_LAMP_INTENSITY),
        })
        .expect("a valid light");
    // Looking slightly down: the plane below, the water's surface from beneath above.
    let eye = Vec3::new(0.0, 0.6, 0.8);
    f.camera(
        eye,
        Vec3::new(0.0, -0.15, -1.0),
        60f32.to_radians(),
        None,
        "under water",
    );
}

/// [`underwater_lamp`] with an invisible marble between the lamp and the plane: a solid
/// sphere ([`UNDERWATER_MARBLE_CENTRE`], [`UNDERWATER_MARBLE_RADIUS`]) of the water's own
/// index and absorption, its surface a different material inside the water's, so that the
/// plane's radiance is [`underwater_lamp`]'s. Light leaving the marble is in the water again
/// (`render::nesting`): a path that believed itself outside every solid there would cross the
/// water below the marble unabsorbed.
pub fn underwater_lamp_with_marble() -> Scene {
    let mut f = Fixture::new("testing::underwater_lamp_with_marble");
    lamp_in_water(&mut f);
    let marble = f.builder.add_material(Material {
        name: "invisible marble".into(),
        surface: Surface::Dielectric {
            ior: 1.0,
            thin_walled: false,
        },
        base_color: Vec3::ONE,
        absorption: UNDERWATER_ABSORPTION,
        ..Material::default()
    });
    f.sphere(
        UNDERWATER_MARBLE_CENTRE,
        UNDERWATER_MARBLE_RADIUS,
        marble,
        false,
    );
    f.finish()
}

/// [`underwater_lamp_with_marble`]'s marble.
pub const UNDERWATER_MARBLE_CENTRE: Vec3 = Vec3::new(0.0, 0.3, 0.0);
pub const UNDERWATER_MARBLE_RADIUS: f32 = 0.12;

/// [`underwater_lamp`]'s water depth, absorption, lamp height and intensity.
pub const UNDERWATER_DEPTH: f32 = 1.2;
pub const UNDERWATER_ABSORPTION: Vec3 = Vec3::new(0.8, 0.4, 0.2);
pub const UNDERWATER_LAMP_HEIGHT: f32 = 1.0;
pub const UNDERWATER_LAMP_INTENSITY: f32 = 2.0;

/// The radiance of [`plane_under_water`]'s plane (one channel's `absorption`) under a uniform
/// sky of radiance `sky`, seen from above the layer at `cos_view` from the vertical: sky light
/// reaching the plane at cosine μ crossed depth/μ of water, so its irradiance is
/// 2π·sky·∫₀¹ μ·exp(−τ/μ) dμ = 2π·sky·E₃(τ) with τ = absorption·depth, and the plane's
/// radiance ρ/π of that loses exp(−τ/cos_view) on its way up ([`diffuse_slab_transmittance`]
/// is 2·E₃).
pub fn plane_under_water_radiance(depth: f32, absorption: f32, sky: f32, cos_view: f32) -> f32 {
    let tau = absorption as f64 * depth as f64;
    let kept = (-tau / cos_view as f64).exp();
    (LIT_PLANE_ALBEDO as f64 * sky as f64 * diffuse_slab_transmittance(tau) * kept) as f32
}

/// [`cornell_box`] with four more lights: a point light in the middle of the room, a spot
/// under the ceiling pointing at the floor's back left, a directional light shining in
/// slantwise from above (onto the outside of the box), and a blue sky (seen past the box's
/// edges).
pub fn cornell_box_punctual() -> Scene {
    let mut scene = cornell_box();
    let lights = [
        PunctualLight {
            kind: PunctualKind::Point,
            position: Vec3::new(278.0, 274.0, 280.0),
            direction: Vec3::ZERO,
            intensity: Vec3::new(20_000.0, 30_000.0, 40_000.0),
        },
        PunctualLight {
            kind: PunctualKind::Spot {
                cos_inner: 20f32.to_radians().cos(),
                cos_outer: 35f32.to_radians().cos(),
                falloff: SpotFalloff::Gltf,
            },
            position: Vec3::new(400.0, 500.0, 300.0),
            direction: Vec3::new(-0.3, -1.0, 0.2).normalize(),
            intensity: Vec3::splat(50_000.0),
        },
        PunctualLight {
            kind: PunctualKind::Directional,
            position: Vec3::ZERO,
            direction: Vec3::new(0.3, -1.0, 0.5).normalize(),
            intensity: Vec3::splat(2.0),
        },
    ];
    let bounds = scene.bounds();
    for light in lights {
        scene.lights.add_punctual(light, bounds);
    }
    scene.lights.set_sky(Vec3::new(0.2, 0.3, 0.5), bounds);
    scene
}

/// [`cornell_caustics`] with a spot light high at the back aimed down through the glass
/// sphere, so that its caustic falls on the floor in front of the sphere: a point source's
/// caustic is sharp, and one no unidirectional path tracer can find (a camera path reaches the
/// spot's point through the glass with probability zero).
pub fn cornell_spot() -> Scene {
    let mut scene = cornell_caustics();
    let position = Vec3::new(250.0, 520.0, 480.0);
    let glass_centre = Vec3::new(180.0, 90.0, 170.0);
    let spot = PunctualLight {
        kind: PunctualKind::Spot {
            cos_inner: 10f32.to_radians().cos(),
            cos_outer: 18f32.to_radians().cos(),
            falloff: SpotFalloff::Gltf,
        },
        position,
        direction: (glass_centre - position).normalize(),
        intensity: Vec3::new(1_200_000.0, 1_080_000.0, 900_000.0),
    };
    let bounds = scene.bounds();
    scene.lights.add_punctual(spot, bounds);
    scene
}

/// The lit plane's outgoing radiance at (x, 0, z) (|x|, |z| ≤ [`LIT_PLANE_HALF_SIZE`]):
/// ρ·E/π with E the irradiance from the light. The light splits into four rectangles with a
/// corner straight above the point; each contributes π·Le times the form factor from a
/// differential area to a parallel rectangle over one of its corners (sides a, b, height h,
/// X = a/h, Y = b/h): F = 1/(2π) [X/√(1+X²) atan(Y/√(1+X²)) + Y/√(1+Y²) atan(X/√(1+Y²))].
pub fn lit_plane_radiance(x: f32, z: f32) -> f32 {
    square_light_radiance(x, z, LIT_PLANE_LIGHT_HALF_SIZE)
}

/// [`lit_plane_radiance`] under the light of [`lit_plane_under`].
pub fn square_light_radiance(x: f32, z: f32, light_half_size: f32) -> f32 {
    let corner = |a: f64, b: f64| {
        let h = LIT_PLANE_LIGHT_HEIGHT as f64;
        let (x, y) = (a / h, b / h);
        let (sx, sy) = ((1.0 + x * x).sqrt(), (1.0 + y * y).sqrt());
        (x / sx * (y / sx).atan() + y / sy * (x / sy).atan()) / (2.0 * std::f64::consts::PI)
    };
    let half = light_half_size as f64;
    let (x, z) = (x as f64, z as f64);
    let form_factor = corner(half - x, half - z)
        + corner(half + x, half - z)
        + corner(half - x, half + z)
        + corner(half + x, half + z);
    // E = π Le F and L = ρ E / π.
    (LIT_PLANE_ALBEDO as f64 * LIT_PLANE_EMISSION as f64 * form_factor) as f32
}

/// The Cornell data's floor, back wall, right (green) wall, left (red) wall, ceiling and light
/// corners, as published (the ceiling's corners listed from (0, 548.8, 0) to match the light's
/// order, which the ceiling's hole relies on).
#[rustfmt::skip]
const CORNELL_QUADS: [[[f32; 3]; 4]; 6] = [
    [[552.8, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 559.2], [549.6, 0.0, 559.2]],
    [[549.6, 0.0, 559.2], [0.0, 0.0, 559.2], [0.0, 548.8, 559.2], [556.0, 548.8, 559.2]],
    [[0.0, 0.0, 559.2], [0.0, 0.0, 0.0], [0.0, 548.8, 0.0], [0.0, 548.8, 559.2]],
    [[552.8, 0.0, 0.0], [549.6, 0.0, 559.2], [556.0, 548.8, 559.2], [556.0, 548.8, 0.0]],
    [[0.0, 548.8, 0.0], [556.0, 548.8, 0.0], [556.0, 548.8, 559.2], [0.0, 548.8, 559.2]],
    [[213.0, 548.8, 227.0], [343.0, 548.8, 227.0], [343.0, 548.8, 332.0], [213.0, 548.8, 332.0]],
];

/// The Cornell room without blocks: floor, ceiling with the light's hole, back, left (red)
/// and right (green) walls, the light, the camera. Returns the white material.
fn cornell_room(f: &mut Fixture) -> u32 {
    let white = f.material("white", Surface::Diffuse, CORNELL_WHITE);
    cornell_room_on(f, white, white);
    white
}

/// [`cornell_room`] with white walls of material `white` and a floor of `floor_material`.
fn cornell_room_on(f: &mut Fixture, white: u32, floor_material: u32) {
    let red = f.material("red", Surface::Diffuse, CORNELL_RED);
    let green = f.material("green", Surface::Diffuse, CORNELL_GREEN);
    let light = f.builder.add_material(Material {
        name: "light".into(),
        base_color: CORNELL_LIGHT_ALBEDO,
        emission: CORNELL_LIGHT_RADIANCE,
        ..Material::default()
    });
    let [floor, back, right, left, ceiling, lamp] = CORNELL_QUADS.map(|q| q.map(Vec3::from));
    f.quad(floor, floor_material, Vec3::Y);
    f.quad(back, white, Vec3::NEG_Z);
    f.quad(right, green, Vec3::X);
    f.quad(left, red, Vec3::NEG_X);
    // The ceiling as four trapezoids around the light: outer edge k to inner edge k.
    for k in 0..4 {
        let next = (k + 1) % 4;
        f.quad(
            [ceiling[k], ceiling[next], lamp[next], lamp[k]],
            white,
            Vec3::NEG_Y,
        );
    }
    f.quad(lamp, light, Vec3::NEG_Y);
    // The film is 25 mm × 25 mm at a focal length of 35 mm.
    let yfov = (2.0 * (12.5f64 / 35.0).atan()) as f32;
    let eye = Vec3::new(278.0, 273.0, -800.0);
    f.camera(eye, Vec3::Z, yfov, Some(1.0), "cornell");
}

/// Builds a fixture; every helper orients faces explicitly, whatever order corners come in.
struct Fixture {
    builder: SceneBuilder,
}

impl Fixture {
    fn new(name: &str) -> Self {
        Fixture {
            builder: SceneBuilder::new(Path::new(name)),
        }
    }

    fn material(&mut self, name: &str, surface: Surface, base_color: Vec3) -> u32 {
        self.builder.add_material(Material {
            name: name.into(),
            surface,
            base_color,
            ..Material::default()
        })
    }

    /// A camera looking along `forward` with +y up.
    fn camera(
        &mut self,
        eye: Vec3,
        forward: Vec3,
        yfov: f32,
        aspect_ratio: Option<f32>,
        name: &str,
    ) {
        let mut camera = Camera::look_at(eye, eye + forward, Vec3::Y, yfov)
            .expect("fixture cameras have a valid frame")
            .named(name);
        camera.aspect_ratio = aspect_ratio;
        self.builder.add_camera(camera);
    }

    /// A triangle whose front faces `facing`; shading normals are given or geometric (zero).
    fn triangle(&mut self, mut vertices: [Vertex; 3], material: u32, facing: Vec3) {
        let mut triangle = Triangle { vertices, material };
        if triangle.geometric_normal_unnormalized().dot(facing) < 0.0 {
            vertices.swap(1, 2);
            triangle.vertices = vertices;
        }
        self.builder
            .add_triangle(triangle)
            .expect("fixture geometry is finite");
    }

    /// A planar convex quad as two triangles (0, 1, 2) and (0, 2, 3), front facing `facing`.
    /// Clear solid glass of ior 1.5, named "glass".
    fn clear_glass(&mut self) -> u32 {
        let glass = Surface::Dielectric {
            ior: 1.5,
            thin_walled: false,
        };
        self.material("glass", glass, Vec3::ONE)
    }

    fn quad(&mut self, corners: [Vec3; 4], material: u32, facing: Vec3) {
        let v = corners.map(|position| Vertex {
            position,
            ..Vertex::default()
        });
        self.triangle([v[0], v[1], v[2]], material, facing);
        self.triangle([v[0], v[2], v[3]], material, facing);
    }

    /// A block standing on the floor: its top and four sides (its bottom is never seen).
    fn block(&mut self, footprint: [[f32; 2]; 4], height: f32, material: u32) {
        let at = |[x, z]: [f32; 2], y: f32| Vec3::new(x, y, z);
        let centre = footprint.iter().fold(Vec2::ZERO, |s, &c| s + Vec2::from(c)) / 4.0;
        self.quad(footprint.map(|c| at(c, height)), material, Vec3::Y);
        for k in 0..4 {
            let (a, b) = (footprint[k], footprint[(k + 1) % 4]);
            let outward = (Vec2::from(a) + Vec2::from(b)) / 2.0 - centre;
            let side = [at(a, 0.0), at(a, height), at(b, height), at(b, 0.0)];
            self.quad(side, material, Vec3::new(outward.x, 0.0, outward.y));
        }
    }

    /// A closed axis-aligned box from `min` to `max`, its six faces facing out.
    fn closed_box(&mut self, min: Vec3, max: Vec3, material: u32) {
        let centre = (min + max) / 2.0;
        for axis in 0..3 {
            for sign in [-1.0f32, 1.0] {
                let mut facing = Vec3::ZERO;
                facing[axis] = sign;
                let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
                let corner = |a: f32, b: f32| {
                    let mut p = centre;
                    p[axis] = if sign > 0.0 { max[axis] } else { min[axis] };
                    p[u] = if a > 0.0 { max[u] } else { min[u] };
                    p[v] = if b > 0.0 { max[v] } else { min[v] };
                    p
                };
                let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
                self.quad(corners.map(|(a, b)| corner(a, b)), material, facing);
            }
        }
    }

    /// A UV sphere with exact normals, facing outwards (or inwards, normals too).
    fn sphere(&mut self, centre: Vec3, radius: f32, material: u32, inward: bool) {
        let sign = if inward { -1.0 } else { 1.0 };
        // Trigonometry in f64, rounded once: the same f32 values on every platform's libm,
        // so the shipped glTF files regenerate byte for byte.
        let vertex = |ring: u32, segment: u32| {
            let theta = std::f64::consts::PI * ring as f64 / SPHERE_RINGS as f64;
            let phi =
                std::f64::consts::TAU * (segment % SPHERE_SEGMENTS) as f64 / SPHERE_SEGMENTS as f64;
            let direction = match ring {
                0 => Vec3::Y,
                r if r == SPHERE_RINGS => Vec3::NEG_Y,
                _ => glam::DVec3::new(
                    theta.sin() * phi.cos(),
                    theta.cos(),
                    theta.sin() * phi.sin(),
                )
                .as_vec3(),
            };
            Vertex {
                position: centre + radius * direction,
                normal: sign * direction,
                ..Vertex::default()
            }
        };
        for ring in 0..SPHERE_RINGS {
            for segment in 0..SPHERE_SEGMENTS {
                let [a, b] = [vertex(ring, segment), vertex(ring, segment + 1)];
                let [c, d] = [vertex(ring + 1, segment), vertex(ring + 1, segment + 1)];
                let outward = |t: [Vertex; 3]| {
                    sign * (t.iter().map(|v| v.position).sum::<Vec3>() / 3.0 - centre)
                };
                if ring > 0 {
                    self.triangle([a, b, d], material, outward([a, b, d]));
                }
                if ring + 1 < SPHERE_RINGS {
                    self.triangle([a, d, c], material, outward([a, d, c]));
                }
            }
        }
    }

    fn finish(self) -> Scene {
        self.builder.finish().expect("fixtures are valid scenes")
    }
}

/// A benchmark scene from the project's shared folder (`shared/scenes/` beside the repository,
/// or the folder `KOUSEN_SHARED_SCENES` names). Those files are not in the repository, so a
/// clean clone may lack them: `None` then, after printing a note, and the caller skips.
pub fn shared_scene(relative: &str) -> Option<PathBuf> {
    let workspace = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let folders = [
        std::env::var_os("KOUSEN_SHARED_SCENES").map(PathBuf::from),
        Some(workspace.join("../shared/scenes")),
        Some(PathBuf::from("/work/shared/scenes")),
    ];
    let found = folders
        .into_iter()
        .flatten()
        .map(|folder| folder.join(relative))
        .find(|path| path.is_file());
    if found.is_none() {
        println!("note: shared scene {relative} is absent; test skipped");
    }
    found
}

#[cfg(test)]
mod tests;

/// A small sky map for tests: a blue gradient above the horizon, a bright off-white sun one
/// texel wide at 28–39° from the zenith, and a warm ground below the horizon; 32 × 16 texels,
/// nothing about it symmetric in azimuth.
pub fn sunset_sky_map() -> crate::SkyMap {
    let (width, height) = (32u32, 16u32);
    let texels = (0..height)
        .flat_map(|y| (0..width).map(move |x| (x, y)))
        .map(|(x, y)| {
            if (x, y) == (21, 3) {
                Vec3::new(60.0, 50.0, 35.0)
            } else if y < height / 2 {
                let up = 1.0 - y as f32 / (height / 2) as f32;
                Vec3::new(0.3 + 0.2 * up, 0.5 + 0.2 * up, 0.9 + 0.3 * up)
                    * (1.0 + 0.3 * (x as f32 * 0.4).sin())
            } else {
                Vec3::new(0.4, 0.25, 0.1)
            }
        })
        .collect();
    crate::SkyMap::new(width, height, texels).expect("a valid sky map")
}

/// [`punctual_plane`] under [`sunset_sky_map`] scaled by `scale` and turned `rotation`
/// radians, and no other light. The plane's top sees only the upper hemisphere of the map, so
/// its radiance is albedo/π × `SkyMap::floor_irradiance` × `scale`.
pub fn plane_under_sky_map(scale: Vec3, rotation: f32) -> Scene {
    under_sky_map(punctual_plane(&[]), scale, rotation)
}

/// [`spheres_on_a_floor`] under [`sunset_sky_map`] turned 0.6 radians: refraction, glossy
/// reflection and the background seen past the floor all read the map.
pub fn spheres_under_sky_map() -> Scene {
    under_sky_map(spheres_on_a_floor(), Vec3::ONE, 0.6)
}

/// An open grey floor 4 wide with a glass sphere, a rough gold one and a white one on it, and
/// no light of its own: made to be lit by a sky (`kousen render --sky-map`), the shipped
/// `scenes/spheres-on-a-floor.gltf`. The camera looks down from above and aside, the horizon
/// in view.
pub fn spheres_on_a_floor() -> Scene {
    let mut f = Fixture::new("testing::spheres_on_a_floor");
    let floor = f.material("floor", Surface::Diffuse, Vec3::splat(LIT_PLANE_ALBEDO));
    let half = 2.0 * PUNCTUAL_PLANE_HALF_SIZE;
    let corners = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]]
        .map(|[x, z]| Vec3::new(x * half, 0.0, z * half));
    f.quad(corners, floor, Vec3::Y);
    let glass = f.clear_glass();
    let gold = f.material(
        "rough gold",
        Surface::RoughConductor { alpha: 0.3 * 0.3 },
        Vec3::new(0.95, 0.75, 0.4),
    );
    let white = f.material("white", Surface::Diffuse, Vec3::splat(0.8));
    f.sphere(Vec3::new(-0.35, 0.3, 0.1), 0.3, glass, false);
    f.sphere(Vec3::new(0.4, 0.25, -0.2), 0.25, gold, false);
    f.sphere(Vec3::new(0.25, 0.15, 0.5), 0.15, white, false);
    let eye = Vec3::new(0.3, 0.9, 2.4);
    f.camera(
        eye,
        Vec3::new(0.0, 0.25, 0.0) - eye,
        50f32.to_radians(),
        None,
        "above",
    );
    f.finish()
}

/// The sky map shipped as `scenes/skies/sunset.hdr` (`width` × `width`/2 texels): a blue sky
/// brightening to a warm horizon, a sun 5° across 20° above the horizon towards −Z turned 40°
/// to +X, and a dim brown ground. Written by `make_scenes`.
pub fn sunset_sky(width: u32) -> crate::SkyMap {
    let height = width / 2;
    let sun = {
        let (elevation, azimuth) = (20f32.to_radians(), 40f32.to_radians());
        Vec3::new(
            elevation.cos() * azimuth.sin(),
            elevation.sin(),
            -elevation.cos() * azimuth.cos(),
        )
    };
    let cos_sun = 2.5f32.to_radians().cos();
    let texels = (0..height)
        .flat_map(|y| (0..width).map(move |x| (x, y)))
        .map(|(x, y)| {
            let u = (x as f32 + 0.5) / width as f32;
            let v = (y as f32 + 0.5) / height as f32;
            let d = crate::sky_map::map_direction(u, v);
            if d.y < 0.0 {
                return Vec3::new(0.12, 0.09, 0.06);
            }
            let blue = Vec3::new(0.25, 0.45, 1.0) * (0.5 + 0.7 * d.y);
            let glow = Vec3::new(1.0, 0.55, 0.25) * (1.0 - d.y).powi(6);
            let sun_disc = if d.dot(sun) > cos_sun {
                Vec3::new(900.0, 700.0, 450.0)
            } else {
                Vec3::ZERO
            };
            blue + glow + sun_disc
        })
        .collect();
    crate::SkyMap::new(width, height, texels).expect("a valid sky map")
}

fn under_sky_map(mut scene: Scene, scale: Vec3, rotation: f32) -> Scene {
    let bounds = scene.bounds();
    let map = std::sync::Arc::new(sunset_sky_map());
    let sky = crate::Sky::with_map(map, scale, rotation, bounds);
    scene.lights.replace_sky(sky);
    scene
}
