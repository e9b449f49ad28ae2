//! Wall time of each SPPM kernel on the default adapter (a development aid):
//! `cargo run --release -p gpu --example sppm_kernel_times -- SCENE [WIDTH] [SLOTS] [WARMUP]
//! [talk|render] [CANDIDATES]`, timing five passes after WARMUP whole passes (default 1; later passes
//! gather with smaller, more varied radii). `talk` (the default): the stochastic hash and
//! photon-gathered direct light; `render`: what `kousen render` runs on CPU-type adapters at
//! glslppm's α (full per-cell lists, sampled direct light, α 0.7 for both photon classes);
//! `gpu`: what `kousen render` runs on a GPU (the stochastic hash, sampled direct light).
//! CANDIDATES: light candidates per Lambertian light sample (`render::resampling`).

use std::time::Instant;

use render::Backend;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let scene = scene::load(std::path::Path::new(&args[1]))?;
    let width: u32 = args.get(2).map_or(Ok(512), |s| s.parse())?;
    let slots: u32 = args.get(3).map_or(Ok(1 << 18), |s| s.parse())?;
    let warmup: u32 = args.get(4).map_or(Ok(1), |s| s.parse())?;
    let bvh = bvh::PackedBvh::build(&scene.triangles, &bvh::BuildOptions::default());
    let camera = scene.camera(None).ok_or("no camera")?;
    let backend = gpu::sppm::GpuBackend::new(gpu::GpuContext::new(None)?, &scene, bvh)?;
    let mut talk = render::Settings::new(width, width, slots);
    if let Some(candidates) = args.get(6) {
        talk.light_candidates = Some(candidates.parse()?);
    }
    let settings = match args.get(5).map_or("talk", String::as_str) {
        "talk" => talk,
        "render" => render::Settings {
            density: render::Density::FullHash,
            direct: render::direct::DirectLight::Sampled,
            alpha: 0.7,
            indirect_alpha: 0.7,
            caustic_radius_share: render::settings::MEASURED_CAUSTIC_RADIUS_SHARE,
            ..talk
        },
        "gpu" => render::Settings {
            direct: render::direct::DirectLight::Sampled,
            caustic_radius_share: render::settings::MEASURED_CAUSTIC_RADIUS_SHARE,
            ..talk
        },
        other => return Err(format!("unknown settings {other:?} (talk, render or gpu)").into()),
    };
    let mut sppm = render::Sppm::new(backend, &scene, &camera, settings)?;
    for _ in 0..warmup {
        sppm.pass();
    }
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
