// render::sky_map: the sky's environment map in the `sky_map` buffer (declared by the kernels
// that read it), its bilinear lookups and importance sampling, twins of the CPU's functions.

// render::sky_map::MapFrame: the map's size and rotation from the sky's table entry (width 0:
// a uniform sky).
struct MapFrame {
    width: u32,
    height: u32,
    cos_turn: f32,
    sin_turn: f32,
}

// render::sky_map::MapFrame::turned_to_world: a map-frame direction turned about +Y.
fn turned_to_world(frame: MapFrame, d: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(frame.cos_turn * d.x + frame.sin_turn * d.z, d.y, -frame.sin_turn * d.x + frame.cos_turn * d.z);
}

// render::sky_map::MapFrame::turned_to_map: turned_to_world's inverse.
fn turned_to_map(frame: MapFrame, d: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(frame.cos_turn * d.x - frame.sin_turn * d.z, d.y, frame.sin_turn * d.x + frame.cos_turn * d.z);
}

// Texel (x, y)'s radiance (render::sky_map's layout).
fn sky_texel(frame: MapFrame, x: u32, y: u32) -> vec3<f32> {
    let i = 3u * (y * frame.width + x);
    return vec3<f32>(sky_map[i], sky_map[i + 1u], sky_map[i + 2u]);
}

// render::sky_map::MapFrame::coordinates, with scene::sky_map::map_coordinates.
fn sky_coordinates(frame: MapFrame, direction: vec3<f32>) -> vec2<f32> {
    let d = turned_to_map(frame, direction);
    var u = 0.5 + atan2(d.x, -d.z) / (2.0 * PI);
    if u >= 1.0 {
        u -= 1.0;
    }
    return vec2<f32>(u, acos(clamp(d.y, -1.0, 1.0)) / PI);
}

// render::sky_map::MapFrame::radiance_at, with scene::sky_map::bilinear_footprint: bilinear
// between texel centres, columns wrapping, rows clamped.
fn sky_radiance_at(frame: MapFrame, uv: vec2<f32>) -> vec3<f32> {
    let s = uv.x * f32(frame.width) - 0.5;
    let t = uv.y * f32(frame.height) - 0.5;
    let left = floor(s);
    let top = floor(t);
    let w = i32(frame.width);
    let x0 = u32(((i32(left) % w) + w) % w);
    let x1 = (x0 + 1u) % frame.width;
    let y0 = min(u32(max(top, 0.0)), frame.height - 1u);
    let y1 = min(u32(max(top + 1.0, 0.0)), frame.height - 1u);
    let a = s - left;
    let upper = mix(sky_texel(frame, x0, y0), sky_texel(frame, x1, y0), a);
    let lower = mix(sky_texel(frame, x0, y1), sky_texel(frame, x1, y1), a);
    return mix(upper, lower, t - top);
}

// render::sky_map::cell_row_span: cell row j's extent in v.
fn sky_cell_row_span(frame: MapFrame, j: u32) -> vec2<f32> {
    let h = f32(frame.height);
    return vec2<f32>(max(f32(j) - 0.5, 0.0) / h, min(f32(j) + 0.5, h) / h);
}

// render::sky_map::last_upper_row: the last cell row of the upper half.
fn sky_last_upper_row(frame: MapFrame) -> u32 {
    return frame.height / 2u;
}

// render::sky_map::MapFrame::offsets: where the rows' CDFs over cells begin, then those over
// rows, the rows' density factors, and the upper half's share.
fn sky_offsets(frame: MapFrame) -> vec4<u32> {
    let rows = frame.height + 1u;
    let cells = 3u * frame.width * frame.height;
    let marginal = cells + rows * frame.width;
    return vec4<u32>(cells, marginal, marginal + rows, marginal + 2u * rows);
}

// render::sky_map::MapFrame::map_upper_share.
fn sky_map_upper_share(frame: MapFrame) -> f32 {
    return sky_map[sky_offsets(frame).w];
}

// render::sky_map::MapFrame::upper_share_facing.
fn sky_upper_share_facing(frame: MapFrame, normal: vec3<f32>) -> f32 {
    let share = sky_map_upper_share(frame);
    if share <= 0.0 || share >= 1.0 {
        return clamp(share, 0.0, 1.0);
    }
    if normal.y >= 0.0 {
        return share + normal.y * (1.0 - share);
    }
    return share * (1.0 + normal.y);
}

// render::sky_map::MapFrame::density: the density over map coordinates of a point of cell
// row j where the map holds `radiance`, drawing from the upper half with probability `upper`.
fn sky_density(frame: MapFrame, j: u32, radiance: vec3<f32>, upper: f32) -> f32 {
    var half = 1.0 - upper;
    if j <= sky_last_upper_row(frame) {
        half = upper;
    }
    return sky_channel_sum(radiance) * sky_map[sky_offsets(frame).z + j] * half;
}

