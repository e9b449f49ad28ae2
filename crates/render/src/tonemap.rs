//! From linear radiance to display values: exposure (in stops), a tone map to [0, 1] (a clamp,
//! or Khronos's PBR Neutral curve, [`ToneMap`]) and the sRGB transfer function
//! (IEC 61966-2-1). PNG output (`kousen`) and the GPU display pass (`gpu::display`, whose WGSL
//! mirrors these formulas) share these definitions.

use glam::Vec3;

/// How exposed radiance becomes a display value in [0, 1].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ToneMap {
    /// Each channel clamped: exact below 1, every brighter value white (bright caustics and
    /// lamps burn out to flat white).
    #[default]
    Clamp,
    /// Khronos's PBR Neutral curve (Khronos 3D Commerce, 2024, [`pbr_neutral`]): colours well
    /// below white kept nearly as they are (the base colours of glTF materials print true),
    /// highlights compressed towards white smoothly, so a caustic keeps its shape and hue.
    Neutral,
}

impl ToneMap {
    pub fn name(self) -> &'static str {
        match self {
            ToneMap::Clamp => "clamp",
            ToneMap::Neutral => "neutral",
        }
    }

    /// Its number in the display shader's uniform (`gpu::display::DisplayParams::tone_map`).
    pub fn code(self) -> u32 {
        match self {
            ToneMap::Clamp => 0,
            ToneMap::Neutral => 1,
        }
    }
}

/// Exposure and tone map: how a picture is made from linear radiance.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Look {
    /// Stops: radiance is multiplied by 2^exposure first.
    pub exposure: f32,
    pub tone_map: ToneMap,
}

impl Look {
    /// `exposure` stops and the clamp.
    pub fn exposure(exposure: f32) -> Look {
        Look {
            exposure,
            tone_map: ToneMap::Clamp,
        }
    }

    /// The display values in [0, 1] (before the sRGB transfer) of `linear` radiance; channels
    /// whose exposed value is not finite count as 0.
    pub fn display_rgb(&self, linear: Vec3) -> Vec3 {
        match self.tone_map {
            ToneMap::Clamp => {
                Vec3::from_array(linear.to_array().map(|c| display_value(c, self.exposure)))
            }
            ToneMap::Neutral => {
                let scale = 2f32.powf(self.exposure);
                let exposed = (linear * scale)
                    .to_array()
                    .map(|c| if c.is_finite() { c.max(0.0) } else { 0.0 });
                pbr_neutral(Vec3::from_array(exposed))
            }
        }
    }

    /// [`Look::display_rgb`] encoded as 8-bit sRGB.
    pub fn srgb8(&self, linear: Vec3) -> [u8; 3] {
        self.display_rgb(linear).to_array().map(linear_to_srgb8)
    }
}

/// Where PBR Neutral's highlight compression starts (its 0.8 less the black offset's 0.04).
const NEUTRAL_COMPRESSION_START: f32 = 0.8 - 0.04;
/// How much PBR Neutral desaturates what it compresses.
const NEUTRAL_DESATURATION: f32 = 0.15;

/// Khronos PBR Neutral (the formulas of Khronos's published specification of the tone mapper,
/// 2024) of non-negative exposed radiance `c`: a small black offset (at most 0.04, quadratic
/// near black), then the brightest channel compressed above 0.76 along a hyperbola that meets
/// 1 only at infinity, the other channels scaled with it and pulled towards grey by how much
/// was compressed. Below the compression start it only subtracts the offset.
pub fn pbr_neutral(c: Vec3) -> Vec3 {
    let darkest = c.min_element();
    let offset = if darkest < 0.08 {
        darkest - 6.25 * darkest * darkest
    } else {
        0.04
    };
    let c = c - Vec3::splat(offset);
    let peak = c.max_element();
    if peak < NEUTRAL_COMPRESSION_START {
        return c;
    }
    let d = 1.0 - NEUTRAL_COMPRESSION_START;
    let new_peak = 1.0 - d * d / (peak + d - NEUTRAL_COMPRESSION_START);
    let c = c * (new_peak / peak);
    let grey = 1.0 - 1.0 / (NEUTRAL_DESATURATION * (peak - new_peak) + 1.0);
    c.lerp(Vec3::splat(new_peak), grey)
}

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

    /// PBR Neutral leaves colours below its compression start as they are but for the small
    /// black offset, brings every brightness below white (1 only at infinity) in order, keeps
    /// hue below the start, and is continuous where the offset and the compression begin.
    #[test]
    fn pbr_neutral_keeps_darks_and_compresses_highlights() {
        let grey = |v: f32| pbr_neutral(Vec3::splat(v)).x;
        assert!((grey(0.5) - 0.46).abs() < 1e-6);
        assert_eq!(grey(0.0), 0.0);
        // Continuous at the offset's knee (0.08) and at the compression start.
        assert!((grey(0.08 - 1e-4) - grey(0.08 + 1e-4)).abs() < 1e-3);
        let start = NEUTRAL_COMPRESSION_START + 0.04;
        assert!((grey(start - 1e-4) - grey(start + 1e-4)).abs() < 1e-3);
        let mut last = -1.0;
        for i in 0..=4000 {
            let v = (i as f32 / 200.0).powi(3);
            let out = grey(v);
            // In order, to f32 rounding (1e-6 where the curve is flat near white).
            assert!(out >= last - 1e-6 && out < 1.0, "{v} -> {out} after {last}");
            last = out;
        }
        assert!(grey(1e6) > 0.999);
        // Hue below the start: a mid red keeps its channel ratios after the offset.
        let red = pbr_neutral(Vec3::new(0.6, 0.3, 0.2));
        assert!((red - Vec3::new(0.56, 0.26, 0.16)).abs().max_element() < 1e-6);
        // A bright colour stays in [0, 1] and keeps its brightest channel first.
        let bright = pbr_neutral(Vec3::new(40.0, 10.0, 2.0));
        assert!(bright.max_element() < 1.0 && bright.min_element() >= 0.0);
        assert!(bright.x > bright.y && bright.y > bright.z);
    }

    /// The clamp look is `display_value` per channel; PBR Neutral takes exposure first and
    /// counts non-finite channels as 0.
    #[test]
    fn looks_expose_then_map() {
        let clamp = Look::exposure(1.0);
        let c = Vec3::new(0.2, 0.7, f32::NAN);
        assert_eq!(clamp.display_rgb(c), Vec3::new(0.4, 1.0, 0.0));
        let neutral = Look {
            exposure: 1.0,
            tone_map: ToneMap::Neutral,
        };
        assert_eq!(
            neutral.display_rgb(Vec3::new(0.25, 0.25, f32::INFINITY)),
            pbr_neutral(Vec3::new(0.5, 0.5, 0.0))
        );
        assert_eq!(neutral.srgb8(Vec3::ZERO), [0, 0, 0]);
    }

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
