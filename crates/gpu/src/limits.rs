//! Buffer sizes against the device's limits, checked before allocation so that a too-large
//! scene fails with the buffer's name and the numbers rather than a wgpu validation panic.

use crate::GpuError;

/// Checks that a storage buffer of `bytes` can be created and bound whole on a device with
/// `limits`. The binding limit is usually the tighter (lavapipe: 128 MiB binding, 2 GiB
/// buffer); arrays past it must be split into several buffers.
pub fn check_buffer_fits(label: &str, bytes: u64, limits: &wgpu::Limits) -> Result<(), GpuError> {
    let checks = [
        (
            "max_storage_buffer_binding_size",
            limits.max_storage_buffer_binding_size,
        ),
        ("max_buffer_size", limits.max_buffer_size),
    ];
    match checks.into_iter().find(|&(_, limit)| bytes > limit) {
        None => Ok(()),
        Some((limit_name, limit)) => Err(GpuError::BufferTooLarge {
            label: label.to_owned(),
            size: in_mib(bytes),
            limit_name,
            limit: in_mib(limit),
        }),
    }
}

/// Halves the sky map in `lights` (if it has one) until its buffer (`render::sky_map`) fits a
/// device with `limits`, so that a map larger than the device binds renders coarser rather
/// than not at all; what was done, in words, when it had to.
pub fn fit_sky_map(lights: &mut scene::Lights, limits: &wgpu::Limits) -> Option<String> {
    let sky = lights.sky.as_ref()?;
    let original = sky.map.clone()?;
    let check = |map: &scene::SkyMap| {
        check_buffer_fits("sky_map", render::sky_map::sky_map_bytes(map), limits)
    };
    let refusal = check(&original).err()?;
    let mut map = original.halved();
    while check(&map).is_err() && (map.width() > 1 || map.height() > 1) {
        map = map.halved();
    }
    let note = format!(
        "{refusal}: the {}x{} sky map is rendered at {}x{}",
        original.width(),
        original.height(),
        map.width(),
        map.height()
    );
    let resized = sky.with_map_replaced(std::sync::Arc::new(map));
    lights.replace_sky(resized);
    Some(note)
}

/// Checks that `bytes` fit one rgba32uint texture of `row` texels a row (16 bytes a texel) on a
/// device with `limits`: its rows within `max_texture_dimension_2d`.
pub fn check_texels_fit(
    label: &str,
    bytes: u64,
    row: u32,
    limits: &wgpu::Limits,
) -> Result<(), GpuError> {
    let rows = bytes.div_ceil(16).div_ceil(u64::from(row));
    let side = u64::from(limits.max_texture_dimension_2d);
    if row as u64 <= side && rows <= side {
        return Ok(());
    }
    Err(GpuError::TexelsTooLarge {
        label: label.to_owned(),
        size: in_mib(bytes),
        rows,
        row,
        limit: limits.max_texture_dimension_2d,
    })
}

/// "1.5 MiB (1572864 bytes)": MiB to read, bytes to be exact.
fn in_mib(bytes: u64) -> String {
    format!(
        "{:.1} MiB ({bytes} bytes)",
        bytes as f64 / (1024.0 * 1024.0)
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn texels_past_the_texture_side_are_an_error_in_words() {
        let limits = wgpu::Limits {
            max_texture_dimension_2d: 8,
            ..wgpu::Limits::default()
        };
        // 8 rows of 8 texels of 16 bytes fit; one byte more needs a ninth row.
        assert!(check_texels_fit("bvh_nodes", 8 * 8 * 16, 8, &limits).is_ok());
        let message = check_texels_fit("bvh_nodes", 8 * 8 * 16 + 1, 8, &limits)
            .unwrap_err()
            .to_string();
        assert!(message.contains("bvh_nodes"), "{message}");
        assert!(message.contains("9 rows"), "{message}");
        assert!(
            message.contains("max_texture_dimension_2d = 8"),
            "{message}"
        );
        assert!(check_texels_fit("wide", 16, 16, &limits).is_err());
    }

    const MIB: u64 = 1 << 20;

    /// A 64 × 32 map (32 KiB of buffer) under an 8 KiB binding: halved twice (32 × 16 needs 8.2), to 16 × 8,
    /// its power kept within the halving's rounding, and said so; under the default limits it
    /// is left alone.
    #[test]
    fn a_sky_map_past_the_binding_is_halved_until_it_fits() {
        let texels = (0..64 * 32)
            .map(|i| glam::Vec3::new(1.0 + (i % 64) as f32 * 0.1, 1.0, 0.5))
            .collect();
        let map = std::sync::Arc::new(scene::SkyMap::new(64, 32, texels).unwrap());
        let bounds = scene::Bounds::EMPTY
            .grow(glam::Vec3::ZERO)
            .grow(glam::Vec3::ONE);
        let sky = scene::Sky::with_map(map, glam::Vec3::ONE, 0.3, bounds);
        let mut lights = scene::Lights::default();
        lights.replace_sky(sky.clone());
        assert_eq!(
            fit_sky_map(&mut lights.clone(), &wgpu::Limits::default()),
            None
        );

        let limits = wgpu::Limits {
            max_storage_buffer_binding_size: 8 * 1024,
            ..wgpu::Limits::default()
        };
        let note = fit_sky_map(&mut lights, &limits).expect("halved");
        assert!(note.contains("sky_map"), "{note}");
        assert!(note.contains("64x32 sky map is rendered at 16x8"), "{note}");
        let fitted = lights.sky.as_ref().unwrap();
        let map = fitted.map.as_ref().unwrap();
        assert_eq!((map.width(), map.height()), (16, 8));
        assert!(render::sky_map::sky_map_bytes(map) <= 8 * 1024);
        let change = (fitted.power / sky.power - glam::Vec3::ONE)
            .abs()
            .max_element();
        assert!(change < 0.02, "{} -> {}", sky.power, fitted.power);
        assert_eq!(lights.total_power, fitted.power);
        assert_eq!(fitted.rotation, sky.rotation);
    }

    fn lowered() -> wgpu::Limits {
        wgpu::Limits {
            max_storage_buffer_binding_size: 4 * MIB,
            max_buffer_size: 8 * MIB,
            ..wgpu::Limits::downlevel_defaults()
        }
    }

    #[test]
    fn check_buffer_fits_accepts_up_to_the_limit() {
        assert!(check_buffer_fits("photons", 0, &lowered()).is_ok());
        assert!(check_buffer_fits("photons", 4 * MIB, &lowered()).is_ok());
    }

    #[test]
    fn check_buffer_fits_names_buffer_and_binding_limit() {
        let message = check_buffer_fits("photons", 4 * MIB + 1, &lowered())
            .unwrap_err()
            .to_string();
        assert!(message.contains("photons"), "{message}");
        assert!(
            message.contains("max_storage_buffer_binding_size"),
            "{message}"
        );
        assert!(message.contains("4.0 MiB"), "{message}");
        assert!(!message.contains('\n'), "{message}");
    }

    #[test]
    fn check_buffer_fits_reports_buffer_size_limit_when_it_is_tighter() {
        let limits = wgpu::Limits {
            max_buffer_size: 2 * MIB,
            ..lowered()
        };
        let message = check_buffer_fits("hit_points", 3 * MIB, &limits)
            .unwrap_err()
            .to_string();
        assert!(message.contains("hit_points"), "{message}");
        assert!(message.contains("max_buffer_size = 2.0 MiB"), "{message}");
        assert!(message.contains("3.0 MiB"), "{message}");
    }
}
