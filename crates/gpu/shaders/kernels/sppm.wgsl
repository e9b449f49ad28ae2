// The SPPM kernels, twins of cpu::kernels (same names, arithmetic and random numbers).

@group(1) @binding(0) var<uniform> params: SppmParams;
@group(1) @binding(1) var<storage, read> lights: array<Light>;
@group(1) @binding(2) var<storage, read_write> slots: array<PathSlot>;
// Bindings 3 and 4 (photons, visible points) are declared by photon_storage_*.wgsl, with
// load_/store_ functions in the storage's precision.
@group(1) @binding(5) var<storage, read_write> pixels: array<PixelStats>;
@group(1) @binding(6) var<storage, read_write> hash: array<atomic<u32>>;
@group(1) @binding(7) var<storage, read_write> counters: array<atomic<u32>, COUNTER_COUNT>;
// render::sky_map's buffer: the sky's environment map, its texels and CDFs.
@group(1) @binding(8) var<storage, read> sky_map: array<f32>;
// render::normal_map::packed_tangents: the mesh's tangents, three a packed triangle (read
// only where TANGENTS).
@group(1) @binding(9) var<storage, read> vertex_tangents: array<vec4<f32>>;

// The sky's table entry as a render::sky_map::MapFrame (shared/sky_map.wgsl; width 0: a
// uniform sky).
fn map_frame(light: Light) -> MapFrame {
    if !SKY_MAP || light.kind != LIGHT_SKY {
        return MapFrame(0u, 0u, 1.0, 0.0);
    }
    return MapFrame(u32(light.edge2.y), u32(light.edge2.z), light.edge1.x, light.edge1.y);
}

// render::sky_map::sky_radiance: what a camera path leaving the scene along `direction` sees.
fn sky_radiance(direction: vec3<f32>) -> vec3<f32> {
    let uniform_sky = vec3<f32>(params.sky_r, params.sky_g, params.sky_b);
    if !SKY_MAP || params.light_count == 0u {
        return uniform_sky;
    }
    let frame = map_frame(lights[params.light_count - 1u]);
    if frame.width == 0u {
        return uniform_sky;
    }
    return sky_radiance_at(frame, sky_coordinates(frame, direction));
}

// render::emission::pick_light: binary search of the CDF.
fn pick_light(u: f32) -> u32 {
    var lo = 0u;
    var hi = params.light_count - 1u;
    while lo < hi {
        let mid = (lo + hi) / 2u;
        if u < lights[mid].cdf {
            hi = mid;
        } else {
            lo = mid + 1u;
        }
    }
    return lo;
}

// render::sampling::uniform_cone: uniform direction about +Z with z >= cos_max.
fn uniform_cone(u1: f32, u2: f32, cos_max: f32) -> vec3<f32> {
    let z = 1.0 - u1 * (1.0 - cos_max);
    let r = sqrt(max(1.0 - z * z, 0.0));
    let phi = 2.0 * PI * u2;
    return vec3<f32>(r * cos(phi), r * sin(phi), z);
}

// render::sampling::uniform_disk.
fn uniform_disk(u1: f32, u2: f32) -> vec2<f32> {
    let r = sqrt(u1);
    let phi = 2.0 * PI * u2;
    return vec2<f32>(r * cos(phi), r * sin(phi));
}

// render::sampling::concentric_disk (Shirley and Chiu's map).
fn concentric_disk(u1: f32, u2: f32) -> vec2<f32> {
    let a = 2.0 * u1 - 1.0;
    let b = 2.0 * u2 - 1.0;
    if a == 0.0 && b == 0.0 {
        return vec2<f32>(0.0);
    }
    let quarter = 0.25 * PI;
    var r = b;
    var phi = 2.0 * quarter - quarter * (a / b);
    if abs(a) > abs(b) {
        r = a;
        phi = quarter * (b / a);
    }
    return vec2<f32>(r * cos(phi), r * sin(phi));
}

// render::sampling::aperture_point: the unit disk for 0 blades, else the regular polygon of
// `blades` sides inscribed in it with a vertex at angle `rotation`.
fn aperture_point(u1: f32, u2: f32, blades: u32, rotation: f32) -> vec2<f32> {
    if blades == 0u {
        return concentric_disk(u1, u2);
    }
    let scaled = u1 * f32(blades);
    let side = min(u32(scaled), blades - 1u);
    let along = clamp(scaled - f32(side), 0.0, 1.0);
    let step = 2.0 * PI / f32(blades);
    let first = rotation + step * f32(side);
    let second = rotation + step * f32(side + 1u);
    let a = vec2<f32>(cos(first), sin(first));
    let b = vec2<f32>(cos(second), sin(second));
    return sqrt(along) * mix(a, b, u2);
}

// render::lens::camera_ray: the origin and unit direction of the camera ray through film point
// (sx, sy) that leaves the lens at the point `lens` maps to; the pinhole's ray at radius 0.
struct CameraRay {
    origin: vec3<f32>,
    direction: vec3<f32>,
}

fn camera_ray(sx: f32, sy: f32, lens: vec2<f32>) -> CameraRay {
    let through = params.forward + sx * params.right + sy * params.up;
    if params.lens_radius <= 0.0 {
        return CameraRay(params.eye, normalize(through));
    }
    let focus = params.eye + params.focus_distance * through;
    let disk = params.lens_radius * aperture_point(lens.x, lens.y, params.aperture_blades, params.aperture_rotation);
    let origin = params.eye + disk.x * normalize(params.right) + disk.y * normalize(params.up);
    return CameraRay(origin, normalize(focus - origin));
}

// render::emission::disk_point: uniform on the disk of `radius` about `centre`, perpendicular
// to `direction`.
fn disk_point(centre: vec3<f32>, radius: f32, direction: vec3<f32>, u1: f32, u2: f32) -> vec3<f32> {
    let disk = radius * uniform_disk(u1, u2);
    return centre + basis_tangent(direction) * disk.x + basis_bitangent(direction) * disk.y;
}

// render::emission::parallel_start: where a photon of parallel light starts (the disk's
// point, or the rectangle bounding the scene box's shadow where smaller), and the factor its
// flux, counted over the disk, takes.
struct ParallelStart {
    origin: vec3<f32>,
    share: f32,
}

fn parallel_start(centre: vec3<f32>, radius: f32, direction: vec3<f32>, u1: f32, u2: f32) -> ParallelStart {
    let half_extent = params.scene_half_extent;
    let t = basis_tangent(direction);
    let b = basis_bitangent(direction);
    let across_t = dot(abs(t), half_extent);
    let across_b = dot(abs(b), half_extent);
    let share = 4.0 * across_t * across_b / (PI * radius * radius);
    if all(half_extent == vec3<f32>(0.0)) || !(share < 1.0) {
        return ParallelStart(disk_point(centre, radius, direction, u1, u2), 1.0);
    }
    let point = centre + t * ((2.0 * u1 - 1.0) * across_t) + b * ((2.0 * u2 - 1.0) * across_b);
    return ParallelStart(point, share);
}

// scene::lights::spot_falloff.
fn spot_falloff(cos_angle: f32, cos_inner: f32, cos_outer: f32) -> f32 {
    let ramp = clamp((cos_angle - cos_outer) / max(cos_inner - cos_outer, 1.17549435e-38), 0.0, 1.0);
    return ramp * ramp;
}

// render::emission::triangle_point: a uniform point on a triangle light.
fn triangle_point(light: Light, u1: f32, u2: f32) -> vec3<f32> {
    var b1 = u1;
    var b2 = u2;
    if b1 + b2 > 1.0 {
        b1 = 1.0 - b1;
        b2 = 1.0 - b2;
    }
    return light.v0 + b1 * light.edge1 + b2 * light.edge2;
}

// render::emission::sample_emission, written into a fresh slot.
fn emit(rng: ptr<function, Rng>) -> PathSlot {
    let u0 = next_f32(rng);
    let u1 = next_f32(rng);
    let u2 = next_f32(rng);
    let u3 = next_f32(rng);
    let u4 = next_f32(rng);
    let light_index = pick_light(u0);
    let light = lights[light_index];
    var origin = light.v0;
    var normal: vec3<f32>;
    var direction: vec3<f32>;
    var flux = light.flux;
    if light.kind == LIGHT_POINT {
        direction = uniform_cone(u3, u4, -1.0);
        normal = direction;
    } else if light.kind == LIGHT_SPOT {
        let axis = light.edge1;
        let local = uniform_cone(u3, u4, light.edge2.y);
        direction = normalize(about_axis(axis, local));
        normal = direction;
        flux = spot_falloff(local.z, light.edge2.x, light.edge2.y) * flux;
    } else if light.kind == LIGHT_DIRECTIONAL {
        direction = light.edge1;
        normal = direction;
        let start = parallel_start(light.v0, light.edge2.x, direction, u1, u2);
        origin = start.origin;
        flux *= start.share;
    } else if light.kind == LIGHT_SKY {
        let frame = map_frame(light);
        if !SKY_MAP || frame.width == 0u {
            direction = uniform_cone(u3, u4, -1.0);
        } else {
            // render::sky_map::sky_photon_flux: the map's direction by its importance.
            let s = sample_sky_map(frame, u3, u4, sky_map_upper_share(frame));
            direction = -s.direction;
            flux = vec3<f32>(0.0);
            if s.found {
                let radius = light.edge2.x;
                flux = s.radiance * (PI * radius * radius / (s.pdf * pick_probability(light_index)));
            }
        }
        normal = direction;
        let radius = light.edge2.x;
        let start = parallel_start(light.v0 - 2.0 * radius * direction, radius, direction, u1, u2);
        origin = start.origin;
        flux *= start.share;
    } else {
        origin = triangle_point(light, u1, u2);
        normal = normalize(cross(light.edge1, light.edge2));
        var u_direction = u3;
        if light.double_sided != 0u {
            u_direction *= 2.0;
            if u_direction >= 1.0 {
                u_direction -= 1.0;
                normal = -normal;
            }
        }
        direction = normalize(cosine_direction(normal, u_direction, u4));
    }
    // render::emission::sample_emission: the path starts in the light's medium.
    return PathSlot(origin + params.epsilon * normal, 0u, direction, 0u, flux, pack_slot_state(false, light.medium, WHOLE_SPECTRUM));
}