// render::sky_map::solid_angle_density.
fn sky_solid_angle_density(density: f32, sine: f32) -> f32 {
    if sine > 0.0 {
        return density / (2.0 * PI * PI * sine);
    }
    return 0.0;
}

// render::sky_map::SkyDirection; `found` false at the poles.
struct SkyDirection {
    direction: vec3<f32>,
    radiance: vec3<f32>,
    pdf: f32,
    found: bool,
}

// render::sky_map::sky_map_lookup: the radiance along `direction` and its density.
fn sky_map_lookup(frame: MapFrame, direction: vec3<f32>, upper: f32) -> SkyDirection {
    let uv = sky_coordinates(frame, direction);
    let radiance = sky_radiance_at(frame, uv);
    let j = min(u32(uv.y * f32(frame.height) + 0.5), frame.height);
    let sine = sqrt(max(1.0 - direction.y * direction.y, 0.0));
    let pdf = sky_solid_angle_density(sky_density(frame, j, radiance, upper), sine);
    return SkyDirection(direction, radiance, pdf, true);
}

// render::sky_map::search over sky_map[first .. first + count]: the entry and the fraction.
fn sky_search(first: u32, count: u32, u: f32) -> vec2<f32> {
    var lo = 0u;
    var hi = count - 1u;
    while lo < hi {
        let mid = (lo + hi) / 2u;
        if u < sky_map[first + mid] {
            hi = mid;
        } else {
            lo = mid + 1u;
        }
    }
    var before = 0.0;
    if lo > 0u {
        before = sky_map[first + lo - 1u];
    }
    let width = sky_map[first + lo] - before;
    var fraction = 0.5;
    if width > 0.0 {
        fraction = clamp((u - before) / width, 0.0, 0.99999994);
    }
    return vec2<f32>(f32(lo), fraction);
}

// render::sky_map::sample_linear.
fn sky_sample_linear(u: f32, p0: f32, p1: f32) -> f32 {
    if p0 == p1 {
        return u;
    }
    let x = u * (p0 + p1) / (p0 + sqrt(max(p0 * p0 + (p1 * p1 - p0 * p0) * u, 0.0)));
    return clamp(x, 0.0, 0.99999994);
}

// The channel sum of a radiance.
fn sky_channel_sum(radiance: vec3<f32>) -> f32 {
    return radiance.x + radiance.y + radiance.z;
}

// render::sky_map::sample_sky_map.
fn sample_sky_map(frame: MapFrame, u1: f32, u2: f32, upper_share: f32) -> SkyDirection {
    let offsets = sky_offsets(frame);
    let split = sky_last_upper_row(frame) + 1u;
    // u1 picks the half, then (stretched back to [0, 1)) the row within it.
    var first = split;
    var rows = frame.height + 1u - split;
    var u = 0.0;
    if u1 < upper_share {
        first = 0u;
        rows = split;
        u = u1 / upper_share;
    } else {
        u = (u1 - upper_share) / (1.0 - upper_share);
    }
    let row = sky_search(offsets.y + first, rows, min(u, 0.99999994));
    let j = first + u32(row.x);
    let column = sky_search(offsets.x + j * frame.width, frame.width, u2);
    let x = u32(column.x);
    let top_row = max(j, 1u) - 1u;
    let bottom_row = min(j, frame.height - 1u);
    let next = (x + 1u) % frame.width;
    let t00 = sky_texel(frame, x, top_row);
    let t10 = sky_texel(frame, next, top_row);
    let t01 = sky_texel(frame, x, bottom_row);
    let t11 = sky_texel(frame, next, bottom_row);
    let c00 = sky_channel_sum(t00);
    let c10 = sky_channel_sum(t10);
    let c01 = sky_channel_sum(t01);
    let c11 = sky_channel_sum(t11);
    let b = sky_sample_linear(row.y, c00 + c10, c01 + c11);
    let a = sky_sample_linear(column.y, c00 + (c01 - c00) * b, c10 + (c11 - c10) * b);
    // sky_radiance_at's interpolation, on the corners at hand.
    let radiance = mix(mix(t00, t10, a), mix(t01, t11, a), b);
    var map_u = (f32(x) + 0.5 + a) / f32(frame.width);
    if map_u >= 1.0 {
        map_u -= 1.0;
    }
    let span = sky_cell_row_span(frame, j);
    let v = span.x + (span.y - span.x) * b;
    let sine = sin(PI * v);
    var sample = SkyDirection(vec3<f32>(0.0, 1.0, 0.0), vec3<f32>(0.0), 0.0, false);
    if sine <= 0.0 {
        return sample;
    }
    // scene::sky_map::map_direction, then turned to the world.
    let phi = 2.0 * PI * (map_u - 0.5);
    let local = vec3<f32>(sine * sin(phi), cos(PI * v), -sine * cos(phi));
    sample.direction = turned_to_world(frame, local);
    sample.radiance = radiance;
    sample.pdf = sky_solid_angle_density(sky_density(frame, j, sample.radiance, upper_share), sine);
    sample.found = true;
    return sample;
}
