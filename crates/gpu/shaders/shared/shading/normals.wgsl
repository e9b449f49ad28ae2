// The shading normal at a hit: normal maps and the frames they (and brushing) are given in,
// the factors where it is not the geometric normal, and the shadow terminator's lift.

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

// render::normal_map::MAX_SHADING_CORRECTION and bounded_correction.
const MAX_SHADING_CORRECTION: f32 = 4.0;

fn bounded_correction(factor: f32) -> f32 {
    return min(factor, MAX_SHADING_CORRECTION);
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
