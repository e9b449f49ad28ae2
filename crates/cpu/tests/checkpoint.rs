//! A render stopped between passes and continued from its checkpoint on a new backend gives
//! the image of the render that was never stopped, bit for bit, with every density estimator
//! and storage precision; a checkpoint of another size is refused in words.

use render::half_storage::Precision;
use render::{Budget, Checkpoint, Density, Image, Settings, Sppm};

fn start(settings: &Settings) -> Sppm<cpu::CpuBackend> {
    let scene = scene::testing::cornell_caustics();
    let bvh = bvh::PackedBvh::build(&scene.triangles, &bvh::BuildOptions::default());
    let camera = scene.camera(None).unwrap();
    let backend = cpu::CpuBackend::new(cpu::SceneData::new(&scene, bvh));
    Sppm::new(backend, &scene, &camera, settings.clone()).unwrap()
}

fn run(sppm: &mut Sppm<cpu::CpuBackend>, passes: u32) -> Image {
    sppm.run(Budget::Passes(passes), &mut |_| {}).unwrap().image
}

#[test]
fn continued_render_equals_the_uninterrupted_one() {
    for (density, precision) in [
        (Density::StochasticHash, Precision::F32),
        (Density::FullHash, Precision::F16),
        (Density::KdTree, Precision::F32),
    ] {
        let settings = Settings {
            seed: 9,
            eye_every: 2,
            density,
            precision,
            ..Settings::new(20, 16, 2048)
        };
        let straight = run(&mut start(&settings), 7);
        let mut first = start(&settings);
        run(&mut first, 3);
        let checkpoint: Checkpoint = first.checkpoint().unwrap();
        assert_eq!((checkpoint.passes, checkpoint.eye_passes), (3, 2));
        let mut second = start(&settings);
        second.restore(&checkpoint).unwrap();
        let continued = run(&mut second, 7);
        assert!(straight.pixels.iter().any(|p| p.max_element() > 0.0));
        assert_eq!(continued, straight, "{density:?} {precision:?}");
        assert_eq!((second.passes(), second.eye_passes()), (7, 4));
    }
}

#[test]
fn checkpoint_of_another_size_is_refused() {
    let settings = Settings::new(20, 16, 2048);
    let mut small = start(&settings);
    run(&mut small, 1);
    let checkpoint = small.checkpoint().unwrap();
    let mut other = start(&Settings::new(20, 16, 4096));
    let message = other.restore(&checkpoint).unwrap_err().to_string();
    assert!(message.contains("slots"), "{message}");
    assert!(!message.contains('\n'), "{message}");
}

/// Checkpoints handed over during a run (`Sppm::run_with`) come with the run's rendering time
/// so far, and the time their sink takes is left out of the render's clock, as the
/// intermediate images' is: a sink that sleeps 80 ms at each of 4 passes leaves the rendered
/// seconds at least 0.3 s short of the wall time, and each checkpoint's seconds within them.
#[test]
fn handing_over_checkpoints_is_left_out_of_the_render_clock() {
    let mut sppm = start(&Settings::new(20, 16, 2048));
    let pause = std::time::Duration::from_millis(80);
    let mut handed: Vec<(u32, f64)> = Vec::new();
    let mut save = |checkpoint: &Checkpoint, seconds: f64| {
        handed.push((checkpoint.passes, seconds));
        std::thread::sleep(pause);
        Ok(())
    };
    let hooks = render::RunHooks {
        checkpoints: Some((std::time::Duration::ZERO, &mut save)),
        intermediates: None,
    };
    let started = std::time::Instant::now();
    let rendered = sppm
        .run_with(Budget::Passes(4), &mut |_| {}, hooks)
        .unwrap();
    let wall = started.elapsed().as_secs_f64();
    assert_eq!(handed.iter().map(|h| h.0).collect::<Vec<_>>(), [1, 2, 3, 4]);
    assert!(
        wall - rendered.seconds >= 4.0 * pause.as_secs_f64() - 1e-3,
        "rendered {} s of {wall} s",
        rendered.seconds
    );
    assert!(handed.windows(2).all(|w| w[0].1 <= w[1].1), "{handed:?}");
    assert!(handed.iter().all(|h| h.1 <= rendered.seconds), "{handed:?}");
}
