// Twins of render::{optics, sampling, packing, emission, hash} and cpu::surface: what the SPPM
// kernels know about a hit, and the arithmetic both eye and photon paths share.

fn max3(v: vec3<f32>) -> f32 {
    return max(max(v.x, v.y), v.z);
}

fn sign_not_zero(x: f32) -> f32 {
    return select(-1.0, 1.0, x >= 0.0);
}

// ---- render::packing: octahedral normals in one u32 ----
fn fold(a: f32, b: f32) -> f32 {
    return (1.0 - abs(b)) * sign_not_zero(a);
}

fn pack_normal(n: vec3<f32>) -> u32 {
    var p = n.xy / max(abs(n.x) + abs(n.y) + abs(n.z), 1.17549435e-38);
    if n.z < 0.0 {
        p = vec2<f32>(fold(p.x, p.y), fold(p.y, p.x));
    }
    return pack2x16snorm(p);
}

// render::packing::surface_normal: VOLUME_BIT clear (surface visible points and photons).
fn surface_normal(n: vec3<f32>) -> u32 {
    return pack_normal(n) & ~VOLUME_BIT;
}

// render::packing::photon_normal: the class in the lowest bit (1: caustic), VOLUME_BIT clear.
fn photon_normal(n: vec3<f32>, caustic: bool) -> u32 {
    return (surface_normal(n) & ~1u) | select(0u, 1u, caustic);
}

fn is_caustic(packed_normal: u32) -> bool {
    return (packed_normal & 1u) != 0u;
}

// render::packing::is_volume: a volume photon's or visible point's word (murky glass).
fn is_volume(packed_normal: u32) -> bool {
    return (packed_normal & VOLUME_BIT) != 0u;
}

// render::packing::volume_photon_direction: the way it travelled, no caustic class.
fn volume_photon_direction(direction: vec3<f32>) -> u32 {
    return (pack_normal(direction) & ~1u) | VOLUME_BIT;
}

// render::packing's ANISOTROPY_BITS (private there; tests/packing_twins.rs checks the words
// bit for bit): the nine bits of a volume visible point's word that hold its asymmetry.
const ANISOTROPY_BITS: u32 = 0x001e001fu;

// render::packing::volume_point_direction: the way the eye path travelled and its medium's
// Henyey–Greenstein asymmetry to nine bits. Rust's round() takes halves away from zero,
// WGSL's to even: the level is rounded by hand (x − floor(x) is exact).
fn volume_point_direction(direction: vec3<f32>, g: f32) -> u32 {
    let scaled = (clamp(g, -1.0, 1.0) + 1.0) * 0.5 * 511.0;
    let below = floor(scaled);
    let level = u32(select(below, below + 1.0, scaled - below >= 0.5));
    let bits = (level & 0x1fu) | ((level >> 5u) << 17u);
    return (pack_normal(direction) & ~(ANISOTROPY_BITS | VOLUME_BIT)) | bits | VOLUME_BIT;
}

// render::packing::unpack_volume_point: its direction (xyz) and asymmetry (w).
fn unpack_volume_point(word: u32) -> vec4<f32> {
    let level = (word & 0x1fu) | (((word >> 17u) & 0xfu) << 5u);
    let g = f32(level) / 511.0 * 2.0 - 1.0;
    return vec4<f32>(unpack_normal(word & ~(ANISOTROPY_BITS | VOLUME_BIT)), g);
}

fn unpack_normal(bits: u32) -> vec3<f32> {
    let o = unpack2x16snorm(bits);
    let z = 1.0 - abs(o.x) - abs(o.y);
    var xy = o;
    if z < 0.0 {
        xy = vec2<f32>(fold(o.x, o.y), fold(o.y, o.x));
    }
    let n = vec3<f32>(xy, z);
    let length_squared = dot(n, n);
    return select(vec3<f32>(0.0, 0.0, 1.0), n * inverseSqrt(length_squared), length_squared > 0.0);
}

// ---- render::sampling ----
fn cosine_hemisphere(u1: f32, u2: f32) -> vec3<f32> {
    let r = sqrt(u1);
    let phi = 2.0 * PI * u2;
    return vec3<f32>(r * cos(phi), r * sin(phi), sqrt(max(1.0 - u1, 0.0)));
}

// copysign(1, z), as Rust's: -0.0 counts as negative.
fn sign_of(z: f32) -> f32 {
    return select(1.0, -1.0, (bitcast<u32>(z) & 0x80000000u) != 0u);
}

