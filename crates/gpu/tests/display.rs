//! The display pass (`gpu::display`) against its CPU twin: the statistics read back and resolved
//! by `render::resolve::resolve_pixel`, tonemapped by `render::tonemap`. The shader works in
//! f32 where the CPU resolves the photon term in f64, and its sRGB power is the GPU's, so a
//! channel may land one step off where a value sits at a quantisation threshold: at most
//! 1 LSB is allowed, and few channels may use it ([`MAX_OFF_BY_ONE`]). A hardware sRGB
//! encoder may approximate more (lavapipe's is a step off in ~5% of channels), so sRGB targets
//! get their own share ([`MAX_OFF_BY_ONE_HARDWARE`]). Runs on whatever adapter wgpu finds
//! (lavapipe in CI), so sizes are small.
//!
//! - `capture_matches_the_cpu_twin_at_the_render_size`: every pixel, exposures 0, +2, −3;
//! - `murky_capture_matches_the_cpu_twin`: murky glass's volume term too;
//! - `capture_at_other_sizes_shows_the_nearest_render_pixel`: 2× (2×2 blocks) and 1.5 × 0.75;
//! - `shader_srgb_encoding_matches_the_hardware_encoding`: sRGB targets (linear output, the
//!   hardware encodes) vs the shader's encoding, and BGRA vs RGBA;
//! - `draw_fills_the_viewport_and_follows_a_restarted_render`: the viewer's path, a caller's
//!   render pass with a viewport, then a restarted render (new buffers, a rebuilt bind group).

use bvh::{BuildOptions, PackedBvh};
use gpu::GpuContext;
use gpu::display::{DisplayPass, DisplaySource};
use gpu::sppm::GpuBackend;
use render::buffers::PixelStats;
use render::resolve::{Parts, resolve_parts};
use render::tonemap::{Look, ToneMap};
use render::{Backend, Settings, Setup, Sppm};
use scene::{Camera, Scene};

const WIDTH: u32 = 32;
const HEIGHT: u32 = 24;
const PASSES: u32 = 6;
/// Share of channels allowed one step off the CPU twin when the shader encodes.
const MAX_OFF_BY_ONE: f64 = 0.02;
/// The same through a hardware sRGB encoder.
const MAX_OFF_BY_ONE_HARDWARE: f64 = 0.15;
/// Share of pixels that must show something at exposure ≥ 0. The box's open front does not
/// fill the camera's view: about 73% of the pixels see the box, the rest see nothing.
const MIN_LIT: f64 = 0.6;

fn context() -> GpuContext {
    GpuContext::new(None).unwrap_or_else(|e| {
        panic!("no usable GPU adapter in the test environment (CI installs Mesa lavapipe): {e}")
    })
}

fn settings(width: u32, height: u32) -> Settings {
    Settings {
        // An eye pass every other pass: E = 3 after six passes, so direct / E is exercised.
        eye_every: 2,
        seed: 7,
        ..Settings::new(width, height, 4096)
    }
}

/// A GPU render after [`PASSES`] passes: of the Cornell caustics scene ([`Render::new`]; its
/// light is seen directly and through the mirror sphere, so both terms of the resolve are
/// non-zero somewhere), or of another ([`Render::of`]).
struct Render {
    scene: Scene,
    camera: Camera,
    sppm: Sppm<GpuBackend>,
    source: DisplaySource,
}

impl Render {
    fn new() -> Render {
        Render::of(scene::testing::cornell_caustics())
    }

    fn of(scene: Scene) -> Render {
        let camera = scene.camera(None).expect("the test scene has a camera");
        let bvh = PackedBvh::build(&scene.triangles, &BuildOptions::default());
        let backend = GpuBackend::new(context(), &scene, bvh).expect("gpu backend");
        assert!(
            backend.display_source().is_none(),
            "a display source before the render started"
        );
        let mut sppm =
            Sppm::new(backend, &scene, &camera, settings(WIDTH, HEIGHT)).expect("gpu render");
        for _ in 0..PASSES {
            sppm.pass();
        }
        let source = sppm.backend().display_source().expect("started");
        assert_eq!((source.width, source.height), (WIDTH, HEIGHT));
        Render {
            scene,
            camera,
            sppm,
            source,
        }
    }

