// The eye pass (cpu::kernels::eye_pass): each pixel's camera paths to its visible point, with
// the emission and direct light they meet on the way.

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
    // cpu::kernels::eye_path: the path's walk through murky glass, one over all its flights
    // there (hero NO_WALK until the first draws it).
    var walk = Walk(NO_WALK, vec3<f32>(1.0), vec3<f32>(1.0));
    // cpu::kernels::eye_path: the plane of the surface the ray last left (normal, offset),
    // where a volume visible point's depth is measured from; none from the camera.
    var behind = vec4<f32>(vec3<f32>(0.0), NO_SURFACE);
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
        // cpu::kernels::eye_path: in murky glass the flight may end where it scatters, with a
        // volume visible point; else it passes, weighed by what is not scattered. A ray out of
        // the scene runs on forever: in an atmosphere it scatters on the way.
        let in_murky_glass = is_murky_glass(medium);
        if in_murky_glass {
            let murky = materials[medium];
            if walk.hero == NO_WALK {
                walk = walk_start(next_f32(rng));
            }
            let distance = select(RAY_T_MAX, hit.distance, hit.found);
            let t = walk_flight(&walk, murky.absorption, murky.scattering, distance, next_f32(rng));
            if t >= 0.0 {
                let weight = throughput * walk_weight_over_scattering(walk, murky.scattering);
                if max3(weight) > 0.0 {
                    let word = volume_point_direction(direction, murky.scatter_anisotropy);
                    let position = origin + t * direction;
                    let depth_behind = abs(dot(behind.xyz, position) + behind.w);
                    var depth_ahead = NO_SURFACE;
                    if hit.found {
                        depth_ahead = (hit.distance - t) * abs(dot(direction, hit.geometric));
                    }
                    point = VisiblePoint(position, word, weight, depths_word(depth_behind, depth_ahead));
                }
                break;
            }
            throughput *= walk.weight;
            walk.weight = vec3<f32>(1.0);
        }
        if !hit.found {
            // Out of the scene: the sky (zero without one), less what water around the path
            // absorbs (a walk's weight holds that already).
            var kept = vec3<f32>(1.0);
            if !in_murky_glass {
                kept = medium_transmittance(medium, RAY_T_MAX);
            }
            direct += throughput * emission_share * (sky_radiance(direction) * kept) * sky_weight(glossy, direction);
            break;
        }
        if !in_murky_glass {
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
        // Only volume points (murky glass) read it: elsewhere it is not kept per bounce.
        if MURKY_GLASS {
            behind = vec4<f32>(hit.geometric, -dot(hit.geometric, hit.position));
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
                var lit = LitLobes(vec3<f32>(0.0), throughput * sheen_lobe_scale(sheen, dot(direction, hit.shading)), sheen.alpha, 0.0, 0.0, 0.0, coat_weight, true, no_sheen(), 0.0, vec3<f32>(0.0), false, vec3<f32>(0.0), vec3<f32>(0.0), no_film(), bare_dielectric_layer(), bare_dielectric_layer());
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
        var base_film_tint = vec3<f32>(1.0);
        var lit = LitLobes(vec3<f32>(0.0), vec3<f32>(0.0), 0.0, 0.0, 0.0, 0.0, coat_weight, false, sheen, 0.0, vec3<f32>(0.0), false, vec3<f32>(0.0), vec3<f32>(0.0), no_film(), bare_dielectric_layer(), bare_dielectric_layer());
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
            let layer = hit_dielectric_layer(material, hit.uv);
            lit.coat_layer = layer;
            let choice = plastic_bounce(material, hit, direction, layer, u, u_micro.x, u_micro.y);
            base = choice.base;
            base_weight = choice.base_weight;
            base_film_tint = choice.film_tint;
            bounce = choice.coat;
            bounce_tint = choice.film_tint;
        }
        // cpu::kernels::eye_path: where glTF's diffuse transmission took the light through,
        // the Lambertian lobe's side, with a light sample of its own.
        var far_side = false;
        var side = LambertianSide(hit, tint);
        if base {
            var scale = vec3<f32>(1.0);
            if plastic {
                let bare_scale = coat_diffuse_scale_of(hit.material, material.roughness_alpha);
                scale = bare_scale * coat_layer_diffuse_share(lit.coat_layer, bare_scale, material.ior);
            }
            if transmits_diffusely(material) {
                var u_side = numbers.y;
                if u_side < 0.0 {
                    u_side = next_f32(rng);
                }
                side = lambertian_side(material, hit, tint, u_side);
                far_side = side.hit.front != hit.front;
            }
            let weight = throughput * side.tint * base_film_tint * (scale * base_weight / PI);
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
            // cpu::kernels: a thin film colours the metal by the angle to each micro-normal;
            // glass wears the film and the specular layer.
            let layer = hit_dielectric_layer(material, hit.uv);
            let film = layer.film;
            if material.surface == SURFACE_ROUGH_CONDUCTOR {
                lit.glossy = throughput;
                lit.alpha = material.roughness_alpha;
                lit.brush = hit.brush;
                lit.metal = true;
                lit.metal_f0 = tint;
                lit.metal_edge = material.metal_edge;
                lit.film = film;
            }
            // cpu::kernels: solid frosted glass met from outside reflects as a coat does; met
            // from inside, its refraction out is the lobe.
            if FROSTED_GLASS && material.surface == SURFACE_ROUGH_DIELECTRIC && (material.flags & MATERIAL_THIN_WALLED) == 0u {
                lit.glossy = throughput * tint;
                lit.alpha = material.roughness_alpha;
                lit.dielectric_layer = layer;
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
                lit.dielectric_layer = layer;
                lit.sheet_eta = relative_eta(material.ior, hit.front, true);
            }
            bounce = specular_direction(material, hit, direction, layer, u, u_second, u_third);
            // Smooth glass's film takes its share below, after the way not taken is counted.
            if material.surface != SURFACE_DIELECTRIC {
                bounce_tint = bounce_tint_of(material, tint, layer, hit, direction, bounce.direction);
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
        // cpu::kernels::eye_path: under a layer (thin film, specular layer) each channel of
        // either way takes the layer's share of it.
        let probe = !met_glass && depth < params.max_depth;
        var glass_layer = bare_dielectric_layer();
        if material.surface == SURFACE_DIELECTRIC {
            glass_layer = hit_dielectric_layer(material, hit.uv);
        }
        let layered = !dielectric_layer_is_bare(glass_layer);
        if material.surface == SURFACE_DIELECTRIC && (probe || layered) {
            let branches = dielectric_branches(material, hit, direction, glass_layer);
            var other = branches.reflected;
            var other_share = branches.reflectance;
            var other_weight = branches.layered_reflectance;
            if u < branches.reflectance {
                other = branches.transmitted;
                other_share = 1.0 - branches.reflectance;
                other_weight = vec3<f32>(1.0) - branches.layered_reflectance;
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
            if layered {
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
