// The light table: the sky's radiance, a light picked by its power, and where and how a
// photon path leaves it (render::emission).

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

// scene::lights::spot_falloff, its shape by scene::SpotFalloff::code (0 glTF's, 1 smoothstep,
// 2 linear in the angle).
fn spot_falloff(cos_angle: f32, cos_inner: f32, cos_outer: f32, shape: f32) -> f32 {
    if cos_angle >= cos_inner {
        return 1.0;
    }
    if cos_angle <= cos_outer {
        return 0.0;
    }
    let ramp = (cos_angle - cos_outer) / max(cos_inner - cos_outer, 1.17549435e-38);
    if shape == 1.0 {
        return ramp * ramp * (3.0 - 2.0 * ramp);
    }
    if shape == 2.0 {
        let inner = acos(cos_inner);
        let outer = acos(cos_outer);
        let width = max(outer - inner, 1.17549435e-38);
        return clamp((outer - acos(cos_angle)) / width, 0.0, 1.0);
    }
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
        flux = spot_falloff(local.z, light.edge2.x, light.edge2.y, light.edge2.z) * flux;
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
    return PathSlot(origin + params.epsilon * normal, 0u, direction, 0u, flux, pack_slot_state(false, light.medium, WHOLE_SPECTRUM), vec3<f32>(1.0), NO_WALK);
}
