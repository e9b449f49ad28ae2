// Light samples at an eye path's hit (render::direct, render::resampling): one light's sample
// and its density, and the sample kept among several candidates.

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
            let falloff = spot_falloff(-dot(sample.direction, light.edge1), light.edge2.x, light.edge2.y, light.edge2.z);
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
