//! Mitsuba's `homogeneous` media inside solids, read as kousen's absorbing and scattering
//! solids (`Material::absorption`, `Material::scattering`): coloured glass, murky water, milk
//! and smoke in a glass, fog in a box of `null` walls.
//!
//! A shape's `interior` medium (inline `<medium name="interior">` or a `<ref name="interior">`
//! to a top-level one) fills the solid the shape bounds. Its extinction is `sigma_t` × `scale`,
//! of which `albedo` scatters (Mitsuba 0.6's `sigmaA` and `sigmaS` too), by the
//! Henyey–Greenstein phase function of its `phase`'s `g` (isotropic where none). The solid's
//! surface is its BSDF's: a smooth or rough `dielectric`; a `null` BSDF (a boundary light
//! crosses unbent) becomes glass of index 1. Interiors of other surfaces are warned about and
//! not read.
//!
//! The sensor's medium (`<ref name="medium">` or an inline `<medium>`) is where the camera
//! is: where a shape is filled with it, the camera's place in that solid says so already;
//! where none is, it fills all space outside the solids, the scene's atmosphere
//! (`Scene::atmosphere`, `crate::media`). A shape's `exterior` and a light's medium are
//! found from the geometry as well (the solid around them, `render::nesting`), so they are
//! read only as checks: one that is neither a filled solid's nor the atmosphere is warned
//! about.

use glam::Vec3;
use roxmltree::Node;

use super::Reader;
use super::properties::property;
use crate::SceneError;
use crate::media::Medium;

impl<'a> Reader<'a> {
    /// The `interior` medium of shape `node`, if it has one that kousen reads, and its
    /// element (for [`Reader::filled_with`]); an `exterior` one is kept for
    /// [`Reader::place_outside_media`].
    pub(super) fn interior_medium(
        &mut self,
        node: Node<'a, 'a>,
    ) -> Result<Option<(Medium, Node<'a, 'a>)>, SceneError> {
        let mut interior = None;
        let is_medium = |c: &Node| {
            c.has_tag_name("medium")
                || (c.has_tag_name("ref")
                    && matches!(c.attribute("name"), Some("interior" | "exterior")))
        };
        for child in node.children().filter(is_medium) {
            let role = child.attribute("name").unwrap_or("interior");
            let medium = match child.has_tag_name("ref") {
                true => self.referenced(child, "medium")?,
                false => child,
            };
            if let Some(id) = medium.attribute("id") {
                self.media_used.insert(id.to_string());
            }
            match role {
                "interior" => interior = Some(medium),
                _ => self.media_around.push((child, medium)),
            }
        }
        let Some(interior) = interior else {
            return Ok(None);
        };
        Ok(self.homogeneous(interior)?.map(|m| (m, interior)))
    }

    /// Notes that a shape is filled with `medium` (an interior that [`Reader::interior_medium`]
    /// returned and the shape's surface took).
    pub(super) fn filled_with(&mut self, medium: Node<'a, 'a>) {
        if let Some(id) = medium.attribute("id") {
            self.media_filled.insert(id.to_string());
        }
    }

    /// The medium a sensor or a light names among its children (`<medium>`, or a `<ref>` to
    /// one), if any; marked used.
    pub(super) fn endpoint_medium(
        &mut self,
        node: Node<'a, 'a>,
    ) -> Result<Option<(Node<'a, 'a>, Node<'a, 'a>)>, SceneError> {
        for child in node.children().filter(Node::is_element) {
            let medium = match child.tag_name().name() {
                "medium" => child,
                "ref" if (child.attribute("id")).is_some_and(|id| self.media.contains_key(id)) => {
                    self.referenced(child, "medium")?
                }
                _ => continue,
            };
            if let Some(id) = medium.attribute("id") {
                self.media_used.insert(id.to_string());
            }
            return Ok(Some((child, medium)));
        }
        Ok(None)
    }