// Duff et al. 2017 (render::sampling::orthonormal_basis); returns the two tangents.
fn basis_tangent(n: vec3<f32>) -> vec3<f32> {
    let s = sign_of(n.z);
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    return vec3<f32>(1.0 + s * n.x * n.x * a, s * b, -s * n.x);
}

fn basis_bitangent(n: vec3<f32>) -> vec3<f32> {
    let s = sign_of(n.z);
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    return vec3<f32>(b, s + n.y * n.y * a, -n.y);
}

// render::sampling::about_axis: `local` (about +Z) in the frame of n.
fn about_axis(n: vec3<f32>, local: vec3<f32>) -> vec3<f32> {
    return basis_tangent(n) * local.x + basis_bitangent(n) * local.y + n * local.z;
}

fn cosine_direction(n: vec3<f32>, u1: f32, u2: f32) -> vec3<f32> {
    return about_axis(n, cosine_hemisphere(u1, u2));
}

// ---- render::optics ----
fn reflect_about(incoming: vec3<f32>, normal: vec3<f32>) -> vec3<f32> {
    return incoming - 2.0 * dot(incoming, normal) * normal;
}

fn fresnel_dielectric(cos_incident: f32, eta: f32) -> f32 {
    let cos_i = clamp(cos_incident, 0.0, 1.0);
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = sqrt(1.0 - sin2_t);
    let r_parallel = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    let r_perpendicular = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    return 0.5 * (r_parallel * r_parallel + r_perpendicular * r_perpendicular);
}

// render::optics::relative_eta: n_incident / n_transmitted at a dielectric of `ior`.
fn relative_eta(ior: f32, front: bool, thin_walled: bool) -> f32 {
    return select(ior, 1.0 / ior, front || thin_walled);
}

// Refraction, or reflection under total internal reflection.
fn refract_or_reflect(incoming: vec3<f32>, normal: vec3<f32>, eta: f32) -> vec3<f32> {
    let cos_i = -dot(incoming, normal);
    let sin2_t = eta * eta * max(1.0 - cos_i * cos_i, 0.0);
    if sin2_t >= 1.0 {
        return reflect_about(incoming, normal);
    }
    let cos_t = sqrt(1.0 - sin2_t);
    return normalize(eta * incoming + (eta * cos_i - cos_t) * normal);
}

// ---- render::normal_map ----
// render::normal_map::texture_frame: the tangent along +u and the bitangent towards the
// image's top about `normal`; `found` false where the coordinates are degenerate.
struct TextureFrame {
    tangent: vec3<f32>,
    bitangent: vec3<f32>,
    found: bool,
}

fn texture_frame(normal: vec3<f32>, p0: vec3<f32>, p1: vec3<f32>, p2: vec3<f32>, uv0: vec2<f32>, uv1: vec2<f32>, uv2: vec2<f32>) -> TextureFrame {
    var frame: TextureFrame;
    let e1 = p1 - p0;
    let e2 = p2 - p0;
    let d1 = uv1 - uv0;
    let d2 = uv2 - uv0;
    let determinant = d1.x * d2.y - d2.x * d1.y;
    if determinant == 0.0 {
        return frame;
    }
    let s = sign(determinant);
    let along_u = s * (e1 * d2.y - e2 * d1.y);
    let towards_top = -s * (e2 * d1.x - e1 * d2.x);
    let unnormalised = along_u - normal * dot(normal, along_u);
    let length_squared = dot(unnormalised, unnormalised);
    // Also false for NaN (and for infinity, which the next test catches).
    if !(length_squared > 0.0) || length_squared > 3.40282347e38 {
        return frame;
    }
    frame.tangent = unnormalised / sqrt(length_squared);
    frame.bitangent = cross(normal, frame.tangent);
    if dot(frame.bitangent, towards_top) < 0.0 {
        frame.bitangent = -frame.bitangent;
    }
    frame.found = true;
    return frame;
}

