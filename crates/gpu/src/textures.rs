//! The scene's textures on the device: a [`TextureArray`] as one `texture_2d_array<f32>` of
//! RGBA8 (bind group 2 of the SPPM kernels, read with `textureLoad` in `textures.wgsl`).
//!
//! The format is `Rgba8Unorm`, not `Rgba8UnormSrgb`: `textures.wgsl` decodes sRGB itself with
//! the formula of `scene::textures::srgb_to_linear`, so the CPU backend's
//! [`TextureArray::sample`] and the GPU agree whatever the hardware's decoding tables hold.

use render::textures::{DEFAULT_MAX_SIDE, TextureArray};

use crate::{GpuContext, GpuError};

/// The texel format of the array (sRGB is decoded in the shader).
pub const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

/// The common side the GPU backend asks [`TextureArray::build`] for on a device with `limits`.
pub fn max_side(limits: &wgpu::Limits) -> u32 {
    limits.max_texture_dimension_2d.min(DEFAULT_MAX_SIDE)
}

/// The texture array uploaded, its view and its size.
pub struct GpuTextures {
    pub texture: wgpu::Texture,
    pub view: wgpu::TextureView,
    pub side: u32,
    pub layers: u32,
    pub bytes: u64,
}

/// Checks that an array of `layers` layers of `side`² texels fits the device, failing in words.
pub fn check_texture_array_fits(
    side: u32,
    layers: u32,
    limits: &wgpu::Limits,
) -> Result<(), GpuError> {
    if side > limits.max_texture_dimension_2d {
        return Err(GpuError::TexturesTooLarge {
            needed: format!("{side}×{side} texels a layer"),
            limit_name: "max_texture_dimension_2d",
            limit: limits.max_texture_dimension_2d,
        });
    }
    if layers > limits.max_texture_array_layers {
        return Err(GpuError::TexturesTooLarge {
            needed: format!("{layers} array layers (one per texture)"),
            limit_name: "max_texture_array_layers",
            limit: limits.max_texture_array_layers,
        });
    }
    Ok(())
}

/// The bind group layout entry of the array: a non-filtered float texture, 2D array.
pub fn layout_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable: false },
            view_dimension: wgpu::TextureViewDimension::D2Array,
            multisampled: false,
        },
        count: None,
    }
}

impl GpuTextures {
    /// Uploads `array` after checking it against the device's limits.
    pub fn upload(context: &GpuContext, array: &TextureArray) -> Result<GpuTextures, GpuError> {
        let (side, layers) = (array.side, array.layers);
        check_texture_array_fits(side, layers, &context.limits)?;
        let texture = context.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("scene_textures"),
            size: wgpu::Extent3d {
                width: side,
                height: side,
                depth_or_array_layers: layers,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: FORMAT,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        });
        // One layer per write keeps the queue's staging copy to a layer's size.
        for layer in 0..layers {
            context.queue.write_texture(
                wgpu::TexelCopyTextureInfo {
                    texture: &texture,
                    mip_level: 0,
                    origin: wgpu::Origin3d {
                        x: 0,
                        y: 0,
                        z: layer,
                    },
                    aspect: wgpu::TextureAspect::All,
                },
                bytemuck::cast_slice(array.layer(layer)),
                wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(4 * side),
                    rows_per_image: Some(side),
                },
                wgpu::Extent3d {
                    width: side,
                    height: side,
                    depth_or_array_layers: 1,
                },
            );
        }
        // An array view even with one layer (a plain 2D view would not match the binding).
        let view = texture.create_view(&wgpu::TextureViewDescriptor {
            label: Some("scene_textures"),
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            array_layer_count: Some(layers),
            ..Default::default()
        });
        Ok(GpuTextures {
            texture,
            view,
            side,
            layers,
            bytes: array.bytes(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lowered() -> wgpu::Limits {
        wgpu::Limits {
            max_texture_dimension_2d: 1024,
            max_texture_array_layers: 16,
            ..wgpu::Limits::downlevel_defaults()
        }
    }

    #[test]
    fn texture_array_fits_up_to_the_limits() {
        assert!(check_texture_array_fits(1024, 16, &lowered()).is_ok());
        assert!(check_texture_array_fits(1, 1, &lowered()).is_ok());
    }

    #[test]
    fn texture_array_too_many_layers_names_the_limit() {
        let message = check_texture_array_fits(512, 17, &lowered())
            .unwrap_err()
            .to_string();
        assert!(message.contains("17 array layers"), "{message}");
        assert!(
            message.contains("max_texture_array_layers = 16"),
            "{message}"
        );
        assert!(!message.contains('\n'), "{message}");
    }

    #[test]
    fn texture_array_too_wide_names_the_limit() {
        let message = check_texture_array_fits(2048, 1, &lowered())
            .unwrap_err()
            .to_string();
        assert!(message.contains("2048×2048"), "{message}");
        assert!(
            message.contains("max_texture_dimension_2d = 1024"),
            "{message}"
        );
    }

    #[test]
    fn max_side_is_the_smaller_of_device_and_default() {
        assert_eq!(max_side(&lowered()), 1024);
        let big = wgpu::Limits {
            max_texture_dimension_2d: 16_384,
            ..lowered()
        };
        assert_eq!(max_side(&big), DEFAULT_MAX_SIDE);
    }
}
