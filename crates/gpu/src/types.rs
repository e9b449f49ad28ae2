//! The structs the kernels read and write, `#[repr(C)]` and Pod, mirrored in
//! `shaders/shared/gpu_types.wgsl` and `shaders/kernels/raygen.wgsl` (checked by
//! `tests/layout.rs`), with the conversions from the CPU-side types.

use bytemuck::{Pod, Zeroable};
use glam::Vec3;

use bvh::bench_rays::BenchCamera;
use bvh::{Hit, PackedBvh, Ray};
use render::dispersion::WAVELENGTH_LEVELS;
use render::iridescence::FILM_WAVELENGTHS;
use scene::{AlphaMode, Material, Surface, TexturedLobe};

/// `GpuHit::triangle` of a ray that hit nothing.
pub const NO_HIT: u32 = u32::MAX;

/// The slab test's "missed" distance. WGSL may assume there are no infinities, so the kernels
/// use the largest finite f32 where the CPU twins use `f32::INFINITY`.
pub const NO_DISTANCE: f32 = f32::MAX;

/// The largest `t_max` a GPU ray carries (an unbounded ray's): half of [`NO_DISTANCE`], so
/// that widening a slab exit by `1 + 2γ₃` cannot overflow.
pub const RAY_T_MAX: f32 = render::buffers::RAY_T_MAX;

/// A ray for the kernels (32 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuRay {
    pub origin: [f32; 3],
    /// Hits count for `t` in `[0, t_max)`; 0 marks an unused slot.
    pub t_max: f32,
    pub direction: [f32; 3],
    pub pad: u32,
}

impl GpuRay {
    /// `ray` with an infinite `t_max` clamped to [`RAY_T_MAX`].
    pub fn from_ray(ray: &Ray) -> GpuRay {
        GpuRay {
            origin: ray.origin.to_array(),
            t_max: ray.t_max.min(RAY_T_MAX),
            direction: ray.direction.to_array(),
            pad: 0,
        }
    }

    /// The CPU ray, with [`RAY_T_MAX`] read back as infinite.
    pub fn to_ray(&self) -> Ray {
        Ray {
            origin: Vec3::from(self.origin),
            direction: Vec3::from(self.direction),
            t_max: if self.t_max >= RAY_T_MAX {
                f32::INFINITY
            } else {
                self.t_max
            },
        }
    }

    /// False for the unused slots ray generation leaves (t_max 0).
    pub fn is_used(&self) -> bool {
        self.t_max > 0.0
    }
}

/// A traversal's answer (16 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuHit {
    /// Distance of the hit; the ray's `t_max` on a miss.
    pub t: f32,
    /// Index into the packed triangles, [`NO_HIT`] on a miss.
    pub triangle: u32,
    pub u: f32,
    pub v: f32,
}

impl GpuHit {
    /// The CPU form: `None` on a miss.
    pub fn to_hit(&self) -> Option<Hit> {
        (self.triangle != NO_HIT).then_some(Hit {
            triangle: self.triangle,
            t: self.t,
            u: self.u,
            v: self.v,
        })
    }
}

/// The uploaded BVH's sizes and where the TBVH's threaded records start (16 bytes). Every
/// threading's records begin at its root, so no root is stored.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct SceneInfo {
    pub node_count: u32,
    pub triangle_count: u32,
    /// Index of the TBVH's first threaded record (after the six MTBVH sets).
    pub tbvh_record_base: u32,
    pub pad: u32,
    /// The wavelengths dispersive glass draws from (`render::dispersion::levels`): each
    /// level's wavelength, then its weight. Kernels index it straight from the storage
    /// buffer: a WGSL `const` table indexed at run time is copied per invocation, which made
    /// lavapipe's eye and photon kernels 40–70 % slower in dispersive scenes.
    pub spectrum: [[f32; 4]; WAVELENGTH_LEVELS as usize],
    /// The wavelengths a thin film's reflectance is summed over
    /// (`render::iridescence::film_spectrum`): each one's wavelength, then its weight.
    pub film_spectrum: [[f32; 4]; FILM_WAVELENGTHS],
}

