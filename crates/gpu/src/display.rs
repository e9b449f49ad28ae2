//! The progressive image on screen, straight from the SPPM statistics on the device: a
//! full-screen triangle whose fragment shader (`shaders/kernels/display.wgsl`) resolves each
//! pixel like `render::resolve::resolve_pixel`, applies the exposure and tone map of
//! `render::tonemap::Look` ([`DisplayPass::set_tone_map`]: the clamp, or PBR Neutral), showing
//! the parts of the radiance [`DisplayPass::set_parts`] selects (`render::resolve::Parts`), and,
//! where the target format is not sRGB, the transfer of
//! `render::tonemap::linear_to_srgb`. Nothing is read back to the host.
//!
//! [`DisplayPass::draw`] records into a render pass the caller owns (the viewer draws egui
//! after it in the same pass); [`DisplayPass::prepare`] and [`DisplayPass::record`] are its two
//! halves, for an egui-wgpu paint callback. [`DisplayPass::capture`] renders into an offscreen
//! texture and reads it back as RGBA8 bytes (screenshots, tests).
//!
//! In a viewer's frame, with egui drawn after the image in the same pass:
//!
//! ```ignore
//! let source = sppm.backend().display_source().expect("started"); // after every start
//! let mut pass = encoder.begin_render_pass(&descriptor).forget_lifetime();
//! display.draw(&device, &queue, &mut pass, &source, sppm.eye_passes(), exposure, (w, h));
//! egui_renderer.render(&mut pass, &paint_jobs, &screen_descriptor);
//! ```
//!
//! `eye_passes` must count the eye passes of the work submitted: read it between
//! `Sppm::pass` calls (the GPU backend submits a pass as a whole). Storage buffers are read in
//! the fragment stage (two, read-only; WebGPU guarantees eight per stage).

use render::resolve::Parts;
use render::tonemap::{Look, ToneMap};
use std::borrow::Cow;

use bytemuck::{Pod, Zeroable};
use wgpu::util::DeviceExt;

use crate::readback::map_staging;
use crate::shader::Module;
use crate::{GpuContext, GpuError};

/// The display shader's uniform (48 bytes), mirrored by `DisplayParams` in `display.wgsl`
/// (`tests/layout.rs` checks the offsets).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct DisplayParams {
    pub render_width: u32,
    pub render_height: u32,
    /// The size in pixels of the viewport the image fills.
    pub target_width: u32,
    pub target_height: u32,
    /// Eye passes so far (the `E` of `direct / E`).
    pub eye_passes: u32,
    /// Stops: radiance is multiplied by 2^exposure.
    pub exposure: f32,
    /// 1: the shader applies the sRGB transfer (the target format is not sRGB); 0: it writes
    /// linear values and the hardware encodes.
    pub encode_srgb: u32,
    /// `render::tonemap::ToneMap::code`: 0 the clamp, 1 PBR Neutral.
    pub tone_map: u32,
    /// `render::resolve::Parts::bits`: the parts of the radiance shown.
    pub parts: u32,
    pub pad0: u32,
    pub pad1: u32,
    pub pad2: u32,
}

/// What the display reads: the backend's statistics and counters buffers (see
/// `GpuBackend::display_source`) and the render's size. The buffers are clones of the backend's
/// handles (wgpu buffers are reference-counted), so a source has no lifetime: it can be kept
/// across frames or moved into a `'static` paint callback. A restarted render allocates new
/// buffers, so take a fresh source after every `start`.
#[derive(Clone, Debug)]
pub struct DisplaySource {
    /// `array<PixelStats>`, `width × height` of them, row-major, top row first.
    pub pixels: wgpu::Buffer,
    /// Their volume photons' τ (`array<vec4<f32>>`): one a pixel where the scene has murky
    /// glass, else one zero element. Allocated with `pixels`.
    pub volume_tau: wgpu::Buffer,
    /// The counters (`render::buffers::counter`); the emitted-path total is read from them.
    pub counters: wgpu::Buffer,
    pub width: u32,
    pub height: u32,
}

/// The bind group over one source's buffers (rebuilt when the buffers change).
struct Bound {
    pixels: wgpu::Buffer,
    counters: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
}

