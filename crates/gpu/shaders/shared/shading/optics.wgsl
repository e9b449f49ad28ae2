// Twins of render::{optics, sampling, packing, emission, hash} and cpu::surface, split by
// concern under shared/shading/: what the SPPM kernels know about a hit, and the arithmetic
// both eye and photon paths share. This piece: small helpers, render::sampling, render::optics.

fn max3(v: vec3<f32>) -> f32 {
    return max(max(v.x, v.y), v.z);
}

fn sign_not_zero(x: f32) -> f32 {
    return select(-1.0, 1.0, x >= 0.0);
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