impl SceneInfo {
    pub fn new(bvh: &PackedBvh) -> SceneInfo {
        let node_count = bvh.nodes.len() as u32;
        SceneInfo {
            node_count,
            triangle_count: bvh.triangles.len() as u32,
            tbvh_record_base: bvh::DIRECTION_COUNT as u32 * node_count,
            pad: 0,
            spectrum: std::array::from_fn(|level| {
                let level = render::dispersion::levels()[level];
                let [r, g, b] = level.weight.to_array();
                [level.wavelength, r, g, b]
            }),
            film_spectrum: std::array::from_fn(|i| {
                let (lambda, weight) = render::iridescence::film_spectrum()[i];
                let [r, g, b] = weight.to_array();
                [lambda, r, g, b]
            }),
        }
    }
}

/// `GpuMaterial::surface` values.
pub const SURFACE_DIFFUSE: u32 = 0;
pub const SURFACE_MIRROR: u32 = 1;
pub const SURFACE_DIELECTRIC: u32 = 2;
pub const SURFACE_ROUGH_CONDUCTOR: u32 = 3;
pub const SURFACE_ROUGH_DIELECTRIC: u32 = 4;
pub const SURFACE_PLASTIC: u32 = 5;
/// A texture index meaning "none".
pub const NO_TEXTURE: u32 = u32::MAX;
/// `GpuMaterial::flags` bits.
pub const MATERIAL_DOUBLE_SIDED: u32 = 1;
pub const MATERIAL_THIN_WALLED: u32 = 2;
/// A blend's first material (`scene::Blend`), whose hits draw a member.
pub const MATERIAL_BLEND: u32 = 4;
/// Paths crossing the surface go inside a volume (`scene::Material::bounds_volume`: solid
/// glass, or a translucent solid).
pub const MATERIAL_BOUNDS_VOLUME: u32 = 8;
/// Solid glass that scatters inside (`scene::Material::has_murky_glass`): photons walking in
/// it keep volume photons, eye paths end where they scatter (`render::scattering`); a
/// translucent solid scatters too but is not murky glass.
pub const MATERIAL_MURKY_GLASS: u32 = 16;
/// A mapped metal or coat that keeps its lobe however rough the texel
/// (`scene::RoughnessMap::keeps_lobe`).
pub const MATERIAL_KEEPS_LOBE: u32 = 32;
/// `GpuMaterial::roughness_lobe` values (`scene::TexturedLobe`, or none).
pub const ROUGHNESS_METAL: u32 = 0;
pub const ROUGHNESS_COATED: u32 = 1;
pub const ROUGHNESS_UNMAPPED: u32 = 2;
pub const ROUGHNESS_GLASS: u32 = 3;

