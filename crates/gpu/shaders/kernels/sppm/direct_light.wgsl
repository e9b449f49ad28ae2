// Direct light at an eye path's hit (cpu::kernels::direct_light): the lobes a light sample
// serves, its shadow ray, and the MIS weights of emission met after a glossy bounce.

// cpu::surface::unoccluded: nothing but alpha cut-outs' holes on the segment. The CPU tests
// each hit's alpha inside its any-hit traversal; here the closest hit is found and passed
// through, hole after hole: the same answer (tested), and through lavapipe texture sampling
// inside the traversal loop made eye passes 15 % slower (docs/BENCHMARKS.md §3, session 12).
fn unoccluded(origin_in: vec3<f32>, direction: vec3<f32>, distance_in: f32) -> bool {
    if params.cut_outs == 0u {
        return trace_mtbvh(GpuRay(origin_in, distance_in, direction, 0u), true).triangle == NO_HIT;
    }
    var origin = origin_in;
    var distance = distance_in;
    for (var i = 0u; i <= MAX_PASS_THROUGHS; i++) {
        let hit = trace_surface_within(origin, direction, distance);
        if !hit.found {
            return true;
        }
        if !is_cut_out(materials[hit.material], hit.uv) {
            return false;
        }
        origin = hit.position + params.epsilon * direction;
        distance -= hit.distance + params.epsilon;
        if distance <= 0.0 {
            return true;
        }
    }
    return false;
}

// cpu::kernels::LitLobes: the lobes one light sample at an eye path's hit serves, with their
// weights (zero for a lobe that is not there). `alpha`, `coat_ior` and `refraction_eta` are
// its render::microfacet::GlossyLobe (`coat_ior` its fresnel_ior), `coat_ior` also telling a
// coat over the Lambertian lobe (LitLobes::coated): where both lobes are there they share it;
// the coat's width for its tables is `coat_alpha`, kept where the glossy lobe is not sampled.
struct LitLobes {
    diffuse: vec3<f32>,
    glossy: vec3<f32>,
    alpha: f32,
    coat_ior: f32,
    refraction_eta: f32,
    sheet_eta: f32,
    // glTF's clear coat over both lobes (its weight; 0: none), which the light passes on its
    // way in.
    clearcoat: f32,
    // The glossy lobe is glTF's sheen (render::microfacet::GlossyLobe::sheen) of width alpha.
    sheen_lobe: bool,
    // glTF's sheen over both lobes (colour black: none), which the light passes too.
    sheen: Sheen,
    coat_alpha: f32,
    // render::microfacet::GlossyLobe::brush: a brushed metal's brushing (zero: isotropic).
    brush: vec3<f32>,
    // cpu::kernels::LitLobes::metal: a rough-metal lobe's metal (`metal` false: none;
    // `glossy` then leaves its colour out): its colour, edge and thin film (factor 0: none).
    metal: bool,
    metal_f0: vec3<f32>,
    metal_edge: vec3<f32>,
    film: Film,
    // cpu::kernels::LitLobes::dielectric_layer: frosted glass's layer (thin film, specular
    // layer; bare: none).
    dielectric_layer: DielectricLayer,
    // cpu::kernels::LitLobes::coat's layer: what lies on plastic's coat (bare elsewhere).
    coat_layer: DielectricLayer,
}

// render::microfacet::GlossyLobe::facing.
fn lit_facing(lit: LitLobes, hit: SurfaceHit) -> vec3<f32> {
    if FROSTED_GLASS && (lit.refraction_eta > 0.0 || lit.sheet_eta > 0.0) {
        return -hit.shading;
    }
    return hit.shading;
}

