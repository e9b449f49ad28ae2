//! The SPPM kernels, one function per GPU invocation: the same names, arithmetic and random
//! numbers as `crates/gpu/shaders/kernels/sppm/*.wgsl`. Each takes one element's input and
//! returns its output, so the backend can run them on rayon and the tests can run them alone.

use std::f32::consts::FRAC_1_PI;
use std::sync::atomic::{AtomicU32, Ordering::Relaxed};

use glam::Vec3;
use render::blend::{blend_member, blend_photon_member, mapped_material, mapped_surface};
use render::buffers::{
    HASH_ENTRY_WORDS, MAX_PASS_THROUGHS, PathSlot, Photon, PixelStats, RAY_T_MAX, SAMPLE_AT_GLOSSY,
    SAMPLE_AT_VISIBLE_POINTS, SLOT_IDLE, SppmParams, VisiblePoint, counter, hash_word, vec3,
};
use render::clearcoat::clearcoat_transmittance;
use render::conductor::Metal;
use render::dielectric_layer::{DielectricLayer, lobe_layer_weight};
use render::direct::{shadow_ray, sky_pdf, triangle_pdf};
use render::dispersion::WHOLE_SPECTRUM;
use render::emission::sample_emission;
use render::hash::{caustic_apart, class_is_caustic};
use render::hash::{
    cell_of, class_entry, class_mark, entry_count, entry_of, grid_cell_size, grid_largest_radius,
    grid_salt, lies_in, photon_class, priority, query_entries, volume_query_entries,
};
use render::lens::camera_ray;
use render::light_sampling::power_heuristic;
use render::medium::{pack_slot_state, slot_bounced, slot_medium, slot_wavelength};
use render::microfacet::GlossyLobe;
use render::normal_map::{arrival_factor, bounded_correction, departure_factor};
use render::optics::relative_eta;
use render::packing::{
    is_caustic, is_volume, photon_normal, surface_normal, unpack_normal, unpack_volume_point,
    volume_photon_direction, volume_point_direction,
};
use render::radius_histogram::{RADIUS_BUCKETS, radius_bucket, served_radius};
use render::random::StreamRng;
use render::resampling::resample_light;
use render::rng::{
    EYE_STREAM, KernelRng, PHOTON_STREAM, pixel_jitter, pixel_lens, pixel_side, pixel_wavelength,
};
use render::scattering::{
    SCATTERINGS_PER_STEP, Walk, henyey_greenstein, henyey_greenstein_phase, murky_glass,
    scattering_solid,
};
use render::shadow_terminator::is_lifted;
use render::volume_boundary;
use scene::{Material, Surface};

use crate::SceneData;
use crate::surface::{
    HitTexel, PlasticBounce, SurfaceHit, base_color, bounce_tint, clearcoat_bounce,
    dielectric_branches, diffuse_bounce, diffuse_transmission_at, dispersed_surface, emitted,
    eye_crossing_scale, hit_clearcoat, hit_dielectric_layer, hit_sheen, is_cut_out,
    lambertian_side, medium_after_bounce, medium_transmittance, offset_origin, plastic_bounce,
    shadow_ray_origin, sheen_bounce, specular_direction, trace, transmittance_to, unoccluded,
};

/// What one photon-pass invocation leaves behind.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhotonStep {
    pub slot: PathSlot,
    /// The photon stored at this bounce (zero flux if none).
    pub photon: Photon,
    /// Whether the slot started a new light path.
    pub emitted: bool,
}

/// Photon pass, slot `index`: an idle slot starts a new light path; then the path advances
/// one segment. A diffuse hit stores a photon and continues by Russian roulette on its albedo;
/// a specular one reflects or refracts (roulette on its tint); a cut-out is passed through.
pub fn photon_pass(
    scene: &SceneData,
    params: &SppmParams,
    pass: u32,
    index: u32,
    slot: PathSlot,
) -> PhotonStep {
    photon_pass_with::<KernelRng>(scene, params, pass, index, slot)
}

