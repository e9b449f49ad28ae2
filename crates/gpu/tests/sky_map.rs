//! The sky map's WGSL (`shared/sky_map.wgsl`) against its CPU twin (`render::sky_map`), function
//! by function: `sky_map_lookup` on directions over the sphere (the seam behind the map, the
//! poles, cell-row borders) and `sample_sky_map` on uniform pairs (the CDFs' ends included),
//! both on a map with a one-texel sun in a gradient, turned. The kernel twins
//! (`sppm_twins.rs`) see these functions only through the few pixels and photons that reach
//! the sky; here every output is compared.

use glam::Vec3;
use gpu::GpuContext;
use render::sky_map::{MapFrame, sample_sky_map, sky_light, sky_map_buffer, sky_map_lookup};
use scene::{Bounds, Sky, SkyMap};
use std::sync::Arc;

/// The lookup's map coordinates come from atan2 and acos, which Vulkan lets err by 4096 ulp;
/// the radiance and density follow the coordinates continuously, steeply beside the sun. A
/// lookup matches when it lies within what an error of this many texels in each coordinate
/// changes, plus 1e-5 relative.
const LOOKUP_TEXELS: f32 = 1e-3;
/// Samples compute their coordinates from the CDFs alike on both sides: relative.
const SAMPLE_TOLERANCE: f32 = 1e-4;
/// Sampled directions (unit; sin and cos of the sampled angles): absolute.
const DIRECTION_TOLERANCE: f32 = 1e-5;
/// Lookups allowed to differ more: a direction within rounding of a cell row's border takes
/// the density of the row on the other side.
const MAX_BORDER_LOOKUPS: usize = 4;

/// Group 0: the map, the queries (first the frame: width, height, cos, sin; then two a query:
/// a direction or two uniform numbers, and [kind, receiver's normal]), the results (two a
/// query: radiance and density; direction and whether found). Kinds: 0 a lookup by the whole
/// map's importance, 1 a lookup for a receiver facing the normal, 2 and 3 samples alike.
const KERNEL: &str = r#"
@group(0) @binding(0) var<storage, read> sky_map: array<f32>;
@group(0) @binding(1) var<storage, read> queries: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read_write> results: array<vec4<f32>>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = 2u * id.x + 1u;
    if i >= arrayLength(&queries) {
        return;
    }
    let f = queries[0];
    let frame = MapFrame(u32(f.x), u32(f.y), f.z, f.w);
    let q = queries[i];
    let how = queries[i + 1u];
    let kind = u32(how.x);
    var upper = sky_map_upper_share(frame);
    if kind % 2u == 1u {
        upper = sky_upper_share_facing(frame, how.yzw);
    }
    var s: SkyDirection;
    if kind < 2u {
        s = sky_map_lookup(frame, q.xyz, upper);
    } else {
        s = sample_sky_map(frame, q.x, q.y, upper);
    }
    results[2u * id.x] = vec4<f32>(s.radiance, s.pdf);
    results[2u * id.x + 1u] = vec4<f32>(s.direction, select(0.0, 1.0, s.found));
}
"#;

/// A 24 × 12 map: a gradient with a one-texel sun, turned 1.1 rad.
fn sky() -> Sky {
    let (width, height) = (24, 12);
    let texels = (0..width * height)
        .map(|i| {
            let (x, y) = (i % width, i / width);
            if (x, y) == (17, 3) {
                Vec3::new(300.0, 250.0, 180.0)
            } else {
                Vec3::new(0.2 + 0.05 * y as f32, 0.4, 0.9 - 0.06 * y as f32)
                    * (1.0 + 0.4 * (x as f32 * 0.7).sin())
            }
        })
        .collect();
    let map = SkyMap::new(width, height, texels).unwrap();
    let bounds = Bounds::EMPTY.grow(Vec3::ZERO).grow(Vec3::ONE);
    Sky::with_map(Arc::new(map), Vec3::new(1.0, 0.8, 1.2), 1.1, bounds)
}

fn uniform(i: u32, dimension: u32) -> f32 {
    (render::rng::stream_key(3, dimension, 0, i) >> 8) as f32 / (1u32 << 24) as f32
}