// render::microfacet::GlossyLobe::response.
fn lit_glossy_lobe(lit: LitLobes, hit: SurfaceHit, outgoing: vec3<f32>, incident: vec3<f32>) -> GlossyResponse {
    if SHEENS && lit.sheen_lobe {
        return sheen_response(outgoing, incident, hit.shading, lit.alpha);
    }
    if FROSTED_GLASS && lit.refraction_eta > 0.0 {
        var response = refraction_response(outgoing, incident, hit.shading, lit.alpha, lit.refraction_eta);
        // Light refracting out towards the eye inside (render::optics::eye_refraction_scale).
        response.value *= lit.refraction_eta * lit.refraction_eta;
        return response;
    }
    if FROSTED_GLASS && lit.sheet_eta > 0.0 {
        return sheet_response(outgoing, incident, hit.shading, lit.alpha, lit.sheet_eta);
    }
    if ANISOTROPY && any(lit.brush != vec3<f32>(0.0)) {
        return brushed_response(outgoing, incident, hit.shading, lit.brush, lit.alpha);
    }
    return glossy_response(outgoing, incident, hit.shading, lit.alpha, lit.coat_ior);
}

fn is_lit(lit: LitLobes) -> bool {
    return max3(lit.diffuse) > 0.0 || (lit.alpha > 0.0 && max3(lit.glossy) > 0.0);
}

// cpu::kernels::LitLobes::response.
fn lit_response(lit: LitLobes, hit: SurfaceHit, outgoing: vec3<f32>, incident: vec3<f32>, light_pdf: f32) -> vec3<f32> {
    let cosine = dot(incident, hit.shading);
    var response = vec3<f32>(0.0);
    if max3(lit.diffuse) > 0.0 {
        var coat = vec3<f32>(1.0);
        if lit.coat_ior > 0.0 {
            let layer = coat_layer_transmission(lit.coat_layer, lit.coat_ior, cosine);
            coat = coat_transmittance_of(hit.material, lit.coat_alpha, cosine) * layer;
        }
        response += lit.diffuse * coat * cosine;
    }
    if lit.alpha > 0.0 {
        let lobe = lit_glossy_lobe(lit, hit, outgoing, incident);
        if lobe.value > 0.0 {
            var tint = vec3<f32>(1.0);
            if lit.metal {
                tint = metal_tint(lit.metal_f0, lit.metal_edge, lit.film, outgoing, incident);
            }
            if !dielectric_layer_is_bare(lit.dielectric_layer) {
                // render::dielectric_layer::lobe_layer_weight.
                var eta = 1.0 / lit.coat_ior;
                var thin_walled = false;
                if lit.sheet_eta > 0.0 {
                    eta = lit.sheet_eta;
                    thin_walled = true;
                } else if lit.refraction_eta > 0.0 {
                    eta = lit.refraction_eta;
                }
                tint *= rough_dielectric_layer_weight(lit.dielectric_layer, outgoing, incident, hit.shading, eta, thin_walled);
            }
            // A rough coat's reflection under its layer (1 elsewhere: a bare layer).
            tint *= coat_layer_reflection(lit.coat_layer, lit.coat_ior, outgoing, incident);
            response += lit.glossy * tint * (lobe.value * power_heuristic(light_pdf, lobe.pdf));
        }
    }
    // In through the clear coat and the sheen, if any (the coat about the normal before the
    // map).
    let sheen = sheen_transmittance(lit.sheen, cosine);
    return response * (clearcoat_transmittance(lit.clearcoat, dot(incident, hit.interpolated)) * sheen);
}

