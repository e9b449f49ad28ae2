//! Tangent-space normal maps and the shading-normal factors of photon transport, shared by the
//! CPU backend (`cpu::surface`, `cpu::kernels`) and their WGSL twins in
//! `shading/normals.wgsl`.
//!
//! A map's texel (r, g, b) is the normal (2r − 1, 2g − 1, 2b − 1) in a frame whose X runs
//! along increasing u, whose Y points to the image's top (decreasing v: texture rows run top to
//! bottom) and whose Z is the interpolated normal: glTF's convention (and OpenGL's, as Blender
//! and most bakers write it). Where the mesh carries its own tangents (glTF's TANGENT, which
//! exporters fill with MikkTSpace's, the frame maps are baked against) the frame is theirs,
//! interpolated across the triangle as the normal is: X the tangent made perpendicular to the
//! normal, Y = w · normal × X. The glTF loader makes tangents where a file has none for a
//! material that reads a frame (from the texture coordinates, angle-weighted at each vertex and
//! split at mirror seams, as glTF's MikkTSpace does). Elsewhere (OBJ
//! meshes, scenes built in code, a vertex whose tangent vanished) the frame is each
//! triangle's own, from its texture-coordinate gradients.

use glam::{Vec2, Vec3, Vec4};

/// What a hit's tangent frame is made from: the triangle's corner `positions` and texture
/// coordinates `uvs`, and the mesh's tangent interpolated at the hit ([`tangent_at`]; zero:
/// none).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameSource {
    pub positions: [Vec3; 3],
    pub uvs: [Vec2; 3],
    pub tangent: Vec4,
}

impl FrameSource {
    /// The frame about unit `normal`: the mesh's tangent's ([`tangent_frame`]) where it has
    /// one that is not along the normal, else the texture frame ([`texture_frame`]).
    pub fn frame(&self, normal: Vec3) -> Option<(Vec3, Vec3)> {
        tangent_frame(normal, self.tangent)
            .or_else(|| texture_frame(normal, self.positions, self.uvs))
    }
}

/// The mesh's tangents of each triangle in a packed tree's order (`triangle_ids`, as
/// `bvh::PackedBvh::triangle_ids`), corner by corner; empty where no vertex has one.
pub fn packed_tangents(scene: &scene::Scene, triangle_ids: &[u32]) -> Vec<[Vec4; 3]> {
    if !scene.has_vertex_tangents() {
        return Vec::new();
    }
    let corners = |id: &u32| scene.triangles[*id as usize].vertices.map(|v| v.tangent);
    triangle_ids.iter().map(corners).collect()
}

/// The mesh's tangent at barycentric coordinates `barycentric` from its corners' `tangents`
/// (glTF TANGENT: xyz, w = ±1): the directions interpolated, the handedness the weighted
/// corners' sign; zero (none) where a corner has none.
pub fn tangent_at(tangents: [Vec4; 3], barycentric: [f32; 3]) -> Vec4 {
    if tangents.iter().any(|t| t.w == 0.0) {
        return Vec4::ZERO;
    }
    let [a, b, c] = barycentric;
    let sum = a * tangents[0] + b * tangents[1] + c * tangents[2];
    if sum.w == 0.0 {
        return Vec4::ZERO;
    }
    sum.truncate().extend(sum.w.signum())
}

/// The frame of the mesh's `tangent` (w: the handedness, 0: none) about unit `normal`: the
/// tangent made perpendicular to the normal and unit, and w · normal × it; `None` without a
/// tangent or where it runs along the normal.
pub fn tangent_frame(normal: Vec3, tangent: Vec4) -> Option<(Vec3, Vec3)> {
    if tangent.w == 0.0 {
        return None;
    }
    let along = tangent.truncate();
    let perpendicular = along - normal * normal.dot(along);
    let length_squared = perpendicular.length_squared();
    if !(length_squared > 1e-12 * along.length_squared() && length_squared.is_finite()) {
        return None;
    }
    let tangent_unit = perpendicular / length_squared.sqrt();
    Some((tangent_unit, normal.cross(tangent_unit) * tangent.w))
}