/// The display pipeline for one target format, its uniform buffer and the cached bind group.
pub struct DisplayPass {
    format: wgpu::TextureFormat,
    layout: wgpu::BindGroupLayout,
    pipeline_layout: wgpu::PipelineLayout,
    module: wgpu::ShaderModule,
    /// One pipeline per colour format, the target's first. [`DisplayPass::capture_as`] may
    /// render to another format than the window's, and a pipeline is bound to one format, so
    /// the others are made on first use and kept (there are at most a few).
    pipelines: Vec<(wgpu::TextureFormat, wgpu::RenderPipeline)>,
    /// The uniform of [`DisplayPass::draw`] (captures use their own, see `capture_as`).
    params: wgpu::Buffer,
    bound: Option<Bound>,
    /// Whether the last `prepare` left something to draw.
    ready: bool,
    /// How draws and captures map exposed radiance to [0, 1] ([`DisplayPass::set_tone_map`]).
    tone_map: ToneMap,
    /// The parts of the radiance draws and captures show ([`DisplayPass::set_parts`]).
    parts: Parts,
}

/// The formats [`DisplayPass::capture_as`] reads back: four 8-bit channels.
const CAPTURE_FORMATS: [wgpu::TextureFormat; 4] = [
    wgpu::TextureFormat::Rgba8Unorm,
    wgpu::TextureFormat::Rgba8UnormSrgb,
    wgpu::TextureFormat::Bgra8Unorm,
    wgpu::TextureFormat::Bgra8UnormSrgb,
];

fn layout_entry(binding: u32, ty: wgpu::BufferBindingType) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Buffer {
            ty,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

fn create_pipeline(
    device: &wgpu::Device,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
    format: wgpu::TextureFormat,
) -> wgpu::RenderPipeline {
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("display"),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some("display_vertex"),
            compilation_options: Default::default(),
            buffers: &[],
        },
        primitive: wgpu::PrimitiveState::default(),
        depth_stencil: None,
        multisample: wgpu::MultisampleState::default(),
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some("display_fragment"),
            compilation_options: Default::default(),
            targets: &[Some(wgpu::ColorTargetState {
                format,
                blend: None,
                write_mask: wgpu::ColorWrites::ALL,
            })],
        }),
        multiview_mask: None,
        cache: None,
    })
}

/// The uniform's value for drawing the `parts` of `source` into a `target_size` viewport of
/// `format`.
fn params_for(
    source: &DisplaySource,
    eye_passes: u32,
    (look, parts): (Look, Parts),
    target_size: (u32, u32),
    format: wgpu::TextureFormat,
) -> DisplayParams {
    DisplayParams {
        render_width: source.width,
        render_height: source.height,
        target_width: target_size.0,
        target_height: target_size.1,
        eye_passes,
        exposure: look.exposure,
        encode_srgb: u32::from(!format.is_srgb()),
        tone_map: look.tone_map.code(),
        parts: parts.bits(),
        ..DisplayParams::default()
    }
}

/// Whether there is anything to draw: a non-empty render into a non-empty viewport.
fn drawable(source: &DisplaySource, target_size: (u32, u32)) -> bool {
    source.width > 0 && source.height > 0 && target_size.0 > 0 && target_size.1 > 0
}

