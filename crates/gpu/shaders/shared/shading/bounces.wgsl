// How a path leaves a surface, by its kind: the Lambertian bounce, plastic's coat or base,
// the specular and rough directions, smooth glass's branches, and the tints films give them.

// cpu::surface::diffuse_bounce: weight 0 where it would go below the geometric surface.
fn diffuse_bounce(hit: SurfaceHit, u1: f32, u2: f32) -> Scattered {
    let next = cosine_direction(hit.shading, u1, u2);
    return Scattered(next, select(0.0, 1.0, dot(next, hit.geometric) > 0.0));
}

// cpu::surface::plastic_bounce (render::plastic::layered_coat_event): `base` true where the
// light passes the coat to the base, whose estimate it multiplies by `base_weight`; otherwise
// the coat's reflection (weight 0 where the path ends). `film_tint`: the coat's layer's share
// of the way taken (1 for a bare coat).
struct PlasticBounce {
    base: bool,
    base_weight: f32,
    coat: Scattered,
    film_tint: vec3<f32>,
}

fn plastic_bounce(material: GpuMaterial, hit: SurfaceHit, incoming: vec3<f32>, layer: DielectricLayer, u_choice: f32, u1: f32, u2: f32) -> PlasticBounce {
    let ior = material.ior;
    let alpha = material.roughness_alpha;
    let normal = hit.shading;
    let cos_view = -dot(incoming, normal);
    let none = Scattered(vec3<f32>(0.0), 0.0);
    if alpha == 0.0 {
        let chosen = coat_choice(layer, cos_view, ior);
        if u_choice < chosen.w {
            let tint = film_share(chosen.w, chosen.xyz, true);
            return PlasticBounce(false, 0.0, Scattered(reflect_about(incoming, normal), 1.0), tint);
        }
        let tint = film_share(chosen.w, chosen.xyz, false);
        return PlasticBounce(true, 1.0, none, tint);
    }
    let frame = frame_about(normal);
    let view = to_local(frame, -incoming);
    let through = coat_layer_transmission(layer, ior, cos_view);
    if view.z <= 0.0 {
        return PlasticBounce(true, 1.0, none, through);
    }
    let micro = sample_visible_normal(view, alpha, u1, u2);
    let chosen = coat_choice(layer, dot(view, micro), ior);
    if u_choice < chosen.w {
        let out = reflect_about(-view, micro);
        let weight = smith_g1(out, alpha);
        let next = to_world(frame, out);
        let tint = film_share(chosen.w, chosen.xyz, true);
        if weight <= 0.0 || dot(next, hit.geometric) <= 0.0 {
            return PlasticBounce(false, 0.0, none, tint);
        }
        return PlasticBounce(false, 0.0, Scattered(next, weight), tint);
    }
    return PlasticBounce(true, coat_transmittance_of(hit.material, alpha, cos_view) / (1.0 - chosen.w), none, through);
}

// render::plastic::layered_coat_event's choice at cosine `cos` to the (micro-)normal: each
// channel's reflectance (xyz) and the probability of reflecting (w), their mean under a
// layer, else the bare coat's Fresnel reflectance (whose way chosen keeps a film_share of
// exactly 1).
fn coat_choice(layer: DielectricLayer, cos: f32, ior: f32) -> vec4<f32> {
    let bare = coat_reflectance(cos, ior);
    if dielectric_layer_is_bare(layer) {
        return vec4<f32>(vec3<f32>(bare), bare);
    }
    let each = dielectric_layer_reflectance(layer, bare, cos, ior);
    return vec4<f32>(each, (each.x + each.y + each.z) / 3.0);
}

// cpu::surface::specular_direction; only called for non-diffuse surfaces other than plastic.
fn specular_direction(material: GpuMaterial, hit: SurfaceHit, incoming: vec3<f32>, layer: DielectricLayer, u: f32, u_second: f32, u_third: f32) -> Scattered {
    let normal = hit.shading;
    if material.surface == SURFACE_ROUGH_CONDUCTOR {
        if ANISOTROPY && any(hit.brush != vec3<f32>(0.0)) {
            return brushed_reflection(hit, incoming, material.roughness_alpha, u, u_second);
        }
        return rough_reflection(hit, incoming, material.roughness_alpha, u, u_second);
    }
    if material.surface == SURFACE_ROUGH_DIELECTRIC {
        return rough_dielectric(material, hit, incoming, u, u_second, u_third);
    }
    if material.surface == SURFACE_MIRROR {
        return Scattered(reflect_about(incoming, normal), 1.0);
    }
    let branches = dielectric_branches(material, hit, incoming, layer);
    if u < branches.reflectance {
        return Scattered(branches.reflected, 1.0);
    }
    return Scattered(branches.transmitted, 1.0);
}