/// The texture frame about unit `normal` on the triangle with corner `positions` and texture
/// coordinates `uvs`: a unit tangent along increasing u (perpendicular to `normal`) and the
/// bitangent towards the image's top (mirrored coordinates turn it left-handed); `None` where
/// the coordinates are degenerate (no gradient).
pub fn texture_frame(normal: Vec3, positions: [Vec3; 3], uvs: [Vec2; 3]) -> Option<(Vec3, Vec3)> {
    let (e1, e2) = (positions[1] - positions[0], positions[2] - positions[0]);
    let (d1, d2) = (uvs[1] - uvs[0], uvs[2] - uvs[0]);
    let determinant = d1.x * d2.y - d2.x * d1.y;
    if determinant == 0.0 {
        return None;
    }
    // dp/du and −dp/dv times |determinant| (their lengths do not matter, only directions).
    let sign = determinant.signum();
    let along_u = sign * (e1 * d2.y - e2 * d1.y);
    let towards_top = -sign * (e2 * d1.x - e1 * d2.x);
    let tangent = along_u - normal * normal.dot(along_u);
    let length_squared = tangent.length_squared();
    if length_squared <= 0.0 || !length_squared.is_finite() {
        return None;
    }
    let tangent = tangent / length_squared.sqrt();
    let bitangent = normal.cross(tangent);
    // Mirrored texture coordinates turn the frame left-handed.
    let bitangent = if bitangent.dot(towards_top) < 0.0 {
        -bitangent
    } else {
        bitangent
    };
    Some((tangent, bitangent))
}

/// A brushed metal's brushing at a hit (`render::microfacet::brushed_reflection`): `brush`,
/// given in the hit's frame about unit `normal` ([`FrameSource::frame`]; any frame about it
/// where there is none), in the world, its length (the strength) kept.
pub fn brushing(normal: Vec3, source: &FrameSource, brush: Vec2) -> Vec3 {
    let (tangent, bitangent) = source
        .frame(normal)
        .unwrap_or_else(|| crate::sampling::orthonormal_basis(normal));
    tangent * brush.x + bitangent * brush.y
}

/// `normal` (unit, interpolated) bent by a map's linear `texel` in the hit's frame
/// ([`FrameSource::frame`]); `scale` multiplies the texel's X and Y (glTF's
/// `normalTexture.scale`). The normal as it was where there is no frame (no tangent and
/// degenerate coordinates) or the bent normal vanishes.
pub fn mapped_normal(normal: Vec3, source: &FrameSource, texel: Vec3, scale: f32) -> Vec3 {
    let Some((tangent, bitangent)) = source.frame(normal) else {
        return normal;
    };
    let local = texel * 2.0 - Vec3::ONE;
    let bent = tangent * (local.x * scale) + bitangent * (local.y * scale) + normal * local.z;
    bent.try_normalize().unwrap_or(normal)
}

/// What a photon's flux is weighted by where it is stored at a surface whose shading normal
/// differs from its geometric one: photons land in proportion to the geometric cosine, the
/// eye's reflected light follows the shading one (Veach 1997, §5.3). `towards_light` points
/// back along the photon; both normals are unit and on its side. 0 where the photon grazes the
/// geometric surface or arrives from behind the shading normal: the eye's side counts no light
/// from there (its light samples and bounces keep to the shading normal's hemisphere).
pub fn arrival_factor(towards_light: Vec3, shading: Vec3, geometric: Vec3) -> f32 {
    if towards_light.dot(shading) <= 0.0 {
        return 0.0;
    }
    shading_ratio(towards_light, shading, geometric)
}

/// The factor a photon's flux takes on, with [`arrival_factor`], when a bounce sends it on in
/// `next`: the geometric cosine over the shading one. Together they are Veach's correction of
/// the adjoint BSDF for shading normals, |ωᵢ·nₛ| |ωₒ·n_g| / (|ωᵢ·n_g| |ωₒ·nₛ|), which every
/// scattering of a photon takes (diffuse, mirror, glass, rough): the eye's side weighs its
/// paths by the shading normal, and this keeps the photons' light equal to what it counts.
pub fn departure_factor(next: Vec3, shading: Vec3, geometric: Vec3) -> f32 {
    shading_ratio(next, geometric, shading)
}

/// The most Veach's correction may weigh a photon by at one surface: the [`arrival_factor`]
/// where it lands, or that times the [`departure_factor`] where it goes on. Unbounded, the
/// ratio of cosines grows without limit where a photon grazes the geometric surface of a
/// coarse smooth mesh (on `scenes/cornell-murky.gltf`'s 960-triangle quartz ball, whose
/// vertex normals lean up to 7° from its facets: geometric cosines down to 0.007, arrival
/// factors to 16, a bounce's product to 40), and a glass ball's internal reflections, which
/// keep their angle, multiply it from bounce to bounce: photons thousands of times the
/// light's (measured: 9.3e9 where the lamp emits 7.3e5 a photon), the ball's fireflies. At 4,
/// that scene's ball came out 0.2 % darker (100 passes, 256²: noise level), its firefly gone;
/// normal maps and fine meshes keep factors far below it (session 42).
pub const MAX_SHADING_CORRECTION: f32 = 4.0;