    fn context(&mut self) -> &GpuContext {
        self.sppm.backend().context()
    }

    fn display(&mut self, format: wgpu::TextureFormat) -> DisplayPass {
        DisplayPass::new(&self.context().device, format)
    }

    /// [`DisplayPass::capture`], or [`DisplayPass::capture_as`] `format`.
    fn capture(
        &mut self,
        display: &mut DisplayPass,
        exposure: f32,
        size: (u32, u32),
        format: Option<wgpu::TextureFormat>,
    ) -> Vec<u8> {
        let eye_passes = self.sppm.eye_passes();
        let source = self.source.clone();
        let context = self.context();
        let bytes = match format {
            None => display.capture(context, &source, eye_passes, exposure, size),
            Some(format) => {
                display.capture_as(context, &source, eye_passes, exposure, size, format)
            }
        }
        .expect("capture");
        assert_eq!(bytes.len(), size.0 as usize * size.1 as usize * 4);
        bytes
    }

    /// The CPU twin at the render size: RGBA8, top row first.
    fn cpu_twin(&mut self, look: Look) -> Vec<u8> {
        self.cpu_twin_of(look, |_| {})
    }

    /// [`Render::cpu_twin`] of the statistics as `change` leaves them.
    fn cpu_twin_of(&mut self, look: Look, change: impl Fn(&mut PixelStats)) -> Vec<u8> {
        self.cpu_twin_showing(look, Parts::ALL, change)
    }

    /// [`Render::cpu_twin_of`] showing the parts of the radiance `parts` selects.
    fn cpu_twin_showing(
        &mut self,
        look: Look,
        parts: Parts,
        change: impl Fn(&mut PixelStats),
    ) -> Vec<u8> {
        let eye_passes = self.sppm.eye_passes();
        assert_eq!(eye_passes, PASSES / 2);
        let mut stats = self.sppm.backend().read_statistics().expect("statistics");
        assert!(stats.emitted_paths > 0);
        stats.pixels.iter_mut().for_each(&change);
        stats
            .pixels
            .iter()
            .flat_map(|s| {
                let l = resolve_parts(s, eye_passes, stats.emitted_paths, parts);
                let [r, g, b] = look.srgb8(l);
                [r, g, b, 255]
            })
            .collect()
    }
}

/// Per channel |a − b| ≤ 1 everywhere; returns the share of channels that differ at all.
fn assert_within_one_step(gpu: &[u8], cpu: &[u8], what: &str) -> f64 {
    assert_eq!(gpu.len(), cpu.len(), "{what}: lengths");
    let mut differing = 0;
    for (i, (g, c)) in gpu.iter().zip(cpu).enumerate() {
        let step = g.abs_diff(*c);
        assert!(
            step <= 1,
            "{what}: pixel {} channel {}: gpu {g} vs cpu {c}",
            i / 4,
            i % 4
        );
        differing += usize::from(step > 0);
    }
    differing as f64 / gpu.len() as f64
}

/// Share of pixels (RGBA8) with a non-zero colour channel.
fn lit_share(rgba: &[u8]) -> f64 {
    let pixels = rgba.len() / 4;
    let lit = rgba
        .chunks_exact(4)
        .filter(|p| p[..3].iter().any(|&c| c > 0))
        .count();
    lit as f64 / pixels as f64
}

/// Share of pixels with a saturated (255) channel.
fn clamped_share(rgba: &[u8]) -> f64 {
    let clamped = rgba
        .chunks_exact(4)
        .filter(|p| p[..3].contains(&255))
        .count();
    clamped as f64 / (rgba.len() / 4) as f64
}

