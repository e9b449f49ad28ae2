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
