// render::volume_boundary: the share of a volume gather's sphere inside its medium, from the
// depths below the surfaces behind and ahead of the visible point, kept as two bfloat16 in
// its spare word (tests/packing_twins.rs checks these bit for bit).

// render::volume_boundary::MIN_SHARE and NO_SURFACE (the largest f32: WGSL has no infinity).
const MIN_BOUNDARY_SHARE: f32 = 0.125;
const NO_SURFACE: f32 = 3.40282347e+38;
const DEPTHS_PRESENT: u32 = 0x80000000u;

// render::volume_boundary::depths_word.
fn depths_word(behind: f32, ahead: f32) -> u32 {
    let b = bitcast<u32>(max(behind, 0.0)) >> 16u;
    let a = bitcast<u32>(max(ahead, 0.0)) >> 16u;
    return DEPTHS_PRESENT | (b << 16u) | a;
}

// render::volume_boundary's cap_share: the share of the sphere beyond a plane `depth` above
// its centre.
fn cap_share(depth: f32, radius: f32) -> f32 {
    let beyond = 1.0 - min(depth / radius, 1.0);
    return beyond * beyond * (3.0 - beyond) * 0.25;
}

// render::volume_boundary::share_inside.
fn share_inside(word: u32, radius: f32) -> f32 {
    if (word & DEPTHS_PRESENT) == 0u || radius <= 0.0 {
        return 1.0;
    }
    let behind = bitcast<f32>((word & ~DEPTHS_PRESENT) & 0xffff0000u);
    let ahead = bitcast<f32>(word << 16u);
    return max(1.0 - (cap_share(behind, radius) + cap_share(ahead, radius)), MIN_BOUNDARY_SHARE);
}

// render::volume_boundary::share_in_weight: for the f16 storage, which has no spare word, the
// share at the pixel's volume radius `radius` folded into the weight.
fn share_in_weight(point: VisiblePoint, radius: f32) -> VisiblePoint {
    return VisiblePoint(point.position, point.normal, point.weight / share_inside(point.pad, radius), 0u);
}
