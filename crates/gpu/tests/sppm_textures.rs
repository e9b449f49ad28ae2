//! Textures on both backends: a small scene whose floor has a checker base-colour texture (with
//! uv outside [0, 1], so wrapping counts), whose back panel emits through a striped emission
//! texture, and whose hanging screen is an alpha cut-out, rendered a few passes by the CPU and
//! GPU backends. They draw the same random numbers and read the same texture array
//! (`render::textures::TextureArray`), so the images must agree closely; and the textures must
//! matter (the image differs from the same scene with its textures dropped).
//!
//! `sample_texture_matches_texture_array_sample` checks the lookup itself: `sample_texture` of
//! `textures.wgsl` run in a small kernel against `TextureArray::sample` on the same uv
//! (wrapping, edges, every byte value, a resampled non-square texture, NO_TEXTURE).

use bvh::{BuildOptions, PackedBvh};
use cpu::{CpuBackend, SceneData};
use glam::{Vec2, Vec3};
use gpu::GpuContext;
use gpu::sppm::GpuBackend;
use render::direct::DirectLight;
use render::textures::{DEFAULT_MAX_SIDE, TextureArray};
use render::{Backend, Budget, Image, Settings, Sppm};
use scene::{AlphaMode, Camera, Material, Scene, SceneBuilder, Texels, Texture, Triangle, Vertex};

const WIDTH: u32 = 48;
const HEIGHT: u32 = 36;
const PHOTONS: u32 = 4096;
const PASSES: u32 = 8;
/// Mean over pixels of |gpu − cpu| / (|gpu| + |cpu|)/2, per channel.
const MAX_MEAN_RELATIVE_DIFFERENCE: f64 = 1e-2;
/// Sampled against photon direct light under the cut-out screen, 256 passes each: measured
/// 1.018, 1.018, 1.029 (seeds 7, 1, 2), 1.012 at 2048 passes: the photons' gather blur at the
/// shadow's sharp edges and the floor's border, shrinking with the radius. Shadow rays that
/// took the screen for opaque give 0.73.
const MAX_DIRECT_LIGHT_RATIO_ERROR: f64 = 0.05;
/// The textured image must differ from the untextured one by at least this (same measure).
const MIN_TEXTURE_EFFECT: f64 = 0.1;

/// An `n`×`n` RGBA8 texture whose texel (x, y) is `texel(x, y)`.
fn texture(name: &str, n: u32, texel: impl Fn(u32, u32) -> [u8; 4]) -> Texture {
    let texels = (0..n * n).map(|i| texel(i % n, i / n)).collect();
    Texture {
        name: name.into(),
        width: n,
        height: n,
        texels: Texels::Srgb8(texels),
    }
}

/// A quad (two triangles) with corners and texture coordinates, front facing `facing`.
fn quad(builder: &mut SceneBuilder, corners: [(Vec3, Vec2); 4], material: u32, facing: Vec3) {
    let v = corners.map(|(position, uv)| Vertex {
        position,
        normal: Vec3::ZERO,
        uv,
        ..Vertex::default()
    });
    for mut vertices in [[v[0], v[1], v[2]], [v[0], v[2], v[3]]] {
        let mut triangle = Triangle { vertices, material };
        if triangle.geometric_normal_unnormalized().dot(facing) < 0.0 {
            vertices.swap(1, 2);
            triangle.vertices = vertices;
        }
        builder.add_triangle(triangle).expect("finite geometry");
    }
}

