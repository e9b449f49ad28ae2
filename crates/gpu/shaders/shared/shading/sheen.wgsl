// render::sheen: glTF's sheen, its Charlie lobe and albedo tables, and the bounce off it.

// ---- render::sheen ----
// render::sheen::SheenAt: a material's sheen at a hit (colour black: none); its table is
// record `id`'s sheen_albedo, or for a textured roughness the blend by `t` of the sheen grid's
// tables in records `id` and `upper` (render::sheen::grid_table).
struct Sheen {
    color: vec3<f32>,
    alpha: f32,
    id: u32,
    upper: u32,
    t: f32,
}

fn no_sheen() -> Sheen {
    return Sheen(vec3<f32>(0.0), 0.0, 0u, 0u, 0.0);
}

// render::sheen::SheenAt::new: material `id`'s sheen where the hit's texture coordinates are
// `uv`.
fn sheen_at(id: u32, material: GpuMaterial, uv: vec2<f32>) -> Sheen {
    var scale = vec3<f32>(1.0);
    if material.sheen_color_texture != NO_TEXTURE {
        scale = sample_texture(material.sheen_color_texture, uv).xyz;
    }
    let color = material.sheen_color * clamp(scale, vec3<f32>(0.0), vec3<f32>(1.0));
    if material.sheen_roughness_texture == NO_TEXTURE {
        return Sheen(color, material.sheen_alpha, id, id, 0.0);
    }
    // render::sheen::textured_roughness and grid_position.
    let texel = sample_texture(material.sheen_roughness_texture, uv).w;
    let roughness = max(material.sheen_roughness * clamp(texel, 0.0, 1.0), SHEEN_MIN_ROUGHNESS);
    let s = sqrt(clamp((roughness - SHEEN_MIN_ROUGHNESS) / (1.0 - SHEEN_MIN_ROUGHNESS), 0.0, 1.0));
    let x = s * f32(SHEEN_GRID_NODES - 1u);
    let i = min(u32(x), SHEEN_GRID_NODES - 2u);
    let record = material.sheen_grid_first + i;
    return Sheen(color, roughness * roughness, record, record + 1u, x - f32(i));
}

// cpu::surface::sheen_faces: everywhere but on the inside of solid glass.
fn sheen_faces(material: GpuMaterial, front: bool) -> bool {
    let glass = material.surface == SURFACE_DIELECTRIC || material.surface == SURFACE_ROUGH_DIELECTRIC;
    return front || !glass || (material.flags & MATERIAL_THIN_WALLED) != 0u;
}

// render::sheen::SheenTable::albedo of one record's table, read straight from the storage
// buffer as coat_table is.
fn sheen_record_albedo(id: u32, cos: f32) -> f32 {
    let node = table_node(cos, SHEEN_NODES);
    let j = node.i + 1u;
    let first = materials[id].sheen_albedo[node.i / 4u][node.i % 4u];
    let second = materials[id].sheen_albedo[j / 4u][j % 4u];
    return first * (1.0 - node.t) + second * node.t;
}

// render::sheen::SheenTable::albedo of the sheen's table.
fn sheen_albedo(sheen: Sheen, cos: f32) -> f32 {
    let below = sheen_record_albedo(sheen.id, cos);
    if sheen.t <= 0.0 {
        return below;
    }
    return below * (1.0 - sheen.t) + sheen_record_albedo(sheen.upper, cos) * sheen.t;
}

// render::sheen::SheenTable::reflectance.
fn sheen_reflectance(sheen: Sheen, cos: f32) -> f32 {
    return max3(sheen.color) * min(sheen_albedo(sheen, cos), 1.0);
}

// render::sheen::SheenTable::transmittance: 1 without a sheen.
fn sheen_transmittance(sheen: Sheen, cos: f32) -> f32 {
    if !SHEENS || max3(sheen.color) <= 0.0 {
        return 1.0;
    }
    return 1.0 - sheen_reflectance(sheen, cos);
}

