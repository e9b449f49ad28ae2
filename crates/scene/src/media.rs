//! Homogeneous media inside solids, as Mitsuba's and pbrt's scene files give them (a shape's
//! interior medium), read as kousen's absorbing and scattering solids
//! (`Material::absorption`, `Material::scattering`): coloured glass, murky water, milk and
//! smoke in a glass, fog in a box whose walls light crosses unbent.
//!
//! A medium around the camera that no shape bounds (Mitsuba's sensor medium, pbrt's camera
//! medium) fills all space outside the solids: the scene's atmosphere (`Scene::atmosphere`),
//! a material no triangle uses, which paths outside every solid are in. As in Mitsuba and
//! pbrt, it reaches to infinity: of the light from infinitely far away, the sky's and
//! directional lights', it keeps nothing in the channels where it has any extinction
//! ([`Scene::dim_far_lights`]).

use glam::Vec3;

use crate::{Material, Scene, Surface};

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

    /// The material of an atmosphere of this medium (`Scene::atmosphere`): glass of index 1
    /// filled with it, which bends nothing where a path meets it.
    pub fn atmosphere(self) -> Material {
        let boundary = Material {
            name: "atmosphere".to_owned(),
            alpha: 0.0,
            ..Material::default()
        };
        self.fill(&boundary)
            .expect("an invisible boundary holds any medium")
    }
}

impl Scene {
    /// Per channel, whether light from infinitely far away crosses the atmosphere (1) or
    /// not (0): an atmosphere with any extinction in a channel keeps none of it over an
    /// infinite distance. All ones without an atmosphere.
    pub fn far_light_mask(&self) -> Vec3 {
        let Some(id) = self.atmosphere else {
            return Vec3::ONE;
        };
        let material = &self.materials[id as usize];
        let extinction = material.absorption + material.scattering;
        Vec3::select(extinction.cmpgt(Vec3::ZERO), Vec3::ZERO, Vec3::ONE)
    }

    /// Takes out of the sky and the directional lights what the atmosphere keeps from the
    /// scene ([`Scene::far_light_mask`]), with a warning (logged, naming the scene's file
    /// `path`, and kept in [`Scene::warnings`]) where that dims any.
    pub fn dim_far_lights(&mut self, path: &std::path::Path) {
        let mask = self.far_light_mask();
        if self.lights.dim_far_lights(mask) {
            let warning = "the medium around the camera reaches to infinity and hides the sky and directional lights where it has extinction, as in Mitsuba and pbrt: bound it with a shape to let them in";
            log::warn!("{}: {warning}", path.display());
            self.warnings.push(warning.to_owned());
        }
    }
}