/// The test scene; `textured: false` gives the same scene with every texture dropped.
fn textured_scene(textured: bool) -> Scene {
    let mut b = SceneBuilder::new(std::path::Path::new("sppm_textures"));
    let checker = b.add_texture(texture("checker", 8, |x, y| {
        if (x + y) % 2 == 0 {
            [230, 40, 30, 255]
        } else {
            [30, 60, 220, 255]
        }
    }));
    let stripes = b.add_texture(texture("stripes", 4, |x, _| {
        let level = [255, 40, 180, 0][x as usize];
        [level, level, level, 255]
    }));
    let mask = b.add_texture(texture("mask", 4, |x, y| {
        let alpha = if (x / 2 + y / 2) % 2 == 0 { 255 } else { 0 };
        [200, 200, 200, alpha]
    }));
    let id = |t| textured.then_some(t);
    let floor = b.add_material(Material {
        name: "floor".into(),
        base_color: Vec3::splat(0.9),
        base_color_texture: id(checker),
        ..Material::default()
    });
    let panel = b.add_material(Material {
        name: "panel".into(),
        base_color: Vec3::splat(0.2),
        emission: Vec3::splat(2.0),
        emission_texture: id(stripes),
        ..Material::default()
    });
    let light = b.add_material(Material {
        name: "light".into(),
        base_color: Vec3::ZERO,
        emission: Vec3::splat(4.0),
        ..Material::default()
    });
    let screen = b.add_material(Material {
        name: "screen".into(),
        base_color: Vec3::splat(0.7),
        base_color_texture: id(mask),
        alpha_mode: AlphaMode::Mask { cutoff: 0.5 },
        ..Material::default()
    });
    let p = |x: f32, y: f32, z: f32, u: f32, v: f32| (Vec3::new(x, y, z), Vec2::new(u, v));
    // Floor at y = 0, uv from −0.5 to 1.5 (two wraps).
    quad(
        &mut b,
        [
            p(-1.0, 0.0, -1.0, -0.5, -0.5),
            p(1.0, 0.0, -1.0, 1.5, -0.5),
            p(1.0, 0.0, 1.0, 1.5, 1.5),
            p(-1.0, 0.0, 1.0, -0.5, 1.5),
        ],
        floor,
        Vec3::Y,
    );
    // Back panel at z = −1 facing +z, emitting through its stripes.
    quad(
        &mut b,
        [
            p(-1.0, 0.0, -1.0, 0.0, 1.0),
            p(1.0, 0.0, -1.0, 1.0, 1.0),
            p(1.0, 1.0, -1.0, 1.0, 0.0),
            p(-1.0, 1.0, -1.0, 0.0, 0.0),
        ],
        panel,
        Vec3::Z,
    );
    // Ceiling light at y = 1.5 facing down.
    quad(
        &mut b,
        [
            p(-0.6, 1.5, -0.6, 0.0, 0.0),
            p(0.6, 1.5, -0.6, 1.0, 0.0),
            p(0.6, 1.5, 0.6, 1.0, 1.0),
            p(-0.6, 1.5, 0.6, 0.0, 1.0),
        ],
        light,
        Vec3::NEG_Y,
    );
    // A horizontal cut-out screen at y = 0.8 over the floor's right half: a shadow pattern.
    quad(
        &mut b,
        [
            p(0.0, 0.8, -0.5, 0.0, 0.0),
            p(0.8, 0.8, -0.5, 1.0, 0.0),
            p(0.8, 0.8, 0.3, 1.0, 1.0),
            p(0.0, 0.8, 0.3, 0.0, 1.0),
        ],
        screen,
        Vec3::Y,
    );
    let eye = Vec3::new(0.0, 1.1, 2.2);
    let camera = Camera::look_at(eye, Vec3::new(0.0, 0.2, -0.3), Vec3::Y, 55f32.to_radians())
        .expect("valid camera")
        .named("front");
    b.add_camera(camera);
    b.finish().expect("a valid scene")
}

fn settings(direct: DirectLight) -> Settings {
    Settings {
        eye_every: 4,
        seed: 7,
        direct,
        ..Settings::new(WIDTH, HEIGHT, PHOTONS)
    }
}

struct Prepared {
    scene: Scene,
    bvh: PackedBvh,
    camera: Camera,
}