impl DisplayPass {
    /// The pipeline for a single-sampled colour target of `target_format` with no depth
    /// attachment (the window surface's format; sRGB or not, either works).
    pub fn new(device: &wgpu::Device, target_format: wgpu::TextureFormat) -> DisplayPass {
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("display"),
            entries: &[
                layout_entry(0, wgpu::BufferBindingType::Uniform),
                layout_entry(1, wgpu::BufferBindingType::Storage { read_only: true }),
                layout_entry(2, wgpu::BufferBindingType::Storage { read_only: true }),
                layout_entry(3, wgpu::BufferBindingType::Storage { read_only: true }),
            ],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("display"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(Module::Display.label()),
            source: wgpu::ShaderSource::Wgsl(Cow::Owned(Module::Display.source())),
        });
        let pipeline = create_pipeline(device, &pipeline_layout, &module, target_format);
        let params = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("display params"),
            size: size_of::<DisplayParams>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        DisplayPass {
            format: target_format,
            layout,
            pipeline_layout,
            module,
            pipelines: vec![(target_format, pipeline)],
            params,
            bound: None,
            ready: false,
            tone_map: ToneMap::Clamp,
            parts: Parts::ALL,
        }
    }

    /// The tone map of the draws and captures from now on (`render::tonemap::ToneMap`; the
    /// clamp to begin with).
    pub fn set_tone_map(&mut self, tone_map: ToneMap) {
        self.tone_map = tone_map;
    }

    /// The parts of the radiance the draws and captures show from now on
    /// (`render::resolve::Parts`; all to begin with).
    pub fn set_parts(&mut self, parts: Parts) {
        self.parts = parts;
    }

    /// The look and parts of a draw or capture at `exposure`.
    fn look(&self, exposure: f32) -> (Look, Parts) {
        let look = Look {
            exposure,
            tone_map: self.tone_map,
        };
        (look, self.parts)
    }

    /// The colour format [`DisplayPass::draw`] renders to.
    pub fn format(&self) -> wgpu::TextureFormat {
        self.format
    }

    /// The pipeline for `format`, made on first use.
    fn pipeline(&mut self, device: &wgpu::Device, format: wgpu::TextureFormat) -> usize {
        if let Some(i) = self.pipelines.iter().position(|(f, _)| *f == format) {
            return i;
        }
        let pipeline = create_pipeline(device, &self.pipeline_layout, &self.module, format);
        self.pipelines.push((format, pipeline));
        self.pipelines.len() - 1
    }

    fn bind_group(
        &self,
        device: &wgpu::Device,
        params: &wgpu::Buffer,
        source: &DisplaySource,
    ) -> wgpu::BindGroup {
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("display"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: params.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: source.pixels.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: source.counters.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: source.volume_tau.as_entire_binding(),
                },
            ],
        })
    }

    /// The first half of [`DisplayPass::draw`]: writes the uniform (through `queue`, so it
    /// takes effect at the next submission) and binds `source`'s buffers, rebuilding the bind
    /// group only when they are not the ones bound last time. `target_size` is the size in
    /// pixels of the viewport the image is to fill (the whole attachment unless the pass's
    /// viewport was set). There is one uniform, so prepare once per submitted frame.
    pub fn prepare(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        source: &DisplaySource,
        eye_passes: u32,
        exposure: f32,
        target_size: (u32, u32),
    ) {
        self.ready = drawable(source, target_size);
        if !self.ready {
            return;
        }
        let params = params_for(
            source,
            eye_passes,
            self.look(exposure),
            target_size,
            self.format,
        );
        queue.write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
        let current = self
            .bound
            .as_ref()
            .is_some_and(|b| b.pixels == source.pixels && b.counters == source.counters);
        if !current {
            self.bound = Some(Bound {
                pixels: source.pixels.clone(),
                counters: source.counters.clone(),
                bind_group: self.bind_group(device, &self.params, source),
            });
        }
    }

    /// The second half of [`DisplayPass::draw`]: records the draw of what `prepare` bound into
    /// `pass`, whose colour attachment must have the format given to [`DisplayPass::new`].
    /// Does nothing if the last `prepare` had nothing to draw.
    pub fn record(&self, pass: &mut wgpu::RenderPass<'_>) {
        let Some(bound) = self.bound.as_ref().filter(|_| self.ready) else {
            return;
        };
        pass.set_pipeline(&self.pipelines[0].1);
        pass.set_bind_group(0, &bound.bind_group, &[]);
        pass.draw(0..3, 0..1);
    }

    /// Writes the uniform and records the draw into `pass` ([`DisplayPass::prepare`], then
    /// [`DisplayPass::record`]). The draw covers the pass's viewport, of `target_size` pixels.
    #[allow(clippy::too_many_arguments)]
    pub fn draw(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        pass: &mut wgpu::RenderPass<'_>,
        source: &DisplaySource,
        eye_passes: u32,
        exposure: f32,
        target_size: (u32, u32),
    ) {
        self.prepare(device, queue, source, eye_passes, exposure, target_size);
        self.record(pass);
    }

    /// Renders the image at `size` into an offscreen texture and reads it back: tightly packed
    /// RGBA8 rows, sRGB-encoded, top row first, alpha 255; the bytes a PNG written from the
    /// statistics read back would hold. The texture is `Rgba8Unorm` and the shader encodes:
    /// its encoding is `render::tonemap::linear_to_srgb` in f32, where a hardware sRGB
    /// encoder may approximate (lavapipe's lands a step off in ~5% of channels).
    pub fn capture(
        &mut self,
        context: &GpuContext,
        source: &DisplaySource,
        eye_passes: u32,
        exposure: f32,
        size: (u32, u32),
    ) -> Result<Vec<u8>, GpuError> {
        self.capture_as(
            context,
            source,
            eye_passes,
            exposure,
            size,
            wgpu::TextureFormat::Rgba8Unorm,
        )
    }

    /// [`DisplayPass::capture`] through a texture of `format`: `Rgba8Unorm`, `Rgba8UnormSrgb`,
    /// `Bgra8Unorm` or `Bgra8UnormSrgb` (BGRA is returned as RGBA). The bytes are sRGB-encoded
    /// whichever it is: by the hardware for the sRGB formats, by the shader for the others.
    /// Captures use a uniform buffer and bind group of their own, so they never disturb what
    /// `prepare` left for the window's next frame. Waits for the device.
    pub fn capture_as(
        &mut self,
        context: &GpuContext,
        source: &DisplaySource,
        eye_passes: u32,
        exposure: f32,
        size: (u32, u32),
        format: wgpu::TextureFormat,
    ) -> Result<Vec<u8>, GpuError> {
        if !CAPTURE_FORMATS.contains(&format) {
            return Err(GpuError::Device(format!(
                "cannot capture the display as {format:?}: only RGBA8 and BGRA8 formats"
            )));
        }
        let (width, height) = size;
        let max = context.limits.max_texture_dimension_2d;
        if width > max || height > max {
            return Err(GpuError::Device(format!(
                "cannot capture the display at {width}x{height}: the device allows \
                 max_texture_dimension_2d = {max}"
            )));
        }
        if !drawable(source, size) {
            // Nothing rendered yet: opaque black.
            return Ok([0, 0, 0, 255].repeat(width as usize * height as usize));
        }
        let device = &context.device;
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let pipeline = self.pipeline(device, format);
        let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("display capture params"),
            contents: bytemuck::bytes_of(&params_for(
                source,
                eye_passes,
                self.look(exposure),
                size,
                format,
            )),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let bind_group = self.bind_group(device, &params, source);
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("display capture"),
            size: wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let view = texture.create_view(&wgpu::TextureViewDescriptor::default());
        // Rows of a texture-to-buffer copy start at multiples of 256 bytes.
        let row_bytes = width * 4;
        let padded_row_bytes = row_bytes.next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
        let staging = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("display capture readback"),
            size: padded_row_bytes as u64 * height as u64,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("display capture"),
        });
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("display capture"),
                color_attachments: &[Some(cleared_attachment(&view))],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&self.pipelines[pipeline].1);
            pass.set_bind_group(0, &bind_group, &[]);
            pass.draw(0..3, 0..1);
        }
        encoder.copy_texture_to_buffer(
            wgpu::TexelCopyTextureInfo {
                texture: &texture,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            wgpu::TexelCopyBufferInfo {
                buffer: &staging,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(padded_row_bytes),
                    rows_per_image: Some(height),
                },
            },
            wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
        );
        context.queue.submit([encoder.finish()]);
        if let Some(error) = pollster::block_on(scope.pop()) {
            return Err(GpuError::Device(format!("display capture: {error}")));
        }
        let mut bytes = map_staging(context, &staging, |mapped| {
            let mut bytes = Vec::with_capacity(row_bytes as usize * height as usize);
            for row in mapped.chunks_exact(padded_row_bytes as usize) {
                bytes.extend_from_slice(&row[..row_bytes as usize]);
            }
            bytes
        })?;
        if matches!(
            format,
            wgpu::TextureFormat::Bgra8Unorm | wgpu::TextureFormat::Bgra8UnormSrgb
        ) {
            for pixel in bytes.chunks_exact_mut(4) {
                pixel.swap(0, 2);
            }
        }
        Ok(bytes)
    }
}

/// A colour attachment cleared to black and stored: the window's frame and the captures.
pub fn cleared_attachment(view: &wgpu::TextureView) -> wgpu::RenderPassColorAttachment<'_> {
    wgpu::RenderPassColorAttachment {
        view,
        depth_slice: None,
        resolve_target: None,
        ops: wgpu::Operations {
            load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
            store: wgpu::StoreOp::Store,
        },
    }
}
