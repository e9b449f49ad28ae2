//! Blended materials (`scene::Blend`): which member surface a hit takes, and which member
//! keeps the photons that land on the blend. The kernels' twins (`blend_member`,
//! `blend_photon_member` in `shading.wgsl`) run the same arithmetic.

use scene::{MAX_BLEND_MEMBERS, Material};

/// The member of the blend starting at material `id` that a hit takes for a uniform `u`:
/// the chain's first material whose weight `u` falls under, `u` rescaled onto the rest of
/// the interval at each step, so one number decides the whole chain. `id` itself for a
/// material without a blend.
pub fn blend_member(materials: &[Material], id: u32, u: f32) -> u32 {
    let (mut id, mut u) = (id, u);
    for _ in 1..MAX_BLEND_MEMBERS {
        let Some(blend) = materials[id as usize].blend else {
            break;
        };
        if u < blend.weight {
            break;
        }
        u = (u - blend.weight) / (1.0 - blend.weight);
        id = blend.other;
    }
    id
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
            let member = blend_member(&materials, root, u);
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
        assert_eq!(blend_member(&materials, 0, 0.99), 0);
        assert_eq!(blend_photon_member(&materials, 0), 0);
    }
}
