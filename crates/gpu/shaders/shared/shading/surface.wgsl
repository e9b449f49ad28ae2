// cpu::surface's hit: the closest surface along a ray, its normals, texture coordinates and
// brushing, its emission and the side its Lambertian lobe sends light to; and the overrides
// that compile features a scene lacks out of the kernels.

// ---- cpu::surface ----
struct SurfaceHit {
    position: vec3<f32>,
    shadow_origin: vec3<f32>,
    distance: f32,
    geometric: vec3<f32>,
    shading: vec3<f32>,
    // cpu::surface::SurfaceHit::interpolated: the shading normal before the normal map.
    interpolated: vec3<f32>,
    uv: vec2<f32>,
    material: u32,
    front: bool,
    found: bool,
    // cpu::surface::SurfaceHit::brush: a brushed metal's brushing (zero elsewhere).
    brush: vec3<f32>,
}

fn vertex_normal(v: PackedVertex) -> vec3<f32> {
    let z = sqrt(max(1.0 - v.normal_xy.x * v.normal_xy.x - v.normal_xy.y * v.normal_xy.y, 0.0));
    return vec3<f32>(v.normal_xy, select(z, -z, v.signed_material < 0.0));
}

fn normalize_or(v: vec3<f32>, fallback: vec3<f32>) -> vec3<f32> {
    let length_squared = dot(v, v);
    return select(fallback, v * inverseSqrt(length_squared), length_squared > 0.0);
}

// Whether some material has a normal map. The backend compiles the kernels of a scene without
// one with this false, so that its hits carry no normal-map code: even skipped at run time,
// that code made lavapipe's eye pass 10-15 % and its photon pass ~5 % slower.
override NORMAL_MAPS: bool = true;

// Whether some material is rough plastic (its coat's table) or frosted glass, solid or a thin
// sheet (light samples through it); compiled out as NORMAL_MAPS is, for the same reason.
override ROUGH_COATS: bool = true;
override FROSTED_GLASS: bool = true;
// Whether some material is a blend (scene::Blend), whose member each hit draws.
override BLENDS: bool = true;
// Whether some material wears glTF's clear coat (scene::Clearcoat).
override CLEARCOATS: bool = true;
// Whether some material wears glTF's sheen (scene::Sheen).
override SHEENS: bool = true;
// Whether some blend's glass member is weighed by a transmission texture.
override TRANSMISSION_MAPS: bool = true;
// Whether some material transmits diffusely (scene::DiffuseTransmission).
override DIFFUSE_TRANSMISSION: bool = true;
// Whether some material is brushed (scene::Anisotropy): hits carry the brushing.
override ANISOTROPY: bool = true;
// Whether hits read the mesh's own tangents (render::normal_map::packed_tangents), for a
// normal map's or a brushing's frame.
override TANGENTS: bool = true;
// Whether the sky has an environment map (render::sky_map, read in kernels/sppm/): compiled out
// otherwise, as NORMAL_MAPS is (its lookups and searches, inlined, made lavapipe's eye pass
// ~10 % slower in scenes without one).
override SKY_MAP: bool = true;

// Whether some material's surface follows a metallic-roughness texture (scene::RoughnessMap);
// compiled out as NORMAL_MAPS is.
override ROUGHNESS_MAPS: bool = true;

fn trace_surface(origin: vec3<f32>, direction: vec3<f32>) -> SurfaceHit {
    return trace_surface_within(origin, direction, RAY_T_MAX);
}

