// render::iridescence: a thin film's Airy reflectance over the film spectrum, and the tints
// it gives metals and glass.

// ---- render::iridescence ----
// Whether some material wears a thin film; compiled out as MEDIA is.
override IRIDESCENCE: bool = true;

// render::iridescence::Film: glTF's factor (0: none), the film's index and thickness (nm).
struct Film {
    factor: f32,
    ior: f32,
    thickness: f32,
}

fn no_film() -> Film {
    return Film(0.0, 0.0, 0.0);
}

// cpu::surface::hit_film (scene::Iridescence::at).
fn hit_film(material: GpuMaterial, uv: vec2<f32>) -> Film {
    if !IRIDESCENCE || material.iridescence.x <= 0.0 {
        return no_film();
    }
    var film = Film(material.iridescence.x, material.iridescence.y, material.iridescence.w);
    if material.iridescence_texture != NO_TEXTURE {
        film.factor *= sample_texture(material.iridescence_texture, uv).x;
    }
    if material.iridescence_thickness_texture != NO_TEXTURE {
        let g = sample_texture(material.iridescence_thickness_texture, uv).y;
        film.thickness = material.iridescence.z + (material.iridescence.w - material.iridescence.z) * g;
    }
    return film;
}

// render::iridescence::ior_from_f0.
fn ior_from_f0(f0: vec3<f32>) -> vec3<f32> {
    let s = sqrt(clamp(f0, vec3<f32>(0.0), vec3<f32>(0.9999)));
    return (vec3<f32>(1.0) + s) / (vec3<f32>(1.0) - s);
}

// render::iridescence::film_reflectance: the Airy sum of the film's reflections, both
// polarisations, over the scene's film spectrum.
fn film_reflectance(cos_outside: f32, film_ior: f32, thickness: f32, base_ior: vec3<f32>) -> vec3<f32> {
    let cos1 = clamp(cos_outside, 0.0, 1.0);
    let sin2_1 = 1.0 - cos1 * cos1;
    let cos2_film = 1.0 - sin2_1 / (film_ior * film_ior);
    if cos2_film <= 0.0 {
        return vec3<f32>(1.0);
    }
    let cos2_base = vec3<f32>(1.0) - sin2_1 / (base_ior * base_ior);
    let base_blocked = cos2_base <= vec3<f32>(0.0);
    let n2 = film_ior;
    let n3 = base_ior;
    let cos2 = sqrt(cos2_film);
    let cos3 = sqrt(max(cos2_base, vec3<f32>(0.0)));
    let r12_s = (cos1 - n2 * cos2) / (cos1 + n2 * cos2);
    let r12_p = (n2 * cos1 - cos2) / (n2 * cos1 + cos2);
    let t12_s = 1.0 - r12_s * r12_s;
    let t12_p = 1.0 - r12_p * r12_p;
    let film_s = vec3<f32>(n2 * cos2);
    let base_s = n3 * cos3;
    let r23_s = (film_s - base_s) / max(film_s + base_s, vec3<f32>(1e-30));
    let film_p = n3 * cos2;
    let base_p = n2 * cos3;
    let r23_p = (film_p - base_p) / max(film_p + base_p, vec3<f32>(1e-30));
    let sum_s = r12_s + r23_s;
    let sum_p = r12_p + r23_p;
    let bare_s = sum_s * sum_s;
    let bare_p = sum_p * sum_p;
    let cross_s = 2.0 * r12_s * r23_s;
    let cross_p = 2.0 * r12_p * r23_p;
    let through_s = t12_s * (vec3<f32>(1.0) - r23_s * r23_s);
    let through_p = t12_p * (vec3<f32>(1.0) - r23_p * r23_p);
    // The phases' cosines along the even steps in wavenumber by Chebyshev's recurrence.
    let phase = 4.0 * PI * n2 * thickness * cos2;
    let first = phase * FILM_WAVENUMBER_FIRST;
    let step = phase * FILM_WAVENUMBER_STEP;
    let twice_cos_step = 2.0 * cos(step);
    var before = cos(first - step);
    var cos_delta = cos(first);
    var total = vec3<f32>(0.0);
    for (var i = 0u; i < FILM_WAVELENGTHS; i += 1u) {
        let entry = scene_info.film_spectrum[i];
        let one_minus_cos = 1.0 - cos_delta;
        let after = twice_cos_step * cos_delta - before;
        before = cos_delta;
        cos_delta = after;
        let reflected_s = max(bare_s - cross_s * one_minus_cos, vec3<f32>(0.0));
        let reflected_p = max(bare_p - cross_p * one_minus_cos, vec3<f32>(0.0));
        let r_s = reflected_s / (reflected_s + through_s);
        let r_p = reflected_p / (reflected_p + through_p);
        total += entry.yzw * (0.5 * (r_s + r_p));
    }
    return clamp(select(total, vec3<f32>(1.0), base_blocked), vec3<f32>(0.0), vec3<f32>(1.0));
}

// render::conductor::conductor_fresnel.
fn conductor_fresnel(f0: vec3<f32>, edge: vec3<f32>, cos_incident: f32) -> vec3<f32> {
    let grazing = pow(1.0 - clamp(cos_incident, 0.0, 1.0), 5.0);
    return f0 + edge * (vec3<f32>(1.0) - f0) * grazing;
}

// render::conductor::Metal::reflectance.
fn metal_reflectance(f0: vec3<f32>, edge: vec3<f32>, film: Film, cos_incident: f32) -> vec3<f32> {
    let bare = conductor_fresnel(f0, edge, cos_incident);
    if !IRIDESCENCE || film.factor <= 0.0 {
        return bare;
    }
    let cos_i = clamp(cos_incident, 0.0, 1.0);
    let film_colour = film_reflectance(cos_i, film.ior, film.thickness, ior_from_f0(f0));
    return mix(bare, film_colour, min(film.factor, 1.0));
}

// render::iridescence::film_mix.
fn film_mix(bare: vec3<f32>, film: Film, cos_outside: f32, ior: f32) -> vec3<f32> {
    let film_colour = film_reflectance(cos_outside, film.ior, film.thickness, vec3<f32>(ior));
    return mix(bare, film_colour, min(film.factor, 1.0));
}

// render::iridescence::film_share.
fn film_share(bare: f32, filmed: vec3<f32>, reflected: bool) -> vec3<f32> {
    if reflected {
        if bare > 0.0 {
            return filmed / bare;
        }
        return vec3<f32>(0.0);
    }
    if bare < 1.0 {
        return (vec3<f32>(1.0) - filmed) / (1.0 - bare);
    }
    return vec3<f32>(0.0);
}

// render::conductor::Metal::tint.
fn metal_tint(f0: vec3<f32>, edge: vec3<f32>, film: Film, outgoing: vec3<f32>, incident: vec3<f32>) -> vec3<f32> {
    let half_sum = outgoing + incident;
    let length_sum = length(half_sum);
    var cos_i = 0.0;
    if length_sum > 0.0 {
        cos_i = dot(outgoing, half_sum / length_sum);
    }
    return metal_reflectance(f0, edge, film, cos_i);
}

// cpu::surface::metal_bounce_tint.
fn metal_bounce_tint(material: GpuMaterial, tint: vec3<f32>, film: Film, incoming: vec3<f32>, next: vec3<f32>) -> vec3<f32> {
    if material.surface == SURFACE_MIRROR || material.surface == SURFACE_ROUGH_CONDUCTOR {
        return metal_tint(tint, material.metal_edge, film, -incoming, next);
    }
    return tint;
}
