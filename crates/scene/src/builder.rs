//! Assembles a [`Scene`] while keeping its invariants; every loader goes through it.

use std::path::{Path, PathBuf};

use crate::{
    Blend, Camera, Lights, MAX_BLEND_MEMBERS, Material, PunctualKind, PunctualLight, RoughnessMap,
    Scene, SceneError, Surface, Texture, TextureId, TexturedLobe, Triangle,
};

pub struct SceneBuilder {
    path: PathBuf,
    scene: Scene,
    punctual_lights: Vec<PunctualLight>,
}

impl SceneBuilder {
    /// `path` names the file in errors.
    pub fn new(path: &Path) -> Self {
        SceneBuilder {
            path: path.to_path_buf(),
            scene: Scene::default(),
            punctual_lights: Vec::new(),
        }
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Fills all space outside the solids with `medium` (`Scene::atmosphere`), replacing any
    /// atmosphere set before; its material's id.
    pub fn set_atmosphere(&mut self, medium: crate::Medium) -> u32 {
        let id = self.add_material(medium.atmosphere());
        self.scene.atmosphere = Some(id);
        id
    }

    pub fn add_material(&mut self, material: Material) -> u32 {
        self.scene.materials.push(material);
        (self.scene.materials.len() - 1) as u32
    }

    /// Adds `base` as a mixture of `members`' surfaces, each with its probability (they are
    /// normalised to sum to 1), and returns the id triangles use ([`crate::Blend`]). Members
    /// of probability 0 are dropped and equal surfaces merged, so one left is a plain material.
    /// At most one member may have a Lambertian lobe; it goes last. `base.absorption` is kept
    /// by the solid dielectric member and by the first material, through whichever member a
    /// ray that ran inside meets.
    ///
    /// # Panics
    /// With no member of positive probability, more than [`MAX_BLEND_MEMBERS`] distinct
    /// surfaces, or two with Lambertian lobes: the loaders never ask for these.
    pub fn add_blend(&mut self, base: Material, members: &[(f32, Surface)]) -> u32 {
        let members: Vec<_> = members.iter().map(|&(p, s)| (p, s, None)).collect();
        self.add_mapped_blend(base, &members)
    }

    /// [`SceneBuilder::add_blend`] with members that may carry a [`RoughnessMap`] (members
    /// merge where surface and map are equal; mapped members share one texture, so that the
    /// kernels read one texel a hit: a panic otherwise).
    pub fn add_mapped_blend(
        &mut self,
        base: Material,
        members: &[(f32, Surface, Option<RoughnessMap>)],
    ) -> u32 {
        type Member = (f32, Surface, Option<RoughnessMap>);
        let mut distinct: Vec<Member> = Vec::new();
        for &(probability, surface, map) in members.iter().filter(|(p, ..)| *p > 0.0) {
            match distinct
                .iter_mut()
                .find(|(_, s, m)| *s == surface && *m == map)
            {
                Some((p, ..)) => *p += probability,
                None => distinct.push((probability, surface, map)),
            }
        }
        // The member with a Lambertian lobe last: the photon pass finds it at the chain's end.
        distinct.sort_by_key(|(_, surface, _)| surface.has_diffuse_lobe());
        assert!(
            !distinct.is_empty() && distinct.len() <= MAX_BLEND_MEMBERS,
            "a blend of {} surfaces",
            distinct.len()
        );
        assert!(
            distinct
                .iter()
                .filter(|(_, s, _)| s.has_diffuse_lobe())
                .count()
                <= 1,
            "a blend with two Lambertian lobes: {distinct:?}"
        );
        let mut textures = distinct
            .iter()
            .filter_map(|(.., map)| map.map(|m| m.texture));
        let texture = textures.next();
        assert!(
            textures.all(|t| Some(t) == texture),
            "a blend's mapped members with different textures"
        );
        let first = self.scene.materials.len() as u32;
        let mut left: f32 = distinct.iter().map(|(p, ..)| p).sum();
        let last = distinct.len() - 1;
        for (k, &(probability, surface, roughness_map)) in distinct.iter().enumerate() {
            let blend = (k < last).then(|| Blend {
                weight: (probability / left).clamp(f32::MIN_POSITIVE, 1.0 - f32::EPSILON),
                other: first + k as u32 + 1,
            });
            left -= probability;
            self.add_material(Material {
                surface,
                blend,
                roughness_map,
                ..base.clone()
            });
        }
        first
    }

    /// glTF's metal of probability `metallic` (in (0, 1]) whose metalness and roughness a
    /// texture maps (`metal`'s map, of [`TexturedLobe::Metal`]), blended with the
    /// `dielectric` members ([`SceneBuilder::add_mapped_blend`]): the metal first, its weight
    /// `metallic` multiplied per hit by the texel's metalness, so even 1 stays a blend. Returns
    /// the metal's id.
    ///
    /// # Panics
    /// Where `metallic` is outside (0, 1], the map is not a metal's, a dielectric member's map
    /// has another texture or the dielectric members are more than [`MAX_BLEND_MEMBERS`] − 1
    /// after merging.
    pub fn add_textured_metal_blend(
        &mut self,
        base: Material,
        metallic: f32,
        metal: (Surface, RoughnessMap),
        dielectric: &[(f32, Surface, Option<RoughnessMap>)],
    ) -> u32 {
        assert!(metallic > 0.0 && metallic <= 1.0, "metallic {metallic}");
        assert_eq!(metal.1.lobe, TexturedLobe::Metal);
        assert!(
            (dielectric.iter()).all(|(.., map)| map.is_none_or(|m| m.texture == metal.1.texture)),
            "a blend's mapped members with different textures"
        );
        let id = self.scene.materials.len() as u32;
        self.add_material(Material {
            surface: metal.0,
            blend: Some(Blend {
                weight: metallic,
                other: id + 1,
            }),
            roughness_map: Some(metal.1),
            ..base.clone()
        });
        self.add_mapped_blend(base, dielectric);
        let members = self.blend_length(id);
        assert!(
            members <= MAX_BLEND_MEMBERS,
            "a blend of {members} surfaces"
        );
        id
    }

    /// Adds a mixture of whole materials, each drawn with its probability (mixtures of other
    /// renderers' materials: pbrt's `mix`, Mitsuba's `blendbsdf`), and returns the id
    /// triangles use: a blend chain ([`crate::Blend`]) with its Lambertian-lobed member last,
    /// or one material. A blend holds one Lambertian-lobed member: several are read as one,
    /// the likeliest's surface in their mean colour; more than [`MAX_BLEND_MEMBERS`] members
    /// leave the likeliest alone. Either simplification is returned in words. `fallback` is
    /// added where no member has a probability.
    pub fn add_mixture(
        &mut self,
        mixture: Vec<(f32, Material)>,
        fallback: Material,
    ) -> (u32, Option<&'static str>) {
        let (mut lambertian, mut members): (Vec<_>, Vec<_>) = (mixture.into_iter())
            .filter(|(p, _)| *p > 0.0)
            .partition(|(_, m)| m.surface.has_diffuse_lobe());
        let mut simplified = None;
        lambertian.sort_by(|a, b| b.0.total_cmp(&a.0));
        if lambertian.len() > 1 {
            simplified = Some("a mix of diffuse materials is read as one, of their mean colour");
            let share: f32 = lambertian.iter().map(|(p, _)| p).sum();
            let weighted = lambertian.iter().map(|(p, m)| *p * m.base_color);
            let colour = weighted.sum::<glam::Vec3>() / share;
            lambertian.truncate(1);
            lambertian[0].0 = share;
            lambertian[0].1.base_color = colour;
        }
        members.extend(lambertian);
        if members.len() > MAX_BLEND_MEMBERS {
            simplified = Some("a mix of more materials than kousen blends: the likeliest drawn");
            members.sort_by(|a, b| b.0.total_cmp(&a.0));
            members.truncate(1);
        }
        match members.len() {
            0 => return (self.add_material(fallback), simplified),
            1 => return (self.add_material(members.remove(0).1), simplified),
            _ => {}
        }
        let first = self.scene.materials.len() as u32;
        let mut left: f32 = members.iter().map(|(p, _)| p).sum();
        let last = members.len() - 1;
        for (k, (probability, material)) in members.into_iter().enumerate() {
            let blend = (k < last).then(|| Blend {
                weight: (probability / left).clamp(f32::MIN_POSITIVE, 1.0 - f32::EPSILON),
                other: first + k as u32 + 1,
            });
            left -= probability;
            self.add_material(Material { blend, ..material });
        }
        (first, simplified)
    }

    /// How many materials the blend starting at `id` chains.
    fn blend_length(&self, id: u32) -> usize {
        let mut id = id as usize;
        let mut length = 1;
        while let Some(blend) = self.scene.materials[id].blend {
            id = blend.other as usize;
            length += 1;
        }
        length
    }

    /// A texture added so far.
    pub fn texture(&self, id: TextureId) -> &Texture {
        &self.scene.textures[id as usize]
    }

    pub fn materials(&self) -> &[Material] {
        &self.scene.materials
    }

    pub fn add_texture(&mut self, texture: Texture) -> TextureId {
        self.scene.textures.push(texture);
        (self.scene.textures.len() - 1) as TextureId
    }

    pub fn add_camera(&mut self, camera: Camera) {
        self.scene.cameras.push(camera);
    }

    /// Names the file's material variants (`Scene::variants`).
    pub fn set_variants(&mut self, names: Vec<String>) {
        self.scene.variants = names;
    }

    /// Lists one of the file's animations (`Scene::animations`).
    pub fn add_animation(&mut self, clip: crate::AnimationClip) {
        self.scene.animations.push(clip);
    }

    /// Adds a light without area. Its intensity must be finite and not negative, a spot's or
    /// directional light's direction finite and not zero (it is made unit length), a spot's
    /// cone cosines ordered `0 ≤ cos_outer < cos_inner ≤ 1`.
    pub fn add_punctual_light(&mut self, mut light: PunctualLight) -> Result<(), SceneError> {
        let error = |message: String| Err(SceneError::format(&self.path, message));
        if !(light.intensity.is_finite() && light.intensity.min_element() >= 0.0) {
            return error(format!(
                "light intensity {} is not finite and ≥ 0",
                light.intensity
            ));
        }
        if !light.position.is_finite() {
            return error(format!("non-finite light position {}", light.position));
        }
        if let PunctualKind::Spot {
            cos_inner,
            cos_outer,
            ..
        } = light.kind
            && !(0.0 <= cos_outer && cos_outer < cos_inner && cos_inner <= 1.0)
        {
            return error(format!(
                "spot light cone cosines {cos_inner} (inner) and {cos_outer} (outer) are not 0 ≤ outer < inner ≤ 1"
            ));
        }
        if light.kind != PunctualKind::Point {
            let Some(direction) = light.direction.try_normalize() else {
                return error(format!("light direction {} has no length", light.direction));
            };
            light.direction = direction;
        }
        self.punctual_lights.push(light);
        Ok(())
    }

    /// Records something the loader ignored; it is also logged.
    pub fn warn(&mut self, message: impl Into<String>) {
        let message = message.into();
        log::warn!("{}: {message}", self.path.display());
        self.scene.warnings.push(message);
    }

    pub fn triangle_count(&self) -> usize {
        self.scene.triangles.len()
    }

    /// Adds a triangle. Non-finite positions or texture coordinates are an error; a zero-area
    /// triangle is dropped and counted; a missing or non-finite shading normal becomes the
    /// geometric normal, and every normal is made unit length.
    pub fn add_triangle(&mut self, mut triangle: Triangle) -> Result<(), SceneError> {
        for v in &triangle.vertices {
            if !v.position.is_finite() {
                return Err(SceneError::format(
                    &self.path,
                    format!("non-finite vertex position {}", v.position),
                ));
            }
            if !v.uv.is_finite() {
                return Err(SceneError::format(
                    &self.path,
                    format!("non-finite texture coordinate {}", v.uv),
                ));
            }
        }
        let cross = triangle.geometric_normal_unnormalized();
        if !cross.is_finite() {
            return Err(SceneError::format(
                &self.path,
                "a triangle's coordinates are too large for 32-bit floats",
            ));
        }
        let Some(geometric) = cross.try_normalize() else {
            self.scene.degenerate_dropped += 1;
            return Ok(());
        };
        for v in &mut triangle.vertices {
            v.normal = v.normal.try_normalize().unwrap_or(geometric);
        }
        self.scene.triangles.push(triangle);
        Ok(())
    }

    /// Checks references, collects the lights, and refuses a scene without triangles.
    pub fn finish(mut self) -> Result<Scene, SceneError> {
        let scene = &mut self.scene;
        if scene.triangles.is_empty() {
            let detail = if scene.degenerate_dropped > 0 {
                format!(
                    " (all {} were degenerate and dropped)",
                    scene.degenerate_dropped
                )
            } else {
                String::new()
            };
            return Err(SceneError::NoTriangles {
                path: self.path,
                detail,
            });
        }
        let material_count = scene.materials.len() as u32;
        if let Some(t) = scene
            .triangles
            .iter()
            .find(|t| t.material >= material_count)
        {
            return Err(SceneError::format(
                &self.path,
                format!("material index {} out of range", t.material),
            ));
        }
        let texture_count = scene.textures.len() as u32;
        for m in &scene.materials {
            let ids = [m.base_color_texture, m.emission_texture];
            if ids.iter().flatten().any(|&id| id >= texture_count) {
                return Err(SceneError::format(
                    &self.path,
                    format!("material {:?} refers to a missing texture", m.name),
                ));
            }
        }
        scene.lights = Lights::collect(
            &scene.triangles,
            &scene.materials,
            &scene.textures,
            &self.punctual_lights,
        );
        Ok(self.scene)
    }
}