// cpu::surface::trace_within: the closest hit nearer than t_max.
fn trace_surface_within(origin: vec3<f32>, direction: vec3<f32>, t_max: f32) -> SurfaceHit {
    var result: SurfaceHit;
    let hit = trace_mtbvh(GpuRay(origin, t_max, direction, 0u), false);
    if hit.triangle == NO_HIT {
        result.found = false;
        return result;
    }
    let triangle = load_triangle(hit.triangle);
    let a = triangle.vertices[0];
    let b = triangle.vertices[1];
    let c = triangle.vertices[2];
    let geometric = normalize_or(cross(b.position - a.position, c.position - a.position), vec3<f32>(0.0, 0.0, 1.0));
    let w = 1.0 - hit.u - hit.v;
    let normal_a = vertex_normal(a);
    let normal_b = vertex_normal(b);
    let normal_c = vertex_normal(c);
    let interpolated = w * normal_a + hit.u * normal_b + hit.v * normal_c;
    result.position = origin + hit.t * direction;
    result.shadow_origin = result.position;
    if dot(interpolated, direction) < 0.0 {
        result.shadow_origin = smooth_position(result.position, a.position, b.position, c.position, normal_a, normal_b, normal_c, vec3<f32>(w, hit.u, hit.v));
    }
    let unit_interpolated = normalize_or(interpolated, geometric);
    var shading = unit_interpolated;
    let uv_a = vec2<f32>(a.u, a.v);
    let uv_b = vec2<f32>(b.u, b.v);
    let uv_c = vec2<f32>(c.u, c.v);
    let uv = w * uv_a + hit.u * uv_b + hit.v * uv_c;
    let material_index = u32(abs(a.signed_material)) - 1u;
    // cpu::surface::trace_within: the frame normal maps and brushing are given in.
    let tangent = tangent_at(hit.triangle, vec3<f32>(w, hit.u, hit.v));
    if NORMAL_MAPS {
        let map = materials[material_index].normal_texture;
        if map != NO_TEXTURE {
            let texel = sample_texture(map, uv).xyz;
            shading = mapped_normal(shading, a.position, b.position, c.position, uv_a, uv_b, uv_c, tangent, texel, materials[material_index].normal_scale);
        }
    }
    if ANISOTROPY {
        // cpu::surface::brush_at: a brushed metal's brushing in the triangle's texture frame.
        let base = materials[material_index].anisotropy;
        if any(base != vec2<f32>(0.0)) {
            var brush = base;
            let map = materials[material_index].anisotropy_texture;
            if map != NO_TEXTURE {
                let texel = sample_texture(map, uv);
                let raw = texel.xy * 2.0 - vec2<f32>(1.0);
                let length_squared = dot(raw, raw);
                var d = vec2<f32>(1.0, 0.0);
                if length_squared > 0.0 {
                    d = raw * (1.0 / sqrt(length_squared));
                }
                brush = vec2<f32>(d.x * base.x - d.y * base.y, d.x * base.y + d.y * base.x) * texel.z;
            }
            result.brush = brushing(unit_interpolated, a.position, b.position, c.position, uv_a, uv_b, uv_c, tangent, brush);
        }
    }
    let front = dot(direction, geometric) < 0.0;
    let side = select(-1.0, 1.0, front);
    result.geometric = side * geometric;
    result.shading = side * shading;
    if dot(result.shading, result.geometric) <= 0.0 {
        result.shading = result.geometric;
    }
    result.interpolated = result.shading;
    if NORMAL_MAPS {
        // cpu::surface::trace_within: a clear coat with a normal map of its own follows it.
        var coat_normal = unit_interpolated;
        if CLEARCOATS {
            let coat_map = materials[material_index].clearcoat_normal_texture;
            if coat_map != NO_TEXTURE {
                let texel = sample_texture(coat_map, uv).xyz;
                coat_normal = mapped_normal(coat_normal, a.position, b.position, c.position, uv_a, uv_b, uv_c, tangent, texel, materials[material_index].clearcoat_normal_scale);
            }
        }
        result.interpolated = side * coat_normal;
        if dot(result.interpolated, result.geometric) <= 0.0 {
            result.interpolated = result.geometric;
        }
    }
    result.distance = hit.t;
    result.uv = uv;
    result.material = material_index;
    result.front = front;
    result.found = true;
    return result;
}

fn offset_origin(hit: SurfaceHit, direction: vec3<f32>, epsilon: f32) -> vec3<f32> {
    let side = select(-1.0, 1.0, dot(direction, hit.geometric) >= 0.0);
    return hit.position + side * epsilon * hit.geometric;
}

fn shadow_ray_origin(hit: SurfaceHit, epsilon: f32) -> vec3<f32> {
    return hit.shadow_origin + epsilon * hit.geometric;
}

fn is_cut_out(material: GpuMaterial, uv: vec2<f32>) -> bool {
    if material.alpha_cutoff < 0.0 {
        return false;
    }
    return sample_texture(material.base_color_texture, uv).w < material.alpha_cutoff;
}

fn base_color(material: GpuMaterial, uv: vec2<f32>) -> vec3<f32> {
    return material.base_color * sample_texture(material.base_color_texture, uv).xyz;
}

// Whether `material` (a hit's member) has glTF's diffuse transmission on a Lambertian lobe:
// its paths draw one more number to choose the lobe's side (cpu::kernels).
fn transmits_diffusely(material: GpuMaterial) -> bool {
    let lambertian = material.surface == SURFACE_DIFFUSE || material.surface == SURFACE_PLASTIC;
    return DIFFUSE_TRANSMISSION && material.diffuse_transmission > 0.0 && lambertian;
}

// cpu::surface::SurfaceHit::flipped: the point seen from the other side.
fn flipped(hit: SurfaceHit) -> SurfaceHit {
    var far = hit;
    far.shadow_origin = hit.position;
    far.geometric = -hit.geometric;
    far.shading = -hit.shading;
    far.interpolated = -hit.interpolated;
    far.front = !hit.front;
    return far;
}

// cpu::surface::lambertian_side: the side of `hit` the Lambertian lobe of `material` sends
// its light to and its tint there, the far one where its diffuse transmission's share (its
// factor times its texture's alpha) exceeds `u`, else the hit and `reflected`.
struct LambertianSide {
    hit: SurfaceHit,
    tint: vec3<f32>,
}

fn lambertian_side(material: GpuMaterial, hit: SurfaceHit, reflected: vec3<f32>, u: f32) -> LambertianSide {
    if transmits_diffusely(material) {
        let share = material.diffuse_transmission * sample_texture(material.diffuse_transmission_texture, hit.uv).w;
        if u < clamp(share, 0.0, 1.0) {
            let texel = sample_texture(material.diffuse_transmission_color_texture, hit.uv).xyz;
            return LambertianSide(flipped(hit), material.diffuse_transmission_color * texel);
        }
    }
    return LambertianSide(hit, reflected);
}

fn emitted(material: GpuMaterial, hit: SurfaceHit) -> vec3<f32> {
    let double_sided = (material.flags & MATERIAL_DOUBLE_SIDED) != 0u;
    if max3(material.emission) <= 0.0 || !(hit.front || double_sided) {
        return vec3<f32>(0.0);
    }
    return material.emission * sample_texture(material.emission_texture, hit.uv).xyz;
}