#[test]
fn capture_matches_the_cpu_twin_at_the_render_size() {
    let mut render = Render::new();
    // A window's usual format; the capture renders to its own texture.
    let mut display = render.display(wgpu::TextureFormat::Bgra8UnormSrgb);
    for exposure in [0.0, 2.0, -3.0] {
        let gpu = render.capture(&mut display, exposure, (WIDTH, HEIGHT), None);
        let cpu = render.cpu_twin(Look::exposure(exposure));
        let off = assert_within_one_step(&gpu, &cpu, &format!("exposure {exposure}"));
        let (lit, clamped) = (lit_share(&cpu), clamped_share(&cpu));
        eprintln!(
            "exposure {exposure:+}: {:.2}% of channels one step off; {:.1}% of pixels lit, \
             {:.1}% clamped",
            100.0 * off,
            100.0 * lit,
            100.0 * clamped
        );
        assert!(gpu.chunks_exact(4).all(|p| p[3] == 255), "alpha");
        if exposure >= 0.0 {
            assert!(
                lit > MIN_LIT,
                "exposure {exposure}: only {lit} of the pixels lit"
            );
        }
        if exposure == 2.0 {
            assert!(clamped > 0.02, "+2 stops clamps nothing: {clamped}");
        }
        // Rounding flips few channels: a systematic error would flip many.
        assert!(
            off <= MAX_OFF_BY_ONE,
            "exposure {exposure}: {off} of the channels one step off"
        );
    }
}

/// The same in the murky Cornell box (`scene::testing::cornell_murky`): the pixels seeing the
/// quartz ball or the water resolve the volume photons' τ over the sphere's 4/3 π R³ too,
/// which moves their colour by more than a step (checked: the twin without it differs).
#[test]
fn murky_capture_matches_the_cpu_twin() {
    let mut render = Render::of(scene::testing::cornell_murky());
    let mut display = render.display(wgpu::TextureFormat::Bgra8UnormSrgb);
    for exposure in [0.0, 2.0] {
        let gpu = render.capture(&mut display, exposure, (WIDTH, HEIGHT), None);
        let cpu = render.cpu_twin(Look::exposure(exposure));
        let off = assert_within_one_step(&gpu, &cpu, &format!("murky, exposure {exposure}"));
        assert!(off <= MAX_OFF_BY_ONE, "{off} of the channels one step off");
        let without = render.cpu_twin_of(Look::exposure(exposure), |s| s.volume_tau = [0.0; 3]);
        let moved = (cpu.iter().zip(&without)).filter(|(a, b)| a.abs_diff(**b) > 1);
        assert!(
            moved.count() > 20,
            "exposure {exposure}: the volume term shows nowhere"
        );
    }
}

/// Each part of the radiance alone (`DisplayPass::set_parts`), and the direct light with the
/// caustics, against the CPU twin's `render::resolve::resolve_parts`, in the murky box so
/// that every part shows somewhere: each selection lights pixels, and differs from the whole
/// image where it leaves parts out.
#[test]
fn captures_of_parts_match_the_cpu_twin() {
    let mut render = Render::of(scene::testing::cornell_murky());
    let mut display = render.display(wgpu::TextureFormat::Bgra8UnormSrgb);
    let exposure = 2.0;
    let whole = render.cpu_twin(Look::exposure(exposure));
    let none = (0..4).fold(Parts::ALL, |parts, k| parts.with(k, false));
    let selections = (0..4)
        .map(|k| none.with(k, true))
        .chain([none.with(0, true).with(2, true)]);
    for parts in selections {
        display.set_parts(parts);
        let gpu = render.capture(&mut display, exposure, (WIDTH, HEIGHT), None);
        let cpu = render.cpu_twin_showing(Look::exposure(exposure), parts, |_| {});
        let what = format!("parts {}", parts.name());
        let off = assert_within_one_step(&gpu, &cpu, &what);
        assert!(
            off <= MAX_OFF_BY_ONE,
            "{what}: {off} of the channels one step off"
        );
        let lit = lit_share(&cpu);
        let moved = (cpu.iter().zip(&whole))
            .filter(|(a, b)| a.abs_diff(**b) > 1)
            .count();
        eprintln!(
            "{what}: {:.1} % lit, {moved} channels off the whole image",
            100.0 * lit
        );
        // The direct part alone is the lamp's few pixels: photons carry the rest here.
        assert!(lit > 0.005, "{what}: only {lit} of the pixels lit");
        assert!(moved > 20, "{what}: no different from the whole image");
    }
}

