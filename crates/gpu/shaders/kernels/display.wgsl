// The progressive image on screen (gpu::display): a full-screen triangle whose fragments read
// the SPPM statistics in place, resolve them like render::resolve::resolve_pixel, apply the
// exposure and tone map like render::tonemap::Look::display_rgb (a clamp like display_value,
// or PBR Neutral like pbr_neutral) and, for targets that are not sRGB, the sRGB transfer like
// render::tonemap::linear_to_srgb.

// Mirrors gpu::display::DisplayParams (tests/layout.rs checks the offsets).
struct DisplayParams {
    render_width: u32,
    render_height: u32,
    // The size in pixels of the viewport the image fills.
    target_width: u32,
    target_height: u32,
    eye_passes: u32,
    // Stops: the radiance is multiplied by 2^exposure.
    exposure: f32,
    // 1: write sRGB-encoded values (the target is not an sRGB format); 0: linear values.
    encode_srgb: u32,
    // render::tonemap::ToneMap::code: 0 the clamp, 1 PBR Neutral.
    tone_map: u32,
    // render::resolve::Parts::bits: bit k shows part k (direct, indirect, caustic, volume).
    parts: u32,
    pad0: u32,
    pad1: u32,
    pad2: u32,
}

@group(0) @binding(0) var<uniform> display: DisplayParams;
@group(0) @binding(1) var<storage, read> display_pixels: array<PixelStats>;
@group(0) @binding(2) var<storage, read> display_counters: array<u32>;
// The volume photons' τ (render::buffers::PixelStats::volume_tau), a pixel each where the
// scene has murky glass, else one unused element.
@group(0) @binding(3) var<storage, read> display_volume_tau: array<vec4<f32>>;

struct DisplayVertex {
    @builtin(position) position: vec4<f32>,
    // (0, 0) at the viewport's top-left corner, (1, 1) at its bottom-right.
    @location(0) uv: vec2<f32>,
}

// One triangle covering the viewport: vertices at clip (-1, -1), (3, -1) and (-1, 3).
@vertex
fn display_vertex(@builtin(vertex_index) index: u32) -> DisplayVertex {
    let x = f32((index & 1u) * 4u) - 1.0;
    let y = f32((index >> 1u) * 4u) - 1.0;
    var out: DisplayVertex;
    out.position = vec4<f32>(x, y, 0.0, 1.0);
    out.uv = vec2<f32>(0.5 * (x + 1.0), 0.5 * (1.0 - y));
    return out;
}

// The render pixel shown at viewport pixel `target` of `target_size` pixels in one dimension:
// the one under its centre when the image is scaled to fill the viewport (nearest pixel).
fn display_source_index(target_pixel: u32, target_size: u32, render_size: u32) -> u32 {
    let scaled = ((2u * target_pixel + 1u) * render_size) / (2u * target_size);
    return min(scaled, render_size - 1u);
}

// render::resolve::resolve_parts: direct / E + τ / (π R² N_emitted) for each class on
// surfaces, τ / (4/3 π R³ N_emitted) for the volume photons, each where display.parts shows it.
fn display_resolve(stats: PixelStats, volume_tau: vec3<f32>) -> vec3<f32> {
    var direct = vec3<f32>(0.0);
    if display.eye_passes > 0u {
        direct = stats.direct / f32(display.eye_passes);
    }
    let emitted = f32(display_counters[COUNTER_EMITTED_HI]) * 4294967296.0
        + f32(display_counters[COUNTER_EMITTED_LO]);
    let volume = 4.0 / 3.0 * PI * stats.volume_radius * stats.volume_radius * stats.volume_radius;
    return display_part(0u, direct)
        + display_part(1u, display_density(stats.tau, PI * stats.radius * stats.radius, emitted))
        + display_part(2u, display_density(stats.caustic_tau, PI * stats.caustic_radius * stats.caustic_radius, emitted))
        + display_part(3u, display_density(volume_tau, volume, emitted));
}