fn prepare(textured: bool) -> Prepared {
    let scene = textured_scene(textured);
    let bvh = PackedBvh::build(&scene.triangles, &BuildOptions::default());
    let camera = scene.camera(None).expect("the scene has a camera");
    Prepared { scene, bvh, camera }
}

fn render_cpu(p: &Prepared, direct: DirectLight) -> Image {
    let backend = CpuBackend::new(SceneData::new(&p.scene, p.bvh.clone()));
    let mut sppm = Sppm::new(backend, &p.scene, &p.camera, settings(direct)).expect("cpu render");
    sppm.run(Budget::Passes(PASSES), &mut |_| {})
        .expect("cpu passes")
        .image
}

fn render_gpu(context: GpuContext, p: &Prepared, direct: DirectLight) -> Image {
    let backend = GpuBackend::new(context, &p.scene, p.bvh.clone()).expect("gpu backend");
    let mut sppm = Sppm::new(backend, &p.scene, &p.camera, settings(direct)).expect("gpu render");
    let memory = sppm.backend().memory();
    let textures = memory
        .iter()
        .find(|(kind, _)| *kind == "textures")
        .map(|&(_, bytes)| bytes);
    // Three 8×8 layers (the common side of 8² and 4² textures) of RGBA8.
    assert_eq!(textures, Some(3 * 8 * 8 * 4), "{memory:?}");
    sppm.run(Budget::Passes(PASSES), &mut |_| {})
        .expect("gpu passes")
        .image
}

/// The default adapter, or `None` with a note saying what the test then leaves out.
fn gpu_context(skipped: &str) -> Option<GpuContext> {
    GpuContext::new(None)
        .map_err(|e| eprintln!("note: no GPU adapter ({e}); {skipped}"))
        .ok()
}

/// Mean over pixels and channels of |a − b| / mean(|a|, |b|) (0 where both are 0).
fn mean_relative_difference(a: &Image, b: &Image) -> f64 {
    assert_eq!((a.width, a.height), (b.width, b.height));
    let mut sum = 0.0;
    let mut count = 0usize;
    for (p, q) in a.pixels.iter().zip(&b.pixels) {
        for (x, y) in p.to_array().into_iter().zip(q.to_array()) {
            let scale = 0.5 * (x.abs() + y.abs()) as f64;
            if scale > 0.0 {
                sum += (x - y).abs() as f64 / scale;
            }
            count += 1;
        }
    }
    sum / count as f64
}

#[test]
fn textured_scene_matches_between_backends_and_textures_matter() {
    let textured = prepare(true);
    let cpu = render_cpu(&textured, DirectLight::Photons);
    assert!(
        cpu.pixels.iter().all(|p| p.is_finite()),
        "cpu image has non-finite pixels"
    );
    assert!(cpu.mean().max_element() > 0.0, "cpu image is black");

    let untextured = render_cpu(&prepare(false), DirectLight::Photons);
    let effect = mean_relative_difference(&cpu, &untextured);
    println!("textures change the cpu image by {effect:.3} (mean relative difference)");
    assert!(
        effect > MIN_TEXTURE_EFFECT,
        "the textures barely change the image: {effect}"
    );

    let Some(context) = gpu_context("the GPU half of this test is skipped") else {
        return;
    };
    println!("gpu: {}", context.description());
    let gpu = render_gpu(context, &textured, DirectLight::Photons);
    let difference = mean_relative_difference(&gpu, &cpu);
    println!("gpu vs cpu: mean relative difference {difference:.2e}");
    assert!(
        difference < MAX_MEAN_RELATIVE_DIFFERENCE,
        "gpu and cpu images differ: mean relative difference {difference}"
    );
    // And the GPU's textures matter as much as the CPU's.
    let gpu_effect = mean_relative_difference(&gpu, &untextured);
    assert!(
        (gpu_effect - effect).abs() < 0.5 * effect,
        "gpu texture effect {gpu_effect} vs cpu {effect}"
    );
}

