//! What the kernels know about a hit, read from the packed triangles exactly as the WGSL
//! kernels read them, and the specular events both eye and photon paths take.

use glam::{Vec2, Vec3, Vec4};
#[cfg(doc)]
use render::buffers::MAX_PASS_THROUGHS;
use render::buffers::{RAY_T_MAX, SppmParams};
use render::clearcoat::{ClearcoatEvent, clearcoat_at, clearcoat_event, clearcoat_numbers};
use render::conductor::Metal;
use render::dielectric_layer::{
    DielectricLayer, LayerReflectance, layered_reflectance, rough_dielectric_layer_weight,
};
use render::dispersion::{disperse, draws_wavelength};
use render::iridescence::{Film, film_share};
use render::medium::{NO_MEDIUM, medium_after, segment_medium, transmittance};
use render::microfacet::{brushed_reflection, rough_dielectric, rough_reflection};
use render::normal_map::{FrameSource, brushing, mapped_normal, tangent_at};
use render::optics::{eye_refraction_scale, fresnel_dielectric, reflect, refract, relative_eta};
use render::plastic::{Coat, CoatEvent, layered_coat_event};
use render::sampling::{cosine_hemisphere, orthonormal_basis};
use render::shadow_terminator::shadow_origin;
use render::sheen::{SheenAt, SheenEvent};
use render::textures::TextureArray;
use scene::{AlphaMode, Clearcoat, Material, Surface};

use crate::SceneData;

/// A ray's hit, turned to face the side the ray came from.
#[derive(Clone, Copy, Debug)]
pub struct SurfaceHit {
    pub position: Vec3,
    /// Where shadow rays from the hit start: `position` lifted onto the smooth surface of the
    /// vertex normals (`render::shadow_terminator`) when the ray came from their side.
    pub shadow_origin: Vec3,
    /// How far along the ray it lies.
    pub distance: f32,
    /// Unit geometric normal on the ray's side.
    pub geometric: Vec3,
    /// Unit shading normal on the ray's side: interpolated, then bent by the material's normal
    /// map if it has one (the geometric one where that turns it below the surface).
    pub shading: Vec3,
    /// The same before the normal map: the interpolated normal (bent by the clear coat's own
    /// normal map where it has one), which a clear coat over the
    /// material follows (glTF's coat has a normal of its own).
    pub interpolated: Vec3,
    pub uv: Vec2,
    pub material: u32,
    /// Whether the ray met the triangle's front (counter-clockwise) face.
    pub front: bool,
    /// A brushed metal's brushing here (`render::normal_map::brushing`, from the root
    /// material's `scene::Anisotropy`): its direction times its strength; zero elsewhere.
    pub brush: Vec3,
}

impl SurfaceHit {
    /// The same point seen from the other side of the surface: where glTF's diffuse
    /// transmission sends light through, the Lambertian lobe lies on that side (no lift onto
    /// the smooth surface there: it was the arriving side's).
    pub fn flipped(&self) -> SurfaceHit {
        SurfaceHit {
            shadow_origin: self.position,
            geometric: -self.geometric,
            shading: -self.shading,
            interpolated: -self.interpolated,
            front: !self.front,
            ..*self
        }
    }
}

/// glTF's diffuse transmission of `material` at `uv` (`scene::DiffuseTransmission`): the
/// share of its Lambertian lobe's light that leaves from the other side, and that light's
/// tint; `None` where the material has none.
pub fn diffuse_transmission_at(
    scene: &SceneData,
    material: &Material,
    uv: Vec2,
) -> Option<(f32, Vec3)> {
    diffuse_transmission_of(material, |id| texture(&scene.textures, id, uv))
}

/// [`diffuse_transmission_at`] with the hit's texels read by `texel` (white for `None`).
pub fn diffuse_transmission_of(
    material: &Material,
    texel: impl Fn(Option<u32>) -> Vec4,
) -> Option<(f32, Vec3)> {
    let transmission = material.diffuse_transmission?;
    let share = transmission.factor * texel(transmission.texture).w;
    let tint = transmission.color * texel(transmission.color_texture).truncate();
    Some((share.clamp(0.0, 1.0), tint))
}