// render::direct::LightSample; `found` false where the light sends nothing this way.
struct LightSample {
    direction: vec3<f32>,
    distance: f32,
    target_point: vec3<f32>,
    incident: vec3<f32>,
    // render::direct::LightSample::pdf; DELTA_LIGHT_PDF for point, spot and directional
    // lights (the twin's infinity: the power heuristic gives them weight 1 either way).
    pdf: f32,
    found: bool,
}

const DELTA_LIGHT_PDF: f32 = 1e38;

// render::direct::pick_probability.
fn pick_probability(index: u32) -> f32 {
    var before = 0.0;
    if index > 0u {
        before = lights[index - 1u].cdf;
    }
    return lights[index].cdf - before;
}

// render::direct::sky_pdf.
fn sky_pdf(direction: vec3<f32>, normal: vec3<f32>) -> f32 {
    if params.light_count == 0u {
        return 0.0;
    }
    let last = params.light_count - 1u;
    if lights[last].kind != LIGHT_SKY {
        return 0.0;
    }
    let pick = pick_probability(last);
    let cos_normal = dot(direction, normal);
    let frame = map_frame(lights[last]);
    if !SKY_MAP || frame.width == 0u {
        return pick * max(cos_normal, 0.0) / PI;
    }
    if cos_normal <= 0.0 {
        return 0.0;
    }
    return pick * sky_map_lookup(frame, direction, sky_upper_share_facing(frame, normal)).pdf;
}

// render::direct::triangle_pdf.
fn triangle_pdf(area_density: f32, distance: f32, cos_light: f32) -> f32 {
    let c = abs(cos_light);
    if c > 0.0 {
        return area_density * distance * distance / c;
    }
    return 0.0;
}

// render::light_sampling::power_heuristic.
fn power_heuristic(a: f32, b: f32) -> f32 {
    if a <= 0.0 {
        return 0.0;
    }
    let ratio = b / a;
    return 1.0 / (1.0 + ratio * ratio);
}

// render::direct::sample_light: one sample of the light table seen from `position` on a
// surface facing `normal`.
fn sample_light(u0: f32, u1: f32, u2: f32, position: vec3<f32>, normal: vec3<f32>) -> LightSample {
    let index = pick_light(u0);
    let light = lights[index];
    let pick = pick_probability(index);
    var sample = LightSample(vec3<f32>(0.0), RAY_T_MAX, position, vec3<f32>(0.0), DELTA_LIGHT_PDF, false);
    if light.kind == LIGHT_DIRECTIONAL {
        sample.direction = -light.edge1;
        sample.incident = light.flux / (PI * light.edge2.x * light.edge2.x);
    } else if SKY_MAP && light.kind == LIGHT_SKY && map_frame(light).width != 0u {
        let frame = map_frame(light);
        let s = sample_sky_map(frame, u1, u2, sky_upper_share_facing(frame, normal));
        if !s.found || dot(s.direction, normal) <= 0.0 {
            return sample;
        }
        sample.direction = s.direction;
        sample.incident = s.radiance / (pick * s.pdf);
        sample.pdf = pick * s.pdf;
    } else if light.kind == LIGHT_SKY {
        let local = cosine_hemisphere(u1, u2);
        sample.direction = normalize(about_axis(normal, local));
        sample.incident = light.flux / (4.0 * PI * light.edge2.x * light.edge2.x * local.z);
        sample.pdf = pick * local.z / PI;
    } else {
        var light_point = light.v0;
        if light.kind == LIGHT_TRIANGLE {
            light_point = triangle_point(light, u1, u2);
        }
        let offset = light_point - position;
        let distance_squared = dot(offset, offset);
        if distance_squared <= 0.0 {
            return sample;
        }
        sample.distance = sqrt(distance_squared);
        sample.target_point = light_point;
        sample.direction = offset / sample.distance;
        if light.kind == LIGHT_POINT {
            sample.incident = light.flux / (4.0 * PI * distance_squared);
        } else if light.kind == LIGHT_SPOT {
            let falloff = spot_falloff(-dot(sample.direction, light.edge1), light.edge2.x, light.edge2.y);
            let cone = 2.0 * PI * (1.0 - light.edge2.y);
            sample.incident = light.flux * falloff / (cone * distance_squared);
        } else {
            let light_cross = cross(light.edge1, light.edge2);
            let normal = normalize(light_cross);
            var cos_light = -dot(sample.direction, normal);
            var faces = 1.0;
            if light.double_sided != 0u {
                cos_light = abs(cos_light);
                faces = 2.0;
            }
            sample.incident = light.flux * cos_light / (PI * faces * distance_squared);
            sample.pdf = pick * distance_squared / (0.5 * length(light_cross) * cos_light);
        }
    }
    sample.found = max3(sample.incident) > 0.0;
    return sample;
}

// render::resampling::candidate_weight: what a candidate brings a Lambertian lobe facing
// `normal`, per its density (Rec. 709 luminance).
fn candidate_weight(sample: LightSample, normal: vec3<f32>) -> f32 {
    let luminance = dot(sample.incident, vec3<f32>(0.2126, 0.7152, 0.0722));
    return luminance * max(dot(sample.direction, normal), 0.0);
}

// The largest finite f32 (a candidate's weight beyond it is not kept, as on the CPU).
const F32_MAX: f32 = 3.40282347e38;

// render::resampling::resample_light: one light sample kept among `candidates`, three numbers
// a candidate and one more for each after the first.
fn resample_light(candidates: u32, position: vec3<f32>, normal: vec3<f32>, rng: ptr<function, Rng>) -> LightSample {
    let u0 = next_f32(rng);
    let u1 = next_f32(rng);
    let u2 = next_f32(rng);
    let first = sample_light(u0, u1, u2, position, normal);
    // render::resampling::is_lone_non_triangle.
    if candidates <= 1u || (params.light_count == 1u && lights[0].kind != LIGHT_TRIANGLE) {
        return first;
    }
    var kept = first;
    kept.found = false;
    var kept_weight = 0.0;
    var total = 0.0;
    for (var i = 0u; i < candidates; i++) {
        var sample = first;
        var u_keep = 0.0;
        if i > 0u {
            let v0 = next_f32(rng);
            let v1 = next_f32(rng);
            let v2 = next_f32(rng);
            sample = sample_light(v0, v1, v2, position, normal);
            u_keep = next_f32(rng);
        }
        if !sample.found {
            continue;
        }
        let weight = candidate_weight(sample, normal);
        if !(weight > 0.0 && weight <= F32_MAX) {
            continue;
        }
        total += weight;
        if u_keep * total < weight {
            kept = sample;
            kept_weight = weight;
        }
    }
    if kept.found {
        kept.incident *= total / (f32(candidates) * kept_weight);
    }
    return kept;
}

// cpu::surface::unoccluded: nothing but alpha cut-outs' holes on the segment. The CPU tests
// each hit's alpha inside its any-hit traversal; here the closest hit is found and passed
// through, hole after hole: the same answer (tested), and through lavapipe texture sampling
// inside the traversal loop made eye passes 15 % slower (docs/BENCHMARKS.md §3, session 12).
fn unoccluded(origin_in: vec3<f32>, direction: vec3<f32>, distance_in: f32) -> bool {
    if params.cut_outs == 0u {
        return trace_mtbvh(GpuRay(origin_in, distance_in, direction, 0u), true).triangle == NO_HIT;
    }
    var origin = origin_in;
    var distance = distance_in;
    for (var i = 0u; i <= MAX_PASS_THROUGHS; i++) {
        let hit = trace_surface_within(origin, direction, distance);
        if !hit.found {
            return true;
        }
        if !is_cut_out(materials[hit.material], hit.uv) {
            return false;
        }
        origin = hit.position + params.epsilon * direction;
        distance -= hit.distance + params.epsilon;
        if distance <= 0.0 {
            return true;
        }
    }
    return false;
}