// render::normal_map::tangent_at: the mesh's tangent at barycentric `b` of packed triangle
// `triangle` (zero: none).
fn tangent_at(triangle: u32, b: vec3<f32>) -> vec4<f32> {
    if !TANGENTS {
        return vec4<f32>(0.0);
    }
    let t0 = vertex_tangents[3u * triangle];
    let t1 = vertex_tangents[3u * triangle + 1u];
    let t2 = vertex_tangents[3u * triangle + 2u];
    if t0.w == 0.0 || t1.w == 0.0 || t2.w == 0.0 {
        return vec4<f32>(0.0);
    }
    let sum = b.x * t0 + b.y * t1 + b.z * t2;
    if sum.w == 0.0 {
        return vec4<f32>(0.0);
    }
    return vec4<f32>(sum.xyz, sign(sum.w));
}

// render::normal_map::FrameSource::frame: the mesh's tangent's frame about `normal`
// (render::normal_map::tangent_frame), else the texture frame.
fn surface_frame(normal: vec3<f32>, p0: vec3<f32>, p1: vec3<f32>, p2: vec3<f32>, uv0: vec2<f32>, uv1: vec2<f32>, uv2: vec2<f32>, tangent: vec4<f32>) -> TextureFrame {
    if TANGENTS && tangent.w != 0.0 {
        let along = tangent.xyz;
        let perpendicular = along - normal * dot(normal, along);
        let length_squared = dot(perpendicular, perpendicular);
        if length_squared > 1e-12 * dot(along, along) && length_squared <= 3.40282347e38 {
            var frame: TextureFrame;
            frame.tangent = perpendicular / sqrt(length_squared);
            frame.bitangent = cross(normal, frame.tangent) * tangent.w;
            frame.found = true;
            return frame;
        }
    }
    return texture_frame(normal, p0, p1, p2, uv0, uv1, uv2);
}

// render::normal_map::brushing: `brush` (in the hit's frame) in the world.
fn brushing(normal: vec3<f32>, p0: vec3<f32>, p1: vec3<f32>, p2: vec3<f32>, uv0: vec2<f32>, uv1: vec2<f32>, uv2: vec2<f32>, mesh_tangent: vec4<f32>, brush: vec2<f32>) -> vec3<f32> {
    var frame = surface_frame(normal, p0, p1, p2, uv0, uv1, uv2, mesh_tangent);
    if !frame.found {
        frame.tangent = basis_tangent(normal);
        frame.bitangent = basis_bitangent(normal);
    }
    return frame.tangent * brush.x + frame.bitangent * brush.y;
}

fn mapped_normal(normal: vec3<f32>, p0: vec3<f32>, p1: vec3<f32>, p2: vec3<f32>, uv0: vec2<f32>, uv1: vec2<f32>, uv2: vec2<f32>, mesh_tangent: vec4<f32>, texel: vec3<f32>, scale: f32) -> vec3<f32> {
    let frame = surface_frame(normal, p0, p1, p2, uv0, uv1, uv2, mesh_tangent);
    if !frame.found {
        return normal;
    }
    let tangent = frame.tangent;
    let bitangent = frame.bitangent;
    let local = texel * 2.0 - vec3<f32>(1.0);
    let bent = tangent * (local.x * scale) + bitangent * (local.y * scale) + normal * local.z;
    return normalize_or(bent, normal);
}

// |d·numerator| / |d·denominator|, 0 where the denominator vanishes.
fn shading_ratio(direction: vec3<f32>, numerator: vec3<f32>, denominator: vec3<f32>) -> f32 {
    let below = abs(dot(direction, denominator));
    if below == 0.0 {
        return 0.0;
    }
    return abs(dot(direction, numerator)) / below;
}

fn arrival_factor(towards_light: vec3<f32>, shading: vec3<f32>, geometric: vec3<f32>) -> f32 {
    if dot(towards_light, shading) <= 0.0 {
        return 0.0;
    }
    return shading_ratio(towards_light, shading, geometric);
}

fn departure_factor(next: vec3<f32>, shading: vec3<f32>, geometric: vec3<f32>) -> f32 {
    return shading_ratio(next, geometric, shading);
}

// ---- render::shadow_terminator ----
fn smooth_position(position: vec3<f32>, p0: vec3<f32>, p1: vec3<f32>, p2: vec3<f32>, n0: vec3<f32>, n1: vec3<f32>, n2: vec3<f32>, barycentric: vec3<f32>) -> vec3<f32> {
    var lifted = position;
    lifted -= (barycentric.x * min(dot(position - p0, n0), 0.0)) * n0;
    lifted -= (barycentric.y * min(dot(position - p1, n1), 0.0)) * n1;
    lifted -= (barycentric.z * min(dot(position - p2, n2), 0.0)) * n2;
    return lifted;
}