/// [`photon_pass`] drawing from generator `R` (the twin of the kernels compiled with
/// `gpu::random_variants`), for `kousen bench rng`.
pub fn photon_pass_with<R: StreamRng>(
    scene: &SceneData,
    params: &SppmParams,
    pass: u32,
    index: u32,
    mut slot: PathSlot,
) -> PhotonStep {
    let mut rng = R::start(params.seed, PHOTON_STREAM, pass, index);
    let mut emitted = false;
    if slot.depth == SLOT_IDLE {
        let u = [(); 5].map(|_| rng.next_f32());
        let e = sample_emission(
            &scene.lights,
            &scene.sky_map,
            vec3(params.scene_half_extent),
            u,
        );
        slot = PathSlot {
            origin: (e.origin + params.epsilon * e.normal).to_array(),
            depth: 0,
            direction: e.direction.to_array(),
            pass_throughs: 0,
            flux: e.flux.to_array(),
            state: pack_slot_state(false, e.medium, WHOLE_SPECTRUM),
            ..PathSlot::IDLE
        };
        emitted = true;
    }
    let mut photon = Photon::default();
    // The medium the path is in (`render::medium`) absorbs along the segment, up to a
    // cut-out too; a scattering one walks it to a surface (`render::scattering`).
    let medium = slot_medium(slot.state);
    let Some(segment) = photon_segment(scene, &slot, medium, || rng.next_f32()) else {
        slot.depth = SLOT_IDLE;
        return PhotonStep {
            slot,
            photon,
            emitted,
        };
    };
    let PhotonSegment {
        hit,
        origin,
        direction,
        flux,
        scattered,
        volume_photon,
        walk,
    } = segment;
    if let Some(kept) = volume_photon {
        photon = kept;
    }
    if let Some(walk) = walk {
        slot.walk_hero = walk.hero();
        slot.walk_densities = walk.densities().to_array();
    }
    let Some(mut hit) = hit else {
        // Still walking inside a scattering solid: it goes on from there next pass, the step
        // counted as a bounce (ended where its walk's roulette ended it in murky glass).
        slot.depth += 1;
        if slot.depth >= params.max_depth || flux == Vec3::ZERO {
            slot.depth = SLOT_IDLE;
        } else {
            slot.origin = origin.to_array();
            slot.direction = direction.to_array();
            slot.flux = flux.to_array();
            slot.state = pack_slot_state(true, medium, slot_wavelength(slot.state));
        }
        return PhotonStep {
            slot,
            photon,
            emitted,
        };
    };
    let material = &scene.materials[hit.material as usize];
    if is_cut_out(scene, material, hit.uv) {
        slot.flux = flux.to_array();
        slot.pass_throughs += 1;
        slot.origin = (hit.position + params.epsilon * direction).to_array();
        slot.direction = direction.to_array();
        if slot.pass_throughs > MAX_PASS_THROUGHS {
            slot.depth = SLOT_IDLE;
        }
        return PhotonStep {
            slot,
            photon,
            emitted,
        };
    }
    // glTF's clear coat over the material meets the photon first (`render::clearcoat`): what
    // it reflects is not kept on the surface beneath and goes on as from a mirror.
    let through_coat = hit_clearcoat(scene, material, hit.uv);
    if let Some(coat) = through_coat
        && let Some(reflected) = clearcoat_bounce(&hit, direction, &coat, || rng.next_f32())
    {
        let reflected = reflected.map(|(next, weight)| {
            let shading_factors = bounded_correction(
                arrival_factor(-direction, hit.interpolated, hit.geometric)
                    * departure_factor(next, hit.interpolated, hit.geometric),
            );
            (next, weight * shading_factors)
        });
        slot.depth += 1;
        match reflected {
            Some((next, weight)) if weight > 0.0 && slot.depth < params.max_depth => {
                slot.origin = offset_origin(&hit, next, params.epsilon).to_array();
                slot.direction = next.to_array();
                slot.flux = (flux * weight).to_array();
            }
            _ => slot.depth = SLOT_IDLE,
        }
        return PhotonStep {
            slot,
            photon,
            emitted,
        };
    }
    let root = hit.material;
    // glTF's sheen beneath the coat meets it next (`render::sheen`): what it reflects is not
    // kept on the material beneath and goes on from the sheen's lobe.
    let through_sheen = hit_sheen(scene, root, &hit);
    if let Some(sheen) = through_sheen
        && let Some(reflected) = sheen_bounce(&hit, direction, &sheen, || rng.next_f32())
    {
        slot.depth += 1;
        match reflected {
            Some((next, weight)) if slot.depth < params.max_depth => {
                let shading_factors = bounded_correction(
                    arrival_factor(-direction, hit.shading, hit.geometric)
                        * departure_factor(next, hit.shading, hit.geometric),
                );
                let coat = through_coat.map_or(1.0, |c| {
                    clearcoat_transmittance(&c, next.dot(hit.interpolated))
                });
                slot.origin = offset_origin(&hit, next, params.epsilon).to_array();
                slot.direction = next.to_array();
                slot.flux = (flux * weight * (shading_factors * coat)).to_array();
            }
            _ => slot.depth = SLOT_IDLE,
        }
        return PhotonStep {
            slot,
            photon,
            emitted,
        };
    }
    // A blend keeps the photon for its Lambertian member whichever member the path takes
    // (`render::blend`); the member is drawn only at blends, so other streams stay as they were.
    let keeper = blend_photon_member(&scene.materials, hit.material);
    let hit_texel = HitTexel::new(&scene.textures, hit.uv);
    let texel = |texture| hit_texel.get(texture);
    if material.blend.is_some() {
        hit.material = blend_member(&scene.materials, hit.material, rng.next_f32(), texel);
    }
    // Where a metallic-roughness texture maps the member, its surface here (`render::blend`).
    let member = mapped_material(&scene.materials[hit.material as usize], texel);
    let material: &Material = &member;
    let tint = base_color(scene, material, hit.uv);
    let (u_roulette, u_direction) = (rng.next_f32(), [rng.next_f32(), rng.next_f32()]);
    // Rough glass chooses its way with a third number, and plastic between its coat and its
    // base; other surfaces draw none, so their streams stay as they were.
    let u_choice = if matches!(
        material.surface,
        Surface::RoughDielectric { .. } | Surface::Plastic { .. }
    ) {
        rng.next_f32()
    } else {
        0.0
    };
    // Dispersive glass keeps one wavelength of a path that carries the whole spectrum, drawn
    // with one more number (`render::dispersion`); other surfaces draw none.
    let (dispersed, wavelength, spectral_weight) =
        dispersed_surface(material, slot_wavelength(slot.state), || rng.next_f32());
    // Photons are weighted where the shading normal is not the geometric one (interpolated or
    // normal-mapped): by `arrival` where they land, and by it and the departure factor where
    // they go on (`render::normal_map`).
    let arrival = arrival_factor(-direction, hit.shading, hit.geometric);
    // A Lambertian surface, or plastic's base under the coat (which lets T(θ) through),
    // keeps the photon. Straight from the light it is direct light, which eye passes sample
    // themselves when `sample_lights` says so.
    let mut bounced = slot_bounced(slot.state) || scattered;
    let keeper_material = &scene.materials[keeper as usize];
    let base_share = match mapped_surface(keeper_material, texel) {
        Surface::Diffuse => Some(Vec3::ONE),
        surface @ Surface::Plastic { .. } => {
            let coat = scene.coats.at(keeper, surface);
            let cos = direction.dot(hit.shading);
            let layer = hit_dielectric_layer(scene, keeper_material, hit.uv);
            Some(coat.transmittance(cos) * layer.transmission_share(coat.ior, cos))
        }
        _ => None,
    };
    if let Some(share) = base_share
        && (slot.depth > 0 || scattered || params.sample_lights & SAMPLE_AT_VISIBLE_POINTS == 0)
    {
        let landed = Photon {
            position: hit.position.to_array(),
            normal: photon_normal(hit.shading, !bounced),
            flux: (flux * (bounded_correction(arrival) * share)).to_array(),
            pad: 0,
        };
        photon = one_of(photon, landed, || rng.next_f32());
    }
    // glTF's diffuse transmission sends the Lambertian lobe's light out on the far side when
    // a further number chooses it; materials without it draw none.
    let transmission = diffuse_transmission_at(scene, material, hit.uv)
        .filter(|_| material.surface.has_diffuse_lobe())
        .map(|t| (t, rng.next_f32()));
    let lambertian = |tint| match transmission {
        Some((t, u)) => lambertian_side(&hit, tint, t, u),
        None => (hit, tint),
    };
    // The side the path leaves from: the hit's, but the far one where it passed through.
    let mut out = hit;
    // The way on and its tint. After a diffuse bounce the path's later photons are indirect
    // (if it goes on; an ended slot's is not read).
    let (next, tint) = match material.surface {
        Surface::Diffuse => {
            bounced = true;
            let side_tint;
            (out, side_tint) = lambertian(tint);
            (diffuse_bounce(&out, u_direction), side_tint)
        }
        surface @ Surface::Plastic { .. } => {
            let coat = scene.coats.at(hit.material, surface);
            let layer = hit_dielectric_layer(scene, material, hit.uv);
            match plastic_bounce(&hit, direction, (&coat, layer), u_choice, u_direction) {
                PlasticBounce::Coat { next, tint } => (next, tint),
                PlasticBounce::Base(weight) => {
                    bounced = true;
                    let side_tint;
                    (out, side_tint) = lambertian(tint);
                    let next = diffuse_bounce(&out, u_direction);
                    // The base's lobe over the choice's T(θi): ρ · scale · T(θo).
                    let leaving = next.map_or(Vec3::ZERO, |(next, _)| {
                        let cos = next.dot(out.shading);
                        coat.transmittance(cos) * layer.transmission_share(coat.ior, cos)
                    });
                    let scale =
                        coat.diffuse_scale * layer.diffuse_share(coat.diffuse_scale, coat.ior);
                    (next, side_tint * leaving * weight * scale)
                }
            }
        }
        _ => {
            let [u0, u1] = u_direction;
            let layer = hit_dielectric_layer(scene, material, hit.uv);
            let next = specular_direction(dispersed, &hit, (direction, layer), [u0, u1, u_choice]);
            let tint = next.map_or(tint, |(next, _)| {
                bounce_tint(
                    dispersed,
                    (tint, material.metal_edge),
                    layer,
                    &hit,
                    (direction, next),
                )
            });
            (next, tint * spectral_weight)
        }
    };
    // Out through the sheen and the clear coat, if any (the far side's, by symmetry, where
    // the light passed through).
    let next = next.map(|(next, weight)| {
        let departure = departure_factor(next, out.shading, out.geometric);
        let coat = through_coat.map_or(1.0, |c| {
            clearcoat_transmittance(&c, next.dot(out.interpolated))
        });
        let sheen = through_sheen.map_or(1.0, |s| s.transmittance(next.dot(out.shading)));
        (
            next,
            weight * (bounded_correction(arrival * departure) * coat * sheen),
        )
    });
    let survival = tint.max_element().min(1.0);
    slot.depth += 1;
    match next {
        Some((next, weight))
            if weight > 0.0 && u_roulette < survival && slot.depth < params.max_depth =>
        {
            slot.origin = offset_origin(&hit, next, params.epsilon).to_array();
            slot.direction = next.to_array();
            slot.flux = (flux * tint * (weight / survival)).to_array();
            let medium = medium_after_bounce(scene, material, root, medium, &hit, next);
            slot.state = pack_slot_state(bounced, medium, wavelength);
        }
        _ => slot.depth = SLOT_IDLE,
    }
    PhotonStep {
        slot,
        photon,
        emitted,
    }
}

/// The photon a slot keeps where a walk in murky glass kept `walked` (a volume photon, or
/// none) and its surface keeps `landed`: a slot keeps one a pass, so where both are, one drawn
/// by `next` with even odds, its flux doubled.
fn one_of(walked: Photon, landed: Photon, next: impl FnOnce() -> f32) -> Photon {
    if !walked.is_stored() {
        return landed;
    }
    let chosen = if next() < 0.5 { walked } else { landed };
    Photon {
        flux: (vec3(chosen.flux) * 2.0).to_array(),
        ..chosen
    }
}

/// Where a photon slot's segment leads ([`photon_segment`]).
struct PhotonSegment {
    /// The surface it reaches; `None` where it is still walking inside a scattering solid
    /// after `SCATTERINGS_PER_STEP` scatterings, at `origin`.
    hit: Option<SurfaceHit>,
    origin: Vec3,
    /// The way it arrives there (turned where it scattered).
    direction: Vec3,
    /// The flux arriving.
    flux: Vec3,
    /// Whether it scattered in a medium on the way (its light is no longer direct).
    scattered: bool,
    /// In murky glass, the photon kept where it scattered (`render::scattering`).
    volume_photon: Option<Photon>,
    /// The path's walk after the segment, its weight in `flux`: `None` where it did not walk.
    walk: Option<Walk>,
}

/// The segment of `slot` (in `medium`) to its next surface: through a clear or absorbing
/// medium straight, the flux absorbed by the way (`transmittance_to`); inside a scattering
/// solid the path's walk (`render::scattering::Walk`) goes on from the slot's (its hero
/// channel drawn by one number `next` gives where the path has not walked before), each
/// flight by one, and at each scattering its Russian roulette by one and its new
/// direction by two; after `SCATTERINGS_PER_STEP` scatterings it stops where it is, to go on
/// next pass. In murky glass it keeps one volume photon a step: one of its scattering events
/// drawn uniformly (by one more number at each), of the flux scattered there times their
/// number (the roulette's end keeps it too). `None` where the path leaves the scene or ends
/// in the walk's roulette without a photon.
fn photon_segment(
    scene: &SceneData,
    slot: &PathSlot,
    medium: u32,
    mut next: impl FnMut() -> f32,
) -> Option<PhotonSegment> {
    let (mut origin, mut direction) = (vec3(slot.origin), vec3(slot.direction));
    let flux = vec3(slot.flux);
    let Some(solid) = scattering_solid(&scene.materials, medium) else {
        let hit = trace(scene, origin, direction)?;
        let flux = flux * transmittance_to(scene, medium, &hit);
        return Some(PhotonSegment {
            hit: Some(hit),
            origin,
            direction,
            flux,
            scattered: false,
            volume_photon: None,
            walk: None,
        });
    };
    let (extinction, scattering) = (solid.interior_extinction(), solid.interior_scattering());
    let murky = solid.has_murky_glass();
    let densities = vec3(slot.walk_densities);
    let mut walk = Walk::resume(slot.walk_hero, densities).unwrap_or_else(|| Walk::start(next()));
    let mut events = 0;
    // In murky glass, one of the step's scattering events, each kept with probability
    // 1/events as they come (a reservoir of one), its photon's flux × events at the end.
    let mut kept = Photon::default();
    let volume_photon = |kept: Photon, events: u32| {
        (murky && events > 0).then(|| Photon {
            flux: (vec3(kept.flux) * events as f32).to_array(),
            ..kept
        })
    };
    // The walk ended at `origin` (left the scene, or its roulette ended it): only the photon
    // kept, if any (no flux goes on).
    let ended = |kept: Photon, events: u32, origin: Vec3, direction: Vec3| {
        volume_photon(kept, events).map(|kept| PhotonSegment {
            hit: None,
            origin,
            direction,
            flux: Vec3::ZERO,
            scattered: true,
            volume_photon: Some(kept),
            walk: None,
        })
    };
    loop {
        // Out of the scene the flight runs on forever: in an atmosphere it scatters on the way,
        // or leaves (keeping its photon, if any).
        let hit = trace(scene, origin, direction);
        let distance = hit.as_ref().map_or(RAY_T_MAX, |hit| hit.distance);
        let Some(t) = walk.flight(extinction, scattering, distance, next()) else {
            let Some(hit) = hit else {
                return ended(kept, events, origin, direction);
            };
            return Some(PhotonSegment {
                hit: Some(hit),
                origin,
                direction,
                flux: flux * walk.take_weight(),
                scattered: events > 0,
                volume_photon: volume_photon(kept, events),
                walk: Some(walk),
            });
        };
        events += 1;
        origin += t * direction;
        if murky && next() * (events as f32) < 1.0 {
            kept = Photon {
                position: origin.to_array(),
                normal: volume_photon_direction(direction),
                flux: (flux * walk.weight()).to_array(),
                pad: 0,
            };
        }
        if !walk.survives(next()) {
            return ended(kept, events, origin, direction);
        }
        direction = henyey_greenstein(direction, solid.scatter_anisotropy, [next(), next()]);
        if events == SCATTERINGS_PER_STEP {
            return Some(PhotonSegment {
                hit: None,
                origin,
                direction,
                flux: flux * walk.take_weight(),
                scattered: true,
                volume_photon: volume_photon(kept, events),
                walk: Some(walk),
            });
        }
    }
}

