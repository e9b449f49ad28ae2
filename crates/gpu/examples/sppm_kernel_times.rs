//! Wall time of each SPPM kernel on the default adapter (a development aid):
//! `cargo run --release -p gpu --example sppm_kernel_times -- SCENE [WIDTH] [SLOTS]`.

use std::time::Instant;

use render::Backend;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let scene = scene::load(std::path::Path::new(&args[1]))?;
    let width: u32 = args.get(2).map_or(Ok(512), |s| s.parse())?;
    let slots: u32 = args.get(3).map_or(Ok(1 << 18), |s| s.parse())?;
    let bvh = bvh::PackedBvh::build(&scene.triangles, &bvh::BuildOptions::default());
    let camera = scene.camera(None).ok_or("no camera")?;
    let backend = gpu::sppm::GpuBackend::new(gpu::GpuContext::new(None)?, &scene, bvh)?;
    let settings = render::Settings::new(width, width, slots);
    let mut sppm = render::Sppm::new(backend, &scene, &camera, settings)?;
    sppm.pass();
    sppm.backend().synchronize()?;
    let mut totals = [0.0f64; 4];
    let passes = 5;
    for _ in 0..passes {
        let b = sppm.backend();
        let steps: [&dyn Fn(&mut gpu::sppm::GpuBackend); 4] = [
            &|b| b.eye_pass(),
            &|b| b.photon_pass(),
            &|b| b.build_hash(),
            &|b| b.gather(),
        ];
        for (total, step) in totals.iter_mut().zip(steps) {
            let started = Instant::now();
            step(b);
            b.synchronize()?;
            *total += started.elapsed().as_secs_f64();
        }
    }
    for (name, total) in ["eye", "photon", "hash", "gather"].iter().zip(totals) {
        println!("{name:8} {:8.1} ms", total / passes as f64 * 1e3);
    }
    Ok(())
}
