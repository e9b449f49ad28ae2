//! From linear radiance to display values: exposure (in stops), a clamp to [0, 1] and the sRGB
//! transfer function (IEC 61966-2-1). PNG output (`kousen`) and the GPU display pass
//! (`gpu::display`, whose WGSL mirrors these formulas) share these definitions.

/// The sRGB transfer function, unclamped.
pub fn linear_to_srgb(c: f32) -> f32 {
    if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// The inverse of [`linear_to_srgb`].
pub fn srgb_to_linear(s: f32) -> f32 {
    if s <= 0.040_45 {
        s / 12.92
    } else {
        ((s + 0.055) / 1.055).powf(2.4)
    }
}

/// Clamps to [0, 1] (non-finite values to 0) and applies the sRGB transfer function, rounded
/// to 8 bits.
pub fn linear_to_srgb8(c: f32) -> u8 {
    let c = if c.is_finite() {
        c.clamp(0.0, 1.0)
    } else {
        0.0
    };
    (linear_to_srgb(c) * 255.0 + 0.5) as u8
}

/// `linear` scaled by 2^`exposure_stops` and clamped to [0, 1]; non-finite results become 0.
pub fn display_value(linear: f32, exposure_stops: f32) -> f32 {
    let scaled = linear * 2f32.powf(exposure_stops);
    if scaled.is_finite() {
        scaled.clamp(0.0, 1.0)
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_round_trip_is_close() {
        for i in 0..=1000 {
            let c = i as f32 / 1000.0;
            let back = srgb_to_linear(linear_to_srgb(c));
            assert!((back - c).abs() <= 1e-6 + 1e-5 * c, "{c} -> {back}");
        }
    }

    #[test]
    fn srgb_known_values_and_continuity() {
        assert_eq!(linear_to_srgb(0.0), 0.0);
        assert!((linear_to_srgb(1.0) - 1.0).abs() < 1e-6);
        assert!((linear_to_srgb(0.5) - 0.735_356_6).abs() < 1e-5);
        // The linear and power segments meet at the threshold.
        let t = 0.003_130_8f32;
        let below = 12.92 * t;
        let above = 1.055 * t.powf(1.0 / 2.4) - 0.055;
        assert!((below - above).abs() < 1e-6, "{below} vs {above}");
    }

    #[test]
    fn srgb8_clamps_and_maps_non_finite_to_black() {
        assert_eq!(linear_to_srgb8(0.0), 0);
        assert_eq!(linear_to_srgb8(-3.0), 0);
        assert_eq!(linear_to_srgb8(1.0), 255);
        assert_eq!(linear_to_srgb8(7.0), 255);
        assert_eq!(linear_to_srgb8(f32::NAN), 0);
        assert_eq!(linear_to_srgb8(f32::INFINITY), 0);
        assert_eq!(linear_to_srgb8(f32::NEG_INFINITY), 0);
        assert_eq!(linear_to_srgb8(0.5), 188);
        // Every byte value's midpoint decodes back to it.
        for b in 0..=255u8 {
            assert_eq!(linear_to_srgb8(srgb_to_linear(b as f32 / 255.0)), b);
        }
    }

    #[test]
    fn display_value_applies_exposure_and_clamps() {
        assert_eq!(display_value(0.25, 0.0), 0.25);
        assert_eq!(display_value(0.25, 1.0), 0.5);
        assert_eq!(display_value(0.25, -2.0), 0.0625);
        assert_eq!(display_value(0.3, 2.0), 1.0);
        assert_eq!(display_value(-0.5, 0.0), 0.0);
        assert_eq!(display_value(f32::NAN, 0.0), 0.0);
        assert_eq!(display_value(f32::INFINITY, 0.0), 0.0);
        // Overflow is non-finite too (as in PNG output).
        assert_eq!(display_value(f32::MAX, 1.0), 0.0);
        assert_eq!(display_value(0.0, 200.0), 0.0);
    }
}
