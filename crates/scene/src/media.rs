//! Homogeneous media inside solids, as Mitsuba's and pbrt's scene files give them (a shape's
//! interior medium), read as kousen's absorbing and scattering solids
//! (`Material::absorption`, `Material::scattering`): coloured glass, murky water, milk and
//! smoke in a glass, fog in a box whose walls light crosses unbent.

use glam::Vec3;

use crate::{Material, Surface};

/// A homogeneous medium as kousen's solids hold it, per unit of length and colour channel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Medium {
    pub absorption: Vec3,
    pub scattering: Vec3,
    pub anisotropy: f32,
}

impl Medium {
    /// `material` (a shape's) filled with the medium: solid glass keeps its surface, an
    /// invisible boundary (cut out everywhere: Mitsuba's `null`, pbrt's `interface`) becomes
    /// glass of index 1, which light crosses unbent; `None` for any other surface.
    pub fn fill(self, material: &Material) -> Option<Material> {
        let surface = match material.surface {
            Surface::Dielectric {
                thin_walled: false, ..
            }
            | Surface::RoughDielectric {
                thin_walled: false, ..
            } => material.surface,
            _ if material.alpha == 0.0 => Surface::Dielectric {
                ior: 1.0,
                thin_walled: false,
            },
            _ => return None,
        };
        Some(Material {
            surface,
            base_color: if material.alpha == 0.0 {
                Vec3::ONE
            } else {
                material.base_color
            },
            alpha: 1.0,
            alpha_mode: crate::AlphaMode::Opaque,
            absorption: self.absorption,
            scattering: self.scattering,
            scatter_anisotropy: self.anisotropy,
            name: format!("{} (filled)", material.name),
            ..material.clone()
        })
    }
}