const LIFT_THRESHOLD: f32 = 0.01;

fn is_lifted(position: vec3<f32>, shadow_origin: vec3<f32>, geometric: vec3<f32>, epsilon: f32) -> bool {
    return dot(shadow_origin - position, geometric) > LIFT_THRESHOLD * epsilon;
}

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
// Whether the sky has an environment map (render::sky_map, read in sppm.wgsl): compiled out
// otherwise, as NORMAL_MAPS is (its lookups and searches, inlined, made lavapipe's eye pass
// ~10 % slower in scenes without one).
override SKY_MAP: bool = true;

// Whether some material's surface follows a metallic-roughness texture (scene::RoughnessMap);
// compiled out as NORMAL_MAPS is.
override ROUGHNESS_MAPS: bool = true;

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
    if material.roughness_lobe == ROUGHNESS_METAL {
        // scene::metal_surface (scene::brushed_metal_surface for a brushed metal).
        if roughness < MIRROR_MAX_ROUGHNESS && ANISOTROPY && any(material.anisotropy != vec2<f32>(0.0)) {
            mapped.surface = SURFACE_ROUGH_CONDUCTOR;
            mapped.roughness_alpha = max(roughness * roughness, MIN_BRUSHED_ALPHA);
        } else if roughness < MIRROR_MAX_ROUGHNESS {
            mapped.surface = SURFACE_MIRROR;
            mapped.roughness_alpha = 0.0;
        } else if roughness < DIFFUSE_MIN_ROUGHNESS {
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
        if roughness >= DIFFUSE_MIN_ROUGHNESS {
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

// ---- render::medium ----
// The solid a path is inside, for Beer–Lambert absorption; NO_MEDIUM outside every one.
const NO_MEDIUM: u32 = 0xffffffffu;

// Whether some solid absorbs inside (a material with interior absorption); compiled out as
// NORMAL_MAPS is: without one every transmittance is 1 and paths need no medium.
override MEDIA: bool = true;

// render::medium::medium_after.
fn medium_after(medium: u32, root: u32, exterior: u32, solid: bool, front: bool, crosses: bool) -> u32 {
    if !(solid && crosses) {
        return medium;
    }
    return select(exterior, root, front);
}

// render::medium::segment_medium.
fn segment_medium(medium: u32, root: u32, absorbs_inside: bool, front: bool) -> u32 {
    return select(medium, root, !front && absorbs_inside);
}

// cpu::surface::medium_transmittance (render::medium::transmittance): from RAY_T_MAX on the
// distance is infinite.
fn medium_transmittance(medium: u32, distance: f32) -> vec3<f32> {
    if !MEDIA || medium == NO_MEDIUM {
        return vec3<f32>(1.0);
    }
    let absorption = materials[medium].absorption;
    if distance < RAY_T_MAX {
        return exp(-absorption * distance);
    }
    return select(vec3<f32>(1.0), vec3<f32>(0.0), absorption > vec3<f32>(0.0));
}

// cpu::surface::transmittance_to: what a path in `medium` keeps over the segment that ended at
// `hit` (its material still the root one).
fn transmittance_to(medium: u32, hit: SurfaceHit) -> vec3<f32> {
    if !MEDIA {
        return vec3<f32>(1.0);
    }
    let absorbs_inside = max3(materials[hit.material].absorption) > 0.0;
    return medium_transmittance(segment_medium(medium, hit.material, absorbs_inside, hit.front), hit.distance);
}

// cpu::surface::medium_after_bounce.
fn medium_after_bounce(material: GpuMaterial, root: u32, medium: u32, hit: SurfaceHit, next: vec3<f32>) -> u32 {
    let solid = (material.flags & MATERIAL_BOUNDS_VOLUME) != 0u;
    let crosses = dot(next, hit.geometric) < 0.0;
    // The solid around, read only where the path leaves one.
    var exterior = NO_MEDIUM;
    if solid && crosses && !hit.front {
        exterior = materials[root].exterior;
    }
    return medium_after(medium, root, exterior, solid, hit.front, crosses);
}

// ---- render::scattering ----
// Whether some solid scatters inside (a translucent solid or murky glass); compiled out as
// MEDIA is.
override SCATTERING: bool = true;
// Whether some of them is murky glass (MATERIAL_MURKY_GLASS): volume photons, volume visible
// points and their statistics; compiled out as MEDIA is.
override MURKY_GLASS: bool = true;

// render::scattering::murky_glass: whether `medium` is murky glass, where photons are kept as
// they scatter and eye paths end where they scatter.
fn is_murky_glass(medium: u32) -> bool {
    return MURKY_GLASS && medium != NO_MEDIUM && (materials[medium].flags & MATERIAL_MURKY_GLASS) != 0u;
}

// render::scattering::Walk: its hero channel, its weight, and each channel's density of it
// over their mean.
struct Walk {
    hero: u32,
    weight: vec3<f32>,
    densities: vec3<f32>,
}

// render::scattering::Walk::start.
fn walk_start(u: f32) -> Walk {
    return Walk(min(u32(u * 3.0), 2u), vec3<f32>(1.0), vec3<f32>(1.0));
}

// render::scattering::Walk::flight: the distance to the scattering event, or -1 where the
// walk reaches the segment's end.
fn walk_flight(walk: ptr<function, Walk>, extinction: vec3<f32>, scattering: vec3<f32>, distance: f32, u: f32) -> f32 {
    let rate = extinction[(*walk).hero];
    let t = -log(1.0 - u) / max(rate, 1e-30);
    var value: vec3<f32>;
    var density: vec3<f32>;
    var scattered = -1.0;
    if rate > 0.0 && t < distance {
        let kept = exp(-extinction * t);
        value = scattering * kept;
        density = extinction * kept;
        scattered = t;
    } else {
        let kept = exp(-extinction * distance);
        value = kept;
        density = kept;
    }
    let densities = (*walk).densities * density;
    let mean = (densities.x + densities.y + densities.z) / 3.0;
    if mean > 0.0 {
        (*walk).weight *= value / mean;
        (*walk).densities = densities / mean;
    } else {
        (*walk).weight = vec3<f32>(0.0);
    }
    return scattered;
}

// render::scattering::Walk::survives.
fn walk_survives(walk: ptr<function, Walk>, u: f32) -> bool {
    let survival = min(max3((*walk).weight), 1.0);
    if u >= survival {
        return false;
    }
    (*walk).weight /= survival;
    return true;
}

// render::scattering::Walk::weight_over_scattering: the weight after a flight that ended at
// a scattering event over σs (0 in a channel that does not scatter).
fn walk_weight_over_scattering(walk: Walk, scattering: vec3<f32>) -> vec3<f32> {
    let over = walk.weight / max(scattering, vec3<f32>(1.17549435e-38));
    return select(vec3<f32>(0.0), over, scattering > vec3<f32>(0.0));
}

// render::scattering::henyey_greenstein_phase: per steradian, at the cosine between the way
// light travelled and the way it is scattered.
fn henyey_greenstein_phase(g: f32, cos: f32) -> f32 {
    let denominator = max(1.0 + g * g - 2.0 * g * cos, 1e-12);
    return (1.0 - g * g) / (4.0 * PI * denominator * sqrt(denominator));
}

// render::scattering::henyey_greenstein.
fn henyey_greenstein(direction: vec3<f32>, g: f32, u0: f32, u1: f32) -> vec3<f32> {
    var cos_theta = 1.0 - 2.0 * u0;
    if abs(g) >= 1e-3 {
        let s = (1.0 - g * g) / (1.0 - g + 2.0 * g * u0);
        cos_theta = clamp((1.0 + g * g - s * s) / (2.0 * g), -1.0, 1.0);
    }
    let sin_theta = sqrt(max(1.0 - cos_theta * cos_theta, 0.0));
    let phi = 2.0 * PI * u1;
    return to_world(frame_about(direction), vec3<f32>(sin_theta * cos(phi), sin_theta * sin(phi), cos_theta));
}

// render::medium::pack_slot_state, slot_bounced, slot_medium and slot_wavelength.
fn pack_slot_state(bounced: bool, medium: u32, wavelength: u32) -> u32 {
    return ((wavelength + 1u) << WAVELENGTH_SHIFT) | (((medium + 1u) & MEDIUM_MASK) << 1u) | select(0u, 1u, bounced);
}

fn slot_bounced(state: u32) -> bool {
    return (state & 1u) != 0u;
}

fn slot_medium(state: u32) -> u32 {
    return ((state >> 1u) & MEDIUM_MASK) - 1u;
}

fn slot_wavelength(state: u32) -> u32 {
    return (state >> WAVELENGTH_SHIFT) - 1u;
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

// render::iridescence::iridescent_metal.
fn iridescent_metal(base_color: vec3<f32>, film: Film, cos_incident: f32) -> vec3<f32> {
    if film.factor <= 0.0 {
        return base_color;
    }
    let cos_i = clamp(cos_incident, 0.0, 1.0);
    let film_colour = film_reflectance(cos_i, film.ior, film.thickness, ior_from_f0(base_color));
    return mix(base_color, film_colour, min(film.factor, 1.0));
}

// render::iridescence::iridescent_dielectric.
fn iridescent_dielectric(fresnel: f32, film: Film, cos_incident_in: f32, ior: f32, from_outside: bool) -> vec3<f32> {
    if film.factor <= 0.0 {
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
    let film_colour = film_reflectance(cos_outside, film.ior, film.thickness, vec3<f32>(ior));
    return mix(vec3<f32>(fresnel), film_colour, min(film.factor, 1.0));
}

// render::iridescence::rough_dielectric_film_weight.
fn rough_dielectric_film_weight(film: Film, view: vec3<f32>, out: vec3<f32>, normal: vec3<f32>, eta: f32, thin_walled: bool) -> vec3<f32> {
    if film.factor <= 0.0 {
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
    var filmed = iridescent_dielectric(bare, film, cos_view, ior, from_outside);
    if thin_walled {
        bare = 2.0 * bare / (1.0 + bare);
        filmed = 2.0 * filmed / (vec3<f32>(1.0) + filmed);
    }
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

// render::iridescence::metal_tint.
fn metal_tint(base_color: vec3<f32>, film: Film, outgoing: vec3<f32>, incident: vec3<f32>) -> vec3<f32> {
    let half_sum = outgoing + incident;
    let length_sum = length(half_sum);
    var cos_i = 0.0;
    if length_sum > 0.0 {
        cos_i = dot(outgoing, half_sum / length_sum);
    }
    return iridescent_metal(base_color, film, cos_i);
}

// cpu::surface::metal_bounce_tint.
fn metal_bounce_tint(material: GpuMaterial, tint: vec3<f32>, film: Film, incoming: vec3<f32>, next: vec3<f32>) -> vec3<f32> {
    let metal = material.surface == SURFACE_MIRROR || material.surface == SURFACE_ROUGH_CONDUCTOR;
    if IRIDESCENCE && metal && film.factor > 0.0 {
        return metal_tint(tint, film, -incoming, next);
    }
    return tint;
}

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

// cpu::surface::diffuse_bounce: weight 0 where it would go below the geometric surface.
fn diffuse_bounce(hit: SurfaceHit, u1: f32, u2: f32) -> Scattered {
    let next = cosine_direction(hit.shading, u1, u2);
    return Scattered(next, select(0.0, 1.0, dot(next, hit.geometric) > 0.0));
}

// cpu::surface::plastic_bounce (render::plastic::coat_event): `base` true where the light
// passes the coat to the base, whose estimate it multiplies by `base_weight`; otherwise the
// coat's reflection (weight 0 where the path ends).
struct PlasticBounce {
    base: bool,
    base_weight: f32,
    coat: Scattered,
}

fn plastic_bounce(material: GpuMaterial, hit: SurfaceHit, incoming: vec3<f32>, u_choice: f32, u1: f32, u2: f32) -> PlasticBounce {
    let ior = material.ior;
    let alpha = material.roughness_alpha;
    let normal = hit.shading;
    let cos_view = -dot(incoming, normal);
    let none = Scattered(vec3<f32>(0.0), 0.0);
    if alpha == 0.0 {
        if u_choice < coat_reflectance(cos_view, ior) {
            return PlasticBounce(false, 0.0, Scattered(reflect_about(incoming, normal), 1.0));
        }
        return PlasticBounce(true, 1.0, none);
    }
    let frame = frame_about(normal);
    let view = to_local(frame, -incoming);
    if view.z <= 0.0 {
        return PlasticBounce(true, 1.0, none);
    }
    let micro = sample_visible_normal(view, alpha, u1, u2);
    let micro_reflectance = coat_reflectance(dot(view, micro), ior);
    if u_choice < micro_reflectance {
        let out = reflect_about(-view, micro);
        let weight = smith_g1(out, alpha);
        let next = to_world(frame, out);
        if weight <= 0.0 || dot(next, hit.geometric) <= 0.0 {
            return PlasticBounce(false, 0.0, none);
        }
        return PlasticBounce(false, 0.0, Scattered(next, weight));
    }
    return PlasticBounce(true, coat_transmittance_of(hit.material, alpha, cos_view) / (1.0 - micro_reflectance), none);
}

// cpu::surface::specular_direction; only called for non-diffuse surfaces other than plastic.
fn specular_direction(material: GpuMaterial, hit: SurfaceHit, incoming: vec3<f32>, film: Film, u: f32, u_second: f32, u_third: f32) -> Scattered {
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
    let branches = dielectric_branches(material, hit, incoming, film);
    if u < branches.reflectance {
        return Scattered(branches.reflected, 1.0);
    }
    return Scattered(branches.transmitted, 1.0);
}

// cpu::surface::DielectricBranches: reflected with probability `reflectance`, else
// transmitted (refracted; straight on through a thin-walled sheet; reflected at total
// internal reflection); under a thin film each channel's share reflected is
// `film_reflectance`.
struct DielectricBranches {
    reflectance: f32,
    film_reflectance: vec3<f32>,
    reflected: vec3<f32>,
    transmitted: vec3<f32>,
}

// cpu::surface::dielectric_branches.
fn dielectric_branches(material: GpuMaterial, hit: SurfaceHit, incoming: vec3<f32>, film: Film) -> DielectricBranches {
    let normal = hit.shading;
    let thin_walled = (material.flags & MATERIAL_THIN_WALLED) != 0u;
    let eta = relative_eta(material.ior, hit.front, thin_walled);
    let cos_incident = -dot(incoming, normal);
    var reflectance = fresnel_dielectric(cos_incident, eta);
    var film_reflectance = vec3<f32>(reflectance);
    if IRIDESCENCE && film.factor > 0.0 {
        film_reflectance = iridescent_dielectric(reflectance, film, cos_incident, material.ior, hit.front || thin_walled);
    }
    if thin_walled {
        reflectance = 2.0 * reflectance / (1.0 + reflectance);
        film_reflectance = 2.0 * film_reflectance / (vec3<f32>(1.0) + film_reflectance);
    }
    if IRIDESCENCE && film.factor > 0.0 {
        reflectance = (film_reflectance.x + film_reflectance.y + film_reflectance.z) / 3.0;
    }
    let reflected = reflect_about(incoming, normal);
    var transmitted = incoming;
    if !thin_walled {
        transmitted = refract_or_reflect(incoming, normal, eta);
    }
    return DielectricBranches(reflectance, film_reflectance, reflected, transmitted);
}

// cpu::surface::DielectricBranches::weight.
fn branch_weight(branches: DielectricBranches, reflected: bool) -> vec3<f32> {
    if reflected {
        if branches.reflectance > 0.0 {
            return branches.film_reflectance / branches.reflectance;
        }
        return vec3<f32>(0.0);
    }
    if branches.reflectance < 1.0 {
        return (vec3<f32>(1.0) - branches.film_reflectance) / (1.0 - branches.reflectance);
    }
    return vec3<f32>(0.0);
}

// cpu::surface::bounce_tint.
fn bounce_tint_of(material: GpuMaterial, tint: vec3<f32>, film: Film, hit: SurfaceHit, incoming: vec3<f32>, next: vec3<f32>) -> vec3<f32> {
    if IRIDESCENCE && material.surface == SURFACE_DIELECTRIC && film.factor > 0.0 {
        let branches = dielectric_branches(material, hit, incoming, film);
        return tint * branch_weight(branches, all(next == branches.reflected));
    }
    if IRIDESCENCE && material.surface == SURFACE_ROUGH_DIELECTRIC && film.factor > 0.0 {
        let thin_walled = (material.flags & MATERIAL_THIN_WALLED) != 0u;
        let eta = relative_eta(material.ior, hit.front, thin_walled);
        return tint * rough_dielectric_film_weight(film, -incoming, next, hit.shading, eta, thin_walled);
    }
    return metal_bounce_tint(material, tint, film, incoming, next);
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

// ---- render::hash ----
fn hash_cell_size(max_radius: f32) -> f32 {
    return max(2.0 * max_radius * CELL_SLACK, 1.17549435e-38 * 4.0);
}

// render::hash::largest_radius: the inverse of hash_cell_size.
fn largest_radius(cell_size: f32) -> f32 {
    return cell_size * (0.5 / CELL_SLACK);
}

// render::hash::cell_of: the grid offset by half a cell (no boundary on the plane 0).
fn cell_of(position: vec3<f32>, cell_size: f32) -> vec3<i32> {
    return vec3<i32>(floor(position / cell_size + 0.5));
}

// render::buffers::SppmParams::hash_classes.
fn hash_classes() -> u32 {
    return max(params.photon_classes, 1u);
}

// render::hash::photon_class: where the scene keeps classes apart, 1–3 for a photon with a
// channel of zero (its brightest channel, the first of equals), 0 otherwise.
fn photon_class(flux: vec3<f32>) -> u32 {
    if hash_classes() <= 1u || min(min(flux.x, flux.y), flux.z) > 0.0 {
        return 0u;
    }
    if flux.x >= flux.y && flux.x >= flux.z {
        return 1u;
    }
    return select(3u, 2u, flux.y >= flux.z);
}

// render::hash::entry_count: a count word's count, the class marks cleared.
fn class_entry_count(word: u32, classes: u32) -> u32 {
    if classes > 1u {
        return word & ((1u << CLASS_MARK_SHIFT) - 1u);
    }
    return word;
}

// render::hash::class_mark.
fn class_mark(photon_table: u32) -> u32 {
    return 1u << (CLASS_MARK_SHIFT + photon_table - 1u);
}

fn entry_of(cell: vec3<i32>, table_size: u32) -> u32 {
    let h = pcg_hash(bitcast<u32>(cell.x) ^ pcg_hash(bitcast<u32>(cell.y) ^ pcg_hash(bitcast<u32>(cell.z))));
    return h % table_size;
}

// The table entry of the 2×2×2 block's cell `lo + d`, or NO_CELL where that cell lies past
// the gather sphere's box (`span`: 0 or 1 per axis).
const NO_CELL: u32 = 0xffffffffu;

fn block_entry(lo: vec3<i32>, span: vec3<i32>, d: vec3<i32>) -> u32 {
    if any(d > span) {
        return NO_CELL;
    }
    return entry_of(lo + d, params.hash_size);
}

// render::hash::query_entries: the distinct table entries a gather sphere's box touches, in the
// twin's order (x fastest, then y, then z; an entry reached again by a collision kept at its
// first cell). The eight cells of the block from the box's lowest cell, each NO_CELL where
// it is past the box or repeats an earlier entry: fixed slots in two vectors rather than a
// list grown per invocation, which CPU-type adapters (lavapipe) store and read lane by lane
// (the gather took a third less time through lavapipe).
struct QueryEntries {
    low: vec4<u32>,
    high: vec4<u32>,
}

fn query_entries(position: vec3<f32>, radius: f32, cell_size: f32) -> QueryEntries {
    let lo = cell_of(position - vec3<f32>(radius), cell_size);
    let span = min(cell_of(position + vec3<f32>(radius), cell_size) - lo, vec3<i32>(1));
    let a = vec4<u32>(
        block_entry(lo, span, vec3<i32>(0, 0, 0)),
        block_entry(lo, span, vec3<i32>(1, 0, 0)),
        block_entry(lo, span, vec3<i32>(0, 1, 0)),
        block_entry(lo, span, vec3<i32>(1, 1, 0)),
    );
    let b = vec4<u32>(
        block_entry(lo, span, vec3<i32>(0, 0, 1)),
        block_entry(lo, span, vec3<i32>(1, 0, 1)),
        block_entry(lo, span, vec3<i32>(0, 1, 1)),
        block_entry(lo, span, vec3<i32>(1, 1, 1)),
    );
    // Whether each slot repeats an entry of a slot before it.
    let a_seen = vec4<bool>(false, a.y == a.x, any(a.zz == a.xy), any(a.www == a.xyz));
    let b_seen = vec4<bool>(
        any(b.xxxx == a),
        any(b.yyyy == a) || b.y == b.x,
        any(b.zzzz == a) || any(b.zz == b.xy),
        any(b.wwww == a) || any(b.www == b.xyz),
    );
    let none = vec4<u32>(NO_CELL);
    return QueryEntries(select(a, none, a_seen), select(b, none, b_seen));
}

// The entry in slot `slot` (0–7) of a query, or NO_CELL.
fn query_entry(query: QueryEntries, slot: u32) -> u32 {
    if slot < 4u {
        return query.low[slot];
    }
    return query.high[slot - 4u];
}