/// One material (432 bytes), or a record of a mapped coat's grid (`GpuMaterial::coat_record`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuMaterial {
    pub base_color: [f32; 3],
    /// One of the `SURFACE_*` constants.
    pub surface: u32,
    pub emission: [f32; 3],
    /// Index of refraction (dielectrics and plastic's coat; 1 otherwise).
    pub ior: f32,
    pub base_color_texture: u32,
    pub emission_texture: u32,
    /// A hit is passed through where the base-colour texture's alpha is below this: glTF's
    /// `alpha < cutoff` with the constant alpha factor divided out (`cutoff / alpha`), so the
    /// kernel needs one comparison. Negative: opaque.
    pub alpha_cutoff: f32,
    /// `MATERIAL_*` bits.
    pub flags: u32,
    /// Beer–Lambert extinction inside a solid (solid glass or a translucent solid), per unit
    /// length: its absorption and scattering together (`Material::interior_extinction`; 0
    /// otherwise).
    pub absorption: [f32; 3],
    /// GGX width α (rough conductors, dielectrics and plastic coats; 0 otherwise).
    pub roughness_alpha: f32,
    /// A tangent-space normal map (`render::normal_map`), or `NO_TEXTURE`.
    pub normal_texture: u32,
    /// Multiplies the normal map's X and Y.
    pub normal_scale: f32,
    /// An emitter's light-sampling density per area (`render::emission::light_area_density`;
    /// 0 for others, and where the upload was not told).
    pub light_area_density: f32,
    /// Plastic: `render::plastic::Coat::diffuse_scale` (0 otherwise).
    pub coat_diffuse_scale: f32,
    /// A rough plastic coat's `render::plastic::Coat::transmittance_nodes`, four a row.
    pub coat_transmittance: [[f32; 4]; 4],
    /// A blend's probability of this material's own surface (`scene::Blend`); 1 for none.
    pub blend_weight: f32,
    /// The material a blend takes otherwise (itself for none).
    pub blend_other: u32,
    /// The member keeping photons that land on this material (`render::blend::
    /// blend_photon_member`; the upload sets it, itself where it was not told).
    pub blend_photon_member: u32,
    /// The solid this material lies in (`render::nesting::Nesting::exterior`), which a path
    /// leaving it through a back face enters; `render::medium::NO_MEDIUM` for none (the
    /// upload sets it).
    pub exterior: u32,
    /// Smooth solid glass's dispersion (`scene::Material::dispersion`; 0: none).
    pub dispersion: f32,
    /// The metallic-roughness texture of this material's blend (`scene::RoughnessMap`: its
    /// mapped members share one; the upload gives it every member, so the kernels read the
    /// texel once at the hit's first material), or `NO_TEXTURE`.
    pub roughness_texture: u32,
    /// glTF's `roughnessFactor` (of a mapped member).
    pub roughness_factor: f32,
    /// `ROUGHNESS_METAL`, `ROUGHNESS_COATED` or `ROUGHNESS_GLASS` for a mapped member,
    /// `ROUGHNESS_UNMAPPED` otherwise.
    pub roughness_lobe: u32,
    /// A mapped coat's `render::coats::CoatGrid`: the index in the materials buffer of its
    /// smooth coat's record, its rough nodes' records following (the upload sets it).
    pub coat_grid_first: u32,
    /// Its rough nodes (0: no grid).
    pub coat_grid_nodes: u32,
    /// `CoatGrid::first_roughness` and `roughness_step`.
    pub coat_grid_roughness: f32,
    pub coat_grid_step: f32,
    /// glTF's clear coat (`scene::Clearcoat`): its weight (0: none) and GGX width, and the
    /// textures scaling them (`NO_TEXTURE` for none).
    pub clearcoat: f32,
    pub clearcoat_alpha: f32,
    pub clearcoat_texture: u32,
    pub clearcoat_roughness_texture: u32,
    /// glTF's sheen (`render::sheen`): its colour (black: none) and Charlie width α, its
    /// table's albedo nodes four a row (`render::sheen::SheenTable`; the upload sets them),
    /// its colour and roughness textures (`NO_TEXTURE` for none), where the latter is given
    /// the index in the materials buffer of the grid's first table (`render::sheen::
    /// sheen_grid`, `SHEEN_GRID_NODES` records; the upload sets it), and its roughness.
    pub sheen_color: [f32; 3],
    pub sheen_alpha: f32,
    pub sheen_albedo: [[f32; 4]; 4],
    pub sheen_color_texture: u32,
    pub sheen_roughness_texture: u32,
    pub sheen_grid_first: u32,
    pub sheen_roughness: f32,
    /// The clear coat's own normal map (`scene::Clearcoat::normal_texture`; `NO_TEXTURE`
    /// for none) and its scale.
    pub clearcoat_normal_texture: u32,
    pub clearcoat_normal_scale: f32,
    /// glTF's transmission texture (`scene::Material::transmission_texture`), or
    /// `NO_TEXTURE`.
    pub transmission_texture: u32,
    /// glTF's diffuse transmission (`scene::DiffuseTransmission`): its strength texture
    /// (alpha channel), its colour, its factor (0: none) and its colour texture
    /// (`NO_TEXTURE` for none).
    pub diffuse_transmission_texture: u32,
    pub diffuse_transmission_color: [f32; 3],
    pub diffuse_transmission: f32,
    pub diffuse_transmission_color_texture: u32,
    /// glTF's anisotropy (`scene::Anisotropy`): its texture (`NO_TEXTURE` for none) and its
    /// brushing without a texture in the texture frame (`Anisotropy::base`; zero: none).
    pub anisotropy_texture: u32,
    pub anisotropy: [f32; 2],
    /// A translucent solid's or murky glass's scattering inside
    /// (`Material::interior_scattering`; zero: none) and its phase function's asymmetry
    /// (`render::scattering`).
    pub scattering: [f32; 3],
    pub scatter_anisotropy: f32,
    /// glTF's iridescence (`scene::Iridescence`): its factor (0: none), the film's index and
    /// its least and greatest thickness (nm), then its factor and thickness textures
    /// (`NO_TEXTURE` for none).
    pub iridescence: [f32; 4],
    pub iridescence_texture: u32,
    pub iridescence_thickness_texture: u32,
    /// glTF's specular layer on the dielectric (`scene::SpecularLayer`): its strength and
    /// colour textures (`NO_TEXTURE` for none), its tinted F0 and factor, and whether there is
    /// one (1; 0: none, the dielectric reflecting by its index alone).
    pub specular_texture: u32,
    pub specular_color_texture: u32,
    pub specular_tinted_f0: [f32; 3],
    pub specular_factor: f32,
    /// How far a metal's reflectance rises from its colour towards white at grazing angles
    /// (`scene::Material::metal_edge`, `render::conductor`).
    pub metal_edge: [f32; 3],
    pub specular_layer: u32,
}

