//! Photon paths walking through scattering solids over many passes (`render::scattering`):
//! a path's walk is one walk however many steps it takes, its hero channel and densities
//! carried in the slot from pass to pass, so its weight stays bounded.

use glam::Vec3;
use render::Settings;
use render::buffers::{PathSlot, SLOT_IDLE, vec3};
use scene::testing;

/// A lamp in a lossless cube scattering σs = (16, 4, 1) (optical half side 32, 8 and 2:
/// red walks hundreds of scatterings, a dozen steps of 16, before it leaves): every slot's
/// flux stays within 3 times what its path was emitted with, in every channel and at every
/// step (each channel's weight is its density of the whole walk over the three's mean).
/// Restarting the walk at each step instead multiplies the steps' weights (up to 3 each): a
/// slot then carried 9 times its emitted flux in red after its second step.
#[test]
fn a_path_s_walk_keeps_its_weight_bounded_over_its_steps() {
    let scene = testing::lamp_in_scattering_cube(Vec3::new(16.0, 4.0, 1.0), 0.0);
    let camera = scene.camera(None).unwrap();
    let settings = Settings {
        max_depth: 256,
        ..Settings::new(16, 16, 5_000)
    };
    let lights = render::emission::light_table(&scene).len() as u32;
    let params = render::integrator::params(&scene, &camera, &settings, lights);
    let bvh = bvh::PackedBvh::build(&scene.triangles, &bvh::BuildOptions::default());
    let data = cpu::SceneData::new(&scene, bvh);

    // Every path from the point light starts with its power, 4πI.
    let emitted = 4.0 * std::f32::consts::PI * testing::TRANSLUCENT_CUBE_LAMP_INTENSITY;
    let mut slots = vec![PathSlot::IDLE; params.slot_count as usize];
    let (mut worst, mut long_walks) = (0.0f32, 0);
    for pass in 0..48 {
        for (index, slot) in slots.iter_mut().enumerate() {
            *slot = cpu::kernels::photon_pass(&data, &params, pass, index as u32, *slot).slot;
            if slot.depth == SLOT_IDLE {
                continue;
            }
            let ratio = vec3(slot.flux).max_element() / emitted;
            worst = worst.max(ratio);
            assert!(
                ratio <= 3.0 + 1e-3,
                "pass {pass}, slot {index}: flux {:?} from {emitted} emitted (depth {})",
                slot.flux,
                slot.depth
            );
            if slot.depth == 8 {
                long_walks += 1;
            }
        }
    }
    println!("worst flux over emitted {worst}; {long_walks} paths walked 8 steps");
    assert!(worst > 1.5, "the walks' weights never left 1 ({worst})");
    assert!(long_walks > 1_000, "only {long_walks} paths walked 8 steps");
}
