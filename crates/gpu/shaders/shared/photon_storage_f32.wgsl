// Photons and visible points stored as they are (32 bytes each, f32; the default).

@group(1) @binding(3) var<storage, read_write> photons: array<Photon>;
@group(1) @binding(4) var<storage, read_write> visible_points: array<VisiblePoint>;

// A photon as it lies in memory (the full hash copies them into list order as they are).
alias StoredPhoton = Photon;

fn unpack_photon(stored: StoredPhoton) -> Photon {
    return stored;
}

fn load_photon(index: u32) -> Photon {
    return photons[index];
}

fn store_photon(index: u32, photon: Photon) {
    photons[index] = photon;
}

fn load_visible_point(index: u32) -> VisiblePoint {
    return visible_points[index];
}

fn store_visible_point(index: u32, point: VisiblePoint) {
    visible_points[index] = point;
}