// cpu::kernels::LitLobes: the lobes one light sample at an eye path's hit serves, with their
// weights (zero for a lobe that is not there). `alpha`, `coat_ior` and `refraction_eta` are
// its render::microfacet::GlossyLobe (`coat_ior` its fresnel_ior), `coat_ior` also telling a
// coat over the Lambertian lobe (LitLobes::coated): where both lobes are there they share it;
// the coat's width for its tables is `coat_alpha`, kept where the glossy lobe is not sampled.
struct LitLobes {
    diffuse: vec3<f32>,
    glossy: vec3<f32>,
    alpha: f32,
    coat_ior: f32,
    refraction_eta: f32,
    sheet_eta: f32,
    // glTF's clear coat over both lobes (its weight; 0: none), which the light passes on its
    // way in.
    clearcoat: f32,
    // The glossy lobe is glTF's sheen (render::microfacet::GlossyLobe::sheen) of width alpha.
    sheen_lobe: bool,
    // glTF's sheen over both lobes (colour black: none), which the light passes too.
    sheen: Sheen,
    coat_alpha: f32,
    // render::microfacet::GlossyLobe::brush: a brushed metal's brushing (zero: isotropic).
    brush: vec3<f32>,
    // cpu::kernels::LitLobes::metal_film: a metal's colour and its thin film (factor 0: none;
    // `glossy` then leaves the colour out).
    film_base: vec3<f32>,
    film: Film,
    // cpu::kernels::LitLobes::glass_film: frosted glass's thin film (factor 0: none).
    glass_film: Film,
}

// render::microfacet::GlossyLobe::facing.
fn lit_facing(lit: LitLobes, hit: SurfaceHit) -> vec3<f32> {
    if FROSTED_GLASS && (lit.refraction_eta > 0.0 || lit.sheet_eta > 0.0) {
        return -hit.shading;
    }
    return hit.shading;
}

// render::microfacet::GlossyLobe::response.
fn lit_glossy_lobe(lit: LitLobes, hit: SurfaceHit, outgoing: vec3<f32>, incident: vec3<f32>) -> GlossyResponse {
    if SHEENS && lit.sheen_lobe {
        return sheen_response(outgoing, incident, hit.shading, lit.alpha);
    }
    if FROSTED_GLASS && lit.refraction_eta > 0.0 {
        var response = refraction_response(outgoing, incident, hit.shading, lit.alpha, lit.refraction_eta);
        // Light refracting out towards the eye inside (render::optics::eye_refraction_scale).
        response.value *= lit.refraction_eta * lit.refraction_eta;
        return response;
    }
    if FROSTED_GLASS && lit.sheet_eta > 0.0 {
        return sheet_response(outgoing, incident, hit.shading, lit.alpha, lit.sheet_eta);
    }
    if ANISOTROPY && any(lit.brush != vec3<f32>(0.0)) {
        return brushed_response(outgoing, incident, hit.shading, lit.brush, lit.alpha);
    }
    return glossy_response(outgoing, incident, hit.shading, lit.alpha, lit.coat_ior);
}

fn is_lit(lit: LitLobes) -> bool {
    return max3(lit.diffuse) > 0.0 || (lit.alpha > 0.0 && max3(lit.glossy) > 0.0);
}

// cpu::kernels::LitLobes::response.
fn lit_response(lit: LitLobes, hit: SurfaceHit, outgoing: vec3<f32>, incident: vec3<f32>, light_pdf: f32) -> vec3<f32> {
    let cosine = dot(incident, hit.shading);
    var response = vec3<f32>(0.0);
    if max3(lit.diffuse) > 0.0 {
        var coat = 1.0;
        if lit.coat_ior > 0.0 {
            coat = coat_transmittance_of(hit.material, lit.coat_alpha, cosine);
        }
        response += lit.diffuse * (cosine * coat);
    }
    if lit.alpha > 0.0 {
        let lobe = lit_glossy_lobe(lit, hit, outgoing, incident);
        if lobe.value > 0.0 {
            var tint = vec3<f32>(1.0);
            if IRIDESCENCE && lit.film.factor > 0.0 {
                tint = metal_tint(lit.film_base, lit.film, outgoing, incident);
            }
            if IRIDESCENCE && lit.glass_film.factor > 0.0 {
                // render::iridescence::lobe_film_weight.
                var eta = 1.0 / lit.coat_ior;
                var thin_walled = false;
                if lit.sheet_eta > 0.0 {
                    eta = lit.sheet_eta;
                    thin_walled = true;
                } else if lit.refraction_eta > 0.0 {
                    eta = lit.refraction_eta;
                }
                tint *= rough_dielectric_film_weight(lit.glass_film, outgoing, incident, hit.shading, eta, thin_walled);
            }
            response += lit.glossy * tint * (lobe.value * power_heuristic(light_pdf, lobe.pdf));
        }
    }
    // In through the clear coat and the sheen, if any (the coat about the normal before the
    // map).
    let sheen = sheen_transmittance(lit.sheen, cosine);
    return response * (clearcoat_transmittance(lit.clearcoat, dot(incident, hit.interpolated)) * sheen);
}

// cpu::kernels::direct_light: one light sample at an eye path's hit, through the lobes `lit`
// names; kept among params.light_candidates where there is no glossy lobe (MIS needs the
// sample's density).
fn direct_light(hit: SurfaceHit, outgoing: vec3<f32>, lit: LitLobes, medium: u32, rng: ptr<function, Rng>) -> vec3<f32> {
    let facing = lit_facing(lit, hit);
    var candidates = params.light_candidates;
    if lit.alpha > 0.0 {
        candidates = 1u;
    }
    let light = resample_light(candidates, hit.position, facing, rng);
    if !light.found {
        return vec3<f32>(0.0);
    }
    // A thin sheet takes light from both sides.
    if dot(light.direction, facing) <= 0.0 && !(FROSTED_GLASS && lit.sheet_eta > 0.0) {
        return vec3<f32>(0.0);
    }
    let response = lit_response(lit, hit, outgoing, light.direction, light.pdf);
    if max3(response) <= 0.0 {
        return vec3<f32>(0.0);
    }
    var origin: vec3<f32>;
    // cpu::kernels::direct_light: the shadow ray's medium; a refraction out of a solid leaves it.
    var shadow_medium = medium;
    if FROSTED_GLASS && dot(light.direction, hit.shading) < 0.0 {
        // cpu::kernels::direct_light: through the glass (a refraction out, a sheet's
        // transmission), from just beyond it.
        if dot(light.direction, hit.geometric) >= 0.0 {
            return vec3<f32>(0.0);
        }
        if lit.refraction_eta > 0.0 {
            shadow_medium = materials[hit.material].exterior;
        }
        origin = hit.position - params.epsilon * hit.geometric;
    } else {
        // cpu::kernels::direct_light: a coarse mesh's terminator, decided by the shadow ray.
        let lifted = is_lifted(hit.position, hit.shadow_origin, hit.geometric, params.epsilon);
        if dot(light.direction, hit.geometric) <= 0.0 && !lifted {
            return vec3<f32>(0.0);
        }
        origin = shadow_ray_origin(hit, params.epsilon);
    }
    let shadow = shadow_ray(light, origin);
    if !unoccluded(origin, shadow.xyz, shadow.w) {
        return vec3<f32>(0.0);
    }
    return light.incident * response * medium_transmittance(shadow_medium, shadow.w);
}

// cpu::kernels::eye_path: one light sample through the lobes `lit` names, its numbers drawn
// only where they light something.
fn sampled_light(hit: SurfaceHit, outgoing: vec3<f32>, lit: LitLobes, medium: u32, rng: ptr<function, Rng>) -> vec3<f32> {
    if !is_lit(lit) || params.light_count == 0u {
        return vec3<f32>(0.0);
    }
    return direct_light(hit, outgoing, lit, medium, rng);
}

// cpu::kernels::GlossyVertex: where an eye path last left a glossy lobe (pdf 0: it did not).
struct GlossyVertex {
    position: vec3<f32>,
    normal: vec3<f32>,
    pdf: f32,
}

// cpu::kernels::GlossyVertex::after.
fn glossy_after(hit: SurfaceHit, lit: LitLobes, outgoing: vec3<f32>, next: vec3<f32>) -> GlossyVertex {
    if lit.alpha <= 0.0 {
        return GlossyVertex(vec3<f32>(0.0), vec3<f32>(0.0), 0.0);
    }
    let lobe = lit_glossy_lobe(lit, hit, outgoing, next);
    return GlossyVertex(hit.position, lit_facing(lit, hit), lobe.pdf);
}

// cpu::kernels::GlossyVertex::emitter_weight.
fn emitter_weight(glossy: GlossyVertex, hit: SurfaceHit, direction: vec3<f32>) -> f32 {
    if glossy.pdf <= 0.0 {
        return 1.0;
    }
    let area_density = materials[hit.material].light_area_density;
    let distance = length(hit.position - glossy.position);
    let light_pdf = triangle_pdf(area_density, distance, dot(direction, hit.geometric));
    return power_heuristic(glossy.pdf, light_pdf);
}

// cpu::kernels::GlossyVertex::sky_weight.
fn sky_weight(glossy: GlossyVertex, direction: vec3<f32>) -> f32 {
    if glossy.pdf <= 0.0 {
        return 1.0;
    }
    return power_heuristic(glossy.pdf, sky_pdf(direction, glossy.normal));
}

// render::direct::shadow_ray: the direction (xyz) and length (w) of the shadow ray from
// `origin` towards a light sample.
fn shadow_ray(light: LightSample, origin: vec3<f32>) -> vec4<f32> {
    if light.distance >= RAY_T_MAX {
        return vec4<f32>(light.direction, RAY_T_MAX);
    }
    let offset = light.target_point - origin;
    let distance = length(offset);
    if distance <= 0.0 {
        return vec4<f32>(light.direction, 0.0);
    }
    return vec4<f32>(offset / distance, distance * (1.0 - SHADOW_SHORTENING));
}