/// The naive scheme's path for slot `index` in pass `pass`: `pass × slots + index`, wrapping,
/// so that every pass traces new paths (see `render::PhotonTracing`).
pub fn naive_path(params: &SppmParams, pass: u32, index: u32) -> u32 {
    pass.wrapping_mul(params.slot_count).wrapping_add(index)
}

/// Segments a path can take at most: every bounce counts towards `max_depth`, and the alpha
/// pass-throughs end it once there are more than [`MAX_PASS_THROUGHS`]. The naive loop stops
/// here too, though a path always ends by then.
pub fn naive_segment_limit(params: &SppmParams) -> u32 {
    params.max_depth.saturating_add(MAX_PASS_THROUGHS + 1)
}

/// What one invocation of the naive scheme leaves.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NaivePath {
    /// Segments traced, the first (from the light) included.
    pub segments: u32,
    /// The last photon the path stored (zero flux if none).
    pub photon: Photon,
}

/// The naive scheme, slot `index` in pass `pass`: a new light path traced to its end in one
/// invocation, as [`photon_pass`] steps on a slot from idle until the slot is idle again, its
/// `k`-th step drawing the numbers of pass `k` for slot [`naive_path`].
pub fn photon_trace_naive(
    scene: &SceneData,
    params: &SppmParams,
    pass: u32,
    index: u32,
) -> NaivePath {
    let path = naive_path(params, pass, index);
    let limit = naive_segment_limit(params);
    let mut slot = PathSlot::IDLE;
    let mut last = NaivePath {
        segments: 0,
        photon: Photon::default(),
    };
    loop {
        let step = photon_pass(scene, params, last.segments, path, slot);
        last.segments += 1;
        if step.photon.is_stored() {
            last.photon = step.photon;
        }
        slot = step.slot;
        if slot.depth == SLOT_IDLE || last.segments >= limit {
            return last;
        }
    }
}

/// What one eye-pass invocation leaves: the pixel's new visible point and the emission its
/// camera path saw on the way.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EyeStep {
    pub visible_point: VisiblePoint,
    pub direct: Vec3,
    /// Whether the camera ray's first surface was a mirror, glass or metal: the pixel then
    /// traces [`render::buffers::SPECULAR_EXTRA_PATHS`] more paths in later eye passes.
    pub specular_first: bool,
}

/// The eye pass on pixel `index` with its statistics: [`eye_pass`] with the extra paths its
/// flag asks for, its direct sum added and its flag updated; the new visible point.
pub fn eye_pass_pixel(
    scene: &SceneData,
    params: &SppmParams,
    pass: u32,
    index: u32,
    stats: &mut PixelStats,
) -> VisiblePoint {
    let extra = if stats.specular_seen != 0 {
        render::buffers::SPECULAR_EXTRA_PATHS
    } else {
        0
    };
    let step = eye_pass(scene, params, pass, index, extra);
    stats.direct = (vec3(stats.direct) + step.direct).to_array();
    stats.specular_seen |= step.specular_first as u32;
    step.visible_point
}

/// Eye pass, pixel `index`: a jittered camera ray through mirror and glass chains to the
/// first diffuse surface, where it leaves a visible point (and, with `sample_lights`, adds the
/// direct light of one light sample there). `extra` more jittered paths, each adding what it
/// sees but leaving no visible point, are averaged with the first: their count must not
/// depend on this pass's paths (the caller takes it from earlier passes), so that each pass's
/// average keeps the expectation.
pub fn eye_pass(
    scene: &SceneData,
    params: &SppmParams,
    pass: u32,
    index: u32,
    extra: u32,
) -> EyeStep {
    let mut rng = KernelRng::new(params.seed, EYE_STREAM, pass, index);
    let eye_pass = pass / params.eye_every.max(1);
    let jitter = pixel_jitter(params.seed, index, eye_pass);
    let lens = pixel_lens(params.seed, index, eye_pass);
    let wavelength = |path| Some(pixel_wavelength(params.seed, index, eye_pass, path));
    let side = pixel_side(params.seed, index, eye_pass);
    let first = eye_path(
        scene,
        params,
        &mut rng,
        index,
        [jitter, lens],
        (wavelength(0), Some(side)),
    );
    let mut direct = first.direct;
    for path in 1..=extra {
        let jitter = [rng.next_f32(), rng.next_f32()];
        // A pinhole draws no lens point, so its images keep their numbers.
        let lens = if params.lens_radius > 0.0 {
            [rng.next_f32(), rng.next_f32()]
        } else {
            lens
        };
        let start = [jitter, lens];
        let numbers = (wavelength(path), None);
        direct += eye_path(scene, params, &mut rng, index, start, numbers).direct;
    }
    EyeStep {
        visible_point: first.visible_point,
        direct: direct / (1 + extra) as f32,
        specular_first: first.specular_first,
    }
}

/// One camera path of an eye pass.
struct EyePath {
    visible_point: VisiblePoint,
    /// The emission met on the way (and the sky), then the light sample at the visible point.
    direct: Vec3,
    /// Whether its first surface was specular.
    specular_first: bool,
}

