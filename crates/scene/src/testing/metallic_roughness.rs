//! A room whose floor and one sphere follow glTF's metallic-roughness texture
//! (`scene::RoughnessMap`): tiles of polished and brushed metal, glossy plastic and matte paint
//! in one material.

use glam::{Vec2, Vec3};

use super::{Fixture, cornell_room_on, spherical_uvs};
use crate::{
    Material, RoughnessMap, Scene, Surface, Texels, Texture, TextureRoughness, TexturedLobe,
    glass_surface, metal_surface,
};

/// Texels along a tile's side in [`metallic_roughness_tiles`].
pub const TILE_TEXELS: u32 = 16;
/// The tiles' (roughness, metalness) as 8-bit texel values (green, blue): polished metal (a
/// mirror), brushed metal (GGX α ≈ 0.063), glossy plastic (the same roughness under a coat of
/// ior 1.5) and matte paint (Lambertian).
pub const TILE_TEXELS_GREEN_BLUE: [(u8, u8); 4] = [(0, 255), (64, 255), (64, 0), (255, 0)];
/// The tiled material's base colour: brass, which its metal tiles reflect and its paint and
/// plastic tiles scatter.
pub const TILED_BASE_COLOR: Vec3 = Vec3::new(0.9, 0.72, 0.4);
/// Texture repeats across the floor (each holding 2 × 2 tiles of every kind).
pub const FLOOR_REPEATS: f32 = 2.0;

/// A metallic-roughness texture (linear data) of 4 × 4 tiles of [`TILE_TEXELS`]² texels of the
/// kinds of [`TILE_TEXELS_GREEN_BLUE`]: metal and non-metal alternating as a checkerboard, the
/// smooth kinds on even rows and the rough ones on odd rows.
pub fn metallic_roughness_tiles() -> Texture {
    let side = 4 * TILE_TEXELS;
    let texels = (0..side * side)
        .map(|i| {
            let (x, y) = (i % side / TILE_TEXELS, i / side / TILE_TEXELS);
            let kind = 2 * ((x + y) % 2) + y % 2;
            let (green, blue) = TILE_TEXELS_GREEN_BLUE[kind as usize];
            [0.0, f32::from(green) / 255.0, f32::from(blue) / 255.0, 1.0]
        })
        .collect();
    Texture {
        name: "metallic-roughness tiles".into(),
        width: side,
        height: side,
        texels: Texels::LinearF32(texels),
    }
}

/// [`super::cornell_caustics`]'s room whose floor and front-right sphere are one brass material
/// mapped by [`metallic_roughness_tiles`] (glTF: metallic 1, roughness 1, the texture's blue
/// and green channels saying where and how rough), made as the glTF loader makes it
/// (`SceneBuilder::add_textured_metal_blend`); a glass sphere back left mapped by the same
/// texture (glTF: transmission 1, metallic 0, roughness 1), clear where the tiles are polished
/// and frosted elsewhere (α 0.063 and 1). Texture coordinates: planar on the floor
/// ([`FLOOR_REPEATS`] across it), longitude and latitude on the spheres (4 × 2 repeats).
pub fn cornell_metallic_roughness() -> Scene {
    let mut f = Fixture::new("testing::cornell_metallic_roughness");
    let tiles = f.builder.add_texture(metallic_roughness_tiles());
    let roughness = TextureRoughness::of(f.builder.texture(tiles), 1.0, 1.0);
    let map = |lobe| RoughnessMap {
        texture: tiles,
        roughness_factor: 1.0,
        roughness_range: roughness.range,
        lobe,
        keeps_lobe: false,
    };
    let coat_roughness = roughness.coat.expect("plastic tiles");
    let coat = Surface::Plastic {
        ior: 1.5,
        alpha: coat_roughness * coat_roughness,
    };
    let base = Material {
        name: "brass tiles".into(),
        base_color: TILED_BASE_COLOR,
        ..Material::default()
    };
    let metal = (
        metal_surface(roughness.metal_mean),
        map(TexturedLobe::Metal),
    );
    let tiled = f.builder.add_textured_metal_blend(
        base,
        1.0,
        metal,
        &[(1.0, coat, Some(map(TexturedLobe::Coated)))],
    );
    let white = f.material("white", Surface::Diffuse, super::CORNELL_WHITE);
    cornell_room_on(&mut f, white, tiled);
    let glass_roughness = TextureRoughness::of(f.builder.texture(tiles), 1.0, 0.0).mean;
    let glass = f.builder.add_material(Material {
        name: "tiled glass".into(),
        surface: glass_surface(1.5, false, glass_roughness),
        base_color: Vec3::ONE,
        roughness_map: Some(map(TexturedLobe::Glass)),
        ..Material::default()
    });
    let front = Vec3::new(180.0, 90.0, 170.0);
    let back = Vec3::new(380.0, 110.0, 370.0);
    f.sphere(front, 90.0, tiled, false);
    f.sphere(back, 110.0, glass, false);
    let mut scene = f.finish();
    let floor_scale = FLOOR_REPEATS / 559.0;
    let sphere_uvs = |triangle: &mut crate::Triangle, centre| {
        spherical_uvs(triangle, centre);
        for v in &mut triangle.vertices {
            v.uv /= 3.0;
        }
    };
    for triangle in &mut scene.triangles {
        let centre = triangle.vertices.iter().map(|v| v.position).sum::<Vec3>() / 3.0;
        if triangle.material == glass {
            sphere_uvs(triangle, back);
        } else if triangle.material != tiled {
            continue;
        } else if centre.distance(front) > 100.0 {
            for v in &mut triangle.vertices {
                v.uv = Vec2::new(v.position.x, -v.position.z) * floor_scale;
            }
        } else {
            sphere_uvs(triangle, front);
        }
    }
    scene
}

