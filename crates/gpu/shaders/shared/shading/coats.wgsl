// The coats over a surface: plastic's (render::plastic's tables, render::coats' grids under
// a metallic-roughness texture) and glTF's clear coat (render::clearcoat).

// ---- render::plastic ----
fn coat_reflectance(cos_view: f32, ior: f32) -> f32 {
    return fresnel_dielectric(abs(cos_view), 1.0 / ior);
}

fn coat_transmittance(cos_view: f32, ior: f32) -> f32 {
    return 1.0 - coat_reflectance(cos_view, ior);
}

// render::plastic::Coat::transmittance of the table in record `record` (a material, or a
// coat grid's node): cosines (i / (COAT_NODES − 1))², interpolated linearly, its two nodes
// read straight from the storage buffer (a copy of the table to index it cost lavapipe's
// plastic scenes ~14 %).
fn coat_table(record: u32, cos_view: f32) -> f32 {
    let node = table_node(cos_view, COAT_NODES);
    let j = node.i + 1u;
    let first = materials[record].coat_transmittance[node.i / 4u][node.i % 4u];
    let second = materials[record].coat_transmittance[j / 4u][j % 4u];
    return first * (1.0 - node.t) + second * node.t;
}

// Where cosine `cos` falls in a table of `count` nodes at cosines (i / (count − 1))²: the node
// below it and the weight of the one above (render::plastic::Coat::transmittance,
// render::sheen::SheenTable::albedo).
struct TableNode {
    i: u32,
    t: f32,
}

fn table_node(cos: f32, count: u32) -> TableNode {
    let x = sqrt(min(abs(cos), 1.0)) * f32(count - 1u);
    let i = min(u32(x), count - 2u);
    return TableNode(i, x - f32(i));
}

// render::coats::CoatGrid::at: the records of the rough nodes about width `alpha` of material
// `id`'s grid, and the weight of the second.
struct CoatNodes {
    lower: u32,
    upper: u32,
    t: f32,
}

fn coat_grid_nodes(id: u32, alpha: f32) -> CoatNodes {
    let first = materials[id].coat_grid_first + 1u;
    let last = materials[id].coat_grid_nodes - 1u;
    if last == 0u {
        return CoatNodes(first, first, 0.0);
    }
    let x = clamp((sqrt(alpha) - materials[id].coat_grid_roughness) / materials[id].coat_grid_step, 0.0, f32(last));
    let i = min(u32(x), last - 1u);
    return CoatNodes(first + i, first + i + 1u, x - f32(i));
}

// Whether material `id`'s coat follows a metallic-roughness texture (a grid of tables).
fn has_coat_grid(id: u32) -> bool {
    return ROUGHNESS_MAPS && materials[id].coat_grid_nodes > 0u;
}

// render::coats::Coats::at(id, ..).transmittance: the coat of material `id` at a hit where its
// width is `alpha` (mapped_material's): a smooth coat's 1 − F, a rough one's table, a mapped
// one's grid interpolated entry by entry, then in the cosine, as the CPU twin does.
fn coat_transmittance_of(id: u32, alpha: f32, cos_view: f32) -> f32 {
    if !ROUGH_COATS || alpha <= 0.0 {
        return coat_transmittance(cos_view, materials[id].ior);
    }
    if !has_coat_grid(id) {
        return coat_table(id, cos_view);
    }
    let nodes = coat_grid_nodes(id, alpha);
    let x = sqrt(min(abs(cos_view), 1.0)) * f32(COAT_NODES - 1u);
    let i = min(u32(x), COAT_NODES - 2u);
    let s = x - f32(i);
    let j = i + 1u;
    let t = nodes.t;
    let first = materials[nodes.lower].coat_transmittance[i / 4u][i % 4u] * (1.0 - t)
        + materials[nodes.upper].coat_transmittance[i / 4u][i % 4u] * t;
    let second = materials[nodes.lower].coat_transmittance[j / 4u][j % 4u] * (1.0 - t)
        + materials[nodes.upper].coat_transmittance[j / 4u][j % 4u] * t;
    return first * (1.0 - s) + second * s;
}

// render::plastic::Coat::diffuse_scale of the same coat.
fn coat_diffuse_scale_of(id: u32, alpha: f32) -> f32 {
    if !has_coat_grid(id) {
        return materials[id].coat_diffuse_scale;
    }
    if alpha <= 0.0 {
        return materials[materials[id].coat_grid_first].coat_diffuse_scale;
    }
    let nodes = coat_grid_nodes(id, alpha);
    return materials[nodes.lower].coat_diffuse_scale * (1.0 - nodes.t)
        + materials[nodes.upper].coat_diffuse_scale * nodes.t;
}

// ---- render::clearcoat ----
// clearcoat_reflectance: the share of light meeting a clear coat of `weight` at cosine `cos`
// that it reflects.
fn clearcoat_reflectance(weight: f32, cos: f32) -> f32 {
    return weight * fresnel_dielectric(abs(cos), 1.0 / CLEARCOAT_IOR);
}

