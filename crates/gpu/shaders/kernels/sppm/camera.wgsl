// Where an eye path starts: its pixel's numbers this eye pass (render::rng) and the camera ray
// through the lens (render::lens).

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
// (sx, sy) that leaves the lens at the point `lens` maps to; the pinhole's ray at radius 0; an
// orthographic camera's from the film point along the view.
struct CameraRay {
    origin: vec3<f32>,
    direction: vec3<f32>,
}

fn camera_ray(sx: f32, sy: f32, lens: vec2<f32>) -> CameraRay {
    if params.orthographic != 0u {
        return CameraRay(params.eye + sx * params.right + sy * params.up, normalize(params.forward));
    }
    let through = params.forward + sx * params.right + sy * params.up;
    if params.lens_radius <= 0.0 {
        return CameraRay(params.eye, normalize(through));
    }
    let focus = params.eye + params.focus_distance * through;
    let disk = params.lens_radius * aperture_point(lens.x, lens.y, params.aperture_blades, params.aperture_rotation);
    let origin = params.eye + disk.x * normalize(params.right) + disk.y * normalize(params.up);
    return CameraRay(origin, normalize(focus - origin));
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