    /// Once every shape is read: the sensor's medium becomes the scene's atmosphere where no
    /// shape is filled with it, and the media named around shapes and lights are checked
    /// against the solids and the atmosphere, which decide where kousen's paths are.
    pub(super) fn place_outside_media(&mut self) -> Result<(), SceneError> {
        let is_filled = |reader: &Self, medium: Node| {
            (medium.attribute("id")).is_some_and(|id| reader.media_filled.contains(id))
        };
        let mut atmosphere = None;
        if let Some(medium) = self.sensor_medium
            && !is_filled(self, medium)
            && let Some(fog) = self.homogeneous(medium)?
        {
            self.builder.set_atmosphere(fog);
            atmosphere = Some(medium);
        }
        let same = |a: Node, b: Node| match (a.attribute("id"), b.attribute("id")) {
            (Some(a), Some(b)) => a == b,
            _ => a == b,
        };
        for (reference, medium) in std::mem::take(&mut self.media_around) {
            if is_filled(self, medium) || atmosphere.is_some_and(|a| same(a, medium)) {
                continue;
            }
            let name = medium.attribute("id").unwrap_or("inline");
            self.warn(
                reference,
                format!("medium \"{name}\" fills no shape and is not the sensor's: not read (kousen places media by the shapes they fill and the sensor's)"),
            );
        }
        Ok(())
    }

    /// A `homogeneous` medium (`None`, warned, for any other kind).
    fn homogeneous(&mut self, node: Node<'a, 'a>) -> Result<Option<Medium>, SceneError> {
        let kind = self.context.required(node, "type")?;
        if kind != "homogeneous" {
            self.warn(
                node,
                format!("medium \"{kind}\" is not read (homogeneous only)"),
            );
            return Ok(None);
        }
        for name in ["albedo", "sigma_t", "sigma_a", "sigma_s"] {
            if property(node, name).is_some_and(|p| p.has_tag_name("volume")) {
                let message = format!("{name} given as a volume grid is not read");
                return Err(self.context.error(node, message));
            }
        }
        if property(node, "material").is_some() {
            self.warn(
                node,
                "a named medium material is not read: give sigma_t and albedo",
            );
        }
        let scale = self.float(node, "scale", 1.0)?;
        let (absorption, scattering) =
            if property(node, "sigma_a").is_some() || property(node, "sigma_s").is_some() {
                let absorption = self.colour(node, "sigma_a", Vec3::ZERO)?;
                let scattering = self.colour(node, "sigma_s", Vec3::ZERO)?;
                (absorption * scale, scattering * scale)
            } else {
                let extinction = self.colour(node, "sigma_t", Vec3::ONE)? * scale;
                let albedo = self.colour(node, "albedo", Vec3::splat(0.75))?;
                let scattering = extinction * albedo;
                (extinction - scattering, scattering)
            };
        let valid = |v: Vec3| v.is_finite() && v.min_element() >= 0.0;
        if !(valid(absorption) && valid(scattering)) {
            let message = format!(
                "absorption {absorption} and scattering {scattering} must be ≥ 0 (albedo in [0, 1])"
            );
            return Err(self.context.error(node, message));
        }
        Ok(Some(Medium {
            absorption,
            scattering,
            anisotropy: self.phase_anisotropy(node)?,
        }))
    }

    /// The Henyey–Greenstein `g` of a medium's `phase` (0: isotropic, or none).
    fn phase_anisotropy(&mut self, node: Node<'a, 'a>) -> Result<f32, SceneError> {
        let Some(phase) = node.children().find(|c| c.has_tag_name("phase")) else {
            return Ok(0.0);
        };
        match self.context.required(phase, "type")?.as_str() {
            "isotropic" => Ok(0.0),
            "hg" => {
                let g = self.float(phase, "g", 0.8)?;
                if !(-1.0 < g && g < 1.0) {
                    let message = format!("g {g} is not in (−1, 1)");
                    return Err(self.context.error(phase, message));
                }
                Ok(g)
            }
            other => {
                self.warn(phase, format!("phase \"{other}\" is read as isotropic"));
                Ok(0.0)
            }
        }
    }
}