/// A camera path through pixel `index` at sub-pixel `jitter`, leaving the lens at `lens`
/// (`render::lens::camera_ray`); at the first dispersive glass
/// it draws its wavelength with `wavelength_number` (`render::rng::pixel_wavelength`); it
/// keeps that wavelength at later ones (`render::dispersion`). At a translucent surface it
/// chooses the Lambertian lobe's side with `side_number` (`render::rng::pixel_side`), or
/// draws one where that is `None`.
fn eye_path(
    scene: &SceneData,
    params: &SppmParams,
    rng: &mut KernelRng,
    index: u32,
    [[jx, jy], lens]: [[f32; 2]; 2],
    (mut wavelength_number, side_number): (Option<f32>, Option<f32>),
) -> EyePath {
    let (x, y) = (index % params.width, index / params.width);
    let sx = (x as f32 + jx) / params.width as f32 * 2.0 - 1.0;
    let sy = 1.0 - (y as f32 + jy) / params.height as f32 * 2.0;
    let (mut origin, mut direction) = camera_ray(params, sx, sy, lens);
    let mut throughput = Vec3::ONE;
    let mut direct = Vec3::ZERO;
    let mut specular_first = false;
    let mut visible_point = VisiblePoint::default();
    let (mut depth, mut pass_throughs) = (0, 0);
    // The share of the next surface's emission (or the sky's) still to count: less than 1
    // after a glass surface whose other branch was counted already (below).
    let mut emission_share = 1.0;
    let mut met_glass = false;
    // Where the path last left a glossy lobe, and the lobe's density for the way it took:
    // emission met next is weighed against the light sample taken there (0: not glossy).
    let mut glossy = GlossyVertex::default();
    // The solid the path is inside (`render::medium`): where the camera is, to begin with.
    let mut medium = params.camera_medium;
    // The wavelength the path keeps since its first dispersive glass.
    let mut wavelength = WHOLE_SPECTRUM;
    // The path's walk through murky glass, one over all its flights there (its hero drawn at
    // the first: `render::scattering`).
    let mut walk: Option<Walk> = None;
    // The plane of the surface the ray last left (normal, offset), where a volume visible
    // point measures its depth from (`render::volume_boundary`): none from the camera.
    let mut behind = (Vec3::ZERO, volume_boundary::NO_SURFACE);
    while depth < params.max_depth {
        let traced = trace(scene, origin, direction);
        // In murky glass the path's flight may end where it scatters, with a volume visible
        // point (`render::scattering`); else it passes, weighed by what is not scattered. A
        // ray out of the scene runs on forever: in an atmosphere it scatters on the way.
        let murky = murky_glass(&scene.materials, medium);
        if let Some(murky) = murky {
            let scattering = murky.interior_scattering();
            let walk = walk.get_or_insert_with(|| Walk::start(rng.next_f32()));
            let extinction = murky.interior_extinction();
            let distance = traced.as_ref().map_or(RAY_T_MAX, |hit| hit.distance);
            let flight = walk.flight(extinction, scattering, distance, rng.next_f32());
            if let Some(t) = flight {
                let weight = throughput * walk.weight_over_scattering(scattering);
                if weight.max_element() > 0.0 {
                    let position = origin + t * direction;
                    let depth_behind = (behind.0.dot(position) + behind.1).abs();
                    let depth_ahead = traced.as_ref().map_or(volume_boundary::NO_SURFACE, |hit| {
                        (hit.distance - t) * direction.dot(hit.geometric).abs()
                    });
                    visible_point = VisiblePoint {
                        position: position.to_array(),
                        normal: volume_point_direction(direction, murky.scatter_anisotropy),
                        weight: weight.to_array(),
                        pad: volume_boundary::depths_word(depth_behind, depth_ahead),
                    };
                }
                break;
            }
            throughput *= walk.take_weight();
        }
        let Some(mut hit) = traced else {
            // Out of the scene: the sky (zero without one), unless water around the path
            // absorbs it on the way (a walk's weight holds that already).
            let kept = match murky {
                Some(_) => Vec3::ONE,
                None => medium_transmittance(scene, medium, RAY_T_MAX),
            };
            let sky = sky_seen(scene, params, direction) * kept;
            direct += throughput * emission_share * sky * glossy.sky_weight(scene, direction);
            break;
        };
        if murky.is_none() {
            throughput *= transmittance_to(scene, medium, &hit);
        }
        let material = &scene.materials[hit.material as usize];
        if is_cut_out(scene, material, hit.uv) {
            pass_throughs += 1;
            if pass_throughs > MAX_PASS_THROUGHS {
                break;
            }
            origin = hit.position + params.epsilon * direction;
            continue;
        }
        behind = (hit.geometric, -hit.geometric.dot(hit.position));
        let emission = emitted(scene, material, &hit);
        if emission.max_element() > 0.0 {
            let weight = glossy.emitter_weight(scene, &hit, direction);
            direct += throughput * emission_share * emission * weight;
        }
        emission_share = 1.0;
        // glTF's clear coat over the material meets the path first (`render::clearcoat`): its
        // reflection goes on as a mirror's (no light sample: emission met next counts whole).
        let through_coat = hit_clearcoat(scene, material, hit.uv);
        if let Some(coat) = through_coat
            && let Some(reflected) = clearcoat_bounce(&hit, direction, &coat, || rng.next_f32())
        {
            let Some((next, weight)) = reflected else {
                break;
            };
            throughput *= weight;
            glossy = GlossyVertex::default();
            depth += 1;
            origin = offset_origin(&hit, next, params.epsilon);
            direction = next;
            continue;
        }
        let root = hit.material;
        // glTF's sheen beneath the coat meets it next (`render::sheen`): its reflection takes
        // a light sample for the sheen's lobe and goes on from it, weighed against that sample.
        let through_sheen = hit_sheen(scene, root, &hit);
        if let Some(sheen) = through_sheen
            && let Some(reflected) = sheen_bounce(&hit, direction, &sheen, || rng.next_f32())
        {
            let Some((next, weight)) = reflected else {
                break;
            };
            let mut lit = LitLobes {
                glossy: throughput * sheen.lobe_scale(direction.dot(hit.shading)),
                lobe: GlossyLobe::sheen(sheen.table.alpha),
                clearcoat: through_coat,
                ..LitLobes::default()
            };
            if params.sample_lights & SAMPLE_AT_GLOSSY == 0 {
                lit.lobe = GlossyLobe::default();
            }
            if lit.is_lit() && !scene.lights.is_empty() {
                let next = || rng.next_f32();
                direct += direct_light(scene, params, &hit, -direction, &lit, medium, next);
            }
            glossy = GlossyVertex::after(&hit, &lit, -direction, next);
            let coat = through_coat.map_or(1.0, |c| {
                clearcoat_transmittance(&c, next.dot(hit.interpolated))
            });
            throughput *= weight * coat;
            depth += 1;
            origin = offset_origin(&hit, next, params.epsilon);
            direction = next;
            continue;
        }
        // A blend's member for this path (`render::blend`), drawn only at blends.
        let hit_texel = HitTexel::new(&scene.textures, hit.uv);
        let texel = |texture| hit_texel.get(texture);
        if material.blend.is_some() {
            hit.material = blend_member(&scene.materials, hit.material, rng.next_f32(), texel);
        }
        // Where a metallic-roughness texture maps the member, its surface here.
        let member = mapped_material(&scene.materials[hit.material as usize], texel);
        let material: &Material = &member;
        let tint = base_color(scene, material, hit.uv).max(Vec3::ZERO);
        let u = rng.next_f32();
        let mut base_weight = Vec3::ONE;
        // The lobes a light sample here serves: a glossy one (rough metal, a rough coat,
        // frosted glass's reflection)
        // always, the Lambertian one where the path ends on it (below).
        let mut lit = LitLobes {
            clearcoat: through_coat,
            sheen: through_sheen,
            ..LitLobes::default()
        };
        // The surface the path meets: dispersive glass's, for the path's wavelength.
        let mut surface = material.surface;
        let bounce = match material.surface {
            Surface::Diffuse => None,
            Surface::Plastic { ior, alpha } => {
                let coat = scene.coats.at(hit.material, material.surface);
                let layer = hit_dielectric_layer(scene, material, hit.uv);
                lit.coat = Some((coat, layer));
                // A rough coat draws its micro-normal with two more numbers.
                let u_micro = if alpha > 0.0 {
                    lit.glossy = throughput;
                    lit.lobe = GlossyLobe::reflection(alpha, ior);
                    [rng.next_f32(), rng.next_f32()]
                } else {
                    [0.0; 2]
                };
                match plastic_bounce(&hit, direction, (&coat, layer), u, u_micro) {
                    PlasticBounce::Base(weight) => {
                        base_weight = weight;
                        None
                    }
                    PlasticBounce::Coat { next, tint } => Some((next, tint)),
                }
            }
            _ => {
                // Rough metal and glass draw their micro-normal with a second number, and
                // rough glass chooses its way with a third.
                let rough = matches!(
                    material.surface,
                    Surface::RoughConductor { .. } | Surface::RoughDielectric { .. }
                );
                let u_second = if rough { rng.next_f32() } else { 0.0 };
                let u_third = if matches!(material.surface, Surface::RoughDielectric { .. }) {
                    rng.next_f32()
                } else {
                    0.0
                };
                // Dispersive glass keeps one wavelength (`render::dispersion`), drawn where
                // the path carries the whole spectrum with the pixel's own number for this
                // eye pass; the lobes below, light samples' among them, are that
                // wavelength's.
                let weight;
                (surface, wavelength, weight) = dispersed_surface(material, wavelength, || {
                    wavelength_number.take().unwrap_or_else(|| rng.next_f32())
                });
                throughput *= weight;
                // A thin film colours the metal by the angle to each micro-normal: the light
                // sample's tint is the film's at the light's direction. Glass wears the film
                // and the specular layer.
                let layer = hit_dielectric_layer(scene, material, hit.uv);
                if let Surface::RoughConductor { alpha } = surface {
                    lit.glossy = throughput;
                    lit.lobe = GlossyLobe::metal(alpha, hit.brush);
                    lit.metal = Some(Metal {
                        f0: tint,
                        edge: material.metal_edge,
                        film: layer.film,
                    });
                }
                // Solid frosted glass met from outside reflects as a plastic coat does: a
                // visible micro-normal, reflection about it with its Fresnel probability,
                // weight G1 (`render::microfacet::rough_dielectric`); met from inside, its
                // refraction out is the lobe a light sample serves. Light refracted into the
                // glass (blocked by it) gets no light sample.
                if let Surface::RoughDielectric {
                    ior,
                    thin_walled: false,
                    alpha,
                } = surface
                {
                    lit.glossy = throughput * tint;
                    lit.dielectric_layer = layer;
                    lit.lobe = if hit.front {
                        GlossyLobe::reflection(alpha, ior)
                    } else {
                        // From inside: its refraction out (the light seen through it).
                        GlossyLobe::refraction(alpha, ior)
                    };
                }
                // A thin frosted sheet: its reflection, and its transmission of the light
                // beyond it (a lamp shade, a frosted window in the sun).
                if let Surface::RoughDielectric {
                    ior,
                    thin_walled: true,
                    alpha,
                } = surface
                {
                    lit.glossy = throughput * tint;
                    lit.dielectric_layer = layer;
                    lit.lobe = GlossyLobe::sheet(alpha, relative_eta(ior, hit.front, true));
                }
                let next =
                    specular_direction(surface, &hit, (direction, layer), [u, u_second, u_third]);
                // Only these send pixels more eye paths: a plastic coat's reflection mostly
                // shows gathered light, which extra paths would not sample.
                specular_first |= depth == 0;
                // Smooth glass's layer takes its share below, after the way not taken is
                // counted.
                let tint = match (surface, next) {
                    (Surface::Dielectric { .. }, _) | (_, None) => tint,
                    (_, Some((next, _))) => {
                        let metal = (tint, material.metal_edge);
                        bounce_tint(surface, metal, layer, &hit, (direction, next))
                    }
                };
                Some((next, tint))
            }
        };
        // Where glTF's diffuse transmission took the light through, the Lambertian lobe's
        // side: the visible point gathers the photons landing there, and its light sample
        // is taken there (a second one; the glossy lobes keep the hit's).
        let mut far_side = None;
        if bounce.is_none() {
            // A Lambertian surface, or plastic's base (the coat's T(θo) in the choice's
            // weight, its T(θi) left to the light sample and the photons).
            let transmission = diffuse_transmission_at(scene, material, hit.uv);
            let (side, tint) = match transmission {
                Some(t) => {
                    let u = side_number.unwrap_or_else(|| rng.next_f32());
                    lambertian_side(&hit, tint, t, u)
                }
                None => (hit, tint),
            };
            let scale = lit.coat.map_or(Vec3::ONE, |(coat, layer)| {
                coat.diffuse_scale * layer.diffuse_share(coat.diffuse_scale, coat.ior)
            });
            let weight = throughput * tint * base_weight * (scale * FRAC_1_PI);
            if weight.max_element() > 0.0 {
                visible_point = VisiblePoint {
                    position: hit.position.to_array(),
                    normal: surface_normal(side.shading),
                    weight: weight.to_array(),
                    pad: 0,
                };
                if params.sample_lights & SAMPLE_AT_VISIBLE_POINTS != 0 {
                    lit.diffuse = weight;
                }
            }
            far_side = (side.front != hit.front).then_some(side);
        }
        if params.sample_lights & SAMPLE_AT_GLOSSY == 0 {
            lit.lobe = GlossyLobe::default();
        }
        if !scene.lights.is_empty() {
            let mut light_sample = |at: &SurfaceHit, lit: &LitLobes, medium: u32| {
                if lit.is_lit() {
                    let next = || rng.next_f32();
                    direct += direct_light(scene, params, at, -direction, lit, medium, next);
                }
            };
            match far_side {
                None => light_sample(&hit, &lit, medium),
                Some(far) => {
                    // Inside a translucent solid where the surface bounds one.
                    let far_medium =
                        medium_after_bounce(scene, material, root, medium, &hit, -hit.geometric);
                    let far_lit = LitLobes {
                        diffuse: lit.diffuse,
                        coat: lit.coat,
                        clearcoat: lit.clearcoat,
                        sheen: lit.sheen,
                        ..LitLobes::default()
                    };
                    lit.diffuse = Vec3::ZERO;
                    light_sample(&hit, &lit, medium);
                    light_sample(&far, &far_lit, far_medium);
                }
            }
        }
        let Some((next, tint)) = bounce else {
            break;
        };
        let Some((next, weight)) = next else {
            break;
        };
        glossy = GlossyVertex::after(&hit, &lit, -direction, next);
        // Out through the sheen and the clear coat, if any.
        let coat = through_coat.map_or(1.0, |c| {
            clearcoat_transmittance(&c, next.dot(hit.interpolated))
        });
        let sheen = through_sheen.map_or(1.0, |s| s.transmittance(next.dot(hit.shading)));
        throughput *= tint * (weight * coat * sheen);
        if throughput.max_element() <= 0.0 {
            break;
        }
        depth += 1;
        // At glass the path goes on one way, chosen by Fresnel; what the other way sees at
        // once (a light reflected in the glass, say) is counted now, weighted by its
        // probability, and the next surface's emission by the chosen way's. The expectation
        // is the same, without the variance of the choice: a highlight reflected in glass is
        // otherwise seen by a few eye paths in twenty. Only at the first glass surface of the
        // path: deeper ones (inside a glass sphere) add little and cost most (lavapipe's eye
        // pass on cornell-caustics: +7 % probing at the first, +23 % at every one).
        // Under a layer (glTF's thin film and specular layer) each channel of either way takes
        // the layer's share of it (the way not taken counted with it, the way taken weighed by
        // it over its probability).
        let probe = !met_glass && depth < params.max_depth;
        let layer = match surface {
            Surface::Dielectric { .. } => hit_dielectric_layer(scene, material, hit.uv),
            _ => DielectricLayer::default(),
        };
        if let Surface::Dielectric { ior, thin_walled } = surface
            && (probe || !layer.is_bare())
        {
            let branches = dielectric_branches(&hit, direction, ior, thin_walled, layer);
            let (other, other_share, other_weight) = if u < branches.reflectance {
                let share = 1.0 - branches.reflectance;
                (
                    branches.transmitted,
                    share,
                    Vec3::ONE - branches.layered_reflectance,
                )
            } else {
                let share = branches.reflectance;
                (branches.reflected, share, branches.layered_reflectance)
            };
            if probe {
                met_glass = true;
                if other != next && other_share > 0.0 {
                    let seen = emission_seen(
                        scene,
                        params,
                        offset_origin(&hit, other, params.epsilon),
                        other,
                        medium_after_bounce(scene, material, root, medium, &hit, other),
                    );
                    let crossing = eye_crossing_scale(surface, &hit, other);
                    direct += throughput * (other_weight * crossing) * seen;
                    emission_share = 1.0 - other_share;
                }
            }
            if !layer.is_bare() {
                throughput *= branches.weight(next == branches.reflected);
            }
        }
        throughput *= eye_crossing_scale(surface, &hit, next);
        medium = medium_after_bounce(scene, material, root, medium, &hit, next);
        origin = offset_origin(&hit, next, params.epsilon);
        direction = next;
    }
    EyePath {
        visible_point,
        direct,
        specular_first,
    }
}