impl GpuMaterial {
    /// `material` and its plastic `coat` (`render::coats::Coats::own`; the default for none).
    pub fn new(material: &Material, coat: &render::plastic::Coat) -> GpuMaterial {
        let (surface, ior, thin_walled, roughness_alpha) = match material.surface {
            Surface::Diffuse => (SURFACE_DIFFUSE, 1.0, false, 0.0),
            Surface::Mirror => (SURFACE_MIRROR, 1.0, false, 0.0),
            Surface::Dielectric { ior, thin_walled } => (SURFACE_DIELECTRIC, ior, thin_walled, 0.0),
            Surface::RoughConductor { alpha } => (SURFACE_ROUGH_CONDUCTOR, 1.0, false, alpha),
            Surface::RoughDielectric {
                ior,
                thin_walled,
                alpha,
            } => (SURFACE_ROUGH_DIELECTRIC, ior, thin_walled, alpha),
            Surface::Plastic { ior, alpha } => (SURFACE_PLASTIC, ior, false, alpha),
        };
        let alpha_cutoff = match material.alpha_mode {
            AlphaMode::Opaque => -1.0,
            AlphaMode::Mask { cutoff } if material.alpha > 0.0 => {
                (cutoff / material.alpha).min(f32::MAX)
            }
            AlphaMode::Mask { .. } => f32::MAX,
        };
        let nodes = coat.transmittance_nodes;
        let flag = |on: bool, bit: u32| if on { bit } else { 0 };
        let flags = flag(material.double_sided, MATERIAL_DOUBLE_SIDED)
            | flag(thin_walled, MATERIAL_THIN_WALLED)
            | flag(material.blend.is_some(), MATERIAL_BLEND)
            | flag(material.bounds_volume(), MATERIAL_BOUNDS_VOLUME)
            | flag(material.has_murky_glass(), MATERIAL_MURKY_GLASS)
            | flag(
                material.roughness_map.is_some_and(|m| m.keeps_lobe),
                MATERIAL_KEEPS_LOBE,
            );
        let map = material.roughness_map;
        GpuMaterial {
            base_color: material.base_color.to_array(),
            surface,
            emission: material.emission.to_array(),
            ior,
            base_color_texture: material.base_color_texture.unwrap_or(NO_TEXTURE),
            emission_texture: material.emission_texture.unwrap_or(NO_TEXTURE),
            alpha_cutoff,
            flags,
            absorption: material.interior_extinction().to_array(),
            roughness_alpha,
            normal_texture: material.normal_texture.unwrap_or(NO_TEXTURE),
            normal_scale: material.normal_scale,
            light_area_density: 0.0,
            coat_diffuse_scale: coat.diffuse_scale,
            coat_transmittance: std::array::from_fn(|row| {
                std::array::from_fn(|column| nodes[4 * row + column])
            }),
            blend_weight: material.blend.map_or(1.0, |b| b.weight),
            blend_other: material.blend.map_or(0, |b| b.other),
            blend_photon_member: 0,
            exterior: render::medium::NO_MEDIUM,
            dispersion: material.dispersion,
            roughness_texture: map.map_or(NO_TEXTURE, |m| m.texture),
            roughness_factor: map.map_or(0.0, |m| m.roughness_factor),
            roughness_lobe: match map.map(|m| m.lobe) {
                Some(TexturedLobe::Metal) => ROUGHNESS_METAL,
                Some(TexturedLobe::Coated) => ROUGHNESS_COATED,
                Some(TexturedLobe::Glass) => ROUGHNESS_GLASS,
                None => ROUGHNESS_UNMAPPED,
            },
            coat_grid_first: 0,
            coat_grid_nodes: 0,
            coat_grid_roughness: 0.0,
            coat_grid_step: 0.0,
            clearcoat: material.clearcoat.map_or(0.0, |c| c.weight),
            clearcoat_alpha: material.clearcoat.map_or(0.0, |c| c.alpha),
            clearcoat_texture: (material.clearcoat)
                .and_then(|c| c.weight_texture)
                .unwrap_or(NO_TEXTURE),
            clearcoat_roughness_texture: (material.clearcoat)
                .and_then(|c| c.roughness_texture)
                .unwrap_or(NO_TEXTURE),
            sheen_color: material.sheen.map_or([0.0; 3], |s| s.color.to_array()),
            sheen_alpha: material.sheen.map_or(0.0, |s| s.roughness * s.roughness),
            sheen_albedo: [[0.0; 4]; 4],
            sheen_color_texture: (material.sheen)
                .and_then(|s| s.color_texture)
                .unwrap_or(NO_TEXTURE),
            sheen_roughness_texture: (material.sheen)
                .and_then(|s| s.roughness_texture)
                .unwrap_or(NO_TEXTURE),
            sheen_grid_first: 0,
            sheen_roughness: material.sheen.map_or(0.0, |s| s.roughness),
            clearcoat_normal_texture: (material.clearcoat)
                .and_then(|c| c.normal_texture)
                .unwrap_or(NO_TEXTURE),
            clearcoat_normal_scale: material.clearcoat.map_or(1.0, |c| c.normal_scale),
            transmission_texture: material.transmission_texture.unwrap_or(NO_TEXTURE),
            diffuse_transmission_texture: (material.diffuse_transmission)
                .and_then(|t| t.texture)
                .unwrap_or(NO_TEXTURE),
            diffuse_transmission_color: (material.diffuse_transmission)
                .map_or([0.0; 3], |t| t.color.to_array()),
            diffuse_transmission: material.diffuse_transmission.map_or(0.0, |t| t.factor),
            diffuse_transmission_color_texture: (material.diffuse_transmission)
                .and_then(|t| t.color_texture)
                .unwrap_or(NO_TEXTURE),
            anisotropy: material
                .anisotropy
                .map_or([0.0; 2], |a| a.base().to_array()),
            anisotropy_texture: (material.anisotropy)
                .and_then(|a| a.texture)
                .unwrap_or(NO_TEXTURE),
            scattering: material.interior_scattering().to_array(),
            scatter_anisotropy: material.scatter_anisotropy,
            iridescence: material.iridescence.map_or([0.0; 4], |i| {
                [i.factor, i.ior, i.thickness_min, i.thickness_max]
            }),
            iridescence_texture: (material.iridescence)
                .and_then(|i| i.texture)
                .unwrap_or(NO_TEXTURE),
            iridescence_thickness_texture: (material.iridescence)
                .and_then(|i| i.thickness_texture)
                .unwrap_or(NO_TEXTURE),
            specular_texture: (material.specular)
                .and_then(|s| s.texture)
                .unwrap_or(NO_TEXTURE),
            specular_color_texture: (material.specular)
                .and_then(|s| s.color_texture)
                .unwrap_or(NO_TEXTURE),
            specular_tinted_f0: material
                .specular
                .map_or([0.0; 3], |s| s.tinted_f0.to_array()),
            specular_factor: material.specular.map_or(0.0, |s| s.factor),
            metal_edge: material.metal_edge.to_array(),
            specular_layer: material.specular.is_some() as u32,
        }
    }

