//! A material another renderer's scene file describes, as its loader reads it (Mitsuba's
//! BSDFs, pbrt's materials): one of kousen's materials, or a mixture of whole materials
//! (Mitsuba's `blendbsdf` and partial `principled`, pbrt's `mix`), with how the shapes
//! wearing it map their texture coordinates (`Uv`: each format's own).

use crate::media::Medium;
use crate::{Material, SceneBuilder};

/// A material read: `material`, and where it mixes materials the members with their
/// probabilities (`material` the first's; empty for one material: `SceneBuilder::add_mixture`).
pub(crate) struct Mapped<Uv> {
    pub material: Material,
    pub mixture: Vec<(f32, Material)>,
    /// How its textures map the shapes' texture coordinates, if they do.
    pub uv: Option<Uv>,
}

impl<Uv> Mapped<Uv> {
    pub fn plain(material: Material, uv: Option<Uv>) -> Mapped<Uv> {
        Mapped {
            material,
            mixture: Vec::new(),
            uv,
        }
    }

    /// A mixture (at least one member), a plain material where it has one member.
    pub fn mixed(mut mixture: Vec<(f32, Material)>, uv: Option<Uv>) -> Mapped<Uv> {
        let material = mixture[0].1.clone();
        if mixture.len() == 1 {
            mixture.clear();
        }
        Mapped {
            material,
            mixture,
            uv,
        }
    }

    /// The material and every member of its mixture.
    pub fn members_mut(&mut self) -> impl Iterator<Item = &mut Material> {
        std::iter::once(&mut self.material).chain(self.mixture.iter_mut().map(|(_, m)| m))
    }

    /// Adds it to `mixture` as a member of an outer mixture drawn with `probability`: itself,
    /// or its own members with their probabilities times that. Returns its texture mapping.
    pub fn spread_into(self, probability: f32, mixture: &mut Vec<(f32, Material)>) -> Option<Uv> {
        match self.mixture.is_empty() {
            true => mixture.push((probability, self.material)),
            false => {
                let members = self.mixture.into_iter();
                mixture.extend(members.map(|(q, m)| (probability * q, m)));
            }
        }
        self.uv
    }

    /// Fills it with `medium` (`Medium::fill`); false, leaving it as it was, where it is a
    /// mixture or its surface holds no medium.
    pub fn fill(&mut self, medium: Medium) -> bool {
        match medium.fill(&self.material) {
            Some(filled) if self.mixture.is_empty() => {
                self.material = filled;
                true
            }
            _ => false,
        }
    }

    /// Adds it to the scene: its id for triangles, its texture mapping and what the mixture
    /// lost in words (`SceneBuilder::add_mixture`).
    pub fn add_to(self, builder: &mut SceneBuilder) -> (u32, Option<Uv>, Option<&'static str>) {
        let (id, simplified) = match self.mixture.is_empty() {
            true => (builder.add_material(self.material), None),
            false => builder.add_mixture(self.mixture, self.material),
        };
        (id, self.uv, simplified)
    }
}