/// The side of `hit` a Lambertian lobe sends its light to and takes it from, and the lobe's
/// tint there: the far side with the transmission's tint where glTF's diffuse transmission
/// (`(share, tint)` from [`diffuse_transmission_at`]) is chosen by `u` below the share, else
/// the hit and `reflected` (the base colour). The choice's probability is the share, so
/// neither side's weight carries it.
pub fn lambertian_side(
    hit: &SurfaceHit,
    reflected: Vec3,
    (share, tint): (f32, Vec3),
    u: f32,
) -> (SurfaceHit, Vec3) {
    if u < share {
        (hit.flipped(), tint)
    } else {
        (*hit, reflected)
    }
}

/// A brushed metal's brushing (`render::normal_map::brushing`) at a hit on `material` (the
/// root: every member carries its anisotropy) with unit interpolated `normal`, in the frame
/// `source` makes, its texture read by `texel`; zero without anisotropy.
pub fn brush_at(
    material: &Material,
    texel: impl Fn(u32) -> Vec4,
    normal: Vec3,
    source: &FrameSource,
) -> Vec3 {
    let Some(anisotropy) = material.anisotropy else {
        return Vec3::ZERO;
    };
    brushing(normal, source, anisotropy.at(anisotropy.texture.map(texel)))
}

/// The mesh's tangent at barycentric coordinates `barycentric` of packed triangle `triangle`
/// (zero where the scene has none).
pub fn tangent_of(scene: &SceneData, triangle: u32, barycentric: [f32; 3]) -> Vec4 {
    scene
        .tangents
        .get(triangle as usize)
        .map_or(Vec4::ZERO, |&corners| tangent_at(corners, barycentric))
}

/// Closest hit along a ray, or `None` if it leaves the scene.
pub fn trace(scene: &SceneData, origin: Vec3, direction: Vec3) -> Option<SurfaceHit> {
    trace_within(scene, origin, direction, RAY_T_MAX)
}

/// Closest hit along a ray closer than `t_max`.
pub fn trace_within(
    scene: &SceneData,
    origin: Vec3,
    direction: Vec3,
    t_max: f32,
) -> Option<SurfaceHit> {
    let ray = bvh::Ray {
        origin,
        direction,
        t_max,
    };
    let hit = bvh::closest_hit_cpu(&scene.bvh, scene.wide.as_ref(), &ray)?;
    let triangle = scene.bvh.triangles[hit.triangle as usize].unpack();
    let [a, b, c] = triangle.vertices;
    let geometric = triangle
        .geometric_normal_unnormalized()
        .normalize_or(Vec3::Z);
    let w = 1.0 - hit.u - hit.v;
    let position = origin + hit.t * direction;
    let positions = [a.position, b.position, c.position];
    let normals = [a.normal, b.normal, c.normal];
    let interpolated = w * a.normal + hit.u * b.normal + hit.v * c.normal;
    let barycentric = [w, hit.u, hit.v];
    let shadow_origin = shadow_origin(
        position,
        direction,
        interpolated,
        positions,
        normals,
        barycentric,
    );
    let unit_interpolated = interpolated.normalize_or(geometric);
    let mut shading = unit_interpolated;
    let uvs = [a.uv, b.uv, c.uv];
    let uv = uv_at(uvs, hit.u, hit.v);
    let material = &scene.materials[triangle.material as usize];
    // The frame normal maps and brushing are given in: the mesh's tangent, or the texture's.
    let source = FrameSource {
        positions,
        uvs,
        tangent: tangent_of(scene, hit.triangle, barycentric),
    };
    if let Some(map) = material.normal_texture {
        let texel = scene.textures.sample(map, uv).truncate();
        shading = mapped_normal(shading, &source, texel, material.normal_scale);
    }
    let texel = |t| scene.textures.sample(t, uv);
    let brush = brush_at(material, texel, unit_interpolated, &source);
    // A clear coat with a normal map of its own follows it.
    let mut coat_normal = unit_interpolated;
    if let Some(coat) = material.clearcoat
        && let Some(map) = coat.normal_texture
    {
        let texel = scene.textures.sample(map, uv).truncate();
        coat_normal = mapped_normal(coat_normal, &source, texel, coat.normal_scale);
    }
    let front = direction.dot(geometric) < 0.0;
    let side = if front { 1.0 } else { -1.0 };
    let (geometric, mut shading) = (side * geometric, side * shading);
    let mut interpolated = side * coat_normal;
    if shading.dot(geometric) <= 0.0 {
        shading = geometric;
    }
    if interpolated.dot(geometric) <= 0.0 {
        interpolated = geometric;
    }
    Some(SurfaceHit {
        position,
        shadow_origin,
        distance: hit.t,
        geometric,
        shading,
        interpolated,
        uv,
        material: triangle.material,
        front,
        brush,
    })
}

