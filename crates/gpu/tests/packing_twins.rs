//! The packed words of murky glass (`render::packing`: `surface_normal`, `photon_normal`,
//! `volume_photon_direction`, `volume_point_direction`, `unpack_volume_point`) against their
//! WGSL twins in `shading/packing.wgsl`, bit for bit: the kernel twins (`sppm_twins.rs`) compare
//! packed normals by the cosine between them, which would let a misplaced flag bit or
//! asymmetry level through. The direction's own bits follow `pack_normal`, which may round a
//! half the other way ([`FLAG_BITS`]). Directions over the sphere and asymmetries over [−1, 1] (each of
//! the 512 levels' midpoints, where the rounding decides, and values past either end). Also
//! `render::volume_boundary`'s depth word and sphere share against `shading/volume_boundary.wgsl`.

use glam::Vec3;
use gpu::GpuContext;
use gpu::shader::Module;
use render::packing::{
    VOLUME_BIT, photon_normal, surface_normal, unpack_volume_point, volume_photon_direction,
    volume_point_direction,
};
use wgpu::util::DeviceExt;

/// The bits of each word the kernel returns that are not its direction's: the volume bit, the
/// caustic class (bit 0) of the photons' words, and a volume visible point's asymmetry
/// (render::packing's private `ANISOTROPY_BITS`). These must agree exactly; the direction's
/// may differ by a step where the octahedral coordinate times 32767 lies within an ulp of a
/// half: both round halves up (`render::packing::pack_normal`), but the GPU's coordinate may
/// be an ulp off the CPU's (1 of the 4096 directions here; 2 when Rust rounded negative halves
/// away from zero).
const FLAG_BITS: [u32; 4] = [
    VOLUME_BIT,
    1 | VOLUME_BIT,
    1 | VOLUME_BIT,
    0x001e_001f | VOLUME_BIT,
];

/// Appended to the SPPM module (for `shading/packing.wgsl`), binding past its group 1 buffers as
/// `kdtree_query.wgsl` does: per query (direction, g), the words surface_normal,
/// photon_normal (caustic), volume_photon_direction and volume_point_direction, then the
/// bits of unpack_volume_point of the CPU's volume_point_direction word (given in `.w`'s
/// place by the second vec4 of the query).
const KERNEL: &str = r#"
@group(1) @binding(16) var<storage, read> packing_queries: array<vec4<f32>>;
@group(1) @binding(17) var<storage, read_write> packing_words: array<vec4<u32>>;

@compute @workgroup_size(64)
fn boundary_twins(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if 2u * i + 1u >= arrayLength(&packing_queries) {
        return;
    }
    let q = packing_queries[2u * i];
    let word = depths_word(q.x, q.y);
    packing_words[2u * i] = vec4<u32>(word, bitcast<u32>(share_inside(word, q.z)), 0u, 0u);
    packing_words[2u * i + 1u] = vec4<u32>(0u);
}

@compute @workgroup_size(64)
fn packing_twins(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if 2u * i + 1u >= arrayLength(&packing_queries) {
        return;
    }
    let q = packing_queries[2u * i];
    let cpu_word = bitcast<u32>(packing_queries[2u * i + 1u].x);
    packing_words[2u * i] = vec4<u32>(
        surface_normal(q.xyz),
        photon_normal(q.xyz, true),
        volume_photon_direction(q.xyz),
        volume_point_direction(q.xyz, q.w),
    );
    packing_words[2u * i + 1u] = bitcast<vec4<u32>>(unpack_volume_point(cpu_word));
}
"#;

fn context() -> GpuContext {
    GpuContext::new(None).unwrap_or_else(|e| {
        panic!("no usable GPU adapter in the test environment (CI installs Mesa lavapipe): {e}")
    })
}

fn uniform(i: u32, dimension: u32) -> f32 {
    (render::rng::stream_key(11, dimension, 0, i) >> 8) as f32 / (1u32 << 24) as f32
}

/// Runs the kernel's entry point `entry`: two vec4 a query in, two vec4<u32> a query out.
fn run(context: &GpuContext, entry: &str, queries: &[[f32; 4]]) -> Vec<[u32; 4]> {
    let device = &context.device;
    let source = format!("{}\n{KERNEL}", Module::Sppm.source());
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("packing twins"),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    });
    // The layout the entry point uses: group 1's two buffers only.
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("packing twins"),
        layout: None,
        module: &module,
        entry_point: Some(entry),
        compilation_options: Default::default(),
        cache: None,
    });
    let input = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("packing queries"),
        contents: bytemuck::cast_slice(queries),
        usage: wgpu::BufferUsages::STORAGE,
    });
    let output = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("packing words"),
        size: (queries.len() * 16) as u64,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("packing twins"),
        layout: &pipeline.get_bind_group_layout(1),
        entries: &[
            wgpu::BindGroupEntry {
                binding: 16,
                resource: input.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 17,
                resource: output.as_entire_binding(),
            },
        ],
    });
    let mut encoder = device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(1, &group, &[]);
        pass.dispatch_workgroups((queries.len() as u32 / 2).div_ceil(64), 1, 1);
    }
    context.queue.submit([encoder.finish()]);
    gpu::readback::read_buffer(context, &output, queries.len()).expect("readback")
}