// Where a photon slot's segment leads (cpu::kernels::PhotonSegment); found false where it
// leaves the scene or ends in a walk; walking where it is still inside a scattering solid
// after SCATTERINGS_PER_STEP scatterings, at origin (hit not set). In murky glass the volume
// photon its walk kept (zero flux: none), also where found is false because the walk's
// roulette ended it (cpu::kernels: a segment with no hit and zero flux, whose slot idles).
struct PhotonSegment {
    found: bool,
    walking: bool,
    hit: SurfaceHit,
    origin: vec3<f32>,
    direction: vec3<f32>,
    flux: vec3<f32>,
    scattered: bool,
    volume_photon: Photon,
}

// cpu::kernels::photon_segment: straight through a clear or absorbing medium, a walk from
// scattering to scattering inside a scattering solid, drawing the same numbers; in murky
// glass one more number at each scattering event keeps it as the step's volume photon with
// probability 1/events (a reservoir of one), whose flux is multiplied by the events at the
// end.
fn photon_segment(slot: PathSlot, medium: u32, rng: ptr<function, Rng>) -> PhotonSegment {
    var segment: PhotonSegment;
    segment.scattered = false;
    segment.walking = false;
    segment.volume_photon = Photon(vec3<f32>(0.0), 0u, vec3<f32>(0.0), 0u);
    var origin = slot.origin;
    var direction = slot.direction;
    var scatters = false;
    if SCATTERING && medium != NO_MEDIUM {
        scatters = max3(materials[medium].scattering) > 0.0;
    }
    if !scatters {
        segment.hit = trace_surface(origin, direction);
        segment.found = segment.hit.found;
        if segment.found {
            segment.direction = direction;
            segment.flux = slot.flux * transmittance_to(medium, segment.hit);
        }
        return segment;
    }
    let extinction = materials[medium].absorption;
    let scattering = materials[medium].scattering;
    let anisotropy = materials[medium].scatter_anisotropy;
    let murky = is_murky_glass(medium);
    var walk = walk_start(next_f32(rng));
    var events = 0u;
    var kept = segment.volume_photon;
    loop {
        let hit = trace_surface(origin, direction);
        if !hit.found {
            segment.found = false;
            return segment;
        }
        let t = walk_flight(&walk, extinction, scattering, hit.distance, next_f32(rng));
        if t < 0.0 {
            segment.found = true;
            segment.hit = hit;
            segment.direction = direction;
            segment.flux = slot.flux * walk.weight;
            segment.scattered = events > 0u;
            if murky && events > 0u {
                segment.volume_photon = times_events(kept, events);
            }
            return segment;
        }
        events += 1u;
        origin += t * direction;
        if murky && next_f32(rng) * f32(events) < 1.0 {
            kept = Photon(origin, volume_photon_direction(direction), slot.flux * walk.weight, 0u);
        }
        if !walk_survives(&walk, next_f32(rng)) {
            // Ended here: only the photon kept, if any (no flux goes on).
            segment.found = false;
            if murky {
                segment.volume_photon = times_events(kept, events);
            }
            return segment;
        }
        let u0 = next_f32(rng);
        let u1 = next_f32(rng);
        direction = henyey_greenstein(direction, anisotropy, u0, u1);
        if events == SCATTERINGS_PER_STEP {
            segment.found = true;
            segment.walking = true;
            segment.origin = origin;
            segment.direction = direction;
            segment.flux = slot.flux * walk.weight;
            segment.scattered = true;
            if murky {
                segment.volume_photon = times_events(kept, events);
            }
            return segment;
        }
    }
    // Not reached (the loop returns); naga asks for a return all the same.
    return segment;
}

// The volume photon a murky walk's reservoir kept among `events` scattering events: its flux
// times their number.
fn times_events(kept: Photon, events: u32) -> Photon {
    return Photon(kept.position, kept.normal, kept.flux * f32(events), kept.pad);
}

// cpu::kernels::one_of: the photon a slot keeps where its walk kept `walked` (zero flux: none)
// and its surface keeps `landed`: one of them drawn with even odds, its flux doubled.
fn one_of(walked: Photon, landed: Photon, rng: ptr<function, Rng>) -> Photon {
    if !MURKY_GLASS || !any(walked.flux != vec3<f32>(0.0)) {
        return landed;
    }
    var chosen = landed;
    if next_f32(rng) < 0.5 {
        chosen = walked;
    }
    chosen.flux *= 2.0;
    return chosen;
}

// What one photon-pass step leaves (cpu::kernels::PhotonStep).
struct PhotonStep {
    slot: PathSlot,
    // The photon stored at this bounce (zero flux if none).
    photon: Photon,
    // Whether the slot started a new light path.
    emitted: bool,
}