/// Whether nothing blocks the segment from `origin` along `direction` for `distance`: the
/// holes of alpha cut-outs let it through, anything else stops it, glass included (light
/// through glass reaches the eye as photons: a caustic). Without cut-outs in the scene any hit
/// decides at once; with them, the traversal tests each hit's alpha in the leaf (the WGSL twin
/// passes through hole after hole from the closest hit, up to [`MAX_PASS_THROUGHS`] of them:
/// the same answer unless a ray meets more holes than that).
pub fn unoccluded(
    scene: &SceneData,
    params: &SppmParams,
    origin: Vec3,
    direction: Vec3,
    distance: f32,
) -> bool {
    let ray = bvh::Ray {
        origin,
        direction,
        t_max: distance,
    };
    let (tree, wide) = (&scene.bvh, scene.wide.as_ref());
    if params.cut_outs == 0 {
        return !bvh::any_hit_cpu(tree, wide, &ray);
    }
    !bvh::any_hit_cpu_where(tree, wide, &ray, |hit| occludes(scene, hit))
}

/// Whether a ray's hit stops light: any surface but an alpha cut-out's hole.
fn occludes(scene: &SceneData, hit: &bvh::Hit) -> bool {
    let packed = &scene.bvh.triangles[hit.triangle as usize];
    let material = &scene.materials[packed.material() as usize];
    // Most hits are opaque: no texture coordinates to read for them.
    if matches!(material.alpha_mode, AlphaMode::Opaque) {
        return true;
    }
    let uvs = packed.vertices.map(|v| Vec2::new(v.u, v.v));
    !is_cut_out(scene, material, uv_at(uvs, hit.u, hit.v))
}

/// The texture coordinates at barycentrics `(u, v)` of a triangle whose corners have `uvs`.
fn uv_at(uvs: [Vec2; 3], u: f32, v: f32) -> Vec2 {
    (1.0 - u - v) * uvs[0] + u * uvs[1] + v * uvs[2]
}

/// Where a ray leaving `hit` in `direction` starts: off the surface on the side it goes.
pub fn offset_origin(hit: &SurfaceHit, direction: Vec3, epsilon: f32) -> Vec3 {
    let side = if direction.dot(hit.geometric) >= 0.0 {
        1.0
    } else {
        -1.0
    };
    hit.position + side * epsilon * hit.geometric
}

/// Where a shadow ray from `hit` starts: off the smooth surface (`SurfaceHit::shadow_origin`)
/// on the side the hit was seen from, where the light is.
pub fn shadow_ray_origin(hit: &SurfaceHit, epsilon: f32) -> Vec3 {
    hit.shadow_origin + epsilon * hit.geometric
}

/// A texture's linear RGBA at `uv` (bilinear, repeat), white for none: `sample_texture` of
/// `textures.wgsl`.
pub fn texture(textures: &TextureArray, id: Option<u32>, uv: Vec2) -> Vec4 {
    id.map_or(Vec4::ONE, |t| textures.sample(t, uv))
}