/// The lobes at an eye path's hit that one light sample there lights, each with its weight
/// (the path's throughput and the surface's tint; zero for a lobe that is not there).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LitLobes {
    /// A Lambertian lobe: the visible point's weight (ρ/π and plastic's scale included).
    pub diffuse: Vec3,
    /// The plastic coat over the Lambertian lobe, which gets what it lets through (the hit's:
    /// `render::coats::Coats::at`), and the layer on it there (`render::dielectric_layer::DielectricLayer`),
    /// whose share of the coat's reflection and transmission depends on the light's direction.
    pub coat: Option<(
        render::plastic::Coat,
        render::dielectric_layer::DielectricLayer,
    )>,
    /// The glossy lobe's weight.
    pub glossy: Vec3,
    pub lobe: GlossyLobe,
    /// glTF's clear coat over both lobes, which the light passes on its way in.
    pub clearcoat: Option<scene::Clearcoat>,
    /// glTF's sheen over both lobes (beneath the clear coat), which the light passes too.
    pub sheen: Option<render::sheen::SheenAt>,
    /// The metal of a rough-metal lobe (`glossy` then leaves its colour out: its Fresnel
    /// reflectance depends on the light's direction).
    pub metal: Option<Metal>,
    /// The layer on frosted glass (glTF's thin film and specular layer), whose share of the
    /// lobe's way depends on the light's direction
    /// (`render::dielectric_layer::lobe_layer_weight`; bare: none).
    pub dielectric_layer: DielectricLayer,
}

impl LitLobes {
    fn is_lit(&self) -> bool {
        self.diffuse.max_element() > 0.0 || (self.lobe.is_some() && self.glossy.max_element() > 0.0)
    }

    /// What light arriving along `incident` with solid-angle density `light_pdf` sends
    /// towards `outgoing`, per unit of its radiance divided by that density.
    fn response(&self, hit: &SurfaceHit, outgoing: Vec3, incident: Vec3, light_pdf: f32) -> Vec3 {
        let cosine = incident.dot(hit.shading);
        let mut response = Vec3::ZERO;
        if self.diffuse.max_element() > 0.0 {
            let coat = self.coat.map_or(Vec3::ONE, |(coat, layer)| {
                coat.transmittance(cosine) * layer.transmission_share(coat.ior, cosine)
            });
            response += self.diffuse * coat * cosine;
        }
        if self.lobe.is_some() {
            let lobe = self.lobe.response(hit.shading, outgoing, incident);
            if lobe.value > 0.0 {
                let mut tint = self
                    .metal
                    .map_or(Vec3::ONE, |metal| metal.tint(outgoing, incident));
                if !self.dielectric_layer.is_bare() {
                    let ways = (outgoing, incident);
                    let layer = self.dielectric_layer;
                    tint *= lobe_layer_weight(&self.lobe, layer, hit.shading, ways);
                }
                // A rough coat's reflection under its layer.
                if let Some((coat, layer)) = self.coat {
                    tint *= layer.reflection_share(coat.ior, (outgoing, incident));
                }
                response +=
                    self.glossy * tint * (lobe.value * power_heuristic(light_pdf, lobe.pdf));
            }
        }
        // In through the clear coat, if any (about the normal before the map).
        let through =
            |c: scene::Clearcoat| clearcoat_transmittance(&c, incident.dot(hit.interpolated));
        let sheen = self.sheen.map_or(1.0, |s| s.transmittance(cosine));
        response * (self.clearcoat.map_or(1.0, through) * sheen)
    }
}

/// Where an eye path last left a glossy lobe: the point, its shading normal, and the lobe's
/// density for the direction taken (0 where the last bounce was not glossy, and emission met
/// next counts in full).
#[derive(Clone, Copy, Debug, Default)]
struct GlossyVertex {
    position: Vec3,
    normal: Vec3,
    pdf: f32,
}

impl GlossyVertex {
    /// The vertex a bounce from `hit` along `next` leaves, its lobes as `lit` has them.
    fn after(hit: &SurfaceHit, lit: &LitLobes, outgoing: Vec3, next: Vec3) -> GlossyVertex {
        if !lit.lobe.is_some() {
            return GlossyVertex::default();
        }
        GlossyVertex {
            position: hit.position,
            normal: lit.lobe.facing(hit.shading),
            pdf: lit.lobe.response(hit.shading, outgoing, next).pdf,
        }
    }

    /// The share of an emitter's radiance met at `hit` (along `direction`) that this path
    /// counts: the rest came through the light sample at the glossy vertex.
    fn emitter_weight(&self, scene: &SceneData, hit: &SurfaceHit, direction: Vec3) -> f32 {
        if self.pdf <= 0.0 {
            return 1.0;
        }
        let area_density = scene.light_area_density[hit.material as usize];
        let distance = (hit.position - self.position).length();
        let light_pdf = triangle_pdf(area_density, distance, direction.dot(hit.geometric));
        power_heuristic(self.pdf, light_pdf)
    }

    /// The same for the sky, met along `direction`.
    fn sky_weight(&self, scene: &SceneData, direction: Vec3) -> f32 {
        if self.pdf <= 0.0 {
            return 1.0;
        }
        power_heuristic(
            self.pdf,
            sky_pdf(&scene.lights, &scene.sky_map, direction, self.normal),
        )
    }
}