/// Runs the kernel on `queries` (two vec4 each, after the frame); two results a query.
fn run(
    context: &GpuContext,
    buffer: &[f32],
    frame: [f32; 4],
    queries: &[[f32; 4]],
) -> Vec<[f32; 4]> {
    use wgpu::util::DeviceExt;
    let device = &context.device;
    let source = format!("{}\n{KERNEL}", gpu::shader::sky_map_source());
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("sky map twins"),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    });
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("sky map twins"),
        entries: &[
            gpu::scene_upload::storage_entry(0, true),
            gpu::scene_upload::storage_entry(1, true),
            gpu::scene_upload::storage_entry(2, false),
        ],
    });
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("sky map twins"),
        bind_group_layouts: &[Some(&layout)],
        immediate_size: 0,
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("sky map twins"),
        layout: Some(&pipeline_layout),
        module: &module,
        entry_point: Some("main"),
        compilation_options: Default::default(),
        cache: None,
    });
    let init = |label, contents: &[u8]| {
        device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents,
            usage: wgpu::BufferUsages::STORAGE,
        })
    };
    let map = init("sky map", bytemuck::cast_slice(buffer));
    let all: Vec<[f32; 4]> = std::iter::once(frame)
        .chain(queries.iter().copied())
        .collect();
    let input = init("queries", bytemuck::cast_slice(&all));
    let output = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("results"),
        size: (queries.len() * 16) as u64,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let group =
        gpu::scene_upload::bind_buffers(device, "sky map twins", &layout, &[&map, &input, &output]);
    let mut encoder = device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &group, &[]);
        pass.dispatch_workgroups((queries.len() as u32 / 2).div_ceil(64), 1, 1);
    }
    context.queue.submit([encoder.finish()]);
    gpu::readback::read_buffer(context, &output, queries.len()).expect("readback")
}

fn relative_error(a: Vec3, b: Vec3) -> f32 {
    let scale = a.abs().max(b.abs()).max_element();
    if scale == 0.0 {
        0.0
    } else {
        (a - b).abs().max_element() / scale
    }
}

fn scalar_error(a: f32, b: f32) -> f32 {
    relative_error(Vec3::splat(a), Vec3::splat(b))
}