/// A hit's texel of the texture `render::blend` asks for (a material's metallic-roughness
/// texture, asked once for the blend's weight and again for each member's surface), sampled
/// once per texture.
pub struct HitTexel<'a> {
    textures: &'a TextureArray,
    uv: Vec2,
    sampled: std::cell::Cell<Option<(u32, Vec4)>>,
}

impl<'a> HitTexel<'a> {
    pub fn new(textures: &'a TextureArray, uv: Vec2) -> HitTexel<'a> {
        HitTexel {
            textures,
            uv,
            sampled: std::cell::Cell::new(None),
        }
    }

    /// Texture `id`'s texel at the hit.
    pub fn get(&self, id: u32) -> Vec4 {
        match self.sampled.get() {
            Some((sampled, texel)) if sampled == id => texel,
            _ => {
                let texel = self.textures.sample(id, self.uv);
                self.sampled.set(Some((id, texel)));
                texel
            }
        }
    }
}

/// Whether an alpha cut-out lets the ray through here.
pub fn is_cut_out(scene: &SceneData, material: &Material, uv: Vec2) -> bool {
    match material.alpha_mode {
        AlphaMode::Opaque => false,
        AlphaMode::Mask { cutoff } => {
            material.alpha * texture(&scene.textures, material.base_color_texture, uv).w < cutoff
        }
    }
}

/// Base colour × texture: a diffuse surface's albedo, a specular one's tint.
pub fn base_color(scene: &SceneData, material: &Material, uv: Vec2) -> Vec3 {
    material.base_color * texture(&scene.textures, material.base_color_texture, uv).truncate()
}

/// The thin film on `material` at texture coordinates `uv` (glTF's iridescence:
/// `render::iridescence::Film`, factor 0 for none).
pub fn hit_film(scene: &SceneData, material: &Material, uv: Vec2) -> Film {
    let Some(iridescence) = material.iridescence else {
        return Film::default();
    };
    let texel = |id: Option<u32>| id.map(|id| texture(&scene.textures, Some(id), uv));
    Film::of(
        &iridescence,
        texel(iridescence.texture),
        texel(iridescence.thickness_texture),
    )
}

/// What lies on plastic's coat at texture coordinates `uv` (`render::dielectric_layer::DielectricLayer`):
/// glTF's specular layer (`render::dielectric_layer`) and thin film ([`hit_film`]).
pub fn hit_dielectric_layer(scene: &SceneData, material: &Material, uv: Vec2) -> DielectricLayer {
    let texel = |id: Option<u32>| id.map(|id| texture(&scene.textures, Some(id), uv));
    DielectricLayer {
        specular: (material.specular.as_ref())
            .map(|s| LayerReflectance::of(s, texel(s.texture), texel(s.color_texture))),
        film: hit_film(scene, material, uv),
    }
}

/// What a bounce of `incoming` into `next` at `hit` on a `surface` of colour `tint` keeps
/// under the `layer` on it (glTF's thin film, and on glass its specular layer): a metal's
/// reflection its Fresnel reflectance at the bounce's angle, rising from `tint` by
/// `metal_edge` (`scene::Material::metal_edge`), under the film ([`metal_bounce_tint`]); smooth
/// glass's reflection or transmission the layer's share of that way over the choice's
/// probability ([`DielectricBranches::weight`]), frosted glass's at its micro-normal
/// (`render::dielectric_layer::rough_dielectric_layer_weight`); every other bounce, and every
/// bounce without a layer, `tint`.
pub fn bounce_tint(
    surface: Surface,
    (tint, metal_edge): (Vec3, Vec3),
    layer: DielectricLayer,
    hit: &SurfaceHit,
    (incoming, next): (Vec3, Vec3),
) -> Vec3 {
    match surface {
        Surface::Dielectric { ior, thin_walled } if !layer.is_bare() => {
            let branches = dielectric_branches(hit, incoming, ior, thin_walled, layer);
            tint * branches.weight(next == branches.reflected)
        }
        Surface::RoughDielectric {
            ior, thin_walled, ..
        } if !layer.is_bare() => {
            let eta = relative_eta(ior, hit.front, thin_walled);
            let ways = (-incoming, next);
            tint * rough_dielectric_layer_weight(layer, ways, hit.shading, eta, thin_walled)
        }
        _ => metal_bounce_tint(surface, (tint, metal_edge), layer.film, (incoming, next)),
    }
}

/// A metal's reflection (mirror or rough) of `incoming` into `next` under a thin `film`: its
/// reflectance at the angle to the bounce's micro-normal (`render::conductor::Metal::tint`)
/// from its colour `f0`; every other bounce `f0`.
fn metal_bounce_tint(
    surface: Surface,
    (f0, edge): (Vec3, Vec3),
    film: Film,
    (incoming, next): (Vec3, Vec3),
) -> Vec3 {
    match surface {
        Surface::Mirror | Surface::RoughConductor { .. } => {
            Metal { f0, edge, film }.tint(-incoming, next)
        }
        _ => f0,
    }
}

/// Radiance the surface emits towards the ray (front face only unless double-sided).
pub fn emitted(scene: &SceneData, material: &Material, hit: &SurfaceHit) -> Vec3 {
    if !material.is_emissive() || !(hit.front || material.double_sided) {
        return Vec3::ZERO;
    }
    material.emission * texture(&scene.textures, material.emission_texture, hit.uv).truncate()
}

/// What a path in `medium` (`render::medium`) keeps of its light over the segment that ended
/// at `hit`, whose material is still the root one (a blend's root carries the absorption):
/// Beer–Lambert in the medium the segment ran through, all of it outside every solid. In a
/// scattering solid it is what is not scattered away (`render::scattering`: the extinction).
pub fn transmittance_to(scene: &SceneData, medium: u32, hit: &SurfaceHit) -> Vec3 {
    let root = &scene.materials[hit.material as usize];
    let absorbs_inside = root.interior_extinction().max_element() > 0.0;
    let medium = segment_medium(medium, hit.material, absorbs_inside, hit.front);
    if medium == NO_MEDIUM {
        return Vec3::ONE;
    }
    let extinction = scene.materials[medium as usize].interior_extinction();
    transmittance(extinction, hit.distance)
}

/// What a path in `medium` keeps of its light over `distance` (infinite: it left the scene).
pub fn medium_transmittance(scene: &SceneData, medium: u32, distance: f32) -> Vec3 {
    if medium == NO_MEDIUM {
        return Vec3::ONE;
    }
    transmittance(
        scene.materials[medium as usize].interior_extinction(),
        distance,
    )
}

/// The medium a path in `medium` is in after leaving `hit` along `next`, `material` being the
/// surface it bounced off (a blend's member) and `root` the hit's own material.
pub fn medium_after_bounce(
    scene: &SceneData,
    material: &Material,
    root: u32,
    medium: u32,
    hit: &SurfaceHit,
    next: Vec3,
) -> u32 {
    let crosses = next.dot(hit.geometric) < 0.0;
    medium_after(
        medium,
        root,
        scene.exterior[root as usize],
        material.bounds_volume(),
        hit.front,
        crosses,
    )
}

/// The direction a non-diffuse surface sends `incoming` on and its weight (the tint aside):
/// a dielectric chooses reflection or refraction by Fresnel with `u[0]`; rough metal draws
/// a micro-normal with `u[0]` and `u[1]`, rough glass too and then chooses with `u[2]`
/// (`render::microfacet`). `None` for a diffuse surface or plastic (whose coat
/// [`plastic_bounce`] decides), or where a micro-normal sends the path to the wrong side of the
/// surface (it ends).
pub fn specular_direction(
    surface: Surface,
    hit: &SurfaceHit,
    (incoming, layer): (Vec3, DielectricLayer),
    u: [f32; 3],
) -> Option<(Vec3, f32)> {
    let normal = hit.shading;
    let direction = match surface {
        Surface::Diffuse | Surface::Plastic { .. } => return None,
        Surface::RoughConductor { alpha } => {
            let (next, weight) = if hit.brush == Vec3::ZERO {
                rough_reflection(incoming, normal, alpha, u[0], u[1])?
            } else {
                brushed_reflection(incoming, normal, hit.brush, alpha, [u[0], u[1]])?
            };
            // Bent below the geometric surface by the shading normal: it would leak through.
            return (next.dot(hit.geometric) > 0.0).then_some((next, weight));
        }
        Surface::RoughDielectric {
            ior,
            thin_walled,
            alpha,
        } => {
            let eta = relative_eta(ior, hit.front, thin_walled);
            let (next, weight) = rough_dielectric(incoming, normal, eta, thin_walled, alpha, u)?;
            // On the other side of the geometric surface than of the shading normal: the
            // shading normal bent it across, and it would leak.
            let same_side = (next.dot(normal) > 0.0) == (next.dot(hit.geometric) > 0.0);
            return same_side.then_some((next, weight));
        }
        Surface::Mirror => reflect(incoming, normal),
        Surface::Dielectric { ior, thin_walled } => {
            let branches = dielectric_branches(hit, incoming, ior, thin_walled, layer);
            if u[0] < branches.reflectance {
                branches.reflected
            } else {
                branches.transmitted
            }
        }
    };
    Some((direction, 1.0))
}

/// The clear coat of `material` (a hit's root) at texture coordinates `uv`
/// (`render::clearcoat::clearcoat_at`), `None` for none.
pub fn hit_clearcoat(scene: &SceneData, material: &Material, uv: Vec2) -> Option<Clearcoat> {
    let texel = |id| texture(&scene.textures, Some(id), uv);
    material.clearcoat.map(|coat| clearcoat_at(&coat, texel))
}

/// glTF's clear coat at `hit` (`render::clearcoat::clearcoat_event` about the hit's normal
/// before any normal map, its numbers drawn from `next_number` as `clearcoat_numbers` does):
/// `None` where it lets the ray through to the surface beneath; else its reflection as a
/// mirror's or, rough, as rough metal's (inside: `None` where the path ends).
pub fn clearcoat_bounce(
    hit: &SurfaceHit,
    incoming: Vec3,
    coat: &Clearcoat,
    next_number: impl FnMut() -> f32,
) -> Option<Option<(Vec3, f32)>> {
    let u = clearcoat_numbers(coat, next_number);
    match clearcoat_event(incoming, hit.interpolated, coat, u) {
        ClearcoatEvent::Through => None,
        ClearcoatEvent::Reflected(next) => Some(next.filter(|(next, _)| {
            // Bent below the geometric surface by the shading normal: it would leak through.
            coat.alpha == 0.0 || next.dot(hit.geometric) > 0.0
        })),
    }
}

/// The sheen of material `id` (`hit`'s root) at the hit (`render::sheen::SheenAt`), `None`
/// for none, and where the hit is on the inside of solid glass: the sheen lies on its outside
/// ([`sheen_faces`]).
pub fn hit_sheen(scene: &SceneData, id: u32, hit: &SurfaceHit) -> Option<SheenAt> {
    let material = &scene.materials[id as usize];
    let (sheen, table) = (material.sheen?, scene.sheens[id as usize]?);
    if !sheen_faces(material.surface, hit.front) {
        return None;
    }
    let texel = |id| texture(&scene.textures, Some(id), hit.uv);
    Some(SheenAt::new(&sheen, table, texel))
}

/// Whether a sheen on a material of `surface` meets a ray hitting its `front` (or back) face:
/// everywhere but on the inside of a solid dielectric (a blend's root surface standing for
/// the blend).
pub fn sheen_faces(surface: Surface, front: bool) -> bool {
    front || !surface.is_solid_dielectric()
}

/// glTF's sheen at `hit` (`render::sheen::sheen_event` about the shading normal, three numbers
/// drawn from `next_number`): `None` where it lets the ray through to the material beneath;
/// else the direction it reflects into and its weight, `None` where that lies below the
/// geometric surface (the path ends).
pub fn sheen_bounce(
    hit: &SurfaceHit,
    incoming: Vec3,
    sheen: &SheenAt,
    mut next_number: impl FnMut() -> f32,
) -> Option<Option<(Vec3, Vec3)>> {
    let u = [next_number(), next_number(), next_number()];
    match sheen.event(incoming, hit.shading, u) {
        SheenEvent::Through => None,
        SheenEvent::Reflected(next, weight) => Some(
            (next.dot(hit.geometric) > 0.0 && weight.max_element() > 0.0).then_some((next, weight)),
        ),
    }
}

/// The eye-path factor [`eye_refraction_scale`] where `next` crosses the `surface` of a solid
/// dielectric at `hit` (refracts into or out of it); 1 for every other way on.
pub fn eye_crossing_scale(surface: Surface, hit: &SurfaceHit, next: Vec3) -> f32 {
    match surface.solid_ior() {
        Some(ior) if next.dot(hit.geometric) < 0.0 => {
            eye_refraction_scale(relative_eta(ior, hit.front, false))
        }
        _ => 1.0,
    }
}

/// The surface a path carrying `wavelength` (`render::dispersion`: a level or
/// `WHOLE_SPECTRUM`) meets at `material`, the wavelength it carries from there on and the
/// weight its throughput takes: dispersive glass, smooth or frosted, refracts with the index
/// of the path's wavelength, drawn with a number from `draw` where the path carries the
/// whole spectrum (called only at glass where `draws_wavelength` says so, so that other
/// surfaces, a dispersive blend's other members among them, leave the random stream as it
/// was); every other surface is itself, weight 1.
pub fn dispersed_surface(
    material: &Material,
    wavelength: u32,
    draw: impl FnOnce() -> f32,
) -> (Surface, u32, Vec3) {
    let ior = match material.surface {
        Surface::Dielectric { ior, .. } | Surface::RoughDielectric { ior, .. } => ior,
        surface => return (surface, wavelength, Vec3::ONE),
    };
    let u = if draws_wavelength(material.dispersion, wavelength) {
        draw()
    } else {
        0.0
    };
    match disperse(ior, material.dispersion, wavelength, u) {
        Some(d) => (with_ior(material.surface, d.ior), d.wavelength, d.weight),
        None => (material.surface, wavelength, Vec3::ONE),
    }
}

/// Glass `surface` (smooth or frosted) with index `ior`; any other surface as it is.
fn with_ior(surface: Surface, ior: f32) -> Surface {
    match surface {
        Surface::Dielectric { thin_walled, .. } => Surface::Dielectric { ior, thin_walled },
        Surface::RoughDielectric {
            thin_walled, alpha, ..
        } => Surface::RoughDielectric {
            ior,
            thin_walled,
            alpha,
        },
        other => other,
    }
}

/// A cosine-distributed bounce off a Lambertian surface (or plastic's base) from two uniform
/// numbers, weight 1; `None` where it would go below the geometric surface (light would leak
/// through it).
pub fn diffuse_bounce(hit: &SurfaceHit, [u1, u2]: [f32; 2]) -> Option<(Vec3, f32)> {
    let (t, b) = orthonormal_basis(hit.shading);
    let local = cosine_hemisphere(u1, u2);
    let next = t * local.x + b * local.y + hit.shading * local.z;
    (next.dot(hit.geometric) > 0.0).then_some((next, 1.0))
}

/// Where plastic (`render::plastic`) sends a ray arriving along `incoming`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PlasticBounce {
    /// The coat reflected it: the new direction and its weight, or `None` where a rough
    /// coat's micro-normal sent it below the surface (the path ends), and the tint a thin film
    /// on the coat gives the reflection (1 without one).
    Coat {
        next: Option<(Vec3, f32)>,
        tint: Vec3,
    },
    /// It passed the coat to the Lambertian base, whose estimate it multiplies by this weight
    /// (a thin film's share of the coat's transmittance included).
    Base(Vec3),
}