    /// The albedo nodes of this material's sheen `table` (`render::sheen::SheenTable`).
    pub fn set_sheen_table(&mut self, table: &render::sheen::SheenTable) {
        self.sheen_alpha = table.alpha;
        self.sheen_albedo = std::array::from_fn(|row| {
            std::array::from_fn(|column| table.albedo_nodes[4 * row + column])
        });
    }

    /// A record holding one table of the sheen grid (after the scene's materials; no triangle
    /// refers to it): what `sheen_albedo` reads for a textured roughness.
    pub fn sheen_record(table: &render::sheen::SheenTable) -> GpuMaterial {
        let mut record = GpuMaterial::coat_record(&render::plastic::Coat::default());
        record.surface = SURFACE_DIFFUSE;
        record.sheen_color_texture = NO_TEXTURE;
        record.sheen_roughness_texture = NO_TEXTURE;
        record.set_sheen_table(table);
        record
    }
}

impl GpuMaterial {
    /// A record holding one of a mapped coat's tables (after the scene's materials; no
    /// triangle refers to it): what `coat_transmittance_of` and `coat_diffuse_scale_of` read.
    pub fn coat_record(coat: &render::plastic::Coat) -> GpuMaterial {
        let nodes = coat.transmittance_nodes;
        GpuMaterial {
            surface: SURFACE_PLASTIC,
            ior: coat.ior,
            roughness_alpha: coat.alpha,
            base_color_texture: NO_TEXTURE,
            emission_texture: NO_TEXTURE,
            normal_texture: NO_TEXTURE,
            roughness_texture: NO_TEXTURE,
            roughness_lobe: ROUGHNESS_UNMAPPED,
            alpha_cutoff: -1.0,
            exterior: render::medium::NO_MEDIUM,
            clearcoat_texture: NO_TEXTURE,
            clearcoat_roughness_texture: NO_TEXTURE,
            sheen_color_texture: NO_TEXTURE,
            sheen_roughness_texture: NO_TEXTURE,
            clearcoat_normal_texture: NO_TEXTURE,
            transmission_texture: NO_TEXTURE,
            diffuse_transmission_texture: NO_TEXTURE,
            diffuse_transmission_color_texture: NO_TEXTURE,
            anisotropy_texture: NO_TEXTURE,
            iridescence_texture: NO_TEXTURE,
            iridescence_thickness_texture: NO_TEXTURE,
            specular_texture: NO_TEXTURE,
            specular_color_texture: NO_TEXTURE,
            coat_diffuse_scale: coat.diffuse_scale,
            coat_transmittance: std::array::from_fn(|row| {
                std::array::from_fn(|column| nodes[4 * row + column])
            }),
            ..GpuMaterial::default()
        }
    }
}