#[test]
fn murky_glass_words_match_render_packing_bit_for_bit_but_for_half_steps() {
    let mut directions: Vec<Vec3> = (0..4096)
        .map(|i| {
            let z = 2.0 * uniform(i, 0) - 1.0;
            let phi = std::f32::consts::TAU * uniform(i, 1);
            let r = (1.0 - z * z).max(0.0).sqrt();
            Vec3::new(r * phi.cos(), r * phi.sin(), z)
        })
        .collect();
    directions.extend([
        Vec3::X,
        Vec3::NEG_X,
        Vec3::Y,
        Vec3::NEG_Y,
        Vec3::Z,
        Vec3::NEG_Z,
    ]);
    // Each level's midpoint (2/511 apart), the ends and past them, then uniform values.
    let mut anisotropies: Vec<f32> = (0..511)
        .map(|level| ((level as f64 + 0.5) / 511.0 * 2.0 - 1.0) as f32)
        .collect();
    anisotropies.extend([-1.5, -1.0, 0.0, 1.0, 1.5]);
    let queries: Vec<(Vec3, f32)> = (0..directions.len().max(anisotropies.len()))
        .map(|i| {
            let g = anisotropies
                .get(i)
                .copied()
                .unwrap_or_else(|| 2.0 * uniform(i as u32, 2) - 1.0);
            (directions[i % directions.len()], g)
        })
        .collect();
    let input: Vec<[f32; 4]> = queries
        .iter()
        .flat_map(|&(n, g)| {
            let word = f32::from_bits(volume_point_direction(n, g));
            [n.extend(g).to_array(), [word, 0.0, 0.0, 0.0]]
        })
        .collect();
    let output = run(&context(), "packing_twins", &input);
    let mut moved = 0;
    for (i, (&(n, g), words)) in queries.iter().zip(output.chunks(2)).enumerate() {
        let cpu = [
            surface_normal(n),
            photon_normal(n, true),
            volume_photon_direction(n),
            volume_point_direction(n, g),
        ];
        for ((gpu, cpu), flags) in words[0].iter().zip(cpu).zip(FLAG_BITS) {
            assert_eq!(gpu & flags, cpu & flags, "query {i}: {n}, g {g}");
            // Each half's direction differs by at most a step: one more than its low flag bits.
            let halves = |w: u32| [(w & 0xffff) as u16 as i16, (w >> 16) as u16 as i16];
            let [gpu, cpu, step] = [*gpu & !flags, cpu & !flags, flags + 0x0001_0001].map(halves);
            for k in 0..2 {
                let off = (gpu[k] as i32 - cpu[k] as i32).abs();
                assert!(
                    off <= step[k] as i32,
                    "query {i}: {n}: {gpu:?} against {cpu:?}"
                );
            }
        }
        moved += usize::from(words[0] != cpu);
        let (direction, anisotropy) = unpack_volume_point(cpu[3]);
        let [x, y, z, w] = words[1].map(f32::from_bits);
        let gpu = Vec3::new(x, y, z);
        assert!(
            (gpu - direction).abs().max_element() < 1e-6,
            "query {i}: unpacked {gpu} against {direction}"
        );
        assert!(
            (w - anisotropy).abs() < 1e-6,
            "query {i}: unpacked g {w} against {anisotropy}"
        );
    }
    println!("{moved} of {} words moved by a step", queries.len());
    assert!(moved <= queries.len() / 1000, "{moved} words moved");
}

#[test]
fn volume_boundary_words_match_bit_for_bit_and_their_shares_closely() {
    use render::volume_boundary::{NO_SURFACE, depths_word, share_inside};
    // Depths from far inside to on the surface, against radii from a tenth of them to ten
    // times, with the camera's "no surface" and zero among them.
    let depth = |i: u32, k: u32| match i % 7 {
        0 => NO_SURFACE,
        1 => 0.0,
        _ => 10f32.powf(4.0 * uniform(i, k) - 2.0),
    };
    let queries: Vec<[f32; 4]> = (0..2048)
        .map(|i| {
            let (behind, ahead) = (depth(i, 3), depth(i / 7, 4));
            let radius = 10f32.powf(4.0 * uniform(i, 5) - 2.0);
            [behind, ahead, radius, 0.0]
        })
        .collect();
    let input: Vec<[f32; 4]> = queries.iter().flat_map(|&q| [q, [0.0; 4]]).collect();
    let output = run(&context(), "boundary_twins", &input);
    let mut cut = 0;
    for (q, words) in queries.iter().zip(output.chunks(2)) {
        let word = depths_word(q[0], q[1]);
        let share = share_inside(word, q[2]);
        assert_eq!(words[0][0], word, "depths {q:?}");
        // A GPU's division may be a few ulps off (WGSL allows 2.5).
        let gpu_share = f32::from_bits(words[0][1]);
        assert!(
            (gpu_share - share).abs() <= 1e-6,
            "share {gpu_share} against {share}, {q:?}"
        );
        cut += usize::from(share < 1.0);
    }
    // Both the sphere whole and cut by its planes were met.
    assert!(cut > queries.len() / 4 && cut < queries.len(), "{cut} cut");
}