/// Plastic's choice (`render::plastic::layered_coat_event`, from `u_choice` and a rough
/// coat's `u_micro`, under the coat's `layer` at the hit: [`hit_dielectric_layer`]), with the coat's
/// reflection ended where the shading normal bent it below the geometric surface.
pub fn plastic_bounce(
    hit: &SurfaceHit,
    incoming: Vec3,
    (coat, layer): (&Coat, DielectricLayer),
    u_choice: f32,
    [u1, u2]: [f32; 2],
) -> PlasticBounce {
    let u = [u_choice, u1, u2];
    let (event, tint) = layered_coat_event(incoming, hit.shading, (coat, layer), u);
    match event {
        CoatEvent::Base { weight } => PlasticBounce::Base(tint * weight),
        CoatEvent::Reflected { direction, weight } => PlasticBounce::Coat {
            next: (weight > 0.0 && direction.dot(hit.geometric) > 0.0)
                .then_some((direction, weight)),
            tint,
        },
    }
}

/// A smooth dielectric's two ways on: reflected with probability `reflectance` (Fresnel),
/// else transmitted (refracted; straight on through a thin-walled sheet; reflected where
/// total internal reflection leaves no refracted ray). Under a layer (glTF's thin film and
/// specular layer) the share reflected is `layered_reflectance` in each channel, and the way
/// is chosen by their mean (a film reflects even where the bare surface would not: a soap
/// film of index 1.33 on a sheet of index 1).
#[derive(Clone, Copy, Debug)]
pub struct DielectricBranches {
    pub reflectance: f32,
    pub layered_reflectance: Vec3,
    pub reflected: Vec3,
    pub transmitted: Vec3,
}