// Part `part` of the radiance where display.parts shows it, else 0.
fn display_part(part: u32, radiance: vec3<f32>) -> vec3<f32> {
    return select(vec3<f32>(0.0), radiance, (display.parts & (1u << part)) != 0u);
}

// τ over a disc's area or a sphere's volume (`measure`) and the emitted paths.
fn display_density(tau: vec3<f32>, measure: f32, emitted: f32) -> vec3<f32> {
    if emitted > 0.0 && measure > 0.0 {
        return tau / (measure * emitted);
    }
    return vec3<f32>(0.0);
}

// Whether `x` is neither infinite nor NaN, from its bits (WGSL has no isnan, and compilers may
// assume floats are finite).
fn display_is_finite(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7f800000u) != 0x7f800000u;
}

// render::tonemap::display_value.
fn display_value(linear: f32, scale: f32) -> f32 {
    let scaled = linear * scale;
    if display_is_finite(scaled) {
        return clamp(scaled, 0.0, 1.0);
    }
    return 0.0;
}

// render::tonemap::pbr_neutral: Khronos PBR Neutral of non-negative exposed radiance.
fn display_pbr_neutral(colour: vec3<f32>) -> vec3<f32> {
    let compression_start = 0.8 - 0.04;
    let desaturation = 0.15;
    let darkest = min(colour.x, min(colour.y, colour.z));
    var offset = 0.04;
    if darkest < 0.08 {
        offset = darkest - 6.25 * darkest * darkest;
    }
    let c = colour - vec3<f32>(offset);
    let peak = max(c.x, max(c.y, c.z));
    if peak < compression_start {
        return c;
    }
    let d = 1.0 - compression_start;
    let new_peak = 1.0 - d * d / (peak + d - compression_start);
    let grey = 1.0 - 1.0 / (desaturation * (peak - new_peak) + 1.0);
    return mix(c * (new_peak / peak), vec3<f32>(new_peak), grey);
}

// render::tonemap::Look::display_rgb under PBR Neutral: non-finite channels count as 0.
fn display_neutral(radiance: vec3<f32>, scale: f32) -> vec3<f32> {
    var exposed = vec3<f32>(0.0);
    for (var i = 0u; i < 3u; i += 1u) {
        let value = radiance[i] * scale;
        if display_is_finite(value) {
            exposed[i] = max(value, 0.0);
        }
    }
    return display_pbr_neutral(exposed);
}

// render::tonemap::linear_to_srgb.
fn display_encode_srgb(c: vec3<f32>) -> vec3<f32> {
    let low = 12.92 * c;
    let high = 1.055 * pow(c, vec3<f32>(1.0 / 2.4)) - 0.055;
    return select(high, low, c <= vec3<f32>(0.0031308));
}

@fragment
fn display_fragment(vertex: DisplayVertex) -> @location(0) vec4<f32> {
    let target_size = vec2<u32>(display.target_width, display.target_height);
    let target_pixel = min(vec2<u32>(vertex.uv * vec2<f32>(target_size)), target_size - 1u);
    let x = display_source_index(target_pixel.x, display.target_width, display.render_width);
    let y = display_source_index(target_pixel.y, display.target_height, display.render_height);
    let index = y * display.render_width + x;
    // A scene without murky glass has one zero element there, not one a pixel: τ is 0.
    var volume_tau = vec3<f32>(0.0);
    if arrayLength(&display_volume_tau) == display.render_width * display.render_height {
        volume_tau = display_volume_tau[index].xyz;
    }
    let radiance = display_resolve(display_pixels[index], volume_tau);
    let scale = exp2(display.exposure);
    var colour = vec3<f32>(
        display_value(radiance.x, scale),
        display_value(radiance.y, scale),
        display_value(radiance.z, scale),
    );
    if display.tone_map == 1u {
        colour = display_neutral(radiance, scale);
    }
    if display.encode_srgb != 0u {
        colour = display_encode_srgb(colour);
    }
    return vec4<f32>(colour, 1.0);
}