#[test]
fn lookups_and_samples_match_their_cpu_twins() {
    let sky = sky();
    let buffer = sky_map_buffer(Some(&sky));
    let frame = MapFrame::of(&sky_light(&sky)).unwrap();
    let frame_row = [
        frame.width as f32,
        frame.height as f32,
        frame.cos,
        frame.sin,
    ];

    // Lookups: directions spread over the sphere, the poles, and the seam behind the map.
    let mut directions: Vec<Vec3> = (0..6000)
        .map(|i| {
            let z = 2.0 * uniform(i, 0) - 1.0;
            let phi = std::f32::consts::TAU * uniform(i, 1);
            let r = (1.0 - z * z).max(0.0).sqrt();
            Vec3::new(r * phi.cos(), z, r * phi.sin())
        })
        .collect();
    directions.extend([Vec3::Y, Vec3::NEG_Y, Vec3::new(1e-4, 1.0, 0.0).normalize()]);
    let seam = Vec3::new(frame.sin, 0.0, frame.cos); // the map's u = 0, turned to the world
    directions
        .extend((0..50).map(|i| (seam + Vec3::new(0.0, -0.9 + 0.036 * i as f32, 0.0)).normalize()));
    // Samples: uniform pairs and the CDFs' ends.
    let mut pairs: Vec<(f32, f32)> = (0..6000).map(|i| (uniform(i, 2), uniform(i, 3))).collect();
    for a in [0.0, 1e-7, 0.5, 0.999_999_9] {
        for b in [0.0, 1e-7, 0.5, 0.999_999_9] {
            pairs.push((a, b));
        }
    }
    // Each query for the whole map (photons) or for a receiver facing one of these normals.
    let normals = [
        None,
        Some(Vec3::Y),
        Some(Vec3::NEG_Y),
        Some(Vec3::X),
        Some(Vec3::new(0.6, 0.8, 0.0)),
        Some(Vec3::new(0.0, -0.6, 0.8)),
    ];
    let receiver = |i: usize| normals[i % normals.len()];
    let upper = |i: usize| match receiver(i) {
        None => frame.map_upper_share(&buffer),
        Some(normal) => frame.upper_share_facing(&buffer, normal),
    };
    let how = |i: usize, sample: bool| {
        let n = receiver(i).unwrap_or(Vec3::ZERO);
        let kind = 2 * sample as u32 + receiver(i).is_some() as u32;
        [kind as f32, n.x, n.y, n.z]
    };
    let queries: Vec<[f32; 4]> = directions
        .iter()
        .enumerate()
        .flat_map(|(i, d)| [[d.x, d.y, d.z, 0.0], how(i, false)])
        .chain(
            pairs
                .iter()
                .enumerate()
                .flat_map(|(i, &(a, b))| [[a, b, 0.0, 0.0], how(i, true)]),
        )
        .collect();

    let Ok(context) = GpuContext::new(None) else {
        panic!("no usable GPU adapter in the test environment (CI installs Mesa lavapipe)");
    };
    let results = run(&context, &buffer, frame_row, &queries);

    let (mut worst_lookup, mut borders) = (0.0f32, 0);
    for (i, d) in directions.iter().enumerate() {
        let (radiance, pdf) = sky_map_lookup(&frame, &buffer, *d, upper(i));
        // What LOOKUP_TEXELS of error in the coordinates can change.
        let (u, v) = frame.coordinates(*d);
        let (du, dv) = (
            LOOKUP_TEXELS / frame.width as f32,
            LOOKUP_TEXELS / frame.height as f32,
        );
        let slack = [(du, dv), (du, -dv), (-du, dv), (-du, -dv)]
            .iter()
            .map(|(a, b)| {
                (frame.radiance_at(&buffer, (u + a, (v + b).clamp(0.0, 1.0))) - radiance).abs()
            })
            .fold(1e-5 * radiance.abs(), Vec3::max);
        let [r, g, b, gpu_pdf] = results[2 * i];
        let gpu = Vec3::new(r, g, b);
        if d.y.abs() == 1.0 {
            // The exact poles: the azimuth is atan2(0, 0), which WGSL leaves undefined, so
            // only a finite radiance and no density are asked.
            assert!(
                gpu.is_finite() && gpu_pdf == 0.0 && pdf == 0.0,
                "pole {d}: {gpu} {gpu_pdf}"
            );
            continue;
        }
        assert!(
            (gpu - radiance)
                .abs()
                .cmple(slack + 1e-5 * radiance.abs())
                .all(),
            "lookup {d}: gpu radiance {gpu} vs cpu {radiance} (within {slack})"
        );
        let used = (gpu - radiance).abs() / (slack + 1e-5 * radiance.abs()).max(Vec3::splat(1e-30));
        worst_lookup = worst_lookup.max(used.max_element());
        // The density follows the radiance's channel sum within a cell row.
        let pdf_slack = 2.0 * slack.element_sum() / radiance.element_sum().max(1e-30) + 1e-5;
        if scalar_error(gpu_pdf, pdf) > pdf_slack {
            borders += 1;
        }
    }
    assert!(
        borders <= MAX_BORDER_LOOKUPS,
        "{borders} lookups' densities differ"
    );

    let mut worst_sample = 0.0f32;
    let mut found = 0;
    for (k, &(a, b)) in pairs.iter().enumerate() {
        let i = directions.len() + k;
        let cpu = sample_sky_map(&frame, &buffer, a, b, upper(k));
        let [r, g, bl, pdf] = results[2 * i];
        let [x, y, z, gpu_found] = results[2 * i + 1];
        assert_eq!(
            gpu_found == 1.0,
            cpu.is_some(),
            "sample ({a}, {b}) found on one side only"
        );
        let Some(cpu) = cpu else { continue };
        found += 1;
        let direction_error = (Vec3::new(x, y, z) - cpu.direction).abs().max_element();
        let error =
            relative_error(Vec3::new(r, g, bl), cpu.radiance).max(scalar_error(pdf, cpu.pdf));
        assert!(
            direction_error <= DIRECTION_TOLERANCE && error <= SAMPLE_TOLERANCE,
            "sample ({a}, {b}): gpu {:?} {pdf} towards {:?}, cpu {cpu:?}",
            [r, g, bl],
            [x, y, z]
        );
        worst_sample = worst_sample.max(error);
    }
    assert!(found > 5000, "{found} samples found");
    println!(
        "{} lookups (worst difference {worst_lookup:.2} of its allowance, {borders} on row borders), \
         {found} samples (worst {worst_sample:.1e})",
        directions.len()
    );
}