/// Light sampled at the visible points: shadow rays through the cut-out screen (the scene's
/// `cut_outs` flag takes the closest-hit path, looking at each hit's alpha) on both backends.
#[test]
fn cut_out_shadows_of_sampled_light_match_between_backends() {
    let textured = prepare(true);
    let cpu = render_cpu(&textured, DirectLight::Sampled);
    assert!(cpu.mean().max_element() > 0.0, "cpu image is black");
    // The light through the screen's holes counts: long CPU renders with sampled and with
    // photon direct light agree under it (bottom right quarter, where its shadow falls).
    let long = |direct| {
        let backend = CpuBackend::new(SceneData::new(&textured.scene, textured.bvh.clone()));
        let settings = Settings {
            eye_every: 1,
            ..settings(direct)
        };
        let mut sppm = Sppm::new(backend, &textured.scene, &textured.camera, settings).unwrap();
        sppm.run(Budget::Passes(256), &mut |_| {}).unwrap().image
    };
    let (sampled, photons) = (long(DirectLight::Sampled), long(DirectLight::Photons));
    let quarter_mean = |image: &Image| {
        let (w, h) = (image.width as usize, image.height as usize);
        let sum: f64 = (h / 2..h)
            .flat_map(|y| (w / 2..w).map(move |x| y * w + x))
            .map(|i| image.pixels[i].element_sum() as f64)
            .sum();
        sum / (w / 2 * (h - h / 2)) as f64
    };
    let ratio = quarter_mean(&sampled) / quarter_mean(&photons);
    println!("under the screen, sampled / photon direct light: {ratio:.4}");
    assert!(
        (ratio - 1.0).abs() < MAX_DIRECT_LIGHT_RATIO_ERROR,
        "{ratio}"
    );
    let Some(context) = gpu_context("the GPU half of this test is skipped") else {
        return;
    };
    let gpu = render_gpu(context, &textured, DirectLight::Sampled);
    let difference = mean_relative_difference(&gpu, &cpu);
    println!("sampled direct light, gpu vs cpu: mean relative difference {difference:.2e}");
    assert!(
        difference < MAX_MEAN_RELATIVE_DIFFERENCE,
        "gpu and cpu images differ: mean relative difference {difference}"
    );
}

const TEXTURES_WGSL: &str = include_str!("../shaders/shared/textures.wgsl");

/// Group 0: (uv, layer) queries in, linear RGBA out; group 2: the texture array.
const LOOKUP_KERNEL: &str = r#"
struct Query { uv: vec2<f32>, layer: u32, pad: u32 }
@group(0) @binding(0) var<storage, read> queries: array<Query>;
@group(0) @binding(1) var<storage, read_write> results: array<vec4<f32>>;

@compute @workgroup_size(64)
fn lookup(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= arrayLength(&queries) {
        return;
    }
    let q = queries[id.x];
    results[id.x] = sample_texture(q.layer, q.uv);
}
"#;

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Query {
    uv: [f32; 2],
    layer: u32,
    pad: u32,
}

