// render::microfacet: GGX sampling and responses, isotropic and brushed, for rough metal,
// rough glass (solid or a thin sheet) and plastic's coat, and the frames they work in.

// ---- render::microfacet ----
fn sample_visible_normal(view: vec3<f32>, alpha: f32, u1: f32, u2: f32) -> vec3<f32> {
    return sample_visible_normal_brushed(view, alpha, alpha, u1, u2);
}

fn smith_g1(w: vec3<f32>, alpha: f32) -> f32 {
    if w.z <= 0.0 {
        return 0.0;
    }
    let tan2 = (w.x * w.x + w.y * w.y) / (w.z * w.z);
    return 2.0 / (1.0 + sqrt(1.0 + alpha * alpha * tan2));
}

// A bounce off a non-diffuse surface: where it goes and its weight (the tint aside); weight 0
// where the path ends (cpu::surface::specular_direction's None).
struct Scattered {
    direction: vec3<f32>,
    weight: f32,
}

// A frame about the shading normal, as render::microfacet works in (orthonormal_basis).
struct Frame {
    t: vec3<f32>,
    b: vec3<f32>,
    n: vec3<f32>,
}

fn frame_about(normal: vec3<f32>) -> Frame {
    return Frame(basis_tangent(normal), basis_bitangent(normal), normal);
}

fn to_local(f: Frame, v: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(dot(v, f.t), dot(v, f.b), dot(v, f.n));
}

fn to_world(f: Frame, v: vec3<f32>) -> vec3<f32> {
    return normalize(f.t * v.x + f.b * v.y + f.n * v.z);
}

// render::microfacet::rough_reflection, with specular_direction's check against the
// geometric normal.
fn rough_reflection(hit: SurfaceHit, incoming: vec3<f32>, alpha: f32, u1: f32, u2: f32) -> Scattered {
    let frame = frame_about(hit.shading);
    let view = to_local(frame, -incoming);
    if view.z <= 0.0 {
        return Scattered(vec3<f32>(0.0), 0.0);
    }
    let micro = sample_visible_normal(view, alpha, u1, u2);
    let out = reflect_about(-view, micro);
    let weight = smith_g1(out, alpha);
    let next = to_world(frame, out);
    if weight <= 0.0 || dot(next, hit.geometric) <= 0.0 {
        return Scattered(vec3<f32>(0.0), 0.0);
    }
    return Scattered(next, weight);
}

// render::microfacet's brushed (anisotropic) GGX: widths `ax` along +X, `ay` along +Y.
fn sample_visible_normal_brushed(view: vec3<f32>, ax: f32, ay: f32, u1: f32, u2: f32) -> vec3<f32> {
    let stretched = normalize(vec3<f32>(ax * view.x, ay * view.y, view.z));
    let length_sq = stretched.x * stretched.x + stretched.y * stretched.y;
    var t1 = vec3<f32>(1.0, 0.0, 0.0);
    if length_sq > 0.0 {
        t1 = vec3<f32>(-stretched.y, stretched.x, 0.0) / sqrt(length_sq);
    }
    let t2 = cross(stretched, t1);
    let r = sqrt(u1);
    let phi = 2.0 * PI * u2;
    let p1 = r * cos(phi);
    let s = 0.5 * (1.0 + stretched.z);
    let p2 = (1.0 - s) * sqrt(max(1.0 - p1 * p1, 0.0)) + s * r * sin(phi);
    let p3 = sqrt(max(1.0 - p1 * p1 - p2 * p2, 0.0));
    let normal = p1 * t1 + p2 * t2 + p3 * stretched;
    return normalize(vec3<f32>(ax * normal.x, ay * normal.y, max(normal.z, 0.0)));
}

fn smith_g1_brushed(w: vec3<f32>, ax: f32, ay: f32) -> f32 {
    if w.z <= 0.0 {
        return 0.0;
    }
    let tan2 = ((ax * w.x) * (ax * w.x) + (ay * w.y) * (ay * w.y)) / (w.z * w.z);
    return 2.0 / (1.0 + sqrt(1.0 + tan2));
}

fn ggx_d_brushed(m: vec3<f32>, ax: f32, ay: f32) -> f32 {
    if m.z <= 0.0 {
        return 0.0;
    }
    let t = (m.x / ax) * (m.x / ax) + (m.y / ay) * (m.y / ay) + m.z * m.z;
    return 1.0 / (PI * ax * ay * t * t);
}