// cpu::kernels::photon_pass for one slot: an idle slot starts a new light path; then the path
// advances one segment, drawing the numbers of stream (pass_index, index). Shared by
// photon_pass and photon_trace_naive, so both schemes run the same bounce.
fn photon_step(slot_in: PathSlot, pass_index: u32, index: u32) -> PhotonStep {
    var rng = rng_start(params.seed, PHOTON_STREAM, pass_index, index);
    var slot = slot_in;
    var emitted = false;
    if slot.depth == SLOT_IDLE {
        slot = emit(&rng);
        emitted = true;
    }
    var photon = Photon(vec3<f32>(0.0), 0u, vec3<f32>(0.0), 0u);
    // cpu::kernels: the medium the path is in absorbs along the segment, up to a cut-out too;
    // a scattering one walks it to a surface.
    let medium = slot_medium(slot.state);
    let segment = photon_segment(slot, medium, &rng);
    // cpu::kernels: the volume photon a walk in murky glass kept, whatever comes next.
    if MURKY_GLASS {
        photon = segment.volume_photon;
    }
    if !segment.found {
        slot.depth = SLOT_IDLE;
        return PhotonStep(slot, photon, emitted);
    }
    if SCATTERING && segment.walking {
        // cpu::kernels: still walking inside a scattering solid; it goes on from there next
        // pass, the step counted as a bounce, unless it carries no flux.
        slot.depth += 1u;
        if slot.depth >= params.max_depth || all(segment.flux == vec3<f32>(0.0)) {
            slot.depth = SLOT_IDLE;
        } else {
            slot.origin = segment.origin;
            slot.direction = segment.direction;
            slot.flux = segment.flux;
            slot.state = pack_slot_state(true, medium, slot_wavelength(slot.state));
        }
        return PhotonStep(slot, photon, emitted);
    }
    var hit = segment.hit;
    let direction = segment.direction;
    let flux = segment.flux;
    let scattered = segment.scattered;
    let root_id = hit.material;
    let root = materials[root_id];
    if is_cut_out(root, hit.uv) {
        slot.flux = flux;
        slot.pass_throughs += 1u;
        slot.origin = hit.position + params.epsilon * direction;
        slot.direction = direction;
        if slot.pass_throughs > MAX_PASS_THROUGHS {
            slot.depth = SLOT_IDLE;
        }
        return PhotonStep(slot, photon, emitted);
    }
    // cpu::kernels: glTF's clear coat meets the photon first; what it reflects is not kept on
    // the surface beneath and goes on as from a mirror.
    var coat_weight = 0.0;
    if CLEARCOATS && root.clearcoat > 0.0 {
        let clearcoat = clearcoat_at(root, hit.uv);
        coat_weight = clearcoat.weight;
        let coat = clearcoat_bounce(clearcoat, hit, direction, &rng);
        if coat.reflected {
            let shading_factors = arrival_factor(-direction, hit.interpolated, hit.geometric)
                * departure_factor(coat.bounce.direction, hit.interpolated, hit.geometric);
            let coat_weight = coat.bounce.weight * shading_factors;
            slot.depth += 1u;
            if coat_weight > 0.0 && slot.depth < params.max_depth {
                slot.origin = offset_origin(hit, coat.bounce.direction, params.epsilon);
                slot.direction = coat.bounce.direction;
                slot.flux = flux * coat_weight;
            } else {
                slot.depth = SLOT_IDLE;
            }
            return PhotonStep(slot, photon, emitted);
        }
    }
    // cpu::kernels: glTF's sheen beneath the coat meets it next; what it reflects is not kept
    // on the material beneath and goes on from the sheen's lobe.
    var sheen = no_sheen();
    if SHEENS && max3(root.sheen_color) > 0.0 && sheen_faces(root, hit.front) {
        sheen = sheen_at(root_id, root, hit.uv);
        let bounce = sheen_bounce(sheen, hit, direction, &rng);
        if bounce.reflected {
            slot.depth += 1u;
            if max3(bounce.weight) > 0.0 && slot.depth < params.max_depth {
                let shading_factors = arrival_factor(-direction, hit.shading, hit.geometric)
                    * departure_factor(bounce.direction, hit.shading, hit.geometric);
                let coat = clearcoat_transmittance(coat_weight, dot(bounce.direction, hit.interpolated));
                slot.origin = offset_origin(hit, bounce.direction, params.epsilon);
                slot.direction = bounce.direction;
                slot.flux = flux * bounce.weight * (shading_factors * coat);
            } else {
                slot.depth = SLOT_IDLE;
            }
            return PhotonStep(slot, photon, emitted);
        }
    }
    // cpu::kernels: a blend keeps the photon for its Lambertian member whichever member the
    // path takes; the member is drawn only at blends.
    var keeper = hit.material;
    var material = root;
    let map_texel = roughness_texel(root, hit.uv);
    if BLENDS && (root.flags & MATERIAL_BLEND) != 0u {
        keeper = root.blend_photon_member;
        hit.material = blend_member(hit.material, next_f32(&rng), map_texel, hit.uv);
        material = materials[hit.material];
    }
    // cpu::kernels: where a metallic-roughness texture maps the member, its surface here.
    material = mapped_material(material, map_texel);
    let surface_tint = base_color(material, hit.uv);
    let u_roulette = next_f32(&rng);
    let u_direction0 = next_f32(&rng);
    let u_direction1 = next_f32(&rng);
    // cpu::kernels: rough glass chooses its way with a third number, and plastic between its
    // coat and its base.
    var u_choice = 0.0;
    if material.surface == SURFACE_ROUGH_DIELECTRIC || material.surface == SURFACE_PLASTIC {
        u_choice = next_f32(&rng);
    }
    // cpu::kernels: dispersive glass keeps one wavelength of a path that carries the whole
    // spectrum, drawn with one more number.
    var wavelength = slot_wavelength(slot.state);
    var u_wavelength = 0.0;
    if draws_wavelength(material, wavelength) {
        u_wavelength = next_f32(&rng);
    }
    var next = vec3<f32>(0.0);
    var weight = 1.0;
    var tint = surface_tint;
    // The side the path leaves from: the far one where it passed through.
    var out = hit;
    // cpu::kernels: weighted where the shading normal is not the geometric one.
    let arrival = arrival_factor(-direction, hit.shading, hit.geometric);
    // cpu::kernels: a Lambertian surface, or plastic's base under the coat, keeps the photon
    // (not straight from the light where eye passes sample the light themselves).
    let plastic = material.surface == SURFACE_PLASTIC;
    var keeper_material = material;
    if BLENDS && keeper != hit.material {
        keeper_material = mapped_material(materials[keeper], map_texel);
    }
    let keeper_surface = keeper_material.surface;
    var bounced = slot_bounced(slot.state) || scattered;
    if keeper_surface == SURFACE_DIFFUSE || keeper_surface == SURFACE_PLASTIC {
        if slot.depth > 0u || scattered || (params.sample_lights & SAMPLE_AT_VISIBLE_POINTS) == 0u {
            var share = 1.0;
            if keeper_surface == SURFACE_PLASTIC {
                share = coat_transmittance_of(keeper, keeper_material.roughness_alpha, dot(direction, hit.shading));
            }
            let landed = Photon(hit.position, photon_normal(hit.shading, !bounced), flux * (arrival * share), 0u);
            photon = one_of(photon, landed, &rng);
        }
    }
    // cpu::kernels: glTF's diffuse transmission chooses the Lambertian lobe's side with one
    // more number (after the choice of photon).
    var u_side = 1.0;
    if transmits_diffusely(material) {
        u_side = next_f32(&rng);
    }
    if material.surface == SURFACE_DIFFUSE {
        // Its later photons are indirect (if it goes on; an ended slot's is not read).
        bounced = true;
        let side = lambertian_side(material, hit, surface_tint, u_side);
        out = side.hit;
        tint = side.tint;
        let bounce = diffuse_bounce(out, u_direction0, u_direction1);
        next = bounce.direction;
        weight = bounce.weight;
    } else if plastic {
        let choice = plastic_bounce(material, hit, direction, u_choice, u_direction0, u_direction1);
        if choice.base {
            bounced = true;
            let side = lambertian_side(material, hit, surface_tint, u_side);
            out = side.hit;
            let bounce = diffuse_bounce(out, u_direction0, u_direction1);
            next = bounce.direction;
            weight = bounce.weight;
            let alpha = material.roughness_alpha;
            let leaving = coat_transmittance_of(hit.material, alpha, dot(next, out.shading));
            let scale = coat_diffuse_scale_of(hit.material, alpha);
            tint = side.tint * (scale * leaving * choice.base_weight);
        } else {
            next = choice.coat.direction;
            weight = choice.coat.weight;
            tint = vec3<f32>(1.0);
        }
    } else {
        let dispersed = dispersed_material(material, wavelength, u_wavelength);
        let film = hit_film(material, hit.uv);
        let bounce = specular_direction(dispersed.material, hit, direction, film, u_direction0, u_direction1, u_choice);
        next = bounce.direction;
        weight = bounce.weight;
        tint = bounce_tint_of(dispersed.material, surface_tint, film, hit, direction, next) * dispersed.weight;
        wavelength = dispersed.wavelength;
    }
    // Out through the sheen and the clear coat, if any (the far side's where it passed
    // through).
    let out_of_coat = clearcoat_transmittance(coat_weight, dot(next, out.interpolated));
    let out_of_sheen = sheen_transmittance(sheen, dot(next, out.shading));
    weight = weight * (arrival * departure_factor(next, out.shading, out.geometric) * out_of_coat * out_of_sheen);
    let survival = min(max3(tint), 1.0);
    slot.depth += 1u;
    if weight > 0.0 && u_roulette < survival && slot.depth < params.max_depth {
        slot.origin = offset_origin(hit, next, params.epsilon);
        slot.direction = next;
        slot.flux = flux * tint * (weight / survival);
        slot.state = pack_slot_state(bounced, medium_after_bounce(material, root_id, medium, hit, next), wavelength);
    } else {
        slot.depth = SLOT_IDLE;
    }
    return PhotonStep(slot, photon, emitted);
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn photon_pass(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let index = invocation_index(id, groups);
    if index >= params.slot_count {
        return;
    }
    let pass_index = atomicLoad(&counters[COUNTER_PASS]);
    let step = photon_step(slots[index], pass_index, index);
    if step.emitted {
        atomicAdd(&counters[COUNTER_EMITTED_PASS], 1u);
    }
    slots[index] = step.slot;
    store_photon(index, step.photon);
}

// render::rng::pixel_jitter: the R2 sequence's point `eye_pass`, rotated per pixel.
fn pixel_jitter(index: u32, eye_pass: u32) -> vec2<f32> {
    let shift_x = stream_key(params.seed, JITTER_STREAM, 0u, index);
    let shift_y = stream_key(params.seed, JITTER_STREAM, 1u, index);
    let fixed = vec2<u32>(eye_pass * R2_STEP_X + shift_x, eye_pass * R2_STEP_Y + shift_y);
    return vec2<f32>(fixed >> vec2<u32>(8u)) * (1.0 / 16777216.0);
}

// render::rng::pixel_lens: the lens's Kronecker sequence's point `eye_pass`, rotated per pixel.
fn pixel_lens(index: u32, eye_pass: u32) -> vec2<f32> {
    let shift_x = stream_key(params.seed, JITTER_STREAM, 3u, index);
    let shift_y = stream_key(params.seed, JITTER_STREAM, 4u, index);
    let fixed = vec2<u32>(eye_pass * LENS_STEP_X + shift_x, eye_pass * LENS_STEP_Y + shift_y);
    return vec2<f32>(fixed >> vec2<u32>(8u)) * (1.0 / 16777216.0);
}

// render::rng::pixel_side: √11's Kronecker sequence's point `eye_pass`, rotated per pixel.
fn pixel_side(index: u32, eye_pass: u32) -> f32 {
    let shift = stream_key(params.seed, JITTER_STREAM, 5u, index);
    return f32((eye_pass * SIDE_STEP + shift) >> 8u) * (1.0 / 16777216.0);
}

// render::rng::pixel_wavelength: 1/φ further each eye pass and path (`step`: their sum),
// rotated per pixel.
fn pixel_wavelength(index: u32, step: u32) -> f32 {
    let shift = stream_key(params.seed, JITTER_STREAM, 2u, index);
    return f32((step * GOLDEN_STEP + shift) >> 8u) * (1.0 / 16777216.0);
}

// cpu::kernels::eye_pass_pixel and eye_pass: the first path leaves the visible point; where an
// earlier eye pass met a specular surface first, SPECULAR_EXTRA_PATHS more paths add what they
// see, averaged with the first path's.
@compute @workgroup_size(WORKGROUP_SIZE)
fn eye_pass(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let index = invocation_index(id, groups);
    if index >= params.width * params.height {
        return;
    }
    let pass_index = atomicLoad(&counters[COUNTER_PASS]);
    var rng = rng_start(params.seed, EYE_STREAM, pass_index, index);
    var extra = 0u;
    if pixels[index].specular_seen != 0u {
        extra = SPECULAR_EXTRA_PATHS;
    }
    // One call site in a loop over the paths: a second call of eye_path made the kernel a third
    // slower through lavapipe even where no pixel took the extra path.
    let eye_pass_index = pass_index / max(params.eye_every, 1u);
    var jitter = pixel_jitter(index, eye_pass_index);
    var lens = pixel_lens(index, eye_pass_index);
    // render::rng::pixel_side for the first path; the extra paths draw their own (negative).
    var side_number = -1.0;
    if DIFFUSE_TRANSMISSION {
        side_number = pixel_side(index, eye_pass_index);
    }
    var wavelength_number = 0.0;
    var direct = vec3<f32>(0.0);
    for (var path_index = 0u; path_index <= extra; path_index += 1u) {
        if path_index > 0u {
            let jx = next_f32(&rng);
            let jy = next_f32(&rng);
            jitter = vec2<f32>(jx, jy);
            // A pinhole draws no lens point, so its images keep their numbers.
            if params.lens_radius > 0.0 {
                let lx = next_f32(&rng);
                let ly = next_f32(&rng);
                lens = vec2<f32>(lx, ly);
            }
        }
        if DISPERSION {
            wavelength_number = pixel_wavelength(index, eye_pass_index + path_index);
        }
        let path = eye_path(index, jitter, lens, vec2<f32>(wavelength_number, side_number), &rng);
        side_number = -1.0;
        direct += path.direct;
        if path_index == 0u {
            store_visible_point(index, path.point);
            if path.specular_first {
                pixels[index].specular_seen = 1u;
            }
        }
    }
    pixels[index].direct += direct / f32(1u + extra);
}

// cpu::kernels::EyePath: `direct` is its emission met and then its light sample added.
struct EyePath {
    point: VisiblePoint,
    direct: vec3<f32>,
    specular_first: bool,
}

// cpu::kernels::eye_path: a camera path through pixel `index` at sub-pixel `jitter`, leaving
// the lens at `lens`, drawing its wavelength at the first dispersive glass with `numbers.x`,
// keeping it after, and choosing a translucent surface's side with `numbers.y` (negative:
// drawn).
fn eye_path(index: u32, jitter: vec2<f32>, lens: vec2<f32>, numbers: vec2<f32>, rng: ptr<function, Rng>) -> EyePath {
    var pending_number = numbers.x;
    var wavelength = WHOLE_SPECTRUM;
    let x = index % params.width;
    let y = index / params.width;
    let sx = (f32(x) + jitter.x) / f32(params.width) * 2.0 - 1.0;
    let sy = 1.0 - (f32(y) + jitter.y) / f32(params.height) * 2.0;
    let start = camera_ray(sx, sy, lens);
    var origin = start.origin;
    var direction = start.direction;
    var throughput = vec3<f32>(1.0);
    var direct = vec3<f32>(0.0);
    var point = VisiblePoint(vec3<f32>(0.0), 0u, vec3<f32>(0.0), 0u);
    var depth = 0u;
    var pass_throughs = 0u;
    var specular_first = false;
    // cpu::kernels::eye_pass's share of the next surface's emission still to count, whether
    // the path has met glass, and the glass branch not taken (cpu::kernels::emission_seen),
    // traced by the iteration after the glass surface's so that the kernel keeps one
    // traversal: its ray, the weight of what it sees, and the holes it has passed.
    var emission_share = 1.0;
    var met_glass = false;
    var probing = false;
    var probe_origin = vec3<f32>(0.0);
    var probe_direction = vec3<f32>(0.0);
    var probe_weight = vec3<f32>(0.0);
    var probe_pass_throughs = 0u;
    // What the probe's medium lets through so far (cpu::kernels::emission_seen's `kept`).
    var probe_medium = NO_MEDIUM;
    var probe_kept = vec3<f32>(1.0);
    // cpu::kernels::eye_path: the solid the path is inside, where the camera is to begin with.
    var medium = params.camera_medium;
    // cpu::kernels::eye_path's glossy vertex: emission met next is weighed against the light
    // sample taken there.
    var glossy = GlossyVertex(vec3<f32>(0.0), vec3<f32>(0.0), 0.0);
    while depth < params.max_depth {
        var hit = trace_surface(select(origin, probe_origin, probing), select(direction, probe_direction, probing));
        if probing {
            if !hit.found {
                direct += probe_weight * (probe_kept * sky_radiance(probe_direction) * medium_transmittance(probe_medium, RAY_T_MAX));
                probing = false;
                continue;
            }
            probe_kept *= transmittance_to(probe_medium, hit);
            if is_cut_out(materials[hit.material], hit.uv) {
                probe_pass_throughs += 1u;
                probe_origin = hit.position + params.epsilon * probe_direction;
                probing = probe_pass_throughs <= MAX_PASS_THROUGHS;
            } else {
                direct += probe_weight * (probe_kept * emitted(materials[hit.material], hit));
                probing = false;
            }
            continue;
        }
        if !hit.found {
            // Out of the scene: the sky (zero without one), less what water around the path
            // absorbs.
            direct += throughput * emission_share * (sky_radiance(direction) * medium_transmittance(medium, RAY_T_MAX)) * sky_weight(glossy, direction);
            break;
        }
        // cpu::kernels::eye_path: in murky glass the flight may end where it scatters, with a
        // volume visible point; else it passes, weighed by what is not scattered.
        if is_murky_glass(medium) {
            let murky = materials[medium];
            var walk = walk_start(next_f32(rng));
            let t = walk_flight(&walk, murky.absorption, murky.scattering, hit.distance, next_f32(rng));
            if t >= 0.0 {
                let weight = throughput * walk_weight_over_scattering(walk, murky.scattering);
                if max3(weight) > 0.0 {
                    let word = volume_point_direction(direction, murky.scatter_anisotropy);
                    point = VisiblePoint(origin + t * direction, word, weight, 0u);
                }
                break;
            }
            throughput *= walk.weight;
        } else {
            throughput *= transmittance_to(medium, hit);
        }
        let root_id = hit.material;
        let root = materials[root_id];
        if is_cut_out(root, hit.uv) {
            pass_throughs += 1u;
            if pass_throughs > MAX_PASS_THROUGHS {
                break;
            }
            origin = hit.position + params.epsilon * direction;
            continue;
        }
        let emission = emitted(root, hit);
        if max3(emission) > 0.0 {
            direct += throughput * emission_share * emission * emitter_weight(glossy, hit, direction);
        }
        emission_share = 1.0;
        // cpu::kernels::eye_path: glTF's clear coat meets the path first; its reflection goes
        // on as a mirror's (no light sample: emission met next counts whole).
        var coat_weight = 0.0;
        if CLEARCOATS && root.clearcoat > 0.0 {
            let clearcoat = clearcoat_at(root, hit.uv);
            coat_weight = clearcoat.weight;
            let coat = clearcoat_bounce(clearcoat, hit, direction, rng);
            if coat.reflected {
                if coat.bounce.weight <= 0.0 {
                    break;
                }
                throughput *= coat.bounce.weight;
                glossy = GlossyVertex(vec3<f32>(0.0), vec3<f32>(0.0), 0.0);
                depth += 1u;
                origin = offset_origin(hit, coat.bounce.direction, params.epsilon);
                direction = coat.bounce.direction;
                continue;
            }
        }
        // cpu::kernels::eye_path: glTF's sheen beneath the coat meets it next; its reflection
        // takes a light sample for the sheen's lobe and goes on from it.
        var sheen = no_sheen();
        if SHEENS && max3(root.sheen_color) > 0.0 && sheen_faces(root, hit.front) {
            sheen = sheen_at(root_id, root, hit.uv);
            let bounce = sheen_bounce(sheen, hit, direction, rng);
            if bounce.reflected {
                if max3(bounce.weight) <= 0.0 {
                    break;
                }
                var lit = LitLobes(vec3<f32>(0.0), throughput * sheen_lobe_scale(sheen, dot(direction, hit.shading)), sheen.alpha, 0.0, 0.0, 0.0, coat_weight, true, no_sheen(), 0.0, vec3<f32>(0.0), vec3<f32>(0.0), no_film(), no_film());
                if (params.sample_lights & SAMPLE_AT_GLOSSY) == 0u {
                    lit.alpha = 0.0;
                }
                direct += sampled_light(hit, -direction, lit, medium, rng);
                glossy = glossy_after(hit, lit, -direction, bounce.direction);
                let coat = clearcoat_transmittance(coat_weight, dot(bounce.direction, hit.interpolated));
                throughput *= bounce.weight * coat;
                depth += 1u;
                origin = offset_origin(hit, bounce.direction, params.epsilon);
                direction = bounce.direction;
                continue;
            }
        }
        // cpu::kernels::eye_path: a blend's member, drawn only at blends.
        var material = root;
        let map_texel = roughness_texel(root, hit.uv);
        if BLENDS && (root.flags & MATERIAL_BLEND) != 0u {
            hit.material = blend_member(hit.material, next_f32(rng), map_texel, hit.uv);
            material = materials[hit.material];
        }
        // cpu::kernels::eye_path: where a metallic-roughness texture maps the member, its
        // surface here.
        material = mapped_material(material, map_texel);
        let tint = max(base_color(material, hit.uv), vec3<f32>(0.0));
        let u = next_f32(rng);
        // cpu::kernels::eye_path: plastic's coat or its base, chosen by Fresnel; the lobes a
        // light sample here serves.
        let plastic = material.surface == SURFACE_PLASTIC;
        var base = material.surface == SURFACE_DIFFUSE;
        var bounce = Scattered(vec3<f32>(0.0), 0.0);
        var bounce_tint = tint;
        var base_weight = 1.0;
        var lit = LitLobes(vec3<f32>(0.0), vec3<f32>(0.0), 0.0, 0.0, 0.0, 0.0, coat_weight, false, sheen, 0.0, vec3<f32>(0.0), vec3<f32>(0.0), no_film(), no_film());
        if plastic {
            lit.coat_ior = material.ior;
            lit.coat_alpha = material.roughness_alpha;
            var u_micro = vec2<f32>(0.0);
            if material.roughness_alpha > 0.0 {
                lit.glossy = throughput;
                lit.alpha = material.roughness_alpha;
                let u1 = next_f32(rng);
                let u2 = next_f32(rng);
                u_micro = vec2<f32>(u1, u2);
            }
            let choice = plastic_bounce(material, hit, direction, u, u_micro.x, u_micro.y);
            base = choice.base;
            base_weight = choice.base_weight;
            bounce = choice.coat;
            bounce_tint = vec3<f32>(1.0);
        }
        // cpu::kernels::eye_path: where glTF's diffuse transmission took the light through,
        // the Lambertian lobe's side, with a light sample of its own.
        var far_side = false;
        var side = LambertianSide(hit, tint);
        if base {
            var scale = 1.0;
            if plastic {
                scale = coat_diffuse_scale_of(hit.material, material.roughness_alpha);
            }
            if transmits_diffusely(material) {
                var u_side = numbers.y;
                if u_side < 0.0 {
                    u_side = next_f32(rng);
                }
                side = lambertian_side(material, hit, tint, u_side);
                far_side = side.hit.front != hit.front;
            }
            let weight = throughput * side.tint * (scale * base_weight / PI);
            if max3(weight) > 0.0 {
                point = VisiblePoint(hit.position, surface_normal(side.hit.shading), weight, 0u);
                if (params.sample_lights & SAMPLE_AT_VISIBLE_POINTS) != 0u {
                    lit.diffuse = weight;
                }
            }
        } else if !plastic {
            // Only these send pixels more eye paths (cpu::kernels::eye_path).
            specular_first = specular_first || depth == 0u;
            // Rough metal and glass draw their micro-normal with a second number, and rough
            // glass chooses its way with a third.
            var u_second = 0.0;
            var u_third = 0.0;
            if material.surface == SURFACE_ROUGH_CONDUCTOR || material.surface == SURFACE_ROUGH_DIELECTRIC {
                u_second = next_f32(rng);
            }
            if material.surface == SURFACE_ROUGH_DIELECTRIC {
                u_third = next_f32(rng);
            }
            // cpu::kernels: dispersive glass keeps one wavelength (its index from here on,
            // the lobes' below among them).
            var u_wavelength = 0.0;
            if draws_wavelength(material, wavelength) {
                if pending_number >= 0.0 {
                    u_wavelength = pending_number;
                    pending_number = -1.0;
                } else {
                    u_wavelength = next_f32(rng);
                }
            }
            let dispersed = dispersed_material(material, wavelength, u_wavelength);
            material = dispersed.material;
            wavelength = dispersed.wavelength;
            throughput *= dispersed.weight;
            // cpu::kernels: a thin film colours the metal by the angle to each micro-normal.
            let film = hit_film(material, hit.uv);
            if material.surface == SURFACE_ROUGH_CONDUCTOR {
                lit.glossy = throughput * tint;
                lit.alpha = material.roughness_alpha;
                lit.brush = hit.brush;
                if IRIDESCENCE && film.factor > 0.0 {
                    lit.glossy = throughput;
                    lit.film = film;
                    lit.film_base = tint;
                }
            }
            // cpu::kernels: solid frosted glass met from outside reflects as a coat does; met
            // from inside, its refraction out is the lobe.
            if FROSTED_GLASS && material.surface == SURFACE_ROUGH_DIELECTRIC && (material.flags & MATERIAL_THIN_WALLED) == 0u {
                lit.glossy = throughput * tint;
                lit.alpha = material.roughness_alpha;
                lit.glass_film = film;
                if hit.front {
                    lit.coat_ior = material.ior;
                } else {
                    lit.refraction_eta = material.ior;
                }
            }
            // cpu::kernels: a thin frosted sheet's reflection and transmission.
            if FROSTED_GLASS && material.surface == SURFACE_ROUGH_DIELECTRIC && (material.flags & MATERIAL_THIN_WALLED) != 0u {
                lit.glossy = throughput * tint;
                lit.alpha = material.roughness_alpha;
                lit.glass_film = film;
                lit.sheet_eta = relative_eta(material.ior, hit.front, true);
            }
            bounce = specular_direction(material, hit, direction, film, u, u_second, u_third);
            // Smooth glass's film takes its share below, after the way not taken is counted.
            if material.surface != SURFACE_DIELECTRIC {
                bounce_tint = bounce_tint_of(material, tint, film, hit, direction, bounce.direction);
            }
        }
        if DIFFUSE_TRANSMISSION && far_side {
            // The glossy lobes keep the hit's light sample, the Lambertian one takes the far
            // side's.
            var far_lit = lit;
            far_lit.glossy = vec3<f32>(0.0);
            far_lit.alpha = 0.0;
            lit.diffuse = vec3<f32>(0.0);
            if (params.sample_lights & SAMPLE_AT_GLOSSY) == 0u {
                lit.alpha = 0.0;
            }
            direct += sampled_light(hit, -direction, lit, medium, rng);
            // Inside a translucent solid where the surface bounds one.
            let far_medium = medium_after_bounce(material, root_id, medium, hit, -hit.geometric);
            direct += sampled_light(side.hit, -direction, far_lit, far_medium, rng);
            break;
        }
        if (params.sample_lights & SAMPLE_AT_GLOSSY) == 0u {
            lit.alpha = 0.0;
        }
        direct += sampled_light(hit, -direction, lit, medium, rng);
        if base || bounce.weight <= 0.0 {
            break;
        }
        glossy = glossy_after(hit, lit, -direction, bounce.direction);
        // Out through the sheen and the clear coat, if any.
        let out_of_coat = clearcoat_transmittance(coat_weight, dot(bounce.direction, hit.interpolated));
        let out_of_sheen = sheen_transmittance(sheen, dot(bounce.direction, hit.shading));
        throughput *= bounce_tint * (bounce.weight * out_of_coat * out_of_sheen);
        if max3(throughput) <= 0.0 {
            break;
        }
        depth += 1u;
        // cpu::kernels::eye_pass: at the first glass surface, the branch not taken is probed
        // next.
        // cpu::kernels::eye_path: under a thin film each channel of either way takes the
        // film's share of it.
        let probe = !met_glass && depth < params.max_depth;
        var glass_film = no_film();
        if material.surface == SURFACE_DIELECTRIC {
            glass_film = hit_film(material, hit.uv);
        }
        if material.surface == SURFACE_DIELECTRIC && (probe || glass_film.factor > 0.0) {
            let branches = dielectric_branches(material, hit, direction, glass_film);
            var other = branches.reflected;
            var other_share = branches.reflectance;
            var other_weight = branches.film_reflectance;
            if u < branches.reflectance {
                other = branches.transmitted;
                other_share = 1.0 - branches.reflectance;
                other_weight = vec3<f32>(1.0) - branches.film_reflectance;
            }
            if probe {
                met_glass = true;
                if any(other != bounce.direction) && other_share > 0.0 {
                    probing = true;
                    probe_origin = offset_origin(hit, other, params.epsilon);
                    probe_direction = other;
                    probe_weight = throughput * (other_weight * eye_crossing_scale(material, hit, other));
                    probe_medium = medium_after_bounce(material, root_id, medium, hit, other);
                    probe_kept = vec3<f32>(1.0);
                    emission_share = 1.0 - other_share;
                }
            }
            if IRIDESCENCE && glass_film.factor > 0.0 {
                throughput *= branch_weight(branches, all(bounce.direction == branches.reflected));
            }
        }
        throughput *= eye_crossing_scale(material, hit, bounce.direction);
        medium = medium_after_bounce(material, root_id, medium, hit, bounce.direction);
        origin = offset_origin(hit, bounce.direction, params.epsilon);
        direction = bounce.direction;
    }
    return EyePath(point, direct, specular_first);
}

// cpu::kernels::photon_key: slot `index`'s stored photon's first hash-entry word and its
// priority this pass; `stored` false if the slot stored none (or lies past the slots).
struct PhotonKey {
    entry: u32,
    // The class-0 entry of the same index's first word, which marks the photon's class
    // (photon_table > 0).
    class_zero_entry: u32,
    photon_table: u32,
    priority: u32,
    stored: bool,
}

fn photon_key(index: u32) -> PhotonKey {
    if index >= params.slot_count {
        return PhotonKey(0u, 0u, 0u, 0u, false);
    }
    let photon = load_photon(index);
    if !any(photon.flux != vec3<f32>(0.0)) {
        return PhotonKey(0u, 0u, 0u, 0u, false);
    }
    let cell_size = bitcast<f32>(atomicLoad(&counters[COUNTER_CELL_SIZE]));
    let photon_table = photon_class(photon.flux);
    let entry = entry_of(cell_of(photon.position, cell_size), params.hash_size);
    let pass_index = atomicLoad(&counters[COUNTER_PASS]);
    let priority = stream_key(params.seed, HASH_STREAM, pass_index, index) | 1u;
    let word = (photon_table * params.hash_size + entry) * HASH_ENTRY_WORDS;
    return PhotonKey(word, entry * HASH_ENTRY_WORDS, photon_table, priority, true);
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn hash_count(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let key = photon_key(invocation_index(id, groups));
    if key.stored {
        atomicMax(&hash[key.entry + HASH_PRIORITY], key.priority);
        atomicAdd(&hash[key.entry + HASH_COUNT], 1u);
        if key.photon_table > 0u {
            atomicOr(&hash[key.class_zero_entry + HASH_COUNT], class_mark(key.photon_table));
        }
    }
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn hash_select(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let index = invocation_index(id, groups);
    let key = photon_key(index);
    if key.stored && atomicLoad(&hash[key.entry + HASH_PRIORITY]) == key.priority {
        atomicMax(&hash[key.entry + HASH_WINNER], index);
    }
}

// cpu::kernels::GatherSum: the indirect photons a gather counts (M) and their flux, the
// caustic ones, and the volume ones (their flux times the phase function towards the eye).
struct GatherSum {
    found: u32,
    flux: vec3<f32>,
    caustic_found: u32,
    caustic_flux: vec3<f32>,
    volume_found: u32,
    volume_flux: vec3<f32>,
}

fn no_photons() -> GatherSum {
    return GatherSum(0u, vec3<f32>(0.0), 0u, vec3<f32>(0.0), 0u, vec3<f32>(0.0));
}

// cpu::kernels::GatherQuery with its VolumeQuery: where and how far a visible point gathers.
// A volume visible point (volume true, inside murky glass) gathers the volume photons within
// volume_radius instead, weighed by the phase function between their way and its eye path's
// `direction` in a medium of asymmetry `anisotropy`.
struct GatherQuery {
    position: vec3<f32>,
    normal: vec3<f32>,
    radius: f32,
    caustic_radius: f32,
    volume: bool,
    direction: vec3<f32>,
    anisotropy: f32,
    volume_radius: f32,
}

// cpu::kernels::GatherQuery::reach: how far any photon may count, which the density methods
// search.
fn reach(query: GatherQuery) -> f32 {
    if MURKY_GLASS && query.volume {
        return query.volume_radius;
    }
    return max(query.radius, query.caustic_radius);
}

// cpu::kernels::GatherSum::add_if_near: `count` photons of `photon`'s flux to its class when
// it lies inside that class's sphere and on the visible point's side of the surface; a volume
// visible point counts only volume photons, each times the phase function towards the eye,
// and a surface one none of them.
fn add_if_near(sum: ptr<function, GatherSum>, query: GatherQuery, photon: Photon, count: u32) {
    let offset = photon.position - query.position;
    if MURKY_GLASS {
        if query.volume {
            let radius = query.volume_radius;
            if is_volume(photon.normal) && dot(offset, offset) < radius * radius {
                let cos = -dot(unpack_normal(photon.normal), query.direction);
                let phase = henyey_greenstein_phase(query.anisotropy, cos);
                (*sum).volume_found += count;
                (*sum).volume_flux += (f32(count) * phase) * photon.flux;
            }
            return;
        }
        if is_volume(photon.normal) {
            return;
        }
    }
    let caustic = is_caustic(photon.normal);
    let radius = select(query.radius, query.caustic_radius, caustic);
    if dot(offset, offset) < radius * radius && dot(unpack_normal(photon.normal), query.normal) > 0.0 {
        let flux = f32(count) * photon.flux;
        if caustic {
            (*sum).caustic_found += count;
            (*sum).caustic_flux += flux;
        } else {
            (*sum).found += count;
            (*sum).flux += flux;
        }
    }
}

// The query of visible point `point` with its pixel's radii (cpu::kernels::gather_update): a
// volume visible point's word holds its eye path's way and its medium's asymmetry.
fn gather_query(point: VisiblePoint, radius: f32, caustic_radius: f32, volume_radius: f32) -> GatherQuery {
    var query = GatherQuery(point.position, vec3<f32>(0.0), radius, caustic_radius, false, vec3<f32>(0.0), 0.0, volume_radius);
    if MURKY_GLASS && is_volume(point.normal) {
        let unpacked = unpack_volume_point(point.normal);
        query.volume = true;
        query.direction = unpacked.xyz;
        query.anisotropy = unpacked.w;
        query.normal = -unpacked.xyz;
    } else {
        query.normal = unpack_normal(point.normal);
    }
    return query;
}

// One class's statistics (PixelStats' τ, N and R of the indirect, caustic or volume photons).
struct Estimate {
    tau: vec3<f32>,
    count: f32,
    radius: f32,
}

// cpu::kernels' dimensions a set of statistics gathers over: a disc's on surfaces, a sphere's
// in murky glass.
const AREA: u32 = 2u;
const VOLUME: u32 = 3u;

// cpu::kernels::shrink_to_fit: a radius larger than the cells allow shrinks to `largest`, τ
// scaled with the disc's area or the sphere's volume (Rust's powi: (s·s)·s).
fn shrink_to_fit(e: Estimate, largest: f32, dimensions: u32) -> Estimate {
    let shrink = largest / e.radius;
    var scale = shrink * shrink;
    if dimensions == VOLUME {
        scale *= shrink;
    }
    return Estimate(e.tau * scale, e.count, largest);
}

// f32::cbrt of x in (0, 1]: pow's estimate, a few ulp off on GPUs, and one Newton step.
fn cube_root(x: f32) -> f32 {
    let c = pow(x, 1.0 / 3.0);
    if c <= 0.0 {
        return c;
    }
    return c - (c * c * c - x) / (3.0 * c * c);
}

// cpu::kernels::update: one class's statistics after M > 0 photons of weighted flux `flux`,
// the radius shrinking by the square root of the count's ratio on a disc, the cube root in a
// sphere.
fn update(e: Estimate, found: u32, flux: vec3<f32>, alpha: f32, dimensions: u32) -> Estimate {
    let n = e.count;
    let m = f32(found);
    let n_next = n + alpha * m;
    let ratio = n_next / (n + m);
    var shrink = sqrt(ratio);
    if dimensions == VOLUME {
        shrink = cube_root(ratio);
    }
    return Estimate((e.tau + flux) * ratio, n_next, e.radius * shrink);
}

// `e` shrunk to `largest` where it is larger; `changed` set where it was.
fn fitted(e: Estimate, largest: f32, dimensions: u32, changed: ptr<function, bool>) -> Estimate {
    if e.radius > largest {
        *changed = true;
        return shrink_to_fit(e, largest, dimensions);
    }
    return e;
}

// `e` updated with `found` photons of weighted flux `flux` where there are any, and offered
// to the pass's largest lit radius where it has met photons; `changed` set where it was
// updated.
fn updated(e: Estimate, found: u32, flux: vec3<f32>, alpha: f32, dimensions: u32, changed: ptr<function, bool>) -> Estimate {
    var next = e;
    if found > 0u {
        next = update(e, found, flux, alpha, dimensions);
        *changed = true;
    }
    if next.count > 0.0 {
        atomicMax(&counters[COUNTER_MAX_RADIUS], bitcast<u32>(next.radius));
    }
    return next;
}

// cpu::kernels::gather_with: the update is the same for every density method; the module's
// `density_query` (density_*.wgsl) finds the photons.
@compute @workgroup_size(WORKGROUP_SIZE)
fn gather(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let index = invocation_index(id, groups);
    if index >= params.width * params.height {
        return;
    }
    var stats = pixels[index];
    let point = load_visible_point(index);
    let cell_size = bitcast<f32>(atomicLoad(&counters[COUNTER_CELL_SIZE]));
    // A radius larger than the cells allow shrinks to fit.
    let largest = largest_radius(cell_size);
    var changed = false;
    var indirect = fitted(Estimate(stats.tau, stats.photon_count, stats.radius), largest, AREA, &changed);
    var caustic = fitted(Estimate(stats.caustic_tau, stats.caustic_count, stats.caustic_radius), largest, AREA, &changed);
    var volume = fitted(Estimate(stats.volume_tau, stats.volume_count, stats.volume_radius), largest, VOLUME, &changed);
    if any(point.weight != vec3<f32>(0.0)) {
        let query = gather_query(point, indirect.radius, caustic.radius, volume.radius);
        let sum = density_query(query, cell_size);
        indirect = updated(indirect, sum.found, point.weight * sum.flux, params.indirect_alpha, AREA, &changed);
        caustic = updated(caustic, sum.caustic_found, point.weight * sum.caustic_flux, params.alpha, AREA, &changed);
        volume = updated(volume, sum.volume_found, point.weight * sum.volume_flux, params.alpha, VOLUME, &changed);
    }
    if changed {
        stats.tau = indirect.tau;
        stats.photon_count = indirect.count;
        stats.radius = indirect.radius;
        stats.caustic_tau = caustic.tau;
        stats.caustic_count = caustic.count;
        stats.caustic_radius = caustic.radius;
        stats.volume_tau = volume.tau;
        stats.volume_count = volume.count;
        stats.volume_radius = volume.radius;
        pixels[index] = stats;
    }
}

// One invocation: the pass's emitted paths into the 64-bit total, the next cell size from the
// largest radius, the pass counter advanced (cpu::kernels::finish_pass).
@compute @workgroup_size(1)
fn finish_pass() {
    let emitted = atomicExchange(&counters[COUNTER_EMITTED_PASS], 0u);
    let low = atomicLoad(&counters[COUNTER_EMITTED_LO]);
    let sum = low + emitted;
    atomicStore(&counters[COUNTER_EMITTED_LO], sum);
    atomicAdd(&counters[COUNTER_EMITTED_HI], select(0u, 1u, sum < low));
    let max_radius = bitcast<f32>(atomicExchange(&counters[COUNTER_MAX_RADIUS], 0u));
    if max_radius > 0.0 {
        atomicStore(&counters[COUNTER_CELL_SIZE], bitcast<u32>(hash_cell_size(max_radius)));
    }
    atomicAdd(&counters[COUNTER_PASS], 1u);
}
