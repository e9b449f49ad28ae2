//! Cost of a per-lane random vec4 load from a storage buffer, a uniform buffer and a texture
//! (textureLoad) on the default adapter (a development aid):
//! `cargo run --release -p gpu --example load_microbench -- [INDEX_MASK]` (4095: 64 KiB of
//! vec4s, cached; 1048575: 16 MiB).

use std::time::Instant;

const BINDINGS: &str = r#"
@group(0) @binding(0) var<storage, read> data_storage: array<vec4<f32>>;
@group(0) @binding(1) var<uniform> data_uniform: array<vec4<f32>, 4096>;
@group(0) @binding(2) var data_texture: texture_2d<f32>;
@group(0) @binding(3) var<storage, read_write> out: array<f32>;

fn next(x: u32) -> u32 {
    let s = x * 747796405u + 2891336453u;
    let w = ((s >> ((s >> 28u) + 4u)) ^ s) * 277803737u;
    return (w >> 22u) ^ w;
}
"#;

/// One kernel: 64 dependent random loads per invocation, `LOAD` reading element `j`.
const KERNEL: &str = r#"
@compute @workgroup_size(64)
fn ENTRY(@builtin(global_invocation_id) id: vec3<u32>) {
    var i = next(id.x);
    var acc = vec4<f32>(0.0);
    for (var k = 0u; k < 64u; k++) {
        let j = i & MASK;
        acc += LOAD;
        i = next(i);
    }
    out[id.x] = acc.x + acc.y + acc.z + acc.w;
}
"#;

/// Entry points, what each loads, and the binding it loads from (besides `out`'s 3).
const VARIANTS: [(&str, &str, Option<u32>); 4] = [
    ("no_load", "vec4<f32>(f32(j))", None),
    ("storage_load", "data_storage[j]", Some(0)),
    ("uniform_load", "data_uniform[j & 4095u]", Some(1)),
    (
        "texture_load",
        "textureLoad(data_texture, vec2<u32>(j & 1023u, j >> 10u), 0)",
        Some(2),
    ),
];

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mask: u32 = std::env::args().nth(1).map_or(Ok(4095), |s| s.parse())?;
    let context = gpu::GpuContext::new(None)?;
    println!("{}", context.description());
    let device = &context.device;
    let texels = 1024 * 1024u32;
    let data: Vec<[f32; 4]> = (0..texels).map(|i| [i as f32, 1.0, 2.0, 3.0]).collect();
    use wgpu::util::DeviceExt;
    let storage = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: None,
        contents: bytemuck::cast_slice(&data),
        usage: wgpu::BufferUsages::STORAGE,
    });
    let uniform = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: None,
        contents: bytemuck::cast_slice(&data[..4096]),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let texture = device.create_texture_with_data(
        &context.queue,
        &wgpu::TextureDescriptor {
            label: None,
            size: wgpu::Extent3d {
                width: 1024,
                height: 1024,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba32Float,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        bytemuck::cast_slice(&data),
    );
    let invocations = 1u32 << 18;
    let out = device.create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size: invocations as u64 * 4,
        usage: wgpu::BufferUsages::STORAGE,
        mapped_at_creation: false,
    });
    let mut source = BINDINGS.to_string();
    for (entry, load, _) in VARIANTS {
        source += &KERNEL
            .replace("ENTRY", entry)
            .replace("LOAD", load)
            .replace("MASK", &format!("{mask}u"));
    }
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: None,
        source: wgpu::ShaderSource::Wgsl(source.into()),
    });
    let view = texture.create_view(&Default::default());
    // Each load twice, to see the run-to-run spread.
    for &(entry, _, binding) in VARIANTS.iter().chain(&VARIANTS[1..]) {
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: None,
            layout: None,
            module: &module,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            cache: None,
        });
        let layout = pipeline.get_bind_group_layout(0);
        let entries: Vec<_> = binding
            .into_iter()
            .chain([3])
            .map(|b| wgpu::BindGroupEntry {
                binding: b,
                resource: match b {
                    0 => storage.as_entire_binding(),
                    1 => uniform.as_entire_binding(),
                    2 => wgpu::BindingResource::TextureView(&view),
                    _ => out.as_entire_binding(),
                },
            })
            .collect();
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &layout,
            entries: &entries,
        });
        let mut times = Vec::new();
        for _ in 0..6 {
            let mut encoder = device.create_command_encoder(&Default::default());
            {
                let mut pass = encoder.begin_compute_pass(&Default::default());
                pass.set_pipeline(&pipeline);
                pass.set_bind_group(0, &group, &[]);
                pass.dispatch_workgroups(invocations / 64, 1, 1);
            }
            let started = Instant::now();
            context.queue.submit([encoder.finish()]);
            gpu::readback::wait_idle(&context)?;
            times.push(started.elapsed().as_secs_f64());
        }
        times.sort_by(f64::total_cmp);
        let loads = invocations as f64 * 64.0;
        println!(
            "{entry:14} {:8.2} ms  {:6.2} ns/load",
            times[2] * 1e3,
            times[2] / loads * 1e9
        );
    }
    Ok(())
}