/// Under PBR Neutral (`DisplayPass::set_tone_map`) the capture is the CPU twin's
/// `Look::display_rgb` within one 8-bit step, and most of what the clamp burns to white stays
/// below it (at +2 stops 0.65 % of pixels reach 255 against the clamp's 5.5 %: the lamp).
#[test]
fn neutral_capture_matches_the_cpu_twin() {
    let mut render = Render::new();
    let mut display = render.display(wgpu::TextureFormat::Bgra8UnormSrgb);
    display.set_tone_map(ToneMap::Neutral);
    for exposure in [0.0, 2.0] {
        let look = Look {
            exposure,
            tone_map: ToneMap::Neutral,
        };
        let gpu = render.capture(&mut display, exposure, (WIDTH, HEIGHT), None);
        let cpu = render.cpu_twin(look);
        let off = assert_within_one_step(&gpu, &cpu, &format!("neutral, exposure {exposure}"));
        assert!(off <= MAX_OFF_BY_ONE, "{off} of the channels one step off");
        assert!(lit_share(&cpu) > MIN_LIT);
        let clamped = render.cpu_twin(Look::exposure(exposure));
        let (white, clamped_white) = (clamped_share(&cpu), clamped_share(&clamped));
        assert!(
            white <= 0.5 * clamped_white,
            "exposure {exposure}: {white} of the pixels white, clamped {clamped_white}"
        );
    }
}

/// The render pixel under a viewport pixel's centre, as the shader picks it.
fn nearest(target_pixel: u32, target_size: u32, render_size: u32) -> u32 {
    ((2 * target_pixel + 1) * render_size / (2 * target_size)).min(render_size - 1)
}

#[test]
fn capture_at_other_sizes_shows_the_nearest_render_pixel() {
    let mut render = Render::new();
    let mut display = render.display(wgpu::TextureFormat::Rgba8UnormSrgb);
    let exposure = 1.0;
    let base = render.capture(&mut display, exposure, (WIDTH, HEIGHT), None);
    assert!(lit_share(&base) > MIN_LIT, "black image");
    let pixel = |x: u32, y: u32| {
        let at = 4 * (y * WIDTH + x) as usize;
        &base[at..at + 4]
    };
    // 2×: every 2×2 block is one render pixel.
    let (w, h) = (2 * WIDTH, 2 * HEIGHT);
    let double = render.capture(&mut display, exposure, (w, h), None);
    for y in 0..h {
        for x in 0..w {
            let at = 4 * (y * w + x) as usize;
            assert_eq!(&double[at..at + 4], pixel(x / 2, y / 2), "2x at ({x}, {y})");
        }
    }
    // Neither a multiple nor the same aspect: 48 × 18 (1.5 wide, 0.75 high).
    let (w, h) = (WIDTH * 3 / 2, HEIGHT * 3 / 4);
    let odd = render.capture(&mut display, exposure, (w, h), None);
    for y in 0..h {
        for x in 0..w {
            let at = 4 * (y * w + x) as usize;
            let (sx, sy) = (nearest(x, w, WIDTH), nearest(y, h, HEIGHT));
            assert_eq!(
                &odd[at..at + 4],
                pixel(sx, sy),
                "{w}x{h} at ({x}, {y}) from ({sx}, {sy})"
            );
        }
    }
}