/// The benchmark camera and what diffuse rays need (64 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct BenchCameraUniform {
    pub eye: [f32; 3],
    pub tan_half_fov: f32,
    pub forward: [f32; 3],
    pub side: u32,
    pub right: [f32; 3],
    /// The scene's bounding-box diagonal (diffuse ray origin offset).
    pub diagonal: f32,
    pub up: [f32; 3],
    pub ray_count: u32,
}

impl BenchCameraUniform {
    pub fn new(camera: &BenchCamera, diagonal: f32) -> BenchCameraUniform {
        BenchCameraUniform {
            eye: camera.eye.to_array(),
            tan_half_fov: camera.tan_half_fov,
            forward: camera.forward.to_array(),
            side: camera.side,
            right: camera.right.to_array(),
            diagonal,
            up: camera.up.to_array(),
            ray_count: camera.ray_count() as u32,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rays_round_trip_with_infinite_t_max_clamped() {
        let ray = Ray {
            origin: Vec3::new(1.0, 2.0, 3.0),
            direction: Vec3::new(0.0, -1.0, 0.0),
            t_max: f32::INFINITY,
        };
        let gpu = GpuRay::from_ray(&ray);
        assert_eq!(gpu.t_max, RAY_T_MAX);
        const { assert!(RAY_T_MAX * bvh::intersect::ROBUST_EXIT < NO_DISTANCE) };
        assert_eq!(gpu.to_ray(), ray);
        let short = Ray { t_max: 2.5, ..ray };
        assert_eq!(GpuRay::from_ray(&short).to_ray(), short);
    }

    #[test]
    fn materials_map_surface_alpha_and_flags() {
        let glass = Material {
            surface: Surface::Dielectric {
                ior: 1.5,
                thin_walled: true,
            },
            double_sided: true,
            ..Material::default()
        };
        let gpu = GpuMaterial::new(&glass, &Default::default());
        assert_eq!(gpu.surface, SURFACE_DIELECTRIC);
        assert_eq!(gpu.ior, 1.5);
        assert_eq!(gpu.flags, MATERIAL_DOUBLE_SIDED | MATERIAL_THIN_WALLED);
        assert!(gpu.alpha_cutoff < 0.0, "opaque");
        assert_eq!(gpu.base_color_texture, NO_TEXTURE);

        let leaves = Material {
            alpha: 0.5,
            alpha_mode: AlphaMode::Mask { cutoff: 0.25 },
            base_color_texture: Some(3),
            ..Material::default()
        };
        let gpu = GpuMaterial::new(&leaves, &Default::default());
        // alpha · texel < cutoff  ⇔  texel < cutoff / alpha
        assert_eq!(gpu.alpha_cutoff, 0.5);
        assert_eq!(gpu.base_color_texture, 3);
        assert_eq!(gpu.surface, SURFACE_DIFFUSE);

        // Solid glass and a translucent solid bound volumes; a translucent sheet does not.
        let solid_glass = Material {
            surface: Surface::Dielectric {
                ior: 1.5,
                thin_walled: false,
            },
            ..Material::default()
        };
        let translucent = |volume| Material {
            diffuse_transmission: scene::DiffuseTransmission::new(0.5, glam::Vec3::ONE)
                .map(|t| scene::DiffuseTransmission { volume, ..t }),
            ..Material::default()
        };
        for (material, bounds) in [
            (solid_glass.clone(), true),
            (translucent(true), true),
            (translucent(false), false),
        ] {
            let flags = GpuMaterial::new(&material, &Default::default()).flags;
            assert_eq!(flags & MATERIAL_BOUNDS_VOLUME != 0, bounds, "{material:?}");
        }

        // Solid glass that scatters is murky glass; a translucent solid that scatters is not.
        let scattering = |m: Material| Material {
            scattering: glam::Vec3::splat(0.5),
            ..m
        };
        for (material, murky) in [
            (scattering(solid_glass.clone()), true),
            (solid_glass, false),
            (scattering(translucent(true)), false),
        ] {
            let flags = GpuMaterial::new(&material, &Default::default()).flags;
            assert_eq!(flags & MATERIAL_MURKY_GLASS != 0, murky, "{material:?}");
        }
    }
}
