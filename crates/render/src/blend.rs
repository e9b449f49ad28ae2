//! Blended materials (`scene::Blend`): which member surface a hit takes, and which member
//! keeps the photons that land on the blend; and where glTF's metallic-roughness texture maps
//! a material (`scene::RoughnessMap`), the member's weight and surface at the hit. The
//! kernels' twins (`blend_member`, `mapped_material` in `shading/materials.wgsl`) run the same
//! arithmetic.

use std::borrow::Cow;

use glam::Vec4;
use scene::{MAX_BLEND_MEMBERS, Material, Surface, TextureId};

/// The member of the blend starting at material `id` that a hit takes for a uniform `u`:
/// the chain's first material whose weight `u` falls under, `u` rescaled onto the rest of
/// the interval at each step, so one number decides the whole chain. `id` itself for a
/// material without a blend. `texel` reads the hit's textures: where the first material's
/// weight is a textured metal's ([`scene::RoughnessMap::blend_weight`]), and where a glass
/// member's weight is scaled by the transmission texture's red ([`transmission_weight`]).
pub fn blend_member(
    materials: &[Material],
    id: u32,
    u: f32,
    texel: impl Fn(TextureId) -> Vec4,
) -> u32 {
    let first = &materials[id as usize];
    let Some(blend) = first.blend else {
        return id;
    };
    let weight = match first.roughness_map {
        Some(map) => map.blend_weight(blend.weight, texel(map.texture)),
        None => blend.weight,
    };
    let mut weight = transmission_weight(first, weight, &texel);
    let (mut id, mut u) = (id, u);
    for _ in 1..MAX_BLEND_MEMBERS {
        let Some(blend) = materials[id as usize].blend else {
            break;
        };
        if u < weight {
            break;
        }
        u = (u - weight) / (1.0 - weight);
        id = blend.other;
        let member = &materials[id as usize];
        weight = transmission_weight(member, member.blend.map_or(1.0, |b| b.weight), &texel);
    }
    id
}

/// A blend member's `weight` at a hit whose textures read `texel`: a glass member's scaled by
/// its transmission texture's red (glTF's `transmissionTexture`), the others' as they are.
pub fn transmission_weight(
    member: &Material,
    weight: f32,
    texel: impl Fn(TextureId) -> Vec4,
) -> f32 {
    match member.transmission_texture {
        Some(texture) if member.blend.is_some() && member.surface.is_glass() => {
            weight * texel(texture).x.clamp(0.0, 1.0)
        }
        _ => weight,
    }
}

/// The surface a hit meets on `material` (a blend's member): its own, or where a
/// metallic-roughness texture maps it, the one the texel `texel` reads makes.
pub fn mapped_surface(material: &Material, texel: impl FnOnce(TextureId) -> Vec4) -> Surface {
    match material.roughness_map {
        Some(map) => {
            let brushed = material.anisotropy.is_some();
            map.surface(material.surface, texel(map.texture), brushed)
        }
        None => material.surface,
    }
}

/// `material` with [`mapped_surface`]: itself where no texture maps it (the hits of most
/// materials copy nothing).
pub fn mapped_material(
    material: &Material,
    texel: impl FnOnce(TextureId) -> Vec4,
) -> Cow<'_, Material> {
    if material.roughness_map.is_none() {
        return Cow::Borrowed(material);
    }
    Cow::Owned(Material {
        name: String::new(),
        surface: mapped_surface(material, texel),
        ..*material
    })
}

/// The metallic-roughness texture of the blend starting at material `id`: its first mapped
/// member's (`scene::SceneBuilder` gives all mapped members of a blend one texture), `None`
/// where no member is mapped.
pub fn roughness_texture(materials: &[Material], id: u32) -> Option<TextureId> {
    let mut id = id;
    for _ in 0..MAX_BLEND_MEMBERS {
        let material = &materials[id as usize];
        if let Some(map) = material.roughness_map {
            return Some(map.texture);
        }
        id = material.blend?.other;
    }
    None
}

/// The member that keeps photons landing on the blend starting at `id`: its last, the one
/// with a Lambertian lobe if any (`scene::SceneBuilder::add_blend` puts it there). Photons
/// are kept for it whichever member the photon's path then takes, since the eye paths that
/// gather them reached that member with its probability already.
pub fn blend_photon_member(materials: &[Material], id: u32) -> u32 {
    let mut id = id;
    for _ in 1..MAX_BLEND_MEMBERS {
        match materials[id as usize].blend {
            Some(blend) => id = blend.other,
            None => break,
        }
    }
    id
}

#[cfg(test)]
mod tests {
    use super::*;
    use scene::{SceneBuilder, Surface};
    use std::path::Path;

    fn three_members() -> (Vec<Material>, u32) {
        let mut builder = SceneBuilder::new(Path::new("blend"));
        builder.add_material(Material::default());
        let id = builder.add_blend(
            Material::default(),
            &[
                (0.2, Surface::Mirror),
                (0.3, Surface::RoughConductor { alpha: 0.1 }),
                (0.5, Surface::Diffuse),
            ],
        );
        (builder.materials().to_vec(), id)
    }

    /// A uniform `u` picks each member with its probability, the Lambertian member last.
    #[test]
    fn members_are_taken_with_their_probabilities() {
        let (materials, root) = three_members();
        let n = 100_000;
        let mut counts = [0u32; 3];
        for i in 0..n {
            let u = (i as f32 + 0.5) / n as f32;
            let member = blend_member(&materials, root, u, |_| Vec4::ONE);
            counts[(member - root) as usize] += 1;
        }
        let shares = counts.map(|c| c as f32 / n as f32);
        for (share, expected) in shares.iter().zip([0.2, 0.3, 0.5]) {
            assert!((share - expected).abs() < 1e-3, "{shares:?}");
        }
        assert_eq!(
            materials[(root + 2) as usize].surface,
            Surface::Diffuse,
            "the Lambertian member is not last"
        );
        assert_eq!(blend_photon_member(&materials, root), root + 2);
        // Not a blend: itself, whatever the number.
        assert_eq!(blend_member(&materials, 0, 0.99, |_| Vec4::ONE), 0);
        assert_eq!(blend_photon_member(&materials, 0), 0);
    }
}
