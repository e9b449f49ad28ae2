// A path's medium between surfaces: Beer–Lambert absorption (render::medium), the random walks
// of scattering solids and murky glass (render::scattering), and the slot's state word.

// ---- render::medium ----
// The solid a path is inside, for Beer–Lambert absorption; NO_MEDIUM outside every one.
const NO_MEDIUM: u32 = 0xffffffffu;

// Whether some solid absorbs inside (a material with interior absorption); compiled out as
// NORMAL_MAPS is: without one every transmittance is 1 and paths need no medium.
override MEDIA: bool = true;

// render::medium::medium_after.
fn medium_after(medium: u32, root: u32, exterior: u32, solid: bool, front: bool, crosses: bool) -> u32 {
    if !(solid && crosses) {
        return medium;
    }
    return select(exterior, root, front);
}

// render::medium::segment_medium.
fn segment_medium(medium: u32, root: u32, absorbs_inside: bool, front: bool) -> u32 {
    return select(medium, root, !front && absorbs_inside);
}

// cpu::surface::medium_transmittance (render::medium::transmittance): from RAY_T_MAX on the
// distance is infinite.
fn medium_transmittance(medium: u32, distance: f32) -> vec3<f32> {
    if !MEDIA || medium == NO_MEDIUM {
        return vec3<f32>(1.0);
    }
    let absorption = materials[medium].absorption;
    if distance < RAY_T_MAX {
        return exp(-absorption * distance);
    }
    return select(vec3<f32>(1.0), vec3<f32>(0.0), absorption > vec3<f32>(0.0));
}

// cpu::surface::transmittance_to: what a path in `medium` keeps over the segment that ended at
// `hit` (its material still the root one).
fn transmittance_to(medium: u32, hit: SurfaceHit) -> vec3<f32> {
    if !MEDIA {
        return vec3<f32>(1.0);
    }
    let absorbs_inside = max3(materials[hit.material].absorption) > 0.0;
    return medium_transmittance(segment_medium(medium, hit.material, absorbs_inside, hit.front), hit.distance);
}

// cpu::surface::medium_after_bounce.
fn medium_after_bounce(material: GpuMaterial, root: u32, medium: u32, hit: SurfaceHit, next: vec3<f32>) -> u32 {
    let solid = (material.flags & MATERIAL_BOUNDS_VOLUME) != 0u;
    let crosses = dot(next, hit.geometric) < 0.0;
    // The solid around, read only where the path leaves one.
    var exterior = NO_MEDIUM;
    if solid && crosses && !hit.front {
        exterior = materials[root].exterior;
    }
    return medium_after(medium, root, exterior, solid, hit.front, crosses);
}

// ---- render::scattering ----
// Whether some solid scatters inside (a translucent solid or murky glass); compiled out as
// MEDIA is.
override SCATTERING: bool = true;
// Whether some of them is murky glass (MATERIAL_MURKY_GLASS): volume photons, volume visible
// points and their statistics; compiled out as MEDIA is.
override MURKY_GLASS: bool = true;

// render::scattering::murky_glass: whether `medium` is murky glass, where photons are kept as
// they scatter and eye paths end where they scatter.
fn is_murky_glass(medium: u32) -> bool {
    return MURKY_GLASS && medium != NO_MEDIUM && (materials[medium].flags & MATERIAL_MURKY_GLASS) != 0u;
}

// render::scattering::Walk: its hero channel, its weight, and each channel's density of it
// over their mean.
struct Walk {
    hero: u32,
    weight: vec3<f32>,
    densities: vec3<f32>,
}

// render::scattering::Walk::start.
fn walk_start(u: f32) -> Walk {
    return Walk(min(u32(u * 3.0), 2u), vec3<f32>(1.0), vec3<f32>(1.0));
}

// render::scattering::Walk::resume: a path's walk from the hero and densities it carried, its
// weight since handed to the path (a hero of NO_WALK: the path has not walked; not called).
fn walk_resume(hero: u32, densities: vec3<f32>) -> Walk {
    return Walk(min(hero, 2u), vec3<f32>(1.0), densities);
}

// render::scattering::Walk::flight: the distance to the scattering event, or -1 where the
// walk reaches the segment's end.
fn walk_flight(walk: ptr<function, Walk>, extinction: vec3<f32>, scattering: vec3<f32>, distance: f32, u: f32) -> f32 {
    let rate = extinction[(*walk).hero];
    let t = -log(1.0 - u) / max(rate, 1e-30);
    var value: vec3<f32>;
    var density: vec3<f32>;
    var scattered = -1.0;
    if rate > 0.0 && t < distance {
        let kept = exp(-extinction * t);
        value = scattering * kept;
        density = extinction * kept;
        scattered = t;
    } else {
        let kept = exp(-extinction * distance);
        value = kept;
        density = kept;
    }
    let densities = (*walk).densities * density;
    let mean = (densities.x + densities.y + densities.z) / 3.0;
    if mean > 0.0 {
        (*walk).weight *= value / mean;
        (*walk).densities = densities / mean;
    } else {
        (*walk).weight = vec3<f32>(0.0);
    }
    return scattered;
}

// render::scattering::Walk::survives.
fn walk_survives(walk: ptr<function, Walk>, u: f32) -> bool {
    let survival = min(max3((*walk).weight), 1.0);
    if u >= survival {
        return false;
    }
    (*walk).weight /= survival;
    return true;
}

// render::scattering::Walk::weight_over_scattering: the weight after a flight that ended at
// a scattering event over σs (0 in a channel that does not scatter).
fn walk_weight_over_scattering(walk: Walk, scattering: vec3<f32>) -> vec3<f32> {
    let over = walk.weight / max(scattering, vec3<f32>(1.17549435e-38));
    return select(vec3<f32>(0.0), over, scattering > vec3<f32>(0.0));
}

// render::scattering::henyey_greenstein_phase: per steradian, at the cosine between the way
// light travelled and the way it is scattered.
fn henyey_greenstein_phase(g: f32, cos: f32) -> f32 {
    let denominator = max(1.0 + g * g - 2.0 * g * cos, 1e-12);
    return (1.0 - g * g) / (4.0 * PI * denominator * sqrt(denominator));
}

// render::scattering::henyey_greenstein.
fn henyey_greenstein(direction: vec3<f32>, g: f32, u0: f32, u1: f32) -> vec3<f32> {
    var cos_theta = 1.0 - 2.0 * u0;
    if abs(g) >= 1e-3 {
        let s = (1.0 - g * g) / (1.0 - g + 2.0 * g * u0);
        cos_theta = clamp((1.0 + g * g - s * s) / (2.0 * g), -1.0, 1.0);
    }
    let sin_theta = sqrt(max(1.0 - cos_theta * cos_theta, 0.0));
    let phi = 2.0 * PI * u1;
    return to_world(frame_about(direction), vec3<f32>(sin_theta * cos(phi), sin_theta * sin(phi), cos_theta));
}

// render::medium::pack_slot_state, slot_bounced, slot_medium and slot_wavelength.
fn pack_slot_state(bounced: bool, medium: u32, wavelength: u32) -> u32 {
    return ((wavelength + 1u) << WAVELENGTH_SHIFT) | (((medium + 1u) & MEDIUM_MASK) << 1u) | select(0u, 1u, bounced);
}

fn slot_bounced(state: u32) -> bool {
    return (state & 1u) != 0u;
}

fn slot_medium(state: u32) -> u32 {
    return ((state >> 1u) & MEDIUM_MASK) - 1u;
}

fn slot_wavelength(state: u32) -> u32 {
    return (state >> WAVELENGTH_SHIFT) - 1u;
}
