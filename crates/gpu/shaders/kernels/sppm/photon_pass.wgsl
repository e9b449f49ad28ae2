// The photon pass (cpu::kernels::photon_pass): each slot's light path advanced one segment,
// through media and walks, and the photon it keeps.

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
    // The path's walk after the segment, its weight in flux (walked false: it did not walk).
    walked: bool,
    walk: Walk,
}

// cpu::kernels::photon_segment: straight through a clear or absorbing medium, a walk from
// scattering to scattering inside a scattering solid (the path's, going on from the slot's;
// its hero drawn where the path has not walked), drawing the same numbers; in murky
// glass one more number at each scattering event keeps it as the step's volume photon with
// probability 1/events (a reservoir of one), whose flux is multiplied by the events at the
// end.
fn photon_segment(slot: PathSlot, medium: u32, rng: ptr<function, Rng>) -> PhotonSegment {
    var segment: PhotonSegment;
    segment.scattered = false;
    segment.walking = false;
    segment.walked = false;
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
    var walk: Walk;
    if slot.walk_hero == NO_WALK {
        walk = walk_start(next_f32(rng));
    } else {
        walk = walk_resume(slot.walk_hero, slot.walk_densities);
    }
    var events = 0u;
    var kept = segment.volume_photon;
    loop {
        // Out of the scene the flight runs on forever: in an atmosphere it scatters on the
        // way, or leaves (keeping its photon, if any).
        let hit = trace_surface(origin, direction);
        let distance = select(RAY_T_MAX, hit.distance, hit.found);
        let t = walk_flight(&walk, extinction, scattering, distance, next_f32(rng));
        if t < 0.0 && !hit.found {
            segment.found = false;
            if murky {
                segment.volume_photon = times_events(kept, events);
            }
            return segment;
        }
        if t < 0.0 {
            segment.found = true;
            segment.hit = hit;
            segment.direction = direction;
            segment.flux = slot.flux * walk.weight;
            segment.scattered = events > 0u;
            segment.walked = true;
            segment.walk = walk;
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
            segment.walked = true;
            segment.walk = walk;
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
    // cpu::kernels: the slot carries the path's walk on (its weight is in the flux).
    if SCATTERING && segment.walked {
        slot.walk_hero = segment.walk.hero;
        slot.walk_densities = segment.walk.densities;
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
            let shading_factors = bounded_correction(arrival_factor(-direction, hit.interpolated, hit.geometric)
                * departure_factor(coat.bounce.direction, hit.interpolated, hit.geometric));
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
                let shading_factors = bounded_correction(arrival_factor(-direction, hit.shading, hit.geometric)
                    * departure_factor(bounce.direction, hit.shading, hit.geometric));
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
            var share = vec3<f32>(1.0);
            if keeper_surface == SURFACE_PLASTIC {
                let cos = dot(direction, hit.shading);
                let layer = hit_dielectric_layer(keeper_material, hit.uv);
                share = coat_transmittance_of(keeper, keeper_material.roughness_alpha, cos) * coat_layer_transmission(layer, keeper_material.ior, cos);
            }
            let landed = Photon(hit.position, photon_normal(hit.shading, !bounced), flux * (bounded_correction(arrival) * share), 0u);
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
        let layer = hit_dielectric_layer(material, hit.uv);
        let choice = plastic_bounce(material, hit, direction, layer, u_choice, u_direction0, u_direction1);
        if choice.base {
            bounced = true;
            let side = lambertian_side(material, hit, surface_tint, u_side);
            out = side.hit;
            let bounce = diffuse_bounce(out, u_direction0, u_direction1);
            next = bounce.direction;
            weight = bounce.weight;
            let alpha = material.roughness_alpha;
            let cos = dot(next, out.shading);
            let leaving = coat_transmittance_of(hit.material, alpha, cos) * coat_layer_transmission(layer, material.ior, cos);
            let bare_scale = coat_diffuse_scale_of(hit.material, alpha);
            let scale = bare_scale * coat_layer_diffuse_share(layer, bare_scale, material.ior);
            tint = side.tint * leaving * choice.film_tint * (choice.base_weight * scale);
        } else {
            next = choice.coat.direction;
            weight = choice.coat.weight;
            tint = choice.film_tint;
        }
    } else {
        let dispersed = dispersed_material(material, wavelength, u_wavelength);
        let layer = hit_dielectric_layer(material, hit.uv);
        let bounce = specular_direction(dispersed.material, hit, direction, layer, u_direction0, u_direction1, u_choice);
        next = bounce.direction;
        weight = bounce.weight;
        tint = bounce_tint_of(dispersed.material, surface_tint, layer, hit, direction, next) * dispersed.weight;
        wavelength = dispersed.wavelength;
    }
    // Out through the sheen and the clear coat, if any (the far side's where it passed
    // through).
    let out_of_coat = clearcoat_transmittance(coat_weight, dot(next, out.interpolated));
    let out_of_sheen = sheen_transmittance(sheen, dot(next, out.shading));
    weight = weight * (bounded_correction(arrival * departure_factor(next, out.shading, out.geometric)) * out_of_coat * out_of_sheen);
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
