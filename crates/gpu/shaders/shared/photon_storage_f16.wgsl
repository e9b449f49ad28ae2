// Photons and visible points in 16 bytes of f16 (render::half_storage::HalfPoint): positions
// relative to the scene's centre, flux or weight in f16, the octahedral normal as is. An
// unstored photon or invalid point is stored as zeros (zero flux or weight: still unstored).

@group(1) @binding(3) var<storage, read_write> photons: array<HalfPoint>;
@group(1) @binding(4) var<storage, read_write> visible_points: array<HalfPoint>;

fn storage_origin() -> vec3<f32> {
    return vec3<f32>(params.origin_x, params.origin_y, params.origin_z);
}

// render::half_storage::HalfPoint::pack.
fn pack_half_point(position: vec3<f32>, normal: u32, value: vec3<f32>) -> HalfPoint {
    if !any(value != vec3<f32>(0.0)) {
        return HalfPoint(0u, 0u, 0u, 0u);
    }
    let p = position - storage_origin();
    return HalfPoint(pack2x16float(p.xy), pack2x16float(vec2<f32>(p.z, value.x)), pack2x16float(value.yz), normal);
}

// render::half_storage::HalfPoint::unpack: (position, value) with the normal alongside.
struct UnpackedPoint {
    position: vec3<f32>,
    value: vec3<f32>,
}

fn unpack_half_point(h: HalfPoint) -> UnpackedPoint {
    let xy = unpack2x16float(h.xy);
    let z_r = unpack2x16float(h.z_r);
    let g_b = unpack2x16float(h.g_b);
    return UnpackedPoint(vec3<f32>(xy, z_r.x) + storage_origin(), vec3<f32>(z_r.y, g_b));
}

// A photon as it lies in memory (the full hash copies them into list order as they are).
alias StoredPhoton = HalfPoint;

// Fluxes are stored × params.flux_scale (render::half_storage::round_photon).
fn unpack_photon(stored: StoredPhoton) -> Photon {
    let u = unpack_half_point(stored);
    return Photon(u.position, stored.normal, u.value / params.flux_scale, 0u);
}

fn load_photon(index: u32) -> Photon {
    return unpack_photon(photons[index]);
}

fn store_photon(index: u32, photon: Photon) {
    photons[index] = pack_half_point(photon.position, photon.normal, photon.flux * params.flux_scale);
}

fn load_visible_point(index: u32) -> VisiblePoint {
    let h = visible_points[index];
    let u = unpack_half_point(h);
    return VisiblePoint(u.position, h.normal, u.value, 0u);
}

// A volume point's depths have no room here: its weight takes the share inside its medium at
// the pixel's volume radius instead (render::volume_boundary::share_in_weight).
fn store_visible_point(index: u32, point: VisiblePoint) {
    let kept = share_in_weight(point, pixels[index].volume_radius);
    visible_points[index] = pack_half_point(kept.position, kept.normal, kept.weight);
}