// clearcoat_transmittance: 1 without a coat (weight 0).
fn clearcoat_transmittance(weight: f32, cos: f32) -> f32 {
    if !CLEARCOATS {
        return 1.0;
    }
    return 1.0 - clearcoat_reflectance(weight, cos);
}

// render::clearcoat::clearcoat_at (scene::Clearcoat::at): `material`'s coat where the hit's
// texture coordinates are `uv`, as (weight, GGX width).
struct Clearcoat {
    weight: f32,
    alpha: f32,
}

fn clearcoat_at(material: GpuMaterial, uv: vec2<f32>) -> Clearcoat {
    var weight_texel = 1.0;
    var roughness_texel = 1.0;
    if material.clearcoat_texture != NO_TEXTURE {
        weight_texel = sample_texture(material.clearcoat_texture, uv).x;
    }
    if material.clearcoat_roughness_texture != NO_TEXTURE {
        roughness_texel = sample_texture(material.clearcoat_roughness_texture, uv).y;
    }
    let scale = clamp(roughness_texel, 0.0, 1.0);
    var alpha = material.clearcoat_alpha * (scale * scale);
    if alpha < MIRROR_MAX_ROUGHNESS * MIRROR_MAX_ROUGHNESS {
        alpha = 0.0;
    }
    return Clearcoat(material.clearcoat * clamp(weight_texel, 0.0, 1.0), alpha);
}

// cpu::surface::clearcoat_bounce (render::clearcoat::clearcoat_event about the normal before
// the normal map, its numbers drawn as clearcoat_numbers does): `reflected` where the coat
// reflects the ray (weight 0 where the path ends), otherwise it passes to the surface beneath.
struct ClearcoatBounce {
    reflected: bool,
    bounce: Scattered,
}

fn clearcoat_bounce(coat: Clearcoat, surface_hit: SurfaceHit, incoming: vec3<f32>, rng: ptr<function, Rng>) -> ClearcoatBounce {
    var hit = surface_hit;
    hit.shading = surface_hit.interpolated;
    let u_choice = next_f32(rng);
    var u_micro = vec2<f32>(0.0);
    if coat.alpha > 0.0 {
        let u1 = next_f32(rng);
        let u2 = next_f32(rng);
        u_micro = vec2<f32>(u1, u2);
    }
    if u_choice >= clearcoat_reflectance(coat.weight, -dot(incoming, hit.shading)) {
        return ClearcoatBounce(false, Scattered(vec3<f32>(0.0), 0.0));
    }
    if coat.alpha == 0.0 {
        return ClearcoatBounce(true, Scattered(reflect_about(incoming, hit.shading), 1.0));
    }
    return ClearcoatBounce(true, rough_reflection(hit, incoming, coat.alpha, u_micro.x, u_micro.y));
}

// Whether some material wears glTF's specular layer; compiled out as MEDIA is.
override SPECULAR_LAYERS: bool = true;

// render::dielectric_layer::DielectricLayer: what lies on a dielectric's surface at a hit
// (plastic's coat, glass), glTF's specular layer
// (render::dielectric_layer::LayerReflectance: its reflectance head on and at grazing;
// specular_f90 < 0: none) and thin film.
struct DielectricLayer {
    specular_f0: vec3<f32>,
    specular_f90: f32,
    film: Film,
}

// render::dielectric_layer::DielectricLayer::default.
fn bare_dielectric_layer() -> DielectricLayer {
    return DielectricLayer(vec3<f32>(0.0), -1.0, no_film());
}

// cpu::surface::hit_dielectric_layer (scene::SpecularLayer::at).
fn hit_dielectric_layer(material: GpuMaterial, uv: vec2<f32>) -> DielectricLayer {
    var layer = bare_dielectric_layer();
    if SPECULAR_LAYERS && material.specular_layer != 0u {
        var colour = vec3<f32>(1.0);
        if material.specular_color_texture != NO_TEXTURE {
            colour = sample_texture(material.specular_color_texture, uv).xyz;
        }
        var strength = material.specular_factor;
        if material.specular_texture != NO_TEXTURE {
            strength *= sample_texture(material.specular_texture, uv).w;
        }
        layer.specular_f0 = min(material.specular_tinted_f0 * colour, vec3<f32>(1.0)) * strength;
        layer.specular_f90 = strength;
    }
    layer.film = hit_film(material, uv);
    return layer;
}

// render::dielectric_layer::DielectricLayer::is_bare.
fn dielectric_layer_is_bare(layer: DielectricLayer) -> bool {
    return !(SPECULAR_LAYERS && layer.specular_f90 >= 0.0) && !(IRIDESCENCE && layer.film.factor > 0.0);
}