/// The sky's radiance along `direction` (its map's, else the uniform sky's; zero without one).
fn sky_seen(scene: &SceneData, params: &SppmParams, direction: Vec3) -> Vec3 {
    render::sky_map::sky_radiance(&scene.lights, &scene.sky_map, vec3(params.sky), direction)
}

/// What a ray in `medium` sees at once: the emission of the first surface it meets (through
/// alpha cut-outs' holes, as eye paths pass them), or the sky where it leaves the scene, with
/// what the medium lets through on the way.
pub fn emission_seen(
    scene: &SceneData,
    params: &SppmParams,
    mut origin: Vec3,
    direction: Vec3,
    medium: u32,
) -> Vec3 {
    let mut kept = Vec3::ONE;
    for _ in 0..=MAX_PASS_THROUGHS {
        let Some(hit) = trace(scene, origin, direction) else {
            return kept
                * sky_seen(scene, params, direction)
                * medium_transmittance(scene, medium, RAY_T_MAX);
        };
        kept *= transmittance_to(scene, medium, &hit);
        let material = &scene.materials[hit.material as usize];
        if !is_cut_out(scene, material, hit.uv) {
            return kept * emitted(scene, material, &hit);
        }
        origin = hit.position + params.epsilon * direction;
    }
    Vec3::ZERO
}

/// One sample of the light table at an eye path's hit, seen along `outgoing` by a path in
/// `medium`: what reaches it unoccluded, through the lobes `lit` names, divided by the
/// sample's density; a glossy lobe's share weighed against its own sampling (the power
/// heuristic). Zero where the light lies behind the surface or is blocked. Without a glossy
/// lobe the sample is kept among [`SppmParams::light_candidates`] (`render::resampling`).
/// `next` gives its uniform numbers.
pub fn direct_light(
    scene: &SceneData,
    params: &SppmParams,
    hit: &SurfaceHit,
    outgoing: Vec3,
    lit: &LitLobes,
    medium: u32,
    next: impl FnMut() -> f32,
) -> Vec3 {
    let facing = lit.lobe.facing(hit.shading);
    // MIS needs the sample's density, which resampling does not keep.
    let candidates = if lit.lobe.is_some() {
        1
    } else {
        params.light_candidates
    };
    let sample = resample_light(
        &scene.lights,
        &scene.sky_map,
        candidates,
        hit.position,
        facing,
        next,
    );
    let Some(light) = sample else {
        return Vec3::ZERO;
    };
    if light.direction.dot(facing) <= 0.0 && !lit.lobe.is_two_sided() {
        return Vec3::ZERO;
    }
    let response = lit.response(hit, outgoing, light.direction, light.pdf);
    if response.max_element() <= 0.0 {
        return Vec3::ZERO;
    }
    // The medium the shadow ray runs through: a refraction out of a solid leaves it.
    let mut shadow_medium = medium;
    let origin = if light.direction.dot(hit.shading) < 0.0 {
        // Through the glass (a refraction out, a sheet's transmission): beyond the geometric
        // surface too, from just beyond it.
        if light.direction.dot(hit.geometric) >= 0.0 {
            return Vec3::ZERO;
        }
        if lit.lobe.refraction_eta > 0.0 {
            shadow_medium = scene.exterior[hit.material as usize];
        }
        hit.position - params.epsilon * hit.geometric
    } else {
        // A facet turned from the light whose smooth surface faces it (a coarse mesh's
        // terminator): the shadow ray from the smooth surface decides.
        let lifted = is_lifted(
            hit.position,
            hit.shadow_origin,
            hit.geometric,
            params.epsilon,
        );
        if light.direction.dot(hit.geometric) <= 0.0 && !lifted {
            return Vec3::ZERO;
        }
        shadow_ray_origin(hit, params.epsilon)
    };
    let (direction, distance) = shadow_ray(&light, origin);
    if !unoccluded(scene, params, origin, direction, distance) {
        return Vec3::ZERO;
    }
    light.incident * response * medium_transmittance(scene, shadow_medium, distance)
}

/// Hash build, first half, photon `index`: raises its entry's priority to the photon's and
/// counts it.
pub fn hash_count(
    params: &SppmParams,
    counters: &[AtomicU32],
    hash: &[AtomicU32],
    index: u32,
    photon: &Photon,
) {
    if let Some(key) = photon_key(params, counters, index, photon) {
        hash[key.word + hash_word::PRIORITY].fetch_max(key.priority, Relaxed);
        hash[key.word + hash_word::COUNT].fetch_add(1, Relaxed);
        if key.class > 0 {
            hash[key.class_zero_word + hash_word::COUNT].fetch_or(class_mark(key.class), Relaxed);
        }
    }
}

/// Hash build, second half, photon `index`: the photon whose priority won writes its index
/// (the largest index among equal priorities, so the result never depends on timing).
pub fn hash_select(
    params: &SppmParams,
    counters: &[AtomicU32],
    hash: &[AtomicU32],
    index: u32,
    photon: &Photon,
) {
    if let Some(key) = photon_key(params, counters, index, photon)
        && hash[key.word + hash_word::PRIORITY].load(Relaxed) == key.priority
    {
        hash[key.word + hash_word::WINNER].fetch_max(index, Relaxed);
    }
}

/// Where a stored photon goes in the hash this pass.
struct PhotonKey {
    /// Its entry's first word, in its class's table.
    word: usize,
    /// The first word of the class-0 entry of the same index (which marks the class).
    class_zero_word: usize,
    class: u32,
    priority: u32,
}

/// A stored photon's [`PhotonKey`]; `None` if the slot stored no photon.
fn photon_key(
    params: &SppmParams,
    counters: &[AtomicU32],
    index: u32,
    photon: &Photon,
) -> Option<PhotonKey> {
    if !photon.is_stored() {
        return None;
    }
    // A volume photon's word has no caustic class (`render::packing::volume_photon_direction`).
    let class = photon_class(
        photon.flux,
        is_caustic(photon.normal),
        params.hash_classes(),
    );
    let entry = photon_entry(params, counters, photon);
    let pass = counters[counter::PASS].load(Relaxed);
    Some(PhotonKey {
        word: class_entry(entry, class, params.hash_size) as usize * HASH_ENTRY_WORDS,
        class_zero_word: entry as usize * HASH_ENTRY_WORDS,
        class,
        priority: priority(params.seed, pass, index),
    })
}

/// The class-0 table entry of a stored photon's cell this pass: in the volume photons' grid for
/// a volume photon (`render::hash`), in the caustic photons' for a caustic one where they are
/// kept apart (`render::hash::caustic_apart`), else in the surfaces'.
pub fn photon_entry(params: &SppmParams, counters: &[AtomicU32], photon: &Photon) -> u32 {
    let volume = is_volume(photon.normal);
    let cell_size = if caustic_apart(params.hash_classes()) && is_caustic(photon.normal) {
        caustic_cell_size_of(counters)
    } else {
        cell_size_of(counters, volume)
    };
    let cell = cell_of(vec3(photon.position), cell_size);
    entry_of(cell, grid_salt(volume), params.hash_size)
}

/// This pass's cell size of the caustic photons' own grid.
fn caustic_cell_size_of(counters: &[AtomicU32]) -> f32 {
    f32::from_bits(counters[counter::CAUSTIC_CELL_SIZE].load(Relaxed))
}

/// This pass's cell size of the volume photons' grid (`volume`) or the surfaces'.
fn cell_size_of(counters: &[AtomicU32], volume: bool) -> f32 {
    let index = if volume {
        counter::VOLUME_CELL_SIZE
    } else {
        counter::CELL_SIZE
    };
    f32::from_bits(counters[index].load(Relaxed))
}

/// Gather and update, one pixel: the visible point reads the hash entries its radius
/// overlaps, weights each kept photon by its entry's count, and updates N, R and τ
/// (DESIGN.md, "SPPM update"). Lit pixels then offer their radii to the pass's maxima and
/// histograms.
pub fn gather(
    params: &SppmParams,
    counters: &[AtomicU32],
    hash: &[AtomicU32],
    photons: &[Photon],
    visible_point: &VisiblePoint,
    stats: PixelStats,
) -> PixelStats {
    gather_with(counters, params, visible_point, stats, |query| {
        stochastic_query(params, hash, photons, query)
    })
}

/// Where and how far a visible point gathers, and the hash cells serving it.
#[derive(Clone, Copy, Debug)]
pub struct GatherQuery {
    pub position: Vec3,
    pub normal: Vec3,
    /// Gather radius of the indirect photons.
    pub radius: f32,
    /// Gather radius of the caustic photons.
    pub caustic_radius: f32,
    /// The size of the cells it reads: the volume photons' grid's for a volume visible point.
    pub cell_size: f32,
    /// The size of the caustic photons' own cells, where they have them
    /// (`render::hash::caustic_apart`).
    pub caustic_cell_size: f32,
    /// For a visible point inside murky glass, what it gathers instead: the volume photons.
    pub volume: Option<VolumeQuery>,
}

/// A volume visible point's gather (`render::scattering`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VolumeQuery {
    /// The way its eye path travelled.
    pub direction: Vec3,
    /// Its medium's Henyey–Greenstein asymmetry.
    pub anisotropy: f32,
    /// Gather radius of the volume photons.
    pub radius: f32,
}

impl GatherQuery {
    /// How far any photon may count: the larger radius (the volume photons' for a volume
    /// visible point), which the density methods search.
    pub fn reach(&self) -> f32 {
        match self.volume {
            Some(volume) => volume.radius,
            None => self.radius.max(self.caustic_radius),
        }
    }