// cpu::kernels::direct_light: one light sample at an eye path's hit, through the lobes `lit`
// names; kept among params.light_candidates where there is no glossy lobe (MIS needs the
// sample's density).
fn direct_light(hit: SurfaceHit, outgoing: vec3<f32>, lit: LitLobes, medium: u32, rng: ptr<function, Rng>) -> vec3<f32> {
    let facing = lit_facing(lit, hit);
    var candidates = params.light_candidates;
    if lit.alpha > 0.0 {
        candidates = 1u;
    }
    let light = resample_light(candidates, hit.position, facing, rng);
    if !light.found {
        return vec3<f32>(0.0);
    }
    // A thin sheet takes light from both sides.
    if dot(light.direction, facing) <= 0.0 && !(FROSTED_GLASS && lit.sheet_eta > 0.0) {
        return vec3<f32>(0.0);
    }
    let response = lit_response(lit, hit, outgoing, light.direction, light.pdf);
    if max3(response) <= 0.0 {
        return vec3<f32>(0.0);
    }
    var origin: vec3<f32>;
    // cpu::kernels::direct_light: the shadow ray's medium; a refraction out of a solid leaves it.
    var shadow_medium = medium;
    if FROSTED_GLASS && dot(light.direction, hit.shading) < 0.0 {
        // cpu::kernels::direct_light: through the glass (a refraction out, a sheet's
        // transmission), from just beyond it.
        if dot(light.direction, hit.geometric) >= 0.0 {
            return vec3<f32>(0.0);
        }
        if lit.refraction_eta > 0.0 {
            shadow_medium = materials[hit.material].exterior;
        }
        origin = hit.position - params.epsilon * hit.geometric;
    } else {
        // cpu::kernels::direct_light: a coarse mesh's terminator, decided by the shadow ray.
        let lifted = is_lifted(hit.position, hit.shadow_origin, hit.geometric, params.epsilon);
        if dot(light.direction, hit.geometric) <= 0.0 && !lifted {
            return vec3<f32>(0.0);
        }
        origin = shadow_ray_origin(hit, params.epsilon);
    }
    let shadow = shadow_ray(light, origin);
    if !unoccluded(origin, shadow.xyz, shadow.w) {
        return vec3<f32>(0.0);
    }
    return light.incident * response * medium_transmittance(shadow_medium, shadow.w);
}

// cpu::kernels::eye_path: one light sample through the lobes `lit` names, its numbers drawn
// only where they light something.
fn sampled_light(hit: SurfaceHit, outgoing: vec3<f32>, lit: LitLobes, medium: u32, rng: ptr<function, Rng>) -> vec3<f32> {
    if !is_lit(lit) || params.light_count == 0u {
        return vec3<f32>(0.0);
    }
    return direct_light(hit, outgoing, lit, medium, rng);
}

// cpu::kernels::GlossyVertex: where an eye path last left a glossy lobe (pdf 0: it did not).
struct GlossyVertex {
    position: vec3<f32>,
    normal: vec3<f32>,
    pdf: f32,
}

// cpu::kernels::GlossyVertex::after.
fn glossy_after(hit: SurfaceHit, lit: LitLobes, outgoing: vec3<f32>, next: vec3<f32>) -> GlossyVertex {
    if lit.alpha <= 0.0 {
        return GlossyVertex(vec3<f32>(0.0), vec3<f32>(0.0), 0.0);
    }
    let lobe = lit_glossy_lobe(lit, hit, outgoing, next);
    return GlossyVertex(hit.position, lit_facing(lit, hit), lobe.pdf);
}

// cpu::kernels::GlossyVertex::emitter_weight.
fn emitter_weight(glossy: GlossyVertex, hit: SurfaceHit, direction: vec3<f32>) -> f32 {
    if glossy.pdf <= 0.0 {
        return 1.0;
    }
    let area_density = materials[hit.material].light_area_density;
    let distance = length(hit.position - glossy.position);
    let light_pdf = triangle_pdf(area_density, distance, dot(direction, hit.geometric));
    return power_heuristic(glossy.pdf, light_pdf);
}

// cpu::kernels::GlossyVertex::sky_weight.
fn sky_weight(glossy: GlossyVertex, direction: vec3<f32>) -> f32 {
    if glossy.pdf <= 0.0 {
        return 1.0;
    }
    return power_heuristic(glossy.pdf, sky_pdf(direction, glossy.normal));
}

// render::direct::shadow_ray: the direction (xyz) and length (w) of the shadow ray from
// `origin` towards a light sample.
fn shadow_ray(light: LightSample, origin: vec3<f32>) -> vec4<f32> {
    if light.distance >= RAY_T_MAX {
        return vec4<f32>(light.direction, RAY_T_MAX);
    }
    let offset = light.target_point - origin;
    let distance = length(offset);
    if distance <= 0.0 {
        return vec4<f32>(light.direction, 0.0);
    }
    return vec4<f32>(offset / distance, distance * (1.0 - SHADOW_SHORTENING));
}
