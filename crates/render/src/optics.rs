//! Specular optics shared by the integrators: mirror reflection, Snell refraction, Fresnel.

use glam::Vec3;

/// Mirror reflection of `incoming` about `normal`.
pub fn reflect(incoming: Vec3, normal: Vec3) -> Vec3 {
    incoming - 2.0 * incoming.dot(normal) * normal
}

/// Snell refraction of `incoming` through a surface with `normal` facing it; `eta` = n_i / n_t.
/// `None` on total internal reflection.
pub fn refract(incoming: Vec3, normal: Vec3, eta: f32) -> Option<Vec3> {
    let cos_i = -incoming.dot(normal);
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i).max(0.0);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some((eta * incoming + (eta * cos_i - cos_t) * normal).normalize())
}

/// `eta` = n_incident / n_transmitted where a ray meets a dielectric of `ior` from its `front`
/// (from outside) or from inside; a `thin_walled` sheet has air on both sides of its surface
/// as the ray meets it, so it is always entered from outside.
pub fn relative_eta(ior: f32, front: bool, thin_walled: bool) -> f32 {
    if front || thin_walled { 1.0 / ior } else { ior }
}

/// What an eye path keeps of its weight where it refracts with `eta` = n_from / n_to (its own
/// direction of travel): eta². Radiance squeezes into a denser medium's narrower cone (L / n²
/// is what a ray keeps), so light leaving glass towards the eye has 1 / n² of the radiance it
/// had inside; photons carry flux, which needs no such factor, and the dielectric sampling
/// weights are the photons'. A path that crosses in and out again keeps nothing of it; it
/// counts where an eye path ends inside a solid dielectric (a diffuse surface under water, a
/// blend of glass and plastic) whose photons crossed only once themselves.
pub fn eye_refraction_scale(eta: f32) -> f32 {
    eta * eta
}

/// Unpolarised Fresnel reflectance of a smooth dielectric; 1 under total internal reflection.
pub fn fresnel_dielectric(cos_i: f32, eta: f32) -> f32 {
    let cos_i = cos_i.clamp(0.0, 1.0);
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let r_parallel = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    let r_perpendicular = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    0.5 * (r_parallel * r_parallel + r_perpendicular * r_perpendicular)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fresnel_matches_normal_incidence_formula() {
        // ((n1 - n2) / (n1 + n2))² = 0.04 for air to glass at 1.5.
        assert!((fresnel_dielectric(1.0, 1.0 / 1.5) - 0.04).abs() < 1e-6);
        assert_eq!(
            fresnel_dielectric(0.1, 1.5),
            1.0,
            "total internal reflection"
        );
    }

    #[test]
    fn refraction_obeys_snell() {
        let normal = Vec3::Y;
        let incoming = Vec3::new(0.6, -0.8, 0.0);
        let out = refract(incoming, normal, 1.0 / 1.5).unwrap();
        let sin_t = out.x;
        assert!((sin_t - 0.6 / 1.5).abs() < 1e-6);
        assert!(out.y < 0.0);
    }
}