/// `sample_texture` on the device for each query.
fn gpu_lookups(context: &GpuContext, array: &TextureArray, queries: &[Query]) -> Vec<[f32; 4]> {
    use wgpu::util::DeviceExt;
    let device = &context.device;
    let textures = gpu::textures::GpuTextures::upload(context, array).expect("texture upload");
    let source = format!("{TEXTURES_WGSL}\n{LOOKUP_KERNEL}");
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("texture lookups"),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    });
    let buffers_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("lookups"),
        entries: &[
            gpu::scene_upload::storage_entry(0, true),
            gpu::scene_upload::storage_entry(1, false),
        ],
    });
    let empty = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("empty"),
        entries: &[],
    });
    let texture_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("textures"),
        entries: &[gpu::textures::layout_entry(0)],
    });
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("lookups"),
        bind_group_layouts: &[Some(&buffers_layout), Some(&empty), Some(&texture_layout)],
        immediate_size: 0,
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("lookup"),
        layout: Some(&pipeline_layout),
        module: &module,
        entry_point: Some("lookup"),
        compilation_options: Default::default(),
        cache: None,
    });
    let input = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("queries"),
        contents: bytemuck::cast_slice(queries),
        usage: wgpu::BufferUsages::STORAGE,
    });
    let output = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("results"),
        size: (queries.len() * 16) as u64,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let buffers =
        gpu::scene_upload::bind_buffers(device, "lookups", &buffers_layout, &[&input, &output]);
    let empty_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("empty"),
        layout: &empty,
        entries: &[],
    });
    let texture_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("textures"),
        layout: &texture_layout,
        entries: &[wgpu::BindGroupEntry {
            binding: 0,
            resource: wgpu::BindingResource::TextureView(&textures.view),
        }],
    });
    let mut encoder = device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &buffers, &[]);
        pass.set_bind_group(1, &empty_group, &[]);
        pass.set_bind_group(2, &texture_group, &[]);
        pass.dispatch_workgroups((queries.len() as u32).div_ceil(64), 1, 1);
    }
    context.queue.submit([encoder.finish()]);
    gpu::readback::read_buffer(context, &output, queries.len()).expect("readback")
}

#[test]
fn sample_texture_matches_texture_array_sample() {
    // Every byte value in every channel, a non-square texture resampled up, a float one.
    let bytes = texture("bytes", 16, |x, y| {
        let i = y * 16 + x;
        [
            i as u8,
            (255 - i) as u8,
            (i * 7 % 256) as u8,
            (i * 13 % 256) as u8,
        ]
    });
    let wide = Texture {
        name: "wide".into(),
        width: 5,
        height: 3,
        texels: Texels::Srgb8((0..15u8).map(|i| [i * 17, 255 - i * 5, i, 255]).collect()),
    };
    let float = Texture {
        name: "float".into(),
        width: 2,
        height: 2,
        texels: Texels::LinearF32(vec![
            [0.0, 0.25, 0.5, 1.0],
            [1.0, 0.0, 0.1, 0.5],
            [0.01, 0.9, 3.0, 0.0],
            [0.5, 0.5, 0.5, 1.0],
        ]),
    };
    let array = TextureArray::build(&[bytes, wide, float], DEFAULT_MAX_SIDE);
    assert_eq!((array.side, array.layers), (16, 3));

    let mut queries = Vec::new();
    let edges = [
        0.0,
        1.0,
        -1.0,
        1e-9,
        -1e-9,
        0.999_999_9,
        1.000_001,
        0.5,
        1e8,
        -1e8,
        7.0,
    ];
    for layer in [0, 1, 2, 3, u32::MAX] {
        for &u in &edges {
            for &v in &edges {
                queries.push(Query {
                    uv: [u, v],
                    layer,
                    pad: 0,
                });
            }
        }
        // A grid over [-2, 3)² off the texel edges, and one on them.
        for i in 0..80 {
            for j in 0..80 {
                let (u, v) = (-2.0 + i as f32 / 16.0, -2.0 + j as f32 / 16.0);
                queries.push(Query {
                    uv: [u + 0.013, v + 0.029],
                    layer,
                    pad: 0,
                });
                queries.push(Query {
                    uv: [u, v],
                    layer,
                    pad: 0,
                });
            }
        }
    }

    let Some(context) = gpu_context("sample_texture is not checked on a device") else {
        return;
    };
    let results = gpu_lookups(&context, &array, &queries);
    let mut worst = 0.0f32;
    for (q, got) in queries.iter().zip(&results) {
        let want = array.sample(q.layer, Vec2::from(q.uv));
        let error = (glam::Vec4::from_array(*got) - want).abs().max_element();
        assert!(
            error <= 1e-5,
            "layer {} uv {:?}: gpu {got:?} vs cpu {want}",
            q.layer,
            q.uv
        );
        worst = worst.max(error);
    }
    println!("{} lookups, largest difference {worst:.2e}", queries.len());
}