    /// The grid it reads, as [`query_entries`] takes it: the volume photons' for a volume
    /// visible point, the surfaces' otherwise (`render::hash`).
    pub fn grid(&self) -> (f32, u32) {
        (self.cell_size, grid_salt(self.volume.is_some()))
    }
}

/// What a gather found: the indirect photons it counts (M) and their flux, the caustic ones,
/// and the volume ones (their flux times the phase function towards the eye).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct GatherSum {
    pub found: u32,
    pub flux: Vec3,
    pub caustic_found: u32,
    pub caustic_flux: Vec3,
    pub volume_found: u32,
    pub volume_flux: Vec3,
}

impl GatherSum {
    /// Adds `count` photons of `flux` each to the photon's class when it lies inside that
    /// class's sphere and on the query's side of the surface; a volume visible point counts
    /// only volume photons, each times the phase function between its way and the way back to
    /// the eye, and a surface one none of them.
    pub fn add_if_near(&mut self, query: &GatherQuery, photon: &Photon, count: u32) {
        let offset = vec3(photon.position) - query.position;
        if let Some(volume) = query.volume {
            if is_volume(photon.normal) && offset.length_squared() < volume.radius * volume.radius {
                let cos = -unpack_normal(photon.normal).dot(volume.direction);
                let phase = henyey_greenstein_phase(volume.anisotropy, cos);
                self.volume_found += count;
                self.volume_flux += (count as f32 * phase) * vec3(photon.flux);
            }
            return;
        }
        if is_volume(photon.normal) {
            return;
        }
        let caustic = is_caustic(photon.normal);
        let radius = if caustic {
            query.caustic_radius
        } else {
            query.radius
        };
        if offset.length_squared() < radius * radius
            && unpack_normal(photon.normal).dot(query.normal) > 0.0
        {
            let flux = count as f32 * vec3(photon.flux);
            if caustic {
                self.caustic_found += count;
                self.caustic_flux += flux;
            } else {
                self.found += count;
                self.flux += flux;
            }
        }
    }
}

/// The stochastic hash's query: each distinct entry the sphere overlaps gives its kept photon,
/// weighted by the entry's count, in class 0's table and each other photon class's table its
/// count word marks (`render::hash::photon_class`, `class_mark`). A volume visible point reads
/// the volume photons' finer grid cell by cell ([`volume_query_cells`]), each cell's kept
/// photon counting only where it lies in that cell.
pub fn stochastic_query(
    params: &SppmParams,
    hash: &[AtomicU32],
    photons: &[Photon],
    query: &GatherQuery,
) -> GatherSum {
    let mut sum = GatherSum::default();
    if query.volume.is_some() {
        let (position, radius, cell_size) = (query.position, query.reach(), query.cell_size);
        for (cell, entry) in volume_query_entries(position, radius, cell_size, params.hash_size) {
            let in_cell = |photon: &Photon| lies_in(vec3(photon.position), cell, cell_size);
            add_kept_photons(
                &mut sum,
                (params, hash, photons),
                query,
                entry,
                (Kinds::All, in_cell),
            );
        }
        return sum;
    }
    // Every class in the surfaces' grid; or, where caustic photons have their own, the other
    // classes there and the caustic ones in theirs.
    let together = [(query.reach(), query.cell_size, Kinds::All)];
    let apart = [
        (query.radius, query.cell_size, Kinds::NotCaustic),
        (
            query.caustic_radius,
            query.caustic_cell_size,
            Kinds::Caustic,
        ),
    ];
    let blocks: &[_] = if caustic_apart(params.hash_classes()) {
        &apart
    } else {
        &together
    };
    for &(radius, cell_size, kinds) in blocks {
        let grid = (cell_size, grid_salt(false));
        let (entries, count) = query_entries(query.position, radius, grid, params.hash_size);
        for &entry in &entries[..count] {
            add_kept_photons(
                &mut sum,
                (params, hash, photons),
                query,
                entry,
                (kinds, |_| true),
            );
        }
    }
    sum
}

/// Which photon classes a read of a table entry takes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kinds {
    All,
    /// Those of the surfaces' grid where caustic photons have their own.
    NotCaustic,
    Caustic,
}

impl Kinds {
    fn take(self, class: u32, classes: u32) -> bool {
        match self {
            Kinds::All => true,
            Kinds::NotCaustic => !class_is_caustic(class, classes),
            Kinds::Caustic => class_is_caustic(class, classes),
        }
    }
}

/// Adds the photons table entry `entry` keeps, in class 0's table and in each other class's its
/// count word marks, each weighted by its class's count there, of the classes `kinds` takes
/// and where `counts` accepts the photon.
fn add_kept_photons(
    sum: &mut GatherSum,
    (params, hash, photons): (&SppmParams, &[AtomicU32], &[Photon]),
    query: &GatherQuery,
    entry: u32,
    (kinds, counts): (Kinds, impl Fn(&Photon) -> bool),
) {
    let classes = params.hash_classes();
    // Class 0's count, and the other classes' marks above it.
    let count_word = hash[entry as usize * HASH_ENTRY_WORDS + hash_word::COUNT].load(Relaxed);
    for class in 0..classes {
        if class > 0 && count_word & class_mark(class) == 0 || !kinds.take(class, classes) {
            continue;
        }
        let word = class_entry(entry, class, params.hash_size) as usize * HASH_ENTRY_WORDS;
        let counted = if class == 0 {
            count_word
        } else {
            hash[word + hash_word::COUNT].load(Relaxed)
        };
        let photons_in_entry = entry_count(counted, classes);
        if photons_in_entry == 0 {
            continue;
        }
        let photon = &photons[hash[word + hash_word::WINNER].load(Relaxed) as usize];
        if counts(photon) {
            sum.add_if_near(query, photon, photons_in_entry);
        }
    }
}

/// Gather and update with any density method: `query` finds the photons around the visible
/// point; the statistics update is the same for all. Lit pixels then offer their radius to the
/// pass's maximum and histogram.
pub fn gather_with(
    counters: &[AtomicU32],
    params: &SppmParams,
    visible_point: &VisiblePoint,
    stats: PixelStats,
    query: impl FnOnce(&GatherQuery) -> GatherSum,
) -> PixelStats {
    let (stats, lit) = gather_update(counters, params, visible_point, stats, query);
    LitSummary::default()
        .add(lit, served_largest(counters))
        .offer(counters);
    stats
}

/// One pixel's radii that have met photons, as bits (0 for none; positive floats order as
/// their bits do), each sizing its own grid's cells next pass (`render::hash`): on surfaces
/// its indirect radius, and its caustic radius where caustic photons have their own grid
/// (`render::hash::caustic_apart`; else the larger of the two on surfaces); its volume
/// photons' radius.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LitRadii {
    pub surfaces: u32,
    pub caustic: u32,
    pub volume: u32,
}

impl LitRadii {
    /// The larger of each.
    pub fn max(self, other: LitRadii) -> LitRadii {
        LitRadii {
            surfaces: self.surfaces.max(other.surfaces),
            caustic: self.caustic.max(other.caustic),
            volume: self.volume.max(other.volume),
        }
    }
}

/// Many pixels' [`LitRadii`]: the largest of each, and the surface and caustic radii counted
/// by bucket (`render::radius_histogram`), which [`finish_pass`] sizes the next cells by.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LitSummary {
    pub largest: LitRadii,
    pub histogram: [u32; RADIUS_BUCKETS],
    pub caustic_histogram: [u32; RADIUS_BUCKETS],
}

impl Default for LitSummary {
    fn default() -> LitSummary {
        LitSummary {
            largest: LitRadii::default(),
            histogram: [0; RADIUS_BUCKETS],
            caustic_histogram: [0; RADIUS_BUCKETS],
        }
    }
}

impl LitSummary {
    /// With one pixel's radii, `served` being the largest radii this pass's surface and
    /// caustic cells serve ([`served_largest`]).
    pub fn add(mut self, lit: LitRadii, served: (f32, f32)) -> LitSummary {
        self.largest = self.largest.max(lit);
        if lit.surfaces != 0 {
            self.histogram[radius_bucket(f32::from_bits(lit.surfaces), served.0) as usize] += 1;
        }
        if lit.caustic != 0 {
            let bucket = radius_bucket(f32::from_bits(lit.caustic), served.1);
            self.caustic_histogram[bucket as usize] += 1;
        }
        self
    }

    /// Both summaries' pixels.
    pub fn merge(mut self, other: LitSummary) -> LitSummary {
        self.largest = self.largest.max(other.largest);
        for (mine, theirs) in [
            (&mut self.histogram, other.histogram),
            (&mut self.caustic_histogram, other.caustic_histogram),
        ] {
            for (count, more) in mine.iter_mut().zip(theirs) {
                *count += more;
            }
        }
        self
    }

    /// Offers them to the pass's maxima and histograms (one atomic a word, as the kernels'
    /// pixels each offer theirs).
    pub fn offer(self, counters: &[AtomicU32]) {
        counters[counter::MAX_RADIUS].fetch_max(self.largest.surfaces, Relaxed);
        counters[counter::CAUSTIC_MAX_RADIUS].fetch_max(self.largest.caustic, Relaxed);
        counters[counter::VOLUME_MAX_RADIUS].fetch_max(self.largest.volume, Relaxed);
        for (start, histogram) in [
            (counter::RADIUS_HISTOGRAM, &self.histogram),
            (counter::CAUSTIC_RADIUS_HISTOGRAM, &self.caustic_histogram),
        ] {
            for (bucket, &count) in histogram.iter().enumerate() {
                if count > 0 {
                    counters[start + bucket].fetch_add(count, Relaxed);
                }
            }
        }
    }
}

/// The largest radii this pass's surface cells and caustic cells serve.
pub fn served_largest(counters: &[AtomicU32]) -> (f32, f32) {
    (
        grid_largest_radius(cell_size_of(counters, false), false),
        grid_largest_radius(caustic_cell_size_of(counters), false),
    )
}