#[test]
fn shader_srgb_encoding_matches_the_hardware_encoding() {
    use wgpu::TextureFormat::{Bgra8Unorm, Bgra8UnormSrgb, Rgba8Unorm, Rgba8UnormSrgb};
    let mut render = Render::new();
    // One pass for all formats: the pipelines for the others are made on first use.
    let mut display = render.display(Rgba8UnormSrgb);
    let size = (WIDTH, HEIGHT);
    for exposure in [0.0, 2.0] {
        // `capture` is Rgba8Unorm: the shader encodes.
        let shader = render.capture(&mut display, exposure, size, None);
        let cpu = render.cpu_twin(Look::exposure(exposure));
        assert_eq!(
            render.capture(&mut display, exposure, size, Some(Rgba8Unorm)),
            shader
        );
        assert_eq!(
            render.capture(&mut display, exposure, size, Some(Bgra8Unorm)),
            shader,
            "BGRA is returned as RGBA"
        );
        for format in [Rgba8UnormSrgb, Bgra8UnormSrgb] {
            // Linear output, encoded by the hardware.
            let hardware = render.capture(&mut display, exposure, size, Some(format));
            let what = format!("{format:?} vs the shader's encoding, exposure {exposure}");
            let off = assert_within_one_step(&hardware, &shader, &what);
            eprintln!("{what}: {:.2}% of channels one step off", 100.0 * off);
            assert!(off <= MAX_OFF_BY_ONE_HARDWARE, "{what}: {off}");
            let off = assert_within_one_step(&hardware, &cpu, &format!("{format:?} vs cpu"));
            assert!(off <= MAX_OFF_BY_ONE_HARDWARE, "{format:?} vs cpu: {off}");
        }
    }
    let source = render.source.clone();
    let error = display
        .capture_as(
            render.context(),
            &source,
            1,
            0.0,
            (4, 4),
            wgpu::TextureFormat::Rgba16Float,
        )
        .expect_err("a capture format that is not 8-bit RGBA");
    assert!(error.to_string().contains("Rgba16Float"), "{error}");
}

/// `texture` (RGBA8 or BGRA8, COPY_SRC) read back as tightly packed RGBA rows.
fn read_texture(context: &GpuContext, texture: &wgpu::Texture) -> Vec<u8> {
    let (width, height) = (texture.width(), texture.height());
    let padded = (4 * width).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
    let staging = context.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("test readback"),
        size: (padded * height) as u64,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut encoder = context
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
    encoder.copy_texture_to_buffer(
        texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &staging,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded),
                rows_per_image: None,
            },
        },
        texture.size(),
    );
    context.queue.submit([encoder.finish()]);
    staging.map_async(wgpu::MapMode::Read, .., |result| result.expect("map"));
    context
        .device
        .poll(wgpu::PollType::wait_indefinitely())
        .expect("poll");
    let mapped = staging.get_mapped_range(..).expect("mapped");
    let mut bytes: Vec<u8> = mapped
        .chunks_exact(padded as usize)
        .flat_map(|row| &row[..4 * width as usize])
        .copied()
        .collect();
    if texture.format().remove_srgb_suffix() == wgpu::TextureFormat::Bgra8Unorm {
        bytes.chunks_exact_mut(4).for_each(|p| p.swap(0, 2));
    }
    bytes
}

/// Clears an 80×40 texture of the display's format to blue and draws the display into the viewport
/// (16, 8) + 48×24, as the viewer does in its own pass; returns the texture's bytes.
fn draw_into_viewport(
    context: &GpuContext,
    display: &mut DisplayPass,
    source: &DisplaySource,
    eye_passes: u32,
) -> Vec<u8> {
    let device = &context.device;
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("test target"),
        size: wgpu::Extent3d {
            width: 80,
            height: 40,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: display.format(),
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    });
    let view = texture.create_view(&wgpu::TextureViewDescriptor::default());
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
    {
        let pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("test pass"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::BLUE),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        // As egui-wgpu hands its pass to paint callbacks.
        let mut pass: wgpu::RenderPass<'static> = pass.forget_lifetime();
        pass.set_viewport(16.0, 8.0, 48.0, 24.0, 0.0, 1.0);
        display.draw(
            device,
            &context.queue,
            &mut pass,
            source,
            eye_passes,
            0.0,
            (48, 24),
        );
    }
    context.queue.submit([encoder.finish()]);
    read_texture(context, &texture)
}