// render::microfacet::Frame::along.
fn frame_along(normal: vec3<f32>, direction: vec3<f32>) -> Frame {
    let projected = direction - normal * dot(normal, direction);
    let length_squared = dot(projected, projected);
    if !(length_squared > 1e-12) || length_squared > 3.40282347e38 {
        return frame_about(normal);
    }
    let t = projected / sqrt(length_squared);
    return Frame(t, cross(normal, t), normal);
}

// render::microfacet::brushed_widths: (along the brushing, across it).
fn brushed_widths(alpha: f32, strength: f32) -> vec2<f32> {
    return vec2<f32>(alpha + (1.0 - alpha) * strength * strength, alpha);
}

// render::microfacet::brushed_reflection about the hit's brushing, with specular_direction's
// check against the geometric normal.
fn brushed_reflection(hit: SurfaceHit, incoming: vec3<f32>, alpha: f32, u1: f32, u2: f32) -> Scattered {
    let frame = frame_along(hit.shading, hit.brush);
    let widths = brushed_widths(alpha, min(length(hit.brush), 1.0));
    let view = to_local(frame, -incoming);
    if view.z <= 0.0 {
        return Scattered(vec3<f32>(0.0), 0.0);
    }
    let micro = sample_visible_normal_brushed(view, widths.x, widths.y, u1, u2);
    let out = reflect_about(-view, micro);
    let weight = smith_g1_brushed(out, widths.x, widths.y);
    let next = to_world(frame, out);
    if weight <= 0.0 || dot(next, hit.geometric) <= 0.0 {
        return Scattered(vec3<f32>(0.0), 0.0);
    }
    return Scattered(next, weight);
}

// render::microfacet::brushed_response.
fn brushed_response(outgoing: vec3<f32>, incident: vec3<f32>, normal: vec3<f32>, brush: vec3<f32>, alpha: f32) -> GlossyResponse {
    let frame = frame_along(normal, brush);
    let widths = brushed_widths(alpha, min(length(brush), 1.0));
    let view = to_local(frame, outgoing);
    let light = to_local(frame, incident);
    if view.z <= 0.0 || light.z <= 0.0 {
        return GlossyResponse(0.0, 0.0);
    }
    let half = normalize(view + light);
    let pdf = smith_g1_brushed(view, widths.x, widths.y) * ggx_d_brushed(half, widths.x, widths.y) / (4.0 * view.z);
    return GlossyResponse(pdf * smith_g1_brushed(light, widths.x, widths.y), pdf);
}

// render::microfacet::ggx_d.
fn ggx_d(m: vec3<f32>, alpha: f32) -> f32 {
    if m.z <= 0.0 {
        return 0.0;
    }
    let a2 = alpha * alpha;
    let denom = m.z * m.z * (a2 - 1.0) + 1.0;
    return a2 / (PI * denom * denom);
}

// render::microfacet::GlossyResponse.
struct GlossyResponse {
    value: f32,
    pdf: f32,
}

// render::microfacet::glossy_response: a rough conductor's lobe (coat_ior 0) or a plastic
// coat's, lit along `incident` and seen along `outgoing`.
fn glossy_response(outgoing: vec3<f32>, incident: vec3<f32>, normal: vec3<f32>, alpha: f32, coat_ior: f32) -> GlossyResponse {
    let frame = frame_about(normal);
    let view = to_local(frame, outgoing);
    let light = to_local(frame, incident);
    if view.z <= 0.0 || light.z <= 0.0 {
        return GlossyResponse(0.0, 0.0);
    }
    let half = normalize(view + light);
    var fresnel = 1.0;
    if coat_ior > 0.0 {
        fresnel = coat_reflectance(dot(view, half), coat_ior);
    }
    let pdf = fresnel * smith_g1(view, alpha) * ggx_d(half, alpha) / (4.0 * view.z);
    return GlossyResponse(pdf * smith_g1(light, alpha), pdf);
}