// cpu::surface::DielectricBranches: reflected with probability `reflectance`, else
// transmitted (refracted; straight on through a thin-walled sheet; reflected at total
// internal reflection); under a layer (thin film, specular layer) each channel's share
// reflected is `layered_reflectance`.
struct DielectricBranches {
    reflectance: f32,
    layered_reflectance: vec3<f32>,
    reflected: vec3<f32>,
    transmitted: vec3<f32>,
}

// cpu::surface::dielectric_branches.
fn dielectric_branches(material: GpuMaterial, hit: SurfaceHit, incoming: vec3<f32>, layer: DielectricLayer) -> DielectricBranches {
    let normal = hit.shading;
    let thin_walled = (material.flags & MATERIAL_THIN_WALLED) != 0u;
    let eta = relative_eta(material.ior, hit.front, thin_walled);
    let cos_incident = -dot(incoming, normal);
    var reflectance = fresnel_dielectric(cos_incident, eta);
    let bare = dielectric_layer_is_bare(layer);
    var layered_reflectance = vec3<f32>(reflectance);
    if !bare {
        layered_reflectance = layered_dielectric(reflectance, layer, cos_incident, material.ior, hit.front || thin_walled);
    }
    if thin_walled {
        reflectance = 2.0 * reflectance / (1.0 + reflectance);
        layered_reflectance = 2.0 * layered_reflectance / (vec3<f32>(1.0) + layered_reflectance);
    }
    if !bare {
        reflectance = (layered_reflectance.x + layered_reflectance.y + layered_reflectance.z) / 3.0;
    }
    let reflected = reflect_about(incoming, normal);
    var transmitted = incoming;
    if !thin_walled {
        transmitted = refract_or_reflect(incoming, normal, eta);
    }
    return DielectricBranches(reflectance, layered_reflectance, reflected, transmitted);
}

// cpu::surface::DielectricBranches::weight.
fn branch_weight(branches: DielectricBranches, reflected: bool) -> vec3<f32> {
    return film_share(branches.reflectance, branches.layered_reflectance, reflected);
}

// cpu::surface::bounce_tint.
fn bounce_tint_of(material: GpuMaterial, tint: vec3<f32>, layer: DielectricLayer, hit: SurfaceHit, incoming: vec3<f32>, next: vec3<f32>) -> vec3<f32> {
    let bare = dielectric_layer_is_bare(layer);
    if material.surface == SURFACE_DIELECTRIC && !bare {
        let branches = dielectric_branches(material, hit, incoming, layer);
        return tint * branch_weight(branches, all(next == branches.reflected));
    }
    if material.surface == SURFACE_ROUGH_DIELECTRIC && !bare {
        let thin_walled = (material.flags & MATERIAL_THIN_WALLED) != 0u;
        let eta = relative_eta(material.ior, hit.front, thin_walled);
        return tint * rough_dielectric_layer_weight(layer, -incoming, next, hit.shading, eta, thin_walled);
    }
    return metal_bounce_tint(material, tint, layer.film, incoming, next);
}

// cpu::surface::eye_crossing_scale: an eye path's render::optics::eye_refraction_scale where
// `next` crosses a solid dielectric's surface; 1 for every other way on.
fn eye_crossing_scale(material: GpuMaterial, hit: SurfaceHit, next: vec3<f32>) -> f32 {
    let dielectric = material.surface == SURFACE_DIELECTRIC || material.surface == SURFACE_ROUGH_DIELECTRIC;
    let solid = (material.flags & MATERIAL_THIN_WALLED) == 0u;
    if dielectric && solid && dot(next, hit.geometric) < 0.0 {
        let eta = relative_eta(material.ior, hit.front, false);
        return eta * eta;
    }
    return 1.0;
}
