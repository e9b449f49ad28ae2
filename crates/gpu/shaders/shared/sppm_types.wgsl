// WGSL twins of render::buffers; tests/layout.rs checks sizes and offsets against Rust.

struct PathSlot {
    origin: vec3<f32>,
    depth: u32,
    direction: vec3<f32>,
    pass_throughs: u32,
    flux: vec3<f32>,
    // render::buffers::PathSlot::state (render::medium::pack_slot_state).
    state: u32,
    // The path's walk through scattering solids (render::scattering::Walk): its channels'
    // densities over their mean and its hero (NO_WALK before its first).
    walk_densities: vec3<f32>,
    walk_hero: u32,
}

struct Photon {
    position: vec3<f32>,
    normal: u32,
    flux: vec3<f32>,
    pad: u32,
}

struct VisiblePoint {
    position: vec3<f32>,
    normal: u32,
    weight: vec3<f32>,
    pad: u32,
}

// render::buffers::PixelStats up to its volume_tau (64 bytes, PIXEL_STATS_SURFACE_BYTES;
// each τ on a 16-byte boundary): the volume photons' τ has its own buffer, pixel_volume_tau,
// only as long as the image where the scene has murky glass.
struct PixelStats {
    tau: vec3<f32>,
    photon_count: f32,
    direct: vec3<f32>,
    radius: f32,
    caustic_tau: vec3<f32>,
    caustic_count: f32,
    caustic_radius: f32,
    // render::buffers::PixelStats::specular_seen.
    specular_seen: u32,
    // N and R of the volume photons (murky glass; τ in pixel_volume_tau).
    volume_count: f32,
    volume_radius: f32,
}

// render::buffers::Light: what v0, edge1 and edge2 hold depends on kind (LIGHT_*).
struct Light {
    v0: vec3<f32>,
    cdf: f32,
    edge1: vec3<f32>,
    double_sided: u32,
    edge2: vec3<f32>,
    kind: u32,
    flux: vec3<f32>,
    // render::buffers::Light::medium.
    medium: u32,
}

struct SppmParams {
    eye: vec3<f32>,
    width: u32,
    forward: vec3<f32>,
    height: u32,
    right: vec3<f32>,
    slot_count: u32,
    up: vec3<f32>,
    hash_size: u32,
    alpha: f32,
    max_depth: u32,
    light_count: u32,
    seed: u32,
    epsilon: f32,
    // render::buffers::SppmParams::storage_origin (scalars: a vec3 would be 16-byte aligned).
    origin_x: f32,
    origin_y: f32,
    origin_z: f32,
    flux_scale: f32,
    // render::buffers::SppmParams::sky, the sky's radiance (zero without one), as scalars.
    sky_r: f32,
    sky_g: f32,
    sky_b: f32,
    // render::buffers::SppmParams::sample_lights, cut_outs, eye_every and indirect_alpha.
    sample_lights: u32,
    cut_outs: u32,
    eye_every: u32,
    indirect_alpha: f32,
    // render::buffers::SppmParams::camera_medium.
    camera_medium: u32,
    // render::buffers::SppmParams::photon_classes (render::hash::photon_class).
    photon_classes: u32,
    // render::buffers::SppmParams::lens_radius and focus_distance (render::lens).
    lens_radius: f32,
    focus_distance: f32,
    // render::buffers::SppmParams::scene_half_extent (render::emission::parallel_start).
    scene_half_extent: vec3<f32>,
    // render::buffers::SppmParams::aperture_blades and aperture_rotation (render::lens).
    aperture_blades: u32,
    aperture_rotation: f32,
    // render::buffers::SppmParams::light_candidates (render::resampling).
    light_candidates: u32,
    // render::buffers::SppmParams::orthographic (render::lens::camera_ray).
    orthographic: u32,
    // render::buffers::SppmParams::shrunk_tenths (render::radius_histogram).
    shrunk_tenths: u32,
}

// render::half_storage::HalfPoint: a photon or visible point in f16 (16 bytes).
struct HalfPoint {
    xy: u32,
    z_r: u32,
    g_b: u32,
    normal: u32,
}