// render::dielectric_layer::LayerReflectance::remap.
fn layer_reflectance_remap(f0: vec3<f32>, f90: f32, bare: f32, ior: f32) -> vec3<f32> {
    let bare_f0 = fresnel_dielectric(1.0, 1.0 / ior);
    let towards_grazing = clamp((bare - bare_f0) / (1.0 - bare_f0), 0.0, 1.0);
    return f0 + (vec3<f32>(f90) - f0) * towards_grazing;
}

// render::dielectric_layer::DielectricLayer::reflectance.
fn dielectric_layer_reflectance(layer: DielectricLayer, bare: f32, cos: f32, ior: f32) -> vec3<f32> {
    var scaled = vec3<f32>(bare);
    if SPECULAR_LAYERS && layer.specular_f90 >= 0.0 {
        scaled = layer_reflectance_remap(layer.specular_f0, layer.specular_f90, bare, ior);
    }
    if !IRIDESCENCE || layer.film.factor <= 0.0 {
        return scaled;
    }
    return film_mix(scaled, layer.film, min(abs(cos), 1.0), ior);
}

// render::dielectric_layer::DielectricLayer::diffuse_share.
fn coat_layer_diffuse_share(layer: DielectricLayer, diffuse_scale: f32, ior: f32) -> vec3<f32> {
    if !(SPECULAR_LAYERS && layer.specular_f90 >= 0.0) {
        return vec3<f32>(1.0);
    }
    let bare_mean = 1.0 - 1.0 / diffuse_scale;
    let layered_mean = layer_reflectance_remap(layer.specular_f0, layer.specular_f90, bare_mean, ior);
    return (1.0 - bare_mean) / (vec3<f32>(1.0) - layered_mean);
}

// render::dielectric_layer::DielectricLayer::transmission_share.
fn coat_layer_transmission(layer: DielectricLayer, ior: f32, cos: f32) -> vec3<f32> {
    if dielectric_layer_is_bare(layer) {
        return vec3<f32>(1.0);
    }
    let bare = coat_reflectance(cos, ior);
    return film_share(bare, dielectric_layer_reflectance(layer, bare, cos, ior), false);
}

// render::dielectric_layer::DielectricLayer::reflection_share.
fn coat_layer_reflection(layer: DielectricLayer, ior: f32, outgoing: vec3<f32>, incident: vec3<f32>) -> vec3<f32> {
    let sum = outgoing + incident;
    let length_sum = length(sum);
    if dielectric_layer_is_bare(layer) || !(length_sum > 0.0) {
        return vec3<f32>(1.0);
    }
    let cos = min(abs(dot(outgoing, sum / length_sum)), 1.0);
    let bare = coat_reflectance(cos, ior);
    return film_share(bare, dielectric_layer_reflectance(layer, bare, cos, ior), true);
}

// render::dielectric_layer::layered_dielectric.
fn layered_dielectric(fresnel: f32, layer: DielectricLayer, cos_incident_in: f32, ior: f32, from_outside: bool) -> vec3<f32> {
    if dielectric_layer_is_bare(layer) {
        return vec3<f32>(fresnel);
    }
    let cos_incident = clamp(cos_incident_in, 0.0, 1.0);
    var cos_outside = cos_incident;
    if !from_outside {
        let sin2_outside = ior * ior * (1.0 - cos_incident * cos_incident);
        if sin2_outside >= 1.0 {
            return vec3<f32>(1.0);
        }
        cos_outside = sqrt(1.0 - sin2_outside);
    }
    return dielectric_layer_reflectance(layer, fresnel, cos_outside, ior);
}

// render::dielectric_layer::rough_dielectric_layer_weight.
fn rough_dielectric_layer_weight(layer: DielectricLayer, view: vec3<f32>, out: vec3<f32>, normal: vec3<f32>, eta: f32, thin_walled: bool) -> vec3<f32> {
    if dielectric_layer_is_bare(layer) {
        return vec3<f32>(1.0);
    }
    let reflected = dot(out, normal) > 0.0;
    var micro = -(eta * view + out);
    if reflected {
        micro = view + out;
    } else if thin_walled {
        micro = view + out - 2.0 * dot(out, normal) * normal;
    }
    let length_micro = length(micro);
    if !(length_micro > 0.0) {
        return vec3<f32>(1.0);
    }
    micro = micro / length_micro;
    if dot(micro, normal) < 0.0 {
        micro = -micro;
    }
    let cos_view = clamp(dot(view, micro), 0.0, 1.0);
    var ior = eta;
    var from_outside = false;
    if thin_walled || eta <= 1.0 {
        ior = 1.0 / eta;
        from_outside = true;
    }
    var bare = fresnel_dielectric(cos_view, eta);
    var layered = layered_dielectric(bare, layer, cos_view, ior, from_outside);
    if thin_walled {
        bare = 2.0 * bare / (1.0 + bare);
        layered = 2.0 * layered / (vec3<f32>(1.0) + layered);
    }
    return film_share(bare, layered, reflected);
}
