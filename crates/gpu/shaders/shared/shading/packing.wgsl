// render::packing: the octahedral words of photons' and visible points' normals, with their
// flags (caustic, volume) and a volume point's asymmetry (tests/packing_twins.rs).

// ---- render::packing: octahedral normals in one u32 ----
fn fold(a: f32, b: f32) -> f32 {
    return (1.0 - abs(b)) * sign_not_zero(a);
}

fn pack_normal(n: vec3<f32>) -> u32 {
    var p = n.xy / max(abs(n.x) + abs(n.y) + abs(n.z), 1.17549435e-38);
    if n.z < 0.0 {
        p = vec2<f32>(fold(p.x, p.y), fold(p.y, p.x));
    }
    return pack2x16snorm(p);
}

// render::packing::surface_normal: VOLUME_BIT clear (surface visible points and photons).
fn surface_normal(n: vec3<f32>) -> u32 {
    return pack_normal(n) & ~VOLUME_BIT;
}

// render::packing::photon_normal: the class in the lowest bit (1: caustic), VOLUME_BIT clear.
fn photon_normal(n: vec3<f32>, caustic: bool) -> u32 {
    return (surface_normal(n) & ~1u) | select(0u, 1u, caustic);
}

fn is_caustic(packed_normal: u32) -> bool {
    return (packed_normal & 1u) != 0u;
}

// render::packing::is_volume: a volume photon's or visible point's word (murky glass).
fn is_volume(packed_normal: u32) -> bool {
    return (packed_normal & VOLUME_BIT) != 0u;
}

// render::packing::volume_photon_direction: the way it travelled, no caustic class.
fn volume_photon_direction(direction: vec3<f32>) -> u32 {
    return (pack_normal(direction) & ~1u) | VOLUME_BIT;
}

// render::packing's ANISOTROPY_BITS (private there; tests/packing_twins.rs checks the words
// bit for bit): the nine bits of a volume visible point's word that hold its asymmetry.
const ANISOTROPY_BITS: u32 = 0x001e001fu;

// render::packing::volume_point_direction: the way the eye path travelled and its medium's
// Henyey–Greenstein asymmetry to nine bits. Rust's round() takes halves away from zero,
// WGSL's to even: the level is rounded by hand (x − floor(x) is exact).
fn volume_point_direction(direction: vec3<f32>, g: f32) -> u32 {
    let scaled = (clamp(g, -1.0, 1.0) + 1.0) * 0.5 * 511.0;
    let below = floor(scaled);
    let level = u32(select(below, below + 1.0, scaled - below >= 0.5));
    let bits = (level & 0x1fu) | ((level >> 5u) << 17u);
    return (pack_normal(direction) & ~(ANISOTROPY_BITS | VOLUME_BIT)) | bits | VOLUME_BIT;
}

// render::packing::unpack_volume_point: its direction (xyz) and asymmetry (w).
fn unpack_volume_point(word: u32) -> vec4<f32> {
    let level = (word & 0x1fu) | (((word >> 17u) & 0xfu) << 5u);
    let g = f32(level) / 511.0 * 2.0 - 1.0;
    return vec4<f32>(unpack_normal(word & ~(ANISOTROPY_BITS | VOLUME_BIT)), g);
}

fn unpack_normal(bits: u32) -> vec3<f32> {
    let o = unpack2x16snorm(bits);
    let z = 1.0 - abs(o.x) - abs(o.y);
    var xy = o;
    if z < 0.0 {
        xy = vec2<f32>(fold(o.x, o.y), fold(o.y, o.x));
    }
    let n = vec3<f32>(xy, z);
    let length_squared = dot(n, n);
    return select(vec3<f32>(0.0, 0.0, 1.0), n * inverseSqrt(length_squared), length_squared > 0.0);
}