/// (inside the viewport, outside it) of an 80×40 frame from [`draw_into_viewport`].
fn split_viewport(frame: &[u8]) -> (Vec<u8>, Vec<[u8; 4]>) {
    let (mut inside, mut outside) = (Vec::new(), Vec::new());
    for (i, p) in frame.chunks_exact(4).enumerate() {
        let (x, y) = (i % 80, i / 80);
        if (16..64).contains(&x) && (8..32).contains(&y) {
            inside.extend_from_slice(p);
        } else {
            outside.push([p[0], p[1], p[2], p[3]]);
        }
    }
    (inside, outside)
}

#[test]
fn draw_fills_the_viewport_and_follows_a_restarted_render() {
    let mut render = Render::new();
    let eye_passes = render.sppm.eye_passes();
    let source = render.source.clone();
    // A window surface that is not sRGB (the shader encodes) and one that is (the hardware
    // encodes; see MAX_OFF_BY_ONE_HARDWARE).
    for (format, max_off) in [
        (wgpu::TextureFormat::Rgba8Unorm, MAX_OFF_BY_ONE),
        (wgpu::TextureFormat::Bgra8UnormSrgb, MAX_OFF_BY_ONE_HARDWARE),
    ] {
        let mut display = render.display(format);
        let expected = render.capture(&mut display, 0.0, (48, 24), None);
        for frame in 0..2 {
            // The second frame reuses the cached bind group.
            let bytes = draw_into_viewport(render.context(), &mut display, &source, eye_passes);
            let (inside, outside) = split_viewport(&bytes);
            let what = format!("{format:?}, frame {frame}");
            assert!(outside.iter().all(|p| *p == [0, 0, 255, 255]), "{what}");
            let off = assert_within_one_step(&inside, &expected, &what);
            assert!(off <= max_off, "{what}: {off} of the channels one step off");
            assert!(lit_share(&inside) > MIN_LIT, "{what}: black");
        }
    }

    // A restarted render, smaller, with no passes yet: new buffers of initial statistics,
    // which resolve to black. A stale bind group would still show the old image.
    let mut display = render.display(wgpu::TextureFormat::Rgba8Unorm);
    let bytes = draw_into_viewport(render.context(), &mut display, &source, eye_passes);
    assert!(
        lit_share(&split_viewport(&bytes).0) > MIN_LIT,
        "black before the restart"
    );
    let restarted = settings(16, 12);
    let lights = render::emission::light_table(&render.scene);
    let setup = Setup {
        params: render::integrator::params(
            &render.scene,
            &render.camera,
            &restarted,
            lights.len() as u32,
        ),
        lights,
        initial_radius: render::integrator::initial_radius(&render.scene, 16, 12),
        initial_caustic_radius: render::integrator::initial_radius(&render.scene, 16, 12),
        initial_volume_radius: render::integrator::initial_radius(&render.scene, 16, 12),
        density: render::Density::default(),
        precision: Default::default(),
    };
    render.sppm.backend().start(&setup).expect("restart");
    let fresh = render.sppm.backend().display_source().expect("restarted");
    assert_eq!((fresh.width, fresh.height), (16, 12));
    assert!(
        fresh.pixels != source.pixels,
        "a restart allocates new buffers"
    );
    let bytes = draw_into_viewport(render.context(), &mut display, &fresh, 0);
    let (inside, outside) = split_viewport(&bytes);
    assert!(outside.iter().all(|p| *p == [0, 0, 255, 255]));
    assert!(
        inside.chunks_exact(4).all(|p| p == [0, 0, 0, 255]),
        "the restarted render is not black: the old buffers are still bound"
    );
}