// render::sheen::SheenTable::lobe_scale.
fn sheen_lobe_scale(sheen: Sheen, cos: f32) -> vec3<f32> {
    let denominator = max3(sheen.color) * sheen_albedo(sheen, cos);
    if denominator > 0.0 {
        return sheen.color / denominator;
    }
    return vec3<f32>(0.0);
}

// render::sheen::charlie_distribution.
fn charlie_distribution(alpha: f32, cos_h: f32) -> f32 {
    let sin2 = max(1.0 - cos_h * cos_h, 0.0);
    if sin2 <= 0.0 {
        return 0.0;
    }
    let inverse = 1.0 / alpha;
    return (2.0 + inverse) * pow(sin2, 0.5 * inverse) / (2.0 * PI);
}

// render::sheen::lambda_exponent (Estevez and Kulla's fit).
fn sheen_lambda_exponent(x: f32, alpha: f32) -> f32 {
    let t = (1.0 - alpha) * (1.0 - alpha);
    let a = mix(21.5473, 25.3245, t);
    let b = mix(3.82987, 3.32435, t);
    let c = mix(0.19823, 0.16801, t);
    let d = mix(-1.97760, -1.27393, t);
    let e = mix(-4.32054, -4.85967, t);
    return a / (1.0 + b * select(pow(x, c), 0.0, x <= 0.0)) + d * x + e;
}

// render::sheen::charlie_lambda.
fn charlie_lambda(cos_in: f32, alpha: f32) -> f32 {
    let cos = abs(cos_in);
    if cos < 0.5 {
        return exp(sheen_lambda_exponent(cos, alpha));
    }
    return exp(2.0 * sheen_lambda_exponent(0.5, alpha) - sheen_lambda_exponent(1.0 - cos, alpha));
}

// render::sheen::local_sheen: `f cos θi` of the white lobe and the cosine density.
fn local_sheen(view: vec3<f32>, light: vec3<f32>, alpha: f32) -> GlossyResponse {
    if view.z <= 0.0 || light.z <= 0.0 {
        return GlossyResponse(0.0, 0.0);
    }
    let half = normalize(view + light);
    let shadowing = 1.0 + charlie_lambda(light.z, alpha) + charlie_lambda(view.z, alpha);
    let visibility = 1.0 / (shadowing * 4.0 * light.z * view.z);
    let value = charlie_distribution(alpha, half.z) * visibility * light.z;
    return GlossyResponse(value, light.z / PI);
}

// render::sheen::sheen_response.
fn sheen_response(outgoing: vec3<f32>, incident: vec3<f32>, normal: vec3<f32>, alpha: f32) -> GlossyResponse {
    let frame = frame_about(normal);
    return local_sheen(to_local(frame, outgoing), to_local(frame, incident), alpha);
}

// cpu::surface::sheen_bounce (render::sheen::sheen_event about the shading normal, three
// numbers): `reflected` where the sheen reflects the ray (weight 0 where the path ends),
// otherwise it passes to the material beneath.
struct SheenBounce {
    reflected: bool,
    direction: vec3<f32>,
    weight: vec3<f32>,
}

fn sheen_bounce(sheen: Sheen, hit: SurfaceHit, incoming: vec3<f32>, rng: ptr<function, Rng>) -> SheenBounce {
    let u0 = next_f32(rng);
    let u1 = next_f32(rng);
    let u2 = next_f32(rng);
    let cos_view = -dot(incoming, hit.shading);
    if cos_view <= 0.0 || u0 >= sheen_reflectance(sheen, cos_view) {
        return SheenBounce(false, vec3<f32>(0.0), vec3<f32>(0.0));
    }
    let light = cosine_hemisphere(u1, u2);
    let response = local_sheen(to_local(frame_about(hit.shading), -incoming), light, sheen.alpha);
    let direction = about_axis(hit.shading, light);
    var weight = vec3<f32>(0.0);
    if response.pdf > 0.0 && dot(direction, hit.geometric) > 0.0 {
        weight = sheen_lobe_scale(sheen, cos_view) * (response.value / response.pdf);
    }
    return SheenBounce(true, direction, weight);
}
