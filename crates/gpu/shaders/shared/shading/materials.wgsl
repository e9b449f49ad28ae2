// The material a hit meets: a blend's member (render::blend), its surface under a
// metallic-roughness texture, and dispersive glass's index at the path's wavelength.

// The metallic-roughness texel at `uv` of the material whose hit is on `root` (its members
// share one texture, which the upload gives every member: GpuMaterial::roughness_texture), read
// once a hit for blend_member and mapped_material; white where none maps it.
fn roughness_texel(root: GpuMaterial, uv: vec2<f32>) -> vec4<f32> {
    if !ROUGHNESS_MAPS || root.roughness_texture == NO_TEXTURE {
        return vec4<f32>(1.0);
    }
    return sample_texture(root.roughness_texture, uv);
}

// render::blend::blend_member: the member of the blend starting at material `id` that a hit
// takes for a uniform `u`, which is rescaled onto the rest of its interval at each step; a
// textured metal's weight is multiplied by the hit's metalness (`texel`, roughness_texel).
// Materials without a blend have weight 1, so `u` always stops at them.
fn blend_member(id: u32, u: f32, texel: vec4<f32>, uv: vec2<f32>) -> u32 {
    var member = id;
    var rest = u;
    var weight = materials[id].blend_weight;
    if ROUGHNESS_MAPS && materials[id].roughness_lobe == ROUGHNESS_METAL {
        weight *= clamp(texel.z, 0.0, 1.0);
    }
    weight = transmission_weight(id, weight, uv);
    for (var i = 1u; i < MAX_BLEND_MEMBERS; i += 1u) {
        if rest < weight {
            break;
        }
        rest = (rest - weight) / (1.0 - weight);
        member = materials[member].blend_other;
        weight = transmission_weight(member, materials[member].blend_weight, uv);
    }
    return member;
}

// render::blend::transmission_weight: a glass member's weight scaled by its transmission
// texture's red at `uv`.
fn transmission_weight(member: u32, weight: f32, uv: vec2<f32>) -> f32 {
    if !TRANSMISSION_MAPS {
        return weight;
    }
    let texture = materials[member].transmission_texture;
    if texture == NO_TEXTURE {
        return weight;
    }
    let surface = materials[member].surface;
    let is_glass = surface == SURFACE_DIELECTRIC || surface == SURFACE_ROUGH_DIELECTRIC;
    if !is_glass || (materials[member].flags & MATERIAL_BLEND) == 0u {
        return weight;
    }
    return weight * clamp(sample_texture(texture, uv).x, 0.0, 1.0);
}

// render::blend::mapped_material (scene::RoughnessMap::surface): the member as a hit meets
// it, its surface (and GGX width) from the hit's metallic-roughness `texel` where one maps it.
fn mapped_material(material: GpuMaterial, texel: vec4<f32>) -> GpuMaterial {
    var mapped = material;
    if !ROUGHNESS_MAPS || material.roughness_lobe == ROUGHNESS_UNMAPPED {
        return mapped;
    }
    let roughness = clamp(material.roughness_factor * texel.y, 0.0, 1.0);
    // scene::RoughnessMap::keeps_lobe: no Lambertian however rough.
    let keeps_lobe = (material.flags & MATERIAL_KEEPS_LOBE) != 0u;
    if material.roughness_lobe == ROUGHNESS_METAL {
        // scene::metal_surface (scene::brushed_metal_surface for a brushed metal).
        if roughness < MIRROR_MAX_ROUGHNESS && ANISOTROPY && any(material.anisotropy != vec2<f32>(0.0)) {
            mapped.surface = SURFACE_ROUGH_CONDUCTOR;
            mapped.roughness_alpha = max(roughness * roughness, MIN_BRUSHED_ALPHA);
        } else if roughness < MIRROR_MAX_ROUGHNESS {
            mapped.surface = SURFACE_MIRROR;
            mapped.roughness_alpha = 0.0;
        } else if roughness < DIFFUSE_MIN_ROUGHNESS || keeps_lobe {
            mapped.surface = SURFACE_ROUGH_CONDUCTOR;
            mapped.roughness_alpha = roughness * roughness;
        } else {
            mapped.surface = SURFACE_DIFFUSE;
            mapped.roughness_alpha = 0.0;
        }
    } else if material.roughness_lobe == ROUGHNESS_GLASS {
        // scene::glass_surface (the member's index and walls kept).
        if roughness < MIRROR_MAX_ROUGHNESS {
            mapped.surface = SURFACE_DIELECTRIC;
            mapped.roughness_alpha = 0.0;
        } else {
            mapped.surface = SURFACE_ROUGH_DIELECTRIC;
            mapped.roughness_alpha = roughness * roughness;
        }
    } else if material.surface == SURFACE_PLASTIC {
        // scene::coated_surface (the member's index kept).
        if roughness >= DIFFUSE_MIN_ROUGHNESS && !keeps_lobe {
            mapped.surface = SURFACE_DIFFUSE;
            mapped.roughness_alpha = 0.0;
        } else if roughness < MIRROR_MAX_ROUGHNESS {
            mapped.roughness_alpha = 0.0;
        } else {
            mapped.roughness_alpha = roughness * roughness;
        }
    }
    return mapped;
}

// ---- render::dispersion ----
// Whether some glass disperses; compiled out as MEDIA is.
override DISPERSION: bool = true;

// render::dispersion::level_wavelength, from the scene's table (wavelength, then weight).
fn level_wavelength(level: u32) -> f32 {
    return scene_info.spectrum[level].x;
}

// render::dispersion::draws_wavelength, at glass only (cpu::surface::dispersed_surface).
fn draws_wavelength(material: GpuMaterial, wavelength: u32) -> bool {
    let glass = material.surface == SURFACE_DIELECTRIC || material.surface == SURFACE_ROUGH_DIELECTRIC;
    return DISPERSION && material.dispersion > 0.0 && glass && wavelength == WHOLE_SPECTRUM;
}

struct Dispersed {
    material: GpuMaterial,
    wavelength: u32,
    weight: vec3<f32>,
}

// cpu::surface::dispersed_surface (render::dispersion::disperse): glass, smooth or frosted, of
// the index of the path's wavelength, drawn with `u` where it carries the whole spectrum, the wavelength
// it keeps and the weight the throughput takes.
fn dispersed_material(material: GpuMaterial, wavelength: u32, u: f32) -> Dispersed {
    var out = Dispersed(material, wavelength, vec3<f32>(1.0));
    let glass = material.surface == SURFACE_DIELECTRIC || material.surface == SURFACE_ROUGH_DIELECTRIC;
    if !DISPERSION || material.dispersion <= 0.0 || !glass {
        return out;
    }
    if wavelength == WHOLE_SPECTRUM {
        out.wavelength = min(u32(u * f32(WAVELENGTH_LEVELS)), WAVELENGTH_LEVELS - 1u);
        out.weight = scene_info.spectrum[out.wavelength].yzw;
    }
    let lambda = level_wavelength(out.wavelength);
    out.material.ior = material.ior + material.dispersion * (523655.0 / (lambda * lambda) - 1.5168);
    return out;
}