/// Veach's correction `factor` at one surface, bounded ([`MAX_SHADING_CORRECTION`]).
pub fn bounded_correction(factor: f32) -> f32 {
    factor.min(MAX_SHADING_CORRECTION)
}

/// |d·numerator| / |d·denominator|, 0 where the denominator vanishes.
fn shading_ratio(direction: Vec3, numerator: Vec3, denominator: Vec3) -> f32 {
    let below = direction.dot(denominator).abs();
    if below == 0.0 {
        return 0.0;
    }
    direction.dot(numerator).abs() / below
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The frame of the triangle's coordinates alone (no mesh tangent).
    fn uv_frame(positions: [Vec3; 3], uvs: [Vec2; 3]) -> FrameSource {
        FrameSource {
            positions,
            uvs,
            tangent: Vec4::ZERO,
        }
    }

    /// A unit quad's lower triangle in the XY plane, u along +X and v growing towards −Y (the
    /// image upright when seen from +Z).
    fn upright() -> ([Vec3; 3], [Vec2; 3]) {
        (
            [Vec3::ZERO, Vec3::X, Vec3::Y],
            [
                Vec2::new(0.0, 1.0),
                Vec2::new(1.0, 1.0),
                Vec2::new(0.0, 0.0),
            ],
        )
    }

    #[test]
    fn a_flat_texel_keeps_the_normal() {
        let (p, uv) = upright();
        let n = mapped_normal(Vec3::Z, &uv_frame(p, uv), Vec3::new(0.5, 0.5, 1.0), 1.0);
        assert!((n - Vec3::Z).length() < 1e-6, "{n}");
    }

    #[test]
    fn red_tilts_along_u_and_green_towards_the_top() {
        let (p, uv) = upright();
        let right = mapped_normal(Vec3::Z, &uv_frame(p, uv), Vec3::new(1.0, 0.5, 0.5), 1.0);
        assert!((right - Vec3::X).length() < 1e-6, "{right}");
        let up = mapped_normal(Vec3::Z, &uv_frame(p, uv), Vec3::new(0.5, 1.0, 0.5), 1.0);
        assert!((up - Vec3::Y).length() < 1e-6, "{up}");
        // 45° towards the top, halved by the scale.
        let half = mapped_normal(Vec3::Z, &uv_frame(p, uv), Vec3::new(0.5, 1.0, 1.0), 0.5);
        assert!((half - Vec3::new(0.0, 0.5, 1.0).normalize()).length() < 1e-6);
    }

    #[test]
    fn mirrored_coordinates_mirror_the_frame() {
        // u runs along −X now: red tilts towards −X; green still towards the image's top, +Y.
        let p = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let uv = [
            Vec2::new(1.0, 1.0),
            Vec2::new(0.0, 1.0),
            Vec2::new(1.0, 0.0),
        ];
        let right = mapped_normal(Vec3::Z, &uv_frame(p, uv), Vec3::new(1.0, 0.5, 0.5), 1.0);
        assert!((right + Vec3::X).length() < 1e-6, "{right}");
        let up = mapped_normal(Vec3::Z, &uv_frame(p, uv), Vec3::new(0.5, 1.0, 0.5), 1.0);
        assert!((up - Vec3::Y).length() < 1e-6, "{up}");
    }

    #[test]
    fn the_frame_follows_a_rotated_triangle_and_a_bent_interpolated_normal() {
        // The quad turned to face +X (u along −Z... here along +Y, top towards +Z).
        let p = [Vec3::ZERO, Vec3::Y, Vec3::Z];
        let uv = [
            Vec2::new(0.0, 1.0),
            Vec2::new(1.0, 1.0),
            Vec2::new(0.0, 0.0),
        ];
        let right = mapped_normal(Vec3::X, &uv_frame(p, uv), Vec3::new(1.0, 0.5, 0.5), 1.0);
        assert!((right - Vec3::Y).length() < 1e-6, "{right}");
        // An interpolated normal tilted from the face: the tangent is made orthogonal to it.
        let n = Vec3::new(1.0, 0.0, 0.3).normalize();
        let flat = mapped_normal(n, &uv_frame(p, uv), Vec3::new(0.5, 0.5, 1.0), 1.0);
        assert!((flat - n).length() < 1e-6);
        let bent = mapped_normal(n, &uv_frame(p, uv), Vec3::new(1.0, 0.5, 0.5), 1.0);
        assert!(
            bent.dot(n).abs() < 1e-6 && (bent - Vec3::Y).length() < 1e-6,
            "{bent}"
        );
    }

    #[test]
    fn degenerate_coordinates_keep_the_normal() {
        let (p, _) = upright();
        let same = [Vec2::splat(0.25); 3];
        let n = mapped_normal(Vec3::Z, &uv_frame(p, same), Vec3::new(1.0, 0.5, 0.5), 1.0);
        assert_eq!(n, Vec3::Z);
    }

    #[test]
    fn a_mesh_tangent_gives_the_frame() {
        let (p, uv) = upright();
        // Along the texture frame's own axes: the same normals.
        let along_u = FrameSource {
            tangent: Vec4::new(1.0, 0.0, 0.0, 1.0),
            ..uv_frame(p, uv)
        };
        for texel in [Vec3::new(1.0, 0.5, 0.5), Vec3::new(0.5, 1.0, 0.5)] {
            let from_uv = mapped_normal(Vec3::Z, &uv_frame(p, uv), texel, 1.0);
            let from_tangent = mapped_normal(Vec3::Z, &along_u, texel, 1.0);
            assert!((from_uv - from_tangent).length() < 1e-6, "{from_tangent}");
        }
        // Turned a quarter about the normal: red tilts along +Y, green along −X; left-handed
        // (w = −1), green along +X.
        let turned = FrameSource {
            tangent: Vec4::new(0.0, 2.0, 0.0, 1.0),
            ..uv_frame(p, uv)
        };
        let right = mapped_normal(Vec3::Z, &turned, Vec3::new(1.0, 0.5, 0.5), 1.0);
        assert!((right - Vec3::Y).length() < 1e-6, "{right}");
        let up = mapped_normal(Vec3::Z, &turned, Vec3::new(0.5, 1.0, 0.5), 1.0);
        assert!((up + Vec3::X).length() < 1e-6, "{up}");
        let left_handed = FrameSource {
            tangent: Vec4::new(0.0, 2.0, 0.0, -1.0),
            ..turned
        };
        let up = mapped_normal(Vec3::Z, &left_handed, Vec3::new(0.5, 1.0, 0.5), 1.0);
        assert!((up - Vec3::X).length() < 1e-6, "{up}");
        // A tangent along the normal gives no frame: the coordinates' serves.
        let along_normal = FrameSource {
            tangent: Vec4::new(0.0, 0.0, 1.0, 1.0),
            ..uv_frame(p, uv)
        };
        let right = mapped_normal(Vec3::Z, &along_normal, Vec3::new(1.0, 0.5, 0.5), 1.0);
        assert!((right - Vec3::X).length() < 1e-6, "{right}");
    }

    #[test]
    fn tangents_interpolate_and_need_every_corner() {
        let x = Vec4::new(1.0, 0.0, 0.0, 1.0);
        let y = Vec4::new(0.0, 1.0, 0.0, 1.0);
        let t = tangent_at([x, y, x], [0.25, 0.5, 0.25]);
        assert_eq!(t, Vec4::new(0.5, 0.5, 0.0, 1.0));
        assert_eq!(tangent_at([x, Vec4::ZERO, x], [0.4, 0.2, 0.4]), Vec4::ZERO);
        let flipped = tangent_at([-x, -x, x.truncate().extend(-1.0)], [0.3, 0.3, 0.4]);
        assert_eq!(flipped.w, -1.0);
    }

    #[test]
    fn the_shading_factors_are_cosine_ratios_and_one_without_a_bent_normal() {
        let g = Vec3::Z;
        let s = Vec3::new(0.0, 0.6, 0.8);
        let w = Vec3::new(0.0, 0.8, 0.6);
        assert!((arrival_factor(w, s, g) - 0.96 / 0.6).abs() < 1e-6);
        assert!((departure_factor(w, s, g) - 0.6 / 0.96).abs() < 1e-6);
        // Bounded where the photon grazes the geometric surface; below the bound, kept.
        let grazing = Vec3::new(0.0, 1.0, 0.01).normalize();
        assert!(arrival_factor(grazing, s, g) > 20.0);
        assert_eq!(bounded_correction(25.0), MAX_SHADING_CORRECTION);
        assert_eq!(bounded_correction(0.96 / 0.6), 0.96 / 0.6);
        assert_eq!(arrival_factor(w, g, g), 1.0);
        assert_eq!(departure_factor(w, g, g), 1.0);
        assert_eq!(arrival_factor(Vec3::X, s, g), 0.0);
        // Above the geometric surface but behind the bent normal: no light for the eye.
        let behind = Vec3::new(0.0, -0.9, 0.3).normalize();
        assert!(behind.dot(g) > 0.0 && behind.dot(s) < 0.0);
        assert_eq!(arrival_factor(behind, s, g), 0.0);
    }
}