/// The (roughness, metalness) 8-bit texel values (green, blue) of [`lit_plane_metallic_tiles`]:
/// a mirror, Lambertian, half mirror and half Lambertian, and metal so rough it is Lambertian.
pub const LIT_TILES_GREEN_BLUE: [(u8, u8); 4] = [(0, 255), (0, 0), (0, 128), (255, 255)];
/// Texels along a side of [`lit_plane_metallic_tiles`]' texture; 4 × 4 tiles of
/// [`TILE_TEXELS`]² texels.
const LIT_TILES_SIDE: u32 = 4 * TILE_TEXELS;

/// The tile kind (an index into [`LIT_TILES_GREEN_BLUE`]) at tile column `x`, row `y`.
fn lit_tile_kind(x: u32, y: u32) -> usize {
    ((x + 2 * y) % 4) as usize
}

/// The half-size of [`lit_plane_metallic_tiles`]' light: small enough that the plane's
/// Lambertian radiance (0.29 at the centre) is well below what its mirrors show (0.5), large
/// enough that a mirror anywhere in the view of a camera at height ½ reflects the light.
pub const LIT_TILES_LIGHT_HALF_SIZE: f32 = 1.5;

/// [`super::lit_plane_under`] a light of half-size [`LIT_TILES_LIGHT_HALF_SIZE`], whose plane
/// (albedo [`super::LIT_PLANE_ALBEDO`]) is glTF's metal where a metallic-roughness texture says
/// so and Lambertian elsewhere (a dielectric without a specular layer): tiles of
/// [`LIT_TILES_GREEN_BLUE`] mapped once over the plane (texture coordinates x + ½, z + ½).
/// Seen from above, a mirror reflects the light overhead, so its radiance is
/// [`lit_plane_metallic_tile_radiance`].
pub fn lit_plane_metallic_tiles() -> Scene {
    let mut scene = super::lit_plane_under(LIT_TILES_LIGHT_HALF_SIZE);
    let texels = (0..LIT_TILES_SIDE * LIT_TILES_SIDE)
        .map(|i| {
            let (x, y) = (i % LIT_TILES_SIDE, i / LIT_TILES_SIDE);
            let (green, blue) =
                LIT_TILES_GREEN_BLUE[lit_tile_kind(x / TILE_TEXELS, y / TILE_TEXELS)];
            [0.0, f32::from(green) / 255.0, f32::from(blue) / 255.0, 1.0]
        })
        .collect();
    let texture = scene.textures.len() as u32;
    scene.textures.push(Texture {
        name: "lit metallic tiles".into(),
        width: LIT_TILES_SIDE,
        height: LIT_TILES_SIDE,
        texels: Texels::LinearF32(texels),
    });
    let plane = scene.materials[0].clone();
    assert_eq!(
        plane.surface,
        Surface::Diffuse,
        "lit_plane's material 0 is its plane"
    );
    let roughness = TextureRoughness::of(&scene.textures[texture as usize], 1.0, 1.0);
    let metal = scene.materials.len() as u32;
    scene.materials.push(Material {
        surface: metal_surface(roughness.metal_mean),
        blend: Some(crate::Blend {
            weight: 1.0,
            other: metal + 1,
        }),
        roughness_map: Some(RoughnessMap {
            texture,
            roughness_factor: 1.0,
            roughness_range: roughness.range,
            lobe: TexturedLobe::Metal,
            keeps_lobe: false,
        }),
        ..plane.clone()
    });
    scene.materials.push(plane);
    for triangle in scene.triangles.iter_mut().filter(|t| t.material == 0) {
        triangle.material = metal;
        for v in &mut triangle.vertices {
            v.uv = Vec2::new(v.position.x + 0.5, v.position.z + 0.5);
        }
    }
    scene
}

/// [`lit_plane_metallic_tiles`]' radiance seen from straight above (x, 0, z), within 0.4 of
/// the centre both ways: a tile of metalness m (where its metal is a mirror) shows m × the
/// mirrored light (albedo × emission) and (1 − m) × the Lambertian plane's radiance
/// ([`super::square_light_radiance`]); the rough metal is Lambertian, as the rest.
/// `None` within `margin` (in the plane's units) of a tile's edge, where the texture's bilinear
/// filter blends two tiles.
pub fn lit_plane_metallic_tile_radiance(x: f32, z: f32, margin: f32) -> Option<f32> {
    let tile = 1.0 / 4.0;
    let (u, v) = (x + 0.5, z + 0.5);
    // The filter blends over one texel either side of an edge.
    let reach = margin + 1.0 / LIT_TILES_SIDE as f32;
    let near_edge = |t: f32| {
        let within = t.rem_euclid(tile);
        within < reach || tile - within < reach
    };
    if near_edge(u) || near_edge(v) {
        return None;
    }
    let kind = lit_tile_kind((u / tile) as u32 % 4, (v / tile) as u32 % 4);
    let (green, blue) = LIT_TILES_GREEN_BLUE[kind];
    let diffuse = super::square_light_radiance(x, z, LIT_TILES_LIGHT_HALF_SIZE);
    if green > 0 {
        return Some(diffuse);
    }
    let metalness = f32::from(blue) / 255.0;
    let mirrored = super::LIT_PLANE_ALBEDO * super::LIT_PLANE_EMISSION;
    Some(metalness * mirrored + (1.0 - metalness) * diffuse)
}