/// [`gather_with`] without its atomics: the new statistics, and the radii that have met
/// photons, which a caller gathering many pixels can reduce itself before offering them once.
pub fn gather_update(
    counters: &[AtomicU32],
    params: &SppmParams,
    visible_point: &VisiblePoint,
    mut stats: PixelStats,
    query: impl FnOnce(&GatherQuery) -> GatherSum,
) -> (PixelStats, LitRadii) {
    let cell_size = cell_size_of(counters, false);
    let volume_cell_size = cell_size_of(counters, true);
    let caustic_cell_size = caustic_cell_size_of(counters);
    let apart = caustic_apart(params.hash_classes());
    // A pixel whose radius is larger than the cells allow (one that has not met a photon
    // while the lit pixels shrank the cells) shrinks to fit, its flux scaled with the area.
    let largest = grid_largest_radius(cell_size, false);
    shrink_to_fit(&mut stats.tau, &mut stats.radius, largest, AREA);
    shrink_to_fit(
        &mut stats.caustic_tau,
        &mut stats.caustic_radius,
        if apart {
            grid_largest_radius(caustic_cell_size, false)
        } else {
            largest
        },
        AREA,
    );
    shrink_to_fit(
        &mut stats.volume_tau,
        &mut stats.volume_radius,
        grid_largest_radius(volume_cell_size, true),
        VOLUME,
    );
    if !visible_point.is_valid() {
        return (stats, LitRadii::default());
    }
    let (normal, volume) = if is_volume(visible_point.normal) {
        let (direction, anisotropy) = unpack_volume_point(visible_point.normal);
        let volume = VolumeQuery {
            direction,
            anisotropy,
            radius: stats.volume_radius,
        };
        (-direction, Some(volume))
    } else {
        (unpack_normal(visible_point.normal), None)
    };
    let sum = query(&GatherQuery {
        position: vec3(visible_point.position),
        normal,
        radius: stats.radius,
        caustic_radius: stats.caustic_radius,
        cell_size: if volume.is_some() {
            volume_cell_size
        } else {
            cell_size
        },
        caustic_cell_size,
        volume,
    });
    let weight = vec3(visible_point.weight);
    let s = &mut stats;
    let indirect = (sum.found, weight * sum.flux, params.indirect_alpha);
    update(
        &mut s.tau,
        &mut s.photon_count,
        &mut s.radius,
        indirect,
        AREA,
    );
    let caustic = (sum.caustic_found, weight * sum.caustic_flux, params.alpha);
    let (tau, count, radius) = (
        &mut s.caustic_tau,
        &mut s.caustic_count,
        &mut s.caustic_radius,
    );
    update(tau, count, radius, caustic, AREA);
    // Divided by the share of the sphere inside the medium: none is found outside.
    let inside = volume_boundary::share_inside(visible_point.pad, s.volume_radius);
    let scattered = (
        sum.volume_found,
        weight * sum.volume_flux / inside,
        params.alpha,
    );
    let (tau, count, radius) = (&mut s.volume_tau, &mut s.volume_count, &mut s.volume_radius);
    update(tau, count, radius, scattered, VOLUME);
    // Only radii that have met photons size the cells: the others would hold them at the
    // initial radius for ever, and one photon kept per cell would then serve ever more
    // pixels.
    let lit = |count: f32, radius: f32| if count > 0.0 { radius.to_bits() } else { 0 };
    let indirect = lit(stats.photon_count, stats.radius);
    let caustic = lit(stats.caustic_count, stats.caustic_radius);
    let lit_radii = LitRadii {
        surfaces: if apart {
            indirect
        } else {
            indirect.max(caustic)
        },
        caustic: if apart { caustic } else { 0 },
        volume: lit(stats.volume_count, stats.volume_radius),
    };
    (stats, lit_radii)
}

/// The dimensions a set of statistics gathers over: a disc's on surfaces, a sphere's in murky
/// glass.
const AREA: i32 = 2;
const VOLUME: i32 = 3;

/// A radius larger than the cells allow shrinks to `largest`, its flux scaled with the disc's
/// area or the sphere's volume (`dimensions`).
fn shrink_to_fit(tau: &mut [f32; 3], radius: &mut f32, largest: f32, dimensions: i32) {
    if *radius > largest {
        let scale = (largest / *radius).powi(dimensions);
        *tau = (vec3(*tau) * scale).to_array();
        *radius = largest;
    }
}

/// SPPM's update of one set of statistics (DESIGN.md, "SPPM update") with M photons found of
/// weighted flux Φ, at α: N' = N + αM, R' = R·√((N + αM)/(N + M)), τ' = (τ + Φ)·R'²/R², over
/// a disc; in a sphere (`dimensions` 3) R' = R·∛((N + αM)/(N + M)), τ' = (τ + Φ)·R'³/R³ (so τ
/// scales by the same ratio either way).
fn update(
    tau: &mut [f32; 3],
    count: &mut f32,
    radius: &mut f32,
    found: (u32, Vec3, f32),
    dimensions: i32,
) {
    let (m, flux, alpha) = found;
    if m == 0 {
        return;
    }
    let n = *count;
    let m = m as f32;
    let n_next = n + alpha * m;
    let ratio = n_next / (n + m);
    *count = n_next;
    *radius *= if dimensions == VOLUME {
        ratio.cbrt()
    } else {
        ratio.sqrt()
    };
    *tau = ((vec3(*tau) + flux) * ratio).to_array();
}

/// Closes a pass (one invocation): folds this pass's emitted paths into the 64-bit total,
/// sets the next pass's cell sizes from the lit radii (the surfaces' for all but
/// `params.shrunk_tenths` of them, `render::radius_histogram`; the volume photons' largest),
/// and advances the pass counter.
pub fn finish_pass(params: &SppmParams, counters: &[AtomicU32]) {
    let emitted = counters[counter::EMITTED_PASS].swap(0, Relaxed);
    let low = counters[counter::EMITTED_LO].load(Relaxed);
    let (sum, carry) = low.overflowing_add(emitted);
    counters[counter::EMITTED_LO].store(sum, Relaxed);
    counters[counter::EMITTED_HI].fetch_add(carry as u32, Relaxed);
    // No pixel has met a photon yet: the cells stay as they are. Each grid by its own radii.
    let largest = served_largest(counters);
    for (histogram, max, cells, largest) in [
        (
            counter::RADIUS_HISTOGRAM,
            counter::MAX_RADIUS,
            counter::CELL_SIZE,
            largest.0,
        ),
        (
            counter::CAUSTIC_RADIUS_HISTOGRAM,
            counter::CAUSTIC_MAX_RADIUS,
            counter::CAUSTIC_CELL_SIZE,
            largest.1,
        ),
    ] {
        let counts: [u32; RADIUS_BUCKETS] =
            std::array::from_fn(|b| counters[histogram + b].swap(0, Relaxed));
        let largest_lit = f32::from_bits(counters[max].swap(0, Relaxed));
        let served = served_radius(&counts, params.shrunk_tenths, largest, largest_lit);
        if let Some(radius) = served {
            counters[cells].store(grid_cell_size(radius, false).to_bits(), Relaxed);
        }
    }
    let volume_radius = f32::from_bits(counters[counter::VOLUME_MAX_RADIUS].swap(0, Relaxed));
    if volume_radius > 0.0 {
        let cells = grid_cell_size(volume_radius, true);
        counters[counter::VOLUME_CELL_SIZE].store(cells.to_bits(), Relaxed);
    }
    counters[counter::PASS].fetch_add(1, Relaxed);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A light sample at rough metal takes the metal's Fresnel reflectance at the half-way
    /// vector of the view and the light (`render::conductor::Metal::tint`), not its colour:
    /// the response is the lobe's times that reflectance, per channel.
    #[test]
    fn a_light_sample_at_rough_metal_takes_fresnel_s_reflectance_at_the_light() {
        let hit = SurfaceHit {
            position: Vec3::ZERO,
            shadow_origin: Vec3::ZERO,
            distance: 1.0,
            geometric: Vec3::Y,
            shading: Vec3::Y,
            interpolated: Vec3::Y,
            uv: glam::Vec2::ZERO,
            material: 0,
            front: true,
            brush: Vec3::ZERO,
        };
        let metal = Metal {
            f0: Vec3::new(0.9, 0.6, 0.3),
            edge: Vec3::new(1.0, 0.5, 0.0),
            film: render::iridescence::Film::default(),
        };
        let lit = LitLobes {
            glossy: Vec3::ONE,
            lobe: GlossyLobe::metal(0.3, Vec3::ZERO),
            metal: Some(metal),
            ..LitLobes::default()
        };
        // Grazing view and light, mirrored: the half-way vector is the normal's neighbour.
        let outgoing = Vec3::new(0.95, 0.2, 0.0).normalize();
        let incident = Vec3::new(-0.9, 0.3, 0.1).normalize();
        let lobe = lit.lobe.response(Vec3::Y, outgoing, incident);
        assert!(lobe.value > 0.0);
        let pdf = 1.0;
        let expected =
            metal.tint(outgoing, incident) * (lobe.value * power_heuristic(pdf, lobe.pdf));
        let response = lit.response(&hit, outgoing, incident, pdf);
        assert!(
            (response - expected).abs().max_element() < 1e-6,
            "{response} vs {expected}"
        );
        // The rise is there: the blue channel (no edge) stays at ρ, red and green rise.
        let ratio = response / (metal.f0 * (response.z / metal.f0.z));
        assert!(
            ratio.x > 1.01 && ratio.y > 1.05 && (ratio.z - 1.0).abs() < 1e-6,
            "{ratio}"
        );
    }
}