// render::microfacet::refraction_response: solid rough glass's refraction lobe, seen along
// `outgoing` on the normal's side and lit along `incident` beyond it; eta = n there / n beyond.
fn refraction_response(outgoing: vec3<f32>, incident: vec3<f32>, normal: vec3<f32>, alpha: f32, eta: f32) -> GlossyResponse {
    let frame = frame_about(normal);
    let view = to_local(frame, outgoing);
    let light = to_local(frame, incident);
    if view.z <= 0.0 || light.z >= 0.0 {
        return GlossyResponse(0.0, 0.0);
    }
    var micro = -(eta * view + light);
    if dot(micro, micro) == 0.0 {
        return GlossyResponse(0.0, 0.0);
    }
    micro = normalize(micro);
    if micro.z < 0.0 {
        micro = -micro;
    }
    let cos_view = dot(view, micro);
    let cos_light = dot(light, micro);
    if cos_view <= 0.0 || cos_light >= 0.0 {
        return GlossyResponse(0.0, 0.0);
    }
    let transmitted = 1.0 - fresnel_dielectric(cos_view, eta);
    let denominator = eta * cos_view + cos_light;
    let jacobian = -cos_light / (denominator * denominator);
    let pdf = transmitted * smith_g1(view, alpha) * cos_view * ggx_d(micro, alpha) / view.z * jacobian;
    let below = vec3<f32>(light.x, light.y, -light.z);
    return GlossyResponse(pdf * smith_g1(below, alpha), pdf);
}

// render::microfacet::sheet_response: a thin rough sheet's reflection (lit on the normal's
// side) and transmission (lit beyond it, as the reflection mirrored); eta = 1 / its index.
fn sheet_response(outgoing: vec3<f32>, incident: vec3<f32>, normal: vec3<f32>, alpha: f32, eta: f32) -> GlossyResponse {
    let frame = frame_about(normal);
    let view = to_local(frame, outgoing);
    let light = to_local(frame, incident);
    if view.z <= 0.0 || light.z == 0.0 {
        return GlossyResponse(0.0, 0.0);
    }
    let reflected = vec3<f32>(light.x, light.y, abs(light.z));
    let half = normalize(view + reflected);
    let fresnel = fresnel_dielectric(dot(view, half), eta);
    let sheet = 2.0 * fresnel / (1.0 + fresnel);
    let choice = select(sheet, 1.0 - sheet, light.z < 0.0);
    let pdf = choice * smith_g1(view, alpha) * ggx_d(half, alpha) / (4.0 * view.z);
    return GlossyResponse(pdf * smith_g1(reflected, alpha), pdf);
}

// render::microfacet::rough_dielectric, with specular_direction's check against the
// geometric normal. (Under total internal reflection Fresnel is 1 and u_third < 1 reflects,
// so the refraction below always exists, as the twin's `?` assumes.)
fn rough_dielectric(material: GpuMaterial, hit: SurfaceHit, incoming: vec3<f32>, u1: f32, u2: f32, u_third: f32) -> Scattered {
    let normal = hit.shading;
    let thin_walled = (material.flags & MATERIAL_THIN_WALLED) != 0u;
    let eta = relative_eta(material.ior, hit.front, thin_walled);
    let alpha = material.roughness_alpha;
    let frame = frame_about(normal);
    let view = to_local(frame, -incoming);
    if view.z <= 0.0 {
        return Scattered(vec3<f32>(0.0), 0.0);
    }
    let micro = sample_visible_normal(view, alpha, u1, u2);
    var reflectance = fresnel_dielectric(dot(view, micro), eta);
    if thin_walled {
        reflectance = 2.0 * reflectance / (1.0 + reflectance);
    }
    let reflects = u_third < reflectance;
    let reflected = reflect_about(-view, micro);
    var out = reflected;
    if !reflects {
        if thin_walled {
            out = vec3<f32>(reflected.x, reflected.y, -reflected.z);
        } else {
            out = refract_or_reflect(-view, micro, eta);
        }
    }
    let side = select(-out.z, out.z, reflects);
    let weight = smith_g1(vec3<f32>(out.x, out.y, side), alpha);
    let next = to_world(frame, out);
    let same_side = (dot(next, normal) > 0.0) == (dot(next, hit.geometric) > 0.0);
    if weight <= 0.0 || !same_side {
        return Scattered(vec3<f32>(0.0), 0.0);
    }
    return Scattered(next, weight);
}