impl DielectricBranches {
    /// The weight of the way chosen (`reflected` or not) under the layer: its share over its
    /// probability (1 when bare).
    pub fn weight(&self, reflected: bool) -> Vec3 {
        film_share(self.reflectance, self.layered_reflectance, reflected)
    }
}

/// The two ways on from a smooth dielectric of `ior` at `hit`, under `layer`.
pub fn dielectric_branches(
    hit: &SurfaceHit,
    incoming: Vec3,
    ior: f32,
    thin_walled: bool,
    layer: DielectricLayer,
) -> DielectricBranches {
    let normal = hit.shading;
    let eta = relative_eta(ior, hit.front, thin_walled);
    let cos_incident = -incoming.dot(normal);
    let fresnel = fresnel_dielectric(cos_incident, eta);
    let seen = (cos_incident, ior, hit.front || thin_walled);
    let (mut reflectance, layered_reflectance) =
        layered_reflectance(fresnel, layer, seen, thin_walled);
    if !layer.is_bare() {
        reflectance = layered_reflectance.element_sum() / 3.0;
    }
    let reflected = reflect(incoming, normal);
    let transmitted = if thin_walled {
        incoming
    } else {
        refract(incoming, normal, eta).unwrap_or(reflected)
    };
    DielectricBranches {
        reflectance,
        layered_reflectance,
        reflected,
        transmitted,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sheen meets rays everywhere but inside solid glass, smooth or frosted.
    #[test]
    fn a_sheen_lies_outside_solid_glass() {
        let solid = Surface::Dielectric {
            ior: 1.5,
            thin_walled: false,
        };
        let frosted = Surface::RoughDielectric {
            ior: 1.5,
            thin_walled: false,
            alpha: 0.1,
        };
        let sheet = Surface::Dielectric {
            ior: 1.5,
            thin_walled: true,
        };
        for surface in [solid, frosted] {
            assert!(sheen_faces(surface, true) && !sheen_faces(surface, false));
        }
        for surface in [sheet, Surface::Diffuse] {
            assert!(sheen_faces(surface, true) && sheen_faces(surface, false));
        }
    }
}
